/*
 * restore_vote.h: the restored cross-section of each layer by the vote of the part's
 * symmetry (issue "beyond the paper"), on real cut contours (contour_slice.h) in the
 * aligned frame (axis = z through the origin; mirror plane x = 0; glide = mirror
 * x -> -x with a shift along z).
 *
 * Damage only ever removes material, so a point of the plane belongs to the restored
 * section when the symmetry's images agree that it holds material:
 *  - mirror: the layer united with its mirror image;
 *  - glide: the layer united with the mirror images of the cuts one shift above and
 *    one shift below (where the part reaches);
 *  - n-fold axial: the layer united with its rotations by +-1 and +-2 steps of 360/n
 *    degrees (all n - 1 when n <= 5);
 *  - continuous axial: the radii where material covers at least `coverage` of the
 *    circle (a key covers a few percent and is kept as it is but not spread; a bore
 *    covers none and stays empty; a chip leaves most of the circle covered), added only
 *    outside the layer's outer contours, so holes through the part (bolt holes on a
 *    flange) are kept.
 * The missing region of a layer is restored minus damaged, opened by `open_mm`
 * (eroded then grown back) so that slivers thinner than 2 * open_mm from scan noise,
 * facets or alignment residue are not reported as damage.
 */
#ifndef SR_RESTORE_VOTE_H
#define SR_RESTORE_VOTE_H

#include <stddef.h>

#include "bridge/polygon.h"
#include "base/status.h"
#include "base/symmetry.h"

typedef struct sr_vote_opts {
    sr_symmetry symmetry;   /* kind, order (axial n-fold), shift_mm (glide, > 0) */
    double coverage;        /* continuous axial: share of the circle, (0, 1]; 0 = 0.5 */
    double radial_step_mm;  /* continuous axial: radius sampling step; 0 = 0.01 */
    double open_mm;         /* opening radius of the missing regions, >= 0 */
} sr_vote_opts;

/* For each of `layers` layers: damaged[l] is the layer's clean region; for glide,
 * shifted_up[l] / shifted_down[l] are the regions cut one shift above / below (empty
 * where the part does not reach), otherwise they may be NULL. Writes restored[l] and
 * missing[l] (arrays of `layers` regions the caller provides, empty on entry; the
 * caller releases them, also on failure). */
sr_status sr_vote_restore(const sr_poly2 *damaged, const sr_poly2 *shifted_up,
                          const sr_poly2 *shifted_down, size_t layers,
                          const sr_vote_opts *opts, sr_poly2 *restored, sr_poly2 *missing,
                          sr_err *err);

/* Continuous axial only: the share of the circle of radius r (centred on the origin)
 * that lies inside the oriented region (0..1); -1 for r <= 0 or out of memory.
 * Exposed for tests. */
double sr_vote_circle_coverage(const sr_poly2 *region, double r);

#endif
