/*
 * plan.h: the build plan for one missing section of a reconstruction run: how to put
 * the lost material back layer by layer by directed energy deposition or spray forming
 * (the paper's repair advice, its Figure 8: a tool path per layer).
 *
 * Input: a run (catalog_runs.h's sr_run) with its per-layer polyline pairs in the
 * aligned frame (damaged outline Polylines(0,.) and restored outline Polylines(1,.),
 * one point per polar sector, NaN = none) and one of its sections. For every run layer
 * the section covers, the missing region is
 *     M = (restored outline polygon  minus  damaged outline polygon)  within  W
 * where W is the section's angular wedge (axial: [from, to] widened by half a sector
 * each side, because the restored outline tapers back to the surface between the last
 * damaged sector's centre and the next sector's centre) or its half-plane (planar:
 * side +1 is x > 0 of the aligned frame, where the symmetry plane is x = 0). A sector
 * without a point is left out of its polygon (its neighbours are joined by a chord).
 * The deposit region is G = (M grown by the machining allowance, round joins) minus the
 * damaged outline: extra stock to machine back, never inside the part that is left.
 * All polygon work goes through bridge/polygon.h (Clipper).
 *
 * Build direction: +z of the aligned frame, i.e. along the symmetry axis (axial) or the
 * plane's in-plane axis (planar): the part stands with that axis vertical and each
 * layer is a horizontal slice of the section, deposited as a planar path at the
 * layer's top height. (Building radially outward would need curved layers on the
 * cylinder; the run's layers are planar slices, so the plan keeps them.)
 *
 * Layers: thickness = opts.layer_mm, or the run's layer spacing when 0; the section's
 * slab [z_min, z_max] is cut into ceil(height / thickness) plan layers from z_min up.
 * A plan layer's missing region is the union of the missing regions of the run layers
 * whose slabs overlap it (more than 1e-6 mm), so with a different thickness nothing
 * missing is left out (resampling by union; with the run's spacing it is one to one).
 * The allowance is added in the plane only, not above the top layer.
 *
 * Paths per layer, in deposition order (step-over s = bead spacing):
 *   SR_PLAN_CONTOUR_RASTER (default): one ring at G offset inwards by s/2, then a
 *     raster clipped to G offset inwards by 3s/2;
 *   SR_PLAN_CONTOUR: rings at G offset inwards by (k + 1/2) s, k = 0, 1, ... until empty;
 *   SR_PLAN_RASTER: a raster clipped to G offset inwards by s/2.
 * The raster is parallel lines s apart at the layer's angle (opts.raster_angle_deg,
 * plus 90 degrees on every other layer), chained nearest end first into a zig-zag:
 * two consecutive pieces are joined by a deposition move when the join is at most 2s
 * long and lies inside G, else they are separate paths (the tool travels between them).
 * A region thinner than the step-over (the offsets are empty) gets a raster clipped to
 * G itself, so no layer with material to deposit is left without a path. Every path
 * point lies inside G, hence inside M grown by the allowance (tests/test_plan.c).
 *
 * Figures: missing volume = sum of area(M) x thickness; deposit volume = sum of
 * area(G) x thickness (what is built, allowance included); deposit mass = deposit
 * volume x density. Build time = the time of the moves the G-code makes
 * (plan_export.h's sr_plan_time): deposition length / feed plus travel length / rapid
 * rate. The feed, unless the machine settings give one, is the one that lays the
 * deposition rate down as beads of step-over x layer: rate / (step-over x layer), so
 * the path deposits the volume the rate says in the time it takes.
 *
 * Settings from the advice (plan_advice.c): the rule that advised a section gives its
 * process and its parameters (rule parameters_json, copied into the advice): layer_mm,
 * step_over_mm, allowance_mm, and deposition_rate_g_min x efficiency / density as the
 * rate. sr_plan_follow_advice puts them into the options; what the user gives on top
 * overrides them.
 */
#ifndef SR_PLAN_H
#define SR_PLAN_H

#include <stddef.h>
#include <stdint.h>

#include "bridge/polygon.h"
#include "run/run.h"
#include "base/status.h"

typedef enum sr_plan_pattern {
    SR_PLAN_CONTOUR_RASTER = 0, /* one contour ring, raster infill */
    SR_PLAN_CONTOUR,            /* contour-parallel rings only */
    SR_PLAN_RASTER,             /* zig-zag raster only */
} sr_plan_pattern;

/* "contour+raster", "contour", "raster". */
const char *sr_plan_pattern_name(sr_plan_pattern pattern);

/* Parses a pattern name; SR_E_RANGE naming `field` otherwise. */
sr_status sr_plan_pattern_parse(const char *text, const char *field, sr_plan_pattern *out,
                                sr_err *err);

/* Plan parameters, valid when zeroed: a 0 takes the default named below (resolved by
 * sr_plan_build). The one exception is the allowance, where 0 is a real setting (no
 * allowance): sr_plan_opts_init (and opts NULL) give the suggested 0.5 mm. */
typedef struct sr_plan_opts {
    double step_over_mm;      /* bead spacing, > 0; 0 = 1.0 */
    double allowance_mm;      /* machining allowance, >= 0; 0 = none; init: 0.5 */
    double layer_mm;          /* layer thickness, > 0, or 0 = the run's layer spacing */
    double density_g_cm3;     /* deposit density, > 0; 0 = 7.85 (steel) */
    double rate_cm3_min;      /* deposition rate, > 0; 0 = 1.0 (about 0.5 kg/h of
                               * steel, a usual powder DED rate) */
    double raster_angle_deg;  /* raster angle of the first layer (finite); default 0;
                               * every other layer adds 90 */
    sr_plan_pattern pattern;  /* default (0) SR_PLAN_CONTOUR_RASTER */
} sr_plan_opts;

#define SR_PLAN_MAX_LAYERS 100000 /* refused beyond: a thickness far too small */

/* Fills the defaults above, the 0.5 mm allowance included. */
void sr_plan_opts_init(sr_plan_opts *opts);

/* Range checks (a 0 that stands for a default passes); SR_E_RANGE naming the field
 * ("step_over_mm must be > 0 (or 0 for 1 mm) and <= 10000, got -1"). */
sr_status sr_plan_opts_check(const sr_plan_opts *opts, sr_err *err);

enum {
    SR_PLAN_PATH_RING = 1,    /* a closed contour ring (last point repeats the first) */
    SR_PLAN_PATH_RASTER = 2,  /* an open zig-zag raster run */
};

typedef struct sr_plan_layer {
    double z_bottom_mm, z_top_mm; /* the layer's slab, aligned frame; deposited at top */
    size_t run_layer_first, run_layer_last; /* the run layers it was built from */
    double raster_angle_deg;
    sr_poly2 damaged;         /* the damaged outline (of run_layer_first), for drawing */
    sr_poly2 missing;         /* M: what is missing in the section (oriented, clean) */
    sr_poly2 region;          /* G: M grown by the allowance, minus the damaged part */
    sr_poly2 paths;           /* deposition paths in order, as open polylines */
    unsigned char *path_kind; /* paths.contour_count entries: SR_PLAN_PATH_* */
    double missing_area_mm2, region_area_mm2, path_length_mm;
} sr_plan_layer;

typedef struct sr_plan {
    int64_t run_id;
    size_t section_index;     /* 0-based, as sr_run_section.index */
    sr_sym_kind kind;
    int has_angles;           /* axial: the wedge below (degrees, to may exceed 360) */
    double angle_from_deg, angle_to_deg;
    int side;                 /* planar: +1 (x > 0) / -1 (x < 0) */
    double z_min_mm, z_max_mm;
    sr_plan_opts opts;        /* as used, layer_mm filled in */
    size_t layer_count;
    sr_plan_layer *layers;
    double missing_volume_mm3, deposit_volume_mm3; /* mm^3 */
    double deposit_mass_g;
    double build_time_min;   /* deposit_time_min + travel_time_min */
    double deposit_time_min; /* path_length_mm / feed_mm_min */
    double travel_time_min;  /* travel_length_mm / the rapid rate */
    double travel_length_mm; /* the G0 moves between paths */
    double feed_mm_min;      /* deposition feed as used */
    double path_length_mm;
    /* what the plan follows (sr_plan_follow_advice; set by the caller): "" = none */
    char process[64], rule[64];
    double preheat_c; /* NaN = none */
} sr_plan;

/* Where a plan's settings came from: the advice for its section (or the whole part). */
typedef struct sr_plan_advice {
    int found;        /* an advice for the section (or the whole part) exists */
    int builds;       /* its process builds material up (spray_forming, ded,
                                 weld_buildup): a plan can follow it */
    char process[64]; /* "" when none */
    char rule[64];    /* the rule that gave it, "" when unknown */
    unsigned taken;   /* SR_PLAN_FROM_* bits of the settings taken from it */
    double preheat_c; /* preheat of the process on the material; NaN = none */
} sr_plan_advice;

enum {
    SR_PLAN_FROM_LAYER = 1u << 0,
    SR_PLAN_FROM_STEP_OVER = 1u << 1,
    SR_PLAN_FROM_ALLOWANCE = 1u << 2,
    SR_PLAN_FROM_RATE = 1u << 3,
};

/* True for the processes that build material up and so have a build plan. */
int sr_plan_process_builds(const char *process);

/* Reads the advice for run section `section_index` (0-based; a whole-part advice when
 * the section has none) into *out, and, when its process builds up, sets opts'
 * layer_mm, step_over_mm, allowance_mm and rate_cm3_min from its parameters (the rate
 * from deposition_rate_g_min x efficiency, default 1, / opts->density_g_cm3, so set
 * the density first). A parameter the advice lacks is left as it is. SR_E_RANGE naming
 * the rule and the key when a parameter is not a number in range. */
sr_status sr_plan_follow_advice(const sr_run *run, size_t section_index, sr_plan_opts *opts,
                                sr_plan_advice *out, sr_err *err);

/* Builds the plan of the section whose sr_run_section.index is `section_index`. The
 * run must carry its layers (SR_RUN_WITH_LAYERS): SR_E_INVALID "run N has no layer
 * polylines" otherwise, or when its arrays disagree with the section's layer range.
 * SR_E_NOTFOUND "run N has no section K" (K 1-based, as the CLI shows it). SR_E_RANGE
 * from sr_plan_opts_check, or for a section of a run with symmetry NONE, or when the
 * thickness gives more than SR_PLAN_MAX_LAYERS layers. Polygon failures pass through.
 * *out only on success (free with sr_plan_release). opts NULL = sr_plan_opts_init's;
 * the plan's opts hold the values used, every default filled in. */
sr_status sr_plan_build(const sr_run *run, size_t section_index, const sr_plan_opts *opts,
                        sr_plan *out, sr_err *err);

/* Frees a plan's arrays and zeroes it; accepts NULL and a zeroed plan. */
void sr_plan_release(sr_plan *plan);

#endif
