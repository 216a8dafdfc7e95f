/*
 * scan_describe.c: the description of a scan (scan_describe.h). Edges: every triangle's
 * three edges listed at their lower vertex and grouped by the other; a pair used once is
 * a boundary edge, kept with the direction its triangle walks it; three or more uses
 * make a non-manifold edge.
 * Strays are found first: the edges and loops are those of the rest.
 * Loops: the boundary edges walked head to tail (at a vertex several openings touch, the
 * first unused edge out of it), each loop's opening measured by its vector area about the
 * loop's centroid (exact for a plane loop, a little under for one on a curved surface).
 * Components: union-find over the triangles' vertices. Strays: components with at most
 * small_fraction of the largest's area (not its triangles: a scan's density varies) whose
 * every vertex lies farther than
 * off_surface_mm from the largest's triangles (closest points, Ericson 5.1.5, with a
 * bounding-box cut per triangle: one pass over the largest component for all the small
 * ones at once).
 */
#include "mesh/scan_describe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "mesh/pair_sort.h"
#include "mesh/scan_int.h"

/* One counting pass of sr_scan_sort_edges: recs into tmp by the 32 bits of the key at
 * shift, stable; count has nv + 1 slots. Inlined where the record size is a constant,
 * so each record moves as a load and a store, not a call to memcpy (which took a
 * tenth of a two-million-triangle scan's closing). */
static inline void count_pass(const unsigned char *recs, unsigned char *tmp, size_t n, size_t size,
                              size_t nv, int shift, size_t *count)
{
    memset(count, 0, (nv + 1) * sizeof *count);
    for (size_t i = 0; i < n; i++) {
        uint64_t key;
        memcpy(&key, recs + i * size, sizeof key);
        count[((key >> shift) & UINT32_MAX) + 1]++;
    }
    for (size_t v = 0; v < nv; v++)
        count[v + 1] += count[v];
    for (size_t i = 0; i < n; i++) {
        uint64_t key;
        memcpy(&key, recs + i * size, sizeof key);
        memcpy(tmp + count[(key >> shift) & UINT32_MAX]++ * size, recs + i * size, size);
    }
}

sr_status sr_scan_sort_edges(void *recs, size_t n, size_t size, size_t nv)
{
    if (n < 2)
        return SR_OK;
    unsigned char *tmp = malloc(n * size);
    size_t *count = malloc((nv + 1) * sizeof *count);
    if (!tmp || !count) {
        free(tmp);
        free(count);
        return SR_E_NOMEM;
    }
    /* by hi, then by lo, hi's order kept */
    if (size == 16) {
        count_pass(recs, tmp, n, 16, nv, 0, count);
        count_pass(tmp, recs, n, 16, nv, 32, count);
    } else if (size == 8) {
        count_pass(recs, tmp, n, 8, nv, 0, count);
        count_pass(tmp, recs, n, 8, nv, 32, count);
    } else {
        count_pass(recs, tmp, n, size, nv, 0, count);
        count_pass(tmp, recs, n, size, nv, 32, count);
    }
    free(tmp);
    free(count);
    return SR_OK;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* Triangles past the described ones (added by sr_scan_close_openings) are kept. */
static bool is_stray(const sr_scan_desc *d, size_t t)
{
    return t < d->triangles && d->components[d->tri_component[t]].stray;
}

static double tri_area(const sr_mesh *m, size_t t)
{
    double n[3];
    sr_mesh_tri_normal(m, t, n);
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

static const double *vtx(const sr_mesh *m, uint32_t v)
{
    return m->xyz + 3 * (size_t)v;
}

/* The edges of m's triangles that are not d's strays': every directed edge listed
 * at its lower end (CSR by vertex, 4 bytes a corner: a key beside each of the 3T edges,
 * sorted, took two 8-byte arrays of 3T, 96 MB for a 1.85M-triangle scan, in each
 * description its closing makes), each vertex's short list of uses grouped by the
 * higher end. An edge used once is a boundary edge, kept (from, to) as its triangle
 * walks it, into *out (count *n_out) in (lower, higher) order; three or more uses make
 * a non-manifold one; the counts into d. Corner numbers are 32-bit: over UINT32_MAX / 3
 * triangles, SR_E_RANGE. */
static sr_status boundary_edges(const sr_mesh *m, uint32_t **out, size_t *n_out, sr_scan_desc *d)
{
    size_t nv = m->vertex_count, nt = m->tri_count, cap = 64, nb = 0, cap_b = 0;
    size_t nonmanifold = 0;
    if (nt > UINT32_MAX / 3)
        return SR_E_RANGE;
    uint32_t *start = calloc(nv + 2, sizeof *start);
    uint32_t *corner = malloc((3 * nt + 1) * sizeof *corner);
    sr_pair32 *rec = malloc(cap * sizeof *rec);
    uint32_t *b = NULL; /* (from, to) pairs */
    sr_status st = SR_OK;
    if (!start || !corner || !rec) {
        st = SR_E_NOMEM;
        goto out;
    }
    const uint32_t *tri = m->tri;
    for (size_t t = 0; t < nt; t++)
        if (!is_stray(d, t))
            for (int k = 0; k < 3; k++) {
                uint32_t a = tri[3 * t + k], c = tri[3 * t + (k + 1) % 3];
                start[(a < c ? a : c) + 2]++;
            }
    for (size_t v = 0; v < nv; v++)
        start[v + 2] += start[v + 1];
    for (size_t t = 0; t < nt; t++)
        if (!is_stray(d, t))
            for (int k = 0; k < 3; k++) {
                uint32_t a = tri[3 * t + k], c = tri[3 * t + (k + 1) % 3];
                corner[start[(a < c ? a : c) + 1]++] = (uint32_t)(3 * t + (size_t)k);
            }
    /* the fill advanced each vertex's start to the next one's: start[u] is u's now */
    for (size_t u = 0; u < nv; u++) {
        size_t c0 = start[u], deg = start[u + 1] - c0;
        if (deg == 0)
            continue;
        if (deg > cap) {
            while (cap < deg)
                cap *= 2;
            sr_pair32 *r2 = realloc(rec, cap * sizeof *rec);
            if (!r2) {
                st = SR_E_NOMEM;
                goto out;
            }
            rec = r2;
        }
        for (size_t j = 0; j < deg; j++) {
            uint32_t c = corner[c0 + j], t = c / 3, k = c % 3;
            uint32_t a = tri[3 * t + k], w = tri[3 * t + (k + 1) % 3];
            /* key: the higher end; tag 1 when the edge runs from u */
            rec[j] = a == u ? (sr_pair32){w, 1} : (sr_pair32){a, 0};
        }
        sr_pair32_sort(rec, deg);
        for (size_t i = 0; i < deg;) {
            size_t j = i + 1;
            while (j < deg && rec[j].key == rec[i].key)
                j++;
            if (j - i >= 3) {
                nonmanifold++;
            } else if (j - i == 1) {
                uint32_t *b2 = sr_grow(b, nb, &cap_b, 2 * sizeof *b);
                if (!b2) {
                    st = SR_E_NOMEM;
                    goto out;
                }
                b = b2;
                b[2 * nb] = rec[i].tag ? (uint32_t)u : rec[i].key;
                b[2 * nb + 1] = rec[i].tag ? rec[i].key : (uint32_t)u;
                nb++;
            }
            i = j;
        }
    }
out:
    free(start);
    free(corner);
    free(rec);
    if (st != SR_OK) {
        free(b);
        return st;
    }
    d->nonmanifold_edges = nonmanifold;
    d->boundary_edges = nb;
    *out = b;
    *n_out = nb;
    return SR_OK;
}

static int by_from(const void *pa, const void *pb)
{
    const uint32_t *a = pa, *b = pb;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

static int loop_cmp(const void *pa, const void *pb)
{
    const sr_scan_loop *a = pa, *b = pb;
    return (a->length_mm < b->length_mm) - (a->length_mm > b->length_mm);
}

/* Walks the boundary edges b (nb of them, sorted by from) into d->loops. */
static sr_status walk_loops(const sr_mesh *m, const uint32_t *b, size_t nb, sr_scan_desc *d)
{
    unsigned char *used = calloc(nb ? nb : 1, 1);
    size_t *order = malloc((nb ? nb : 1) * sizeof *order);
    sr_scan_loop *loops = malloc((nb ? nb : 1) * sizeof *loops);
    uint32_t *lv = malloc((nb ? nb : 1) * sizeof *lv);
    if (!used || !order || !loops || !lv) {
        free(used);
        free(order);
        free(loops);
        free(lv);
        return SR_E_NOMEM;
    }
    size_t nloops = 0, pos = 0;
    for (size_t s = 0; s < nb; s++) {
        if (used[s])
            continue;
        size_t len = 0, cur = s;
        bool closed = false;
        for (;;) {
            used[cur] = 1;
            order[len++] = cur;
            uint32_t to = b[2 * cur + 1];
            if (to == b[2 * s]) {
                closed = true;
                break;
            }
            /* the first unused edge out of `to` (binary search for its run) */
            size_t lo = 0, hi = nb;
            while (lo < hi) {
                size_t mid = lo + (hi - lo) / 2;
                if (b[2 * mid] < to)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            while (lo < nb && b[2 * lo] == to && used[lo])
                lo++;
            if (lo >= nb || b[2 * lo] != to)
                break;
            cur = lo;
        }
        double c[3] = {0, 0, 0}, length = 0, va[3] = {0, 0, 0};
        for (size_t i = 0; i < len; i++)
            for (int k = 0; k < 3; k++)
                c[k] += vtx(m, b[2 * order[i]])[k] / (double)len;
        for (size_t i = 0; i < len; i++) {
            const double *p = vtx(m, b[2 * order[i]]), *q = vtx(m, b[2 * order[i] + 1]);
            double u[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
            double w[3] = {q[0] - c[0], q[1] - c[1], q[2] - c[2]};
            va[0] += 0.5 * (u[1] * w[2] - u[2] * w[1]);
            va[1] += 0.5 * (u[2] * w[0] - u[0] * w[2]);
            va[2] += 0.5 * (u[0] * w[1] - u[1] * w[0]);
            length += sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                           (q[2] - p[2]) * (q[2] - p[2]));
        }
        for (size_t i = 0; i < len; i++)
            lv[pos + i] = b[2 * order[i]];
        loops[nloops++] =
            (sr_scan_loop){len,    length, sqrt(va[0] * va[0] + va[1] * va[1] + va[2] * va[2]),
                           closed, pos,    {c[0], c[1], c[2]}};
        pos += len;
    }
    free(used);
    free(order);
    qsort(loops, nloops, sizeof *loops, loop_cmp);
    d->loops = loops;
    d->loop_count = nloops;
    d->loop_verts = lv;
    for (size_t i = 0; i < nloops; i++)
        d->open_area_mm2 += loops[i].span_mm;
    return SR_OK;
}

typedef struct comp_rank {
    size_t triangles;
    double area;
    uint32_t raw;
} comp_rank;

static int comp_cmp(const void *pa, const void *pb)
{
    const comp_rank *a = pa, *b = pb;
    if (a->triangles != b->triangles)
        return a->triangles < b->triangles ? 1 : -1;
    if (a->area != b->area)
        return a->area < b->area ? 1 : -1;
    return (a->raw > b->raw) - (a->raw < b->raw);
}

/* Components of m into d (components, tri_component), most triangles first. */
static sr_status components(const sr_mesh *m, sr_scan_desc *d)
{
    size_t nv = m->vertex_count ? m->vertex_count : 1, nt = m->tri_count ? m->tri_count : 1;
    uint32_t *parent = malloc(nv * sizeof *parent);
    uint32_t *id = malloc(nv * sizeof *id);
    uint32_t *tc = malloc(nt * sizeof *tc);
    comp_rank *rank = NULL;
    uint32_t *rank_of = NULL;
    if (!parent || !id || !tc)
        goto nomem;
    for (size_t v = 0; v < m->vertex_count; v++)
        parent[v] = (uint32_t)v;
    for (size_t t = 0; t < m->tri_count; t++) {
        uint32_t a = uf_find(parent, m->tri[3 * t]);
        for (int k = 1; k < 3; k++) {
            uint32_t b = uf_find(parent, m->tri[3 * t + k]);
            if (a != b)
                parent[b] = a;
        }
    }
    for (size_t v = 0; v < m->vertex_count; v++)
        id[v] = UINT32_MAX;
    size_t nc = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        uint32_t r = uf_find(parent, m->tri[3 * t]);
        if (id[r] == UINT32_MAX)
            id[r] = (uint32_t)nc++;
        tc[t] = id[r];
    }
    rank = calloc(nc ? nc : 1, sizeof *rank);
    rank_of = malloc((nc ? nc : 1) * sizeof *rank_of);
    d->components = calloc(nc ? nc : 1, sizeof *d->components);
    if (!rank || !rank_of || !d->components)
        goto nomem;
    for (size_t c = 0; c < nc; c++)
        rank[c].raw = (uint32_t)c;
    for (size_t t = 0; t < m->tri_count; t++) {
        double a = tri_area(m, t);
        rank[tc[t]].triangles++;
        rank[tc[t]].area += a;
        d->area_mm2 += a;
    }
    qsort(rank, nc, sizeof *rank, comp_cmp);
    for (size_t c = 0; c < nc; c++) {
        rank_of[rank[c].raw] = (uint32_t)c;
        d->components[c] = (sr_scan_component){rank[c].triangles, rank[c].area, c ? -1 : 0, false};
    }
    for (size_t t = 0; t < m->tri_count; t++)
        tc[t] = rank_of[tc[t]];
    d->component_count = nc;
    d->tri_component = tc;
    free(parent);
    free(id);
    free(rank);
    free(rank_of);
    return SR_OK;
nomem:
    free(parent);
    free(id);
    free(tc);
    free(rank);
    free(rank_of);
    free(d->components);
    d->components = NULL;
    return SR_E_NOMEM;
}

/* The largest component's triangles on a uniform grid (cells of side h from lo, n per
 * axis; CSR start/tri): the strays' distances are looked up in the cells round each
 * stray, ring by ring, not against every triangle (a scan of 1.8M triangles with 700
 * strays spent two minutes in that product). */
typedef struct tgrid {
    double lo[3], h;
    long n[3];
    size_t *start;
    uint32_t *tri;
} tgrid;

static void tgrid_release(tgrid *g)
{
    free(g->start);
    free(g->tri);
    memset(g, 0, sizeof *g);
}

static long cell_of(const tgrid *g, double x, int axis)
{
    return (long)floor((x - g->lo[axis]) / g->h);
}

/* The cell range [c0, c1] of box (lo xyz, hi xyz), per axis, clamped to the grid when
 * clamp. */
static void cell_range(const tgrid *g, const double *b, bool clamp, long c0[3], long c1[3])
{
    for (int i = 0; i < 3; i++) {
        c0[i] = cell_of(g, b[i], i);
        c1[i] = cell_of(g, b[3 + i], i);
        if (clamp) {
            c0[i] = c0[i] < 0 ? 0 : c0[i] >= g->n[i] ? g->n[i] - 1 : c0[i];
            c1[i] = c1[i] < 0 ? 0 : c1[i] >= g->n[i] ? g->n[i] - 1 : c1[i];
        }
    }
}

static void tri_box(const sr_mesh *m, size_t t, double b[6])
{
    const double *p = vtx(m, m->tri[3 * t]);
    for (int i = 0; i < 3; i++)
        b[i] = b[3 + i] = p[i];
    for (int k = 1; k < 3; k++) {
        p = vtx(m, m->tri[3 * t + k]);
        for (int i = 0; i < 3; i++) { /* no fmin/fmax: the coordinates are finite */
            b[i] = p[i] < b[i] ? p[i] : b[i];
            b[3 + i] = p[i] > b[3 + i] ? p[i] : b[3 + i];
        }
    }
}

/* A grid has at most one cell per this many triangles: a surface fills few of a box's
 * cells, and a fine grid's counts cost more to clear and fill than its lookups save
 * (a 1.85M-triangle scan: 0.23 s a description with cells of three triangles' size,
 * 0.14 s with this bound). */
#define CELL_TRIANGLES 4.0

/* Cells of about three triangles' size (area / count), at most 256 a side (so a cell
 * index per axis fits a byte: each triangle's cell range is found once) and at most
 * one per CELL_TRIANGLES triangles. */
static bool tgrid_build(const sr_mesh *m, const uint32_t *comp, double area, tgrid *g)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    size_t nt = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        if (comp[t] == 0) {
            double b[6];
            tri_box(m, t, b);
            for (int i = 0; i < 3; i++) {
                lo[i] = b[i] < lo[i] ? b[i] : lo[i];
                hi[i] = b[3 + i] > hi[i] ? b[3 + i] : hi[i];
            }
            nt++;
        }
    if (nt == 0)
        return true;
    double ext = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    g->h = fmax(3 * sqrt(area / (double)nt), ext / 255);
    double box = (hi[0] - lo[0] + g->h) * (hi[1] - lo[1] + g->h) * (hi[2] - lo[2] + g->h);
    g->h = fmax(g->h, cbrt(box * CELL_TRIANGLES / (double)nt));
    if (!(g->h > 0))
        g->h = 1;
    size_t cells = 1;
    for (int i = 0; i < 3; i++) {
        g->lo[i] = lo[i];
        g->n[i] = (long)floor((hi[i] - lo[i]) / g->h) + 1;
        g->n[i] = g->n[i] > 256 ? 256 : g->n[i];
        cells *= (size_t)g->n[i];
    }
    g->start = calloc(cells + 1, sizeof *g->start);
    uint8_t *range = malloc(6 * nt * sizeof *range); /* c0 xyz, c1 xyz of each */
    if (!g->start || !range) {
        free(range);
        return false;
    }
    size_t r = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        if (comp[t] != 0)
            continue;
        double b[6];
        long c0[3], c1[3];
        tri_box(m, t, b);
        cell_range(g, b, true, c0, c1);
        for (int i = 0; i < 3; i++) {
            range[6 * r + i] = (uint8_t)c0[i];
            range[6 * r + 3 + i] = (uint8_t)c1[i];
        }
        for (long k = c0[2]; k <= c1[2]; k++)
            for (long j = c0[1]; j <= c1[1]; j++)
                for (long i = c0[0]; i <= c1[0]; i++)
                    g->start[((size_t)k * (size_t)g->n[1] + (size_t)j) * (size_t)g->n[0] +
                             (size_t)i + 1]++;
        r++;
    }
    for (size_t c = 0; c < cells; c++)
        g->start[c + 1] += g->start[c];
    g->tri = malloc((g->start[cells] + 1) * sizeof *g->tri);
    if (!g->tri) {
        free(range);
        return false;
    }
    r = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        if (comp[t] != 0)
            continue;
        const uint8_t *q = range + 6 * r++;
        for (size_t k = q[2]; k <= q[5]; k++)
            for (size_t j = q[1]; j <= q[4]; j++)
                for (size_t i = q[0]; i <= q[3]; i++)
                    g->tri[g->start[(k * (size_t)g->n[1] + j) * (size_t)g->n[0] + i]++] =
                        (uint32_t)t;
    }
    free(range);
    /* filling moved each start to the next cell's: move them back */
    memmove(g->start + 1, g->start, cells * sizeof *g->start);
    g->start[0] = 0;
    return true;
}

/* The triangles of cell (i, j, k) (within the grid) not yet measured for component c
 * (box b, vertices vs): *best lowered to the nearest. */
static void visit_cell(const sr_mesh *m, const tgrid *g, long i, long j, long k, size_t c,
                       const double *b, const uint32_t *vs, size_t nv, uint32_t *stamp,
                       double *best)
{
    size_t cell = ((size_t)k * (size_t)g->n[1] + (size_t)j) * (size_t)g->n[0] + (size_t)i;
    for (size_t q = g->start[cell]; q < g->start[cell + 1]; q++) {
        uint32_t t = g->tri[q];
        if (stamp[t] == (uint32_t)c)
            continue;
        stamp[t] = (uint32_t)c;
        double tb[6], gap2 = 0;
        tri_box(m, t, tb);
        for (int x = 0; x < 3; x++) { /* the boxes' gap bounds every vertex's distance */
            double gp = fmax(0, fmax(tb[x] - b[3 + x], b[x] - tb[3 + x]));
            gap2 += gp * gp;
        }
        if (gap2 >= *best * *best)
            continue;
        const double *a = vtx(m, m->tri[3 * t]), *bb = vtx(m, m->tri[3 * t + 1]),
                     *cc = vtx(m, m->tri[3 * t + 2]);
        for (size_t v = 0; v < nv; v++) {
            const double *p = vtx(m, vs[v]);
            double w[3];
            sr_tri_closest_point(p, a, bb, cc, w);
            double dist = sqrt((p[0] - w[0]) * (p[0] - w[0]) + (p[1] - w[1]) * (p[1] - w[1]) +
                               (p[2] - w[2]) * (p[2] - w[2]));
            *best = dist < *best ? dist : *best;
        }
    }
}

static long clamp_cell(long x, long n)
{
    return x < 0 ? 0 : x >= n ? n - 1 : x;
}

/* *best: the distance from the nv vertices vs of component c (box b) to the nearest
 * triangle on the grid, searched ring by ring of cells round b (ring r: the cells r
 * from b's cells, Chebyshev) until no nearer one can lie farther out; stamp[t] == c
 * marks a triangle already measured. */
static void nearest_on_grid(const sr_mesh *m, const tgrid *g, size_t c, const double *b,
                            const uint32_t *vs, size_t nv, uint32_t *stamp, double *best)
{
    if (!g->start)
        return;
    long c0[3], c1[3];
    cell_range(g, b, false, c0, c1);
    for (long r = 0;; r++) {
        long lo[3], hi[3];
        bool all = true; /* the ring reaches past the grid on every side */
        for (int i = 0; i < 3; i++) {
            lo[i] = c0[i] - r;
            hi[i] = c1[i] + r;
            all = all && lo[i] <= 0 && hi[i] >= g->n[i] - 1;
        }
        for (long k = clamp_cell(lo[2], g->n[2]); k <= clamp_cell(hi[2], g->n[2]); k++) {
            if (k < lo[2] || k > hi[2])
                continue; /* the range lies off the grid on this side */
            for (long j = clamp_cell(lo[1], g->n[1]); j <= clamp_cell(hi[1], g->n[1]); j++) {
                if (j < lo[1] || j > hi[1])
                    continue;
                bool face = r == 0 || k == lo[2] || k == hi[2] || j == lo[1] || j == hi[1];
                if (face) {
                    for (long i = clamp_cell(lo[0], g->n[0]); i <= clamp_cell(hi[0], g->n[0]); i++)
                        if (i >= lo[0] && i <= hi[0])
                            visit_cell(m, g, i, j, k, c, b, vs, nv, stamp, best);
                } else { /* inside the shell's faces across k and j: its two ends in i */
                    if (lo[0] >= 0 && lo[0] < g->n[0])
                        visit_cell(m, g, lo[0], j, k, c, b, vs, nv, stamp, best);
                    if (hi[0] != lo[0] && hi[0] >= 0 && hi[0] < g->n[0])
                        visit_cell(m, g, hi[0], j, k, c, b, vs, nv, stamp, best);
                }
            }
        }
        /* a cell r + 1 rings out lies at least r cells from the box */
        if (all || *best <= (double)r * g->h)
            return;
    }
}

/* Distance from the vertices of every small component to the largest's triangles; flags
 * the strays. */
static sr_status find_strays(const sr_mesh *m, double fraction, double off, sr_scan_desc *d)
{
    if (d->component_count < 2)
        return SR_OK;
    const sr_scan_component *big = &d->components[0];
    size_t nc = d->component_count, nsmall = 0;
    /* small components: ranks 1.. with little area */
    size_t *small = malloc(nc * sizeof *small);
    double *box = malloc(nc * 6 * sizeof *box); /* by rank; only small ones filled */
    double *best = malloc(nc * sizeof *best);
    if (!small || !box || !best) {
        free(small);
        free(box);
        free(best);
        return SR_E_NOMEM;
    }
    for (size_t c = 1; c < nc; c++) {
        const sr_scan_component *k = &d->components[c];
        best[c] = INFINITY;
        if (k->area_mm2 <= fraction * big->area_mm2) {
            small[nsmall++] = c;
            for (int i = 0; i < 3; i++) {
                box[6 * c + i] = INFINITY;
                box[6 * c + 3 + i] = -INFINITY;
            }
        }
    }
    if (nsmall == 0)
        goto done;
    for (size_t t = 0; t < m->tri_count; t++) {
        uint32_t c = d->tri_component[t];
        if (c == 0)
            continue;
        for (int k = 0; k < 3; k++) {
            const double *p = vtx(m, m->tri[3 * t + k]);
            for (int i = 0; i < 3; i++) {
                box[6 * c + i] = fmin(box[6 * c + i], p[i]);
                box[6 * c + 3 + i] = fmax(box[6 * c + 3 + i], p[i]);
            }
        }
    }
    /* small components' vertex lists, CSR by rank */
    size_t *start = calloc(nc + 1, sizeof *start);
    uint32_t *verts = NULL;
    if (!start)
        goto nomem;
    size_t total = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        if (d->tri_component[t] != 0)
            start[d->tri_component[t] + 1] += 3;
    for (size_t c = 0; c < nc; c++)
        start[c + 1] += start[c];
    total = start[nc];
    verts = malloc((total ? total : 1) * sizeof *verts);
    size_t *fill = malloc(nc * sizeof *fill);
    if (!verts || !fill) {
        free(start);
        free(verts);
        free(fill);
        goto nomem;
    }
    memcpy(fill, start, nc * sizeof *fill);
    for (size_t t = 0; t < m->tri_count; t++) {
        uint32_t c = d->tri_component[t];
        if (c != 0)
            for (int k = 0; k < 3; k++)
                verts[fill[c]++] = m->tri[3 * t + k];
    }
    free(fill);
    tgrid g = {0};
    uint32_t *stamp = calloc(m->tri_count + 1, sizeof *stamp);
    if (!stamp || !tgrid_build(m, d->tri_component, big->area_mm2, &g)) {
        free(stamp);
        tgrid_release(&g);
        free(start);
        free(verts);
        goto nomem;
    }
    for (size_t s = 0; s < nsmall; s++)
        nearest_on_grid(m, &g, small[s], box + 6 * small[s], verts + start[small[s]],
                        start[small[s] + 1] - start[small[s]], stamp, &best[small[s]]);
    free(stamp);
    tgrid_release(&g);
    free(start);
    free(verts);
    for (size_t s = 0; s < nsmall; s++) {
        size_t c = small[s];
        sr_scan_component *k = &d->components[c];
        k->distance_mm = best[c];
        if (best[c] > off) {
            k->stray = true;
            d->strays++;
            d->stray_triangles += k->triangles;
            d->stray_area_mm2 += k->area_mm2;
        }
    }
done:
    free(small);
    free(box);
    free(best);
    return SR_OK;
nomem:
    free(small);
    free(box);
    free(best);
    return SR_E_NOMEM;
}

void sr_scan_desc_release(sr_scan_desc *d)
{
    if (!d)
        return;
    free(d->loops);
    free(d->loop_verts);
    free(d->components);
    free(d->tri_component);
    sr_mesh_release(&d->fills);
    memset(d, 0, sizeof *d);
}

sr_status sr_scan_describe(const sr_mesh *mesh, const sr_scan_opts *opts, sr_scan_desc *out,
                           sr_err *err)
{
    double fraction = opts && opts->small_fraction != 0 ? opts->small_fraction : 0.01;
    double off = opts && opts->off_surface_mm != 0 ? opts->off_surface_mm : 0.5;
    if (!(fraction > 0 && fraction <= 1) || !(off > 0 && isfinite(off)))
        return sr_err_set(err, SR_E_RANGE,
                          "bad scan options: small fraction %g (0..1), off-surface %g mm (> 0)",
                          fraction, off);
    sr_scan_desc d;
    memset(&d, 0, sizeof d);
    d.triangles = mesh->tri_count;
    uint32_t *b = NULL;
    size_t nb = 0;
    sr_status st = components(mesh, &d);
    if (st == SR_OK)
        st = find_strays(mesh, fraction, off, &d);
    if (st == SR_OK)
        st = boundary_edges(mesh, &b, &nb, &d);
    if (st == SR_OK) {
        if (nb > 1) /* b is NULL when there are none */
            qsort(b, nb, 2 * sizeof *b, by_from);
        st = walk_loops(mesh, b, nb, &d);
    }
    free(b);
    if (st != SR_OK) {
        sr_scan_desc_release(&d);
        if (st == SR_E_RANGE)
            return sr_err_set(err, st, "too many triangles to describe the scan (%zu, at most %u)",
                              mesh->tri_count, UINT32_MAX / 3);
        return sr_err_set(err, st, "out of memory describing the scan");
    }
    d.open = d.boundary_edges > 0;
    double kept = d.area_mm2 - d.stray_area_mm2;
    d.open_share = kept + d.open_area_mm2 > 0 ? d.open_area_mm2 / (kept + d.open_area_mm2) : 0;
    *out = d;
    return SR_OK;
}

#define USED (UINT32_MAX - 1)

sr_status sr_scan_drop_triangles(sr_mesh *mesh, const bool *gone, sr_err *err)
{
    uint32_t *map = malloc((mesh->vertex_count + 1) * sizeof *map);
    if (!map)
        return sr_err_set(err, SR_E_NOMEM, "out of memory taking triangles out of the scan");
    for (size_t v = 0; v < mesh->vertex_count; v++)
        map[v] = UINT32_MAX;
    size_t nt = 0, nv = 0;
    for (size_t t = 0; t < mesh->tri_count; t++)
        if (!gone[t]) {
            for (int k = 0; k < 3; k++)
                map[mesh->tri[3 * t + k]] = USED; /* numbered below in vertex order */
            nt++;
        }
    for (size_t v = 0; v < mesh->vertex_count; v++)
        if (map[v] == USED) {
            map[v] = (uint32_t)nv;
            memmove(mesh->xyz + 3 * nv++, mesh->xyz + 3 * v, 3 * sizeof *mesh->xyz);
        }
    size_t w = 0;
    for (size_t t = 0; t < mesh->tri_count; t++)
        if (!gone[t]) {
            for (int k = 0; k < 3; k++)
                mesh->tri[3 * w + k] = map[mesh->tri[3 * t + k]];
            w++;
        }
    mesh->vertex_count = nv;
    mesh->tri_count = nt;
    free(map);
    return SR_OK;
}

sr_status sr_scan_drop_strays(sr_mesh *mesh, const sr_scan_desc *d, sr_err *err)
{
    if (d->strays == 0)
        return SR_OK;
    bool *gone = malloc((mesh->tri_count + 1) * sizeof *gone);
    if (!gone)
        return sr_err_set(err, SR_E_NOMEM, "out of memory dropping the scan's strays");
    for (size_t t = 0; t < mesh->tri_count; t++)
        gone[t] = is_stray(d, t);
    sr_status st = sr_scan_drop_triangles(mesh, gone, err);
    free(gone);
    return st;
}
