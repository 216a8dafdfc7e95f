/*
 * section_box.c: one section's voxels in a local box and its hull, for the image
 * method's driver (image_restore.c; images_int.h): the box round a section with the
 * band of BAND voxels about it (sr_img_box_make, a dilation axis by axis), and the
 * section's convex hull grown by HULL_GROW voxels (sr_img_hull_make), the clip body
 * of its images.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "bridge/hull.h"
#include "images/images_int.h"

#define BAND 2                  /* voxels around a section where images are compared */

/* out[i] = 1 where in has a 1 within BAND steps of i along a line of len voxels,
 * stride apart (a running count over the window). */
static void dilate_line(const uint8_t *in, uint8_t *out, size_t len, size_t stride)
{
    long n = (long)len, ones = 0;
    for (long i = 0; i < BAND && i < n; i++)
        ones += in[(size_t)i * stride];
    for (long i = 0; i < n; i++) {
        if (i + BAND < n)
            ones += in[(size_t)(i + BAND) * stride];
        if (i - BAND - 1 >= 0)
            ones -= in[(size_t)(i - BAND - 1) * stride];
        out[(size_t)i * stride] = ones > 0;
    }
}

sr_status sr_img_box_make(const sr_voxels *g, const sr_vote_result *vr, int s, local_box *b)
{
    const int *label = vr->label;
    size_t lo[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX}, hi[3] = {0, 0, 0};
    for (size_t q = 0; q < vr->at_count; q++) {
        size_t v = vr->at[q];
        if (label[v] != s)
            continue;
        size_t ijk[3] = {v % g->nx, (v / g->nx) % g->ny, v / (g->nx * g->ny)};
        for (int a = 0; a < 3; a++) {
            if (ijk[a] < lo[a]) lo[a] = ijk[a];
            if (ijk[a] > hi[a]) hi[a] = ijk[a];
        }
    }
    if (lo[0] == SIZE_MAX)
        return SR_E_RANGE; /* no voxel left (a design recess taken out) */
    size_t n[3] = {g->nx, g->ny, g->nz};
    for (int a = 0; a < 3; a++) {
        lo[a] = lo[a] >= BAND ? lo[a] - BAND : 0;
        hi[a] = hi[a] + BAND < n[a] ? hi[a] + BAND : n[a] - 1;
    }
    b->i0 = lo[0];
    b->j0 = lo[1];
    b->k0 = lo[2];
    b->nx = hi[0] - lo[0] + 1;
    b->ny = hi[1] - lo[1] + 1;
    b->nz = hi[2] - lo[2] + 1;
    b->sec = calloc(b->nx * b->ny * b->nz, 1);
    if (!b->sec)
        return SR_E_NOMEM;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++)
                if (label[sr_voxel_index(g, b->i0 + i, b->j0 + j, b->k0 + k)] == s)
                    b->sec[sr_img_lidx(b, i, j, k)] = 1;
    /* the band: within BAND voxels (a cube) of the section, a dilation axis by axis */
    size_t nb = b->nx * b->ny * b->nz;
    uint8_t *m = malloc(nb), *t = malloc(nb);
    if (!m || !t) {
        free(m);
        free(t);
        free(b->sec);
        b->sec = NULL;
        return SR_E_NOMEM;
    }
    for (size_t v = 0; v < nb; v++)
        m[v] = b->sec[v] == 1;
    size_t sx = 1, sy = b->nx, sz = b->nx * b->ny;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            dilate_line(m + k * sz + j * sy, t + k * sz + j * sy, b->nx, sx);
    for (size_t k = 0; k < b->nz; k++)
        for (size_t i = 0; i < b->nx; i++)
            dilate_line(t + k * sz + i, m + k * sz + i, b->ny, sy);
    for (size_t j = 0; j < b->ny; j++)
        for (size_t i = 0; i < b->nx; i++)
            dilate_line(m + j * sy + i, t + j * sy + i, b->nz, sz);
    for (size_t v = 0; v < nb; v++)
        if (b->sec[v] == 0 && t[v])
            b->sec[v] = 2;
    free(m);
    free(t);
    return SR_OK;
}

/* The section's hull: corners of its column-extreme voxels grown by HULL_GROW. */
sr_status sr_img_hull_make(const sr_voxels *g, const local_box *b, double z_min, double z_max,
                           sr_mesh *out, sr_err *err)
{
    size_t cap = 2 * b->nx * b->ny + 8, n = 0;
    double *pts = malloc(cap * 3 * sizeof *pts);
    if (!pts)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a section's hull");
    double r = HULL_GROW * g->h;
    for (size_t j = 0; j < b->ny; j++)
        for (size_t i = 0; i < b->nx; i++) {
            long kmin = -1, kmax = -1;
            for (size_t k = 0; k < b->nz; k++)
                if (b->sec[sr_img_lidx(b, i, j, k)] == 1) {
                    if (kmin < 0)
                        kmin = (long)k;
                    kmax = (long)k;
                }
            if (kmin < 0)
                continue;
            long ks[2] = {kmin, kmax};
            for (int e = 0; e < (kmin == kmax ? 1 : 2) && n < cap; e++, n++) {
                pts[3 * n] = g->origin[0] + (double)(b->i0 + i) * g->h;
                pts[3 * n + 1] = g->origin[1] + (double)(b->j0 + j) * g->h;
                pts[3 * n + 2] = g->origin[2] + (double)(b->k0 + (size_t)ks[e]) * g->h;
            }
        }
    /* the hull of the centres first, then its corners grown: the hull of a set grown
     * by a cube is the hull of its hull's vertices grown by it (8 times fewer points
     * for the large hull) */
    sr_mesh centres = {0};
    sr_status st = sr_convex_hull(pts, n, &centres, err);
    if (st != SR_OK) { /* flat (one layer, one row): every centre grown */
        centres.xyz = pts;
        centres.vertex_count = n;
        pts = NULL;
    }
    size_t m = centres.vertex_count;
    double *grown = malloc((8 * m + 1) * 3 * sizeof *grown);
    if (!grown) {
        free(pts);
        if (st == SR_OK)
            sr_mesh_release(&centres);
        else
            free(centres.xyz);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a section's hull");
    }
    for (size_t v = 0; v < m; v++)
        for (int q = 0; q < 8; q++) {
            const double *c = centres.xyz + 3 * v;
            double *o = grown + 3 * (8 * v + (size_t)q);
            o[0] = c[0] + (q & 1 ? r : -r);
            o[1] = c[1] + (q & 2 ? r : -r);
            o[2] = fmin(fmax(c[2] + (q & 4 ? r : -r), z_min), z_max);
        }
    if (st == SR_OK)
        sr_mesh_release(&centres);
    else
        free(centres.xyz);
    free(pts);
    st = sr_convex_hull(grown, 8 * m, out, err);
    free(grown);
    return st;
}
