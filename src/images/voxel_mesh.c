/*
 * voxel_mesh.c: the closed mesh of a set of voxels of the image method's grid
 * (images_int.h, sr_img_marked_mesh): each layer's voxels as a region of the plane (a
 * rectangle per run along x, united), stacked (robust/stack_mesh.h). Used for a loss
 * on both sides of a mirror (both_sides_lost.c) and for the places the vote judged
 * the design's, cut out of a section's clipped images (image_restore.c).
 */
#include <stdlib.h>

#include "bridge/polygon.h"
#include "images/images_int.h"
#include "robust/stack_mesh.h"

/* Layer k's voxels in box[] with any of bits set in mark, as a region of the plane. */
static sr_status layer_region(const sr_voxels *g, const uint8_t *mark, uint8_t bits, size_t k,
                              const size_t box[6], sr_poly2 *out, sr_err *err)
{
    sr_poly2 raw;
    sr_poly2_init(&raw);
    double h = g->h;
    sr_status st = SR_OK;
    for (size_t j = box[1]; st == SR_OK && j <= box[4]; j++) {
        size_t i = box[0];
        while (i <= box[3]) {
            if (!(mark[sr_voxel_index(g, i, j, k)] & bits)) {
                i++;
                continue;
            }
            size_t i0 = i;
            while (i <= box[3] && (mark[sr_voxel_index(g, i, j, k)] & bits))
                i++;
            double x0 = g->origin[0] + ((double)i0 - 0.5) * h,
                   x1 = g->origin[0] + ((double)i - 0.5) * h,
                   y0 = g->origin[1] + ((double)j - 0.5) * h, y1 = y0 + h;
            double xy[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
            st = sr_poly2_add_contour(&raw, xy, 4, err);
        }
    }
    if (st == SR_OK)
        st = sr_poly2_boolean(SR_POLY_UNION, &raw, NULL, out, err);
    sr_poly2_release(&raw);
    return st;
}

sr_status sr_img_marked_mesh(const sr_voxels *g, const uint8_t *mark, uint8_t bits,
                             const size_t box[6], sr_mesh *out, sr_err *err)
{
    size_t layers = box[5] - box[2] + 1;
    sr_poly2 *reg = calloc(layers, sizeof *reg);
    double *z = malloc((layers + 1) * sizeof *z);
    sr_status st = reg && z ? SR_OK : sr_err_set(err, SR_E_NOMEM, "out of memory");
    for (size_t l = 0; st == SR_OK && l < layers; l++) {
        sr_poly2_init(&reg[l]);
        st = layer_region(g, mark, bits, box[2] + l, box, &reg[l], err);
    }
    for (size_t l = 0; st == SR_OK && l <= layers; l++)
        z[l] = g->origin[2] + ((double)(box[2] + l) - 0.5) * g->h;
    /* runs of identical layers stacked as one: the same solid, its walls no longer cut
     * at every voxel layer */
    size_t runs = layers;
    if (st == SR_OK)
        st = sr_stack_merge_identical(reg, z, &runs, err);
    if (st == SR_OK)
        st = sr_stack_mesh_pulled_in(reg, z, runs, out, err);
    for (size_t l = 0; reg && l < layers; l++)
        sr_poly2_release(&reg[l]);
    free(reg);
    free(z);
    return st;
}
