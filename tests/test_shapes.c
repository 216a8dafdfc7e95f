/*
 * test_shapes.c: parametric solids (revolve, cylinder, box, prism) and the demo
 * catalogue's parts. Each solid is checked against its closed-form volume (a regular
 * n-gon prism for anything round: area = n/2 r^2 sin(2pi/n)), closedness and
 * orientation from the mesh module, and every rejected option has its own case.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "mesh/shapes.h"
#include "base/symmetry.h"
#include "support/assert_near.h"

#define PI 3.14159265358979323846

/* Area of the regular n-gon of circumradius r. */
static double ngon_area(size_t n, double r)
{
    return 0.5 * (double)n * r * r * sin(2 * PI / (double)n);
}

/* Perimeter of the regular n-gon of circumradius r. */
static double ngon_perimeter(size_t n, double r)
{
    return (double)n * 2 * r * sin(PI / (double)n);
}

/* Closed, consistently oriented, no zero-area triangle, finite. */
static void assert_sound(const sr_mesh *m)
{
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    assert_int_equal(e.boundary_edges, 0);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_int_equal(e.misoriented_edges, 0);
    assert_true(sr_mesh_is_closed(m));
    sr_mesh_report r;
    assert_int_equal(sr_mesh_validate(m, "shape", &r, NULL), SR_OK);
    assert_int_equal(r.degenerate_tris, 0);
    /* Euler characteristic of a sphere-like closed surface: V - E + F = 2. */
    assert_int_equal((long)m->vertex_count - (long)e.edge_count + (long)m->tri_count, 2);
}

static void assert_rel(double got, double want, double rel)
{
    assert_near(got, want, rel * fabs(want));
}

/* A mesh the failing calls must leave untouched. */
static sr_mesh sentinel(void)
{
    sr_mesh m = {0};
    m.vertex_count = 12345;
    return m;
}

static void assert_untouched(const sr_mesh *m)
{
    assert_null(m->xyz);
    assert_null(m->tri);
    assert_int_equal(m->vertex_count, 12345);
}

/* ---- radius functions for revolve ---- */

static double radius_const(double theta, size_t ring, void *user)
{
    return *(const double *)user;
}

static double radius_table(double theta, size_t ring, void *user)
{
    return ((const double *)user)[ring];
}

/* Per-ring outer and inner radii (constant round each ring). */
typedef struct ring_table {
    const double *outer;
    const double *inner;
} ring_table;

static double table_outer(double theta, size_t ring, void *user)
{
    return ((const ring_table *)user)->outer[ring];
}

static double table_inner(double theta, size_t ring, void *user)
{
    return ((const ring_table *)user)->inner[ring];
}

static double radius_zero(double theta, size_t ring, void *user)
{
    return 0;
}

static double radius_nan_on_ring1(double theta, size_t ring, void *user)
{
    return ring == 1 ? NAN : 10;
}

/* ---- cylinder, box, revolve ---- */

static void cylinder_volume_is_regular_prism_formula_and_closed(void **state)
{
    sr_mesh m = {0};
    assert_int_equal(sr_shape_cylinder(10, -5, 15, 64, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_int_equal(m.vertex_count, 2 * 64 + 2);
    assert_int_equal(m.tri_count, 4 * 64);
    assert_rel(sr_mesh_volume(&m), ngon_area(64, 10) * 20, 1e-9);
    assert_rel(sr_mesh_area(&m), 2 * ngon_area(64, 10) + ngon_perimeter(64, 10) * 20, 1e-9);
    double lo[3], hi[3];
    sr_mesh_bbox(&m, lo, hi);
    assert_near(lo[2], -5, 0);
    assert_near(hi[2], 15, 0);
    assert_near(hi[0], 10, 1e-12); /* vertex 0 sits at theta = 0 */
    sr_mesh_release(&m);
}

static void triangular_cylinder_with_three_segments_is_exact(void **state)
{
    sr_mesh m = {0};
    assert_int_equal(sr_shape_cylinder(2, 0, 1, 3, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_rel(sr_mesh_volume(&m), 3 * sqrt(3) / 4 * 4, 1e-12);
    sr_mesh_release(&m);
}

static void box_volume_area_and_bbox_are_exact(void **state)
{
    const double lo[3] = {1, -2, 3}, hi[3] = {4, 2, 8};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_int_equal(m.tri_count, 12);
    assert_near(sr_mesh_volume(&m), 3 * 4 * 5, 1e-12);
    assert_near(sr_mesh_area(&m), 2 * (12 + 15 + 20), 1e-12);
    double bl[3], bh[3];
    sr_mesh_bbox(&m, bl, bh);
    for (int k = 0; k < 3; k++) {
        assert_near(bl[k], lo[k], 0);
        assert_near(bh[k], hi[k], 0);
    }
    sr_mesh_release(&m);
}

static void revolve_with_constant_radius_equals_cylinder(void **state)
{
    double r = 7.5, z[3] = {0, 4, 12};
    sr_revolve_opts o = {.segments = 40, .ring_count = 3, .ring_z = z, .outer = radius_const,
                         .user = &r};
    sr_mesh m = {0}, c = {0};
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    assert_int_equal(sr_shape_cylinder(r, 0, 12, 40, &c, NULL), SR_OK);
    assert_sound(&m);
    assert_rel(sr_mesh_volume(&m), sr_mesh_volume(&c), 1e-12);
    assert_rel(sr_mesh_volume(&m), ngon_area(40, r) * 12, 1e-9);
    assert_rel(sr_mesh_area(&m), sr_mesh_area(&c), 1e-12);
    assert_int_equal(m.tri_count, c.tri_count + 2 * 40); /* one more band */
    sr_mesh_release(&m);
    sr_mesh_release(&c);
}

static void hollow_revolve_volume_is_outer_minus_inner(void **state)
{
    const double z[2] = {0, 60}, ro[2] = {25, 25}, ri[2] = {15, 15};
    ring_table t = {ro, ri};
    sr_revolve_opts o = {.segments = 72, .ring_count = 2, .ring_z = z, .outer = table_outer,
                         .inner = table_inner, .user = &t};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    assert_int_equal(m.vertex_count, 4 * 72);
    /* A torus-like closed surface: V - E + F = 0, so assert_sound's sphere check does
     * not apply; check the parts of it that do. */
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_true(sr_mesh_is_closed(&m));
    assert_int_equal((long)m.vertex_count - (long)e.edge_count + (long)m.tri_count, 0);
    sr_mesh_report r;
    assert_int_equal(sr_mesh_validate(&m, "bushing", &r, NULL), SR_OK);
    assert_int_equal(r.degenerate_tris, 0);
    assert_rel(sr_mesh_volume(&m), (ngon_area(72, 25) - ngon_area(72, 15)) * 60, 1e-9);
    assert_rel(sr_mesh_area(&m),
               (ngon_perimeter(72, 25) + ngon_perimeter(72, 15)) * 60 +
                   2 * (ngon_area(72, 25) - ngon_area(72, 15)),
               1e-9);
    sr_mesh_release(&m);
}

static void stepped_revolve_with_two_rings_at_one_z_is_closed_and_exact(void **state)
{
    /* The demo shaft's profile: dia 40 to z 50, dia 60 to z 70, dia 30 to z 100. */
    const double z[6] = {0, 50, 50, 70, 70, 100}, r[6] = {20, 20, 30, 30, 15, 15};
    const size_t n = 48;
    sr_revolve_opts o = {.segments = n, .ring_count = 6, .ring_z = z, .outer = radius_table,
                         .user = (void *)r};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_int_equal(m.tri_count, 5 * 2 * n + 2 * n);
    assert_rel(sr_mesh_volume(&m),
               ngon_area(n, 20) * 50 + ngon_area(n, 30) * 20 + ngon_area(n, 15) * 30, 1e-9);
    /* The two flat annuli are there: the area counts both steps. */
    double lateral = ngon_perimeter(n, 20) * 50 + ngon_perimeter(n, 30) * 20 +
                     ngon_perimeter(n, 15) * 30;
    double flat = ngon_area(n, 20) + (ngon_area(n, 30) - ngon_area(n, 20)) +
                  (ngon_area(n, 30) - ngon_area(n, 15)) + ngon_area(n, 15);
    assert_rel(sr_mesh_area(&m), lateral + flat, 1e-9);
    sr_mesh_release(&m);
}

static void hollow_revolve_steps_its_wall_where_the_bore_is_straight(void **state)
{
    /* Outer wall steps from 25 to 20 at z = 30; the bore (10) has two identical rings
     * there, which share their vertices instead of making a zero-area band. */
    const double z[4] = {0, 30, 30, 60}, ro[4] = {25, 25, 20, 20}, ri[4] = {10, 10, 10, 10};
    ring_table t = {ro, ri};
    const size_t n = 36;
    sr_revolve_opts o = {.segments = n, .ring_count = 4, .ring_z = z, .outer = table_outer,
                         .inner = table_inner, .user = &t};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(&m));
    sr_mesh_report r;
    assert_int_equal(sr_mesh_validate(&m, "sleeve", &r, NULL), SR_OK);
    assert_int_equal(r.degenerate_tris, 0);
    assert_int_equal(m.vertex_count, (4 + 3) * n);
    assert_rel(sr_mesh_volume(&m),
               (ngon_area(n, 25) - ngon_area(n, 10)) * 30 +
                   (ngon_area(n, 20) - ngon_area(n, 10)) * 30,
               1e-9);
    sr_mesh_release(&m);
}

static void revolve_puts_ring_vertices_at_their_angle_and_radius(void **state)
{
    const double z[2] = {1, 3}, r[2] = {4, 6};
    sr_revolve_opts o = {.segments = 4, .ring_count = 2, .ring_z = z, .outer = radius_table,
                         .user = (void *)r};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    /* Ring 1, k = 1: theta = pi/2, so (0, 6, 3). */
    const double *p = m.xyz + 3 * (1 * 4 + 1);
    assert_near(p[0], 0, 1e-12);
    assert_near(p[1], 6, 1e-12);
    assert_near(p[2], 3, 0);
    /* A frustum: h/3 (A1 + A2 + sqrt(A1 A2)) with squares of half-diagonal 4 and 6. */
    assert_rel(sr_mesh_volume(&m), 2.0 / 3 * (32 + 72 + sqrt(32 * 72)), 1e-12);
    sr_mesh_release(&m);
}

/* ---- prism ---- */

static void prism_of_l_shaped_polygon_is_closed_with_area_times_height(void **state)
{
    /* Non-convex: the reflex corner at (1, 1). Area 4 + 2 = 6, perimeter 14. */
    const double xy[] = {0, 0, 4, 0, 4, 1, 1, 1, 1, 3, 0, 3};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_prism(xy, 6, -1, 1.5, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_int_equal(m.tri_count, 2 * 4 + 2 * 6);
    assert_near(sr_mesh_volume(&m), 6 * 2.5, 1e-12);
    assert_near(sr_mesh_area(&m), 2 * 6 + 14 * 2.5, 1e-12);
    sr_mesh_release(&m);
}

static void prism_caps_stay_inside_a_comb_polygon(void **state)
{
    /* A comb with three teeth: any cap triangle crossing a gap would add area, so the
     * area check catches a wrong ear. Area 7x2 base + 3 teeth 1x3 = 23. */
    const double xy[] = {0, 0, 7, 0, 7, 5, 6, 5, 6, 2, 4, 2, 4, 5, 3, 5, 3, 2, 1, 2, 1, 5, 0, 5};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_prism(xy, 12, 0, 1, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_near(sr_mesh_volume(&m), 23, 1e-12);
    /* Top cap alone: the area of the triangles facing +z. */
    double cap = 0;
    for (size_t t = 0; t < m.tri_count; t++) {
        const double *a = m.xyz + 3 * m.tri[3 * t], *b = m.xyz + 3 * m.tri[3 * t + 1],
                     *c = m.xyz + 3 * m.tri[3 * t + 2];
        if (a[2] == 1 && b[2] == 1 && c[2] == 1) {
            double cr = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert_true(cr > 0);
            cap += cr / 2;
        }
    }
    assert_near(cap, 23, 1e-12);
    sr_mesh_release(&m);
}

static void prism_with_collinear_points_has_no_zero_area_triangle(void **state)
{
    /* A square with an extra point in the middle of two sides; the clipping starts at
     * point 0, which is one of them. */
    const double xy[] = {1, 0, 2, 0, 2, 2, 0, 2, 0, 1, 0, 0};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_prism(xy, 6, 0, 3, &m, NULL), SR_OK);
    assert_sound(&m);
    assert_near(sr_mesh_volume(&m), 12, 1e-12);
    sr_mesh_release(&m);
}

/* ---- demo parts ---- */

static void demo_catalogue_lists_four_described_parts(void **state)
{
    assert_int_equal(sr_demo_part_count(), 4);
    const char *numbers[4] = {"SR-SHAFT-01", "SR-BUSH-02", "SR-BRKT-03", "SR-RAIL-04"};
    const int kinds[4] = {SR_SYM_AXIAL, SR_SYM_AXIAL, SR_SYM_MIRROR, SR_SYM_GLIDE};
    for (size_t i = 0; i < 4; i++) {
        const sr_demo_part *p = sr_demo_part_get(i);
        assert_non_null(p);
        assert_string_equal(p->number, numbers[i]);
        assert_int_equal(p->sym_kind, kinds[i]);
        assert_int_equal(p->sym_order, 0);
        assert_true(p->name && *p->name && p->material && *p->material && p->notes &&
                    *p->notes && p->serial && *p->serial && p->damage_notes &&
                    *p->damage_notes);
        sr_symmetry s = {(sr_sym_kind)p->sym_kind, p->sym_order, p->sym_shift_mm};
        assert_int_equal(sr_symmetry_check(&s, NULL), SR_OK);
    }
    assert_near(sr_demo_part_get(3)->sym_shift_mm, 10, 0);
    assert_null(sr_demo_part_get(4));
}

static void demo_part_build_refuses_an_index_past_the_end(void **state)
{
    sr_mesh a = sentinel(), b = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_demo_part_build(4, &a, &b, &err), SR_E_RANGE);
    assert_msg_has(err, "demo part 4");
    assert_untouched(&a);
    assert_untouched(&b);
}

/* Builds part i, checks both meshes and the missing fraction; returns the meshes. */
static void check_demo_part(size_t i, sr_mesh *intact, sr_mesh *damaged)
{
    sr_err err = {{0}};
    assert_int_equal(sr_demo_part_build(i, intact, damaged, &err), SR_OK);
    assert_true(intact->tri_count <= 5000 && damaged->tri_count <= 5000);
    sr_mesh_edges e;
    const sr_mesh *both[2] = {intact, damaged};
    for (int k = 0; k < 2; k++) {
        assert_int_equal(sr_mesh_edge_stats(both[k], &e), SR_OK);
        assert_int_equal(e.boundary_edges + e.nonmanifold_edges + e.misoriented_edges, 0);
        assert_true(sr_mesh_is_closed(both[k]));
        sr_mesh_report r;
        assert_int_equal(sr_mesh_validate(both[k], "demo", &r, NULL), SR_OK);
        assert_int_equal(r.degenerate_tris, 0);
    }
    double vi = sr_mesh_volume(intact), vd = sr_mesh_volume(damaged);
    assert_true(vd > 0 && vd < vi);
    double f = (vi - vd) / vi;
    assert_true(f >= 0.005 && f <= 0.25);
}

/* Every vertex of m mapped by (x, y, z) -> (sx x, y, z + dz) is a vertex of m (to 1e-9),
 * for the vertices with z in [zlo, zhi]. Returns how many had no image. */
static size_t vertices_without_image(const sr_mesh *m, double sx, double dz, double zlo,
                                     double zhi)
{
    size_t missing = 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        if (p[2] < zlo || p[2] > zhi)
            continue;
        double q[3] = {sx * p[0], p[1], p[2] + dz};
        int found = 0;
        for (size_t w = 0; w < m->vertex_count && !found; w++) {
            const double *o = m->xyz + 3 * w;
            found = fabs(o[0] - q[0]) < 1e-9 && fabs(o[1] - q[1]) < 1e-9 &&
                    fabs(o[2] - q[2]) < 1e-9;
        }
        missing += !found;
    }
    return missing;
}

static void demo_shaft_is_closed_and_loses_a_chip_off_the_shoulder(void **state)
{
    sr_mesh a = {0}, b = {0};
    check_demo_part(0, &a, &b);
    /* Intact: the stepped profile's exact volume with 96 segments. */
    assert_rel(sr_mesh_volume(&a),
               ngon_area(96, 20) * 50 + ngon_area(96, 30) * 20 + ngon_area(96, 15) * 30, 1e-9);
    /* The chip is on +x near z = 50, and nowhere else: the bboxes of the vertices that
     * moved. */
    assert_int_equal(a.vertex_count, b.vertex_count);
    size_t moved = 0;
    for (size_t v = 0; v < a.vertex_count; v++) {
        const double *p = a.xyz + 3 * v, *q = b.xyz + 3 * v;
        if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2])
            continue;
        moved++;
        assert_true(p[2] >= 50 && p[2] < 64);
        assert_true(p[0] > 0 && fabs(atan2(p[1], p[0])) < 40 * PI / 180);
        assert_true(hypot(q[0], q[1]) >= 24 - 1e-9);
    }
    assert_true(moved > 0);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void demo_bushing_is_closed_and_keeps_its_bore(void **state)
{
    sr_mesh a = {0}, b = {0};
    check_demo_part(1, &a, &b);
    assert_rel(sr_mesh_volume(&a), (ngon_area(72, 25) - ngon_area(72, 15)) * 60, 1e-9);
    /* Only outer-wall vertices moved, by at most 4 mm, around azimuth 120 deg. */
    size_t moved = 0;
    for (size_t v = 0; v < a.vertex_count; v++) {
        const double *p = a.xyz + 3 * v, *q = b.xyz + 3 * v;
        double ra = hypot(p[0], p[1]), rb = hypot(q[0], q[1]);
        if (ra < 20) {
            assert_near(rb, 15, 1e-9);
            continue;
        }
        if (fabs(ra - rb) < 1e-12)
            continue;
        moved++;
        assert_true(rb >= 21 - 1e-9 && rb < ra);
        assert_true(p[2] > 20 && p[2] < 40);
        double az = atan2(p[1], p[0]) * 180 / PI;
        assert_true(az > 85 && az < 155);
    }
    assert_true(moved > 0);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void demo_bracket_is_mirror_symmetric_and_loses_its_right_ear(void **state)
{
    sr_mesh a = {0}, b = {0};
    check_demo_part(2, &a, &b);
    /* Reflected x -> -x (and re-oriented), the intact bracket has the same volume and
     * bbox, and every vertex lands on a vertex. */
    sr_mesh r = {0};
    assert_int_equal(sr_mesh_copy(&r, &a), SR_OK);
    static const double mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    sr_mesh_transform(&r, mirror);
    sr_mesh_flip(&r);
    assert_true(sr_mesh_is_closed(&r));
    assert_rel(sr_mesh_volume(&r), sr_mesh_volume(&a), 1e-12);
    double al[3], ah[3], rl[3], rh[3];
    sr_mesh_bbox(&a, al, ah);
    sr_mesh_bbox(&r, rl, rh);
    for (int k = 0; k < 3; k++) {
        assert_near(rl[k], al[k], 0);
        assert_near(rh[k], ah[k], 0);
    }
    assert_near(ah[0], 48, 0);
    /* Closed form, 12 thick: base 60 x 40 less the 16 x 8 slot, plus per ear a 10 x 16
     * strip and a half 12-gon of radius 8 (12 triangles of angle pi/12). Broken: one
     * ear replaced by the trapezoid up to the cut, (7 + 5) / 2 x 16. */
    double ear = 160 + 6 * 64 * sin(PI / 12);
    assert_rel(sr_mesh_volume(&a), 12 * (2400 - 128 + 2 * ear), 1e-12);
    assert_rel(sr_mesh_volume(&b), 12 * (2400 - 128 + ear + 96), 1e-12);
    assert_int_equal(vertices_without_image(&a, -1, 0, -1e9, 1e9), 0);
    /* The damaged one is not: its +x side ends at the break (x <= 37). */
    double dl[3], dh[3];
    sr_mesh_bbox(&b, dl, dh);
    assert_near(dl[0], -48, 0);
    assert_near(dh[0], 37, 0);
    assert_true(vertices_without_image(&b, -1, 0, -1e9, 1e9) > 0);
    sr_mesh_release(&r);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void demo_rail_has_glide_symmetry_and_a_chipped_tooth(void **state)
{
    sr_mesh a = {0}, b = {0};
    check_demo_part(3, &a, &b);
    double lo[3], hi[3];
    sr_mesh_bbox(&a, lo, hi);
    assert_near(lo[0], -hi[0], 0);
    assert_near(hi[0], 12, 0);
    assert_near(lo[2], -5, 0);
    assert_near(hi[2], 95, 0);
    /* Area 24 x 100 less ten notches 6 x 4.5, 16 thick. */
    assert_near(sr_mesh_volume(&a), (2400 - 10 * 27) * 16, 1e-9);
    /* The chip: trapezoid (7.5,53) (12,53) (12,64) (7.5,56), area 31.5, 16 thick. */
    assert_near(sr_mesh_volume(&a) - sr_mesh_volume(&b), 31.5 * 16, 1e-9);
    /* Away from the ends, the glide (x, y, z) -> (-x, y, z + 10) maps the notch corners
     * onto notch corners; the plain mirror x -> -x does not. */
    assert_int_equal(vertices_without_image(&a, -1, 10, -3, 83), 0);
    assert_true(vertices_without_image(&a, -1, 0, -3, 83) > 0);
    assert_true(vertices_without_image(&b, -1, 10, -3, 83) > 0);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void demo_part_build_accepts_null_outputs(void **state)
{
    sr_mesh d = {0};
    assert_int_equal(sr_demo_part_build(1, NULL, &d, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(&d));
    sr_mesh_release(&d);
    assert_int_equal(sr_demo_part_build(0, NULL, NULL, NULL), SR_OK);
}

/* The volumes fixtures/README.md publishes (to its 6 decimals): if a builder changes,
 * this fails before the table goes stale. */
static void fixtures_have_the_volumes_in_fixtures_readme(void **state)
{
    sr_mesh m = {0};
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    assert_near(sr_mesh_volume(&m), 6000, 1e-9);
    sr_mesh_release(&m);
    assert_int_equal(sr_shape_cylinder(10, 0, 20, 64, &m, NULL), SR_OK);
    assert_near(sr_mesh_volume(&m), 6273.096981, 1e-6);
    sr_mesh_release(&m);
    const double l[] = {0, 0, 40, 0, 40, 10, 10, 10, 10, 30, 0, 30};
    assert_int_equal(sr_shape_prism(l, 6, 0, 5, &m, NULL), SR_OK);
    assert_near(sr_mesh_volume(&m), 3000, 1e-9);
    sr_mesh_release(&m);
    const double tz[2] = {0, 60}, tro[2] = {25, 25}, tri[2] = {15, 15};
    ring_table t = {tro, tri};
    sr_revolve_opts o = {.segments = 72, .ring_count = 2, .ring_z = tz, .outer = table_outer,
                         .inner = table_inner, .user = &t};
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    assert_near(sr_mesh_volume(&m), 75302.561734, 1e-6);
    sr_mesh_release(&m);
    const double sz[6] = {0, 50, 50, 70, 70, 100}, sr[6] = {20, 20, 30, 30, 15, 15};
    sr_revolve_opts so = {.segments = 48, .ring_count = 6, .ring_z = sz,
                          .outer = radius_table, .user = (void *)sr};
    assert_int_equal(sr_shape_revolve(&so, &m, NULL), SR_OK);
    assert_near(sr_mesh_volume(&m), 140185.130444, 1e-6);
    sr_mesh_release(&m);

    const double demo[4][2] = {{140485.921586, 139246.710275},
                               {75302.561734, 74017.048054},
                               {33489.276320, 31528.638160},
                               {34080, 33576}};
    for (size_t i = 0; i < 4; i++) {
        sr_mesh a = {0}, b = {0};
        assert_int_equal(sr_demo_part_build(i, &a, &b, NULL), SR_OK);
        assert_near(sr_mesh_volume(&a), demo[i][0], 1e-6);
        assert_near(sr_mesh_volume(&b), demo[i][1], 1e-6);
        sr_mesh_release(&a);
        sr_mesh_release(&b);
    }
}

/* ---- rejected options, each its own case ---- */

static sr_status revolve_with(size_t segments, size_t rings, const double *z,
                              sr_ring_radius_fn outer, sr_ring_radius_fn inner, void *user,
                              sr_err *err)
{
    sr_revolve_opts o = {.segments = segments, .ring_count = rings, .ring_z = z,
                         .outer = outer, .inner = inner, .user = user};
    sr_mesh m = sentinel();
    sr_status st = sr_shape_revolve(&o, &m, err);
    assert_untouched(&m);
    return st;
}

static void revolve_refuses_two_segments(void **state)
{
    double r = 1, z[2] = {0, 1};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(2, 2, z, radius_const, NULL, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "'segments' is 2");
}

static void revolve_refuses_a_single_ring(void **state)
{
    double r = 1, z[1] = {0};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 1, z, radius_const, NULL, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "'ring_count' is 1");
}

static void revolve_refuses_decreasing_heights(void **state)
{
    double r = 1, z[3] = {0, 5, 4};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 3, z, radius_const, NULL, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "'ring_z[2]'");
}

static void revolve_refuses_rings_all_at_one_height(void **state)
{
    double r = 1, z[2] = {3, 3};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 2, z, radius_const, NULL, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "'ring_z'");
}

static void revolve_refuses_a_zero_radius(void **state)
{
    double z[2] = {0, 1};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 2, z, radius_zero, NULL, NULL, &err), SR_E_RANGE);
    assert_msg_has(err, "'outer' radius of ring 0");
}

static void revolve_refuses_a_nan_radius(void **state)
{
    double z[2] = {0, 1};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 2, z, radius_nan_on_ring1, NULL, NULL, &err),
                     SR_E_RANGE);
    assert_msg_has(err, "'outer' radius of ring 1");
}

static void revolve_refuses_a_nan_height(void **state)
{
    double r = 1, z[2] = {0, NAN};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 2, z, radius_const, NULL, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "'ring_z[1]'");
}

static void revolve_refuses_inner_radius_not_below_outer(void **state)
{
    const double z[2] = {0, 1}, ro[2] = {5, 5}, ri[2] = {3, 5};
    ring_table t = {ro, ri};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 2, z, table_outer, table_inner, &t, &err), SR_E_RANGE);
    assert_msg_has(err, "'inner' radius of ring 1");
}

static void revolve_refuses_a_missing_radius_function(void **state)
{
    double z[2] = {0, 1};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 2, z, NULL, NULL, NULL, &err), SR_E_RANGE);
    assert_msg_has(err, "'outer'");
}

static double radius_crossing(double theta, size_t ring, void *user)
{
    /* Ring 1 is 5 round the half with theta < pi, ring 2 is 5 elsewhere: they cross. */
    if (ring == 0)
        return 4;
    if (ring == 1)
        return theta < PI ? 5 : 6;
    return theta < PI ? 6 : 5;
}

static void revolve_refuses_a_flat_step_whose_rings_cross(void **state)
{
    double z[4] = {0, 1, 1, 2};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 4, z, radius_crossing, NULL, NULL, &err), SR_E_RANGE);
    assert_msg_has(err, "rings 1 and 2");
}

static void revolve_refuses_an_inward_step_at_the_bottom(void **state)
{
    /* Bottom cap at r = 10 with a flat step in to r = 5 on the same plane: overlap. */
    const double z[3] = {0, 0, 4}, r[3] = {10, 5, 5};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 3, z, radius_table, NULL, (void *)r, &err), SR_E_RANGE);
    assert_msg_has(err, "bottom");
}

static void revolve_refuses_a_step_out_and_back_in(void **state)
{
    const double z[5] = {0, 2, 2, 2, 4}, r[5] = {5, 5, 8, 6, 6};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 5, z, radius_table, NULL, (void *)r, &err), SR_E_RANGE);
    assert_msg_has(err, "out and back in");
}

static void revolve_refuses_a_hollow_step_that_splits_the_wall(void **state)
{
    /* Wall 8..10 below z = 2, 2..4 above: the two annuli do not overlap. */
    const double z[4] = {0, 2, 2, 4}, ro[4] = {10, 10, 4, 4}, ri[4] = {8, 8, 2, 2};
    ring_table t = {ro, ri};
    sr_err err = {{0}};
    assert_int_equal(revolve_with(8, 4, z, table_outer, table_inner, &t, &err), SR_E_RANGE);
    assert_msg_has(err, "do not overlap");
}

static void cylinder_refuses_bad_radius_heights_and_segments(void **state)
{
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_cylinder(0, 0, 1, 8, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "'r'");
    assert_int_equal(sr_shape_cylinder(NAN, 0, 1, 8, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "'r'");
    assert_int_equal(sr_shape_cylinder(1, 1, 1, 8, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "'z1'");
    assert_int_equal(sr_shape_cylinder(1, 0, 1, 2, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "'segments'");
    assert_untouched(&m);
}

static void box_refuses_max_not_above_min(void **state)
{
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 0, 1};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_box(lo, hi, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "'max[1]'");
    assert_untouched(&m);
}

static void prism_refuses_a_clockwise_polygon(void **state)
{
    const double xy[] = {0, 0, 0, 1, 1, 1, 1, 0};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 4, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "clockwise");
    assert_untouched(&m);
}

static void prism_refuses_fewer_than_three_points(void **state)
{
    const double xy[] = {0, 0, 1, 0};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 2, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "has 2 points");
    assert_untouched(&m);
}

static void prism_refuses_a_self_crossing_polygon(void **state)
{
    /* A bow tie. */
    const double xy[] = {0, 0, 1, 1, 1, 0, 0, 1};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 4, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "edges 0 and 2 touch");
    assert_untouched(&m);
}

static void prism_refuses_a_polygon_touching_itself_at_a_vertex(void **state)
{
    /* Two squares meeting at the corner (1, 1), walked as one outline. */
    const double xy[] = {0, 0, 1, 0, 1, 1, 2, 1, 2, 2, 1, 2, 1, 1, 0, 1};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 8, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "not simple");
    assert_untouched(&m);
}

static void prism_refuses_a_vertex_lying_on_another_edge(void **state)
{
    /* Point 3 (2, 0) sits in the middle of edge 0. */
    const double xy[] = {0, 0, 4, 0, 4, 4, 2, 0, 0, 4};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 5, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "edges 0 and 2 touch");
    assert_untouched(&m);
}

static void prism_refuses_repeated_consecutive_points(void **state)
{
    const double xy[] = {0, 0, 1, 0, 1, 0, 0, 1};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 4, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "points 1 and 2 coincide");
    assert_untouched(&m);
}

static void prism_refuses_a_polygon_folding_back_on_itself(void **state)
{
    const double xy[] = {0, 0, 2, 0, 1, 0};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 3, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "folds back");
    assert_untouched(&m);
}

static void prism_refuses_a_nan_point(void **state)
{
    const double xy[] = {0, 0, 1, 0, NAN, 1};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 3, 0, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "point 2");
    assert_untouched(&m);
}

static void prism_refuses_z1_not_above_z0(void **state)
{
    const double xy[] = {0, 0, 1, 0, 0, 1};
    sr_mesh m = sentinel();
    sr_err err = {{0}};
    assert_int_equal(sr_shape_prism(xy, 3, 2, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "'z1'");
    assert_untouched(&m);
}

static void failures_without_an_err_still_return_the_status(void **state)
{
    const double xy[] = {0, 0, 0, 1, 1, 0};
    sr_mesh m = sentinel();
    assert_int_equal(sr_shape_prism(xy, 3, 0, 1, &m, NULL), SR_E_RANGE);
    assert_int_equal(sr_shape_cylinder(-1, 0, 1, 8, &m, NULL), SR_E_RANGE);
    assert_untouched(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cylinder_volume_is_regular_prism_formula_and_closed),
        cmocka_unit_test(triangular_cylinder_with_three_segments_is_exact),
        cmocka_unit_test(box_volume_area_and_bbox_are_exact),
        cmocka_unit_test(revolve_with_constant_radius_equals_cylinder),
        cmocka_unit_test(hollow_revolve_volume_is_outer_minus_inner),
        cmocka_unit_test(stepped_revolve_with_two_rings_at_one_z_is_closed_and_exact),
        cmocka_unit_test(hollow_revolve_steps_its_wall_where_the_bore_is_straight),
        cmocka_unit_test(revolve_puts_ring_vertices_at_their_angle_and_radius),
        cmocka_unit_test(prism_of_l_shaped_polygon_is_closed_with_area_times_height),
        cmocka_unit_test(prism_caps_stay_inside_a_comb_polygon),
        cmocka_unit_test(prism_with_collinear_points_has_no_zero_area_triangle),
        cmocka_unit_test(demo_catalogue_lists_four_described_parts),
        cmocka_unit_test(demo_part_build_refuses_an_index_past_the_end),
        cmocka_unit_test(demo_shaft_is_closed_and_loses_a_chip_off_the_shoulder),
        cmocka_unit_test(demo_bushing_is_closed_and_keeps_its_bore),
        cmocka_unit_test(demo_bracket_is_mirror_symmetric_and_loses_its_right_ear),
        cmocka_unit_test(demo_rail_has_glide_symmetry_and_a_chipped_tooth),
        cmocka_unit_test(demo_part_build_accepts_null_outputs),
        cmocka_unit_test(fixtures_have_the_volumes_in_fixtures_readme),
        cmocka_unit_test(revolve_refuses_two_segments),
        cmocka_unit_test(revolve_refuses_a_single_ring),
        cmocka_unit_test(revolve_refuses_decreasing_heights),
        cmocka_unit_test(revolve_refuses_rings_all_at_one_height),
        cmocka_unit_test(revolve_refuses_a_zero_radius),
        cmocka_unit_test(revolve_refuses_a_nan_radius),
        cmocka_unit_test(revolve_refuses_a_nan_height),
        cmocka_unit_test(revolve_refuses_inner_radius_not_below_outer),
        cmocka_unit_test(revolve_refuses_a_missing_radius_function),
        cmocka_unit_test(revolve_refuses_a_flat_step_whose_rings_cross),
        cmocka_unit_test(revolve_refuses_an_inward_step_at_the_bottom),
        cmocka_unit_test(revolve_refuses_a_step_out_and_back_in),
        cmocka_unit_test(revolve_refuses_a_hollow_step_that_splits_the_wall),
        cmocka_unit_test(cylinder_refuses_bad_radius_heights_and_segments),
        cmocka_unit_test(box_refuses_max_not_above_min),
        cmocka_unit_test(prism_refuses_a_clockwise_polygon),
        cmocka_unit_test(prism_refuses_fewer_than_three_points),
        cmocka_unit_test(prism_refuses_a_self_crossing_polygon),
        cmocka_unit_test(prism_refuses_a_polygon_touching_itself_at_a_vertex),
        cmocka_unit_test(prism_refuses_a_vertex_lying_on_another_edge),
        cmocka_unit_test(prism_refuses_repeated_consecutive_points),
        cmocka_unit_test(prism_refuses_a_polygon_folding_back_on_itself),
        cmocka_unit_test(prism_refuses_a_nan_point),
        cmocka_unit_test(prism_refuses_z1_not_above_z0),
        cmocka_unit_test(failures_without_an_err_still_return_the_status),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
