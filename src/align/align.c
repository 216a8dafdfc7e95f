/*
 * align.c: the public face of the alignment (align.h): checks the inputs, runs the
 * search (align_axial.c, align_planar.c) or the paper's Algorithm 3 (align_paper.c),
 * and turns the symmetry element found into the rigid transform to the canonical frame.
 *
 * Canonical frame chosen here (documented in align.h):
 *  - axial: the rotation is the smallest one taking the axis direction to +z, with the
 *    axis direction's sign chosen so that it points along the scan's +z (a part scanned
 *    roughly upright stays upright); the axis goes to x = y = 0 and z = 0 is the lowest
 *    point of the mesh along the axis (so the part occupies z >= 0, as Alg. 1-5 expect);
 *  - mirror / glide: x = the plane normal (sign: along the scan's +x), z = the in-plane
 *    axis (sign: along the scan's +z), y = z x x; the plane goes to x = 0, z = 0 is the
 *    lowest point along z and y = 0 the middle of the part's extent along y.
 * fit_rms_mm and fit_score are the inlier RMS and the inlier share ("fitness") of the
 * symmetry transform(s) applied to area-uniform samples of the scan: a sample is an
 * inlier when its image lies within 0.4 % of the bounding-box diagonal of the scan.
 */
#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>

#define PROBE_SAMPLES 300
#define SCREEN_SAMPLES 600
#define COARSE_SAMPLES 2000
#define FINE_SAMPLES 10000
#define TOL_OF_DIAG 0.004

/* Sign (+1 / -1) of component `pref` of d, or of its first clearly non-zero component
 * when that one is ~0: fixes the signs of directions deterministically. */
static int sign_of(const double d[3], int pref)
{
    if (fabs(d[pref]) > 1e-12)
        return d[pref] > 0 ? 1 : -1;
    for (int k = 0; k < 3; k++)
        if (fabs(d[k]) > 1e-12)
            return d[k] > 0 ? 1 : -1;
    return 1;
}

/* Rotation rows (3x3 row-major) of the smallest rotation taking unit a to +z. */
static void rot_to_z(const double a[3], double r[9])
{
    double z[3] = {0, 0, 1}, k[3];
    v3_cross(a, z, k);
    double sn = v3_normalize(k), cs = a[2];
    if (sn < 1e-15) {
        if (cs > 0) {
            for (int i = 0; i < 9; i++)
                r[i] = (i % 4) == 0;
        } else { /* half turn about x */
            double x[3] = {1, 0, 0};
            al_rot_axis(x, M_PI, r);
        }
        return;
    }
    al_rot_axis(k, atan2(sn, cs), r);
}

/* xform from rotation rows r and a canonical origin o (scan frame): p' = R (p - o). */
static void make_xform(const double r[9], const double o[3], double xf[12])
{
    for (int i = 0; i < 3; i++) {
        xf[4 * i] = r[3 * i];
        xf[4 * i + 1] = r[3 * i + 1];
        xf[4 * i + 2] = r[3 * i + 2];
        xf[4 * i + 3] = -(r[3 * i] * o[0] + r[3 * i + 1] * o[1] + r[3 * i + 2] * o[2]);
    }
}

/* Fills the frame of *out from an axis (a, c); mesh may be NULL (origin = c). */
static void frame_axial(const sr_mesh *mesh, const double a_in[3], const double c[3],
                        sr_alignment *out)
{
    double a[3];
    memcpy(a, a_in, sizeof a);
    v3_normalize(a);
    double r[9], o[3];
    rot_to_z(a, r);
    double z0 = 0;
    if (mesh && mesh->vertex_count) {
        z0 = INFINITY;
        for (size_t v = 0; v < mesh->vertex_count; v++) {
            const double *p = mesh->xyz + 3 * v;
            double z = a[0] * (p[0] - c[0]) + a[1] * (p[1] - c[1]) + a[2] * (p[2] - c[2]);
            z0 = z < z0 ? z : z0;
        }
    }
    for (int k = 0; k < 3; k++)
        o[k] = c[k] + z0 * a[k];
    make_xform(r, o, out->xform);
    memcpy(out->axis_point, o, sizeof o);
    memcpy(out->axis_dir, a, sizeof a);
    memset(out->plane_normal, 0, sizeof out->plane_normal);
}

/* Frame of a plane (normal n, in-plane axis t, point c); mesh may be NULL. */
static void frame_planar(const sr_mesh *mesh, const double n_in[3], const double t_in[3],
                         const double c[3], sr_alignment *out)
{
    double n[3], t[3], y[3];
    memcpy(n, n_in, sizeof n);
    v3_normalize(n);
    double dn = v3_dot(t_in, n);
    for (int k = 0; k < 3; k++)
        t[k] = t_in[k] - dn * n[k];
    v3_normalize(t);
    v3_cross(t, n, y);
    double r[9] = {n[0], n[1], n[2], y[0], y[1], y[2], t[0], t[1], t[2]};
    double z0 = 0, y0 = 0;
    if (mesh && mesh->vertex_count) {
        double zlo = INFINITY, ylo = INFINITY, yhi = -INFINITY;
        for (size_t v = 0; v < mesh->vertex_count; v++) {
            const double *p = mesh->xyz + 3 * v;
            double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
            double z = v3_dot(d, t), yy = v3_dot(d, y);
            zlo = z < zlo ? z : zlo;
            ylo = yy < ylo ? yy : ylo;
            yhi = yy > yhi ? yy : yhi;
        }
        z0 = zlo;
        y0 = 0.5 * (ylo + yhi);
    }
    double o[3];
    for (int k = 0; k < 3; k++)
        o[k] = c[k] + z0 * t[k] + y0 * y[k];
    make_xform(r, o, out->xform);
    memcpy(out->axis_point, o, sizeof o);
    memcpy(out->axis_dir, t, sizeof t);
    memcpy(out->plane_normal, n, sizeof n);
}

static sr_status check_opts(const sr_align_opts *in, sr_align_opts *o, sr_err *err)
{
    sr_align_opts z = {0};
    *o = in ? *in : z;
    if (o->method != 0 && o->method != 1)
        return sr_err_set(err, SR_E_RANGE,
                          "bad alignment method %d: expected 0 (refined) or 1 (paper)",
                          o->method);
    if (o->layers < 0 || o->layers > 100000)
        return sr_err_set(err, SR_E_RANGE, "bad alignment layers %d: expected 0 or 1..100000",
                          o->layers);
    if (o->sectors < 0 || o->sectors > 100000 || (o->sectors > 0 && o->sectors < 4))
        return sr_err_set(err, SR_E_RANGE, "bad alignment sectors %d: expected 0 or 4..100000",
                          o->sectors);
    if (!isfinite(o->delta_d) || o->delta_d < 0 || o->delta_d >= 1)
        return sr_err_set(err, SR_E_RANGE, "bad alignment delta_d %g: expected 0 or (0, 1)",
                          o->delta_d);
    if (o->threads < 0)
        return sr_err_set(err, SR_E_RANGE, "bad alignment threads %d: expected 0 or more",
                          o->threads);
    if (!isfinite(o->hint[0]) || !isfinite(o->hint[1]) || !isfinite(o->hint[2]))
        return sr_err_set(err, SR_E_RANGE, "bad alignment hint: expected 3 finite numbers");
    if (!isfinite(o->coarse_step_deg) || o->coarse_step_deg < 0 || o->coarse_step_deg > 45)
        return sr_err_set(err, SR_E_RANGE,
                          "bad alignment coarse_step_deg %g: expected 0 or (0, 45]",
                          o->coarse_step_deg);
    if (o->layers == 0)
        o->layers = 64;
    if (o->sectors == 0)
        o->sectors = 72;
    if (o->delta_d == 0)
        o->delta_d = 0.05;
    if (o->coarse_step_deg == 0)
        o->coarse_step_deg = 5;
    return SR_OK;
}

sr_status sr_align(const sr_mesh *mesh, const sr_symmetry *sym, const sr_align_opts *opts,
                   sr_alignment *out, sr_err *err)
{
    sr_align_opts o;
    sr_status st = check_opts(opts, &o, err);
    if (st != SR_OK)
        return st;
    st = sr_symmetry_check(sym, err);
    if (st != SR_OK)
        return st;
    st = sr_mesh_validate(mesh, "mesh", NULL, err);
    if (st != SR_OK)
        return st;
    al_ctx ctx = {0};
    al_surface surf;
    st = al_surface_build(&surf, mesh, err);
    if (st != SR_OK)
        return st;
    if (al_surface_threads(&surf, o.threads) != SR_OK) {
        al_surface_release(&surf);
        return sr_err_set(err, SR_E_NOMEM, "cannot align: out of memory for the search grid");
    }
    ctx.surf = &surf;
    ctx.sym = sym;
    ctx.opts = &o;
    ctx.tol = TOL_OF_DIAG * surf.diag;
    memcpy(ctx.hint, o.hint, sizeof ctx.hint);
    ctx.have_hint = v3_normalize(ctx.hint) > 0;
    if (al_samples_make(&surf, PROBE_SAMPLES, 0x5eed0004u, &ctx.probe) != SR_OK ||
        al_samples_make(&surf, SCREEN_SAMPLES, 0x5eed0003u, &ctx.screen) != SR_OK ||
        al_samples_make(&surf, COARSE_SAMPLES, 0x5eed0001u, &ctx.coarse) != SR_OK ||
        al_samples_make(&surf, FINE_SAMPLES, 0x5eed0002u, &ctx.fine) != SR_OK) {
        st = sr_err_set(err, SR_E_NOMEM, "cannot align: out of memory for samples");
        goto cleanup;
    }
    al_model m;
    al_fit fit;
    sr_alignment res;
    memset(&res, 0, sizeof res);
    if (o.method == 1) {
        al_paper_result pr;
        st = al_paper_align(&surf, sym, &o, &pr);
        if (st != SR_OK) {
            sr_err_set(err, st, "cannot align: %s", sr_status_str(st));
            goto cleanup;
        }
        memset(&m, 0, sizeof m);
        m.scale = surf.diag;
        memcpy(m.c, pr.point, sizeof m.c);
        if (sym->kind == SR_SYM_AXIAL) {
            m.kind = AL_AXIAL;
            memcpy(m.a, pr.dir, sizeof m.a);
            m.variant_count = sym->order >= 2 ? sym->order - 1 : 11;
            for (int k = 0; k < m.variant_count; k++)
                m.angle[k] = 2 * M_PI * (k + 1) / (sym->order >= 2 ? sym->order : 12);
        } else {
            m.kind = sym->kind == SR_SYM_GLIDE ? AL_GLIDE : AL_MIRROR;
            memcpy(m.a, pr.normal, sizeof m.a);
            memcpy(m.t, pr.dir, sizeof m.t);
            m.shift = pr.shift;
            m.variant_count = m.kind == AL_GLIDE ? 2 : 1;
        }
        al_evaluate(&surf, &ctx.fine, &m, ctx.tol, &fit);
        res.symmetric_layers = pr.symmetric_layers;
    } else {
        st = sym->kind == SR_SYM_AXIAL ? al_axial_search(&ctx, &m, &fit)
                                       : al_planar_search(&ctx, &m, &fit);
        if (st != SR_OK) {
            sr_err_set(err, st, "cannot align: %s", sr_status_str(st));
            goto cleanup;
        }
    }
    if (sym->kind == SR_SYM_AXIAL) {
        if (sign_of(m.a, 2) < 0)
            for (int k = 0; k < 3; k++)
                m.a[k] = -m.a[k];
        frame_axial(mesh, m.a, m.c, &res);
    } else {
        if (sign_of(m.a, 0) < 0)
            for (int k = 0; k < 3; k++)
                m.a[k] = -m.a[k];
        if (m.kind == AL_MIRROR) {
            /* the in-plane axis: the principal direction of least spread in the plane */
            double w[3], v[9], best = INFINITY;
            al_eig_sym(3, surf.cov, w, v);
            for (int k = 0; k < 3; k++) {
                double e[3] = {v[k], v[3 + k], v[6 + k]};
                double dn = v3_dot(e, m.a);
                for (int q = 0; q < 3; q++)
                    e[q] -= dn * m.a[q];
                if (v3_normalize(e) < 0.5)
                    continue;
                double var = 0;
                for (int r = 0; r < 3; r++)
                    for (int q = 0; q < 3; q++)
                        var += e[r] * surf.cov[3 * r + q] * e[q];
                if (var < best) {
                    best = var;
                    memcpy(m.t, e, sizeof e);
                }
            }
        }
        if (sign_of(m.t, 2) < 0)
            for (int k = 0; k < 3; k++)
                m.t[k] = -m.t[k];
        frame_planar(mesh, m.a, m.t, m.c, &res);
        res.glide_shift_mm = m.kind == AL_GLIDE ? fabs(m.shift) : 0;
    }
    if (o.method == 0)
        res.symmetric_layers = al_paper_count(&surf, sym, &o, res.xform);
    /* no inlier at all: the tolerance itself, the best that can be said */
    res.fit_rms_mm = isfinite(fit.inlier_rms) ? fit.inlier_rms : ctx.tol;
    res.fit_score = fit.score;
    *out = res;
    st = SR_OK;
cleanup:
    al_samples_release(&ctx.probe);
    al_samples_release(&ctx.screen);
    al_samples_release(&ctx.coarse);
    al_samples_release(&ctx.fine);
    al_surface_release(&surf);
    return st;
}

static bool finite3(const double *p)
{
    return p && isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

sr_status sr_align_from_axis(const double point[3], const double dir[3],
                             const double normal[3], sr_alignment *out, sr_err *err)
{
    if (!finite3(point))
        return sr_err_set(err, SR_E_RANGE, "bad axis point: expected 3 finite numbers");
    if (!finite3(dir) || v3_norm(dir) < 1e-12)
        return sr_err_set(err, SR_E_RANGE, "bad axis direction: expected a non-zero finite vector");
    sr_alignment res;
    memset(&res, 0, sizeof res);
    if (!normal) {
        frame_axial(NULL, dir, point, &res);
    } else {
        if (!finite3(normal) || v3_norm(normal) < 1e-12)
            return sr_err_set(err, SR_E_RANGE,
                              "bad plane normal: expected a non-zero finite vector");
        double n[3], d[3];
        memcpy(n, normal, sizeof n);
        memcpy(d, dir, sizeof d);
        v3_normalize(n);
        v3_normalize(d);
        if (fabs(v3_dot(n, d)) > 1 - 1e-6)
            return sr_err_set(err, SR_E_RANGE,
                              "bad in-plane axis: it is parallel to the plane normal");
        frame_planar(NULL, n, d, point, &res);
    }
    *out = res;
    return SR_OK;
}
