/*
 * align_icp.c: symmetry models and the robust ICP that fits them (align_internal.h).
 *
 * A symmetry of a part is a rigid (or improper) transform T that maps its surface onto
 * itself: rotation about the axis by any angle (continuous axial) or by multiples of
 * 360/n (n-fold), reflection in the plane (mirror), reflection plus a shift s along a
 * direction t in the plane (glide). So for each sample point p of the scan, T(p) must
 * lie on the scan again - except where T(p) or p falls into the damage, which has no
 * partner. The fit is ICP of the surface against itself ("symmetry ICP", e.g. Mitra,
 * Guibas & Pauly 2006 use the same idea for symmetry refinement):
 *   - for each sample, x = T(p), q = closest surface point, m = its triangle normal,
 *     point-to-plane residual r = m.(x - q) (fast, exact on flat pieces);
 *   - Tukey biweights on the distance |x - q| with a cut-off c annealed from the
 *     starting radius towards 4.685 x the robust scale 1.4826 * median (at most 4x per
 *     settled step, never below 0.1 % of the part), so damage, fracture faces and
 *     protruding features (a key on a shaft) get weight 0 once the fit has settled;
 *   - a Gauss-Newton step on the model's local parameters (2 tilt angles of the axis or
 *     normal, position(s) in units of the part size, glide: the in-plane angle of t and
 *     the shift), the Jacobian by central differences of the model's 3x4 matrices
 *     (a handful of matrices per iteration, so it costs nothing per sample), limited
 *     so that no sample moves by more than half the cut-off (the linearisation only
 *     holds within the matching radius);
 *   - a candidate that matches under a quarter of its samples after 5 steps is dropped
 *     early (its evaluation says how poor it is).
 * Several variants of a model (rotation angles; +s and -s of a glide) are used at once:
 * sample i uses variant i mod V, so a continuous axis is constrained by many angles at
 * the cost of one closest-point query per sample.
 * The queries of an iteration (and of an evaluation) are spread over the surface's
 * threads (al_surface_threads); the sums over them are taken in sample order after, so
 * the fit is the same for any number of threads.
 */
#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>

#define FD_EPS 1e-6

int al_model_nparam(const al_model *m)
{
    switch (m->kind) {
    case AL_AXIAL:
        return 4;
    case AL_MIRROR:
        return 3;
    default:
        return m->fix_shift ? 4 : 5;
    }
}

/* Moved element for a local step: direction/normal a2, point c2, glide t2, shift s2. */
static void model_moved(const al_model *m, const double *d, double a2[3], double c2[3],
                        double t2[3], double *s2)
{
    double u[3], v[3];
    if (m->kind == AL_GLIDE) {
        memcpy(u, m->t, sizeof u);
        v3_cross(m->a, m->t, v);
    } else {
        al_perp_frame(m->a, u, v);
    }
    memcpy(a2, m->a, 3 * sizeof(double));
    memcpy(c2, m->c, 3 * sizeof(double));
    memcpy(t2, m->t, 3 * sizeof(double));
    *s2 = m->shift;
    if (!d)
        return;
    for (int k = 0; k < 3; k++)
        a2[k] = m->a[k] + d[0] * u[k] + d[1] * v[k];
    v3_normalize(a2);
    if (m->kind == AL_AXIAL) {
        for (int k = 0; k < 3; k++)
            c2[k] = m->c[k] + m->scale * (d[2] * u[k] + d[3] * v[k]);
        return;
    }
    for (int k = 0; k < 3; k++)
        c2[k] = m->c[k] + m->scale * d[2] * m->a[k];
    if (m->kind == AL_GLIDE) {
        double r[9], tr[3];
        al_rot_axis(m->a, d[3], r);
        for (int k = 0; k < 3; k++)
            tr[k] = r[3 * k] * m->t[0] + r[3 * k + 1] * m->t[1] + r[3 * k + 2] * m->t[2];
        double dn = v3_dot(tr, a2);
        for (int k = 0; k < 3; k++)
            t2[k] = tr[k] - dn * a2[k];
        v3_normalize(t2);
        if (!m->fix_shift)
            *s2 = m->shift + m->scale * d[4];
    }
}

void al_model_matrix(const al_model *m, const double *delta, int variant, double mat[12])
{
    double a[3], c[3], t[3], s;
    model_moved(m, delta, a, c, t, &s);
    double r[9];
    if (m->kind == AL_AXIAL) {
        al_rot_axis(a, m->angle[variant], r);
    } else {
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                r[3 * i + j] = (i == j) - 2 * a[i] * a[j];
    }
    /* x = R (p - c) + c (+ shift) */
    double sh = m->kind == AL_GLIDE ? (variant == 0 ? s : -s) : 0;
    for (int i = 0; i < 3; i++) {
        mat[4 * i] = r[3 * i];
        mat[4 * i + 1] = r[3 * i + 1];
        mat[4 * i + 2] = r[3 * i + 2];
        mat[4 * i + 3] = c[i] - (r[3 * i] * c[0] + r[3 * i + 1] * c[1] + r[3 * i + 2] * c[2]) +
                         sh * t[i];
    }
}

void al_model_step(al_model *m, const double *delta)
{
    double a[3], c[3], t[3], s;
    model_moved(m, delta, a, c, t, &s);
    memcpy(m->a, a, sizeof a);
    memcpy(m->c, c, sizeof c);
    memcpy(m->t, t, sizeof t);
    m->shift = s;
}

static void apply(const double *mat, const double p[3], double x[3])
{
    for (int i = 0; i < 3; i++)
        x[i] = mat[4 * i] * p[0] + mat[4 * i + 1] * p[1] + mat[4 * i + 2] * p[2] + mat[4 * i + 3];
}

/* k-th smallest of v[0..n-1] (Wirth's selection; reorders v; no NaN allowed). */
static double select_kth(double *v, size_t n, size_t k)
{
    ptrdiff_t l = 0, r = (ptrdiff_t)n - 1, kk = (ptrdiff_t)k;
    while (l < r) {
        double x = v[kk];
        ptrdiff_t i = l, j = r;
        do {
            while (v[i] < x)
                i++;
            while (x < v[j])
                j--;
            if (i <= j) {
                double t = v[i];
                v[i] = v[j];
                v[j] = t;
                i++;
                j--;
            }
        } while (i <= j);
        if (j < kk)
            l = i;
        if (kk < i)
            r = j;
    }
    return v[kk];
}

static double median_of(const double *d, size_t n, double *scratch)
{
    if (n == 0)
        return INFINITY;
    memcpy(scratch, d, n * sizeof *d);
    return select_kth(scratch, n, n / 2);
}

bool al_fit_better(const al_fit *a, const al_fit *b)
{
    if (a->score > b->score + 0.01)
        return true;
    if (a->score < b->score - 0.01)
        return false;
    return a->inlier_rms < b->inlier_rms;
}

void al_evaluate(al_surface *s, const al_samples *smp, const al_model *m, double tol,
                 al_fit *fit)
{
    int V = m->variant_count > 0 ? m->variant_count : 1;
    double *mats = malloc((size_t)V * 12 * sizeof *mats);
    double *d = malloc((smp->count ? smp->count : 1) * 2 * sizeof *d);
    al_fit f = {0};
    f.tol = tol;
    f.median = INFINITY;
    if (!mats || !d) {
        free(mats);
        free(d);
        *fit = f;
        return;
    }
    for (int v = 0; v < V; v++)
        al_model_matrix(m, NULL, v, mats + 12 * v);
    size_t in = 0;
    double ss = 0;
    /* the queries on the surface's threads, the sums in order: the same for any number */
#pragma omp parallel for num_threads(s->threads) schedule(static) if (smp->count >= AL_PARALLEL_MIN)
    for (size_t i = 0; i < smp->count; i++) {
        double x[3], q[3], n[3], dist;
        apply(mats + 12 * (i % (size_t)V), smp->p + 3 * i, x);
        d[i] = al_surface_closest(s, x, tol, q, n, &dist) ? dist : INFINITY;
    }
    for (size_t i = 0; i < smp->count; i++)
        if (d[i] <= tol) {
            in++;
            ss += d[i] * d[i];
        }
    f.score = smp->count ? (double)in / (double)smp->count : 0;
    f.inlier_rms = in ? sqrt(ss / (double)in) : INFINITY;
    f.median = median_of(d, smp->count, d + smp->count);
    free(mats);
    free(d);
    *fit = f;
}

/* Largest displacement of a corner of the box (min xyz, max xyz) under a parameter
 * step, over up to four variants (spread over the list). */
static double step_displacement(const al_model *m, const double *step, int V,
                                const double box[6])
{
    double worst = 0;
    for (int q = 0; q < 4 && q < V; q++) {
        int v = q * V / 4;
        double m0[12], m1[12];
        al_model_matrix(m, NULL, v, m0);
        al_model_matrix(m, step, v, m1);
        for (int c = 0; c < 8; c++) {
            double p[3] = {box[c & 1 ? 3 : 0], box[c & 2 ? 4 : 1], box[c & 4 ? 5 : 2]};
            double x0[3], x1[3];
            apply(m0, p, x0);
            apply(m1, p, x1);
            double d = sqrt((x1[0] - x0[0]) * (x1[0] - x0[0]) + (x1[1] - x0[1]) * (x1[1] - x0[1]) +
                            (x1[2] - x0[2]) * (x1[2] - x0[2]));
            worst = d > worst ? d : worst;
        }
    }
    return worst;
}

void al_icp(al_surface *s, const al_samples *smp, al_model *m, int max_iter, double tau0,
            double tol, al_fit *fit)
{
    int V = m->variant_count > 0 ? m->variant_count : 1;
    int np = al_model_nparam(m);
    int nm = 1 + 2 * np; /* matrices per variant: base, then +eps / -eps per parameter */
    size_t n = smp->count;
    double *mats = malloc((size_t)V * (size_t)nm * 12 * sizeof *mats);
    double *rows = malloc((n ? n : 1) * (size_t)(np + 1) * sizeof *rows);
    double *d = malloc((n ? n : 1) * 2 * sizeof *d);
    int it = 0;
    if (!mats || !rows || !d)
        goto done;
    double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double x = smp->p[3 * i + k];
            box[k] = x < box[k] ? x : box[k];
            box[3 + k] = x > box[3 + k] ? x : box[3 + k];
        }
    double cut = tau0;
    /* below 0.1 % of the part size every residual counts (a faceted CAD cylinder turned
     * by an arbitrary angle misses itself by its sagitta, symmetrically) */
    double floor_cut = 1e-3 * (m->scale > 0 ? m->scale : 1);
    int at_level = 0;
    for (it = 0; it < max_iter; it++) {
        for (int v = 0; v < V; v++) {
            double *mv = mats + (size_t)v * nm * 12;
            al_model_matrix(m, NULL, v, mv);
            for (int j = 0; j < np; j++) {
                double dp[AL_MAX_PARAMS] = {0};
                dp[j] = FD_EPS;
                al_model_matrix(m, dp, v, mv + 12 * (1 + 2 * j));
                dp[j] = -FD_EPS;
                al_model_matrix(m, dp, v, mv + 12 * (2 + 2 * j));
            }
        }
#pragma omp parallel for num_threads(s->threads) schedule(static) if (n >= AL_PARALLEL_MIN)
        for (size_t i = 0; i < n; i++) {
            const double *p = smp->p + 3 * i;
            const double *mv = mats + (i % (size_t)V) * nm * 12;
            double x[3], q[3], nq[3], dist;
            apply(mv, p, x);
            double *row = rows + i * (size_t)(np + 1);
            if (!al_surface_closest(s, x, cut, q, nq, &dist)) {
                d[i] = INFINITY;
                continue;
            }
            d[i] = dist;
            row[0] = nq[0] * (x[0] - q[0]) + nq[1] * (x[1] - q[1]) + nq[2] * (x[2] - q[2]);
            for (int j = 0; j < np; j++) {
                double xp[3], xm[3];
                apply(mv + 12 * (1 + 2 * j), p, xp);
                apply(mv + 12 * (2 + 2 * j), p, xm);
                row[1 + j] = (nq[0] * (xp[0] - xm[0]) + nq[1] * (xp[1] - xm[1]) +
                              nq[2] * (xp[2] - xm[2])) / (2 * FD_EPS);
            }
        }
        double med = median_of(d, n, d + n);
        double want = 4.685 * 1.4826 * med;
        if (want < floor_cut)
            want = floor_cut;
        double H[AL_MAX_PARAMS * AL_MAX_PARAMS] = {0}, g[AL_MAX_PARAMS] = {0};
        size_t used = 0;
        for (size_t i = 0; i < n; i++) {
            if (!(d[i] < cut))
                continue;
            double u = d[i] / cut, w = (1 - u * u) * (1 - u * u);
            const double *row = rows + i * (size_t)(np + 1);
            for (int a = 0; a < np; a++) {
                g[a] += w * row[1 + a] * row[0];
                for (int b = 0; b <= a; b++)
                    H[a * np + b] += w * row[1 + a] * row[1 + b];
            }
            used++;
        }
        /* too few matches to say anything, or a hopeless candidate (under a quarter of
         * the samples matched after 5 steps): stop spending queries on it */
        if (used < (size_t)np * 4 || (it >= 5 && used * 4 < n))
            break;
        double trace = 0;
        for (int a = 0; a < np; a++) {
            for (int b = 0; b < a; b++)
                H[b * np + a] = H[a * np + b];
            trace += H[a * np + a];
        }
        for (int a = 0; a < np; a++) {
            H[a * np + a] += 1e-9 * H[a * np + a] + 1e-14 * trace + 1e-300;
            g[a] = -g[a];
        }
        double step[AL_MAX_PARAMS];
        if (!al_solve_spd(np, H, g, step))
            break;
        double big = 0;
        for (int a = 0; a < np; a++)
            big = fabs(step[a]) > big ? fabs(step[a]) : big;
        if (big > 0.05) /* trust region: at most ~3 deg or 5 % of the part per step */
            for (int a = 0; a < np; a++)
                step[a] *= 0.05 / big;
        /* and no sample may move by more than half the cut-off: the linearisation only
         * holds within the matching radius, and a parameter that few samples constrain
         * (a glide's shift: only faces across the shift direction see it) would
         * otherwise take a wild step */
        double disp = step_displacement(m, step, V, box);
        if (disp > 0.5 * cut) {
            for (int a = 0; a < np; a++)
                step[a] *= 0.5 * cut / disp;
            big *= 0.5 * cut / disp;
        }
        al_model_step(m, step);
        /* anneal: once the fit has settled at this cut-off (or after 4 steps), shrink it
         * by at most 4x towards the robust scale; shrinking faster would drop the
         * residuals that still carry the error when most of the surface is blind to it
         * (a flange's flat faces turned about a shifted axis stay on themselves) */
        at_level++;
        if (want < 0.8 * cut && (big < 1e-4 || at_level >= 4)) {
            cut = want > 0.25 * cut ? want : 0.25 * cut;
            at_level = 0;
        } else if (big < 1e-6 && !(want < 0.8 * cut)) {
            break; /* converged at the final cut-off */
        }
    }
done:
    free(mats);
    free(rows);
    free(d);
    al_evaluate(s, smp, m, tol, fit);
    fit->iterations = it;
}
