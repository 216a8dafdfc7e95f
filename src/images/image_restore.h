/*
 * image_restore.h: the "image" reconstruction method (reconstruct.h), restoring in 3D
 * with the symmetry's own images of the scan and exact booleans, instead of layer by
 * layer:
 *
 *  1. the aligned scan's occupancy on a voxel grid (voxels.h) is voted by its images
 *     under the symmetry; the missing voxels, opened and grouped, are the sections
 *     (image_vote.h): where they are, nothing else;
 *     On an axis, a candidate whose walls all face along the axis's frame (an axial
 *     or radial hole, a keyway: a recess of the design that the turns do not carry)
 *     is kept as it is, not filled;
 *  2. each section's clip body is the convex hull of its voxels grown by two voxels
 *     (bridge/hull.h); a damage is a convex cutter's bite out of the part, so the hull
 *     holds the loss and little of the intact surface;
 *  3. the image of the scan that carries the material there (the one whose voxels best
 *     cover the section and agree with the scan around it; more than one only when no
 *     one image covers it) is clipped to the hull, Q = g(scan) ∩ hull, by CGAL;
 *  4. the section's patch is exactly Q \ scan and the restored part scan ∪ Q, both
 *     from one corefinement (bridge/boolean.h sr_boolean_union_local_split, run by
 *     reconstruct_union.c), so the patch never overlaps the scan and holds what the
 *     union added, to the triangle;
 *  5. the section's figures come from its patch (volume, z and angular range,
 *     sr_image_section_figures) and its voxels (depth of build-up from the fracture,
 *     lost surface area).
 * Right by construction: an image of the scan lies inside the intact part wherever the
 * symmetry holds, so the patch can only hold what the scan lacks of it.
 */
#ifndef SR_IMAGE_RESTORE_H
#define SR_IMAGE_RESTORE_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "paper/patch.h"
#include "slice/slice.h"
#include "base/status.h"
#include "base/symmetry.h"

typedef struct sr_image_opts {
    sr_symmetry symmetry;       /* glide: shift_mm > 0 */
    double pitch_mm;            /* voxel pitch; 0 = from the part's size */
    double min_volume_mm3;      /* smallest section kept; 0 = 1 mm^3 */
    double min_depth_mm;        /* shallowest section kept; 0 = any */
    int threads;                /* the vote's threads; 0 = all cores (same result) */
    double noise_mm;            /* the scan's noise (sigma, mm); 0 = a clean mesh */
} sr_image_opts;

typedef struct sr_image_info {
    double pitch_mm;            /* the voxel pitch used */
    size_t voxels;              /* grid size */
    double vote_s, patch_s;     /* seconds: occupancy + vote, hulls + booleans */
    size_t mended_tris;         /* scan triangles replaced where it crossed itself */
    size_t axis_pins;           /* axial: seams on the axis closed by a pin (axis_seam.h) */
    size_t features_kept;       /* axial: candidate sections read as holes, slots or
                                 * keyways of the design (kept, not filled) */
    double misfit;              /* image_vote.h: share of the scan its images lack */
    int misfit_located;         /* 1: misfit_where is set */
    double misfit_where[4];     /* where it lies (image_vote.h): from-to distance from the
                                 * axis or plane, from-to z, mm, aligned frame */
    int poor_fit;               /* 1: misfit beyond what the sections found explain
                                 * (reconstruct.c): the part does not fit the symmetry */
    size_t continued;           /* mirror/glide: sections through the plane carried on
                                 * by continuity along z (reconstruct.c) */
    size_t unbuilt;             /* sections the vote found that gave no patch: no image
                                 * carried them, no hull, or the scan's images clipped
                                 * to nothing closed (a scan not closed there) */
    double unbuilt_mm3;         /* their volume by voxels */
    size_t both_sides;          /* mirror: regions lost on both sides of the plane, built
                                 * from their voxels (images_int.h) */
} sr_image_info;

/* Runs steps 1-3 and the voxel figures of 5 on the aligned scan. grid gives the layer
 * and sector indices of the sections' figures. Writes the sections, largest first, each
 * with patch = its clipped image Q (aligned frame) for the caller's split union to turn
 * into Q \ scan. info may be NULL. Outputs only on success; zero sections is a
 * success. */
sr_status sr_image_reconstruct(const sr_mesh *aligned, const sr_layer_grid *grid,
                               const sr_image_opts *opts, sr_section **sections,
                               size_t *count, sr_image_info *info, sr_err *err);

/* *out = q \ aligned by a whole-mesh boolean (either operand mended near the other
 * where it crosses itself): a section's patch when its union with the scan was
 * refused. mended (may be NULL) adds the triangles replaced. */
sr_status sr_image_patch_alone(const sr_mesh *q, const sr_mesh *aligned, sr_mesh *out,
                               size_t *mended, sr_err *err);

/* A closed piece that crosses itself where near-coincident faces were rounded across
 * each other: its vertices moved apart first (sr_mesh_unfold, 2 um at most), and only
 * what still crosses cut out and filled (sr_mesh_mend_crossings), a fill kept only if
 * it changes the volume by at most max_volume_share of it (a hole's fill can chord a
 * flank). Returns 1 when q is left closed and crossing nowhere; on 0 q may have been
 * changed (the caller drops it or retries). */
int sr_image_uncross(sr_mesh *q, double max_volume_share);

/* A section's z, layer and angular range (and cell count) from its patch (aligned
 * frame): the arc is the smallest one holding every vertex's azimuth. */
void sr_image_section_figures(const sr_layer_grid *grid, sr_section *s);

#endif
