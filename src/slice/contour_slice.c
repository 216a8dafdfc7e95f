/*
 * contour_slice.c: closed cut contours of a mesh per layer plane (contour_slice.h):
 * bucketing triangles by the layers they span, one oriented segment per cut triangle,
 * chaining segments through the mesh edges they start and end on.
 */
#include "slice/contour_slice.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct seg {
    uint64_t from, to;      /* edge keys: min vertex << 32 | max vertex */
    double p[2];            /* the point on edge `from` */
} seg;

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
}

/* The point where edge (a, b) meets z = L; computed from the lower vertex so both
 * triangles sharing the edge get the same bits. */
static void edge_point(const sr_mesh *m, uint32_t a, uint32_t b, double L, double out[2])
{
    if (a > b) {
        uint32_t t = a;
        a = b;
        b = t;
    }
    const double *pa = m->xyz + 3 * (size_t)a, *pb = m->xyz + 3 * (size_t)b;
    double u = (L - pa[2]) / (pb[2] - pa[2]);
    out[0] = pa[0] + u * (pb[0] - pa[0]);
    out[1] = pa[1] + u * (pb[1] - pa[1]);
}

/* The oriented segment of triangle t at z = L: from the edge going down (above ->
 * below) to the edge going up. Returns 0 when the plane does not cut it. */
static int cut(const sr_mesh *m, size_t t, double L, seg *out)
{
    const uint32_t *f = m->tri + 3 * t;
    int above[3];
    for (int i = 0; i < 3; i++)
        above[i] = m->xyz[3 * (size_t)f[i] + 2] >= L;
    int down = -1, up = -1;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3;
        if (above[i] && !above[j])
            down = i;
        else if (!above[i] && above[j])
            up = i;
    }
    if (down < 0 || up < 0)
        return 0;
    out->from = edge_key(f[down], f[(down + 1) % 3]);
    out->to = edge_key(f[up], f[(up + 1) % 3]);
    edge_point(m, f[down], f[(down + 1) % 3], L, out->p);
    return 1;
}

static uint64_t mix(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return k;
}

/* Chains the segments of one layer into contours appended to *poly. */
static sr_status chain(seg *s, size_t n, sr_poly2 *poly, size_t *open_chains)
{
    if (n == 0)
        return SR_OK;
    size_t cap = 16;
    while (cap < 2 * n)
        cap <<= 1;
    size_t *slot = malloc(cap * sizeof *slot);
    unsigned char *used = calloc(n, 1);
    double *pts = malloc(2 * (n + 1) * sizeof *pts);
    size_t *prev = malloc(n * sizeof *prev);
    sr_status st = SR_OK;
    if (!slot || !used || !pts || !prev) {
        st = SR_E_NOMEM;
        goto done;
    }
    for (size_t i = 0; i < cap; i++)
        slot[i] = SIZE_MAX;
    for (size_t i = 0; i < n; i++) {        /* start edge -> segment */
        size_t h = mix(s[i].from) & (cap - 1);
        while (slot[h] != SIZE_MAX)
            h = (h + 1) & (cap - 1);
        slot[h] = i;
    }
    for (size_t i = 0; i < n; i++)
        prev[i] = SIZE_MAX;
    for (size_t i = 0; i < n; i++) {        /* mark which segments have a predecessor */
        size_t h = mix(s[i].to) & (cap - 1);
        while (slot[h] != SIZE_MAX) {
            size_t j = slot[h];
            if (s[j].from == s[i].to && !used[j] && prev[j] == SIZE_MAX) {
                prev[j] = i;
                break;
            }
            h = (h + 1) & (cap - 1);
        }
    }
    /* open chains first (start where no predecessor), then the closed loops */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i0 = 0; i0 < n; i0++) {
            if (used[i0] || (pass == 0 && prev[i0] != SIZE_MAX))
                continue;
            size_t count = 0, i = i0;
            int closed = 0;
            while (!used[i]) {
                used[i] = 1;
                pts[2 * count] = s[i].p[0];
                pts[2 * count + 1] = s[i].p[1];
                count++;
                size_t h = mix(s[i].to) & (cap - 1), next = SIZE_MAX;
                while (slot[h] != SIZE_MAX) {
                    size_t j = slot[h];
                    if (s[j].from == s[i].to && prev[j] == i) {
                        next = j;
                        break;
                    }
                    h = (h + 1) & (cap - 1);
                }
                if (next == SIZE_MAX)
                    break;
                if (next == i0) {
                    closed = 1;
                    break;
                }
                i = next;
            }
            if (!closed)
                (*open_chains)++;
            if (count >= 3) {
                sr_err e;
                st = sr_poly2_add_contour(poly, pts, count, &e);
                if (st != SR_OK)
                    goto done;
            }
        }
    }
done:
    free(slot);
    free(used);
    free(pts);
    free(prev);
    return st;
}

sr_status sr_contour_slice(const sr_mesh *mesh, const double *z, size_t layers,
                           sr_contour_stack *out, sr_err *err)
{
    if (!mesh || mesh->tri_count == 0)
        return sr_err_set(err, SR_E_INVALID, "cannot cut an empty mesh into contours");
    if (layers == 0)
        return sr_err_set(err, SR_E_RANGE, "bad layers 0: expected at least one plane");
    for (size_t l = 0; l < layers; l++)
        if (!isfinite(z[l]))
            return sr_err_set(err, SR_E_RANGE, "bad plane height %zu: not a finite number", l);

    /* layers sorted by height so a triangle's planes are one index range */
    size_t *order = malloc(layers * sizeof *order);
    double *zs = malloc(layers * sizeof *zs);
    size_t *count = calloc(layers + 1, sizeof *count);
    size_t *bucket = NULL;
    seg *segs = NULL;
    sr_contour_stack s = {0};
    s.layers = layers;
    s.z = malloc(layers * sizeof *s.z);
    s.raw = calloc(layers, sizeof *s.raw);
    sr_status st = SR_OK;
    if (!order || !zs || !count || !s.z || !s.raw) {
        st = SR_E_NOMEM;
        goto fail;
    }
    memcpy(s.z, z, layers * sizeof *z);
    for (size_t l = 0; l < layers; l++)
        order[l] = l;
    for (size_t a = 1; a < layers; a++) {   /* insertion sort: layers are few, mostly sorted */
        size_t v = order[a], b = a;
        while (b > 0 && z[order[b - 1]] > z[v]) {
            order[b] = order[b - 1];
            b--;
        }
        order[b] = v;
    }
    for (size_t l = 0; l < layers; l++)
        zs[l] = z[order[l]];

    /* count, then fill, the triangles of each (sorted) layer */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < mesh->tri_count; t++) {
            const uint32_t *f = mesh->tri + 3 * t;
            double za = mesh->xyz[3 * (size_t)f[0] + 2], zb = mesh->xyz[3 * (size_t)f[1] + 2],
                   zc = mesh->xyz[3 * (size_t)f[2] + 2];
            double lo = fmin(za, fmin(zb, zc)), hi = fmax(za, fmax(zb, zc));
            /* planes with lo < L <= hi cut it (a vertex at L counts as above) */
            size_t a = 0, b = layers;
            while (a < b) {
                size_t mid = (a + b) / 2;
                if (zs[mid] <= lo)
                    a = mid + 1;
                else
                    b = mid;
            }
            for (size_t l = a; l < layers && zs[l] <= hi; l++) {
                if (pass == 0)
                    count[l + 1]++;
                else
                    bucket[count[l]++] = (uint32_t)t;
            }
        }
        if (pass == 0) {
            for (size_t l = 0; l < layers; l++)
                count[l + 1] += count[l];
            bucket = malloc((count[layers] + 1) * sizeof *bucket);
            if (!bucket) {
                st = SR_E_NOMEM;
                goto fail;
            }
        } else {
            for (size_t l = layers; l > 0; l--)   /* restore the starts */
                count[l] = count[l - 1];
            count[0] = 0;
        }
    }
    size_t most = 0;
    for (size_t l = 0; l < layers; l++)
        if (count[l + 1] - count[l] > most)
            most = count[l + 1] - count[l];
    segs = malloc((most + 1) * sizeof *segs);
    if (!segs) {
        st = SR_E_NOMEM;
        goto fail;
    }
    for (size_t l = 0; l < layers; l++) {
        size_t n = 0;
        for (size_t i = count[l]; i < count[l + 1]; i++)
            if (cut(mesh, bucket[i], zs[l], &segs[n]))
                n++;
        st = chain(segs, n, &s.raw[order[l]], &s.open_chains);
        if (st != SR_OK)
            goto fail;
    }
    free(order);
    free(zs);
    free(count);
    free(bucket);
    free(segs);
    *out = s;
    return SR_OK;
fail:
    free(order);
    free(zs);
    free(count);
    free(bucket);
    free(segs);
    sr_contour_stack_release(&s);
    return sr_err_set(err, st, "cannot cut the mesh into %zu contour layers: out of memory",
                      layers);
}

void sr_contour_stack_release(sr_contour_stack *s)
{
    if (!s)
        return;
    if (s->raw)
        for (size_t l = 0; l < s->layers; l++)
            sr_poly2_release(&s->raw[l]);
    free(s->raw);
    free(s->z);
    memset(s, 0, sizeof *s);
}
