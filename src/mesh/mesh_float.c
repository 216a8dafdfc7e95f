/*
 * mesh_float.c: sr_mesh_float_ready (mesh_float.h). Vertices are welded through an
 * open-addressing table keyed by their float bits; only the triangles at a vertex
 * that took another in can have become degenerate or a flap, so only they are
 * looked at again.
 */
#include "mesh/mesh_float.h"

#include "mesh/tri_flaps.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint64_t float_key(const double *p)
{
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int k = 0; k < 3; k++) {
        float f = (float)p[k];
        f = f == 0 ? 0.0f : f; /* -0 and +0 alike */
        uint32_t bits;
        memcpy(&bits, &f, sizeof bits);
        h = (h ^ bits) * 0xff51afd7ed558ccdULL;
        h ^= h >> 33;
    }
    return h;
}

/* One float position (the coordinates rounded; -0 and +0 alike). */
static bool same_place(const double *a, const double *b)
{
    return (float)a[0] == (float)b[0] && (float)a[1] == (float)b[1] && (float)a[2] == (float)b[2];
}

/* Each vertex's first vertex at its float position into first[]; returns how many
 * vertices were welded, SIZE_MAX: out of memory. */
static size_t weld(const sr_mesh *m, uint32_t *first)
{
    size_t room = 16;
    while (room < 2 * m->vertex_count)
        room *= 2;
    uint32_t *slot = calloc(room, sizeof *slot); /* vertex + 1; 0: empty */
    if (!slot)
        return SIZE_MAX;
    size_t welded = 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        for (size_t i = (size_t)float_key(p) & (room - 1);; i = (i + 1) & (room - 1)) {
            if (!slot[i]) {
                slot[i] = (uint32_t)v + 1;
                first[v] = (uint32_t)v;
                break;
            }
            if (same_place(m->xyz + 3 * (size_t)(slot[i] - 1), p)) {
                first[v] = slot[i] - 1;
                welded++;
                break;
            }
        }
    }
    free(slot);
    return welded;
}

/* gone[t] for each pair of triangles among those with a corner at a welding vertex
 * (took[]) on the same corners, walked opposite ways; returns the triangles so paired,
 * SIZE_MAX: out of memory. */
static size_t mark_flaps(const sr_mesh *m, const bool *took, bool *gone)
{
    bool *pick = malloc(m->tri_count + 1);
    if (!pick)
        return SIZE_MAX;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *c = m->tri + 3 * t;
        pick[t] = !gone[t] && (took[c[0]] || took[c[1]] || took[c[2]]);
    }
    size_t paired = sr_tri_flaps_pair(m, pick, 0, gone);
    free(pick);
    return paired;
}

/* The float step count between a and b, coordinates already rounded to float: the
 * largest over x, y, z of how many floats lie between them (0: one position). */
static uint32_t float_steps(const double *a, const double *b)
{
    uint32_t most = 0;
    for (int k = 0; k < 3; k++) {
        float fa = (float)a[k], fb = (float)b[k];
        int32_t ia, ib;
        memcpy(&ia, &fa, sizeof ia);
        memcpy(&ib, &fb, sizeof ib);
        /* the bits in the order of the values: negatives mirrored below zero */
        int64_t oa = ia < 0 ? (int64_t)INT32_MIN - ia : ia,
                ob = ib < 0 ? (int64_t)INT32_MIN - ib : ib;
        int64_t d = oa > ob ? oa - ob : ob - oa;
        if (d > (int64_t)most)
            most = d > UINT32_MAX ? UINT32_MAX : (uint32_t)d;
    }
    return most;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static uint32_t root_of(uint32_t *first, uint32_t v)
{
    while (first[v] != v)
        v = first[v] = first[first[v]];
    return v;
}

/* Among the triangles at a vertex that took another in, the edges used more than
 * twice whose ends lie at most SR_FLOAT_NEIGHBOUR_STEPS float steps apart: their
 * higher end is welded into the lower (first[], took[]). Returns the ends so welded,
 * SIZE_MAX: out of memory. */
static size_t weld_crowded_edges(const sr_mesh *m, uint32_t *first, bool *took, const bool *gone)
{
    size_t n = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *c = m->tri + 3 * t;
        n += !gone[t] && (took[c[0]] || took[c[1]] || took[c[2]]);
    }
    uint64_t *edge = malloc((3 * n + 1) * sizeof *edge);
    if (!edge)
        return SIZE_MAX;
    size_t e = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *c = m->tri + 3 * t;
        if (gone[t] || !(took[c[0]] || took[c[1]] || took[c[2]]))
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t a = c[k], b = c[(k + 1) % 3], lo = a < b ? a : b, hi = a ^ b ^ lo;
            edge[e++] = (uint64_t)lo << 32 | hi;
        }
    }
    qsort(edge, e, sizeof *edge, cmp_u64);
    size_t welded = 0;
    for (size_t i = 0, j; i < e; i = j) {
        for (j = i + 1; j < e && edge[j] == edge[i]; j++)
            ;
        uint32_t lo = (uint32_t)(edge[i] >> 32), hi = (uint32_t)edge[i];
        if (j - i <= 2 || float_steps(m->xyz + 3 * (size_t)lo, m->xyz + 3 * (size_t)hi) >
                              SR_FLOAT_NEIGHBOUR_STEPS)
            continue;
        uint32_t rl = root_of(first, lo), rh = root_of(first, hi);
        if (rl == rh)
            continue;
        if (rh < rl) {
            uint32_t s = rl;
            rl = rh;
            rh = s;
        }
        first[rh] = rl;
        took[rl] = true;
        welded++;
    }
    free(edge);
    return welded;
}

size_t sr_mesh_float_welds(const sr_mesh *m)
{
    uint32_t *first = malloc((m->vertex_count + 1) * sizeof *first);
    size_t welded = first ? weld(m, first) : SIZE_MAX;
    free(first);
    return welded;
}

sr_status sr_mesh_float_ready(const sr_mesh *m, sr_mesh *out, sr_float_report *rep)
{
    sr_float_report r = {0, 0, 0, 0};
    sr_mesh o;
    sr_status st = sr_mesh_copy(&o, m);
    if (st != SR_OK)
        return st;
    for (size_t i = 0; i < 3 * o.vertex_count; i++)
        o.xyz[i] = (double)(float)o.xyz[i];
    uint32_t *first = malloc((o.vertex_count + 1) * sizeof *first);
    bool *took = calloc(o.vertex_count + 1, sizeof *took);
    bool *gone = calloc(o.tri_count + 1, sizeof *gone);
    size_t welded = first && took && gone ? weld(&o, first) : SIZE_MAX;
    if (welded == SIZE_MAX) {
        st = SR_E_NOMEM;
        goto fail;
    }
    r.welded = welded;
    if (welded > 0) {
        for (size_t v = 0; v < o.vertex_count; v++)
            if (first[v] != v)
                took[first[v]] = true;
        for (size_t i = 0; i < 3 * o.tri_count; i++)
            o.tri[i] = first[o.tri[i]];
        for (size_t t = 0; t < o.tri_count; t++) {
            const uint32_t *c = o.tri + 3 * t;
            gone[t] = c[0] == c[1] || c[1] == c[2] || c[0] == c[2];
            r.degenerate += gone[t];
        }
        size_t flaps = mark_flaps(&o, took, gone);
        if (flaps == SIZE_MAX) {
            st = SR_E_NOMEM;
            goto fail;
        }
        r.flaps = flaps;
        /* a weld can crowd an edge: two sheets' triangles on it, whose far ends lie a
         * float step or so apart, not at one position; those ends are welded too */
        for (int round = 0; round < 4; round++) {
            size_t more = weld_crowded_edges(&o, first, took, gone);
            if (more == SIZE_MAX) {
                st = SR_E_NOMEM;
                goto fail;
            }
            if (more == 0)
                break;
            r.crowded += more;
            for (size_t i = 0; i < 3 * o.tri_count; i++)
                o.tri[i] = root_of(first, o.tri[i]);
            for (size_t t = 0; t < o.tri_count; t++) {
                const uint32_t *c = o.tri + 3 * t;
                bool flat = !gone[t] && (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]);
                gone[t] = gone[t] || flat;
                r.degenerate += flat;
            }
            flaps = mark_flaps(&o, took, gone);
            if (flaps == SIZE_MAX) {
                st = SR_E_NOMEM;
                goto fail;
            }
            r.flaps += flaps;
        }
        size_t w = 0;
        for (size_t t = 0; t < o.tri_count; t++)
            if (!gone[t])
                memmove(o.tri + 3 * w++, o.tri + 3 * t, 3 * sizeof *o.tri);
        o.tri_count = w;
    }
    free(first);
    free(took);
    free(gone);
    *out = o;
    if (rep)
        *rep = r;
    return SR_OK;
fail:
    free(first);
    free(took);
    free(gone);
    sr_mesh_release(&o);
    return st;
}
