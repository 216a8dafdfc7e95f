/*
 * align_axial.c: finding the axis of an axially symmetric scan (align_internal.h).
 *
 * Candidates, then a robust symmetry ICP (align_icp.c) from each, keeping the best:
 *  1. the normal-line fit of Pottmann & Randrup ("Rotational and helical surface
 *     approximation for reverse engineering", Computing 60, 1998): on a surface of
 *     revolution every normal line meets the axis. With axis direction a and moment
 *     abar = c x a, the line (p, n) meets the axis iff a.(p x n) + abar.n = 0, linear in
 *     (a, abar). Minimising the area-weighted squares subject to |a| = 1 is a 6 x 6
 *     generalised eigenproblem; eliminating abar = -C^-1 B^T a leaves the smallest
 *     eigenvector of the 3 x 3 Schur complement A - B C^-1 B^T. Iteratively reweighted
 *     (Tukey on the residual, scale from the area-weighted median) so the fracture faces
 *     of the damage, keys and involute gear flanks (whose normals miss the axis) drop
 *     out. Flat faces normal to the axis and cylinders are consistent with it;
 *  2. the three principal axes of the surface's area covariance through its area
 *     centroid (a gear's or flange's axis is its distinct principal axis);
 *  3. the caller's hint (opts->hint), if any, through the centroid;
 *  4. only when all of these fit poorly (score < 0.5): the paper's Algorithm 3 axis.
 * Candidates are screened on a few hundred samples, the promising ones refined on a
 * few thousand; the best (highest share of samples whose rotated image lies on the
 * scan, then lowest inlier RMS; with a hint, the nearest to it among those scoring 0.8
 * of the best) is refined again on ten thousand. Continuous symmetry uses 11 rotation
 * angles (30 deg steps), n-fold symmetry the n - 1 rotations by multiples of 360/n.
 */
#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>

#define NL_MAX 200000

/* Area-weighted median of |res| (sorts a copy of index pairs by value). */
typedef struct wres {
    double r, w;
} wres;

static int wres_cmp(const void *pa, const void *pb)
{
    const wres *a = pa, *b = pb;
    return (a->r > b->r) - (a->r < b->r);
}

bool al_axial_normal_lines(const al_surface *s, double a_out[3], double c_out[3])
{
    const double *g = s->centroid;
    wres *res = malloc(s->count * sizeof *res);
    if (!res)
        return false;
    double a[3] = {0, 0, 1}, abar[3] = {0, 0, 0};
    double cut = INFINITY;
    bool ok = false;
    /* on a big scan every k-th triangle (at most ~NL_MAX of them): the estimate is only a
     * candidate for the ICP, and eight weighted passes over a million triangles took
     * 0.2 s; scans up to NL_MAX triangles use all of them */
    size_t step = s->count > NL_MAX ? (s->count + NL_MAX - 1) / NL_MAX : 1;
    for (int iter = 0; iter < 8; iter++) {
        double M[36] = {0};
        for (size_t i = 0; i < s->count; i += step) {
            const uint32_t *f = s->mesh->tri + 3 * al_tri_of(s, i);
            const double *pa = s->mesh->xyz + 3 * (size_t)f[0],
                         *pb = s->mesh->xyz + 3 * (size_t)f[1],
                         *pc = s->mesh->xyz + 3 * (size_t)f[2];
            double p[3], z[6];
            for (int k = 0; k < 3; k++)
                p[k] = (pa[k] + pb[k] + pc[k]) / 3 - g[k];
            double n[3], w;
            al_surface_normal(s, i, n, &w);
            v3_cross(p, n, z);
            z[3] = n[0];
            z[4] = n[1];
            z[5] = n[2];
            if (iter > 0) {
                double r = fabs(v3_dot(a, z) + v3_dot(abar, n));
                if (!(r < cut))
                    continue;
                double u = r / cut;
                w *= (1 - u * u) * (1 - u * u);
            }
            for (int r = 0; r < 6; r++)
                for (int q = 0; q <= r; q++)
                    M[6 * r + q] += w * z[r] * z[q];
        }
        for (int r = 0; r < 6; r++)
            for (int q = 0; q < r; q++)
                M[6 * q + r] = M[6 * r + q];
        /* Schur complement S = A - B C^-1 B^T, C regularised (a pure cylinder has no
         * normal along the axis) */
        double C[9], Ci[9], B[9], S[9];
        double trc = M[21] + M[28] + M[35];
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++) {
                C[3 * r + q] = M[6 * (3 + r) + 3 + q] + (r == q ? 1e-9 * trc + 1e-300 : 0);
                B[3 * r + q] = M[6 * r + 3 + q];
            }
        double det = C[0] * (C[4] * C[8] - C[5] * C[7]) - C[1] * (C[3] * C[8] - C[5] * C[6]) +
                     C[2] * (C[3] * C[7] - C[4] * C[6]);
        if (!(fabs(det) > 0))
            break;
        Ci[0] = (C[4] * C[8] - C[5] * C[7]) / det;
        Ci[1] = (C[2] * C[7] - C[1] * C[8]) / det;
        Ci[2] = (C[1] * C[5] - C[2] * C[4]) / det;
        Ci[3] = (C[5] * C[6] - C[3] * C[8]) / det;
        Ci[4] = (C[0] * C[8] - C[2] * C[6]) / det;
        Ci[5] = (C[2] * C[3] - C[0] * C[5]) / det;
        Ci[6] = (C[3] * C[7] - C[4] * C[6]) / det;
        Ci[7] = (C[1] * C[6] - C[0] * C[7]) / det;
        Ci[8] = (C[0] * C[4] - C[1] * C[3]) / det;
        double BCi[9];
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++) {
                double sum = 0;
                for (int k = 0; k < 3; k++)
                    sum += B[3 * r + k] * Ci[3 * k + q];
                BCi[3 * r + q] = sum;
            }
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++) {
                double sum = 0;
                for (int k = 0; k < 3; k++)
                    sum += BCi[3 * r + k] * B[3 * q + k];
                S[3 * r + q] = M[6 * r + q] - sum;
            }
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < r; q++)
                S[3 * r + q] = S[3 * q + r] = 0.5 * (S[3 * r + q] + S[3 * q + r]);
        double w3[3], v3m[9];
        al_eig_sym(3, S, w3, v3m);
        double an[3] = {v3m[0], v3m[3], v3m[6]};
        if (iter > 0 && v3_dot(an, a) < 0)
            for (int k = 0; k < 3; k++)
                an[k] = -an[k];
        memcpy(a, an, sizeof a);
        /* abar = -C^-1 B^T a, made perpendicular to a */
        double bta[3];
        for (int k = 0; k < 3; k++)
            bta[k] = B[k] * a[0] + B[3 + k] * a[1] + B[6 + k] * a[2];
        for (int k = 0; k < 3; k++)
            abar[k] = -(Ci[3 * k] * bta[0] + Ci[3 * k + 1] * bta[1] + Ci[3 * k + 2] * bta[2]);
        double da = v3_dot(abar, a);
        for (int k = 0; k < 3; k++)
            abar[k] -= da * a[k];
        ok = true;
        /* new cut-off from the area-weighted median residual of at most ~20000
         * evenly spread triangles (sorting them all would dominate on big scans) */
        double wsum = 0;
        size_t stride = s->count > 20000 ? s->count / 20000 : 1, nres = 0;
        for (size_t i = 0; i < s->count; i += stride) {
            const uint32_t *f = s->mesh->tri + 3 * al_tri_of(s, i);
            const double *pa = s->mesh->xyz + 3 * (size_t)f[0],
                         *pb = s->mesh->xyz + 3 * (size_t)f[1],
                         *pc = s->mesh->xyz + 3 * (size_t)f[2];
            double p[3], z[3];
            for (int k = 0; k < 3; k++)
                p[k] = (pa[k] + pb[k] + pc[k]) / 3 - g[k];
            double n[3], area;
            al_surface_normal(s, i, n, &area);
            v3_cross(p, n, z);
            res[nres].r = fabs(v3_dot(a, z) + v3_dot(abar, n));
            res[nres].w = area;
            wsum += area;
            nres++;
        }
        qsort(res, nres, sizeof *res, wres_cmp);
        double acc = 0, med = 0;
        for (size_t i = 0; i < nres; i++) {
            acc += res[i].w;
            if (acc >= 0.5 * wsum) {
                med = res[i].r;
                break;
            }
        }
        double want = 4.685 * 1.4826 * med;
        if (want < 1e-6 * s->diag)
            want = 1e-6 * s->diag;
        cut = want < cut ? want : cut;
    }
    free(res);
    if (!ok)
        return false;
    double crel[3];
    v3_cross(a, abar, crel);
    for (int k = 0; k < 3; k++) {
        a_out[k] = a[k];
        c_out[k] = g[k] + crel[k];
    }
    return true;
}

static void axial_model(const al_surface *s, const sr_symmetry *sym, const double a[3],
                        const double c[3], al_model *m)
{
    memset(m, 0, sizeof *m);
    m->kind = AL_AXIAL;
    memcpy(m->a, a, 3 * sizeof(double));
    v3_normalize(m->a);
    /* keep the point near the part: project the centroid onto the axis */
    double d[3] = {s->centroid[0] - c[0], s->centroid[1] - c[1], s->centroid[2] - c[2]};
    double t = v3_dot(d, m->a);
    for (int k = 0; k < 3; k++)
        m->c[k] = c[k] + t * m->a[k];
    m->scale = s->diag;
    if (sym->order >= 2) {
        m->variant_count = sym->order - 1;
        for (int k = 1; k < sym->order; k++)
            m->angle[k - 1] = 2 * M_PI * k / sym->order;
    } else {
        m->variant_count = 11;
        for (int k = 1; k <= 11; k++)
            m->angle[k - 1] = 2 * M_PI * k / 12;
    }
}

/* Screens the candidate axes on the screening samples (loose tolerance), refines by
 * ICP on the coarse samples those screening at least 0.6 of the best (best first; the
 * hint's candidate, the last one, always), and returns the best refined - or, with a
 * hint, the one nearest the hint among those scoring 0.8 of the best. */
static void refine_axes(al_ctx *ctx, al_model *cand, int count, al_model *best,
                        al_fit *best_fit)
{
    al_surface *s = ctx->surf;
    double sc[8], top = -1;
    int order[8];
    for (int i = 0; i < count; i++) {
        al_fit f;
        al_evaluate(s, &ctx->screen, &cand[i], 0.02 * s->diag, &f);
        sc[i] = f.score;
        order[i] = i;
        top = f.score > top ? f.score : top;
    }
    for (int i = 0; i < count; i++)
        for (int j = i + 1; j < count; j++)
            if (sc[order[j]] > sc[order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    al_model rm[8];
    al_fit rf[8];
    int nr = 0, ib = 0;
    for (int r = 0; r < count; r++) {
        int i = order[r];
        bool hinted = ctx->have_hint && i == count - 1;
        if (nr > 0 && sc[i] < 0.6 * top && !hinted)
            continue;
        rm[nr] = cand[i];
        al_icp(s, &ctx->coarse, &rm[nr], 25, 0.03 * s->diag, ctx->tol, &rf[nr]);
        if (nr == 0 || al_fit_better(&rf[nr], &rf[ib]))
            ib = nr;
        nr++;
    }
    if (ctx->have_hint) {
        int ih = -1;
        for (int i = 0; i < nr; i++)
            if (rf[i].score >= 0.8 * rf[ib].score &&
                (ih < 0 || fabs(v3_dot(rm[i].a, ctx->hint)) > fabs(v3_dot(rm[ih].a, ctx->hint))))
                ih = i;
        if (ih >= 0)
            ib = ih;
    }
    *best = rm[ib];
    *best_fit = rf[ib];
}

sr_status al_axial_search(al_ctx *ctx, al_model *out, al_fit *fit)
{
    al_surface *s = ctx->surf;
    double cand_a[6][3], cand_c[6][3];
    int nc = 0;
    if (al_axial_normal_lines(s, cand_a[nc], cand_c[nc]))
        nc++;
    double w[3], v[9];
    al_eig_sym(3, s->cov, w, v);
    for (int k = 0; k < 3; k++) {
        double e[3] = {v[k], v[3 + k], v[6 + k]};
        memcpy(cand_a[nc], e, sizeof e);
        memcpy(cand_c[nc], s->centroid, sizeof e);
        nc++;
    }
    if (ctx->have_hint) { /* last, see refine_axes */
        memcpy(cand_a[nc], ctx->hint, sizeof cand_a[nc]);
        memcpy(cand_c[nc], s->centroid, sizeof cand_c[nc]);
        nc++;
    }
    al_model models[6], best;
    al_fit bfit;
    for (int i = 0; i < nc; i++)
        axial_model(s, ctx->sym, cand_a[i], cand_c[i], &models[i]);
    double tau0 = 0.03 * s->diag;
    refine_axes(ctx, models, nc, &best, &bfit);
    if (bfit.score < 0.5) {
        al_paper_result pr;
        if (al_paper_align(s, ctx->sym, ctx->opts, &pr) == SR_OK) {
            al_model m;
            al_fit f;
            axial_model(s, ctx->sym, pr.dir, pr.point, &m);
            al_icp(s, &ctx->coarse, &m, 25, tau0, ctx->tol, &f);
            if (al_fit_better(&f, &bfit)) {
                best = m;
                bfit = f;
            }
        }
    }
    double tau1 = 4 * bfit.median;
    if (!(tau1 < tau0))
        tau1 = tau0;
    if (tau1 < ctx->tol)
        tau1 = ctx->tol;
    al_icp(s, &ctx->fine, &best, 30, tau1, ctx->tol, fit);
    *out = best;
    return SR_OK;
}
