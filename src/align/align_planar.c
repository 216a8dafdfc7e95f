/*
 * align_planar.c: finding the plane of a mirror- or glide-symmetric scan
 * (align_internal.h).
 *
 * Plane candidates: the three principal planes of the surface's area covariance and
 * the directions about which the normals are reflection-symmetric (align_egi.c; the
 * principal axes miss a mirror plane when damage tilts them), all through the area
 * centroid. Each is moved along its normal to the offset where most samples find a
 * mirror partner (damage pulls the centroid off the plane), given a few ICP steps on
 * the screening samples and scored with a loose tolerance; those scoring 0.8 of the
 * best are refined by the symmetry ICP (align_icp.c: reflect the samples, closest
 * points on the scan, robust point-to-plane Gauss-Newton on the normal and offset),
 * which trims the damage because a broken-off piece has no mirror partner.
 *
 * Mirror: several planes can be mirror planes of most of the part (a bracket is
 * symmetric about x = 0 and y = 0, a plate about its mid-plane, a U clamp about its
 * half-length). Among the refined planes scoring at least 0.8 of the best, the one
 * across which the matched share of the part spreads widest (the variance of the
 * surface along the normal times the share of samples matched) is taken: the plane
 * whose two halves say most about each other; this is a heuristic, and the caller's hint (opts->hint) overrides it - the hint joins the
 * candidates and the good plane nearest it is taken.
 *
 * Glide: reflection in the plane plus a shift s along a direction t in the plane. For
 * the good planes (within 30 deg of the hint, if given) and the principal directions
 * within them, s is scanned from 4 tol (smaller shifts are a mirror) to half the part's
 * length along t in tol / 2 steps, scored on the samples whose faces look along t (only
 * they tell one shift from another) with the normals required to match; the best
 * (plane, t, s) are refined together by the ICP with both the +s and the -s transform,
 * starting at a small cut-off so the part's ends (which the shift moves off the part)
 * cannot pull the shift. A glide by s is also one by 3s, 5s, ... (its square is a
 * translation by 2s), so the smallest odd fraction of s that matches the facing samples
 * about as well is reported. A given shift (sym->shift_mm > 0) is kept fixed.
 */
#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>

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

#define MAX_PLANES 10 /* 3 principal + 6 EGI + the hint */

/* A plane candidate after refinement. */
typedef struct plane_cand {
    al_model m;
    al_fit f;
    double spread;         /* variance of the surface along the normal, mm^2 */
} plane_cand;

/* Moves the plane of m along its normal to the offset (within +-10 % of the part
 * size) where most screening samples find a mirror partner: the centroid the
 * candidates start from is pulled off the plane by the damage. */
static double scan_offset(al_ctx *ctx, al_model *m)
{
    al_surface *s = ctx->surf;
    double loose = 0.02 * s->diag, step = loose;
    int half = 5;
    double c0[3], best_off = 0, best = -1;
    memcpy(c0, m->c, sizeof c0);
    for (int r = 0; r <= 2 * half; r++) {
        /* 0, +1, -1, +2, -2, ...: ties keep the offset nearest the centroid */
        int i = (r + 1) / 2 * (r % 2 ? 1 : -1);
        al_model t = *m;
        for (int k = 0; k < 3; k++)
            t.c[k] = c0[k] + i * step * m->a[k];
        al_fit f;
        al_evaluate(s, &ctx->probe, &t, loose, &f);
        if (f.score > best) {
            best = f.score;
            best_off = i * step;
        }
    }
    for (int k = 0; k < 3; k++)
        m->c[k] = c0[k] + best_off * m->a[k];
    return best;
}

static double spread_along(const al_surface *s, const double n[3])
{
    double v = 0;
    for (int r = 0; r < 3; r++)
        for (int q = 0; q < 3; q++)
            v += n[r] * s->cov[3 * r + q] * n[q];
    return v;
}

/* The symmetry ICP slides: a part's large flat faces across the plane (a lever's web)
 * reflect onto themselves whatever the plane's tilt about their normal, so once damage
 * has taken away what pinned the tilt (the walls of one boss), the fit can settle a
 * degree or two off, on a plane that matches fewer samples exactly. The refined plane
 * is restarted tilted by POLISH_DEG and twice that about two directions in it, both
 * ways, pivoting about its point and about points 1.5 standard deviations of the
 * surface either way along the tilt (where half a boss has gone, what is left pivots
 * about the other boss, whose round walls fit any plane through its axis: tilted about
 * the centre, every start was as far off at one boss or the other, and a generated
 * lever's fit stayed 1.4 deg off), each start fitted on the screening samples; the
 * best start that matches more
 * of them than the plane does is refined on the coarse samples and replaces the plane
 * if it matches more there too (al_fit_better); at most POLISH_ROUNDS rounds. */
#define POLISH_DEG 1.5
#define POLISH_ROUNDS 2
static void polish_plane(al_ctx *ctx, double tau, plane_cand *pc)
{
    al_surface *s = ctx->surf;
    for (int round = 0; round < POLISH_ROUNDS; round++) {
        double u[3], w[3], ref[3] = {1, 0, 0};
        if (fabs(pc->m.a[0]) > 0.8)
            ref[0] = 0, ref[1] = 1;
        v3_cross(pc->m.a, ref, u);
        v3_normalize(u);
        v3_cross(pc->m.a, u, w);
        al_fit here;
        al_evaluate(s, &ctx->screen, &pc->m, ctx->tol, &here);
        al_model best = pc->m;
        al_fit best_f = here;
        for (int k = 0; k < 24; k++) {
            double deg = (k % 8 < 4 ? 1 : 2) * POLISH_DEG * M_PI / 180;
            const double *d = (k % 2) ? w : u;
            double sg = (k % 4) < 2 ? 1 : -1;
            double arm = (k / 8 == 0 ? 0 : k / 8 == 1 ? 1 : -1) * 1.5 * sqrt(spread_along(s, d));
            double n[3], piv[3];
            for (int q = 0; q < 3; q++) {
                n[q] = cos(deg) * pc->m.a[q] + sg * sin(deg) * d[q];
                piv[q] = pc->m.c[q] + arm * d[q];
            }
            al_model t;
            al_fit tf;
            plane_model(s, AL_MIRROR, n, piv, &t);
            al_icp(s, &ctx->screen, &t, 15, tau, ctx->tol, &tf);
            if (al_fit_better(&tf, &best_f)) {
                best = t;
                best_f = tf;
            }
        }
        if (!al_fit_better(&best_f, &here))
            break;
        plane_cand t = *pc;
        t.m = best;
        al_icp(s, &ctx->coarse, &t.m, 25, tau, ctx->tol, &t.f);
        if (!al_fit_better(&t.f, &pc->f))
            break;
        *pc = t;
    }
}

/* Plane candidates: the three principal planes of the area covariance, the
 * reflection-symmetric directions of the normals (align_egi.c) and the hint, each
 * moved to its best offset and screened; those screening at least 0.8 of the best
 * (and the hint's) are refined as mirrors on the coarse samples (a plane is only
 * chosen when it scores 0.8 of the best); polish: a mirror search, each restarted
 * tilted (polish_plane). Returns the number of refined candidates
 * written to out (<= MAX_PLANES). */
static int plane_candidates(al_ctx *ctx, double keep, bool polish, plane_cand *out)
{
    al_surface *s = ctx->surf;
    double w[3], v[9];
    al_eig_sym(3, s->cov, w, v);
    double normals[MAX_PLANES][3];
    int nn = 0;
    for (int k = 0; k < 3; k++) {
        normals[nn][0] = v[k];
        normals[nn][1] = v[3 + k];
        normals[nn][2] = v[6 + k];
        nn++;
    }
    double egi[6][3];
    int ne = al_egi_mirror_normals(s, egi, 6);
    for (int i = 0; i < ne; i++) {
        bool near = false;
        for (int j = 0; j < nn; j++)
            near = near || fabs(v3_dot(egi[i], normals[j])) > cos(10 * M_PI / 180);
        if (!near)
            memcpy(normals[nn++], egi[i], sizeof egi[i]);
    }
    int hinted = -1;
    if (ctx->have_hint) {
        hinted = nn;
        memcpy(normals[nn++], ctx->hint, sizeof normals[0]);
    }
    al_model m[MAX_PLANES];
    double sc[MAX_PLANES], med[MAX_PLANES], top = 0;
    int order[MAX_PLANES];
    for (int i = 0; i < nn; i++) {
        /* screening: best offset, a few ICP steps on the screening samples (a normal a
         * few degrees off, as damage tilts the principal axes, misses the loose
         * tolerance far from the plane), then the loose score */
        plane_model(s, AL_MIRROR, normals[i], s->centroid, &m[i]);
        scan_offset(ctx, &m[i]);
        al_fit f;
        al_icp(s, &ctx->screen, &m[i], 5, 0.03 * s->diag, 0.02 * s->diag, &f);
        sc[i] = f.score;
        med[i] = f.median;
        top = sc[i] > top ? sc[i] : top;
        order[i] = i;
    }
    for (int i = 0; i < nn; i++)
        for (int j = i + 1; j < nn; j++)
            if (sc[order[j]] > sc[order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    int count = 0;
    for (int r = 0; r < nn; r++) {
        int i = order[r];
        if (count > 0 && sc[i] < keep * top && i != hinted)
            continue;
        plane_cand *pc = &out[count++];
        pc->m = m[i];
        /* start from the screening fit's scale: large radii cost much on dense scans */
        double tau = 4 * med[i];
        tau = tau < ctx->tol ? ctx->tol : (tau < 0.03 * s->diag ? tau : 0.03 * s->diag);
        al_icp(s, &ctx->coarse, &pc->m, 25, tau, ctx->tol, &pc->f);
        if (polish)
            polish_plane(ctx, tau, pc);
        pc->spread = spread_along(s, pc->m.a);
    }
    return count;
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
    plane_cand pc[MAX_PLANES];
    int np = plane_candidates(ctx, 0.8, true, pc);
    double top = 0;
    for (int k = 0; k < np; k++)
        top = pc[k].f.score > top ? pc[k].f.score : top;
    /* several planes can be mirror planes of most of the part (a bracket's y = 0 as
     * well as its x = 0, a plate's mid-plane): among the good ones take the plane
     * across which the part's matched share spreads widest (the spread weighted by
     * the share matched), the one whose halves say most about each other (with a
     * hint: the one nearest the hint); when none is good, the best. The spread alone
     * took a U clamp's false plane across its height (matched 0.825, spread 263 mm2)
     * over its true one (0.965, 246 mm2): 3.3 cm3 of its bolt hole filled */
    int pick = -1;
    for (int k = 0; k < np; k++) {
        bool good = pc[k].f.score >= 0.5 && pc[k].f.score >= 0.8 * top;
        if (!good)
            continue;
        if (pick < 0)
            pick = k;
        else if (ctx->have_hint ? fabs(v3_dot(pc[k].m.a, ctx->hint)) >
                                      fabs(v3_dot(pc[pick].m.a, ctx->hint))
                                : pc[k].f.score * pc[k].spread >
                                      pc[pick].f.score * pc[pick].spread)
            pick = k;
    }
    if (pick < 0) {
        pick = 0;
        for (int k = 1; k < np; k++)
            if (al_fit_better(&pc[k].f, &pc[pick].f))
                pick = k;
    }
    al_model best = pc[pick].m;
    finish(ctx, &best, &pc[pick].f, fit);
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
#pragma omp parallel for num_threads(s->threads) schedule(static) reduction(+ : in) \
    if (count >= AL_PARALLEL_MIN)
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

/* The coarse samples whose faces look along t (|n.t| > 0.5): only they can tell one
 * shift along t from another, since a prismatic surface along t matches any shift.
 * All samples when fewer than 30 do; at most FACING_MAX (evenly thinned). */
#define FACING_MAX 400

typedef struct facing {
    double *p, *n;
    size_t count;
} facing;

static sr_status facing_samples(const al_samples *c, const double t[3], facing *out)
{
    out->p = malloc((c->count ? c->count : 1) * 6 * sizeof *out->p);
    if (!out->p)
        return SR_E_NOMEM;
    out->n = out->p + 3 * c->count;
    size_t cnt = 0;
    for (size_t i = 0; i < c->count; i++) {
        if (fabs(v3_dot(c->n + 3 * i, t)) > 0.5) {
            memcpy(out->p + 3 * cnt, c->p + 3 * i, 3 * sizeof *out->p);
            memcpy(out->n + 3 * cnt, c->n + 3 * i, 3 * sizeof *out->n);
            cnt++;
        }
    }
    if (cnt < 30) {
        memcpy(out->p, c->p, c->count * 3 * sizeof *out->p);
        memcpy(out->n, c->n, c->count * 3 * sizeof *out->n);
        cnt = c->count;
    }
    if (cnt > FACING_MAX) { /* every k-th: enough to tell shifts apart, and cheap */
        size_t stride = (cnt + FACING_MAX - 1) / FACING_MAX, k = 0;
        for (size_t i = 0; i < cnt; i += stride, k++) {
            memmove(out->p + 3 * k, out->p + 3 * i, 3 * sizeof *out->p);
            memmove(out->n + 3 * k, out->n + 3 * i, 3 * sizeof *out->n);
        }
        cnt = k;
    }
    out->count = cnt;
    return SR_OK;
}

/* Scans the shift of glide model m (plane and t set) over [4 tol, smax] on the facing
 * samples, leaving the best in m->shift. Shifts below 4 tol are not a glide but a
 * mirror (a face across t, such as the end of a rail, matches itself under any shift
 * smaller than the tolerance). */
#define SHIFT_STEPS 400 /* the most shifts a scan tries */
static double scan_shift(al_ctx *ctx, al_model *m, const facing *fc, double smax)
{
    double tol = ctx->tol, step = tol / 2, s0 = 4 * tol;
    int nstep = smax > s0 ? (int)((smax - s0) / step) : 0;
    if (nstep > SHIFT_STEPS) {
        nstep = SHIFT_STEPS;
        step = (smax - s0) / nstep;
    }
    double sc[SHIFT_STEPS + 1];
    for (int i = 0; i <= nstep; i++) {
        m->shift = s0 + i * step;
        sc[i] = glide_score(ctx->surf, fc->p, fc->n, fc->count, m, tol);
    }
    /* the best peak inside the range: a score falling away from s0 is the tail of the
     * mirror's own match at shift 0 (a noisy perforated strip's scan peaked there,
     * 0.11, over its glide's 0.095 at 6.3 mm, and slid back to a mirror: +217 %) */
    int bi = -1, gi = 0;
    for (int i = 0; i <= nstep; i++) {
        if (sc[i] > sc[gi])
            gi = i;
        if (i > 0 && i < nstep && sc[i] >= sc[i - 1] && sc[i] >= sc[i + 1] &&
            (bi < 0 || sc[i] > sc[bi]))
            bi = i;
    }
    if (bi < 0)
        bi = gi;
    m->shift = s0 + bi * step;
    return sc[bi];
}

static sr_status glide_search(al_ctx *ctx, al_model *out, al_fit *fit)
{
    al_surface *s = ctx->surf;
    plane_cand pc[MAX_PLANES];
    /* a glide's plane is a poor mirror: its mirror fit is not polished (the glide
     * refinement below fits it with the shift) */
    int np = plane_candidates(ctx, 0.4, false, pc);
    double top = 0;
    for (int k = 0; k < np; k++)
        top = pc[k].f.score > top ? pc[k].f.score : top;
    double w[3], v[9];
    al_eig_sym(3, s->cov, w, v);
    bool given = ctx->sym->shift_mm > 0;
    double smin = 4 * ctx->tol;
    /* (plane, direction) combinations with their shift scanned on the facing samples;
     * the planes must be fair mirrors of the bulk of the part */
    al_model combo[3 * MAX_PLANES];
    int ncombo = 0;
    bool near_hint = false; /* with a hint: only planes within 30 deg of it */
    for (int k = 0; k < np && ctx->have_hint; k++)
        near_hint = near_hint || fabs(v3_dot(pc[k].m.a, ctx->hint)) >= cos(M_PI / 6);
    for (int k = 0; k < np; k++) {
        /* a glide's plane is a poor mirror (its features are offset by the shift), so
         * it may score well below another plane's mirror that the pattern nearly has
         * (a rack's top-bottom plane, with a pitch as the shift: fit score 0.44 where
         * the true glide scores over 0.9): every plane candidate that is a fair mirror
         * of half the best is tried */
        if (near_hint ? fabs(v3_dot(pc[k].m.a, ctx->hint)) < cos(M_PI / 6)
                      : pc[k].f.score < 0.5 * top)
            continue;
        /* in-plane directions: the principal directions not along the normal */
        for (int j = 0; j < 3; j++) {
            double e[3] = {v[j], v[3 + j], v[6 + j]};
            double dn = v3_dot(e, pc[k].m.a);
            if (fabs(dn) > 0.7)
                continue;
            for (int q = 0; q < 3; q++)
                e[q] -= dn * pc[k].m.a[q];
            v3_normalize(e);
            al_model *m = &combo[ncombo];
            *m = pc[k].m;
            m->kind = AL_GLIDE;
            m->variant_count = 2;
            memcpy(m->t, e, sizeof e);
            if (given) {
                m->shift = ctx->sym->shift_mm;
                m->fix_shift = 1;
            } else {
                double smax = 0.5 * extent_along(s, e);
                if (smax > 0.5 * s->diag)
                    smax = 0.5 * s->diag;
                facing fc;
                if (facing_samples(&ctx->coarse, e, &fc) != SR_OK)
                    return SR_E_NOMEM;
                scan_shift(ctx, m, &fc, smax);
                free(fc.p);
            }
            ncombo++;
        }
    }
    al_model best = {0};
    al_fit bfit = {0};
    bool have = false;
    /* every pair is refined before they are compared: its scanned score is taken on a
     * plane not yet polished, and along a long part a plane a degree off moves the
     * faces at its ends by more than tol (a generated ratchet bar's true glide scanned
     * 0.24 beside 0.71 for a near mirror shifted by a whole pitch, and was dropped
     * before its refinement would have scored 0.83: +118 %) */
    for (int i = 0; i < ncombo; i++) {
        al_model m = combo[i];
        al_fit f;
        /* the plane is refined and the shift scanned to tol / 4: start at 2 tol, so
         * the part's ends (which the shift moves off the part) cannot pull the shift,
         * which only the faces across t see */
        al_icp(s, &ctx->coarse, &m, 25, 2 * ctx->tol, ctx->tol, &f);
        if (!given && fabs(m.shift) < smin)
            continue; /* slid back to a mirror */
        if (!have || al_fit_better(&f, &bfit)) {
            best = m;
            bfit = f;
            have = true;
        }
    }
    if (!have) {
        /* no glide at all: report the best plane as a glide with the smallest shift */
        best = pc[0].m;
        best.kind = AL_GLIDE;
        best.variant_count = 2;
        al_perp_frame(best.a, best.t, w);
        best.shift = given ? ctx->sym->shift_mm : smin;
        best.fix_shift = 1;
        bfit = pc[0].f;
    }
    if (best.shift < 0) {
        best.shift = -best.shift;
        for (int k = 0; k < 3; k++)
            best.t[k] = -best.t[k];
    }
    if (!given && have) {
        /* a glide by s is also one by 3s, 5s, ...: take the smallest odd fraction of s
         * that matches the faces along t about as well (90 %) */
        facing fc;
        if (facing_samples(&ctx->coarse, best.t, &fc) != SR_OK)
            return SR_E_NOMEM;
        double ref = glide_score(s, fc.p, fc.n, fc.count, &best, ctx->tol);
        for (int q = 9; q >= 3; q -= 2) {
            al_model m = best;
            m.shift = best.shift / q;
            if (m.shift < smin)
                continue;
            if (glide_score(s, fc.p, fc.n, fc.count, &m, ctx->tol) >= 0.9 * ref) {
                al_fit f;
                al_icp(s, &ctx->coarse, &m, 25, ctx->tol, ctx->tol, &f);
                best = m;
                bfit = f;
                break;
            }
        }
        free(fc.p);
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
