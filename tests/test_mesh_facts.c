/*
 * test_mesh_facts.c: sr_mesh_facts_get and sr_unit_guess (src/mesh/mesh_facts.c), on
 * meshes with known answers: a box (closed, outward, 12 triangles, volume and area
 * known), the same box turned inside out, with a face left off, with a triangle
 * repeated, a degenerate one added and a second box beside it; and the unit guesses.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "mesh/mesh_facts.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

static void box(double x0, sr_mesh *out)
{
    const double lo[3] = {x0, 0, 0}, hi[3] = {x0 + 10, 20, 30};
    assert_int_equal(sr_shape_box(lo, hi, out, NULL), SR_OK);
}

static void a_box_is_a_closed_outward_solid(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    sr_mesh_facts f;
    assert_int_equal(sr_mesh_facts_get(&m, &f, NULL), SR_OK);
    assert_int_equal(f.triangles, 12);
    assert_near(f.volume, 6000, 1e-9);
    assert_near(f.area, 2 * (200 + 300 + 600), 1e-9);
    assert_near(f.largest_extent, 30, 0);
    assert_true(f.closed && f.oriented && f.outward);
    assert_int_equal(f.components, 1);
    assert_int_equal(f.largest_component, 12);
    assert_int_equal(f.degenerate_triangles, 0);
    assert_int_equal(f.duplicate_triangles, 0);
    assert_string_equal(f.likely_unit, "mm");
    sr_mesh_release(&m);
}

static void faults_are_counted(void **state)
{
    (void)state;
    sr_mesh m, other;
    box(0, &m);
    /* inside out: every triangle turned */
    for (size_t t = 0; t < m.tri_count; t++) {
        uint32_t x = m.tri[3 * t + 1];
        m.tri[3 * t + 1] = m.tri[3 * t + 2];
        m.tri[3 * t + 2] = x;
    }
    sr_mesh_facts f;
    assert_int_equal(sr_mesh_facts_get(&m, &f, NULL), SR_OK);
    assert_true(f.closed && f.oriented && !f.outward);
    assert_near(f.volume, -6000, 1e-9);
    sr_mesh_release(&m);

    /* a second box beside, the first triangle repeated, a degenerate one, one left off */
    box(0, &m);
    box(50, &other);
    assert_int_equal(sr_mesh_append(&m, &other), SR_OK);
    sr_mesh grown;
    assert_int_equal(sr_mesh_alloc(&grown, m.vertex_count, m.tri_count + 1), SR_OK);
    memcpy(grown.xyz, m.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    memcpy(grown.tri, m.tri + 3, 3 * (m.tri_count - 1) * sizeof *m.tri);     /* first off */
    memcpy(grown.tri + 3 * (m.tri_count - 1), m.tri + 3, 3 * sizeof *m.tri); /* repeat */
    const uint32_t flat[3] = {0, 0, 1};
    memcpy(grown.tri + 3 * m.tri_count, flat, sizeof flat);
    assert_int_equal(sr_mesh_facts_get(&grown, &f, NULL), SR_OK);
    assert_int_equal(f.triangles, 25); /* 24 - 1 left off + 1 repeated + 1 flat */
    assert_int_equal(f.components, 2);
    assert_int_equal(f.duplicate_triangles, 1);
    assert_int_equal(f.degenerate_triangles, 1);
    assert_false(f.closed);
    assert_true(f.edges.boundary_edges >= 2);
    assert_near(f.largest_extent, 60, 0);
    sr_mesh_release(&grown);
    sr_mesh_release(&m);
    sr_mesh_release(&other);
}

static void the_unit_follows_the_size(void **state)
{
    (void)state;
    assert_string_equal(sr_unit_guess(0.12), "m"); /* a 120 mm part in metres */
    assert_string_equal(sr_unit_guess(2.5), "in"); /* a 63.5 mm part in inches */
    assert_string_equal(sr_unit_guess(5), "mm");
    assert_string_equal(sr_unit_guess(120), "mm");
    assert_string_equal(sr_unit_guess(3000), "mm");
    assert_string_equal(sr_unit_guess(120000), "um");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_box_is_a_closed_outward_solid),
        cmocka_unit_test(faults_are_counted),
        cmocka_unit_test(the_unit_follows_the_size),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
