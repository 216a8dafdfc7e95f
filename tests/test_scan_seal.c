/*
 * test_scan_seal.c: sr_scan_seal (src/mesh/scan_seal.c), the last defects of a closed
 * scan cut out and closed again, on meshes with known answers. A cylinder r = 10 mm,
 * z 0..30, 96 sides (volume 48 * 100 * sin(2 pi / 96) * 30 mm^3): clean, it is left
 * as it is (nothing cut, the same triangles in the same order); with one of its side
 * triangles doubled (three edges used twice the same way) or with a flap standing out
 * of one side edge (used three times), the triangles round the defect go and the
 * opening they leave is closed: every edge used once each way, the volume within the
 * share of two of its sides (the fan over the opening cuts the caps' wedges it spans),
 * the flap's tip gone with it. A tetrahedron with a face doubled has nothing left
 * once its defect is cut out: it cannot be sealed and stays as it came.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "mesh/mesh.h"
#include "mesh/scan_describe.h"
#include "mesh/shapes.h"
#include "support/mesh_edit.h"

#define SIDES 96
#define CYLINDER_MM3 (SIDES / 2.0 * 100.0 * sin(2 * M_PI / SIDES) * 30.0)

static void cylinder(sr_mesh *m)
{
    assert_int_equal(sr_shape_cylinder(10, 0, 30, SIDES, m, NULL), SR_OK);
}

static bool closed_manifold(const sr_mesh *m)
{
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    return e.boundary_edges == 0 && e.nonmanifold_edges == 0 && e.misoriented_edges == 0;
}

/* The first triangle of m with a vertex at z = 0 and one at z = 30 (a side's). */
static size_t side_triangle(const sr_mesh *m)
{
    for (size_t t = 0; t < m->tri_count; t++) {
        bool lo = false, hi = false;
        for (int k = 0; k < 3; k++) {
            double z = m->xyz[3 * m->tri[3 * t + k] + 2];
            lo |= z == 0;
            hi |= z == 30;
        }
        if (lo && hi)
            return t;
    }
    fail_msg("no side triangle");
    return 0;
}

/* Seals m, which has a defect, and checks it closed with the cylinder's volume. */
static void sealed_closed(sr_mesh *m)
{
    assert_false(closed_manifold(m));
    size_t cut = 0;
    sr_err err = {{0}};
    assert_int_equal(sr_scan_seal(m, &cut, &err), SR_OK);
    assert_true(cut > 0);
    assert_true(closed_manifold(m));
    /* the opening, round a few sides and their caps' wedges, closed by a fan: the volume
     * within the share of two of the 96 sides */
    assert_true(fabs(sr_mesh_volume(m) - CYLINDER_MM3) <= 2.0 / SIDES * CYLINDER_MM3);
}

static void a_clean_closed_scan_is_left_as_it_is(void **state)
{
    (void)state;
    sr_mesh m, orig;
    cylinder(&m);
    assert_int_equal(sr_mesh_copy(&orig, &m), SR_OK);
    size_t cut = 1;
    assert_int_equal(sr_scan_seal(&m, &cut, NULL), SR_OK);
    assert_int_equal(cut, 0);
    assert_int_equal(m.tri_count, orig.tri_count);
    assert_int_equal(m.vertex_count, orig.vertex_count);
    assert_memory_equal(m.tri, orig.tri, 3 * m.tri_count * sizeof *m.tri);
    assert_memory_equal(m.xyz, orig.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    sr_mesh_release(&orig);
    sr_mesh_release(&m);
}

static void a_doubled_triangle_is_cut_out_and_closed(void **state)
{
    (void)state;
    sr_mesh m;
    cylinder(&m);
    size_t tris = m.tri_count, t = side_triangle(&m);
    test_add_triangle(&m, m.tri[3 * t], m.tri[3 * t + 1], m.tri[3 * t + 2]);
    sealed_closed(&m);
    assert_true(m.tri_count < 2 * tris); /* local: not the whole surface rebuilt */
    sr_mesh_release(&m);
}

static void a_flap_on_a_side_edge_is_cut_out_with_its_tip(void **state)
{
    (void)state;
    sr_mesh m;
    cylinder(&m);
    size_t t = side_triangle(&m);
    uint32_t a = m.tri[3 * t], b = m.tri[3 * t + 1];
    const double out[3] = {40, 40, 15}; /* far outside the cylinder */
    uint32_t v = test_add_vertex(&m, out);
    test_add_triangle(&m, a, b, v); /* a -> b used twice, b -> a once */
    sealed_closed(&m);
    for (size_t i = 0; i < m.vertex_count; i++)
        assert_true(hypot(m.xyz[3 * i], m.xyz[3 * i + 1]) <= 10 + 1e-9); /* the tip went */
    sr_mesh_release(&m);
}

static void a_defect_with_nothing_round_it_is_left_as_it_came(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_mesh_alloc(&m, 4, 4), SR_OK);
    const double p[12] = {0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 10};
    memcpy(m.xyz, p, sizeof p);
    const uint32_t tri[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    memcpy(m.tri, tri, sizeof tri);
    test_add_triangle(&m, 0, 2, 1);
    sr_mesh orig;
    assert_int_equal(sr_mesh_copy(&orig, &m), SR_OK);
    size_t cut = 1;
    sr_err err = {{0}};
    assert_int_equal(sr_scan_seal(&m, &cut, &err), SR_OK);
    assert_int_equal(cut, 0);
    assert_int_equal(m.tri_count, orig.tri_count);
    assert_memory_equal(m.tri, orig.tri, 3 * m.tri_count * sizeof *m.tri);
    sr_mesh_release(&orig);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_clean_closed_scan_is_left_as_it_is),
        cmocka_unit_test(a_doubled_triangle_is_cut_out_and_closed),
        cmocka_unit_test(a_flap_on_a_side_edge_is_cut_out_with_its_tip),
        cmocka_unit_test(a_defect_with_nothing_round_it_is_left_as_it_came),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
