/*
 * reconstruct_slivers.c: the needles a union leaves folded away (recon_fold_slivers).
 * Where images met each other or the scan to rounding, the union leaves fins of
 * needles inside the solid (joined to the surface by edges of a micrometre): their
 * short edges are collapsed (sr_mesh_collapse_short_edges, which keeps nothing when a
 * face it moved crosses another: a collapse folded a neighbour over on three of the
 * shared parts' patches), kept only when the mesh stays closed with its volume.
 *
 * Only the triangles round the short edges go through the collapse: a few rings of
 * them, cut out as an open mesh whose rim the collapse never moves, put back in
 * place of what they were when their rim is the same and the volume with them is
 * the same. The whole restored part of a two-million-triangle scan was built as a
 * halfedge mesh for two short edges before (3 s of its 6 s union).
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mend.h"
#include "reconstruct_int.h"

#define SLIVER_EDGE_MM 0.005
/* Rings of triangles round a short edge's vertices cut out with it: the collapse moves
 * the short edge's ends and looks at the faces round them; the rim stays two rings
 * away. */
#define FOLD_RINGS 3

static bool short_edged(const sr_mesh *m, size_t t, double len)
{
    for (int k = 0; k < 3; k++) {
        const double *a = m->xyz + 3 * (size_t)m->tri[3 * t + k];
        const double *b = m->xyz + 3 * (size_t)m->tri[3 * t + (k + 1) % 3];
        double d2 = 0;
        for (int j = 0; j < 3; j++)
            d2 += (a[j] - b[j]) * (a[j] - b[j]);
        if (d2 < len * len)
            return true;
    }
    return false;
}

/* Six times the signed volume of the cones from o over the triangles (tri, count):
 * two pieces with the same rim differ by the volume between them, for any o (o on
 * the piece keeps the products small). */
static double volume6(const double *xyz, const uint32_t *tri, size_t count, const double o[3])
{
    double v = 0;
    for (size_t t = 0; t < count; t++) {
        double p[3][3];
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                p[k][j] = xyz[3 * (size_t)tri[3 * t + k] + j] - o[j];
        v += p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
             p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
             p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    }
    return v;
}

typedef struct at_point {
    double p[3];
    uint32_t id;
} at_point;

static int point_cmp(const void *x, const void *y)
{
    const at_point *a = x, *b = y;
    for (int k = 0; k < 3; k++)
        if (a->p[k] != b->p[k])
            return a->p[k] < b->p[k] ? -1 : 1;
    return 0;
}

static int key_cmp(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* The directed edges of tri (count triangles, vertex ids through map when not NULL)
 * that no triangle runs the other way, sorted into *out (malloc'ed); their count, or
 * SIZE_MAX when out of memory. */
static size_t rim_edges(const uint32_t *tri, size_t count, const uint32_t *map, uint64_t **out)
{
    uint64_t *all = malloc((3 * count + 1) * sizeof *all);
    uint64_t *rim = malloc((3 * count + 1) * sizeof *rim);
    if (!all || !rim) {
        free(all);
        free(rim);
        return SIZE_MAX;
    }
    for (size_t t = 0; t < count; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
            if (map) {
                a = map[a];
                b = map[b];
            }
            all[3 * t + k] = a << 32 | b;
        }
    qsort(all, 3 * count, sizeof *all, key_cmp);
    size_t n = 0;
    for (size_t i = 0; i < 3 * count; i++) {
        uint64_t rev = (all[i] & 0xffffffffu) << 32 | all[i] >> 32;
        if (!bsearch(&rev, all, 3 * count, sizeof *all, key_cmp))
            rim[n++] = all[i];
    }
    free(all);
    *out = rim;
    return n;
}

/* The collapse on the cut-out piece s (its triangles sel of m, local vertex ids; glob:
 * each local vertex's id in m) put back into m when it keeps the rim and the volume.
 * Returns the edges collapsed and kept; *whole is set when s alone is no oriented
 * manifold (the collapse is then for the whole of m). */
static size_t put_back(sr_mesh *m, const uint8_t *sel, const sr_mesh *s, const uint32_t *glob,
                       bool *whole)
{
    sr_mesh c = {0};
    size_t n = 0;
    if (sr_mesh_copy(&c, s) != SR_OK)
        return 0;
    size_t kept = 0;
    uint32_t *map = NULL;
    at_point *pts = NULL;
    uint64_t *rim0 = NULL, *rim1 = NULL;
    sr_status cst = sr_mesh_collapse_short_edges(&c, SLIVER_EDGE_MM, &n, NULL, NULL);
    *whole = cst == SR_E_INVALID; /* cut out pinched at a vertex: not a manifold alone */
    if (cst != SR_OK || n == 0)
        goto done;
    /* c's vertices that are s's (by position) keep their ids in m; the rest are new */
    pts = malloc((s->vertex_count + 1) * sizeof *pts);
    map = malloc((c.vertex_count + 1) * sizeof *map);
    if (!pts || !map)
        goto done;
    for (size_t v = 0; v < s->vertex_count; v++) {
        memcpy(pts[v].p, s->xyz + 3 * v, sizeof pts[v].p);
        pts[v].id = glob[v];
    }
    qsort(pts, s->vertex_count, sizeof *pts, point_cmp);
    size_t fresh = 0;
    for (size_t v = 0; v < c.vertex_count; v++) {
        at_point key = {{0, 0, 0}, 0};
        memcpy(key.p, c.xyz + 3 * v, sizeof key.p);
        const at_point *hit = bsearch(&key, pts, s->vertex_count, sizeof *pts, point_cmp);
        map[v] = hit ? hit->id : (uint32_t)(m->vertex_count + fresh++);
    }
    if (m->vertex_count + fresh > SR_MESH_MAX_COUNT)
        goto done;
    /* the same rim (so the mesh stays closed) and the same volume */
    size_t r0 = rim_edges(s->tri, s->tri_count, glob, &rim0);
    size_t r1 = rim_edges(c.tri, c.tri_count, map, &rim1);
    if (r0 == SIZE_MAX || r1 == SIZE_MAX || r0 != r1 || memcmp(rim0, rim1, r0 * sizeof *rim0))
        goto done;
    double v0 = sr_mesh_volume(m);
    const double *o = s->xyz;
    double dv =
        (volume6(c.xyz, c.tri, c.tri_count, o) - volume6(s->xyz, s->tri, s->tri_count, o)) / 6.0;
    if (!(fabs(dv) <= 1e-6 * fabs(v0) + 1e-3))
        goto done;
    /* m's triangles but sel's, then c's; the vertices no triangle uses then dropped */
    size_t nt = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        if (!sel[t])
            memmove(m->tri + 3 * nt++, m->tri + 3 * t, 3 * sizeof *m->tri);
    double *xyz = realloc(m->xyz, (m->vertex_count + fresh + 1) * 3 * sizeof *xyz);
    uint32_t *tri = realloc(m->tri, (nt + c.tri_count + 1) * 3 * sizeof *tri);
    if (xyz)
        m->xyz = xyz;
    if (tri)
        m->tri = tri;
    if (!xyz || !tri) { /* m's triangles were moved down: put sel's back at the end */
        kept = SIZE_MAX;
        goto done;
    }
    for (size_t v = 0; v < c.vertex_count; v++)
        if (map[v] >= m->vertex_count)
            memcpy(m->xyz + 3 * (size_t)map[v], c.xyz + 3 * v, 3 * sizeof *xyz);
    for (size_t k = 0; k < 3 * c.tri_count; k++)
        m->tri[3 * nt + k] = map[c.tri[k]];
    m->tri_count = nt + c.tri_count;
    m->vertex_count += fresh;
    kept = n;
done:
    if (kept == SIZE_MAX) {
        /* out of memory after m's own triangles were packed: s's go back after them */
        size_t packed = 0;
        for (size_t t = 0; t < m->tri_count; t++)
            packed += !sel[t];
        for (size_t k = 0; k < 3 * s->tri_count; k++)
            m->tri[3 * packed + k] = glob[s->tri[k]];
        kept = 0;
    }
    free(pts);
    free(map);
    free(rim0);
    free(rim1);
    sr_mesh_release(&c);
    return kept;
}

/* The vertices of m no triangle uses, dropped (the others keep their order). */
static void drop_unused(sr_mesh *m)
{
    uint32_t *re = malloc((m->vertex_count + 1) * sizeof *re);
    if (!re)
        return;
    memset(re, 0xff, (m->vertex_count + 1) * sizeof *re);
    for (size_t k = 0; k < 3 * m->tri_count; k++)
        re[m->tri[k]] = 0;
    size_t nv = 0;
    for (size_t v = 0; v < m->vertex_count; v++)
        if (re[v] == 0) {
            re[v] = (uint32_t)nv;
            memmove(m->xyz + 3 * nv, m->xyz + 3 * v, 3 * sizeof *m->xyz);
            nv++;
        }
    for (size_t k = 0; k < 3 * m->tri_count; k++)
        m->tri[k] = re[m->tri[k]];
    m->vertex_count = nv;
    free(re);
}

/* The collapse on the whole of m (a piece cut out of it was no oriented manifold, or
 * was most of it). */
static size_t fold_whole(sr_mesh *m)
{
    sr_mesh copy = {0};
    size_t n = 0;
    if (sr_mesh_copy(&copy, m) != SR_OK)
        return 0;
    double v0 = sr_mesh_volume(m);
    sr_status cst = sr_mesh_collapse_short_edges(&copy, SLIVER_EDGE_MM, &n, NULL, NULL);
    if (cst != SR_OK || n == 0 || !sr_mesh_is_closed(&copy) ||
        !(fabs(sr_mesh_volume(&copy) - v0) <= 1e-6 * fabs(v0) + 1e-3)) {
        sr_mesh_release(&copy);
        return 0;
    }
    sr_mesh_release(m);
    *m = copy;
    return n;
}

size_t recon_fold_slivers(sr_mesh *m, size_t *looked_at)
{
    uint8_t *vin = NULL, *sel = calloc(m->tri_count + 1, 1);
    uint32_t *glob = NULL;
    sr_mesh s = {0};
    size_t n = 0, seeds = 0;
    bool whole = false;
    if (looked_at)
        *looked_at = 0;
    if (!sel)
        return 0;
    for (size_t t = 0; t < m->tri_count; t++)
        if (short_edged(m, t, SLIVER_EDGE_MM)) {
            sel[t] = 1;
            seeds++;
        }
    if (!seeds)
        goto done;
    vin = calloc(m->vertex_count + 1, 1);
    if (!vin)
        goto done;
    for (int ring = 0; ring < FOLD_RINGS; ring++) {
        for (size_t t = 0; t < m->tri_count; t++)
            for (int k = 0; sel[t] && k < 3; k++)
                vin[m->tri[3 * t + k]] = 1;
        for (size_t t = 0; t < m->tri_count; t++)
            sel[t] =
                sel[t] || vin[m->tri[3 * t]] || vin[m->tri[3 * t + 1]] || vin[m->tri[3 * t + 2]];
    }
    size_t nt = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        nt += sel[t];
    whole = 4 * nt > m->tri_count;
    if (whole)
        goto done;
    glob = malloc((m->vertex_count + 1) * sizeof *glob);
    if (!glob || sr_mesh_subset(m, sel, &s, glob) != SR_OK)
        goto done;
    if (looked_at)
        *looked_at = nt;
    n = put_back(m, sel, &s, glob, &whole);
    if (n)
        drop_unused(m);
done:
    free(sel);
    free(vin);
    free(glob);
    sr_mesh_release(&s);
    if (whole && looked_at)
        *looked_at = m->tri_count;
    return whole ? fold_whole(m) : n;
}
