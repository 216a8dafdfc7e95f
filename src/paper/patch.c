/*
 * patch.c: missing sections and their closed patch surfaces, paper Algorithm 6 (see
 * patch.h for the construction).
 *
 * Per layer, a section's region is the union of its cells' chord trapezoids, traced
 * here as closed outlines on the grid: every point is (sector border b, radius r) and
 * computed as r (cos, sin)(b 2pi/N) the same way everywhere, so the outer and inner
 * chords and the walls between sectors meet at bitwise-equal points and the layer's
 * outline needs no polygon union (whose rounding would leave slivers between cells
 * sharing a border). The regions are stacked by stack_mesh.h, which makes the walls and
 * caps conform exactly between layers and pulls the outlines in by under a micrometre
 * where cells of neighbouring layers touch only along an edge, so the patch is a closed
 * 2-manifold.
 */
#include "paper/patch.h"

#include "robust/stack_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.28318530717958647692

/* One directed boundary edge of a layer's region between grid points (border b,
 * radius r), the region on its left (counter-clockwise outlines). */
typedef struct gedge {
    size_t b0, b1;
    double r0, r1;
    int used;
} gedge;

typedef struct layer_outline {
    gedge *e;
    size_t n, cap;
} layer_outline;

/* The point's key: border mod N, and every radius-0 point is the one axis point. */
static void canon(size_t N, size_t *b, double *r)
{
    *b %= N;
    if (*r <= 0) {
        *r = 0;
        *b = 0;
    }
}

static int push_edge(layer_outline *o, size_t N, size_t b0, double r0, size_t b1, double r1)
{
    canon(N, &b0, &r0);
    canon(N, &b1, &r1);
    if (b0 == b1 && r0 == r1)
        return 1; /* zero length: an inner chord at the axis */
    if (o->n == o->cap) {
        size_t cap = o->cap ? 2 * o->cap : 64;
        gedge *p = realloc(o->e, cap * sizeof *p);
        if (!p)
            return 0;
        o->e = p;
        o->cap = cap;
    }
    o->e[o->n++] = (gedge){b0, b1, r0, r1, 0};
    return 1;
}

/* The radial interval [lo, hi] of cell (l, j) if it is in section s, else empty. */
static int cell_interval(const sr_layer_grid *g, const sr_analysis *a, const int *sec, int s,
                         size_t l, size_t j, double *lo, double *hi)
{
    size_t c = l * g->sectors + j % g->sectors;
    if (sec[c] != s || !(a->restored_r[c] > g->r[c]) || !(a->restored_r[c] > 0))
        return 0;
    *lo = g->r[c] > 0 ? g->r[c] : 0;
    *hi = a->restored_r[c];
    return 1;
}

/* Parts of [a1,b1] not covered by [a2,b2] (either may be empty: a >= b). */
static size_t interval_minus(double a1, double b1, double a2, double b2, double out[2][2])
{
    size_t n = 0;
    if (!(b1 > a1))
        return 0;
    if (!(b2 > a2)) {
        out[0][0] = a1;
        out[0][1] = b1;
        return 1;
    }
    if (a1 < a2) {
        out[n][0] = a1;
        out[n][1] = fmin(b1, a2);
        n++;
    }
    if (b1 > b2) {
        out[n][0] = fmax(a1, b2);
        out[n][1] = b1;
        n++;
    }
    return n;
}

/* The boundary of layer l's part of section s: per cell its outer chord (increasing
 * angle) and inner chord (decreasing), per sector border the pieces of each side's
 * interval the other side lacks (walls). Every vertex has as many edges in as out. */
static int outline_edges(const sr_layer_grid *g, const sr_analysis *a, const int *sec, int s,
                         size_t l, layer_outline *o)
{
    size_t N = g->sectors;
    o->n = 0;
    for (size_t j = 0; j < N; j++) {
        double lo, hi;
        if (!cell_interval(g, a, sec, s, l, j, &lo, &hi))
            continue;
        if (!push_edge(o, N, j, hi, j + 1, hi) || !push_edge(o, N, j + 1, lo, j, lo))
            return 0;
    }
    for (size_t b = 0; b < N; b++) { /* border b: sector b-1 on its left, b on its right */
        double la = 0, lb = -1, ra = 0, rb = -1, piece[2][2];
        cell_interval(g, a, sec, s, l, b + N - 1, &la, &lb);
        cell_interval(g, a, sec, s, l, b, &ra, &rb);
        size_t n = interval_minus(la, lb, ra, rb, piece);
        for (size_t i = 0; i < n; i++) /* the region is at smaller angles: walk inwards */
            if (!push_edge(o, N, b, piece[i][1], b, piece[i][0]))
                return 0;
        n = interval_minus(ra, rb, la, lb, piece);
        for (size_t i = 0; i < n; i++)
            if (!push_edge(o, N, b, piece[i][0], b, piece[i][1]))
                return 0;
    }
    return 1;
}

static int by_start(const void *pa, const void *pb)
{
    const gedge *a = pa, *b = pb;
    if (a->b0 != b->b0)
        return a->b0 < b->b0 ? -1 : 1;
    return a->r0 < b->r0 ? -1 : (a->r0 > b->r0 ? 1 : 0);
}

/* An unused edge starting at (b, r), or NULL; edges sorted by start. */
static gedge *next_from(layer_outline *o, size_t b, double r)
{
    size_t lo = 0, hi = o->n;
    gedge key = {b, 0, r, 0, 0};
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (by_start(&o->e[mid], &key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (size_t i = lo; i < o->n && o->e[i].b0 == b && o->e[i].r0 == r; i++)
        if (!o->e[i].used)
            return &o->e[i];
    return NULL;
}

/* Layer l's region of section s: the edges chained into closed contours (any
 * choice at a vertex two contours touch closes them), then cleaned by the polygon
 * library (orientation, touching contours). */
static sr_status layer_region(const sr_layer_grid *g, const sr_analysis *a, const int *sec,
                              int s, size_t l, const double *cb, const double *sb,
                              layer_outline *o, sr_poly2 *out, sr_err *err)
{
    if (!outline_edges(g, a, sec, s, l, o))
        return sr_err_set(err, SR_E_NOMEM, "out of memory building a patch outline");
    sr_poly2_release(out);
    if (o->n == 0)
        return SR_OK;
    qsort(o->e, o->n, sizeof *o->e, by_start);
    double *xy = malloc(o->n * 2 * sizeof *xy);
    size_t *start = malloc((o->n + 1) * sizeof *start);
    sr_status st = SR_OK;
    size_t np = 0, nc = 0;
    if (!xy || !start)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory building a patch outline");
    for (size_t i = 0; i < o->n && st == SR_OK; i++) {
        if (o->e[i].used)
            continue;
        start[nc] = np;
        gedge *e = &o->e[i];
        while (e) {
            e->used = 1;
            xy[2 * np] = e->r0 * cb[e->b0];
            xy[2 * np + 1] = e->r0 * sb[e->b0];
            np++;
            e = next_from(o, e->b1, e->r1);
        }
        if (np - start[nc] >= 3)
            nc++;
        else
            np = start[nc]; /* cannot happen for a cell union; dropped if it does */
    }
    start[nc] = np;
    sr_poly2 raw = {0};
    if (st == SR_OK && nc > 0)
        st = sr_poly2_from_contours(xy, start, nc, &raw, err);
    if (st == SR_OK && nc > 0)
        st = sr_poly2_boolean(SR_POLY_UNION, &raw, NULL, out, err);
    sr_poly2_release(&raw);
    free(xy);
    free(start);
    return st;
}

/* The patch of section s: its layers' regions stacked over their slabs (stack_mesh.h
 * conforms the walls and caps at every layer boundary, so no T-junction is left). */
static sr_status build_section(const sr_layer_grid *g, const sr_analysis *a, const int *sec,
                               int s, size_t first, size_t last, const double *cb,
                               const double *sb, sr_mesh *out, sr_err *err)
{
    size_t n = last - first + 1;
    sr_poly2 *reg = calloc(n, sizeof *reg);
    double *z = malloc((n + 1) * sizeof *z);
    layer_outline o = {0};
    sr_status st = SR_OK;
    if (!reg || !z)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory building a patch");
    for (size_t i = 0; i < n && st == SR_OK; i++)
        st = layer_region(g, a, sec, s, first + i, cb, sb, &o, &reg[i], err);
    for (size_t i = 0; i <= n && z; i++)
        z[i] = g->z_init + (double)(first + i) * g->dz;
    if (st == SR_OK)
        st = sr_stack_mesh_pulled_in(reg, z, n, out, err);
    for (size_t i = 0; reg && i < n; i++)
        sr_poly2_release(&reg[i]);
    free(reg);
    free(z);
    free(o.e);
    return st;
}

double sr_section_cell_volume(const sr_layer_grid *grid, const sr_analysis *a,
                              const int *section_of, int s)
{
    double sum = 0, sn = sin(TWO_PI / (double)grid->sectors);
    for (size_t c = 0; c < grid->layers * grid->sectors; c++)
        if (section_of[c] == s)
            sum += 0.5 * (a->restored_r[c] * a->restored_r[c] - grid->r[c] * grid->r[c]) * sn;
    return sum * grid->dz;
}

/* Labels connected damaged cells; returns the number of sections. */
static int label_sections(const sr_layer_grid *g, const sr_analysis *a, int *sec)
{
    size_t L = g->layers, N = g->sectors, cells = L * N;
    size_t *stack = malloc((cells ? cells : 1) * sizeof *stack);
    if (!stack)
        return -1;
    for (size_t c = 0; c < cells; c++)
        sec[c] = -1;
    int count = 0;
    for (size_t c0 = 0; c0 < cells; c0++) {
        if (!a->damaged[c0] || sec[c0] >= 0)
            continue;
        size_t top = 0;
        stack[top++] = c0;
        sec[c0] = count;
        while (top) {
            size_t c = stack[--top];
            size_t l = c / N, j = c % N;
            size_t nb[4] = {l * N + (j + 1) % N, l * N + (j + N - 1) % N,
                            l > 0 ? c - N : SIZE_MAX, l + 1 < L ? c + N : SIZE_MAX};
            for (int i = 0; i < 4; i++) {
                if (nb[i] != SIZE_MAX && a->damaged[nb[i]] && sec[nb[i]] < 0) {
                    sec[nb[i]] = count;
                    stack[top++] = nb[i];
                }
            }
        }
        count++;
    }
    free(stack);
    return count;
}

static void describe(const sr_layer_grid *g, const sr_analysis *a, const int *sec, int s,
                     sr_section *out)
{
    size_t L = g->layers, N = g->sectors;
    unsigned char *used = calloc(N, 1);
    out->layer_first = SIZE_MAX;
    double dsum = 0;
    for (size_t c = 0; c < L * N; c++) {
        if (sec[c] != s)
            continue;
        size_t l = c / N;
        if (out->layer_first == SIZE_MAX)
            out->layer_first = l;
        out->layer_last = l;
        out->cell_count++;
        double d = a->restored_r[c] - g->r[c];
        dsum += d;
        out->depth_max_mm = fmax(out->depth_max_mm, d);
        if (used)
            used[c % N] = 1;
    }
    out->depth_mean_mm = out->cell_count ? dsum / (double)out->cell_count : 0;
    out->z_min = g->z_init + (double)out->layer_first * g->dz;
    out->z_max = g->z_init + (double)(out->layer_last + 1) * g->dz;
    /* the covered arc: complement of the largest run of unused sectors */
    size_t best_gap = 0, best_end = 0;
    if (used) {
        for (size_t start = 0; start < N; start++) {
            if (used[start] || used[(start + N - 1) % N] == 0)
                continue; /* a gap starts where the previous sector is used */
            size_t len = 0;
            while (len < N && !used[(start + len) % N])
                len++;
            if (len > best_gap) {
                best_gap = len;
                best_end = (start + len) % N;
            }
        }
        free(used);
    }
    out->sector_first = best_gap ? best_end : 0;
    out->sector_count = N - best_gap;
    double step = 360.0 / (double)N;
    out->angle_min_deg = (double)out->sector_first * step;
    out->angle_max_deg = fmod((double)(out->sector_first + out->sector_count) * step, 360.0);
    if (out->sector_count == N) {
        out->angle_min_deg = 0;
        out->angle_max_deg = 360;
    }
}

static int by_volume_desc(const void *pa, const void *pb)
{
    const sr_section *a = pa, *b = pb;
    return a->volume_mm3 < b->volume_mm3 ? 1 : a->volume_mm3 > b->volume_mm3 ? -1 : 0;
}

void sr_sections_release(sr_section *sections, size_t count)
{
    if (!sections)
        return;
    for (size_t i = 0; i < count; i++)
        sr_mesh_release(&sections[i].patch);
    free(sections);
}

sr_status sr_patch_build(const sr_layer_grid *grid, const sr_analysis *a, sr_section **out,
                         size_t *count, sr_err *err)
{
    size_t N = grid->sectors, cells = grid->layers * N;
    int *sec = malloc((cells ? cells : 1) * sizeof *sec);
    double *cb = malloc(N * sizeof *cb), *sb = malloc(N * sizeof *sb);
    sr_section *secs = NULL;
    int n = -1;
    sr_status st = SR_E_NOMEM;
    if (!sec || !cb || !sb)
        goto cleanup;
    for (size_t b = 0; b < N; b++) {
        double th = (double)b * TWO_PI / (double)N;
        cb[b] = cos(th);
        sb[b] = sin(th);
    }
    n = label_sections(grid, a, sec);
    if (n < 0)
        goto cleanup;
    secs = calloc(n ? (size_t)n : 1, sizeof *secs);
    if (!secs)
        goto cleanup;
    for (int s = 0; s < n; s++) {
        describe(grid, a, sec, s, &secs[s]);
        st = build_section(grid, a, sec, s, secs[s].layer_first, secs[s].layer_last, cb, sb,
                           &secs[s].patch, err);
        if (st != SR_OK) {
            sr_sections_release(secs, (size_t)s + 1);
            free(sec);
            free(cb);
            free(sb);
            return st;
        }
        secs[s].volume_mm3 = sr_section_cell_volume(grid, a, sec, s);
        secs[s].area_mm2 = sr_mesh_area(&secs[s].patch);
    }
    qsort(secs, (size_t)n, sizeof *secs, by_volume_desc);
    *out = secs;
    *count = (size_t)n;
    secs = NULL;
    st = SR_OK;
cleanup:
    free(sec);
    free(cb);
    free(sb);
    free(secs);
    if (st != SR_OK)
        sr_err_set(err, st, "out of memory building patch meshes");
    return st;
}
