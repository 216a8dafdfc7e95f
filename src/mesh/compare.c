/*
 * compare.c: volumes and two-way surface deviation of two meshes (see compare.h). The
 * distance queries are boolean.h's sr_mesh_deviation (a CGAL AABB tree); this file
 * adds the denser sampling and the figures around it.
 */
#include "mesh/compare.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double tri_area(const double *p, const double *q, const double *r)
{
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                   u[0] * v[1] - u[1] * v[0]};
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/* Cuts of triangle t: k = ceil(sqrt(area / target)), at least 1. */
static size_t cuts(double area, double target)
{
    if (!(target > 0) || !(area > target))
        return 1;
    double k = ceil(sqrt(area / target));
    return k > 4096 ? 4096 : (size_t)k;
}

/* A mesh whose vertices and centroids are at least `samples` points spread over m's
 * surface by area: every triangle cut into k x k similar triangles on a lattice. */
static sr_status densify(const sr_mesh *m, size_t samples, sr_mesh *out, sr_err *err)
{
    double total = sr_mesh_area(m);
    /* a triangle cut k times gives (k+1)(k+2)/2 vertices and k^2 triangles: about
     * 1.5 k^2 samples, so aim at area / target = k^2 with 1.5 sum k^2 ~ samples */
    double target = total > 0 ? 1.5 * total / (double)samples : 0;
    size_t nv = 0, nt = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        size_t k = cuts(tri_area(m->xyz + 3 * f[0], m->xyz + 3 * f[1], m->xyz + 3 * f[2]),
                        target);
        nv += (k + 1) * (k + 2) / 2;
        nt += k * k;
        if (nv > SR_MESH_MAX_COUNT || nt > SR_MESH_MAX_COUNT)
            return sr_err_set(err, SR_E_RANGE, "too many samples (%zu asked)", samples);
    }
    sr_mesh d;
    if (sr_mesh_alloc(&d, nv, nt) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu samples", nv + nt);
    size_t v = 0, tt = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        const double *p0 = m->xyz + 3 * f[0], *p1 = m->xyz + 3 * f[1], *p2 = m->xyz + 3 * f[2];
        size_t k = cuts(tri_area(p0, p1, p2), target);
        size_t base = v;
        /* lattice point (i, j), i + j <= k, row by row in i */
        for (size_t i = 0; i <= k; i++)
            for (size_t j = 0; j + i <= k; j++) {
                double a = (double)i / (double)k, b = (double)j / (double)k;
                for (int c = 0; c < 3; c++)
                    d.xyz[3 * v + c] = p0[c] + a * (p1[c] - p0[c]) + b * (p2[c] - p0[c]);
                v++;
            }
        /* row i starts at offset i (k + 1) - i (i - 1) / 2 */
#define LAT(i, j) (base + (i) * (k + 1) - (i) * ((i) - 1) / 2 + (j) - 0)
        for (size_t i = 0; i < k; i++)
            for (size_t j = 0; j + i < k; j++) {
                uint32_t *o = d.tri + 3 * tt++;
                o[0] = (uint32_t)LAT(i, j);
                o[1] = (uint32_t)LAT(i + 1, j);
                o[2] = (uint32_t)LAT(i, j + 1);
                if (j + i + 1 < k) {
                    o = d.tri + 3 * tt++;
                    o[0] = (uint32_t)LAT(i + 1, j);
                    o[1] = (uint32_t)LAT(i + 1, j + 1);
                    o[2] = (uint32_t)LAT(i, j + 1);
                }
            }
#undef LAT
    }
    *out = d;
    return SR_OK;
}

/* Deviation of a's samples from b's surface, with the densified a when asked. */
static sr_status one_way(const sr_mesh *a, const char *a_what, const sr_mesh *b,
                         const char *b_what, size_t samples, sr_deviation *out, sr_err *err)
{
    sr_mesh dense;
    sr_mesh_init(&dense);
    const sr_mesh *src = a;
    sr_status st = SR_OK;
    if (samples > a->vertex_count + a->tri_count) {
        st = densify(a, samples, &dense, err);
        if (st != SR_OK)
            return st;
        src = &dense;
    }
    sr_err detail;
    sr_err_clear(&detail);
    st = sr_mesh_deviation(src, b, out, &detail);
    sr_mesh_release(&dense);
    if (st != SR_OK) {
        if (st == SR_E_INVALID && strstr(detail.msg, "reference mesh"))
            return sr_err_set(err, st, "cannot compare with '%s': it has no triangle of "
                              "non-zero area", b_what);
        return sr_err_set(err, st, "cannot compare '%s' with '%s': %s", a_what, b_what,
                          detail.msg);
    }
    return SR_OK;
}

sr_status sr_compare_meshes(const sr_mesh *a, const char *a_what, const sr_mesh *b,
                            const char *b_what, const sr_compare_opts *opts,
                            sr_compare_result *out, sr_err *err)
{
    if (!a_what)
        a_what = "first mesh";
    if (!b_what)
        b_what = "second mesh";
    size_t samples = opts ? opts->samples : 0;
    if (samples > SR_COMPARE_MAX_SAMPLES)
        return sr_err_set(err, SR_E_RANGE, "bad samples %zu: expected at most %zu", samples,
                          SR_COMPARE_MAX_SAMPLES);
    sr_status st = sr_mesh_validate(a, a_what, NULL, err);
    if (st == SR_OK)
        st = sr_mesh_validate(b, b_what, NULL, err);
    if (st != SR_OK)
        return st;
    sr_compare_result r;
    memset(&r, 0, sizeof r);
    r.volume_a_mm3 = sr_mesh_volume(a);
    r.volume_b_mm3 = sr_mesh_volume(b);
    r.area_a_mm2 = sr_mesh_area(a);
    r.area_b_mm2 = sr_mesh_area(b);
    r.closed_a = sr_mesh_is_closed(a);
    r.closed_b = sr_mesh_is_closed(b);
    r.volume_diff_mm3 = r.volume_b_mm3 - r.volume_a_mm3;
    r.volume_diff_pct =
        r.volume_a_mm3 != 0 ? 100.0 * r.volume_diff_mm3 / fabs(r.volume_a_mm3) : NAN;
    st = one_way(a, a_what, b, b_what, samples, &r.a_to_b, err);
    if (st == SR_OK)
        st = one_way(b, b_what, a, a_what, samples, &r.b_to_a, err);
    if (st != SR_OK)
        return st;
    r.hausdorff_mm = fmax(r.a_to_b.max_mm, r.b_to_a.max_mm);
    *out = r;
    return SR_OK;
}
