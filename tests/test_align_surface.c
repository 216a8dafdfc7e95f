/*
 * test_align_surface.c: the alignment's surface search structure (src/align/align_surface.c,
 * private interface align_internal.h): the closest surface point from the brick grid
 * must be the one a brute-force scan of every triangle finds, on meshes that stress
 * the filing (a tilted cylinder whose end caps are fans of long thin triangles, a
 * mesh with a zero-area triangle), for queries on, near and far from the surface and
 * beyond max_dist; the recomputed normals and areas are the exact ones.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "align/align_internal.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

/* Squared distance from p to triangle t of m (brute force, by projection and edges). */
static double seg_d2(const double p[3], const double a[3], const double b[3])
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double t = v3_dot(ap, ab) / v3_dot(ab, ab);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return v3_dot(d, d);
}

static double tri_d2(const sr_mesh *m, size_t t, const double p[3])
{
    const double *a = m->xyz + 3 * (size_t)m->tri[3 * t], *b = m->xyz + 3 * (size_t)m->tri[3 * t + 1],
                 *c = m->xyz + 3 * (size_t)m->tri[3 * t + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3];
    v3_cross(u, w, n);
    if (v3_normalize(n) == 0)
        return INFINITY; /* zero-area: not part of the surface */
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double h = v3_dot(ap, n);
    double q[3] = {p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]};
    /* inside test by the signs of the sub-triangle normals */
    const double *v[3] = {a, b, c};
    int inside = 1;
    for (int k = 0; k < 3; k++) {
        const double *e0 = v[k], *e1 = v[(k + 1) % 3];
        double e[3] = {e1[0] - e0[0], e1[1] - e0[1], e1[2] - e0[2]};
        double r[3] = {q[0] - e0[0], q[1] - e0[1], q[2] - e0[2]}, x[3];
        v3_cross(e, r, x);
        if (v3_dot(x, n) < 0)
            inside = 0;
    }
    if (inside)
        return h * h;
    double d = seg_d2(p, a, b), d2 = seg_d2(p, b, c), d3 = seg_d2(p, c, a);
    d = d2 < d ? d2 : d;
    return d3 < d ? d3 : d;
}

static double brute_d2(const sr_mesh *m, const double p[3])
{
    double best = INFINITY;
    for (size_t t = 0; t < m->tri_count; t++) {
        double d = tri_d2(m, t, p);
        best = d < best ? d : best;
    }
    return best;
}

static uint64_t rng = 0x12345678u;
static double urand(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

/* Queries around the mesh's box (grown by `grow`), compared with brute force. */
static void check_queries(al_surface *s, const sr_mesh *m, int count, double grow,
                          double max_dist)
{
    double lo[3], hi[3];
    sr_mesh_bbox(m, lo, hi);
    int found = 0;
    for (int i = 0; i < count; i++) {
        double p[3];
        for (int k = 0; k < 3; k++)
            p[k] = lo[k] - grow + (hi[k] - lo[k] + 2 * grow) * urand();
        double q[3], n[3], dist;
        bool ok = al_surface_closest(s, p, max_dist, q, n, &dist);
        double want = sqrt(brute_d2(m, p));
        if (want <= max_dist * (1 - 1e-9)) {
            assert_true(ok);
            assert_near(dist, want, 1e-9 * (1 + want));
            assert_near(v3_norm(n), 1.0, 1e-12);
            found++;
        } else if (want > max_dist * (1 + 1e-9)) {
            assert_false(ok);
        }
    }
    assert_true(found > 0);
}

/* A cylinder r = 20, h = 30, 200 sides: its caps are fans of 200 triangles 20 mm long,
 * tilted so their boxes span many cells. */
static void closest_points_match_brute_force_on_a_tilted_fan_capped_cylinder(void **state)
{
    sr_mesh m;
    assert_int_equal(sr_shape_cylinder(20, 0, 30, 200, &m, NULL), SR_OK);
    double c = cos(0.5), sn = sin(0.5);
    double t[12] = {1, 0, 0, 3, 0, c, -sn, -4, 0, sn, c, 7};
    sr_mesh_transform(&m, t);
    al_surface s;
    assert_int_equal(al_surface_build(&s, &m, NULL), SR_OK);
    assert_int_equal(s.count, m.tri_count);
    check_queries(&s, &m, 400, 2.0, 100.0);  /* near and inside */
    check_queries(&s, &m, 200, 40.0, 100.0); /* far, outside the grid */
    check_queries(&s, &m, 300, 3.0, 1.0);    /* a short reach: some found, some not */
    /* points on the surface: distance 0 */
    al_samples smp;
    assert_int_equal(al_samples_make(&s, 100, 7, &smp), SR_OK);
    for (size_t i = 0; i < smp.count; i++) {
        double q[3], n[3], dist;
        assert_true(al_surface_closest(&s, smp.p + 3 * i, 1.0, q, n, &dist));
        assert_true(dist < 1e-9);
        assert_near(v3_norm(smp.n + 3 * i), 1.0, 1e-12);
    }
    al_samples_release(&smp);
    al_surface_release(&s);
    sr_mesh_release(&m);
}

/* A zero-area triangle is left out: the surface keeps its own triangle list. */
static void zero_area_triangle_is_left_out(void **state)
{
    sr_mesh m, extra;
    assert_int_equal(sr_shape_cylinder(10, 0, 10, 24, &m, NULL), SR_OK);
    assert_int_equal(sr_mesh_alloc(&extra, 3, 1), SR_OK);
    double v[9] = {0, 0, 50, 1, 0, 50, 2, 0, 50}; /* collinear, far above */
    memcpy(extra.xyz, v, sizeof v);
    extra.tri[0] = 0;
    extra.tri[1] = 1;
    extra.tri[2] = 2;
    assert_int_equal(sr_mesh_append(&m, &extra), SR_OK);
    sr_mesh_release(&extra);
    al_surface s;
    assert_int_equal(al_surface_build(&s, &m, NULL), SR_OK);
    assert_int_equal(s.count, m.tri_count - 1);
    assert_non_null(s.tri);
    double p[3] = {1, 0, 50}, q[3], n[3], dist;
    assert_true(al_surface_closest(&s, p, 100, q, n, &dist));
    assert_near(dist, 40.0, 1e-9); /* the top cap at z = 10, not the sliver */
    check_queries(&s, &m, 200, 5.0, 100.0);
    al_surface_release(&s);
    sr_mesh_release(&m);
}

/* The normal and area recomputed for a triangle are the build's (bit for bit: the
 * float copy rounds them) and the areas add up to the total. */
static void recomputed_normals_and_areas_are_exact(void **state)
{
    sr_mesh m;
    assert_int_equal(sr_shape_cylinder(20, 0, 30, 64, &m, NULL), SR_OK);
    al_surface s;
    assert_int_equal(al_surface_build(&s, &m, NULL), SR_OK);
    assert_null(s.tri); /* no zero-area triangle: the identity */
    double total = 0;
    for (size_t i = 0; i < s.count; i++) {
        double n[3], area;
        al_surface_normal(&s, i, n, &area);
        for (int k = 0; k < 3; k++)
            assert_true((float)n[k] == s.nrm[3 * i + k]);
        total += area;
    }
    assert_near(total, s.total_area, 1e-9 * total);
    assert_near(total, sr_mesh_area(&m), 1e-9 * total);
    al_surface_release(&s);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closest_points_match_brute_force_on_a_tilted_fan_capped_cylinder),
        cmocka_unit_test(zero_area_triangle_is_left_out),
        cmocka_unit_test(recomputed_normals_and_areas_are_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
