/*
 * restore_continuity.h: continuity along z for the planar symmetries (issue 6, "beyond
 * the paper"), the step after the vote (restore_vote.h) in the robust method.
 *
 * The mirror (glide) vote restores a layer from its image; where a break took material
 * from both sides of the plane, neither image holds it and the vote leaves it missed
 * (the lever's broken boss corner). Then the neighbouring layer decides: material that
 * the restored layer `step_z_mm` below (above) holds and this layer lacks is a
 * candidate; thin slivers (facets, noise) are dropped by an opening of `open_mm`, and
 * each remaining connected piece that reaches within `near_mm` of either layer's
 * damage is carried whole, with its exact outline, or not at all. The scan's surface
 * between the two planes decides, sampled on a grid of `sample_mm` inside the piece,
 * for each sample on the point itself and its symmetry images (mirror: (-x, y); glide:
 * (-x, y) one shift above and below):
 *  - an image leaving material through a flat face (normal within `flat_deg` of z) is
 *    one of the part's own end faces: a vote against carrying;
 *  - the point itself leaving material through an oblique face, at a height where no
 *    image leaves it alike and with no material beyond it further along z, is a
 *    fracture: a vote for. A face the images meet alike (a hole or chamfer across the
 *    plane) or with material beyond it (the far side of a hole) is the part's own and
 *    says nothing; so does a face only an image meets;
 *  - no surface at all, where the reference layer's region was already missing (carried
 *    or restored there) and this layer shows damage of its own next to the piece: the
 *    break goes on, a vote for.
 * A piece is carried when the votes for are at least four times those against (a stray
 * noisy triangle on a fracture does not stop it; an end face under most of the piece
 * does). Carrying goes upwards layer by layer, then downwards, so a break is followed
 * from where it starts to the feature's own end face. Layers without damage nearby are
 * not touched, so an intact part is left as the vote restored it.
 *
 * Limits: a break whose face is itself mirror-symmetric (perpendicular to the plane)
 * looks like the part's own chamfer and is not carried; a hole across the plane whose
 * every mirrored pair has one side broken away could be filled (no image shows it
 * intact), unless its far side remains.
 */
#ifndef SR_RESTORE_CONTINUITY_H
#define SR_RESTORE_CONTINUITY_H

#include <stddef.h>

#include "bridge/polygon.h"
#include "mesh/mesh.h"
#include "base/status.h"
#include "base/symmetry.h"

/* Valid when zeroed but for the symmetry: every 0 is the default named. */
typedef struct sr_continuity_opts {
    sr_symmetry symmetry; /* required: SR_SYM_MIRROR or SR_SYM_GLIDE (shift_mm > 0) */
    double open_mm;       /* carried slivers thinner than 2x are dropped, >= 0; also the
                           * height within which images meet a surface "alike"
                           * (at least 0.01 mm) */
    double near_mm;       /* carried material lies within this of the damage, > 0;
                           * 0 = 3 layer spacings + 0.6 mm (what region_sections.c asks) */
    double flat_deg;      /* end face: normal within this of z; 0 = 20 degrees */
    double sample_mm;     /* decision grid step; 0 = 0.2 mm */
    double step_z_mm;     /* carry from the layer this far away (at least one); 0 = 0.5 */
} sr_continuity_opts;

/* Extends restored[l] and missing[l] (l < layers; planes at z[l], increasing and
 * evenly spaced; regions in the aligned frame of `aligned`, the scan they were cut
 * from) in place: first carrying upwards layer by layer, then downwards. *carried (may
 * be NULL) gets the number of layers that received material. On failure the regions
 * may be partly extended (the caller releases them). Errors: SR_E_RANGE (symmetry not
 * planar, bad option), SR_E_NOMEM. */
sr_status sr_continuity_extend(const sr_mesh *aligned, const double *z, size_t layers,
                               sr_poly2 *restored, sr_poly2 *missing,
                               const sr_continuity_opts *opts, size_t *carried, sr_err *err);

#endif
