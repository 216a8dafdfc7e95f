/*
 * voxels.c: occupancy of a closed mesh on a voxel grid (see voxels.h). Each triangle
 * is rasterised onto the column centres its xy projection covers (edge functions with a
 * top-left rule, so a column through a shared edge or vertex is counted once); every hit
 * records (z, +1 entering / -1 leaving) in its column. Each column's hits are then
 * sorted by z and the voxels between are filled where the running winding is positive.
 */
#include "images/voxels.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sr_status sr_voxels_alloc(sr_voxels *g, const size_t n[3], double h, const double origin[3])
{
    memset(g, 0, sizeof *g);
    if (!(h > 0) || n[0] == 0 || n[1] == 0 || n[2] == 0)
        return SR_E_RANGE;
    size_t total = n[0] * n[1];
    if (total / n[1] != n[0] || total * n[2] / n[2] != total || total * n[2] > ((size_t)1 << 32))
        return SR_E_NOMEM;
    g->v = calloc(total * n[2], 1);
    if (!g->v)
        return SR_E_NOMEM;
    g->nx = n[0];
    g->ny = n[1];
    g->nz = n[2];
    g->h = h;
    memcpy(g->origin, origin, sizeof g->origin);
    return SR_OK;
}

void sr_voxels_release(sr_voxels *g)
{
    if (!g)
        return;
    free(g->v);
    memset(g, 0, sizeof *g);
}

typedef struct hit {
    float z;
    int8_t dir;
} hit;

/* top-left rule on the edge (a -> b) of a counter-clockwise triangle: a point exactly on
 * it counts when the edge is a top or a left edge */
static int edge_owns(double ax, double ay, double bx, double by)
{
    double dx = bx - ax, dy = by - ay;
    return dy > 0 || (dy == 0 && dx < 0);
}

/* The edge function of (p -> q) at (x, y), evaluated with the edge's ends in a fixed
 * order (lexicographic) so the two triangles sharing an edge get bitwise opposite
 * values: a column through the edge is then inside exactly one of them. */
static double edge_fn(const double *p, const double *q, double x, double y)
{
    if (p[0] > q[0] || (p[0] == q[0] && p[1] > q[1]))
        return -((p[0] - q[0]) * (y - q[1]) - (p[1] - q[1]) * (x - q[0]));
    return (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
}

/* Calls visit(col, z, dir) for every column centre inside the triangle's projection. */
typedef struct raster {
    const sr_voxels *g;
    size_t *count;   /* per column: hits (counting pass) */
    size_t *start;   /* per column: first slot (filling pass), NULL while counting */
    hit *hits;
} raster;

static void raster_tri(raster *r, const double *p0, const double *p1, const double *p2)
{
    const sr_voxels *g = r->g;
    double area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
    if (area == 0 || !isfinite(area))
        return;
    /* orient counter-clockwise in xy; dir: a triangle facing down is entered going up */
    const double *a = p0, *b = area > 0 ? p1 : p2, *c = area > 0 ? p2 : p1;
    int8_t dir = area > 0 ? -1 : +1;
    double A = fabs(area);
    double xmin = fmin(a[0], fmin(b[0], c[0])), xmax = fmax(a[0], fmax(b[0], c[0]));
    double ymin = fmin(a[1], fmin(b[1], c[1])), ymax = fmax(a[1], fmax(b[1], c[1]));
    double h = g->h;
    long i0 = (long)ceil((xmin - g->origin[0]) / h), i1 = (long)floor((xmax - g->origin[0]) / h);
    long j0 = (long)ceil((ymin - g->origin[1]) / h), j1 = (long)floor((ymax - g->origin[1]) / h);
    if (i0 < 0) i0 = 0;
    if (j0 < 0) j0 = 0;
    if (i1 >= (long)g->nx) i1 = (long)g->nx - 1;
    if (j1 >= (long)g->ny) j1 = (long)g->ny - 1;
    int own_ab = edge_owns(a[0], a[1], b[0], b[1]), own_bc = edge_owns(b[0], b[1], c[0], c[1]),
        own_ca = edge_owns(c[0], c[1], a[0], a[1]);
    for (long j = j0; j <= j1; j++) {
        double y = g->origin[1] + (double)j * h;
        for (long i = i0; i <= i1; i++) {
            double x = g->origin[0] + (double)i * h;
            double w0 = edge_fn(b, c, x, y); /* a's weight */
            double w1 = edge_fn(c, a, x, y); /* b's */
            double w2 = edge_fn(a, b, x, y); /* c's */
            if (w0 < 0 || w1 < 0 || w2 < 0)
                continue;
            if ((w0 == 0 && !own_bc) || (w1 == 0 && !own_ca) || (w2 == 0 && !own_ab))
                continue;
            double z = (w0 * a[2] + w1 * b[2] + w2 * c[2]) / A;
            size_t col = (size_t)j * g->nx + (size_t)i;
            if (r->start) {
                hit *hp = &r->hits[r->start[col] + r->count[col]];
                hp->z = (float)z;
                hp->dir = dir;
            }
            r->count[col]++;
        }
    }
}

static int cmp_hit(const void *pa, const void *pb)
{
    const hit *a = pa, *b = pb;
    return a->z < b->z ? -1 : a->z > b->z ? 1 : a->dir - b->dir;
}

sr_status sr_voxels_fill(sr_voxels *g, const sr_mesh *mesh, sr_err *err)
{
    size_t cols = g->nx * g->ny;
    raster r = {g, calloc(cols, sizeof(size_t)), NULL, NULL};
    size_t *start = malloc((cols + 1) * sizeof(size_t));
    if (!r.count || !start) {
        free(r.count);
        free(start);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu voxel columns", cols);
    }
    for (int pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < mesh->tri_count; t++) {
            const uint32_t *f = mesh->tri + 3 * t;
            raster_tri(&r, mesh->xyz + 3 * f[0], mesh->xyz + 3 * f[1], mesh->xyz + 3 * f[2]);
        }
        if (pass == 1)
            break;
        start[0] = 0;
        for (size_t c = 0; c < cols; c++)
            start[c + 1] = start[c] + r.count[c];
        r.hits = malloc((start[cols] ? start[cols] : 1) * sizeof(hit));
        if (!r.hits) {
            size_t want = start[cols];
            free(r.count);
            free(start);
            return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu voxel hits", want);
        }
        memset(r.count, 0, cols * sizeof(size_t));
        r.start = start;
    }
    size_t plane = cols;
    for (size_t c = 0; c < cols; c++) {
        size_t n = r.count[c];
        if (n < 2)
            continue;
        hit *hs = r.hits + start[c];
        qsort(hs, n, sizeof *hs, cmp_hit);
        int wind = 0;
        for (size_t e = 0; e + 1 < n; e++) {
            wind += hs[e].dir;
            if (wind <= 0)
                continue;
            /* voxels with centre z in (hs[e].z, hs[e+1].z] */
            double k0 = ceil(((double)hs[e].z - g->origin[2]) / g->h);
            double k1 = floor(((double)hs[e + 1].z - g->origin[2]) / g->h);
            if (k0 < 0) k0 = 0;
            if (k1 > (double)g->nz - 1) k1 = (double)g->nz - 1;
            for (long k = (long)k0; k <= (long)k1; k++)
                g->v[(size_t)k * plane + c] |= 1;
        }
    }
    free(r.hits);
    free(r.count);
    free(start);
    return SR_OK;
}
