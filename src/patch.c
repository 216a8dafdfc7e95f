/*
 * patch.c: missing sections and their closed patch surfaces, paper Algorithm 6 (see
 * patch.h for the construction).
 *
 * Every vertex lies on a layer boundary z_k = z_init + k dz at a sector border angle
 * theta_b = b 2pi/N, at some radius r; it is computed from (b, r, k) the same way
 * everywhere so equal vertices are bitwise equal and weld exactly. Faces are convex
 * polygons (rectangles and chord trapezoids); a radial edge (fixed b and k) gets every
 * radius of the section's cells around that line inserted, and a polygon with inserted
 * points is fanned from its centroid.
 */
#include "patch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.28318530717958647692

typedef struct pvert {
    size_t b, k;
    double r;
} pvert;

typedef struct builder {
    const sr_layer_grid *g;
    const sr_analysis *a;
    const int *sec;
    int s;
    double *cb, *sb;    /* cos/sin of border angles */
    sr_mesh m;
    size_t vcap, tcap;
    sr_status st;
} builder;

static int in_sec(const builder *B, long l, long j)
{
    size_t n = B->g->sectors;
    if (l < 0 || l >= (long)B->g->layers)
        return 0;
    j %= (long)n;
    if (j < 0)
        j += (long)n;
    return B->sec[(size_t)l * n + (size_t)j] == B->s;
}

static size_t cell(const builder *B, long l, long j)
{
    long n = (long)B->g->sectors;
    j %= n;
    if (j < 0)
        j += n;
    return (size_t)l * (size_t)n + (size_t)j;
}

static uint32_t add_vertex(builder *B, double x, double y, double z)
{
    if (B->m.vertex_count == B->vcap) {
        size_t cap = B->vcap ? 2 * B->vcap : 256;
        double *p = realloc(B->m.xyz, cap * 3 * sizeof *p);
        if (!p) {
            B->st = SR_E_NOMEM;
            return 0;
        }
        B->m.xyz = p;
        B->vcap = cap;
    }
    double *p = B->m.xyz + 3 * B->m.vertex_count;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return (uint32_t)B->m.vertex_count++;
}

static void add_tri(builder *B, uint32_t a, uint32_t b, uint32_t c)
{
    if (B->m.tri_count == B->tcap) {
        size_t cap = B->tcap ? 2 * B->tcap : 256;
        uint32_t *t = realloc(B->m.tri, cap * 3 * sizeof *t);
        if (!t) {
            B->st = SR_E_NOMEM;
            return;
        }
        B->m.tri = t;
        B->tcap = cap;
    }
    uint32_t *t = B->m.tri + 3 * B->m.tri_count++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

static void vert_xyz(const builder *B, pvert v, double out[3])
{
    size_t b = v.b % B->g->sectors;
    out[0] = v.r * B->cb[b];
    out[1] = v.r * B->sb[b];
    out[2] = B->g->z_init + (double)v.k * B->g->dz;
}

/* Radii of the section's cells around the radial line (b, k), sorted ascending. */
static size_t line_radii(const builder *B, size_t b, size_t k, double out[8])
{
    size_t n = 0;
    for (long l = (long)k - 1; l <= (long)k; l++) {
        for (long j = (long)b - 1; j <= (long)b; j++) {
            if (!in_sec(B, l, j))
                continue;
            size_t c = cell(B, l, j);
            out[n++] = B->g->r[c];
            out[n++] = B->a->restored_r[c];
        }
    }
    for (size_t i = 1; i < n; i++) /* insertion sort, n <= 8 */
        for (size_t j = i; j > 0 && out[j - 1] > out[j]; j--) {
            double t = out[j];
            out[j] = out[j - 1];
            out[j - 1] = t;
        }
    return n;
}

/* Emits a convex polygon given by its corners, inserting breakpoints on radial edges. */
static void emit(builder *B, const pvert *corner, size_t count)
{
    pvert poly[64];
    size_t n = 0;
    for (size_t i = 0; i < count && n < 56; i++) {
        pvert p = corner[i], q = corner[(i + 1) % count];
        poly[n++] = p;
        if (p.b % B->g->sectors == q.b % B->g->sectors && p.k == q.k && p.r != q.r) {
            double rad[8];
            size_t m = line_radii(B, p.b % B->g->sectors, p.k, rad);
            if (p.r < q.r) {
                for (size_t t = 0; t < m; t++)
                    if (rad[t] > p.r && rad[t] < q.r && rad[t] != poly[n - 1].r)
                        poly[n++] = (pvert){p.b, p.k, rad[t]};
            } else {
                for (size_t t = m; t-- > 0;)
                    if (rad[t] < p.r && rad[t] > q.r && rad[t] != poly[n - 1].r)
                        poly[n++] = (pvert){p.b, p.k, rad[t]};
            }
        }
    }
    /* drop repeated points (radius 0 at two borders is the same axis point) */
    double xyz[64][3];
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        vert_xyz(B, poly[i], xyz[m]);
        if (m > 0 && xyz[m][0] == xyz[m - 1][0] && xyz[m][1] == xyz[m - 1][1] &&
            xyz[m][2] == xyz[m - 1][2])
            continue;
        m++;
    }
    while (m > 1 && xyz[m - 1][0] == xyz[0][0] && xyz[m - 1][1] == xyz[0][1] &&
           xyz[m - 1][2] == xyz[0][2])
        m--;
    if (m < 3)
        return;
    uint32_t idx[64];
    for (size_t i = 0; i < m; i++)
        idx[i] = add_vertex(B, xyz[i][0], xyz[i][1], xyz[i][2]);
    if (m == 3) {
        add_tri(B, idx[0], idx[1], idx[2]);
    } else if (m == 4 && count == 4) {
        add_tri(B, idx[0], idx[1], idx[2]);
        add_tri(B, idx[0], idx[2], idx[3]);
    } else {
        double c[3] = {0, 0, 0};
        for (size_t i = 0; i < m; i++)
            for (int d = 0; d < 3; d++)
                c[d] += xyz[i][d] / (double)m;
        uint32_t ci = add_vertex(B, c[0], c[1], c[2]);
        for (size_t i = 0; i < m; i++)
            add_tri(B, ci, idx[i], idx[(i + 1) % m]);
    }
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

static void cell_interval(const builder *B, long l, long j, double *lo, double *hi)
{
    if (in_sec(B, l, j)) {
        size_t c = cell(B, l, j);
        *lo = B->g->r[c];
        *hi = B->a->restored_r[c];
    } else {
        *lo = 0;
        *hi = -1;
    }
}

static void build_section(builder *B)
{
    size_t L = B->g->layers, N = B->g->sectors;
    for (size_t l = 0; l < L; l++) {
        for (size_t j = 0; j < N; j++) {
            if (!in_sec(B, (long)l, (long)j))
                continue;
            size_t c = cell(B, (long)l, (long)j);
            double ri = B->g->r[c], ro = B->a->restored_r[c];
            pvert outer[4] = {{j, l, ro}, {j + 1, l, ro}, {j + 1, l + 1, ro}, {j, l + 1, ro}};
            emit(B, outer, 4);
            if (ri > 0) {
                pvert inner[4] = {{j, l, ri}, {j, l + 1, ri}, {j + 1, l + 1, ri}, {j + 1, l, ri}};
                emit(B, inner, 4);
            }
        }
    }
    /* walls on border b between sector b-1 (left) and b (right), per layer */
    for (size_t l = 0; l < L; l++) {
        for (size_t b = 0; b < N; b++) {
            double la, lb, ra, rb, piece[2][2];
            cell_interval(B, (long)l, (long)b - 1, &la, &lb);
            cell_interval(B, (long)l, (long)b, &ra, &rb);
            size_t n = interval_minus(la, lb, ra, rb, piece);
            for (size_t i = 0; i < n; i++) { /* left-owned: normal +theta */
                pvert w[4] = {{b, l, piece[i][0]}, {b, l + 1, piece[i][0]},
                              {b, l + 1, piece[i][1]}, {b, l, piece[i][1]}};
                emit(B, w, 4);
            }
            n = interval_minus(ra, rb, la, lb, piece);
            for (size_t i = 0; i < n; i++) { /* right-owned: normal -theta */
                pvert w[4] = {{b, l, piece[i][0]}, {b, l, piece[i][1]},
                              {b, l + 1, piece[i][1]}, {b, l + 1, piece[i][0]}};
                emit(B, w, 4);
            }
        }
    }
    /* caps on boundary k between layer k-1 (below) and k (above), per sector */
    for (size_t k = 0; k <= L; k++) {
        for (size_t j = 0; j < N; j++) {
            double ba, bb, aa, ab, piece[2][2];
            cell_interval(B, (long)k - 1, (long)j, &ba, &bb);
            cell_interval(B, (long)k, (long)j, &aa, &ab);
            size_t n = interval_minus(ba, bb, aa, ab, piece);
            for (size_t i = 0; i < n; i++) { /* below-owned: normal +z */
                pvert q[4] = {{j, k, piece[i][0]}, {j, k, piece[i][1]},
                              {j + 1, k, piece[i][1]}, {j + 1, k, piece[i][0]}};
                emit(B, q, 4);
            }
            n = interval_minus(aa, ab, ba, bb, piece);
            for (size_t i = 0; i < n; i++) { /* above-owned: normal -z */
                pvert q[4] = {{j, k, piece[i][0]}, {j + 1, k, piece[i][0]},
                              {j + 1, k, piece[i][1]}, {j, k, piece[i][1]}};
                emit(B, q, 4);
            }
        }
    }
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
        builder B = {grid, a, sec, s, cb, sb, {0}, 0, 0, SR_OK};
        build_section(&B);
        if (B.st == SR_OK)
            B.st = sr_mesh_weld_exact(&B.m);
        if (B.st != SR_OK) {
            sr_mesh_release(&B.m);
            sr_sections_release(secs, (size_t)s);
            secs = NULL;
            goto cleanup;
        }
        describe(grid, a, sec, s, &secs[s]);
        secs[s].patch = B.m;
        secs[s].volume_mm3 = sr_mesh_volume(&B.m);
        secs[s].area_mm2 = sr_mesh_area(&B.m);
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
