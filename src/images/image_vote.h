/*
 * image_vote.h: the symmetry's vote on a voxel grid, the first half of the image
 * method (image_restore.h). The scan's occupancy (voxels.h) is compared with its own
 * images under the symmetry: a voxel the scan lacks is missing when the images say it
 * is material:
 *   mirror   (x, y, z) -> (-x, y, z): its one image;
 *   glide    (x, y, z) -> (-x, y, z +- shift): both images, where they fall inside the
 *            part's length (one alone near an end): a notch at an end of the rail,
 *            which only one of them explains, is not filled;
 *   n-fold   the n - 1 turns by 360k/n: all of them but one in ten (so a wrong order,
 *            whose turns land in gaps, fills nothing);
 *   axial    24 turns by 15 degrees: at least 60 % of them (a key, which few turns
 *            carry, is not spread round the circle).
 * The missing voxels are opened (eroded, then grown back, by one voxel) so the shells
 * a surface and its image leave against each other through noise or the grid's
 * rounding are dropped, and grouped into 26-connected sections.
 */
#ifndef SR_IMAGE_VOTE_H
#define SR_IMAGE_VOTE_H

#include <stddef.h>
#include <stdint.h>

#include "images/voxels.h"
#include "base/status.h"
#include "base/symmetry.h"

/* One image of the symmetry: p -> R p + t (3x4 row-major), a rigid motion of the
 * aligned frame that maps the intact part onto itself. */
typedef enum sr_image_form {
    SR_IMAGE_GENERAL = 0, /* any rigid motion */
    SR_IMAGE_TURN_Z,      /* a turn about z: inv's z row and z column are (0 0 1 0) */
    SR_IMAGE_REFLECT_X    /* x -> -x, then a shift along z (inv[11]; 0 for a mirror) */
} sr_image_form;

typedef struct sr_image {
    double xf[12];       /* the image: a point of the part -> its image */
    double inv[12];      /* its inverse: where a voxel's material comes from */
    sr_image_form form;  /* what inv is, so sr_image_material skips its zero terms (the
                          * same sums: a zero or unit term changes no bit of them) */
} sr_image;

/* The images the vote uses for `sym` (aligned frame: axis z, plane x = 0, shift along
 * z). *out malloc'd, *count >= 1; SR_E_RANGE for a symmetry without images (glide
 * without a shift). */
sr_status sr_images_of(const sr_symmetry *sym, sr_image **out, size_t *count, sr_err *err);

/* Material at the preimage of voxel centre c under image `im`: 1 inside, 0 outside
 * (also outside the grid), -1 when the image is not valid there (glide: the preimage
 * lies beyond the part's ends z_lo..z_hi). */
int sr_image_material(const sr_voxels *scan, const sr_image *im, const double c[3],
                      double z_lo, double z_hi, int glide);

typedef struct sr_vote_result {
    int *label;          /* per voxel: 0 = not missing, k >= 1 = section k */
    size_t sections;     /* labels 1..sections, largest first */
    size_t *voxels;      /* per section (index k - 1): its voxel count */
    size_t *at;          /* the voxels labelled (> 0) when the vote returned, ascending:
                          * every voxel a section holds is among them, also after the
                          * caller sets labels to -1 or renumbers them */
    size_t at_count;
    uint8_t *weak_only;  /* per section: 1 = a glide core of weak evidence alone (the
                          * image from the middle's side): an end of the pattern or a
                          * feature of the ends broken off; the caller decides */
    uint8_t *weak;       /* glide (else NULL): per voxel of at (index q), 1 when only the
                          * image from the middle's side said material there */
    int misfit_located;  /* 1: misfit_where holds where the median image's misfit lies */
    double misfit_where[4]; /* the central 80 % of those voxels: distance from the axis
                             * (axial) or the plane (planar) from, to; z from, to (mm,
                             * aligned frame) */
    double misfit;       /* the scan's share (of its voxels) an image lacks, median
                          * over the images: the damage's share on a part that has the
                          * symmetry, far more on one that has not */
} sr_vote_result;

/* Votes, opens and groups (see above). scan's bit 0 is the occupancy; z_lo..z_hi the
 * part's extent along z (glide validity); min_voxels: sections with fewer voxels after
 * the opening are dropped; threads: the vote's threads (0: OpenMP's default, all
 * cores), the result the same for any number. *out is zeroed first and filled only on
 * success. */
sr_status sr_vote_missing(const sr_voxels *scan, const sr_symmetry *sym, double z_lo,
                          double z_hi, size_t min_voxels, int threads, sr_vote_result *out,
                          sr_err *err);

void sr_vote_result_release(sr_vote_result *r);

#endif
