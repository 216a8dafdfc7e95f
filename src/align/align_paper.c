/*
 * align_paper.c: the paper's heuristic alignment, Algorithm 3 on Algorithm 1 layers
 * (align_internal.h), as read in shared/ALGORITHMS.md.
 *
 * Algorithm 1 (fast layer approximation): the model is sliced along the trial z axis
 * into N_layers layers between its lowest and highest point (layer l holds the vertices
 * with Z_init + l dz <= z < Z_init + (l + 1) dz, i.e. centre L(l) = Z_init + (l + 1/2) dz
 * and half-thickness dz/2); each vertex votes for its sector k = floor(atan2(y, x)
 * mapped to [0, 2pi) / (2pi / N_sectors)) mod N_sectors around the layer's centre, and
 * each sector keeps its farthest vertex (distance D_k). A vertex on the centre belongs
 * to no sector.
 *
 * Algorithm 3 (heuristic alignment): for every trial rotation, count the layers that are
 * symmetric and keep the rotation with the most (ties: the smaller sum of relative
 * differences). Choices made here, because the paper leaves them open:
 *  - rotations: tilts about x and y, alpha and beta in [-90, 90] deg on a grid of
 *    coarse_step_deg (a spin about z changes nothing for an axis), then two finer grids
 *    of step / 5 and step / 25 around the winner;
 *  - the layer's centre: the paper uses the centroid of the layer's vertices, which a
 *    damaged layer pulls off the axis. For axial symmetry the centre is instead a
 *    circle fitted (Kasa's algebraic fit, then once more with Tukey weights on the
 *    radial residuals) to the layer's sector outline, and the axis point reported is
 *    the median of the symmetric layers' centres;
 *  - axial test: D_avg = mean of the non-zero D_k, the layer is symmetric when at least
 *    half the sectors hold a vertex and max_k |D_k - D_avg| / D_avg < delta_D;
 *  - planar (mirror, glide) test: the plane contains the slicing axis, at angle phi in
 *    the layer; phi runs over multiples of half a sector, so sector k's mirror image is
 *    exactly sector (j - k - 1) mod N for phi = j * pi / N. The layer is symmetric when
 *    at least a quarter of the pairs have both sectors filled and
 *    max |D_k - D_k'| / D_avg < delta_D. The centre is the layer's vertex centroid
 *    (which lies on a mirror plane unless the layer is damaged). Tilts use a grid of at
 *    least 10 deg (any direction in the plane is a valid slicing axis), then finer
 *    grids of (tilt, phi);
 *  - glide: at the winning mirror frame the shift is the number of layers m >= 1 for
 *    which layer l mirrored matches layer l + m in the most layer pairs, times dz.
 * al_paper_count (the symmetric_layers reported by method 0) slices once in the final
 * canonical frame, with the canonical z axis as every layer's centre.
 * For speed the vertices are thinned to at most 4000 (every k-th) on the coarse grid
 * and 10000 on the fine ones (500000 for the single count at a given frame); Alg. 1's
 * quality depends on mesh density in any case.
 */
#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>

#define COARSE_POINTS 4000
#define FINE_POINTS 10000
#define COUNT_POINTS 500000

typedef struct slicer {
    const sr_mesh *mesh;
    size_t stride;         /* use every stride-th vertex */
    int L, N;              /* layers, sectors */
    double delta;          /* delta_D */
    /* workspace */
    double *cx, *cy;       /* L layer centres (in the trial frame) */
    int *cnt;              /* L vertex counts */
    double *D;             /* L x N farthest distances (0 = empty sector) */
    double *ox, *oy;       /* L x N outline points */
    double zmin, dz;
} slicer;

static sr_status slicer_init(slicer *sl, const sr_mesh *mesh, const sr_align_opts *o,
                             size_t max_points)
{
    memset(sl, 0, sizeof *sl);
    sl->mesh = mesh;
    sl->L = o->layers;
    sl->N = o->sectors;
    sl->delta = o->delta_d;
    sl->stride = mesh->vertex_count > max_points ? mesh->vertex_count / max_points : 1;
    size_t ln = (size_t)sl->L * (size_t)sl->N;
    sl->cx = malloc((size_t)sl->L * sizeof *sl->cx);
    sl->cy = malloc((size_t)sl->L * sizeof *sl->cy);
    sl->cnt = malloc((size_t)sl->L * sizeof *sl->cnt);
    sl->D = malloc(ln * sizeof *sl->D);
    sl->ox = malloc(ln * sizeof *sl->ox);
    sl->oy = malloc(ln * sizeof *sl->oy);
    if (!sl->cx || !sl->cy || !sl->cnt || !sl->D || !sl->ox || !sl->oy)
        return SR_E_NOMEM;
    return SR_OK;
}

static void slicer_free(slicer *sl)
{
    free(sl->cx);
    free(sl->cy);
    free(sl->cnt);
    free(sl->D);
    free(sl->ox);
    free(sl->oy);
}

/* Trial frame of tilts alpha (about x) and beta (about y): rows u, v, a of
 * R = Ry(beta) Rx(alpha); a is the scan direction that becomes z. */
static void tilt_frame(double alpha, double beta, double u[3], double v[3], double a[3])
{
    double ca = cos(alpha), sa = sin(alpha), cb = cos(beta), sb = sin(beta);
    /* R = Ry Rx: rows */
    u[0] = cb;
    u[1] = sb * sa;
    u[2] = sb * ca;
    v[0] = 0;
    v[1] = ca;
    v[2] = -sa;
    a[0] = -sb;
    a[1] = cb * sa;
    a[2] = cb * ca;
}

static int sector_of(double x, double y, int N)
{
    double ang = atan2(y, x);
    if (ang < 0)
        ang += 2 * M_PI;
    int k = (int)(ang / (2 * M_PI / N));
    return k >= N ? k - N : k;
}

/* Kasa circle fit of the outline of layer l, once reweighted; updates its centre and
 * its D_k (distances from the new centre to the same outline points). */
static void robust_centre(slicer *sl, int l)
{
    int N = sl->N;
    double *D = sl->D + (size_t)l * N, *ox = sl->ox + (size_t)l * N, *oy = sl->oy + (size_t)l * N;
    double cx = sl->cx[l], cy = sl->cy[l], R = 0, cut = INFINITY;
    for (int pass = 0; pass < 2; pass++) {
        double A[9] = {0}, b[3] = {0};
        int used = 0;
        for (int k = 0; k < N; k++) {
            if (D[k] <= 0)
                continue;
            double w = 1;
            if (pass > 0) {
                double r = fabs(hypot(ox[k] - cx, oy[k] - cy) - R);
                if (!(r < cut))
                    continue;
                double q = r / cut;
                w = (1 - q * q) * (1 - q * q);
            }
            double row[3] = {ox[k], oy[k], 1}, rhs = -(ox[k] * ox[k] + oy[k] * oy[k]);
            for (int i = 0; i < 3; i++) {
                b[i] += w * row[i] * rhs;
                for (int j = 0; j < 3; j++)
                    A[3 * i + j] += w * row[i] * row[j];
            }
            used++;
        }
        double sol[3];
        if (used < 5 || !al_solve_spd(3, A, b, sol))
            break;
        double ncx = -sol[0] / 2, ncy = -sol[1] / 2, r2 = ncx * ncx + ncy * ncy - sol[2];
        if (!(r2 > 0))
            break;
        cx = ncx;
        cy = ncy;
        R = sqrt(r2);
        /* Tukey cut-off from the median radial residual */
        double res[4096];
        int nr = 0;
        for (int k = 0; k < N && nr < 4096; k++)
            if (D[k] > 0)
                res[nr++] = fabs(hypot(ox[k] - cx, oy[k] - cy) - R);
        for (int i = 1; i < nr; i++) /* insertion sort: N is small */
            for (int j = i; j > 0 && res[j] < res[j - 1]; j--) {
                double t = res[j];
                res[j] = res[j - 1];
                res[j - 1] = t;
            }
        cut = 4.685 * 1.4826 * (nr ? res[nr / 2] : 0) + 1e-9 * R;
    }
    sl->cx[l] = cx;
    sl->cy[l] = cy;
    for (int k = 0; k < N; k++)
        if (D[k] > 0)
            D[k] = hypot(ox[k] - cx, oy[k] - cy);
}

/* Algorithm 1 for all layers of the trial frame (u, v, a). robust: circle-fit centres. */
static void slice_all(slicer *sl, const double u[3], const double v[3], const double a[3],
                      bool robust)
{
    const sr_mesh *m = sl->mesh;
    int L = sl->L, N = sl->N;
    double zmin = INFINITY, zmax = -INFINITY;
    for (size_t i = 0; i < m->vertex_count; i += sl->stride) {
        double z = v3_dot(a, m->xyz + 3 * i);
        zmin = z < zmin ? z : zmin;
        zmax = z > zmax ? z : zmax;
    }
    double dz = (zmax - zmin) / L;
    if (!(dz > 0))
        dz = 1;
    sl->zmin = zmin;
    sl->dz = dz;
    for (int l = 0; l < L; l++) {
        sl->cx[l] = sl->cy[l] = 0;
        sl->cnt[l] = 0;
    }
    memset(sl->D, 0, (size_t)L * N * sizeof *sl->D);
    for (size_t i = 0; i < m->vertex_count; i += sl->stride) {
        const double *p = m->xyz + 3 * i;
        int l = (int)((v3_dot(a, p) - zmin) / dz);
        l = l < 0 ? 0 : (l >= L ? L - 1 : l);
        sl->cx[l] += v3_dot(u, p);
        sl->cy[l] += v3_dot(v, p);
        sl->cnt[l]++;
    }
    for (int l = 0; l < L; l++)
        if (sl->cnt[l]) {
            sl->cx[l] /= sl->cnt[l];
            sl->cy[l] /= sl->cnt[l];
        }
    for (size_t i = 0; i < m->vertex_count; i += sl->stride) {
        const double *p = m->xyz + 3 * i;
        int l = (int)((v3_dot(a, p) - zmin) / dz);
        l = l < 0 ? 0 : (l >= L ? L - 1 : l);
        double x = v3_dot(u, p), y = v3_dot(v, p);
        double dx = x - sl->cx[l], dy = y - sl->cy[l], r = hypot(dx, dy);
        if (!(r > 0))
            continue;
        size_t k = (size_t)l * N + (size_t)sector_of(dx, dy, N);
        if (r > sl->D[k]) {
            sl->D[k] = r;
            sl->ox[k] = x;
            sl->oy[k] = y;
        }
    }
    if (robust)
        for (int l = 0; l < L; l++)
            if (sl->cnt[l])
                robust_centre(sl, l);
}

/* Axial test of layer l; *rel gets its relative difference (1 when not testable). */
static bool layer_round(const slicer *sl, int l, double *rel)
{
    const double *D = sl->D + (size_t)l * sl->N;
    double sum = 0;
    int n = 0;
    for (int k = 0; k < sl->N; k++)
        if (D[k] > 0) {
            sum += D[k];
            n++;
        }
    *rel = 1;
    if (2 * n < sl->N)
        return false;
    double avg = sum / n, worst = 0;
    for (int k = 0; k < sl->N; k++)
        if (D[k] > 0) {
            double r = fabs(D[k] - avg) / avg;
            worst = r > worst ? r : worst;
        }
    *rel = worst;
    return worst < sl->delta;
}

/* Mirror test of layer l against layer l2 (l2 = l: plain mirror) for the plane at
 * phi = j pi / N: sector k pairs with sector (j - k - 1) mod N. */
static bool layer_mirror(const slicer *sl, int l, int l2, int j, double *rel)
{
    int N = sl->N;
    const double *D = sl->D + (size_t)l * N, *E = sl->D + (size_t)l2 * N;
    double sum = 0, worst = 0;
    int n = 0;
    for (int k = 0; k < N; k++) {
        int k2 = ((j - k - 1) % N + N) % N;
        if (D[k] > 0 && E[k2] > 0) {
            sum += D[k] + E[k2];
            n++;
        }
    }
    *rel = 1;
    if (4 * n < N)
        return false;
    double avg = sum / (2 * n);
    for (int k = 0; k < N; k++) {
        int k2 = ((j - k - 1) % N + N) % N;
        if (D[k] > 0 && E[k2] > 0) {
            double r = fabs(D[k] - E[k2]) / avg;
            worst = r > worst ? r : worst;
        }
    }
    *rel = worst;
    return worst < sl->delta;
}

typedef struct trial {
    double alpha, beta;
    int j;                 /* planar: plane angle index */
    int count;
    double rel;            /* sum of relative differences (tie-break) */
} trial;

static bool trial_better(const trial *a, const trial *b)
{
    return a->count > b->count || (a->count == b->count && a->rel < b->rel);
}

static void eval_axial(slicer *sl, trial *t)
{
    double u[3], v[3], a[3];
    tilt_frame(t->alpha, t->beta, u, v, a);
    slice_all(sl, u, v, a, true);
    t->count = 0;
    t->rel = 0;
    for (int l = 0; l < sl->L; l++) {
        double r;
        t->count += layer_round(sl, l, &r);
        t->rel += r;
    }
}

/* Slices once and tries the plane angles j0 - jhalf .. j0 + jhalf (all when jhalf < 0),
 * keeping the best in *t. */
static void eval_planar(slicer *sl, trial *t, int jhalf)
{
    double u[3], v[3], a[3];
    tilt_frame(t->alpha, t->beta, u, v, a);
    slice_all(sl, u, v, a, false);
    trial best = *t;
    best.count = -1;
    int n = jhalf < 0 ? sl->N : 2 * jhalf + 1;
    for (int i = 0; i < n; i++) {
        trial c = *t;
        c.j = jhalf < 0 ? i : ((t->j - jhalf + i) % sl->N + sl->N) % sl->N;
        c.count = 0;
        c.rel = 0;
        for (int l = 0; l < sl->L; l++) {
            double r;
            c.count += layer_mirror(sl, l, l, c.j, &r);
            c.rel += r;
        }
        if (best.count < 0 || trial_better(&c, &best))
            best = c;
    }
    *t = best;
}

/* Grid search over tilts (and plane angles) of half-width `half` and step `step`
 * around *best; updates *best. */
static void search(slicer *sl, bool planar, trial *best, double half, double step, int jhalf)
{
    trial centre = *best;
    int n = (int)floor(half / step + 1e-9);
    for (int ia = -n; ia <= n; ia++) {
        for (int ib = -n; ib <= n; ib++) {
            trial t = centre;
            t.alpha = centre.alpha + ia * step;
            t.beta = centre.beta + ib * step;
            if (fabs(t.alpha) > M_PI / 2 + 1e-9 || fabs(t.beta) > M_PI / 2 + 1e-9)
                continue;
            if (planar)
                eval_planar(sl, &t, jhalf);
            else
                eval_axial(sl, &t);
            if (trial_better(&t, best))
                *best = t;
        }
    }
}

static double median_inplace(double *v, int n)
{
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && v[j] < v[j - 1]; j--) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return n ? v[n / 2] : 0;
}

sr_status al_paper_align(const al_surface *s, const sr_symmetry *sym,
                         const sr_align_opts *opts, al_paper_result *out)
{
    bool planar = sym->kind != SR_SYM_AXIAL;
    double step = opts->coarse_step_deg * M_PI / 180;
    if (planar && step < 10 * M_PI / 180)
        step = 10 * M_PI / 180;
    slicer sl;
    sr_status st = slicer_init(&sl, s->mesh, opts, COARSE_POINTS);
    if (st != SR_OK) {
        slicer_free(&sl);
        return st;
    }
    trial best = {0};
    best.count = -1;
    search(&sl, planar, &best, M_PI / 2, step, -1);
    slicer_free(&sl);
    st = slicer_init(&sl, s->mesh, opts, FINE_POINTS);
    if (st != SR_OK) {
        slicer_free(&sl);
        return st;
    }
    /* re-score the winner on the denser vertices, then refine around it */
    if (planar)
        eval_planar(&sl, &best, 0);
    else
        eval_axial(&sl, &best);
    search(&sl, planar, &best, step, step / 5, planar ? 2 : -1);
    search(&sl, planar, &best, step / 5, step / 25, planar ? 2 : -1);

    /* the chosen frame, sliced once more for the centres */
    double u[3], v[3], a[3];
    tilt_frame(best.alpha, best.beta, u, v, a);
    slice_all(&sl, u, v, a, !planar);
    double *xs = malloc((size_t)sl.L * 2 * sizeof *xs);
    if (!xs) {
        slicer_free(&sl);
        return SR_E_NOMEM;
    }
    double *ys = xs + sl.L;
    int n = 0;
    for (int pass = 0; pass < 2 && n == 0; pass++) {
        for (int l = 0; l < sl.L; l++) {
            double r;
            bool sym_l = planar ? layer_mirror(&sl, l, l, best.j, &r) : layer_round(&sl, l, &r);
            if (sl.cnt[l] && (sym_l || pass == 1)) {
                xs[n] = sl.cx[l];
                ys[n] = sl.cy[l];
                n++;
            }
        }
    }
    double cx = median_inplace(xs, n), cy = median_inplace(ys, n);
    memset(out, 0, sizeof *out);
    for (int k = 0; k < 3; k++) {
        out->dir[k] = a[k];
        out->point[k] = cx * u[k] + cy * v[k];
    }
    out->symmetric_layers = best.count > 0 ? best.count : 0;
    if (planar) {
        /* the plane through the slicing axis at angle phi = j pi / N: its normal */
        double phi = best.j * M_PI / sl.N;
        for (int k = 0; k < 3; k++)
            out->normal[k] = -sin(phi) * u[k] + cos(phi) * v[k];
        if (sym->kind == SR_SYM_GLIDE) {
            if (sym->shift_mm > 0) {
                out->shift = sym->shift_mm;
            } else {
                int bestm = 1, bestc = -1;
                for (int m = 1; m < sl.L / 2; m++) {
                    int c = 0;
                    for (int l = 0; l + m < sl.L; l++) {
                        double r;
                        c += layer_mirror(&sl, l, l + m, best.j, &r);
                    }
                    if (c > bestc) {
                        bestc = c;
                        bestm = m;
                    }
                }
                out->shift = bestm * sl.dz;
            }
        }
    }
    free(xs);
    slicer_free(&sl);
    return SR_OK;
}

int al_paper_count(const al_surface *s, const sr_symmetry *sym, const sr_align_opts *opts,
                   const double xform[12])
{
    slicer sl;
    if (slicer_init(&sl, s->mesh, opts, COUNT_POINTS) != SR_OK) {
        slicer_free(&sl);
        return 0;
    }
    /* the canonical frame's rows are the trial frame; centres are the z axis */
    double u[3] = {xform[0], xform[1], xform[2]}, v[3] = {xform[4], xform[5], xform[6]},
           a[3] = {xform[8], xform[9], xform[10]};
    slice_all(&sl, u, v, a, false);
    int count = 0;
    /* recentre on the canonical z axis: scan coordinates of it are -t in (u, v) */
    double ax = -xform[3], ay = -xform[7];
    const sr_mesh *m = s->mesh;
    memset(sl.D, 0, (size_t)sl.L * sl.N * sizeof *sl.D);
    for (size_t i = 0; i < m->vertex_count; i += sl.stride) {
        const double *p = m->xyz + 3 * i;
        int l = (int)((v3_dot(a, p) - sl.zmin) / sl.dz);
        l = l < 0 ? 0 : (l >= sl.L ? sl.L - 1 : l);
        double dx = v3_dot(u, p) - ax, dy = v3_dot(v, p) - ay, r = hypot(dx, dy);
        if (!(r > 0))
            continue;
        size_t k = (size_t)l * sl.N + (size_t)sector_of(dx, dy, sl.N);
        if (r > sl.D[k])
            sl.D[k] = r;
    }
    /* the mirror plane x = 0 is at phi = pi / 2, i.e. j = N / 2 (N even) */
    for (int l = 0; l < sl.L; l++) {
        double r;
        if (sym->kind == SR_SYM_AXIAL)
            count += layer_round(&sl, l, &r);
        else if (sl.N % 2 == 0)
            count += layer_mirror(&sl, l, l, sl.N / 2, &r);
    }
    slicer_free(&sl);
    return count;
}
