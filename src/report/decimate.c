/*
 * decimate.c: meshes reduced to the HTML report's display budget (sr_report_decimate in
 * report_html.h) by vertex clustering: a grid over the mesh's box, coarsened until the
 * triangles that survive (those whose corners fall in three different cells) are within
 * the budget; each cell's vertices merge into their mean.
 */
#include "report/report_html.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct vkey {
    uint64_t key;
    uint32_t v;
} vkey;

static int vkey_cmp(const void *a, const void *b)
{
    uint64_t x = ((const vkey *)a)->key, y = ((const vkey *)b)->key;
    return x < y ? -1 : x > y;
}

/* One clustering pass at cell size h: vertices in a cell merge into their mean. */
static sr_status cluster(const sr_mesh *in, const double lo[3], double h, sr_mesh *out)
{
    size_t nv = in->vertex_count, nt = in->tri_count;
    vkey *keys = malloc(nv * sizeof *keys);
    uint32_t *map = malloc(nv * sizeof *map);
    if (!keys || !map) {
        free(keys);
        free(map);
        return SR_E_NOMEM;
    }
    for (size_t i = 0; i < nv; i++) {
        uint64_t k = 0;
        for (int a = 0; a < 3; a++) {
            double c = floor((in->xyz[3 * i + a] - lo[a]) / h);
            uint64_t ic = c < 0 ? 0 : c > 2097151 ? 2097151 : (uint64_t)c;
            k = (k << 21) | ic;
        }
        keys[i].key = k;
        keys[i].v = (uint32_t)i;
    }
    qsort(keys, nv, sizeof *keys, vkey_cmp);
    size_t clusters = 0;
    for (size_t i = 0; i < nv; i++) {
        if (i == 0 || keys[i].key != keys[i - 1].key)
            clusters++;
        map[keys[i].v] = (uint32_t)(clusters - 1);
    }
    free(keys);
    size_t kept = 0;
    for (size_t t = 0; t < nt; t++) {
        uint32_t a = map[in->tri[3 * t]], b = map[in->tri[3 * t + 1]], c = map[in->tri[3 * t + 2]];
        kept += a != b && b != c && a != c;
    }
    sr_mesh m = {0};
    sr_status st = sr_mesh_alloc(&m, clusters ? clusters : 1, kept ? kept : 1);
    if (st != SR_OK) {
        free(map);
        return st;
    }
    double *count = calloc(clusters ? clusters : 1, sizeof *count);
    if (!count) {
        free(map);
        sr_mesh_release(&m);
        return SR_E_NOMEM;
    }
    memset(m.xyz, 0, 3 * (clusters ? clusters : 1) * sizeof *m.xyz);
    for (size_t i = 0; i < nv; i++) {
        uint32_t c = map[i];
        for (int a = 0; a < 3; a++)
            m.xyz[3 * c + a] += in->xyz[3 * i + a];
        count[c] += 1;
    }
    for (size_t c = 0; c < clusters; c++)
        for (int a = 0; a < 3; a++)
            m.xyz[3 * c + a] /= count[c];
    free(count);
    size_t k = 0;
    for (size_t t = 0; t < nt; t++) {
        uint32_t a = map[in->tri[3 * t]], b = map[in->tri[3 * t + 1]], c = map[in->tri[3 * t + 2]];
        if (a != b && b != c && a != c) {
            m.tri[3 * k] = a;
            m.tri[3 * k + 1] = b;
            m.tri[3 * k + 2] = c;
            k++;
        }
    }
    free(map);
    m.vertex_count = clusters;
    m.tri_count = kept;
    *out = m;
    return SR_OK;
}

sr_status sr_report_decimate(const sr_mesh *in, size_t max_tri, sr_mesh *out, sr_err *err)
{
    if (in->tri_count <= max_tri) {
        sr_mesh m = {0};
        if (sr_mesh_copy(&m, in) != SR_OK)
            return sr_err_set(err, SR_E_NOMEM, "out of memory copying a mesh for the report");
        *out = m;
        return SR_OK;
    }
    if (max_tri == 0 || in->vertex_count == 0) {
        sr_mesh m = {0};
        *out = m;
        return SR_OK;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < in->vertex_count; i++)
        for (int a = 0; a < 3; a++) {
            double c = in->xyz[3 * i + a];
            if (c < lo[a])
                lo[a] = c;
            if (c > hi[a])
                hi[a] = c;
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diag > 0))
        diag = 1;
    /* start at the cell size that would give about max_tri triangles on a surface
     * (triangles ~ 2 (diag / h)^2), then coarsen by 1.3 until the budget holds */
    double h = diag / sqrt((double)max_tri / 2.0) / 2.0;
    if (h < diag / 2e6)
        h = diag / 2e6;
    for (int iter = 0; iter < 60; iter++, h *= 1.3) {
        sr_mesh m;
        sr_status st = cluster(in, lo, h, &m);
        if (st != SR_OK)
            return sr_err_set(err, st, "out of memory decimating a mesh for the report");
        if (m.tri_count <= max_tri) {
            *out = m;
            return SR_OK;
        }
        sr_mesh_release(&m);
    }
    sr_mesh m = {0};
    *out = m;
    return SR_OK;
}
