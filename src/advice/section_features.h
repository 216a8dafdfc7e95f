/*
 * section_features.h (not features.h: that name would shadow glibc's <features.h>
 * under -Isrc; the functions keep the sr_features_ prefix): the feature-level description of the missing sections of a run (the
 * paper's "higher feature-level description of missing sections", section 7, which
 * feeds the repair advice of its Figure 8): where each section is (layers, z range,
 * angular range or side and extent from the plane, and where on the part: shoulder,
 * end face, body; ear, arm, edge for planar parts), how deep, how large, how much of
 * the part, and what kind of damage it is, with the reasons for that class.
 *
 * Input is a run record (catalog_runs.h) as the reconstruction leaves it: its sections
 * with their figures, and the per-layer polyline pairs (layer_count x sectors x (x, y)
 * in the aligned frame, NaN = no point). A section's own cells are found again on that
 * grid: the sectors of its angular range (axial; planar: the sectors on its side of the
 * plane x = 0, and of its range when it has one), in its layers, where the restored
 * radius exceeds the damaged one (a damaged sector without a point counts radius 0). The
 * restored outline along z (at the section's own sectors) gives the part's features.
 * Pure C, no I/O; the same run gives byte-identical JSON.
 *
 * Figures (all in mm, mm^2, mm^3, degrees):
 *   local_radius_mm  largest restored radius over the section's cells;
 *   depth_fraction   depth_max / local_radius;
 *   circ_width_mm    mean over the section's layers of the lost arc at the restored
 *                    surface (sum over the layer's cells of r_restored * sector angle);
 *   axial_width_mm   mean over the section's sectors of their lost height (cells x dz);
 *   width_mm         min(circ_width, axial_width): the narrow way across the loss;
 *   length_mm        max(arc the section spans at local_radius, its height);
 *   breadth_mm       min(the same two): the section's bounding box is length x breadth;
 *   aspect           length / breadth;
 *   wall_a, wall_b   across the loss's narrow way (z when axial_width < circ_width, else
 *                    round the axis), on each side: the mean over the section's edge
 *                    cells of the neighbour's restored radius / the cell's (capped at 1;
 *                    nothing there = 0). Near 1: the part continues beside the loss (a
 *                    slot or groove in it); small on both sides: the loss goes through
 *                    a thin feature (an ear, a rim, a tooth);
 *   coverage         sectors touched / sectors around (axial: all N; planar: the N/2
 *                    of its side);
 *   layer_loss_max   the largest fraction of one layer's restored cross-section that the
 *                    section removes (polar areas (r_o^2 - r_i^2)/2 sin(2 pi/N) per cell);
 *   part_fraction    volume / the part's volume.
 * Without per-layer outlines the cell figures fall back to the section's angular range
 * and height at the part's radius (if given), and layer_loss_max is unknown (NaN,
 * written null); the reasons say so.
 *
 * Classes, tried in this order (the first that holds wins; each test's figures are in
 * the reasons, and so are the failed tests before it, so a reader sees why the others
 * were not chosen):
 *   crack          width_mm <= SR_FEAT_CRACK_WIDTH_RATIO * depth_max, and the part
 *                  on both sides of it (wall_a, wall_b >= SR_FEAT_WALL_RATIO, 0.9): a
 *                  loss much narrower than it is deep, cut into the part. 0.5, not
 *                  smaller, because the grid overstates widths by up to one sector or
 *                  layer; a real crack is far narrower than the ratio. Without the walls
 *                  a thin ear broken off would look like a crack (measured on the
 *                  shared bracket part: 8 mm thick, 59 mm deep).
 *   broken_feature depth_fraction >= SR_FEAT_BROKEN_DEPTH_FRACTION (0.4) or
 *                  layer_loss_max >= SR_FEAT_BROKEN_LAYER_LOSS (0.25): deep against the
 *                  local radius, or a quarter of some cross-section gone: the part has
 *                  lost load-carrying section and the feature is missing rather than
 *                  damaged at the surface. 0.25 applies the paper's 25 % volume limit
 *                  (section 1) to one layer; 0.4 of the radius is symrec's choice: a
 *                  loss that deep reaches well into the core, not just the surface.
 *                  Also when the loss goes through a thin feature (wall_a and wall_b
 *                  both < 0.9) and is at least as deep as the feature is thick
 *                  (depth_max >= width_mm): a rim, ear or tooth is gone, not nicked.
 *   wear_band      coverage >= SR_FEAT_WEAR_COVERAGE (0.75) and depth_fraction <=
 *                  SR_FEAT_WEAR_DEPTH_FRACTION (0.1): a shallow loss all or most of the
 *                  way round, the signature of running contact (journals, seal seats),
 *                  not of an impact.
 *   gouge          aspect >= SR_FEAT_GOUGE_ASPECT (3): its bounding box is long in one
 *                  direction, narrow in the other (a diagonal gouge has a squarish box
 *                  and is called a chip); 3 follows the usual NDT convention (e.g. ASME BPVC
 *                  Section V/VIII) that an indication is "linear" when its length
 *                  exceeds three times its width.
 *   chip           otherwise: a local loss, short in z and in angle, shallow to moderate.
 *
 * Locations (features_json.locations, the first is features_json.location):
 *   shoulder   the restored radius at the section's sectors steps by more than
 *              SR_FEAT_STEP_FRACTION (5 %) of the radius (and more than 0.2 mm) between
 *              two adjacent layers within the section's layers or the
 *              max(2, ceil(depth_max / dz)) layers next to them: a step or fillet of the
 *              part is at or beside the loss (a chip at a corner reaches about its own
 *              depth along z);
 *   end_face   the section reaches the first or last layer that has a restored point;
 *   planar:  ear / arm / edge by position = the largest |x| of the section's restored
 *              points over the part's largest |x| in the section's layers on that side:
 *              >= 2/3 ear (the part's outermost features sideways from the plane, where
 *              lugs and ears are), >= 1/3 arm, else edge (the outline near the plane).
 *   body       none of the above (the outer surface of a plain stretch).
 * Bores: the outline is the outermost surface of each sector (paper Alg. 1/2), so an
 * inner surface is never seen and "bore"/"inner" cannot be told; surface is always
 * "outer".
 */
#ifndef SR_SECTION_FEATURES_H
#define SR_SECTION_FEATURES_H

#include <stdbool.h>
#include <stddef.h>

#include "run/run.h"
#include "base/status.h"

#define SR_FEAT_CRACK_WIDTH_RATIO 0.5
#define SR_FEAT_BROKEN_DEPTH_FRACTION 0.4
#define SR_FEAT_BROKEN_LAYER_LOSS 0.25
#define SR_FEAT_WEAR_COVERAGE 0.75
#define SR_FEAT_WEAR_DEPTH_FRACTION 0.1
#define SR_FEAT_GOUGE_ASPECT 3.0
#define SR_FEAT_WALL_RATIO 0.9
#define SR_FEAT_STEP_FRACTION 0.05
#define SR_FEAT_STEP_MIN_MM 0.2

#define SR_FEAT_MAX_REASONS 8
#define SR_FEAT_MAX_LOCATIONS 3

/* What is known of the whole part; zeroed = nothing. */
typedef struct sr_feature_part {
    double volume_mm3;          /* intact (or restored) volume; <= 0 = unknown */
    double radius_mm;           /* largest radius from the axis, used only when the run
                                 * has no per-layer outlines; <= 0 = unknown */
} sr_feature_part;

/* The description of one section. Unknown figures are NaN. */
typedef struct sr_features {
    size_t section;             /* index into run->sections */
    bool axial;                 /* the section has an angular range */
    bool have_cells;            /* the per-layer outlines were there to measure */
    size_t layer_first, layer_last, layer_count;
    double z_min_mm, z_max_mm, height_mm;
    double angle_min_deg, angle_max_deg, arc_deg;   /* axial (max may exceed 360) */
    int side;                                       /* planar: +1 / -1; 0 axial */
    double extent_min_mm, extent_max_mm;            /* planar: |x| range of the loss */
    double position;                                /* planar: see locations above */
    double depth_max_mm, depth_mean_mm, volume_mm3, area_mm2;
    double part_fraction;
    double local_radius_mm, depth_fraction;
    double circ_width_mm, axial_width_mm, width_mm, length_mm, breadth_mm, aspect;
    double wall_a, wall_b;      /* beside the loss across its narrow way (below/above, or
                                 * clockwise/counter-clockwise); see the figures */
    double coverage, layer_loss_max;
    size_t cell_count;
    double shoulder_z_mm;       /* where the step is; NaN if no shoulder */
    char locations[SR_FEAT_MAX_LOCATIONS][16];
    size_t location_count;
    char damage_class[32];
    char reasons[SR_FEAT_MAX_REASONS][200];
    size_t reason_count;
} sr_features;

/* Describes section `index` of `run` (figures, locations, class, reasons).
 * SR_E_RANGE if index is out of range or the run's grid is inconsistent (a section's
 * layers beyond layer_count, outlines without layer_z); *out only on success. */
sr_status sr_features_compute(const sr_run *run, size_t index, const sr_feature_part *part,
                              sr_features *out, sr_err *err);

/* The description as one JSON object (heap; free()): the figures above under their
 * names, plus "class", "location", "locations", "surface", "layers" {first, last,
 * count} and "reasons". SR_E_NOMEM only. */
sr_status sr_features_to_json(const sr_features *f, char **out, sr_err *err);

/* A numeric figure by its JSON key ("depth_max_mm", "arc_deg", "aspect", ...), for
 * rule conditions. Returns false when the name is not a figure or the figure is
 * unknown for this section (NaN, or an axial figure of a planar section). */
bool sr_features_value(const sr_features *f, const char *name, double *out);

/* True when `name` is the key of a numeric figure of some section. */
bool sr_features_is_figure(const char *name);

/* True when the section lies at `location` (one of the names above). */
bool sr_features_at(const sr_features *f, const char *location);

/* Computes every section of `run` and writes its damage_class and features_json
 * (replacing and freeing what was there). All or nothing: on failure the run is
 * untouched. */
sr_status sr_features_describe(sr_run *run, const sr_feature_part *part, sr_err *err);

#endif
