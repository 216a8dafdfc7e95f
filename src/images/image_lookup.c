/*
 * image_lookup.c: the symmetry's images as voxel tables (see image_lookup.h).
 */
#include "images/image_lookup.h"

#include <stdlib.h>

void sr_image_lookup_free(sr_image_lookup *l)
{
    if (!l)
        return;
    for (size_t q = 0; l->image && q < l->count; q++) {
        free(l->image[q].col);
        free(l->image[q].lay);
    }
    free(l->image);
    free(l);
}

/* Image im's tables into one (allocated by the caller). */
static void tables_fill(const sr_voxels *scan, const sr_image *im, double z_lo, double z_hi,
                        int glide, sr_image_lookup_one *one)
{
    size_t nx = scan->nx, ny = scan->ny, nz = scan->nz;
    const double *m = im->inv;
    int reflect = im->form == SR_IMAGE_REFLECT_X;
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++) {
            /* the centre and its preimage as sr_image_material computes them */
            double c0 = scan->origin[0] + (double)i * scan->h,
                   c1 = scan->origin[1] + (double)j * scan->h;
            double p0 = reflect ? -c0 : m[0] * c0 + m[1] * c1;
            double p1 = reflect ? c1 : m[4] * c0 + m[5] * c1;
            long a = sr_voxel_axis_index(p0, scan->origin[0], scan->h, nx),
                 b = sr_voxel_axis_index(p1, scan->origin[1], scan->h, ny);
            one->col[j * nx + i] = a < 0 || b < 0 ? -1 : (int32_t)((size_t)b * nx + (size_t)a);
        }
    for (size_t k = 0; k < nz; k++) {
        double c2 = scan->origin[2] + (double)k * scan->h, p2 = reflect ? c2 + m[11] : c2;
        one->lay[k] = glide && (p2 < z_lo || p2 > z_hi)
                          ? -2
                          : (int32_t)sr_voxel_axis_index(p2, scan->origin[2], scan->h, nz);
    }
}

sr_image_lookup *sr_image_lookup_make(const sr_voxels *scan, const sr_image *im, size_t n,
                                      double z_lo, double z_hi, int glide, size_t budget)
{
    size_t nx = scan->nx, ny = scan->ny, nz = scan->nz, nxy = nx * ny;
    if (n == 0 || nxy == 0 || nxy >= ((size_t)1 << 31) || nz >= ((size_t)1 << 31) ||
        n > budget / sizeof(int32_t) / nxy)
        return NULL;
    for (size_t q = 0; q < n; q++)
        if (im[q].form != SR_IMAGE_TURN_Z && im[q].form != SR_IMAGE_REFLECT_X)
            return NULL;
    sr_image_lookup *l = calloc(1, sizeof *l);
    if (!l)
        return NULL;
    l->count = n;
    l->nx = nx;
    l->nxy = nxy;
    l->image = calloc(n, sizeof *l->image);
    if (!l->image) {
        sr_image_lookup_free(l);
        return NULL;
    }
    for (size_t q = 0; q < n; q++) {
        l->image[q].col = malloc(nxy * sizeof(int32_t));
        l->image[q].lay = malloc(nz * sizeof(int32_t));
        if (!l->image[q].col || !l->image[q].lay) {
            sr_image_lookup_free(l);
            return NULL;
        }
        tables_fill(scan, &im[q], z_lo, z_hi, glide, &l->image[q]);
    }
    return l;
}
