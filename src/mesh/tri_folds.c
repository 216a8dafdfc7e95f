/*
 * tri_folds.c: folds flipped flat (see tri_folds.h).
 */
#include "mesh/tri_folds.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#define FOLD_COS -0.9   /* two faces this far turned onto each other are a fold */
#define CREASE_COS -0.5 /* a flip is kept when its faces turn by at most 120 degrees */
#define MAX_FOLDS 256   /* folds looked at a call (each asks every triangle once) */

/* One directed edge of a picked triangle: its corners sorted into the key. */
typedef struct dedge {
    uint64_t key;
    uint32_t t;
    uint8_t k; /* the edge runs from corner k to corner k + 1 */
} dedge;

static int dedge_cmp(const void *pa, const void *pb)
{
    const dedge *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

static void area_vector(const double *xyz, uint32_t a, uint32_t b, uint32_t c, double n[3])
{
    const double *p = xyz + 3 * (size_t)a, *q = xyz + 3 * (size_t)b, *r = xyz + 3 * (size_t)c;
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

/* The cosine between the normals of (a b c) and (d e f); 1 when either has no area
 * above min2 (squared length of its area vector). */
static double normals_cos(const double *xyz, const uint32_t *x, const uint32_t *y, double min2)
{
    double n[3], m[3];
    area_vector(xyz, x[0], x[1], x[2], n);
    area_vector(xyz, y[0], y[1], y[2], m);
    double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2],
           mm = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
    if (!(nn > min2) || !(mm > min2))
        return 1;
    return (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) / sqrt(nn * mm);
}

/* How many triangles of m have both a and b as corners. */
static size_t edge_uses(const sr_mesh *m, uint32_t a, uint32_t b)
{
    size_t n = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *v = m->tri + 3 * t;
        bool ha = v[0] == a || v[1] == a || v[2] == a, hb = v[0] == b || v[1] == b || v[2] == b;
        n += ha && hb;
    }
    return n;
}

size_t sr_tri_folds_flip(sr_mesh *m, const bool *pick)
{
    size_t n = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        n += pick[t] ? 3 : 0;
    if (n == 0)
        return 0;
    dedge *e = malloc(n * sizeof *e);
    bool *done = calloc(m->tri_count, sizeof *done);
    if (!e || !done) {
        free(e);
        free(done);
        return SIZE_MAX;
    }
    n = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        for (uint8_t k = 0; pick[t] && k < 3; k++) {
            uint32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
            e[n++] = (dedge){a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a, (uint32_t)t, k};
        }
    qsort(e, n, sizeof *e, dedge_cmp);
    size_t flipped = 0, looked = 0;
    for (size_t i = 0; i + 1 < n && looked < MAX_FOLDS; i++) {
        /* an edge two picked triangles share, walked opposite ways, and no third */
        if (e[i].key != e[i + 1].key || (i + 2 < n && e[i + 2].key == e[i].key) ||
            (i > 0 && e[i - 1].key == e[i].key))
            continue;
        uint32_t t1 = e[i].t, t2 = e[i + 1].t;
        if (done[t1] || done[t2] || t1 == t2)
            continue;
        uint32_t *x = m->tri + 3 * (size_t)t1, *y = m->tri + 3 * (size_t)t2;
        uint32_t u = x[e[i].k], v = x[(e[i].k + 1) % 3], a = x[(e[i].k + 2) % 3];
        uint8_t k2 = e[i + 1].k;
        if (y[k2] != v || y[(k2 + 1) % 3] != u)
            continue; /* walked the same way: not an oriented pair */
        uint32_t b = y[(k2 + 2) % 3];
        const double *pu = m->xyz + 3 * (size_t)u, *pv = m->xyz + 3 * (size_t)v;
        double l2 = (pu[0] - pv[0]) * (pu[0] - pv[0]) + (pu[1] - pv[1]) * (pu[1] - pv[1]) +
                    (pu[2] - pv[2]) * (pu[2] - pv[2]);
        double min2 = 1e-12 * l2 * l2; /* areas below a millionth of the edge's square */
        if (!(normals_cos(m->xyz, x, y, min2) < FOLD_COS) || a == b)
            continue;
        looked++;
        if (edge_uses(m, a, b) > 0 || edge_uses(m, u, v) != 2)
            continue; /* the other diagonal is an edge, or u v has a third triangle */
        uint32_t n1[3] = {a, u, b}, n2[3] = {b, v, a};
        double c1[3], c2[3];
        area_vector(m->xyz, a, u, b, c1);
        area_vector(m->xyz, b, v, a, c2);
        if (!(c1[0] * c1[0] + c1[1] * c1[1] + c1[2] * c1[2] > min2) ||
            !(c2[0] * c2[0] + c2[1] * c2[1] + c2[2] * c2[2] > min2) ||
            !(normals_cos(m->xyz, n1, n2, min2) >= CREASE_COS))
            continue;
        for (int k = 0; k < 3; k++) {
            x[k] = n1[k];
            y[k] = n2[k];
        }
        done[t1] = done[t2] = true;
        flipped++;
    }
    free(e);
    free(done);
    return flipped;
}
