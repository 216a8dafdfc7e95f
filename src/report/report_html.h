/*
 * report_html.h: the HTML report of one reconstruction run, as one self-contained
 * text (no network, nothing outside the file: the CSS, the script and the data are
 * inline, three.js included). It shows the part and its patches in 3D (WebGL through
 * three.js: the restored part, the patches and the scan as meshes shown or hidden one by
 * one, opening from outside the part on the largest missing section; a note in its place
 * without WebGL), the per-layer outlines (damaged vs restored, an SVG
 * plot with a layer selector) with each section's build plan drawn over them (the
 * layer's missing region, the deposit region and the deposition paths, contour rings
 * and raster, computed by plan.h exactly as `symrec plan` does), the build plan's
 * figures per section, the table of missing sections with their features, the advice
 * with the rules that fired, and the run's parameters, alignment and timings.
 *
 * Build plans: every section gets one unless its advice (or a whole-part advice) is a
 * process beginning 'replace' (ASCII case ignored): then the page says there is no
 * build plan because the part is to be replaced. A section whose plan cannot be made
 * (no layer polylines stored, a symmetry without sections' geometry) says why in its
 * row; only running out of memory fails the whole report. The plan data in the page's
 * JSON block ("plans") carry coordinates to 1e-5 mm, the polygon library's own grid,
 * so they read back as the very numbers plan.h produced.
 *
 * The tables read as a shop's document: features as named figures with units and the
 * reasons for the class as a list; the advice's process parameters on one line and the
 * rules fired as a list (report_cells.c); the stored JSON behind them is in the data block
 * ("sections", "advice"). Printed (the stylesheet's print rules), the page is A4 with
 * the controls left out, sections starting on new pages and no table row cut in two.
 * The outlines and meshes in the data block are encoded compactly (report_data.c).
 *
 * Meshes above a display budget are decimated by vertex clustering for the viewer
 * (the page says so, with the counts); every figure in the tables is the stored one.
 * Writing the file is the caller's business (cli/cmd_report.c writes it atomically).
 */
#ifndef SR_REPORT_HTML_H
#define SR_REPORT_HTML_H

#include <stddef.h>

#include "inspect/inspect.h"
#include "plan/plan.h"
#include "run/run.h"
#include "base/status.h"

/* The run's latest inspection (issue 20), for the page's inspection section: the scan
 * after repair in 3D coloured by its signed deviation from the restored model (a scale
 * in mm, the tolerance band marked) and the per-section table. */
typedef struct sr_report_inspection {
    long long id;
    const char *inspected_at; /* UTC, ISO 8601 */
    const char *verdict;      /* "pass", "machine", "rework" */
    const char *reasons;
    double tolerance_mm, allowance_mm;
    const sr_inspect_section *sections;
    size_t section_count;
    const sr_mesh *scan;     /* the scan after repair in the restored model's frame, as
                                 * shown: not decimated here (the caller reduces it first);
                                 * NULL = only the table */
    const double *deviation; /* scan->vertex_count signed deviations, mm (positive:
                                 * stock above the restored surface) */
} sr_report_inspection;

typedef struct sr_report_opts {
    size_t max_triangles; /* viewer budget, the restored part and the patches
                                 * together (the scan: a quarter of it more); 0 = 60000 */
    /* The instance's and the part's facts from the catalogue, shown in the run table
     * when given; NULL = the row is left out. */
    const char *serial;         /* the instance's serial */
    const char *received;       /* the date it was received, YYYY-MM-DD */
    const char *part_name;
    const char *material;
    const sr_plan_opts *plan;   /* build plan settings; NULL = sr_plan_opts_init's
                                 * defaults (the caller sets the material's density) */
    const sr_mesh *scan;        /* the instance's scan (scan frame), shown in the 3D view
                                 * on demand; NULL = none. It is decimated to a quarter of
                                 * the budget and not counted in sr_report_info. */
    const sr_report_inspection *inspection; /* NULL = the run was not inspected */
} sr_report_opts;

/* Figures of what the viewer got, for the caller's messages. */
typedef struct sr_report_info {
    size_t tri_stored;          /* restored + patches, as stored */
    size_t tri_shown;           /* after decimation */
    int decimated;              /* 1 when some mesh was reduced */
    size_t plan_sections;       /* sections with a build plan in the page */
    size_t plan_layers;         /* their plan layers, all together */
    size_t replace_sections;    /* sections advised 'replace': no build plan */
} sr_report_info;

/* Builds the report of `run` (read with SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS for
 * the 3D view and the outlines; without them the page says they were not stored).
 * *out receives a NUL-terminated heap string (free()) and *out_len its length, only on
 * success; info may be NULL. SR_E_NOMEM when memory runs out. */
sr_status sr_report_html(const sr_run *run, const sr_report_opts *opts, char **out,
                         size_t *out_len, sr_report_info *info, sr_err *err);

/* Decimates `in` by vertex clustering until it has at most max_tri triangles (a copy
 * when it has no more already). Degenerate triangles are dropped. For display only. */
sr_status sr_report_decimate(const sr_mesh *in, size_t max_tri, sr_mesh *out, sr_err *err);

#endif
