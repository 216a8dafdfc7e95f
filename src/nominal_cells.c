/*
 * nominal_cells.c: the nominal's missing volume measured cell by cell (nominal_int.h),
 * for a scan the exact difference refuses because it crosses itself (a noisy scan
 * folds over along sharp edges and fracture lines).
 *
 * The volume of a closed surface inside a box needs no boolean: by the divergence
 * theorem along z, V(box) = sum over triangles of the integral, over the triangle's
 * projection clipped to the box's xy rectangle, of clamp(z - z0, 0, z1 - z0) with the
 * sign of the triangle's normal's z (its signed projected area). That is the integral
 * of the winding number over the box, exact for any closed surface, crossing itself or
 * not: a fold's two layers count once each with opposite signs. So on one grid of cells
 * over both meshes, d = V(registered intact ∩ cell) - V(scan ∩ cell) is exact cell by
 * cell, and the sum over every cell is V(intact) - V(scan).
 *
 * A cell away from the damage holds the same surface twice (registration scatter and
 * the scan's noise, which average out); a cell in the damage holds material the scan
 * lacks. The cells whose d is over the scatter's volume in a cell (the sliver
 * thickness times twice the cell's face) are joined into pieces through faces, edges
 * and corners; each piece takes also the ring of cells around it (the damage's edge
 * is only partly in a cell, and the ring's scatter averages out), and its volume is
 * the sum of d over them. Pieces under the smallest volume are dropped as slivers.
 * Each cell's d goes to the section whose patch box is nearest the cell's centre
 * (within the box's diagonal), as nominal.c's shares of a piece's surface.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "nominal_int.h"

#define GRID_DIV 50 /* cells along the grid's diagonal */
#define MAX_POLY 16

typedef struct grid {
    double lo[3], h;
    int n[3];
    double *d;     /* n[0] x n[1] x n[2] cell volumes, x fastest */
    double *carry; /* per cell: h x signed area above the layer, summed downwards */
} grid;

static size_t cell_at(const grid *g, int i, int j, int k)
{
    return ((size_t)k * (size_t)g->n[1] + (size_t)j) * (size_t)g->n[0] + (size_t)i;
}

/* The part of polygon p[0..n) (xyz) where coordinate `axis` is >= v (keep > 0) or
 * <= v (keep < 0), into q; returns its vertex count. */
static int clip(const double (*p)[3], int n, int axis, double v, int keep, double (*q)[3])
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const double *a = p[i], *b = p[(i + 1) % n];
        double da = keep * (a[axis] - v), db = keep * (b[axis] - v);
        if (da >= 0 && m < MAX_POLY)
            memcpy(q[m++], a, sizeof q[0]);
        if (((da < 0 && db > 0) || (da > 0 && db < 0)) && m < MAX_POLY) {
            double t = da / (da - db);
            for (int k = 0; k < 3; k++)
                q[m][k] = a[k] + t * (b[k] - a[k]);
            q[m][axis] = v;
            m++;
        }
    }
    return m;
}

/* Signed projected area of p and the integral of z over it (exact: z is linear). */
static void area_and_z(const double (*p)[3], int n, double *area, double *zint)
{
    *area = *zint = 0;
    for (int i = 1; i + 1 < n; i++) {
        double a = 0.5 * ((p[i][0] - p[0][0]) * (p[i + 1][1] - p[0][1]) -
                          (p[i + 1][0] - p[0][0]) * (p[i][1] - p[0][1]));
        *area += a;
        *zint += a * (p[0][2] + p[i][2] + p[i + 1][2]) / 3;
    }
}

/* Adds sign x V(m ∩ cell) to every cell of g (carry still to be summed). */
static void accumulate(const sr_mesh *m, double sign, grid *g)
{
    double h = g->h;
    for (size_t t = 0; t < m->tri_count; t++) {
        double p[3][3], lo[3], hi[3];
        for (int v = 0; v < 3; v++)
            memcpy(p[v], m->xyz + 3 * (size_t)m->tri[3 * t + v], sizeof p[v]);
        int c0[3], c1[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(p[0][k], fmin(p[1][k], p[2][k]));
            hi[k] = fmax(p[0][k], fmax(p[1][k], p[2][k]));
            c0[k] = (int)floor((lo[k] - g->lo[k]) / h);
            c1[k] = (int)floor((hi[k] - g->lo[k]) / h);
            c0[k] = c0[k] < 0 ? 0 : c0[k] >= g->n[k] ? g->n[k] - 1 : c0[k];
            c1[k] = c1[k] < 0 ? 0 : c1[k] >= g->n[k] ? g->n[k] - 1 : c1[k];
        }
        for (int j = c0[1]; j <= c1[1]; j++)
            for (int i = c0[0]; i <= c1[0]; i++) {
                double a[MAX_POLY][3], b[MAX_POLY][3];
                double x0 = g->lo[0] + i * h, y0 = g->lo[1] + j * h;
                int n = clip((const double(*)[3])p, 3, 0, x0, 1, a);
                n = clip((const double(*)[3])a, n, 0, x0 + h, -1, b);
                n = clip((const double(*)[3])b, n, 1, y0, 1, a);
                n = clip((const double(*)[3])a, n, 1, y0 + h, -1, b);
                if (n < 3)
                    continue;
                for (int k = c0[2]; k <= c1[2]; k++) {
                    double z0 = g->lo[2] + k * h, q[MAX_POLY][3], area, zint;
                    int nq = clip((const double(*)[3])b, n, 2, z0, 1, a);
                    nq = clip((const double(*)[3])a, nq, 2, z0 + h, -1, q);
                    if (nq < 3)
                        continue;
                    area_and_z((const double(*)[3])q, nq, &area, &zint);
                    size_t c = cell_at(g, i, j, k);
                    g->d[c] += sign * (zint - z0 * area);
                    if (k > 0) /* every layer below takes h x this area */
                        g->carry[cell_at(g, i, j, k - 1)] += sign * h * area;
                }
            }
    }
}

sr_status nominal_cells(const sr_mesh *registered, const sr_mesh *scan, const double *boxes,
                        size_t count, double sliver_mm, nominal_cell_pieces *out, sr_err *err)
{
    memset(out, 0, sizeof *out);
    grid g;
    memset(&g, 0, sizeof g);
    double lo[3], hi[3], alo[3], ahi[3], diag = 0;
    sr_mesh_bbox(registered, lo, hi);
    sr_mesh_bbox(scan, alo, ahi);
    for (int k = 0; k < 3; k++) {
        lo[k] = fmin(lo[k], alo[k]);
        hi[k] = fmax(hi[k], ahi[k]);
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    diag = sqrt(diag);
    g.h = diag / GRID_DIV;
    if (!(g.h > 0))
        return sr_err_set(err, SR_E_INVALID, "the nominal and the scan have no extent");
    size_t cells = 1;
    for (int k = 0; k < 3; k++) {
        g.lo[k] = lo[k] - 0.5 * g.h;
        g.n[k] = (int)((hi[k] - lo[k]) / g.h) + 2;
        cells *= (size_t)g.n[k];
    }
    g.d = calloc(cells, sizeof *g.d);
    g.carry = calloc(cells, sizeof *g.carry);
    long *label = malloc(cells * sizeof *label);
    size_t *queue = malloc(cells * sizeof *queue);
    if (!g.d || !g.carry || !label || !queue) {
        free(g.d);
        free(g.carry);
        free(label);
        free(queue);
        return sr_err_set(err, SR_E_NOMEM, "out of memory measuring the nominal by cells");
    }
    accumulate(registered, 1, &g);
    accumulate(scan, -1, &g);
    for (int j = 0; j < g.n[1]; j++) /* carries summed from the top layer down */
        for (int i = 0; i < g.n[0]; i++) {
            double above = 0;
            for (int k = g.n[2] - 1; k >= 0; k--) {
                size_t c = cell_at(&g, i, j, k);
                above += g.carry[c];
                g.d[c] += above;
            }
        }
    /* the cells over the scatter, joined into pieces (26-neighbours) */
    double tau = 2.0 * sliver_mm * g.h * g.h;
    for (size_t c = 0; c < cells; c++) {
        label[c] = g.d[c] > tau ? -1 : -2; /* -1: to label; -2: not damage */
        if (g.d[c] < -tau)
            out->extra_mm3 -= g.d[c];
    }
    nominal_cell_piece *pieces = NULL;
    size_t np = 0, cap = 0;
    sr_status st = SR_OK;
    for (size_t seed = 0; seed < cells && st == SR_OK; seed++) {
        if (label[seed] != -1)
            continue;
        size_t head = 0, tail = 0;
        queue[tail++] = seed;
        label[seed] = (long)np;
        while (head < tail) {
            size_t c = queue[head++];
            int i = (int)(c % (size_t)g.n[0]), j = (int)(c / (size_t)g.n[0] % (size_t)g.n[1]),
                k = (int)(c / ((size_t)g.n[0] * (size_t)g.n[1]));
            for (int dk = -1; dk <= 1; dk++)
                for (int dj = -1; dj <= 1; dj++)
                    for (int di = -1; di <= 1; di++) {
                        int x = i + di, y = j + dj, z = k + dk;
                        if (x < 0 || y < 0 || z < 0 || x >= g.n[0] || y >= g.n[1] || z >= g.n[2])
                            continue;
                        size_t e = cell_at(&g, x, y, z);
                        if (label[e] == -1) {
                            label[e] = (long)np;
                            queue[tail++] = e;
                        } else if (label[e] == -2) { /* the ring: taken, not spread from */
                            label[e] = -3 - (long)np;
                        }
                    }
        }
        if (np == cap) {
            size_t nc = cap ? 2 * cap : 8;
            nominal_cell_piece *grown = realloc(pieces, nc * sizeof *grown);
            if (!grown) {
                st = SR_E_NOMEM;
                break;
            }
            pieces = grown;
            cap = nc;
        }
        memset(&pieces[np], 0, sizeof pieces[np]);
        pieces[np].share = calloc(count + 1, sizeof *pieces[np].share);
        if (!pieces[np].share) {
            st = SR_E_NOMEM;
            break;
        }
        np++;
    }
    /* every labelled cell's d to its piece and to the section nearest its centre */
    for (size_t c = 0; c < cells && st == SR_OK; c++) {
        if (label[c] == -2)
            continue;
        long l = label[c] >= 0 ? label[c] : -3 - label[c];
        nominal_cell_piece *p = &pieces[l];
        double cen[3] = {g.lo[0] + ((double)(c % (size_t)g.n[0]) + 0.5) * g.h,
                         g.lo[1] + ((double)(c / (size_t)g.n[0] % (size_t)g.n[1]) + 0.5) * g.h,
                         g.lo[2] + ((double)(c / ((size_t)g.n[0] * (size_t)g.n[1])) + 0.5) * g.h};
        size_t best = nominal_nearest_section(cen, boxes, count);
        p->share[best] += g.d[c];
        p->volume_mm3 += g.d[c];
        for (int k = 0; k < 3; k++) {
            p->centroid[k] += g.d[c] * cen[k];
            if (best == count)
                p->outside_centroid[k] += g.d[c] * cen[k];
        }
    }
    free(g.d);
    free(g.carry);
    free(label);
    free(queue);
    out->pieces = pieces;
    out->count = np;
    out->cell_mm = g.h;
    if (st != SR_OK) {
        nominal_cell_pieces_release(out);
        return sr_err_set(err, st, "out of memory measuring the nominal by cells");
    }
    return SR_OK;
}

void nominal_cell_pieces_release(nominal_cell_pieces *p)
{
    if (!p)
        return;
    for (size_t i = 0; i < p->count; i++)
        free(p->pieces[i].share);
    free(p->pieces);
    memset(p, 0, sizeof *p);
}
