/*
 * slice.c: layer/sector outlines of an aligned model, paper Algorithms 1 and 2
 * (see slice.h for the conventions).
 *
 * Exact per-sector maximum (ALGORITHMS.md, Algorithm 2): a cut segment P1-P2 that does
 * not pass through the axis spans less than pi in angle; walking the short way from
 * P1's sector to P2's, the segment is split where it crosses each sector border ray,
 * and each piece's farthest point is one of its two ends. A segment through the axis is
 * split there into two radial pieces.
 */
#include "slice/slice.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.28318530717958647692
#define AXIS_EPS 1e-12

double sr_layer_z(const sr_layer_grid *grid, size_t l)
{
    return grid->z_init + ((double)l + 0.5) * grid->dz;
}

size_t sr_sector_of(double x, double y, size_t sectors)
{
    if (x * x + y * y < AXIS_EPS * AXIS_EPS)
        return SIZE_MAX;
    double a = atan2(y, x);
    if (a < 0)
        a += TWO_PI;
    size_t k = (size_t)floor(a / (TWO_PI / (double)sectors));
    return k % sectors;
}

double sr_sector_angle(size_t k, size_t sectors)
{
    return ((double)k + 0.5) * TWO_PI / (double)sectors;
}

sr_status sr_layer_grid_alloc(sr_layer_grid *out, size_t layers, size_t sectors,
                              double z_init, double dz)
{
    if (layers == 0 || sectors == 0 || layers > SIZE_MAX / sectors / 3)
        return SR_E_RANGE;
    sr_layer_grid g = {layers, sectors, z_init, dz, NULL, NULL};
    g.r = calloc(layers * sectors, sizeof *g.r);
    g.pt = calloc(layers * sectors * 3, sizeof *g.pt);
    if (!g.r || !g.pt) {
        free(g.r);
        free(g.pt);
        return SR_E_NOMEM;
    }
    *out = g;
    return SR_OK;
}

void sr_layer_grid_release(sr_layer_grid *grid)
{
    if (!grid)
        return;
    free(grid->r);
    free(grid->pt);
    memset(grid, 0, sizeof *grid);
}

/* Keeps point (x, y, z) in cell (l, k) if it is the farthest so far. */
static inline void keep(sr_layer_grid *g, size_t l, size_t k, double x, double y, double z)
{
    double r = sqrt(x * x + y * y);
    size_t c = l * g->sectors + k;
    if (r > g->r[c]) {
        g->r[c] = r;
        g->pt[3 * c] = x;
        g->pt[3 * c + 1] = y;
        g->pt[3 * c + 2] = z;
    }
}

/* Contributes segment a-b (in the plane z) of layer l to every sector it crosses. */
static void add_segment(sr_layer_grid *g, size_t l, const double a[2], const double b[2],
                        double z)
{
    size_t n = g->sectors;
    double dth = TWO_PI / (double)n;
    double cross = a[0] * b[1] - a[1] * b[0];
    double dx = b[0] - a[0], dy = b[1] - a[1];
    double len2 = dx * dx + dy * dy;
    size_t ka = sr_sector_of(a[0], a[1], n), kb = sr_sector_of(b[0], b[1], n);
    if (ka != SIZE_MAX)
        keep(g, l, ka, a[0], a[1], z);
    if (kb != SIZE_MAX)
        keep(g, l, kb, b[0], b[1], z);
    if (ka == kb || ka == SIZE_MAX || kb == SIZE_MAX || len2 == 0)
        return;
    if (fabs(cross) <= 1e-14 * len2) {
        /* collinear with the axis: if it passes through the axis the two radial pieces
         * lie in ka and kb only (already kept: their far ends are a and b) */
        return;
    }
    /* walk from ka towards kb the short way: counter-clockwise when cross > 0 */
    int step = cross > 0 ? 1 : -1;
    size_t k = ka;
    for (size_t guard = 0; guard < n && k != kb; guard++) {
        /* border between k and its neighbour in the walking direction */
        size_t border = step > 0 ? (k + 1) % n : k;
        double th = (double)border * dth;
        double ux = cos(th), uy = sin(th);
        /* a + t (b - a) on the ray direction u: cross(a + t d, u) = 0 */
        double den = dx * uy - dy * ux;
        size_t next = step > 0 ? (k + 1) % n : (k + n - 1) % n;
        if (den != 0) {
            double t = -(a[0] * uy - a[1] * ux) / den;
            if (t < 0)
                t = 0;
            if (t > 1)
                t = 1;
            double px = a[0] + t * dx, py = a[1] + t * dy;
            /* the border point belongs to both neighbouring wedges */
            keep(g, l, k, px, py, z);
            keep(g, l, next, px, py, z);
        }
        k = next;
    }
}

void sr_layer_grid_add_segment(sr_layer_grid *grid, size_t l, const double a[2],
                               const double b[2])
{
    add_segment(grid, l, a, b, sr_layer_z(grid, l));
}

/* Cuts triangle t with the plane z = L; writes the segment ends; returns 0 when the
 * triangle does not give a segment (no crossing, or lying in the plane). */
static int cut_triangle(const sr_mesh *m, size_t t, double L, double a[2], double b[2])
{
    const uint32_t *f = m->tri + 3 * t;
    const double *p[3] = {m->xyz + 3 * f[0], m->xyz + 3 * f[1], m->xyz + 3 * f[2]};
    double s[3] = {p[0][2] - L, p[1][2] - L, p[2][2] - L};
    double pts[3][2];
    int n = 0;
    if (s[0] == 0 && s[1] == 0 && s[2] == 0)
        return 0;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3;
        if (s[i] == 0) {
            pts[n][0] = p[i][0];
            pts[n][1] = p[i][1];
            n++;
        } else if ((s[i] < 0 && s[j] > 0) || (s[i] > 0 && s[j] < 0)) {
            double u = s[i] / (s[i] - s[j]);
            pts[n][0] = p[i][0] + u * (p[j][0] - p[i][0]);
            pts[n][1] = p[i][1] + u * (p[j][1] - p[i][1]);
            n++;
        }
    }
    if (n < 2)
        return n == 1 ? (a[0] = b[0] = pts[0][0], a[1] = b[1] = pts[0][1], 1) : 0;
    a[0] = pts[0][0];
    a[1] = pts[0][1];
    b[0] = pts[1][0];
    b[1] = pts[1][1];
    return 1;
}

static sr_status grid_for(const sr_mesh *mesh, const sr_slice_opts *opts, sr_layer_grid *out,
                          sr_err *err)
{
    if (!opts || opts->layers < 1 || opts->layers > 100000)
        return sr_err_set(err, SR_E_RANGE, "bad layers %zu: expected 1..100000",
                          opts ? opts->layers : 0);
    if (opts->sectors < 3 || opts->sectors > 100000)
        return sr_err_set(err, SR_E_RANGE, "bad sectors %zu: expected 3..100000",
                          opts->sectors);
    double z0 = opts->z_min, z1 = opts->z_max;
    if (z0 == 0 && z1 == 0) {
        double lo[3], hi[3];
        sr_mesh_bbox(mesh, lo, hi);
        z0 = lo[2];
        z1 = hi[2];
    }
    if (!(z1 > z0) || !isfinite(z0) || !isfinite(z1))
        return sr_err_set(err, SR_E_RANGE, "cannot slice: the model has no height along z");
    sr_status st = sr_layer_grid_alloc(out, opts->layers, opts->sectors, z0,
                                       (z1 - z0) / (double)opts->layers);
    if (st != SR_OK)
        return sr_err_set(err, st, "cannot allocate %zu x %zu layer grid", opts->layers,
                          opts->sectors);
    return SR_OK;
}

sr_status sr_slice_accurate(const sr_mesh *mesh, const sr_slice_opts *opts,
                            sr_layer_grid *out, sr_err *err)
{
    sr_layer_grid g;
    sr_status st = grid_for(mesh, opts, &g, err);
    if (st != SR_OK)
        return st;
    double inv = 1.0 / g.dz;
    long last = (long)g.layers - 1;
    for (size_t t = 0; t < mesh->tri_count; t++) {
        const uint32_t *f = mesh->tri + 3 * t;
        double za = mesh->xyz[3 * f[0] + 2], zb = mesh->xyz[3 * f[1] + 2],
               zc = mesh->xyz[3 * f[2] + 2];
        double lo = fmin(za, fmin(zb, zc)), hi = fmax(za, fmax(zb, zc));
        /* layers whose plane lies in [lo, hi]: (l + 0.5) in [(lo-z0)/dz, (hi-z0)/dz] */
        long l0 = (long)ceil((lo - g.z_init) * inv - 0.5);
        long l1 = (long)floor((hi - g.z_init) * inv - 0.5);
        if (l0 < 0)
            l0 = 0;
        if (l1 > last)
            l1 = last;
        for (long l = l0; l <= l1; l++) {
            double L = sr_layer_z(&g, (size_t)l), a[2], b[2];
            if (cut_triangle(mesh, t, L, a, b))
                add_segment(&g, (size_t)l, a, b, L);
        }
    }
    *out = g;
    return SR_OK;
}

sr_status sr_slice_accurate_literal(const sr_mesh *mesh, const sr_slice_opts *opts,
                                    sr_layer_grid *out, sr_err *err)
{
    sr_layer_grid g;
    sr_status st = grid_for(mesh, opts, &g, err);
    if (st != SR_OK)
        return st;
    for (size_t l = 0; l < g.layers; l++) {
        double L = sr_layer_z(&g, l);
        for (size_t t = 0; t < mesh->tri_count; t++) {
            double a[2], b[2];
            if (cut_triangle(mesh, t, L, a, b))
                add_segment(&g, l, a, b, L);
        }
    }
    *out = g;
    return SR_OK;
}

sr_status sr_slice_fast(const sr_mesh *mesh, const sr_slice_opts *opts, sr_layer_grid *out,
                        sr_err *err)
{
    sr_layer_grid g;
    sr_status st = grid_for(mesh, opts, &g, err);
    if (st != SR_OK)
        return st;
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        const double *p = mesh->xyz + 3 * v;
        double u = (p[2] - g.z_init) / g.dz;
        if (u < 0 || u > (double)g.layers)
            continue;
        size_t l = (size_t)u;
        if (l >= g.layers)
            l = g.layers - 1;
        size_t k = sr_sector_of(p[0], p[1], g.sectors);
        if (k != SIZE_MAX)
            keep(&g, l, k, p[0], p[1], p[2]);
    }
    *out = g;
    return SR_OK;
}
