/*
 * scan_close.c: the openings of a scan closed (scan_describe.h, sr_scan_close_openings).
 * A loop whose rim lies in a plane (the face the part stood on, a hole in a flat face) is
 * closed in that plane together with every other rim in it, by the constrained
 * triangulation of the region they wind around (bridge/planar_fill.h): an outer rim with
 * the rims of the bores through the base is one face with holes, a concave rim is filled
 * inside only, so the closed surface is the part's own face. Where two rims cross in the
 * plane (a noisy rim folding over itself, two rims touching), the triangulation cuts them
 * at a point that both rim edges then pass through: the scan's triangle on each such edge
 * is split there, so the fill meets the scan edge for edge. Any other loop (a hole in a
 * curved face) is closed by a fan: a vertex at its centroid and one triangle per rim
 * edge, walked against the rim. Last, a vertex the closing left pinched (two rims that
 * touched) gets one copy per fan (mesh/mesh_pinch.h). The image method's voxels count
 * crossings along z by the winding rule (images/voxels.h): an open base or a hole lets a
 * column miss a crossing and fills or empties it from there on; closed, every column
 * crosses a closed surface again. Which rims lie in one plane is scan_plane.c's
 * (scan_int.h).
 */
#include "mesh/scan_describe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/planar_fill.h"
#include "mesh/mesh_pinch.h"
#include "mesh/scan_int.h"
#include "mesh/tri_flaps.h"

/* What the closing appends: vertices and triangles, grown as needed. */
typedef struct grow {
    double *xyz;
    size_t nv, cap_v;
    uint32_t *tri;
    size_t nt, cap_t;
    uint32_t *cut; /* rim edges cut by a fill: records a, b, k, then k points from a to b */
    size_t ncut, cap_cut;
} grow;

static bool cut_room(grow *g, size_t add)
{
    if (g->ncut + add > g->cap_cut) {
        size_t cap = 2 * (g->ncut + add) + 16;
        uint32_t *p = realloc(g->cut, cap * sizeof *p);
        if (!p)
            return false;
        g->cut = p;
        g->cap_cut = cap;
    }
    return true;
}

static bool grow_room(grow *g, size_t add_v, size_t add_t)
{
    if (g->nv + add_v > g->cap_v) {
        size_t cap = 2 * (g->nv + add_v) + 16;
        double *p = realloc(g->xyz, 3 * cap * sizeof *p);
        if (!p)
            return false;
        g->xyz = p;
        g->cap_v = cap;
    }
    if (g->nt + add_t > g->cap_t) {
        size_t cap = 2 * (g->nt + add_t) + 16;
        uint32_t *p = realloc(g->tri, 3 * cap * sizeof *p);
        if (!p)
            return false;
        g->tri = p;
        g->cap_t = cap;
    }
    return true;
}

/* The fan of the simple cycle cyc[0..n) (rim vertices, walked in that order): a new
 * vertex (index base_v + its place in g) at its centroid. */
static bool fan_cycle(const sr_mesh *mesh, const uint32_t *cyc, size_t n, size_t base_v, grow *g)
{
    if (!grow_room(g, 1, n))
        return false;
    double c[3] = {0, 0, 0};
    for (size_t e = 0; e < n; e++)
        for (int k = 0; k < 3; k++)
            c[k] += mesh->xyz[3 * (size_t)cyc[e] + k] / (double)n;
    uint32_t v = (uint32_t)(base_v + g->nv);
    memcpy(g->xyz + 3 * g->nv++, c, sizeof c);
    for (size_t e = 0; e < n; e++) {
        uint32_t *t = g->tri + 3 * g->nt++;
        t[0] = cyc[(e + 1) % n]; /* the rim walks a -> b: the fan walks b -> a */
        t[1] = cyc[e];
        t[2] = v;
    }
    return true;
}

/* The simple cycles of loop l's walk appended to cyc (cycle k: cs[k] .. cs[k+1]-1,
 * cs[nc] on entry the next free place), cut where the walk passes a vertex twice
 * (stack: room for its edges); returns the cycles now in cs. */
static size_t walk_cycles(const sr_scan_desc *d, const sr_scan_loop *l, uint32_t *stack,
                          uint32_t *cyc, size_t *ncv, size_t *cs, size_t nc)
{
    const uint32_t *lv = d->loop_verts + l->first;
    size_t top = 0;
    for (size_t e = 0; e <= l->edges; e++) {
        size_t j = 0;
        if (e < l->edges)
            while (j < top && stack[j] != lv[e])
                j++;
        if (e == l->edges || j < top) { /* back at stack[j]: stack[j..top) closes there */
            if (top - j >= 3) {
                memcpy(cyc + *ncv, stack + j, (top - j) * sizeof *cyc);
                *ncv += top - j;
                cs[++nc] = *ncv;
            }
            top = j;
        }
        if (e < l->edges)
            stack[top++] = lv[e];
    }
    return nc;
}

/* The fans of loop l: one per simple cycle of its walk. A walk through a vertex twice
 * (two rims touching there, a fold of the face the part stood on joined to the rim at
 * one vertex) is cut there into cycles, each fanned from its own centroid: one fan of
 * the whole walk would use its edges to that vertex twice over each (s60221409p14, whose
 * base loop passed one vertex nine times: edges used up to 18 times). */
static bool fan(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l, size_t base_v,
                grow *g)
{
    uint32_t *stack = malloc((l->edges + 1) * sizeof *stack);
    uint32_t *cyc = malloc((l->edges + 1) * sizeof *cyc);
    size_t *cs = malloc((l->edges + 2) * sizeof *cs);
    bool ok = stack && cyc && cs;
    size_t ncyc = 0, ncv = 0;
    if (ok) {
        cs[0] = 0;
        ncyc = walk_cycles(d, l, stack, cyc, &ncv, cs, 0);
    }
    for (size_t k = 0; ok && k < ncyc; k++)
        ok = fan_cycle(mesh, cyc + cs[k], cs[k + 1] - cs[k], base_v, g);
    free(stack);
    free(cyc);
    free(cs);
    return ok;
}

/* A loop of three edges (a triangle the scan lacks: a pinhole, or a sliver of a wall
 * beside the face it stood on, seen edge on) closed by that triangle, walked against
 * the rim. Such a sliver lies within the noise of the face's plane and joined its
 * group, and its rim, crossing the face's own in the plane, made the face's fill wind
 * twice along it: the face was fanned from its centroid, across a fork's gap
 * (s46368p10, open: 1.4 mm). */
static bool close_triangle(const sr_scan_desc *d, const sr_scan_loop *l, grow *g)
{
    if (!grow_room(g, 0, 1))
        return false;
    const uint32_t *lv = d->loop_verts + l->first;
    uint32_t *t = g->tri + 3 * g->nt++;
    t[0] = lv[2];
    t[1] = lv[1];
    t[2] = lv[0];
    return true;
}

static int key_cmp(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static bool has_key(const uint64_t *keys, size_t n, uint64_t k)
{
    return bsearch(&k, keys, n, sizeof k, key_cmp) != NULL;
}

/* Whether the fill (nt triangles tri, in mesh vertices) closes the rims exactly: every
 * rim edge a -> b (rim: nrim pairs, the rims' edges cut where the fill cut them) met
 * once as b -> a and never as a -> b, no edge of the fill used twice the same way, and
 * no other edge of the fill on its border. Two rim vertices the triangulation merged, a
 * face it wound around twice, fail. */
static bool fill_fits(const uint32_t *tri, size_t nt, const uint32_t *rim, size_t nrim)
{
    uint64_t *keys = malloc((3 * nt + 1) * sizeof *keys);
    if (!keys)
        return false;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            keys[3 * t + k] = (uint64_t)tri[3 * t + k] << 32 | tri[3 * t + (k + 1) % 3];
    size_t n = 3 * nt;
    qsort(keys, n, sizeof *keys, key_cmp);
    bool ok = true;
    for (size_t i = 1; ok && i < n; i++)
        ok = keys[i] != keys[i - 1];
    size_t border = 0;
    for (size_t i = 0; ok && i < n; i++)
        if (!has_key(keys, n, keys[i] << 32 | keys[i] >> 32))
            border++;
    for (size_t r = 0; ok && r < nrim; r++) {
        uint64_t a = rim[2 * r], b = rim[2 * r + 1];
        ok = has_key(keys, n, b << 32 | a) && !has_key(keys, n, a << 32 | b);
    }
    free(keys);
    return ok && border == nrim;
}

/* A cycle of a plane's rims narrower than this on average (twice its area over its
 * perimeter, mm) is a petal: the walk out along a wall's bottom row of needles and back
 * along the next, from a corner they fan from, lying within the noise of the face the
 * part stood on. Closed alone (a fan), not outlined for the face's fill: there it wound
 * the face twice or not at all along the needles, the fill could not meet the rim, and
 * the face was fanned from its centroid, across a fork's gap (s46368p10, open: 1.4 mm)
 * and over a clamp's foot holes. Zipped side to side (zip_cycle), else fanned from its
 * own centroid. */
#define PETAL_WIDTH_MM SR_SCAN_PLANE_RMS_MM

static double dist2(const sr_mesh *mesh, uint32_t a, uint32_t b)
{
    const double *p = mesh->xyz + 3 * (size_t)a, *q = mesh->xyz + 3 * (size_t)b;
    return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
           (p[2] - q[2]) * (p[2] - q[2]);
}

/* The scan's edges lo << 32 | hi, sorted, made the first time a petal asks (the scan
 * does not change while its openings are closed: what they add goes to the grow):
 * once per closing, where each plane's group with a petal sorted all of them anew (a
 * two-million-triangle scan's closing went from 8 s to 23 s). */
typedef struct scan_edges {
    uint64_t *keys;
    size_t n;
} scan_edges;

static bool scan_edges_ready(const sr_mesh *mesh, scan_edges *e)
{
    if (e->keys)
        return true;
    size_t n = 3 * mesh->tri_count;
    uint64_t *keys = malloc((n + 1) * sizeof *keys);
    if (!keys)
        return false;
    for (size_t t = 0; t < mesh->tri_count; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = mesh->tri[3 * t + k], b = mesh->tri[3 * t + (k + 1) % 3];
            keys[3 * t + k] = a < b ? a << 32 | b : b << 32 | a;
        }
    if (sr_scan_sort_edges(keys, n, sizeof *keys, mesh->vertex_count) != SR_OK) {
        free(keys);
        return false;
    }
    e->keys = keys;
    e->n = n;
    return true;
}

/* Whether a-b is an edge of the scan (keys: its edges lo << 32 | hi, n of them, sorted). */
static bool scan_edge(const uint64_t *keys, size_t n, uint32_t a, uint32_t b)
{
    uint64_t k = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
    return has_key(keys, n, k);
}

/* A petal cyc[0..n) (walked out from cyc[0] and back) closed by zipping its two sides
 * together from cyc[0], each step across the shorter diagonal that is no edge of the
 * scan (keys, nk: its edges sorted): n - 2 thin triangles within the sliver. A fan from
 * its centroid reaches along a long petal and crossed what lies beside it (a nut's hole
 * by a merlon then read as a section); a diagonal along a needle's own edge would use
 * that edge four times. False, g unchanged, when no step can be taken that way. */
static bool zip_cycle(const sr_mesh *mesh, const uint32_t *cyc, size_t n, const uint64_t *keys,
                      size_t nk, grow *g)
{
    if (n < 3 || !grow_room(g, 0, n - 2) || (n > 3 && scan_edge(keys, nk, cyc[1], cyc[n - 1])))
        return false;
    uint32_t *t = g->tri + 3 * g->nt;
    size_t lo = 1, hi = n - 1;
    t[0] = cyc[1]; /* the rim walks cyc[0] -> cyc[1] and cyc[n-1] -> cyc[0] */
    t[1] = cyc[0];
    t[2] = cyc[n - 1];
    t += 3;
    while (hi - lo > 1) {
        bool up_ok = hi - lo == 2 || !scan_edge(keys, nk, cyc[lo + 1], cyc[hi]);
        bool down_ok = hi - lo == 2 || !scan_edge(keys, nk, cyc[lo], cyc[hi - 1]);
        if (!up_ok && !down_ok)
            return false; /* g->nt not moved: the triangles written are dropped */
        bool up = up_ok && (!down_ok ||
                            dist2(mesh, cyc[lo + 1], cyc[hi]) <= dist2(mesh, cyc[lo], cyc[hi - 1]));
        if (up) {
            t[0] = cyc[lo + 1];
            t[1] = cyc[lo];
            t[2] = cyc[hi];
            lo++;
        } else {
            t[0] = cyc[lo];
            t[1] = cyc[hi];
            t[2] = cyc[hi - 1];
            hi--;
        }
        t += 3;
    }
    g->nt += n - 2;
    return true;
}

/* Rims crossing one another more often than this (a constant plus a share of their
 * points) are a tangle of scraps, not the outline of a face with a fold here and there:
 * the generated parts' bases filled with up to one crossing in five points; a
 * 658,000-triangle spline's base, left in 4,938 scraps, crossed three times per point,
 * and its groups, each seeding another when its fill failed, took minutes. */
#define TANGLE_CROSSINGS 64
#define TANGLE_PER_POINT 0.5

/* The fill of the outlines (count loops of uv, start, vid: pts points, in the plane's
 * frame c, e1, e2) with the petals (cycles petal[0..npetal) of cyc, cs) zipped alone:
 * appended to g when the triangulation meets every outline edge once the other way
 * (*done), else nothing (*tangled when the rims cross too often to try); SR_E_NOMEM. */
static sr_status fill_outlines(const sr_mesh *mesh, const double c[3], const double e1[3],
                               const double e2[3], const double *uv, const size_t *start,
                               size_t count, const uint32_t *vid, size_t pts, const uint32_t *cyc,
                               const size_t *cs, const size_t *petal, size_t npetal, size_t base_v,
                               scan_edges *edges, grow *g, bool *done, bool *tangled, sr_err *err)
{
    sr_planar_fill_out fo = {0};
    uint32_t *fid = NULL, *rim = NULL, *mtri = NULL;
    double *acc = NULL;
    sr_err ferr;
    sr_status st = SR_OK;
    size_t most = TANGLE_CROSSINGS + (size_t)(TANGLE_PER_POINT * (double)pts);
    *tangled = sr_scan_rim_crossings(uv, start, count, most) > most;
    st = *tangled ? SR_E_INVALID : sr_planar_fill(uv, start, count, &fo, &ferr);
    if (st == SR_E_NOMEM) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    if (st != SR_OK || fo.tri_count == 0) {
        st = SR_OK; /* fanned instead */
        goto out;
    }
    size_t nx = fo.extra_count, nt = fo.tri_count, ncut = fo.split_first[pts];
    fid = malloc((pts + nx) * sizeof *fid);
    rim = malloc(2 * (pts + ncut) * sizeof *rim);
    mtri = malloc(3 * nt * sizeof *mtri);
    acc = calloc(4 * nx + 1, sizeof *acc); /* per made point: x, y, z summed, count */
    if (!fid || !rim || !mtri || !acc) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    for (size_t x = 0; x < pts + nx; x++)
        fid[x] = x < pts ? vid[x] : (uint32_t)(base_v + g->nv + (x - pts));
    for (size_t i = 0; i < 3 * nt; i++)
        mtri[i] = fid[fo.tri[i]];
    /* the rims' edges, cut where the fill cut them; a made point lies where the rim edges
     * through it are, on average (they cross in the plane, not quite in space) */
    size_t nrim = 0;
    for (size_t i = 0; i < count; i++)
        for (size_t q = start[i]; q < start[i + 1]; q++) {
            size_t q2 = q + 1 < start[i + 1] ? q + 1 : start[i];
            uint32_t prev = vid[q];
            const double *pa = mesh->xyz + 3 * (size_t)vid[q],
                         *pb = mesh->xyz + 3 * (size_t)vid[q2];
            double du = uv[2 * q2] - uv[2 * q], dv = uv[2 * q2 + 1] - uv[2 * q + 1];
            double len2 = du * du + dv * dv;
            for (size_t s = fo.split_first[q]; s < fo.split_first[q + 1]; s++) {
                uint32_t x = fo.split[s];
                rim[2 * nrim] = prev;
                rim[2 * nrim++ + 1] = fid[x];
                prev = fid[x];
                if (x < pts || !(len2 > 0))
                    continue;
                const double *xu = fo.extra_uv + 2 * (x - pts);
                double t = ((xu[0] - uv[2 * q]) * du + (xu[1] - uv[2 * q + 1]) * dv) / len2;
                t = t < 0 ? 0 : t > 1 ? 1 : t;
                double *a = acc + 4 * (x - pts);
                for (int k = 0; k < 3; k++)
                    a[k] += pa[k] + t * (pb[k] - pa[k]);
                a[3] += 1;
            }
            rim[2 * nrim] = prev;
            rim[2 * nrim++ + 1] = vid[q2];
        }
    if (!fill_fits(mtri, nt, rim, nrim))
        goto out; /* the loops fold, or overlap: fanned instead */
    if (!grow_room(g, nx, nt) || !cut_room(g, 3 * pts + ncut)) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    for (size_t k = 0; k < nx; k++) {
        double *v = g->xyz + 3 * (g->nv + k);
        const double *a = acc + 4 * k;
        for (int j = 0; j < 3; j++)
            v[j] = a[3] > 0 ? a[j] / a[3]
                            : c[j] + fo.extra_uv[2 * k] * e1[j] + fo.extra_uv[2 * k + 1] * e2[j];
    }
    memcpy(g->tri + 3 * g->nt, mtri, 3 * nt * sizeof *mtri);
    for (size_t i = 0; i < count; i++)
        for (size_t q = start[i]; q < start[i + 1]; q++) {
            size_t k = fo.split_first[q + 1] - fo.split_first[q];
            if (k == 0)
                continue;
            uint32_t *r = g->cut + g->ncut;
            r[0] = vid[q];
            r[1] = vid[q + 1 < start[i + 1] ? q + 1 : start[i]];
            r[2] = (uint32_t)k;
            for (size_t j = 0; j < k; j++)
                r[3 + j] = fid[fo.split[fo.split_first[q] + j]];
            g->ncut += 3 + k;
        }
    g->nv += nx;
    g->nt += nt;
    if (npetal > 0 && !scan_edges_ready(mesh, edges)) { /* for the petals' zips */
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    for (size_t k = 0; k < npetal; k++) {
        const uint32_t *pc = cyc + cs[petal[k]];
        size_t pn = cs[petal[k] + 1] - cs[petal[k]];
        if (!zip_cycle(mesh, pc, pn, edges->keys, edges->n, g) &&
            !fan_cycle(mesh, pc, pn, base_v, g)) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            goto out;
        }
    }
    *done = true;
out:
    sr_planar_fill_free(&fo);
    free(fid);
    free(rim);
    free(mtri);
    free(acc);
    return st;
}

/* Closes the loops group[0..count) (all on the plane c, n) by the triangulation of the
 * region they bound. *done false (g unchanged in its counts) when the triangulation
 * gives nothing usable (then the caller fans them), *tangled true too when the rims
 * cross one another too often to try it; SR_E_NOMEM. */
static sr_status plane_fill(const sr_mesh *mesh, const sr_scan_desc *d, const size_t *group,
                            size_t count, const double c[3], const double n[3], size_t base_v,
                            scan_edges *edges, grow *g, bool *done, bool *tangled, sr_err *err)
{
    *done = false;
    *tangled = false;
    double e1[3], e2[3];
    sr_scan_plane_frame(n, e1, e2);
    size_t all = 0;
    for (size_t i = 0; i < count; i++)
        all += d->loops[group[i]].edges;
    /* the loops' walks cut into simple cycles (cyc, cycle k: cs[k] .. cs[k+1]-1), each
     * an outline for the fill or a petal closed alone */
    uint32_t *cyc = malloc((all + 1) * sizeof *cyc), *stack = malloc((all + 1) * sizeof *stack);
    size_t *cs = malloc((all + 2) * sizeof *cs), *petal = malloc((all + 1) * sizeof *petal);
    double *uv = malloc(2 * (all + 1) * sizeof *uv);
    size_t *start = malloc((all + 2) * sizeof *start);
    uint32_t *vid = malloc((all + 1) * sizeof *vid);
    sr_status st = SR_OK;
    if (!cyc || !stack || !cs || !petal || !uv || !start || !vid) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    size_t ncyc = 0, ncv = 0;
    cs[0] = 0;
    for (size_t i = 0; i < count; i++)
        ncyc = walk_cycles(d, &d->loops[group[i]], stack, cyc, &ncv, cs, ncyc);
    /* the cycles narrower than a petal closed alone, the others outlined */
    size_t p = 0, loops = 0, npetal = 0;
    for (size_t k = 0; k < ncyc; k++) {
        size_t first = p;
        double area = 0, perimeter = 0;
        for (size_t q = cs[k]; q < cs[k + 1]; q++, p++) {
            vid[p] = cyc[q];
            const double *x = mesh->xyz + 3 * (size_t)vid[p];
            double r[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
            uv[2 * p] = r[0] * e1[0] + r[1] * e1[1] + r[2] * e1[2];
            uv[2 * p + 1] = r[0] * e2[0] + r[1] * e2[1] + r[2] * e2[2];
        }
        for (size_t q = first; q < p; q++) {
            size_t q2 = q + 1 < p ? q + 1 : first;
            area += uv[2 * q] * uv[2 * q2 + 1] - uv[2 * q2] * uv[2 * q + 1];
            perimeter += hypot(uv[2 * q2] - uv[2 * q], uv[2 * q2 + 1] - uv[2 * q + 1]);
        }
        if (fabs(area) < PETAL_WIDTH_MM * perimeter) { /* 2 x area / perimeter: its width */
            petal[npetal++] = k;
            p = first;
            continue;
        }
        start[loops++] = first;
    }
    start[loops] = p;
    if (loops > 0) /* else petals only: fanned instead */
        st = fill_outlines(mesh, c, e1, e2, uv, start, loops, vid, p, cyc, cs, petal, npetal,
                           base_v, edges, g, done, tangled, err);
out:
    free(cyc);
    free(stack);
    free(cs);
    free(petal);
    free(uv);
    free(start);
    free(vid);
    return st;
}

typedef struct cut_key {
    uint64_t key; /* a << 32 | b */
    size_t at;    /* its record in grow.cut */
} cut_key;

static int cut_cmp(const void *pa, const void *pb)
{
    uint64_t x = ((const cut_key *)pa)->key, y = ((const cut_key *)pb)->key;
    return (x > y) - (x < y);
}

/* The scan's triangles (mesh's, before the closing) on a rim edge a fill cut, split
 * through the cut points: one cut edge, a fan from the opposite corner; more, a fan from
 * a new vertex at the triangle's centroid. The first piece replaces the triangle (into
 * rep: triangle index, then its 3 corners; *nrep of them), the others are appended to g.
 * false: out of memory. */
static bool cut_rims(const sr_mesh *mesh, size_t base_v, grow *g, uint32_t **rep, size_t *nrep)
{
    size_t nk = 0;
    for (size_t i = 0; i < g->ncut; i += 3 + g->cut[i + 2])
        nk++;
    *rep = NULL;
    *nrep = 0;
    if (nk == 0)
        return true;
    cut_key *keys = malloc(nk * sizeof *keys);
    uint32_t *poly = NULL, *out = malloc(4 * nk * sizeof *out);
    size_t cap_poly = 0, no = 0, cap_out = nk;
    bool ok = keys && out;
    nk = 0;
    for (size_t i = 0; ok && i < g->ncut; i += 3 + g->cut[i + 2])
        keys[nk++] = (cut_key){(uint64_t)g->cut[i] << 32 | g->cut[i + 1], i};
    if (ok)
        qsort(keys, nk, sizeof *keys, cut_cmp);
    for (size_t t = 0; ok && t < mesh->tri_count; t++) {
        const uint32_t *v = mesh->tri + 3 * t;
        const cut_key *hit[3];
        size_t nh = 0, np = 3, edge = 0;
        for (int k = 0; k < 3; k++) {
            cut_key probe = {(uint64_t)v[k] << 32 | v[(k + 1) % 3], 0};
            hit[k] = bsearch(&probe, keys, nk, sizeof *keys, cut_cmp);
            if (hit[k]) {
                nh++;
                edge = (size_t)k;
                np += g->cut[hit[k]->at + 2];
            }
        }
        if (nh == 0)
            continue;
        if (np > cap_poly) {
            cap_poly = 2 * np;
            uint32_t *p2 = realloc(poly, cap_poly * sizeof *poly);
            if (!p2) {
                ok = false;
                break;
            }
            poly = p2;
        }
        size_t n = 0; /* the triangle's border, corners and cut points, from corner edge */
        for (int k = 0; k < 3; k++) {
            size_t e = (edge + (size_t)k) % 3;
            poly[n++] = v[e];
            if (hit[e])
                for (uint32_t j = 0; j < g->cut[hit[e]->at + 2]; j++)
                    poly[n++] = g->cut[hit[e]->at + 3 + j];
        }
        uint32_t apex = v[(edge + 2) % 3];
        size_t pieces = nh == 1 ? n - 2 : n;
        if (!grow_room(g, 1, pieces)) {
            ok = false;
            break;
        }
        if (nh > 1) {
            double *cen = g->xyz + 3 * g->nv;
            for (int j = 0; j < 3; j++)
                cen[j] = (mesh->xyz[3 * (size_t)v[0] + j] + mesh->xyz[3 * (size_t)v[1] + j] +
                          mesh->xyz[3 * (size_t)v[2] + j]) /
                         3;
            apex = (uint32_t)(base_v + g->nv++);
        }
        for (size_t i = 0; i < pieces; i++) {
            uint32_t piece[3] = {poly[i], poly[(i + 1) % n], apex};
            if (i == 0) {
                if (no + 1 > cap_out) { /* more triangles than records: grow */
                    uint32_t *o2 = realloc(out, 4 * 2 * (no + 1) * sizeof *out);
                    if (!o2) {
                        ok = false;
                        break;
                    }
                    out = o2;
                    cap_out = 2 * (no + 1);
                }
                out[4 * no] = (uint32_t)t;
                memcpy(out + 4 * no++ + 1, piece, sizeof piece);
            } else {
                memcpy(g->tri + 3 * g->nt++, piece, sizeof piece);
            }
        }
    }
    free(keys);
    free(poly);
    if (!ok) {
        free(out);
        return false;
    }
    *rep = out;
    *nrep = no;
    return true;
}

/* Removes every pair of triangles on the same three corners walked opposite ways where
 * one of them is the closing's (index >= nt): a fill folding back over a scan triangle
 * standing on the rim (a fold of the rim, wound -1) covers it once each way, a flap of no
 * volume whose edges would be used four times; both go (their sum is nothing). Only
 * triangles whose corners are all rim or new vertices (touched) can pair. d's
 * tri_component and triangles follow the scan's triangles removed. */
static sr_status cancel_folds(sr_mesh *mesh, sr_scan_desc *d, size_t nt, const bool *touched,
                              sr_err *err)
{
    bool *pick = malloc(mesh->tri_count + 1);
    bool *gone = calloc(mesh->tri_count + 1, sizeof *gone);
    size_t removed = SIZE_MAX;
    if (pick && gone) {
        for (size_t t = 0; t < mesh->tri_count; t++) {
            const uint32_t *v = mesh->tri + 3 * t;
            pick[t] = touched[v[0]] && touched[v[1]] && touched[v[2]];
        }
        removed = sr_tri_flaps_pair(mesh, pick, nt, gone);
    }
    free(pick);
    if (removed == SIZE_MAX) {
        free(gone);
        return sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    }
    if (removed > 0) {
        size_t w = 0, wd = 0;
        for (size_t t = 0; t < mesh->tri_count; t++) {
            if (gone[t]) {
                if (t < d->triangles && d->components[d->tri_component[t]].triangles > 0)
                    d->components[d->tri_component[t]].triangles--;
                continue;
            }
            if (t < d->triangles)
                d->tri_component[wd++] = d->tri_component[t];
            memmove(mesh->tri + 3 * w++, mesh->tri + 3 * t, 3 * sizeof *mesh->tri);
        }
        d->triangles = wd;
        mesh->tri_count = w;
    }
    free(gone);
    return SR_OK;
}

/* Whether every vertex of component comp of d lies on the plane (c, n) within
 * SR_SCAN_PLANE_MAX_MM. */
static bool component_on_plane(const sr_mesh *mesh, const sr_scan_desc *d, size_t comp,
                               const double c[3], const double n[3])
{
    for (size_t t = 0; t < d->triangles; t++) {
        if (d->tri_component[t] != comp)
            continue;
        for (int k = 0; k < 3; k++) {
            const double *p = mesh->xyz + 3 * (size_t)mesh->tri[3 * t + k];
            double h = (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2];
            if (fabs(h) > SR_SCAN_PLANE_MAX_MM)
                return false;
        }
    }
    return true;
}

/* Takes out of group (count loops, the first the group's own) every loop round an island:
 * a component other than the largest lying wholly on the group's plane (c, n), a piece
 * of the face the scan lost that the scanner kept (a few noisy triangles, often folded).
 * The fill covers its place; the island is flagged stray (dropped with the strays) and
 * its loop counted closed in the plane. Returns the loops left. */
static size_t drop_islands(const sr_mesh *mesh, sr_scan_desc *d, size_t *group, size_t count,
                           const double c[3], const double n[3], const uint32_t *vcomp,
                           sr_scan_closing *done, size_t *n_closed)
{
    size_t kept = 1;
    for (size_t k = 1; k < count; k++) {
        const sr_scan_loop *l = &d->loops[group[k]];
        uint32_t comp = vcomp[d->loop_verts[l->first]];
        bool island = comp != 0 && comp != UINT32_MAX && comp < d->component_count &&
                      (d->components[comp].stray || component_on_plane(mesh, d, comp, c, n));
        if (!island) {
            group[kept++] = group[k];
            continue;
        }
        if (!d->components[comp].stray) {
            d->components[comp].stray = true;
            d->strays++;
            d->stray_triangles += d->components[comp].triangles;
            d->stray_area_mm2 += d->components[comp].area_mm2;
        }
        done[group[k]] = SR_SCAN_IN_PLANE;
        (*n_closed)++;
    }
    return kept;
}

sr_status sr_scan_close_openings(sr_mesh *mesh, sr_scan_desc *d, double max_span_mm2,
                                 size_t *closed, sr_err *err)
{
    return sr_scan_close_openings_how(mesh, d, max_span_mm2, closed, NULL, err);
}

sr_status sr_scan_close_openings_how(sr_mesh *mesh, sr_scan_desc *d, double max_span_mm2,
                                     size_t *closed, sr_scan_closing *how, sr_err *err)
{
    size_t nv = mesh->vertex_count, nt = mesh->tri_count, n_closed = 0, nrep = 0;
    grow g = {0};
    scan_edges edges = {NULL, 0};
    uint32_t *rep = NULL; /* scan triangles cut on a rim: index, then the first piece */
    sr_scan_closing *done = calloc(d->loop_count + 1, sizeof *done); /* how, as it goes */
    size_t *group = malloc((d->loop_count + 1) * sizeof *group);
    uint32_t *vcomp = malloc((nv + 1) * sizeof *vcomp); /* each vertex's component */
    sr_status st = SR_OK;
    if (!done || !group || !vcomp) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    for (size_t v = 0; v < nv; v++)
        vcomp[v] = UINT32_MAX;
    for (size_t t = 0; t < d->triangles && t < nt; t++)
        for (int k = 0; k < 3; k++)
            vcomp[mesh->tri[3 * t + k]] = (uint32_t)d->tri_component[t];
    for (size_t i = 0; i < d->loop_count && st == SR_OK; i++) {
        const sr_scan_loop *l = &d->loops[i];
        uint32_t comp = vcomp[d->loop_verts[l->first]];
        if (done[i] != SR_SCAN_LEFT_OPEN || l->edges != 3 ||
            !sr_scan_loop_eligible(l, max_span_mm2) ||
            (comp < d->component_count && d->components[comp].triangles < 2))
            continue; /* a lone triangle's rim: an island, a stray */
        if (!close_triangle(d, l, &g))
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        done[i] = SR_SCAN_IN_PLANE;
        n_closed++;
    }
    for (size_t i = 0; i < d->loop_count && st == SR_OK; i++) {
        const sr_scan_loop *l = &d->loops[i];
        if (done[i] != SR_SCAN_LEFT_OPEN || !sr_scan_loop_eligible(l, max_span_mm2))
            continue;
        double c[3], n[3];
        bool filled = false;
        size_t count = sr_scan_plane_group(mesh, d, i, done, max_span_mm2, group, c, n);
        if (count > 0) {
            count = drop_islands(mesh, d, group, count, c, n, vcomp, done, &n_closed);
            bool tangled = false;
            st = plane_fill(mesh, d, group, count, c, n, nv, &edges, &g, &filled, &tangled, err);
            if (filled) {
                for (size_t k = 0; k < count; k++)
                    done[group[k]] = SR_SCAN_IN_PLANE;
                n_closed += count;
            }
            /* a tangle's scraps are fanned now, each: as seeds of groups of their own
             * they would each be tried in the same tangle again */
            for (size_t k = 1; st == SR_OK && tangled && k < count; k++) {
                if (!fan(mesh, d, &d->loops[group[k]], nv, &g))
                    st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
                done[group[k]] = SR_SCAN_BY_FAN;
                n_closed++;
            }
        }
        if (st == SR_OK && !filled) {
            if (!fan(mesh, d, l, nv, &g))
                st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            done[i] = SR_SCAN_BY_FAN;
            n_closed++;
        }
    }
    if (st == SR_OK && !cut_rims(mesh, nv, &g, &rep, &nrep))
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    if (st != SR_OK)
        goto out;
    if (nv + g.nv > SR_MESH_MAX_COUNT || nt + g.nt > SR_MESH_MAX_COUNT) {
        st = sr_err_set(err, SR_E_RANGE, "too many vertices to close the scan's openings");
        goto out;
    }
    if (g.nt > 0) {
        double *xyz = realloc(mesh->xyz, 3 * (nv + g.nv) * sizeof *xyz);
        if (!xyz) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            goto out;
        }
        mesh->xyz = xyz; /* same vertices, more room: the mesh is unchanged so far */
        uint32_t *tri = realloc(mesh->tri, 3 * (nt + g.nt) * sizeof *tri);
        if (!tri) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            goto out;
        }
        mesh->tri = tri;
        if (g.nv > 0) /* a fill may reuse only rim vertices */
            memcpy(xyz + 3 * nv, g.xyz, 3 * g.nv * sizeof *xyz);
        memcpy(tri + 3 * nt, g.tri, 3 * g.nt * sizeof *tri);
        for (size_t r = 0; r < nrep; r++)
            memcpy(tri + 3 * (size_t)rep[4 * r], rep + 4 * r + 1, 3 * sizeof *tri);
        mesh->vertex_count = nv + g.nv;
        mesh->tri_count = nt + g.nt;
        bool *touched = calloc(nv + g.nv + 1, sizeof *touched);
        if (!touched) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            goto out;
        }
        for (size_t e = 0; e < d->boundary_edges; e++)
            touched[d->loop_verts[e]] = true;
        for (size_t v = nv; v < nv + g.nv; v++)
            touched[v] = true;
        st = cancel_folds(mesh, d, nt, touched, err);
        free(touched);
        if (st == SR_OK)
            st = sr_mesh_split_pinches(mesh, NULL, err);
        if (st != SR_OK)
            goto out;
    }
    if (closed)
        *closed = n_closed;
    if (how)
        memcpy(how, done, d->loop_count * sizeof *how);
out:
    free(edges.keys);
    free(rep);
    free(g.xyz);
    free(g.tri);
    free(g.cut);
    free(done);
    free(group);
    free(vcomp);
    return st;
}
