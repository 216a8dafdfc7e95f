/*
 * report_int.h: the private interface between the files that implement report_html.h.
 * Not installed, not used outside src/report/.
 *
 *   report_html.c   the page: head, tables, data block, script; sr_report_html
 *   report_text.c   the growing text the page is written into, HTML- and JSON-escaped
 *   report_plans.c  the build plan of each section, its table and its data
 *   report_cells.c  the feature and advice cells, readable, from the stored JSON
 *   report_nominal.c the "symmetry vs nominal" section (rp_nominal_section)
 *   report_inspect.c the inspection section and its data (rp_inspection_section)
 *   report_data.c   the data block's meshes and layer outlines, compactly encoded
 *   decimate.c      meshes reduced to the display budget (sr_report_decimate)
 *   report.css, report.js, report_view.js  the stylesheet and the scripts (report.js:
 *                   the outlines; report_view.js: the 3D view on three.js), compiled
 *                   in (report_assets.h) with three.js itself
 */
#ifndef SR_REPORT_INT_H
#define SR_REPORT_INT_H

#include <stdbool.h>
#include <stddef.h>

#include "plan/plan.h"
#include "report/report_html.h"

/* ---- growing text (report_text.c) ---- */

/* A heap string grown as text is appended; zeroed is empty. Out of memory is sticky:
 * `failed` is set, later appends do nothing, so a writer checks once at the end. The
 * caller frees p. */
typedef struct sb {
    char *p;
    size_t len, cap;
    bool failed;
} sb;

void sb_put(sb *b, const char *s);
void sb_putn(sb *b, const char *s, size_t n);
void sb_printf(sb *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Text as HTML character data or attribute value (NULL writes nothing). */
void sb_html(sb *b, const char *s);
/* A JSON string for the data block: quotes, backslashes and control characters
 * escaped, and '<', '>', '&' as \u escapes so the text cannot close the script. */
void sb_jstr(sb *b, const char *s);
/* A number for the data block by printf format fmt (null when not finite). */
void sb_jnum(sb *b, double v, const char *fmt);

/* ---- symmetry vs nominal (report_nominal.c) ---- */

/* The section comparing the run's symmetry sections with the nominal's second
 * opinion; nothing when r->nominal is NULL. */
void rp_nominal_section(sb *b, const sr_run *r);

/* ---- the inspection (report_inspect.c) ---- */

/* The half-width of the deviation colour scale, mm (sr_inspect_scale_range). */
double rp_inspection_range(const sr_report_inspection *ins);
/* The "Inspection" section (3D canvas, colour scale legend, per-section table);
 * nothing when ins is NULL. */
void rp_inspection_section(sb *b, const sr_report_inspection *ins);
/* The data block's "inspection" member (",\"inspection\":{...}"): the scale and, when
 * the scan is given, the mesh and its deviations (base64 float32); nothing when ins is
 * NULL. */
void rp_put_inspection(sb *b, const sr_report_inspection *ins);

/* ---- build plans (report_plans.c) ---- */

/* The plan of one section, or why there is none. */
typedef struct report_plan {
    const sr_run_section *section;
    bool replace;               /* advised 'replace': no plan */
    bool built;                 /* plan holds a plan */
    char why[512];              /* no plan, not replace: the plan module's message */
    const char *process;        /* the advised process ("" = none) */
    sr_plan plan;
} report_plan;

/* One entry per section of r (*out NULL when r has none), planned with opts (NULL:
 * the defaults), none for a section advised 'replace'. SR_E_NOMEM only; a plan that
 * cannot be made says why. Release with rp_plans_release. */
sr_status rp_plans_build(const sr_run *r, const sr_plan_opts *opts, report_plan **out,
                         sr_err *err);
/* Frees the n entries of p and p; accepts NULL. */
void rp_plans_release(report_plan *p, size_t n);
/* The "Build plans" section of the page: one row per section of r. */
void rp_plan_table(sb *b, const sr_run *r, const report_plan *p);
/* The data block's "plans" member (",\"plans\":[...]"), one entry per section. */
void rp_put_plans(sb *b, const sr_run *r, const report_plan *p);

/* ---- readable cells (report_cells.c) ---- */

/* The "further features" cell of a section from its features_json (section_features.h):
 * where it is, the figures the other columns do not show, named with their units, and
 * the reasons for its class as a list; "-" when there is no object. */
void rp_feature_cell(sb *b, const char *features_json);
/* The advice cell from details_json (rules.h): the process parameters on one line, the
 * rules fired as a list (the applied one marked), the rules passed over or not
 * evaluated with why, then the other figures; "-" when there is no object. */
void rp_advice_cell(sb *b, const char *details_json);
/* A stored JSON text (valid, as the catalogue keeps it) into the data block, '<', '>'
 * and '&' as \u escapes; null for NULL or empty. */
void rp_put_json(sb *b, const char *json);

/* ---- compact data (report_data.c) ---- */

/* The quantum of the encoded outlines, mm. */
#define RP_OUTLINE_QUANTUM 0.001

/* The data block's "layers" member (",\"layers\":{...}", report_data.c says how the
 * outlines are encoded) for r's layer_count x sectors outlines. */
void rp_put_layers(sb *b, const sr_run *r);
/* A mesh as {"nv", "nt", "v": base64 of nv x 3 float32 (little-endian), "t": base64 of
 * nt x 3 uint32}. */
void rp_put_mesh(sb *b, const sr_mesh *m);
/* n values as base64 of float32, little-endian (no quotes). */
void rp_put_floats(sb *b, const double *v, size_t n);

#endif
