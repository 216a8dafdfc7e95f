/*
 * inspect.c: sr_inspect_run (inspect.h says the method): the checks, the scan taken
 * onto the restored model (as it is, or registered with the sections' surface left
 * out of the fit), the signed distances of area-uniform scan samples and of every
 * scan vertex, the per-section and outside statistics, and the verdicts with their
 * reasons. The volumes are inspect_volume.c's.
 */
#include "inspect/inspect.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "align/register.h"
#include "align/surface_query.h"
#include "inspect/inspect_int.h"

#define DEFAULT_SAMPLES 20000
#define SHARE_LIMIT 0.01 /* a verdict needs more than this share of the samples */
#define SAME_FRAME 0.7   /* coverage outside the sections that takes the scan as it is */

const char *sr_inspect_verdict_str(sr_inspect_verdict v)
{
    switch (v) {
    case SR_INSPECT_PASS: return "pass";
    case SR_INSPECT_MACHINE: return "machine";
    case SR_INSPECT_REWORK: return "rework";
    }
    return "?";
}

int sr_inspect_verdict_parse(const char *s)
{
    for (int v = SR_INSPECT_PASS; v <= SR_INSPECT_REWORK; v++)
        if (s && strcmp(s, sr_inspect_verdict_str((sr_inspect_verdict)v)) == 0)
            return v;
    return -1;
}

struct ins_where {
    sr_surface_query *model;
    sr_surface_query **patch; /* one per section */
    size_t count;
    double on_mm;   /* a restored point this close to a patch lies on it */
    double near_mm; /* a scan point this close to a patch lies over it (the larger of
                     * the tolerance and the registration's) */
};

int ins_section_of(ins_where *w, const double p[3], double *signed_dist)
{
    double q[3], sd = 0;
    double d;
    if (!sr_surface_query_closest(w->model, p, INFINITY, q, &d, &sd)) {
        if (signed_dist)
            *signed_dist = 0;
        return -1;
    }
    if (signed_dist)
        *signed_dist = sd;
    int best = -1;
    double best_d = w->on_mm;
    for (size_t k = 0; k < w->count; k++) {
        double dk;
        if (sr_surface_query_closest(w->patch[k], q, best_d, NULL, &dk, NULL) && dk <= best_d) {
            best = (int)k;
            best_d = dk;
        }
    }
    /* or p itself on a patch: the fracture surface of a section left as it was, whose
     * closest restored point can lie beside the patch near its rim */
    best_d = w->near_mm;
    for (size_t k = 0; best < 0 && k < w->count; k++) {
        double dk;
        if (sr_surface_query_closest(w->patch[k], p, best_d, NULL, &dk, NULL) && dk <= best_d)
            return (int)k;
    }
    return best;
}

static void where_release(ins_where *w)
{
    sr_surface_query_free(w->model);

    for (size_t k = 0; k < w->count; k++)
        sr_surface_query_free(w->patch ? w->patch[k] : NULL);
    free(w->patch);
    memset(w, 0, sizeof *w);
}

static sr_status where_build(const sr_run *run, const sr_mesh *model, double tol, ins_where *w,
                             sr_err *err)
{
    memset(w, 0, sizeof *w);
    double lo[3], hi[3];
    sr_mesh_bbox(model, lo, hi);
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    w->on_mm = 1e-4 * diag + 1e-6;
    w->near_mm = tol;
    w->patch = calloc(run->section_count ? run->section_count : 1, sizeof *w->patch);
    if (!w->patch)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    sr_status st = sr_surface_query_build(model, &w->model, err);
    for (size_t k = 0; st == SR_OK && k < run->section_count; k++) {
        st = sr_surface_query_build(&run->sections[k].patch, &w->patch[k], err);
        w->count = k + 1;
    }
    if (st != SR_OK)
        where_release(w);
    return st;
}

/* The restored solid m without the triangles that lie on a section's patch (the
 * surface the repair rebuilt), for the registration; the whole mesh when nothing is
 * left. */
static sr_status trimmed_model(const sr_mesh *m, ins_where *w, sr_mesh *out)
{
    sr_status st = sr_mesh_alloc(out, m->vertex_count, m->tri_count);
    if (st != SR_OK)
        return st;
    memcpy(out->xyz, m->xyz, 3 * m->vertex_count * sizeof *m->xyz);
    size_t kept = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        double c[3];
        for (int k = 0; k < 3; k++)
            c[k] = (m->xyz[3 * f[0] + k] + m->xyz[3 * f[1] + k] + m->xyz[3 * f[2] + k]) / 3;
        bool on = false;
        for (size_t s = 0; s < w->count && !on; s++) {
            double d;
            on = sr_surface_query_closest(w->patch[s], c, w->on_mm, NULL, &d, NULL);
        }
        if (!on) {
            memcpy(out->tri + 3 * kept, f, 3 * sizeof *f);
            kept++;
        }
    }
    out->tri_count = kept ? kept : m->tri_count;
    if (!kept)
        memcpy(out->tri, m->tri, 3 * m->tri_count * sizeof *m->tri);
    return SR_OK;
}

#define ROLL_SAMPLES 1500
#define ROLL_CAP_MM 1.0 /* a sample's squared deviation counts up to this depth */

/* The rotation by angle a (radians) about the line through c along the unit u, 3x4. */
static void rotation_about(const double c[3], const double u[3], double a, double m[12])
{
    double co = cos(a), si = sin(a), t = 1 - co;
    double r[9] = {
        co + u[0] * u[0] * t,        u[0] * u[1] * t - u[2] * si, u[0] * u[2] * t + u[1] * si,
        u[1] * u[0] * t + u[2] * si, co + u[1] * u[1] * t,        u[1] * u[2] * t - u[0] * si,
        u[2] * u[0] * t - u[1] * si, u[2] * u[1] * t + u[0] * si, co + u[2] * u[2] * t};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            m[4 * i + j] = r[3 * i + j];
        m[4 * i + 3] = c[i] - (r[3 * i] * c[0] + r[3 * i + 1] * c[1] + r[3 * i + 2] * c[2]);
    }
}

/* How far the samples xyz (n by 3), turned by m, lie off the restored surface outside
 * the sections: the sum of their squared deviations, each up to ROLL_CAP_MM. */
static double roll_score(ins_where *w, const double *xyz, size_t n, const double m[12])
{
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        double p[3], d = 0;
        sr_xform_apply(m, xyz + 3 * i, p);
        if (ins_section_of(w, p, &d) < 0)
            sum += fmin(d * d, ROLL_CAP_MM * ROLL_CAP_MM);
    }
    return sum;
}

/* On an axially symmetric part the registration with the sections left out of the fit
 * leaves the rotation about the axis free (measured: the gouged bushing's damaged
 * scan, noisy and posed, landed turned off its section: 1656 of 2416 mm3 under-fill,
 * the rest of the gouge read as the part changed outside). The part's own damage and
 * repair tell it: the roll about the run's axis (its alignment's z axis) that puts
 * the scan's departures from the restored surface inside the sections, least
 * deviation left outside them, is taken, and the turn end for end with it (a plain
 * tube's other symmetry: the same scan landed upside down, z -> 60 - z); kept as
 * registered unless a candidate lowers that by more than a third. Coarse 2 degree
 * steps round the axis, then 0.1 degree. */
static sr_status resolve_roll(const sr_run *run, ins_where *w, sr_inspect_result *r, sr_err *err)
{
    if (run->symmetry.kind != SR_SYM_AXIAL || !run->has_alignment || run->section_count == 0)
        return SR_OK;
    double inv[12], c[3], u[3];
    sr_xform_rigid_inverse(inv, run->alignment);
    for (int i = 0; i < 3; i++) {
        c[i] = inv[4 * i + 3];
        u[i] = inv[4 * i + 2];
    }
    sr_surface_query *sq = NULL;
    sr_status st = sr_surface_query_build(&r->scan, &sq, err);
    if (st != SR_OK)
        return st;
    double *xyz = malloc(3 * ROLL_SAMPLES * sizeof *xyz);
    if (!xyz) {
        sr_surface_query_free(sq);
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    }
    st = sr_surface_query_samples(sq, ROLL_SAMPLES, 0x7011, xyz);
    sr_surface_query_free(sq);
    if (st != SR_OK) {
        free(xyz);
        return sr_err_set(err, st, "out of memory");
    }
    /* the turn end for end too (a plain tube is symmetric that way as well): by a half
     * turn about a line across the axis at the middle of the part's length */
    double lo = INFINITY, hi = -INFINITY;
    for (size_t v = 0; v < run->restored.vertex_count; v++) {
        const double *p = run->restored.xyz + 3 * v;
        double t = (p[0] - c[0]) * u[0] + (p[1] - c[1]) * u[1] + (p[2] - c[2]) * u[2];
        lo = fmin(lo, t);
        hi = fmax(hi, t);
    }
    double mid[3], e[3], x[3] = {1, 0, 0};
    if (fabs(u[0]) > 0.9)
        x[0] = 0, x[1] = 1;
    e[0] = u[1] * x[2] - u[2] * x[1];
    e[1] = u[2] * x[0] - u[0] * x[2];
    e[2] = u[0] * x[1] - u[1] * x[0];
    double el = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (int i = 0; i < 3; i++) {
        e[i] /= el;
        mid[i] = c[i] + u[i] * (lo + hi) / 2;
    }
    double flip[2][12], m[12], roll[12], best_a = 0;
    sr_xform_identity(flip[0]);
    rotation_about(mid, e, M_PI, flip[1]);
    int best_f = 0;
    double base = roll_score(w, xyz, ROLL_SAMPLES, flip[0]), best = base;
    for (int f = 0; f < 2; f++)
        for (int k = f ? 0 : 1; k < 180; k++) {
            double a = 2 * M_PI * k / 180;
            rotation_about(c, u, a, roll);
            sr_xform_mul(m, roll, flip[f]);
            double sc = roll_score(w, xyz, ROLL_SAMPLES, m);
            if (sc < best) {
                best = sc;
                best_a = a;
                best_f = f;
            }
        }
    double coarse = best_a;
    for (int k = -20; k <= 20; k++) {
        double a = coarse + k * (M_PI / 1800);
        rotation_about(c, u, a, roll);
        sr_xform_mul(m, roll, flip[best_f]);
        double sc = roll_score(w, xyz, ROLL_SAMPLES, m);
        if (sc < best) {
            best = sc;
            best_a = a;
        }
    }
    free(xyz);
    if (!(best < base * (2.0 / 3.0)))
        return SR_OK;
    rotation_about(c, u, best_a, roll);
    sr_xform_mul(m, roll, flip[best_f]);
    sr_mesh_transform(&r->scan, m);
    sr_xform_mul(r->transform, m, r->transform);
    return SR_OK;
}

/* Takes r->scan onto the model: as it is when it lies on it, else registered (and on
 * an axially symmetric part turned about the axis to where its damage and repair
 * meet the sections: resolve_roll). */
static sr_status place_scan(const sr_run *run, const sr_mesh *model, ins_where *w, int mode,
                            sr_inspect_result *r, sr_err *err)
{
    sr_mesh trim;
    sr_mesh_init(&trim);
    sr_status st = trimmed_model(model, w, &trim);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory");
    sr_register_opts ro = {0};
    sr_register_result id, reg;
    sr_xform_identity(r->transform);
    r->registered = 0;
    st = sr_register_check(&r->scan, &trim, &ro, &id, err);
    if (st == SR_OK) {
        r->coverage = id.coverage;
        r->reg_tol_mm = id.tol_mm;
    }
    if (st == SR_OK && mode != SR_INSPECT_REGISTER_NEVER &&
        (mode == SR_INSPECT_REGISTER_ALWAYS || id.coverage < SAME_FRAME)) {
        st = sr_register(&r->scan, &trim, &ro, &reg, err);
        if (st == SR_OK && (mode == SR_INSPECT_REGISTER_ALWAYS || reg.coverage > id.coverage)) {
            memcpy(r->transform, reg.mat, sizeof reg.mat);
            r->registered = 1;
            r->coverage = reg.coverage;
            sr_mesh_transform(&r->scan, reg.mat);
        }
    }
    sr_mesh_release(&trim);
    if (st == SR_OK && r->registered)
        st = resolve_roll(run, w, r, err);
    return st;
}

/* Running figures of one set of samples. */
typedef struct acc {
    size_t n, under, stock;
    double sum, sum2, min, max;
    double stock_sum, stock_min, stock_max;
    double under_est, over_est; /* depth x area, mm^3 */
} acc;

static void acc_add(acc *a, double d, double tol, double area)
{
    if (a->n == 0) {
        a->min = d;
        a->max = d;
    }
    a->n++;
    a->sum += d;
    a->sum2 += d * d;
    a->min = fmin(a->min, d);
    a->max = fmax(a->max, d);
    if (d < -tol)
        a->under++;
    if (d > tol) {
        if (a->stock == 0) {
            a->stock_min = d;
            a->stock_max = d;
        }
        a->stock++;
        a->stock_sum += d;
        a->stock_min = fmin(a->stock_min, d);
        a->stock_max = fmax(a->stock_max, d);
    }
    if (d < 0)
        a->under_est += -d * area;
    else
        a->over_est += d * area;
}

static void section_verdict(sr_inspect_section *s, double tol, double allowance)
{
    int n = 0;
    size_t cap = sizeof s->reasons;
    s->verdict = SR_INSPECT_PASS;
    if (s->samples == 0) {
        s->verdict = SR_INSPECT_REWORK;
        snprintf(s->reasons, cap, "the scan does not reach the section");
        return;
    }
    if (s->under_share > SHARE_LIMIT && s->underfill_depth_mm > tol) {
        s->verdict = SR_INSPECT_REWORK;
        n += snprintf(s->reasons + n, cap - (size_t)n,
                      "under-fill %.1f mm3, up to %.3g mm below the restored surface over %.3g %% "
                      "of the region",
                      s->underfill_mm3, s->underfill_depth_mm, 100 * s->under_share);
    }
    if (s->stock_share > SHARE_LIMIT) {
        if (s->verdict == SR_INSPECT_PASS)
            s->verdict = SR_INSPECT_MACHINE;
        if (n > 0 && (size_t)n < cap)
            n += snprintf(s->reasons + n, cap - (size_t)n, "; ");
        if ((size_t)n < cap)
            n += snprintf(s->reasons + n, cap - (size_t)n,
                          "stock %.3g to %.3g mm (mean %.3g) to machine, %s the allowance %.3g mm",
                          s->stock_min_mm, s->stock_max_mm, s->stock_mean_mm,
                          s->stock_max_mm > allowance + tol ? "beyond" : "within", allowance);
    }
    if (s->verdict == SR_INSPECT_PASS)
        snprintf(s->reasons, cap, "on the restored surface within %.3g mm", tol);
}

static void overall_verdict(sr_inspect_result *r)
{
    size_t cap = sizeof r->reasons;
    int n = 0;
    r->verdict = SR_INSPECT_PASS;
    for (size_t k = 0; k < r->section_count; k++) {
        const sr_inspect_section *s = &r->sections[k];
        if (s->verdict > r->verdict)
            r->verdict = s->verdict;
        if (s->verdict != SR_INSPECT_PASS && (size_t)n < cap)
            n += snprintf(r->reasons + n, cap - (size_t)n, "%ssection %zu: %s", n ? "; " : "",
                          s->index + 1, sr_inspect_verdict_str(s->verdict));
    }
    if (r->outside_samples > 0 && r->outside_share > SHARE_LIMIT) {
        r->verdict = SR_INSPECT_REWORK;
        if ((size_t)n < cap)
            n +=
                snprintf(r->reasons + n, cap - (size_t)n,
                         "%soutside the sections the part changed: %.3g %% of its surface beyond "
                         "%.3g mm, up to %.3g mm",
                         n ? "; " : "", 100 * r->outside_share, r->tolerance_mm, r->outside_max_mm);
    }
    if (n == 0)
        snprintf(r->reasons, cap, "every section and the rest of the part within %.3g mm",
                 r->tolerance_mm);
}

static sr_status check_inputs(const sr_run *run, const sr_mesh *scan, const sr_inspect_opts *o,
                              sr_err *err)
{
    if (o && (!(o->allowance_mm >= 0) || !isfinite(o->allowance_mm)))
        return sr_err_set(err, SR_E_RANGE, "allowance must be >= 0 mm, got %g", o->allowance_mm);
    if (o && (!(o->tolerance_mm >= 0) || !isfinite(o->tolerance_mm)))
        return sr_err_set(err, SR_E_RANGE, "tolerance must be >= 0 mm, got %g", o->tolerance_mm);
    if (run->restored.tri_count == 0)
        return sr_err_set(err, SR_E_INVALID, "run %lld has no restored mesh", (long long)run->id);
    sr_status st = sr_mesh_validate(&run->restored, "restored mesh", NULL, err);
    for (size_t k = 0; st == SR_OK && k < run->section_count; k++) {
        char what[48];
        snprintf(what, sizeof what, "patch of section %zu", run->sections[k].index + 1);
        if (run->sections[k].patch.tri_count == 0)
            return sr_err_set(err, SR_E_INVALID, "run %lld keeps no %s", (long long)run->id, what);
        st = sr_mesh_validate(&run->sections[k].patch, what, NULL, err);
    }
    if (st == SR_OK)
        st = sr_mesh_validate(scan, "scan", NULL, err);
    return st;
}

void sr_inspect_release(sr_inspect_result *r)
{
    if (!r)
        return;
    free(r->sections);
    free(r->deviation);
    sr_mesh_release(&r->scan);
    memset(r, 0, sizeof *r);
}

/* Samples of the scan: figures per section slot (acc[k]) and outside (acc[count]). */
static sr_status measure(ins_where *w, sr_inspect_result *r, size_t samples, acc *accs,
                         double *outside_max, sr_err *err)
{
    sr_surface_query *sq = NULL;
    sr_status st = sr_surface_query_build(&r->scan, &sq, err);
    if (st != SR_OK)
        return st;
    double *xyz = malloc(3 * samples * sizeof *xyz);
    if (!xyz) {
        sr_surface_query_free(sq);
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    }
    st = sr_surface_query_samples(sq, samples, 0x5eed, xyz);
    double area = sr_surface_query_area(sq) / (double)samples;
    sr_surface_query_free(sq);
    for (size_t i = 0; st == SR_OK && i < samples; i++) {
        double d;
        int s = ins_section_of(w, xyz + 3 * i, &d);
        acc_add(&accs[s < 0 ? w->count : (size_t)s], d, r->tolerance_mm, area);
        if (s < 0)
            *outside_max = fmax(*outside_max, fabs(d));
    }
    free(xyz);
    /* the vertices too, for the colours and for the extremes samples miss (corners) */
    for (size_t v = 0; st == SR_OK && v < r->scan.vertex_count; v++) {
        int s = ins_section_of(w, r->scan.xyz + 3 * v, &r->deviation[v]);
        double d = r->deviation[v];
        if (s < 0)
            continue;
        acc *a = &accs[s];
        if (a->n > 0) {
            a->min = fmin(a->min, d);
            a->max = fmax(a->max, d);
        }
        if (a->stock > 0 && d > r->tolerance_mm)
            a->stock_max = fmax(a->stock_max, d);
    }
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory");
    return SR_OK;
}

static void solids_free(sr_mesh *solids, size_t n)
{
    for (size_t k = 0; k < n; k++)
        sr_mesh_release(&solids[k]);
    free(solids);
}

static void fill_section(sr_inspect_section *s, const sr_run_section *rs, const acc *a)
{
    s->index = rs->index;
    s->patch_mm3 = sr_mesh_volume(&rs->patch);
    s->samples = a->n;
    if (a->n == 0)
        return;
    double n = (double)a->n;
    s->dev_mean_mm = a->sum / n;
    s->dev_rms_mm = sqrt(a->sum2 / n);
    s->dev_min_mm = a->min;
    s->dev_max_mm = a->max;
    s->underfill_depth_mm = a->min < 0 ? -a->min : 0;
    s->under_share = (double)a->under / n;
    s->stock_share = (double)a->stock / n;
    if (a->stock) {
        s->stock_min_mm = a->stock_min;
        s->stock_max_mm = a->stock_max;
        s->stock_mean_mm = a->stock_sum / (double)a->stock;
    }
    s->underfill_mm3 = a->under_est;
    s->overbuild_mm3 = a->over_est;
}

sr_status sr_inspect_run(const sr_run *run, const sr_mesh *scan, const sr_inspect_opts *opts,
                         sr_inspect_result *out, sr_err *err)
{
    sr_status st = check_inputs(run, scan, opts, err);
    if (st != SR_OK)
        return st;
    sr_inspect_opts o = opts ? *opts : (sr_inspect_opts){0};
    sr_inspect_result r;
    memset(&r, 0, sizeof r);
    r.allowance_mm = o.allowance_mm > 0 ? o.allowance_mm : SR_INSPECT_ALLOWANCE_MM;
    r.tolerance_mm = o.tolerance_mm > 0 ? o.tolerance_mm : SR_INSPECT_TOLERANCE_MM;
    size_t samples = o.samples ? o.samples : DEFAULT_SAMPLES;
    size_t ns = run->section_count;
    ins_where w;
    acc *accs = calloc(ns + 1, sizeof *accs);
    r.sections = calloc(ns ? ns : 1, sizeof *r.sections);
    r.section_count = ns;
    if (!accs || !r.sections) {
        free(accs);
        sr_inspect_release(&r);
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    }
    sr_mesh *solids = NULL, visible;
    size_t nsolid = 0;
    sr_mesh_init(&visible);
    st = ins_solid_shells(&run->restored, &solids, &nsolid, err);
    if (st == SR_OK && nsolid) {
        snprintf(r.model_note, sizeof r.model_note,
                 "the restored mesh is %zu separate solids (a --no-union run): measured "
                 "against the surface of their union",
                 nsolid);
        st = ins_visible_surface(solids, nsolid, &visible, err);
    }
    const sr_mesh *model = nsolid ? &visible : &run->restored;
    if (st == SR_OK)
        st = where_build(run, model, r.tolerance_mm, &w, err);
    if (st != SR_OK) {
        sr_mesh_release(&visible);
        solids_free(solids, nsolid);
        free(accs);
        sr_inspect_release(&r);
        return st;
    }
    st = sr_mesh_copy(&r.scan, scan);
    if (st == SR_OK) {
        r.deviation = calloc(scan->vertex_count ? scan->vertex_count : 1, sizeof *r.deviation);
        if (!r.deviation)
            st = SR_E_NOMEM;
    }
    if (st != SR_OK)
        sr_err_set(err, st, "out of memory");
    if (st == SR_OK)
        st = place_scan(run, model, &w, o.register_mode, &r, err);
    /* a scan point within the registration's tolerance of a patch lies over it */
    w.near_mm = fmax(w.near_mm, r.reg_tol_mm);
    double outside_max = 0;
    if (st == SR_OK)
        st = measure(&w, &r, samples, accs, &outside_max, err);
    if (st == SR_OK) {
        for (size_t k = 0; k < ns; k++)
            fill_section(&r.sections[k], &run->sections[k], &accs[k]);
        const acc *oa = &accs[ns];
        r.outside_samples = oa->n;
        r.outside_share = oa->n ? (double)(oa->under + oa->stock) / (double)oa->n : 0;
        r.outside_max_mm = outside_max;
        r.outside_rms_mm = oa->n ? sqrt(oa->sum2 / (double)oa->n) : 0;
        r.outside_overbuild_mm3 = oa->over_est;
        st = ins_volumes(run, nsolid ? solids : &run->restored, nsolid ? nsolid : 1, &w, &r, err);
    }
    if (st == SR_OK) {
        for (size_t k = 0; k < ns; k++)
            section_verdict(&r.sections[k], r.tolerance_mm, r.allowance_mm);
        overall_verdict(&r);
    }
    where_release(&w);
    solids_free(solids, nsolid);
    sr_mesh_release(&visible);
    free(accs);
    if (st != SR_OK) {
        sr_inspect_release(&r);
        return st;
    }
    *out = r;
    return SR_OK;
}

sr_status sr_inspect_deviations(const sr_mesh *model, const sr_mesh *scan, double *dev, sr_err *err)
{
    sr_surface_query *q = NULL;
    sr_mesh *solids = NULL, visible;
    size_t n = 0;
    sr_mesh_init(&visible);
    sr_status st = ins_solid_shells(model, &solids, &n, err);
    if (st == SR_OK && n)
        st = ins_visible_surface(solids, n, &visible, err);
    if (st == SR_OK)
        st = sr_surface_query_build(n ? &visible : model, &q, err);
    for (size_t v = 0; st == SR_OK && v < scan->vertex_count; v++) {
        double d = 0, sd = 0;
        if (!sr_surface_query_closest(q, scan->xyz + 3 * v, INFINITY, NULL, &d, &sd))
            sd = 0;
        dev[v] = sd;
    }
    sr_surface_query_free(q);
    solids_free(solids, n);
    sr_mesh_release(&visible);
    return st;
}

double sr_inspect_scale_range(double tolerance_mm, double allowance_mm)
{
    double r = fmax(2 * allowance_mm, 5 * tolerance_mm);
    return r > 0 && isfinite(r) ? r : 1.0;
}

void sr_inspect_scale(double tolerance_mm, double allowance_mm, double at[SR_INSPECT_SCALE_STOPS],
                      unsigned rgb[SR_INSPECT_SCALE_STOPS])
{
    static const unsigned c[SR_INSPECT_SCALE_STOPS] = {0x1c3f9e, 0x8fc1f0, 0x36a852,
                                                       0x36a852, 0xffd166, 0xc0261b};
    double r = sr_inspect_scale_range(tolerance_mm, allowance_mm), t = fmin(tolerance_mm, r);
    const double a[SR_INSPECT_SCALE_STOPS] = {-r, -t, -t, t, t, r};
    for (int i = 0; i < SR_INSPECT_SCALE_STOPS; i++) {
        at[i] = a[i];
        rgb[i] = c[i];
    }
}

void sr_inspect_colour(double tolerance_mm, double allowance_mm, double d, float rgb[3])
{
    double at[SR_INSPECT_SCALE_STOPS];
    unsigned c[SR_INSPECT_SCALE_STOPS];
    sr_inspect_scale(tolerance_mm, allowance_mm, at, c);
    int lo = 0, hi = 0;
    double f = 0;
    if (!(d > at[0])) {
        lo = hi = 0;
    } else if (d >= at[SR_INSPECT_SCALE_STOPS - 1]) {
        lo = hi = SR_INSPECT_SCALE_STOPS - 1;
    } else {
        for (int i = 0; i + 1 < SR_INSPECT_SCALE_STOPS; i++)
            if (d <= at[i + 1] && at[i + 1] > at[i]) {
                lo = i;
                hi = i + 1;
                f = (d - at[i]) / (at[i + 1] - at[i]);
                break;
            }
    }
    for (int k = 0; k < 3; k++) {
        double a = (double)((c[lo] >> (16 - 8 * k)) & 0xff) / 255.0;
        double b = (double)((c[hi] >> (16 - 8 * k)) & 0xff) / 255.0;
        rgb[k] = (float)(a + (b - a) * f);
    }
}
