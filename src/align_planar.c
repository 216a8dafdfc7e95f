/*
 * align_planar.c: finding the plane of a mirror- or glide-symmetric scan
 * (align_internal.h).
 *
 * Mirror: the candidates are the three principal planes of the surface's area
 * covariance through its area centroid; each is refined by the symmetry ICP
 * (align_icp.c: reflect the samples, closest points on the scan, robust point-to-plane
 * Gauss-Newton on the normal and offset), which trims the damage because a broken-off
 * piece has no mirror partner. When none fits (score < 0.6), normals spread over a
 * hemisphere (Fibonacci lattice) are tried as well.
 *
 * Glide: reflection in the plane plus a shift s along a direction t in the plane. For
 * every principal plane and both principal directions within it, s is scanned over
 * (0, half the part's length along t] on a small sample set (score with a loose
 * tolerance), then the best (plane, t, s) are refined together by the ICP with both
 * the +s and the -s transform. A glide with shift s is also one with 3s, 5s, ... (its
 * square is a translation by 2s), so the smallest odd fraction of s that fits as well
 * is reported. A given shift (sym->shift_mm > 0) is kept fixed.
 */
#include "align_internal.h"

#include <stdlib.h>
#include <string.h>
#ifdef AL_DEBUG
#include <stdio.h>
#endif

static void plane_model(const al_surface *s, int kind, const double n[3], const double c[3],
                        al_model *m)
{
    memset(m, 0, sizeof *m);
    m->kind = kind;
    memcpy(m->a, n, 3 * sizeof(double));
    v3_normalize(m->a);
    /* the point: centroid projected onto the plane */
    double d = v3_dot(m->a, s->centroid) - v3_dot(m->a, c);
    for (int k = 0; k < 3; k++)
        m->c[k] = s->centroid[k] - d * m->a[k];
    m->scale = s->diag;
    m->variant_count = kind == AL_GLIDE ? 2 : 1;
}

/* Extent of the mesh vertices along unit direction t. */
static double extent_along(const al_surface *s, const double t[3])
{
    const sr_mesh *mesh = s->mesh;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        double x = v3_dot(mesh->xyz + 3 * v, t);
        lo = x < lo ? x : lo;
        hi = x > hi ? x : hi;
    }
    return hi > lo ? hi - lo : 0;
}

/* A plane candidate after refinement. */
typedef struct plane_cand {
    al_model m;
    al_fit f;
    double spread;         /* variance of the surface along the normal, mm^2 */
} plane_cand;

/* Moves the plane of m along its normal to the offset (within +-10 % of the part
 * size) where most screening samples find a mirror partner: the centroid the
 * candidates start from is pulled off the plane by the damage. */
static void scan_offset(al_ctx *ctx, al_model *m)
{
    al_surface *s = ctx->surf;
    double loose = 0.02 * s->diag, step = 0.5 * loose;
    int half = 10;
    double c0[3], best_off = 0, best = -1;
    memcpy(c0, m->c, sizeof c0);
    for (int r = 0; r <= 2 * half; r++) {
        /* 0, +1, -1, +2, -2, ...: ties keep the offset nearest the centroid */
        int i = (r + 1) / 2 * (r % 2 ? 1 : -1);
        al_model t = *m;
        for (int k = 0; k < 3; k++)
            t.c[k] = c0[k] + i * step * m->a[k];
        al_fit f;
        al_evaluate(s, &ctx->screen, &t, loose, &f);
        if (f.score > best) {
            best = f.score;
            best_off = i * step;
        }
    }
    for (int k = 0; k < 3; k++)
        m->c[k] = c0[k] + best_off * m->a[k];
}

static double spread_along(const al_surface *s, const double n[3])
{
    double v = 0;
    for (int r = 0; r < 3; r++)
        for (int q = 0; q < 3; q++)
            v += n[r] * s->cov[3 * r + q] * n[q];
    return v;
}

/* The three principal planes, each moved to its best offset and refined as a mirror
 * on the coarse samples. */
static void principal_planes(al_ctx *ctx, plane_cand out[3])
{
    al_surface *s = ctx->surf;
    double w[3], v[9];
    al_eig_sym(3, s->cov, w, v);
    for (int k = 0; k < 3; k++) {
        double n[3] = {v[k], v[3 + k], v[6 + k]};
        plane_model(s, AL_MIRROR, n, s->centroid, &out[k].m);
        scan_offset(ctx, &out[k].m);
        al_icp(s, &ctx->coarse, &out[k].m, 25, 0.03 * s->diag, ctx->tol, &out[k].f);
        out[k].spread = spread_along(s, out[k].m.a);
#ifdef AL_DEBUG
        fprintf(stderr, "plane %d score %.4f rms %.4f spread %.1f n %.4f %.4f %.4f\n", k,
                out[k].f.score, out[k].f.inlier_rms, out[k].spread, out[k].m.a[0],
                out[k].m.a[1], out[k].m.a[2]);
#endif
    }
}

static void finish(al_ctx *ctx, al_model *m, const al_fit *cf, al_fit *fit)
{
    double tau0 = 0.03 * ctx->surf->diag;
    double tau1 = 4 * cf->median;
    if (!(tau1 < tau0))
        tau1 = tau0;
    if (tau1 < ctx->tol)
        tau1 = ctx->tol;
    al_icp(ctx->surf, &ctx->fine, m, 30, tau1, ctx->tol, fit);
}

static sr_status mirror_search(al_ctx *ctx, al_model *out, al_fit *fit)
{
    al_surface *s = ctx->surf;
    plane_cand pc[3];
    principal_planes(ctx, pc);
    double top = 0;
    for (int k = 0; k < 3; k++)
        top = pc[k].f.score > top ? pc[k].f.score : top;
    /* several planes can be mirror planes of most of the part (a bracket's y = 0 as
     * well as its x = 0, a plate's mid-plane): among the good ones take the plane
     * across which the part spreads widest, the one whose halves say most about each
     * other */
    int pick = -1;
    for (int k = 0; k < 3; k++) {
        bool good = pc[k].f.score >= 0.5 && pc[k].f.score >= top - 0.25;
        if (good && (pick < 0 || pc[k].spread > pc[pick].spread))
            pick = k;
    }
    al_model best;
    al_fit bfit;
    if (pick >= 0) {
        best = pc[pick].m;
        bfit = pc[pick].f;
    } else {
        /* no principal plane fits: normals spread over a hemisphere (Fibonacci) */
        enum { NDIR = 64 };
        al_model cand[NDIR];
        double golden = M_PI * (3 - sqrt(5.0));
        for (int i = 0; i < NDIR; i++) {
            double z = 1 - (i + 0.5) / NDIR;
            double r = sqrt(1 - z * z), ph = golden * i;
            double n[3] = {r * cos(ph), r * sin(ph), z};
            plane_model(s, AL_MIRROR, n, s->centroid, &cand[i]);
        }
        al_refine_candidates(s, &ctx->screen, &ctx->coarse, cand, NDIR, 0.02 * s->diag,
                             0.03 * s->diag, ctx->tol, &best, &bfit);
        int k = 0;
        for (int j = 1; j < 3; j++)
            if (al_fit_better(&pc[j].f, &pc[k].f))
                k = j;
        if (al_fit_better(&pc[k].f, &bfit)) {
            best = pc[k].m;
            bfit = pc[k].f;
        }
    }
    finish(ctx, &best, &bfit, fit);
    *out = best;
    return SR_OK;
}

/* Share of the samples (p, n) whose glide image lies within tol of the surface with a
 * compatible normal (the image of the normal within 60 deg of the surface's). Samples
 * alternate between the +shift and the -shift transform. */
static double glide_score(al_surface *s, const double *p, const double *n, size_t count,
                          const al_model *m, double tol)
{
    double mat[2][12];
    al_model_matrix(m, NULL, 0, mat[0]);
    al_model_matrix(m, NULL, 1, mat[1]);
    size_t in = 0;
    for (size_t i = 0; i < count; i++) {
        const double *M = mat[i & 1], *pi = p + 3 * i, *ni = n + 3 * i;
        double x[3], nx[3], q[3], nq[3], d;
        for (int r = 0; r < 3; r++) {
            x[r] = M[4 * r] * pi[0] + M[4 * r + 1] * pi[1] + M[4 * r + 2] * pi[2] + M[4 * r + 3];
            nx[r] = M[4 * r] * ni[0] + M[4 * r + 1] * ni[1] + M[4 * r + 2] * ni[2];
        }
        if (al_surface_closest(s, x, tol, q, nq, &d) && v3_dot(nx, nq) > 0.5)
            in++;
    }
    return count ? (double)in / (double)count : 0;
}

/* Scans the shift of glide model m (plane and t set) over (0, smax] on the coarse
 * samples whose faces look along t (only they can tell one shift from another; a
 * prismatic surface along t matches any shift), leaving the best in m->shift. */
static sr_status scan_shift(al_ctx *ctx, al_model *m, double smax)
{
    const al_samples *c = &ctx->coarse;
    double *p = malloc((c->count ? c->count : 1) * 6 * sizeof *p);
    if (!p)
        return SR_E_NOMEM;
    double *n = p + 3 * c->count;
    size_t cnt = 0;
    for (size_t i = 0; i < c->count; i++) {
        if (fabs(v3_dot(c->n + 3 * i, m->t)) > 0.5) {
            memcpy(p + 3 * cnt, c->p + 3 * i, 3 * sizeof *p);
            memcpy(n + 3 * cnt, c->n + 3 * i, 3 * sizeof *n);
            cnt++;
        }
    }
    if (cnt < 30) { /* nothing faces along t: use every sample */
        memcpy(p, c->p, c->count * 3 * sizeof *p);
        memcpy(n, c->n, c->count * 3 * sizeof *n);
        cnt = c->count;
    }
    double tol = ctx->tol, step = tol / 2;
    int nstep = (int)(smax / step);
    if (nstep > 400) {
        nstep = 400;
        step = smax / nstep;
    }
    double best_s = step, best = -1;
    for (int i = 1; i <= nstep; i++) {
        m->shift = i * step;
        double sc = glide_score(ctx->surf, p, n, cnt, m, tol);
        if (sc > best) {
            best = sc;
            best_s = m->shift;
        }
    }
    m->shift = best_s;
    free(p);
    return SR_OK;
}

static sr_status glide_search(al_ctx *ctx, al_model *out, al_fit *fit)
{
    al_surface *s = ctx->surf;
    plane_cand pc[3];
    principal_planes(ctx, pc);
    double top = 0;
    for (int k = 0; k < 3; k++)
        top = pc[k].f.score > top ? pc[k].f.score : top;
    double w[3], v[9];
    al_eig_sym(3, s->cov, w, v);
    bool given = ctx->sym->shift_mm > 0;
    al_model best = {0};
    al_fit bfit = {0};
    bool have = false;
    for (int k = 0; k < 3; k++) {
        if (pc[k].f.score < 0.5 * top)
            continue;
        /* in-plane directions: the two principal directions least along the normal */
        for (int j = 0; j < 3; j++) {
            double e[3] = {v[j], v[3 + j], v[6 + j]};
            double dn = v3_dot(e, pc[k].m.a);
            if (fabs(dn) > 0.7)
                continue;
            for (int q = 0; q < 3; q++)
                e[q] -= dn * pc[k].m.a[q];
            v3_normalize(e);
            al_model m = pc[k].m;
            m.kind = AL_GLIDE;
            m.variant_count = 2;
            memcpy(m.t, e, sizeof e);
            if (given) {
                m.shift = ctx->sym->shift_mm;
                m.fix_shift = 1;
            } else {
                double smax = 0.5 * extent_along(s, e);
                if (smax > 0.5 * s->diag)
                    smax = 0.5 * s->diag;
                if (scan_shift(ctx, &m, smax) != SR_OK)
                    return SR_E_NOMEM;
            }
            al_fit f;
#ifdef AL_DEBUG
            fprintf(stderr, "glide plane %d dir %d shift %g\n", k, j, m.shift);
#endif
            al_icp(s, &ctx->coarse, &m, 25, 0.03 * s->diag, ctx->tol, &f);
#ifdef AL_DEBUG
            fprintf(stderr, "  -> shift %g score %g rms %g\n", m.shift, f.score, f.inlier_rms);
#endif
            if (!have || al_fit_better(&f, &bfit)) {
                best = m;
                bfit = f;
                have = true;
            }
        }
    }
    if (!have)
        return SR_E_INTERNAL;
    if (best.shift < 0) {
        best.shift = -best.shift;
        for (int k = 0; k < 3; k++)
            best.t[k] = -best.t[k];
    }
    if (!given) {
        /* a glide by s is also one by 3s, 5s, ...: the smallest odd fraction that fits
         * as well */
        for (int q = 9; q >= 3; q -= 2) {
            al_model m = best;
            m.shift = best.shift / q;
            if (m.shift < ctx->tol)
                continue;
            al_fit f;
            al_icp(s, &ctx->coarse, &m, 25, 0.03 * s->diag, ctx->tol, &f);
            if (f.score >= bfit.score - 0.02) {
                best = m;
                bfit = f;
                break;
            }
        }
    }
    finish(ctx, &best, &bfit, fit);
    if (best.shift < 0) {
        best.shift = -best.shift;
        for (int k = 0; k < 3; k++)
            best.t[k] = -best.t[k];
    }
    *out = best;
    return SR_OK;
}

sr_status al_planar_search(al_ctx *ctx, al_model *out, al_fit *fit)
{
    if (ctx->sym->kind == SR_SYM_GLIDE)
        return glide_search(ctx, out, fit);
    return mirror_search(ctx, out, fit);
}
