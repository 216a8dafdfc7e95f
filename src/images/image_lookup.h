/*
 * image_lookup.h: where each image of the symmetry takes a voxel of the grid, as
 * tables, so the vote (image_vote.c) reads its images' material a byte at a time.
 *
 * A turn about z and a reflection in x (then a shift along z) move a voxel centre's x
 * and y by its column alone and its z by its layer alone, and sr_voxels_locate rounds
 * each coordinate by itself: so an image's preimage voxel is a column table and a
 * layer table, computed once by sr_image_material's own arithmetic. Every answer is
 * sr_image_material's, bit for bit; the rotation's products and the rounding are left
 * out of the vote's hundred million calls.
 */
#ifndef SR_IMAGE_LOOKUP_H
#define SR_IMAGE_LOOKUP_H

#include <stddef.h>
#include <stdint.h>

#include "images/image_vote.h"
#include "images/voxels.h"

/* The vote's budget for the column tables (bytes); beyond it, no tables (a flat disc
 * on a fine grid with 23 turns would take hundreds of MB). */
#define SR_IMAGE_LOOKUP_BUDGET ((size_t)64 << 20)

typedef struct sr_image_lookup_one {
    int32_t *col; /* per column j nx + i: the preimage's column, -1 outside the grid */
    int32_t *lay; /* per layer k: the preimage's layer, -1 outside the grid, -2 beyond
                   * the part's ends (glide validity) */
} sr_image_lookup_one;

typedef struct sr_image_lookup {
    size_t count;   /* images */
    size_t nx, nxy; /* the grid's row and layer sizes */
    sr_image_lookup_one *image;
} sr_image_lookup;

/* The tables of the n images on `scan` (z_lo, z_hi, glide as sr_image_material takes
 * them); NULL when an image is neither a turn about z nor a reflection in x, when the
 * tables would pass budget bytes, or when memory is short: the caller then asks
 * sr_image_material. */
sr_image_lookup *sr_image_lookup_make(const sr_voxels *scan, const sr_image *im, size_t n,
                                      double z_lo, double z_hi, int glide, size_t budget);

/* Frees; accepts NULL. */
void sr_image_lookup_free(sr_image_lookup *l);

/* sr_image_material of image q at voxel (i, j, k) of the grid the tables were made on:
 * 1 material, 0 air or outside the grid, -1 not valid (glide, beyond the ends). */
static inline int sr_image_lookup_material(const sr_image_lookup *l, const sr_voxels *scan,
                                           size_t q, size_t i, size_t j, size_t k)
{
    int32_t kk = l->image[q].lay[k];
    if (kk == -2)
        return -1;
    int32_t cc = l->image[q].col[j * l->nx + i];
    if (kk < 0 || cc < 0)
        return 0;
    return scan->v[(size_t)kk * l->nxy + (size_t)cc] & 1;
}

#endif
