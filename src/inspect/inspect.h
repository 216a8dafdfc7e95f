/*
 * inspect.h: the inspection of a repaired part against its own restoration, which
 * closes the loop of a run (issue 20). The shop builds the lost material up and
 * machines it back, scans the part again, and asks: does every repaired region reach
 * the restored surface, how much stock is left to machine, and is the rest of the part
 * unchanged? The reference is the run's restored mesh (scan + patches, scan frame) and
 * its section patches (the missing volumes), not a CAD model.
 *
 * The method (inspect.c, volumes in inspect_volume.c):
 *   - the scan after repair is taken onto the restored model: as it is when it already
 *     lies on it (the same frame: most of it within the registration tolerance), else
 *     registered (align/register.h) to the restored model with the sections' surface
 *     taken out, so neither the new material nor a missing one pulls the fit;
 *   - area-uniform samples of the scan, each with its signed distance to the restored
 *     surface (positive outside: stock; negative inside: material short of it), are
 *     given to the section whose patch holds their closest restored point, the others
 *     are "outside";
 *   - per section: the under-fill (patch \ scan, the restored material the repair did
 *     not reach, by a CGAL boolean when the scan is closed) and its largest depth; the
 *     over-build (scan \ restored model, its connected pieces given to the section
 *     most of their vertices lie over) with the stock's thickness, min / max / mean
 *     over the samples above the tolerance; the signed deviation statistics (the
 *     extremes, the depth and the largest stock, over the scan's vertices too, which
 *     samples miss at corners);
 *   - outside the sections the share of the samples beyond the tolerance;
 *   - verdicts: rework when a section is under-filled (more than 1 % of its samples
 *     deeper than the tolerance) or not reached by the scan at all, or the part changed
 *     outside the sections (more than 1 % of the outside samples beyond the
 *     tolerance); machine when a section carries stock (more than 1 % of its samples
 *     above the tolerance; said when it exceeds the allowance); pass otherwise. The
 *     overall verdict is the worst of them.
 * When the scan is not closed (or a boolean refuses it) the volumes are estimated from
 * the samples (depth x area each) and volumes_exact is 0.
 */
#ifndef SR_INSPECT_H
#define SR_INSPECT_H

#include <stddef.h>

#include "base/status.h"
#include "mesh/mesh.h"
#include "run/run.h"

typedef enum sr_inspect_verdict {
    SR_INSPECT_PASS = 0, /* on the restored surface within the tolerance */
    SR_INSPECT_MACHINE,  /* stock above the restored surface to machine off */
    SR_INSPECT_REWORK,   /* under-filled, not reached, or changed outside the sections */
} sr_inspect_verdict;

/* "pass", "machine", "rework". */
const char *sr_inspect_verdict_str(sr_inspect_verdict v);
/* The verdict named s; -1 when none is. */
int sr_inspect_verdict_parse(const char *s);

enum {
    SR_INSPECT_REGISTER_AUTO = 0, /* as it is when it lies on the model, else register */
    SR_INSPECT_REGISTER_NEVER,    /* the scan is in the run's frame */
    SR_INSPECT_REGISTER_ALWAYS,
};

/* Valid when zeroed. */
typedef struct sr_inspect_opts {
    double allowance_mm; /* machining stock expected above the restored surface; 0 = 0.5 */
    double tolerance_mm; /* |deviation| within this is on the surface; 0 = 0.1 */
    int register_mode;   /* SR_INSPECT_REGISTER_* */
    size_t samples;      /* scan samples; 0 = 20000 */
} sr_inspect_opts;

#define SR_INSPECT_ALLOWANCE_MM 0.5
#define SR_INSPECT_TOLERANCE_MM 0.1

typedef struct sr_inspect_section {
    size_t index;              /* the run's section index (0 first) */
    double patch_mm3;          /* the section's missing volume (its patch) */
    double underfill_mm3;      /* restored material inside the patch the scan lacks */
    double underfill_depth_mm; /* largest depth of the scan below the restored surface */
    double overbuild_mm3;      /* scan material above the restored model over the section */
    double stock_min_mm, stock_max_mm, stock_mean_mm; /* over samples above the tolerance;
                                                       * 0 when none */
    double stock_share; /* share of the section's samples above the tolerance */
    double under_share; /* share deeper than the tolerance */
    double dev_mean_mm, dev_rms_mm, dev_min_mm, dev_max_mm; /* signed, all its samples */
    size_t samples;
    sr_inspect_verdict verdict;
    char reasons[256];
} sr_inspect_section;

typedef struct sr_inspect_result {
    double transform[12]; /* scan -> restored model frame (3x4 row-major) */
    int registered;       /* 1: registered; 0: taken as it was */
    double coverage;      /* share of the scan within reg_tol_mm of the model, outside
                               * the sections */
    double reg_tol_mm;
    double allowance_mm, tolerance_mm; /* as used */
    int volumes_exact;                 /* 1: booleans; 0: estimated from the samples */
    char model_note[256];              /* how the restored mesh was taken as one solid
                                        * ("" when it was one: see inspect_model.c) */
    char volume_note[512];             /* why not exact ("the scan is not closed", a boolean's
                            * refusal); "" when exact */
    sr_inspect_section *sections;
    size_t section_count;
    size_t outside_samples; /* samples outside every section */
    double outside_share;   /* of them, the share beyond the tolerance */
    double outside_max_mm;  /* largest |deviation| outside */
    double outside_rms_mm;
    double outside_overbuild_mm3; /* scan material above the model away from the sections */
    sr_inspect_verdict verdict;
    char reasons[512];
    sr_mesh scan;      /* the scan in the model's frame */
    double *deviation; /* scan.vertex_count signed distances to the restored
                               * surface, mm (positive outside) */
} sr_inspect_result;

/* Inspects `scan` (the part after repair) against run `run`'s restored mesh and the
 * patches of its sections (SR_RUN_WITH_MESHES). opts may be NULL. SR_E_INVALID when the
 * run has no restored mesh, a section has no patch, or a mesh fails sr_mesh_validate
 * (named 'restored mesh', 'patch of section K', 'scan'); SR_E_RANGE for a negative or
 * non-finite allowance or tolerance; SR_E_NOMEM. *out only on success; release with
 * sr_inspect_release. */
sr_status sr_inspect_run(const sr_run *run, const sr_mesh *scan, const sr_inspect_opts *opts,
                         sr_inspect_result *out, sr_err *err);

/* The signed distance of each vertex of `scan` (already in the model's frame) to the
 * surface of `model` (positive outside) into dev (scan->vertex_count, the caller's):
 * the deviations of an inspection recomputed from its stored scan and transform, as
 * the report colours them (the same figures as sr_inspect_result's deviation for
 * those vertices). SR_E_INVALID when the model has no triangle with an area; SR_E_NOMEM. */
sr_status sr_inspect_deviations(const sr_mesh *model, const sr_mesh *scan, double *dev,
                                sr_err *err);

/* The colour scale of deviations (the report's legend and view, the GLB's vertex
 * colours): SR_INSPECT_SCALE_STOPS (deviation mm, 0xRRGGBB sRGB) stops, left to right,
 * linear between them, the end colours beyond: deep blue at -range to light blue at
 * -tolerance (material short), green over the tolerance band, yellow at +tolerance to
 * red at +range (stock). The range is the larger of twice the allowance and five
 * tolerances (1.0 when that is not positive). */
#define SR_INSPECT_SCALE_STOPS 6
double sr_inspect_scale_range(double tolerance_mm, double allowance_mm);
void sr_inspect_scale(double tolerance_mm, double allowance_mm, double at[SR_INSPECT_SCALE_STOPS],
                      unsigned rgb[SR_INSPECT_SCALE_STOPS]);
/* The colour of deviation d on that scale, sRGB components in 0..1. */
void sr_inspect_colour(double tolerance_mm, double allowance_mm, double d, float rgb[3]);

/* Frees the arrays of a result and zeroes it; accepts NULL. */
void sr_inspect_release(sr_inspect_result *r);

#endif
