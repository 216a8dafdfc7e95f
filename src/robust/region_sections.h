/*
 * region_sections.h: the "robust" reconstruction core on real cross-sections, between
 * alignment and the boolean union (reconstruct.c calls it instead of the paper's
 * Algorithms 4-6 when opts->method is SR_METHOD_ROBUST):
 *
 *  1. cut the aligned scan into closed contours at every layer centre (and, for a
 *     glide, one shift above and below) (contour_slice.h), cleaned into regions;
 *  2. restore each layer by the vote of the symmetry and take restored minus damaged,
 *     opened against noise, as the layer's missing region (restore_vote.h); layers
 *     whose plane lies within 2 x open_mm of the model's end faces read no damage (a
 *     noisy end face cut by a plane that close gives a ragged partial section); for a
 *     mirror or glide, material lost on both sides of the plane is then carried from
 *     layer to layer up to the feature's own end face (restore_continuity.h);
 *  3. group the missing regions into sections: pieces of consecutive layers that
 *     overlap are one section (so two separate chips are two sections, and a section is
 *     never split by the sector grid); a section of one layer no larger than the flat
 *     faces across z within 2 x open_mm of its planes is a noisy face's ragged cut and
 *     is dropped (layer_flats.h);
 *  4. give each section its figures (z and angular range or side, depth as the largest
 *     distance of its restored outline from the damaged contour, volume = sum of
 *     area x layer thickness) and one closed patch mesh (stack_mesh.h) that encloses
 *     exactly that volume;
 *  5. put the restored outlines on the sector grid (farthest point per sector) so the
 *     run records the same polyline pairs as the paper's method.
 */
#ifndef SR_REGION_SECTIONS_H
#define SR_REGION_SECTIONS_H

#include <stddef.h>

#include "paper/analyse.h"
#include "mesh/mesh.h"
#include "paper/patch.h"
#include "slice/slice.h"
#include "base/status.h"
#include "base/symmetry.h"

typedef struct sr_region_opts {
    sr_symmetry symmetry;       /* glide: shift_mm > 0 */
    double open_mm;             /* noise filter: slivers thinner than 2x are dropped */
    double min_depth_mm;        /* sections shallower than this are dropped */
    double min_volume_mm3;      /* sections smaller than this are dropped */
    double coverage;            /* continuous axial vote; 0 = 0.5 */
    /* a region of interest (aligned frame: min x y z, max x y z), used when have_roi:
     * every layer's cross-section is cut to its box and layers outside it are left
     * empty, so the work is the box's; sections that reach a face of the box where it
     * cuts the part are dropped (not known whole), and no restored outline is made
     * (*analysis is left empty). A mirror's box must be symmetric about x = 0. */
    int have_roi;
    double roi[6];
    /* when set, only the sections it wants get a patch (and are returned): it is given
     * a box holding the section (min x y z, max x y z; a little larger than its patch)
     * and its volume, before the patch is built */
    int (*want)(const double box[6], double volume_mm3, void *ctx);
    void *want_ctx;
} sr_region_opts;

/* Runs steps 1-5 on the aligned scan over the layer grid `grid` (its layers and
 * sectors; the grid holds the damaged outline from sr_slice_accurate). Writes the
 * analysis (restored outline per sector, damaged cells) and the sections with their
 * patches in the aligned frame, largest volume first. *analysis, *sections and
 * *count only on success. */
sr_status sr_region_reconstruct(const sr_mesh *aligned, const sr_layer_grid *grid,
                                const sr_region_opts *opts, sr_analysis *analysis,
                                sr_section **sections, size_t *count, sr_err *err);

#endif
