/*
 * register.c: rigid registration of one mesh to another, robust to damage and extra
 * stock (register.h says the method). Uses the alignment's surface machinery
 * (align_surface.c: closest points on a grid, area-uniform samples, principal axes).
 */
#include "align/register.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "align/align_internal.h"

#define TUKEY 4.685
#define MAD_SCALE 1.4826

/* A pose: x' = R x + t. */
typedef struct pose {
    double r[9], t[3];
} pose;

static void pose_apply(const pose *p, const double x[3], double y[3])
{
    for (int i = 0; i < 3; i++)
        y[i] = p->r[3 * i] * x[0] + p->r[3 * i + 1] * x[1] + p->r[3 * i + 2] * x[2] + p->t[i];
}

static void mat3_mul(const double a[9], const double b[9], double c[9])
{
    double m[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
    memcpy(c, m, sizeof m);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The score of a pose: samples within tol, then their squared distances. */
typedef struct score {
    size_t inliers;
    double sum2;
    double median;
} score;

/* Distances of every sample under pose p (capped at cap: farther = cap). */
static void distances(al_surface *fixed, const al_samples *smp, const pose *p, double cap,
                      double *d)
{
    for (size_t i = 0; i < smp->count; i++) {
        double x[3], q[3], n[3], dist;
        pose_apply(p, smp->p + 3 * i, x);
        d[i] = al_surface_closest(fixed, x, cap, q, n, &dist) ? dist : cap;
    }
}

static score score_of(al_surface *fixed, const al_samples *smp, const pose *p, double tol,
                      double *scratch)
{
    score s = {0, 0, 0};
    distances(fixed, smp, p, 4 * tol + 1e-9, scratch);
    for (size_t i = 0; i < smp->count; i++)
        if (scratch[i] <= tol) {
            s.inliers++;
            s.sum2 += scratch[i] * scratch[i];
        }
    qsort(scratch, smp->count, sizeof *scratch, cmp_double);
    s.median = smp->count ? scratch[smp->count / 2] : 0;
    return s;
}

static bool score_better(const score *a, const score *b)
{
    if (a->inliers != b->inliers)
        return a->inliers > b->inliers;
    return a->sum2 < b->sum2;
}

/* Robust point-to-plane ICP from *p: iters steps, the Tukey cut-off annealed from c0
 * towards 4.685 x the robust scale of the distances (never below floor). */
static void icp_run(al_surface *fixed, const al_samples *smp, pose *p, int iters, double c0,
                    double *cut, double floor, double size, double *scratch);

static void icp(al_surface *fixed, const al_samples *smp, pose *p, int iters, double c0,
                double floor, double size, double *scratch)
{
    double c = c0;
    icp_run(fixed, smp, p, iters, c0, &c, floor, size, scratch);
}

/* icp from the cut-off *cut (capped at c0), which it leaves at the next step's. After
 * the run, scratch holds the last step's distances, sorted (capped at its cut-off). */
static void icp_run(al_surface *fixed, const al_samples *smp, pose *p, int iters, double c0,
                    double *cut, double floor, double size, double *scratch)
{
    double c = *cut;
    for (int it = 0; it < iters; it++) {
        double a[36] = {0}, b[6] = {0}, cen[3] = {0, 0, 0};
        size_t used = 0, found = 0;
        /* the samples' centre under the pose (the rotation's pivot) */
        for (size_t i = 0; i < smp->count; i++) {
            double x[3];
            pose_apply(p, smp->p + 3 * i, x);
            for (int k = 0; k < 3; k++)
                cen[k] += x[k];
        }
        for (int k = 0; k < 3 && smp->count; k++)
            cen[k] /= (double)smp->count;
        for (size_t i = 0; i < smp->count; i++) {
            double x[3], q[3], n[3], dist;
            pose_apply(p, smp->p + 3 * i, x);
            if (!al_surface_closest(fixed, x, c, q, n, &dist)) {
                scratch[found++] = c;
                continue;
            }
            scratch[found++] = dist;
            double u = dist / c, w = (1 - u * u) * (1 - u * u);
            if (!(w > 0))
                continue;
            double r = n[0] * (x[0] - q[0]) + n[1] * (x[1] - q[1]) + n[2] * (x[2] - q[2]);
            double y[3] = {x[0] - cen[0], x[1] - cen[1], x[2] - cen[2]}, J[6];
            v3_cross(y, n, J);
            J[3] = n[0], J[4] = n[1], J[5] = n[2];
            for (int j = 0; j < 6; j++) {
                b[j] -= w * J[j] * r;
                for (int k = 0; k < 6; k++)
                    a[6 * j + k] += w * J[j] * J[k];
            }
            used++;
        }
        /* the next cut-off: the robust scale of this step's distances */
        qsort(scratch, found, sizeof *scratch, cmp_double);
        double med = found ? scratch[found / 2] : c;
        double next = TUKEY * MAD_SCALE * med;
        if (next < c / 2)
            next = c / 2;
        if (next < floor)
            next = floor;
        if (used < 6) {
            c = fmin(2 * c, c0);
            continue;
        }
        /* damped: rotations about a symmetry axis are free (singular) */
        double trace = 0;
        for (int j = 0; j < 6; j++)
            trace += a[7 * j];
        for (int j = 0; j < 6; j++)
            a[7 * j] += 1e-9 * trace + 1e-12;
        double d[6];
        if (!al_solve_spd(6, a, b, d))
            break;
        /* no sample moves by more than half the cut-off */
        double rot = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double move = rot * size + sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
        if (move > c / 2) {
            double f = c / 2 / move;
            for (int j = 0; j < 6; j++)
                d[j] *= f;
            rot *= f;
        }
        double rr[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        if (rot > 0) {
            double k[3] = {d[0] / rot, d[1] / rot, d[2] / rot};
            al_rot_axis(k, rot, rr);
        }
        /* x' = Rr (x - cen) + cen + d[3..5], with x = R p + t */
        double tc[3] = {p->t[0] - cen[0], p->t[1] - cen[1], p->t[2] - cen[2]}, nt[3];
        for (int i = 0; i < 3; i++)
            nt[i] = rr[3 * i] * tc[0] + rr[3 * i + 1] * tc[1] + rr[3 * i + 2] * tc[2] + cen[i] +
                    d[3 + i];
        mat3_mul(rr, p->r, p->r);
        memcpy(p->t, nt, sizeof nt);
        c = next;
        if (move < 1e-7 * size && it > 2)
            break;
    }
    *cut = c;
}

/* The principal frame of a surface: columns = eigenvectors, ascending. */
static void principal(const al_surface *s, double e[9], double w[3])
{
    al_eig_sym(3, s->cov, w, e);
}

static double det3(const double m[9])
{
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
           m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/* The start poses: the identity, then E_F S E_M^T for the proper sign choices S, each
 * turned about the fixed principal axes in `turns` steps a turn. The turns of the c-th
 * sign choice are offset by a golden-ratio share of a step, so that the starts about
 * an axis do not all fall at one phase of a part's n-fold pattern (with 45 degree
 * steps, every start of a 16-tooth spline would sit at the same place between two
 * teeth, where the ICP cannot tell which way to go). Returns the count. */
static size_t starts(const al_surface *fix, const al_surface *mov, int turns, pose *out, size_t cap)
{
    double ef[9], em[9], wf[3], wm[3];
    principal(fix, ef, wf);
    principal(mov, em, wm);
    double want = det3(ef) * det3(em) > 0 ? 1 : -1;
    size_t n = 0;
    pose id = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
    out[n++] = id;
    int choice = 0;
    for (int sgn = 0; sgn < 8; sgn++) {
        double s[3] = {sgn & 1 ? -1 : 1, sgn & 2 ? -1 : 1, sgn & 4 ? -1 : 1};
        if (s[0] * s[1] * s[2] != want)
            continue;
        double golden = 0.6180339887498949 * choice++;
        double offset = golden - floor(golden); /* of a step */
        /* R0 = EF diag(s) EM^T */
        double r0[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double v = 0;
                for (int k = 0; k < 3; k++)
                    v += ef[3 * i + k] * s[k] * em[3 * j + k];
                r0[3 * i + j] = v;
            }
        for (int axis = 0; axis < 3; axis++)
            for (int step = axis ? 1 : 0; step < turns && n < cap; step++) {
                double k[3] = {ef[axis], ef[3 + axis], ef[6 + axis]}, rr[9];
                al_rot_axis(k, (step + (step ? offset : 0)) * (2 * M_PI / turns), rr);
                pose p = {{0}, {0}};
                mat3_mul(rr, r0, p.r);
                double c[3];
                for (int i = 0; i < 3; i++)
                    c[i] = p.r[3 * i] * mov->centroid[0] + p.r[3 * i + 1] * mov->centroid[1] +
                           p.r[3 * i + 2] * mov->centroid[2];
                for (int i = 0; i < 3; i++)
                    p.t[i] = fix->centroid[i] - c[i];
                out[n++] = p;
            }
    }
    return n;
}

typedef struct reg_ctx {
    al_surface fix, mov;
    al_samples coarse, medium, fine;
    double *scratch;
} reg_ctx;

static void ctx_release(reg_ctx *c)
{
    al_surface_release(&c->fix);
    al_surface_release(&c->mov);
    al_samples_release(&c->coarse);
    al_samples_release(&c->medium);
    al_samples_release(&c->fine);
    free(c->scratch);
}

static sr_status ctx_make(reg_ctx *c, const sr_mesh *moving, const sr_mesh *fixed,
                          size_t fine_count, sr_err *err)
{
    memset(c, 0, sizeof *c);
    sr_status st = sr_mesh_validate(moving, "moving mesh", NULL, err);
    if (st == SR_OK)
        st = sr_mesh_validate(fixed, "fixed mesh", NULL, err);
    if (st == SR_OK)
        st = al_surface_build(&c->fix, fixed, err);
    if (st == SR_OK)
        st = al_surface_build(&c->mov, moving, err);
    if (st == SR_OK && (al_samples_make(&c->mov, 256, 11, &c->coarse) != SR_OK ||
                        al_samples_make(&c->mov, 1024, 12, &c->medium) != SR_OK ||
                        al_samples_make(&c->mov, fine_count, 13, &c->fine) != SR_OK ||
                        !(c->scratch = malloc(fine_count * sizeof *c->scratch))))
        st = sr_err_set(err, SR_E_NOMEM, "out of memory registering meshes");
    if (st != SR_OK)
        ctx_release(c);
    return st;
}

static void fill_result(reg_ctx *c, const pose *p, double tol, sr_register_result *out)
{
    score s = score_of(&c->fix, &c->fine, p, tol, c->scratch);
    memset(out, 0, sizeof *out);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            out->mat[4 * i + j] = p->r[3 * i + j];
        out->mat[4 * i + 3] = p->t[i];
    }
    double tr = (p->r[0] + p->r[4] + p->r[8] - 1) / 2;
    out->rotation_deg = acos(fmax(-1.0, fmin(1.0, tr))) * 180 / M_PI;
    out->translation_mm = sqrt(p->t[0] * p->t[0] + p->t[1] * p->t[1] + p->t[2] * p->t[2]);
    out->tol_mm = tol;
    out->samples = c->fine.count;
    out->coverage = c->fine.count ? (double)s.inliers / (double)c->fine.count : 0;
    out->rms_mm = s.inliers ? sqrt(s.sum2 / (double)s.inliers) : 0;
    out->median_mm = s.median;
}

static double tol_of(const sr_register_opts *o, const al_surface *fix)
{
    return o && o->tol_mm > 0 ? o->tol_mm : 0.005 * fix->diag;
}

sr_status sr_register_check(const sr_mesh *moving, const sr_mesh *fixed,
                            const sr_register_opts *opts, sr_register_result *out, sr_err *err)
{
    reg_ctx c;
    size_t n = opts && opts->samples ? opts->samples : 4000;
    sr_status st = ctx_make(&c, moving, fixed, n, err);
    if (st != SR_OK)
        return st;
    pose id = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
    fill_result(&c, &id, tol_of(opts, &c.fix), out);
    ctx_release(&c);
    return SR_OK;
}

#define MAX_STARTS 160
#define KEEP 4
#define PRESCORED 4 /* sr_register_from: starts that get the ICP */

/* The fit of al_register_fit from the start poses cand[0..count) (overwritten). */
/* Moves the `keep` starts with the most samples near the surface (near[i]) to the
 * front, in that order; cut (or NULL) moves with them. */
static void keep_most_near(pose *cand, size_t *near, double *cut, size_t count, size_t keep)
{
    for (size_t k = 0; k < keep && k < count; k++) {
        size_t best = k;
        for (size_t i = k + 1; i < count; i++)
            if (near[i] > near[best])
                best = i;
        pose tp = cand[k];
        cand[k] = cand[best];
        cand[best] = tp;
        size_t tn = near[k];
        near[k] = near[best];
        near[best] = tn;
        if (cut) {
            double tc = cut[k];
            cut[k] = cut[best];
            cut[best] = tc;
        }
    }
}

static void fit_from(al_surface *fix, const al_samples *coarse, const al_samples *medium,
                     const al_samples *fine, double tol, const al_register_effort *effort,
                     pose *cand, size_t count, double mat[12], double *scratch)
{
    double size = fix->diag;
    double floor = fmax(tol / 4, 1e-6 * size);
    score sc[MAX_STARTS];
    /* every start, briefly, on a few hundred samples; with many starts, one step each
     * and the rest for those with the most samples near the surface in that step */
    double c0 = effort->coarse_cutoff * size, cut[MAX_STARTS];
    int first = effort->coarse_iters;
    if (effort->coarse_keep && count > effort->coarse_keep && effort->coarse_iters > 1) {
        size_t near[MAX_STARTS];
        for (size_t i = 0; i < count; i++) {
            cut[i] = c0;
            icp_run(fix, coarse, &cand[i], 1, c0, &cut[i], floor, size, scratch);
            near[i] = 0;
            for (size_t k = 0; k < coarse->count && scratch[k] < 4 * tol; k++)
                near[i]++; /* scratch: the step's distances, sorted */
        }
        keep_most_near(cand, near, cut, count, effort->coarse_keep);
        count = effort->coarse_keep;
        first = effort->coarse_iters - 1;
    } else {
        for (size_t i = 0; i < count; i++)
            cut[i] = c0;
    }
    for (size_t i = 0; i < count; i++) {
        icp_run(fix, coarse, &cand[i], first, c0, &cut[i], floor, size, scratch);
        sc[i] = score_of(fix, coarse, &cand[i], 4 * tol, scratch);
    }
    /* the best few again on a thousand */
    size_t keep = count < effort->keep ? count : effort->keep;
    for (size_t k = 0; k < keep; k++) {
        size_t best = k;
        for (size_t i = k + 1; i < count; i++)
            if (score_better(&sc[i], &sc[best]))
                best = i;
        pose tp = cand[k];
        cand[k] = cand[best];
        cand[best] = tp;
        score ts = sc[k];
        sc[k] = sc[best];
        sc[best] = ts;
    }
    /* hopeless (a wrong part, for identify): the best coarse pose as it is */
    if (count && (double)sc[0].inliers < effort->give_up * (double)coarse->count)
        keep = 1;
    size_t winner = 0;
    for (size_t k = 0; k < keep && keep > 1; k++) {
        icp(fix, medium, &cand[k], effort->medium_iters, 0.05 * size, floor, size, scratch);
        sc[k] = score_of(fix, medium, &cand[k], tol, scratch);
        if (k && score_better(&sc[k], &sc[winner]))
            winner = k;
    }
    pose p = cand[winner];
    if (keep > 1 || effort->give_up == 0)
        icp(fix, fine, &p, effort->fine_iters, 0.02 * size, floor, size, scratch);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            mat[4 * i + j] = p.r[3 * i + j];
        mat[4 * i + 3] = p.t[i];
    }
}

void al_register_fit(al_surface *fix, const al_surface *mov, const al_samples *coarse,
                     const al_samples *medium, const al_samples *fine, double tol,
                     const al_register_effort *effort, double mat[12], double *scratch)
{
    pose cand[MAX_STARTS];
    size_t count = starts(fix, mov, effort->turns, cand, MAX_STARTS);
    fit_from(fix, coarse, medium, fine, tol, effort, cand, count, mat, scratch);
}

/* *out from the fitted mat (3 x 4), and c released. */
static sr_status finish(reg_ctx *c, const double mat[12], double tol, sr_register_result *out)
{
    pose p;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            p.r[3 * i + j] = mat[4 * i + j];
        p.t[i] = mat[4 * i + 3];
    }
    fill_result(c, &p, tol, out);
    ctx_release(c);
    return SR_OK;
}

sr_status sr_register(const sr_mesh *moving, const sr_mesh *fixed, const sr_register_opts *opts,
                      sr_register_result *out, sr_err *err)
{
    reg_ctx c;
    size_t n = opts && opts->samples ? opts->samples : 4000;
    sr_status st = ctx_make(&c, moving, fixed, n, err);
    if (st != SR_OK)
        return st;
    static const al_register_effort effort = {12, 0.25, 12, KEEP, 20, 40, 0, 0};
    double tol = tol_of(opts, &c.fix), mat[12];
    al_register_fit(&c.fix, &c.mov, &c.coarse, &c.medium, &c.fine, tol, &effort, mat, c.scratch);
    return finish(&c, mat, tol, out);
}

sr_status sr_register_from(const sr_mesh *moving, const sr_mesh *fixed, const double *start,
                           size_t count, const sr_register_opts *opts, sr_register_result *out,
                           sr_err *err)
{
    if (count == 0 || count > MAX_STARTS)
        return sr_err_set(err, SR_E_RANGE, "registration: %zu start poses (1 to %d)", count,
                          MAX_STARTS);
    reg_ctx c;
    size_t n = opts && opts->samples ? opts->samples : 4000;
    sr_status st = ctx_make(&c, moving, fixed, n, err);
    if (st != SR_OK)
        return st;
    /* the starts are near: a short first cut-off keeps each closest-point query cheap */
    static const al_register_effort effort = {0, 0.03, 12, 2, 20, 40, 0, 0};
    pose cand[MAX_STARTS];
    for (size_t k = 0; k < count; k++)
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++)
                cand[k].r[3 * i + j] = start[12 * k + 4 * i + j];
            cand[k].t[i] = start[12 * k + 4 * i + 3];
        }
    double tol = tol_of(opts, &c.fix), mat[12];
    /* many starts: only the best few by their score as they are go on (a query far from
     * the surface is the costly one, and most starts are far) */
    if (count > PRESCORED) {
        size_t near[MAX_STARTS];
        for (size_t k = 0; k < count; k++) {
            distances(&c.fix, &c.coarse, &cand[k], 4 * tol, c.scratch);
            near[k] = 0;
            for (size_t i = 0; i < c.coarse.count; i++)
                near[k] += c.scratch[i] < 4 * tol;
        }
        keep_most_near(cand, near, NULL, count, PRESCORED);
        count = PRESCORED;
    }
    fit_from(&c.fix, &c.coarse, &c.medium, &c.fine, tol, &effort, cand, count, mat, c.scratch);
    return finish(&c, mat, tol, out);
}

double sr_bbox_overlap(const sr_mesh *a, const sr_mesh *b)
{
    double amin[3], amax[3], bmin[3], bmax[3];
    sr_mesh_bbox(a, amin, amax);
    sr_mesh_bbox(b, bmin, bmax);
    double inter = 1, va = 1, vb = 1;
    for (int k = 0; k < 3; k++) {
        /* a flat box still has a size: 1e-6 of the largest side */
        double pad = 1e-6 * fmax(amax[k] - amin[k], bmax[k] - bmin[k]) + 1e-12;
        double lo = fmax(amin[k], bmin[k]), hi = fmin(amax[k], bmax[k]);
        inter *= hi > lo ? hi - lo + pad : 0;
        va *= amax[k] - amin[k] + pad;
        vb *= bmax[k] - bmin[k] + pad;
    }
    double small = fmin(va, vb);
    return small > 0 ? fmin(1.0, inter / small) : 0;
}
