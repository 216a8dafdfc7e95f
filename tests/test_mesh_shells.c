/*
 * test_mesh_shells.c: removal of small voids from a closed mesh (src/mesh/mesh_shells.h).
 * Known answers from boxes: a 10 mm cube holding a 2 mm cubic void (a shell turned
 * inward, -8 mm^3) loses the void when the limit allows it and keeps it otherwise;
 * solid shells are never removed, whatever their size; vertices only the void used are
 * gone and the rest keeps its order; bad limits are refused; small shells are counted.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "mesh/mesh.h"
#include "mesh/mesh_shells.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

static void box(sr_mesh *m, double a, double b)
{
    double lo[3] = {a, a, a}, hi[3] = {b, b, b};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

/* The 10 mm cube with a 2 mm void at its centre (the inner cube's faces flipped). */
static void cube_with_void(sr_mesh *m)
{
    sr_mesh inner;
    box(m, 0, 10);
    box(&inner, 4, 6);
    sr_mesh_flip(&inner);
    assert_int_equal(sr_mesh_append(m, &inner), SR_OK);
    sr_mesh_release(&inner);
    assert_near(sr_mesh_volume(m), 1000.0 - 8.0, 1e-9);
}

static void small_void_is_dropped_and_the_solid_kept(void **state)
{
    (void)state;
    sr_mesh m, outer;
    cube_with_void(&m);
    box(&outer, 0, 10);
    sr_void_report rep;
    assert_int_equal(sr_mesh_drop_voids(&m, 10.0, &rep, NULL), SR_OK);
    assert_int_equal(rep.shells, 2);
    assert_int_equal(rep.voids_dropped, 1);
    assert_near(rep.void_volume_mm3, 8.0, 1e-9);
    assert_near(sr_mesh_volume(&m), 1000.0, 1e-9);
    /* exactly the outer cube: its vertices and triangles, in order */
    assert_int_equal(m.vertex_count, outer.vertex_count);
    assert_int_equal(m.tri_count, outer.tri_count);
    assert_memory_equal(m.xyz, outer.xyz, 3 * outer.vertex_count * sizeof(double));
    assert_memory_equal(m.tri, outer.tri, 3 * outer.tri_count * sizeof(uint32_t));
    assert_true(sr_mesh_is_closed(&m));
    sr_mesh_release(&m);
    sr_mesh_release(&outer);
}

static void void_above_the_limit_is_kept(void **state)
{
    (void)state;
    sr_mesh m;
    cube_with_void(&m);
    size_t nt = m.tri_count, nv = m.vertex_count;
    sr_void_report rep;
    assert_int_equal(sr_mesh_drop_voids(&m, 7.9, &rep, NULL), SR_OK);
    assert_int_equal(rep.shells, 2);
    assert_int_equal(rep.voids_dropped, 0);
    assert_int_equal(m.tri_count, nt);
    assert_int_equal(m.vertex_count, nv);
    assert_near(sr_mesh_volume(&m), 992.0, 1e-9);
    sr_mesh_release(&m);
}

static void solid_shells_are_never_dropped(void **state)
{
    (void)state;
    sr_mesh m, small;
    box(&m, 0, 10);
    box(&small, 20, 20.1); /* a 0.001 mm^3 fleck */
    assert_int_equal(sr_mesh_append(&m, &small), SR_OK);
    sr_void_report rep;
    assert_int_equal(sr_mesh_drop_voids(&m, 1e9, &rep, NULL), SR_OK);
    assert_int_equal(rep.shells, 2);
    assert_int_equal(rep.voids_dropped, 0);
    assert_int_equal(m.tri_count, 24);
    sr_mesh_release(&m);
    sr_mesh_release(&small);
}

static void bad_limit_is_refused_and_empty_mesh_is_fine(void **state)
{
    (void)state;
    sr_mesh m;
    cube_with_void(&m);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_drop_voids(&m, -1.0, NULL, &err), SR_E_RANGE);
    assert_msg_has(err, "bad largest void -1 mm^3");
    assert_int_equal(sr_mesh_drop_voids(&m, NAN, NULL, &err), SR_E_RANGE);
    assert_int_equal(sr_mesh_drop_voids(&m, INFINITY, NULL, &err), SR_E_RANGE);
    assert_int_equal(m.tri_count, 24);
    sr_mesh empty = {0};
    sr_void_report rep;
    assert_int_equal(sr_mesh_drop_voids(&empty, 1.0, &rep, NULL), SR_OK);
    assert_int_equal(rep.shells, 0);
    sr_mesh_release(&m);
}

/* The shells enclosing less than a limit, counted (solid or void): the cube with its
 * 8 mm^3 void and a 0.001 mm^3 fleck (three shells) has one below 0.01 mm^3, two below
 * 10; the mesh is unchanged. */
static void small_shells_are_counted(void **state)
{
    (void)state;
    sr_mesh m, fleck;
    cube_with_void(&m);
    box(&fleck, 20, 20.1);
    assert_int_equal(sr_mesh_append(&m, &fleck), SR_OK);
    size_t nt = m.tri_count, shells = 0;
    assert_int_equal(sr_mesh_count_small_shells(&m, 0.01, &shells), 1);
    assert_int_equal(shells, 3);
    assert_int_equal(sr_mesh_count_small_shells(&m, 10.0, NULL), 2);
    assert_int_equal(sr_mesh_count_small_shells(&m, 1e-4, NULL), 0);
    assert_int_equal(m.tri_count, nt);
    sr_mesh empty = {0};
    assert_int_equal(sr_mesh_count_small_shells(&empty, 1.0, &shells), 0);
    assert_int_equal(shells, 0);
    sr_mesh_release(&m);
    sr_mesh_release(&fleck);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(small_void_is_dropped_and_the_solid_kept),
        cmocka_unit_test(void_above_the_limit_is_kept),
        cmocka_unit_test(solid_shells_are_never_dropped),
        cmocka_unit_test(bad_limit_is_refused_and_empty_mesh_is_fine),
        cmocka_unit_test(small_shells_are_counted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
