/*
 * images_int.h: the private interface between the files of the image method
 * (image_restore.h). Not for use outside src/images/ (voxels.c, image_vote.c,
 * axis_seam.c and plane_continuation.c need none of it).
 *
 *   image_restore.c  the driver: the voxel grid, the vote's sections merged, the images
 *                    chosen per section, clipped to its hull and united
 *                    (sr_image_reconstruct, sr_image_patch_alone, sr_image_uncross)
 *   section_box.c    one section's voxels in a local box with its band, and its hull
 *   section_kind.c   a recess of the design, and a glide's core bounded by a fracture
 *   both_sides_lost.c a mirror's loss that took a place and its image both
 *   voxel_mesh.c     a set of the grid's voxels as a closed mesh
 *   image_figures.c  a section's figures: from its voxels (depth, lost area) and from
 *                    its patch (sr_image_section_figures)
 */
#ifndef SR_IMAGES_INT_H
#define SR_IMAGES_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "images/image_restore.h"
#include "images/image_vote.h"
#include "images/voxels.h"

#define HULL_GROW 4.5           /* hull corners: voxel half-size + four voxels, in pitches */

/* The centre of voxel v of the grid (aligned frame, mm). */
static inline void sr_img_voxel_centre(const sr_voxels *g, size_t v, double c[3])
{
    size_t i = v % g->nx, j = (v / g->nx) % g->ny, k = v / (g->nx * g->ny);
    c[0] = g->origin[0] + (double)i * g->h;
    c[1] = g->origin[1] + (double)j * g->h;
    c[2] = g->origin[2] + (double)k * g->h;
}

/* ---- a section's local box and hull (section_box.c) ---- */

/* One section's voxels in a local box: sec (1 = in the section), the box's origin in
 * grid indices and its size. */
typedef struct local_box {
    size_t i0, j0, k0, nx, ny, nz;
    uint8_t *sec;      /* 1 section, 2 band (within BAND voxels, not in the section) */
} local_box;

/* The index in b->sec of local voxel (i, j, k), x fastest. */
static inline size_t sr_img_lidx(const local_box *b, size_t i, size_t j, size_t k)
{
    return (k * b->ny + j) * b->nx + i;
}

/* The box round section s of the vote (vr->label[v] == s) with its band; b->sec
 * allocated (the caller frees it). SR_E_RANGE when no voxel is labelled s, SR_E_NOMEM. */
sr_status sr_img_box_make(const sr_voxels *g, const sr_vote_result *vr, int s, local_box *b);

/* The section's hull: the convex hull of its voxels' corners grown by HULL_GROW
 * pitches, z clamped to [z_min, z_max]. */
sr_status sr_img_hull_make(const sr_voxels *g, const local_box *b, double z_min, double z_max,
                           sr_mesh *out, sr_err *err);

/* ---- what a candidate section is (section_kind.c) ---- */

/* Axial: 1 when the scan's surface round section s is a recess of the design (a hole,
 * a slot, a keyway) rather than a fracture. */
int sr_img_design_recess(const sr_mesh *m, const sr_voxels *g, const sr_vote_result *vr, int s);

/* Glide: 1 when the scan's surface facing section s (of weak evidence alone) is mostly
 * fracture, so the section is built; 1 too when the images cannot be had. noise_mm:
 * the scan's noise (sigma), which tilts its facets off the frame. */
int sr_img_fracture_bounded(const sr_mesh *m, const sr_voxels *g, const int *label, int s,
                            const sr_symmetry *sym, double noise_mm);

/* The share (by area) of the scan's facets facing the voxels labelled s that is
 * fracture: without a twin under the symmetry's images, and not along the frame (with
 * continued, only faces of the frame that go on as faces of the part away from every
 * loss count as the design's). dense: triangles longer than a pitch looked at in
 * parts (a thin region beside a coarse mesh's large faces). vbox (i0 j0 k0 i1 j1 k1,
 * or NULL): the voxel indices the labelled voxels lie within, so the parts of a
 * triangle farther away are not looked at (the same answer, the triangles near them
 * alone cut up). 0 when no facet faces them; -1 when out of memory. */
double sr_img_fracture_share(const sr_mesh *m, const sr_voxels *g, const int *label, int s,
                             const sr_symmetry *sym, double noise_mm, bool continued, bool dense,
                             const size_t *vbox);

/* Glide: the regions of weak evidence inside the sections that also hold strong
 * evidence (vr->weak; 26-connected, at least min_voxels), each parted between the
 * design and the fracture by the scan's surface facing it (section_kind.c); the
 * voxels standing in front of a face of the design, when enough go with it (at least
 * min_voxels), are taken out of their section (label -1, its voxel count lowered; no
 * image builds there: image_restore.c cuts them out of the section's images). Returns
 * how many regions lost voxels; 0 when vr has no weak flags or memory runs out
 * (nothing taken). Call it only where the pattern is seen to stop short of an end
 * (image_restore.c). */
size_t sr_img_drop_phantom_ends(const sr_mesh *m, const sr_voxels *g, sr_vote_result *vr,
                                size_t min_voxels, const sr_symmetry *sym, double noise_mm);

/* ---- a loss on both sides of a mirror (both_sides_lost.c) ---- */

/* Mirror: the places the scan and its image both lack between a section's image and a
 * fracture whose image is a section (both_sides_lost.c says how they are found), in
 * 26-connected regions of at least min_voxels whose facing faces are mostly fracture:
 * each region's closed mesh (its voxels grown by two into the material round it)
 * added to fill[s - 1] for the section s it joins (fill: vr->sections meshes, empty
 * or holding earlier pieces). *regions counts them. vr's labels are as they were on
 * return. Anything but a mirror: nothing. SR_E_NOMEM only; a region whose mesh does
 * not close is left out. */
sr_status sr_img_both_sides_lost(const sr_mesh *m, const sr_voxels *g, sr_vote_result *vr,
                                 size_t min_voxels, const sr_symmetry *sym, double noise_mm,
                                 sr_mesh *fill, size_t *regions, sr_err *err);

/* ---- a set of voxels as a mesh (voxel_mesh.c) ---- */

/* The closed mesh of the voxels in box[] (grid indices: i0, j0, k0, i1, j1, k1,
 * inclusive) whose mark has any of bits set: their cubes, united. SR_E_NOMEM, or the
 * stack's error when it does not close; *out only on success. */
sr_status sr_img_marked_mesh(const sr_voxels *g, const uint8_t *mark, uint8_t bits,
                             const size_t box[6], sr_mesh *out, sr_err *err);

/* ---- figures (image_figures.c) ---- */

/* s's depth_max_mm, depth_mean_mm and area_mm2 from the section's voxels in b; left as
 * they are when out of memory. */
void sr_img_voxel_figures(const sr_voxels *g, const local_box *b, sr_section *s);

#endif
