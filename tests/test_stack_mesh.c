/*
 * test_stack_mesh.c: cross-section contours (contour_slice.h) and closed meshes from
 * stacks of planar regions (stack_mesh.h), on shapes with exact answers.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/polygon.h"
#include "slice/contour_slice.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "robust/stack_mesh.h"
#include "support/assert_near.h"
#include "support/heap_stir.h"
#include "support/test_select.h"

static void square(sr_poly2 *p, double x0, double y0, double side, int cw)
{
    double xy[8] = {x0, y0, x0 + side, y0, x0 + side, y0 + side, x0, y0 + side};
    if (cw) {
        double r[8] = {x0, y0, x0, y0 + side, x0 + side, y0 + side, x0 + side, y0};
        memcpy(xy, r, sizeof xy);
    }
    assert_int_equal(sr_poly2_add_contour(p, xy, 4, NULL), SR_OK);
}

static void check_closed(const sr_mesh *m)
{
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    assert_int_equal(e.boundary_edges, 0);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_int_equal(e.misoriented_edges, 0);
}

static void one_square_layer_is_a_closed_box(void **state)
{
    (void)state;
    sr_poly2 r = {0};
    square(&r, 0, 0, 10, 0);
    double z[2] = {0, 1};
    sr_mesh m = {0};
    assert_int_equal(sr_stack_mesh(&r, z, 1, &m, NULL), SR_OK);
    check_closed(&m);
    assert_near(sr_mesh_volume(&m), 100.0, 1e-9);
    assert_near(sr_mesh_area(&m), 2 * 100.0 + 4 * 10.0, 1e-9);
    sr_mesh_release(&m);
    sr_poly2_release(&r);
}

static void identical_layers_leave_no_internal_faces(void **state)
{
    (void)state;
    sr_poly2 r[3] = {{0}};
    for (int i = 0; i < 3; i++)
        square(&r[i], 0, 0, 10, 0);
    double z[4] = {0, 1, 2, 3};
    sr_mesh m = {0};
    assert_int_equal(sr_stack_mesh(r, z, 3, &m, NULL), SR_OK);
    check_closed(&m);
    assert_near(sr_mesh_volume(&m), 300.0, 1e-9);
    /* only the outer skin: two caps and four walls 3 high */
    assert_near(sr_mesh_area(&m), 2 * 100.0 + 4 * 10.0 * 3, 1e-9);
    for (int i = 0; i < 3; i++)
        sr_poly2_release(&r[i]);
    sr_mesh_release(&m);
}

/* Six layers: a 10 mm square three times (the third written from another corner),
 * an empty layer, then a 4 mm square twice. Merged: three runs over the same heights,
 * the same solid as the stack unmerged, and walls no longer cut at every layer. */
static void identical_layers_merge_into_runs(void **state)
{
    (void)state;
    sr_poly2 r[6] = {{0}}, whole[6] = {{0}};
    square(&r[0], 0, 0, 10, 0);
    square(&r[1], 0, 0, 10, 0);
    double turned[8] = {10, 10, 0, 10, 0, 0, 10, 0};
    assert_int_equal(sr_poly2_add_contour(&r[2], turned, 4, NULL), SR_OK);
    square(&r[4], 3, 3, 4, 0);
    square(&r[5], 3, 3, 4, 0);
    for (int i = 0; i < 6; i++)
        assert_int_equal(sr_poly2_copy(&r[i], &whole[i], NULL), SR_OK);
    double z[7] = {0, 1, 2, 3.5, 4, 5, 7}, zw[7];
    memcpy(zw, z, sizeof z);
    size_t layers = 6;
    assert_int_equal(sr_stack_merge_identical(r, z, &layers, NULL), SR_OK);
    assert_int_equal(layers, 3);
    double want_z[4] = {0, 3.5, 4, 7};
    for (int i = 0; i < 4; i++)
        assert_near(z[i], want_z[i], 0);
    assert_near(sr_poly2_area(&r[0]), 100.0, 1e-9);
    assert_int_equal(r[1].contour_count, 0);
    assert_near(sr_poly2_area(&r[2]), 16.0, 1e-9);
    for (int i = 3; i < 6; i++) /* merged away: released, safe to release again */
        assert_int_equal(r[i].contour_count, 0);
    sr_mesh m = {0}, mw = {0};
    assert_int_equal(sr_stack_mesh(r, z, layers, &m, NULL), SR_OK);
    assert_int_equal(sr_stack_mesh(whole, zw, 6, &mw, NULL), SR_OK);
    check_closed(&m);
    assert_near(sr_mesh_volume(&m), 100.0 * 3.5 + 16.0 * 3, 1e-9);
    assert_near(sr_mesh_volume(&m), sr_mesh_volume(&mw), 1e-9);
    assert_near(sr_mesh_area(&m), sr_mesh_area(&mw), 1e-9);
    /* one wall strip a run: 4 edges x 2 triangles x 2 runs, and 2 x 2 caps each */
    assert_int_equal(m.tri_count, 2 * (4 * 2 + 2 * 2));
    assert_true(mw.tri_count > m.tri_count);
    sr_mesh_release(&m);
    sr_mesh_release(&mw);
    for (int i = 0; i < 6; i++) {
        sr_poly2_release(&r[i]);
        sr_poly2_release(&whole[i]);
    }
}

/* Layers that differ at all stay apart: a square moved by 10 nm (one unit of the 2D
 * booleans) is another layer. One layer or none is left as it is. */
static void layers_that_differ_stay_apart(void **state)
{
    (void)state;
    sr_poly2 r[2] = {{0}};
    square(&r[0], 0, 0, 10, 0);
    square(&r[1], 1e-5, 0, 10, 0);
    double z[3] = {0, 1, 2};
    size_t layers = 2;
    assert_int_equal(sr_stack_merge_identical(r, z, &layers, NULL), SR_OK);
    assert_int_equal(layers, 2);
    assert_near(z[1], 1, 0);
    assert_near(z[2], 2, 0);
    assert_int_equal(r[1].contour_count, 1);
    layers = 1;
    assert_int_equal(sr_stack_merge_identical(r, z, &layers, NULL), SR_OK);
    assert_int_equal(layers, 1);
    layers = 0;
    assert_int_equal(sr_stack_merge_identical(r, z, &layers, NULL), SR_OK);
    assert_int_equal(layers, 0);
    for (int i = 0; i < 2; i++)
        sr_poly2_release(&r[i]);
}

static void shifted_and_rotated_layers_stitch_closed(void **state)
{
    (void)state;
    sr_poly2 r[3] = {{0}};
    square(&r[0], 0, 0, 10, 0);
    square(&r[1], 4, 3, 10, 0);             /* overlaps layer 0 by 6 x 7 */
    /* a square turned 45 degrees, centred on (9, 8), half-diagonal 6 */
    double d[8] = {15, 8, 9, 14, 3, 8, 9, 2};
    assert_int_equal(sr_poly2_add_contour(&r[2], d, 4, NULL), SR_OK);
    double z[4] = {0, 0.5, 1.25, 2};
    sr_mesh m = {0};
    assert_int_equal(sr_stack_mesh(r, z, 3, &m, NULL), SR_OK);
    check_closed(&m);
    assert_near(sr_mesh_volume(&m), 100 * 0.5 + 100 * 0.75 + 72 * 0.75, 1e-6);
    for (int i = 0; i < 3; i++)
        sr_poly2_release(&r[i]);
    sr_mesh_release(&m);
}

static void layers_with_holes_stitch_closed(void **state)
{
    (void)state;
    sr_poly2 r[2] = {{0}};
    square(&r[0], 0, 0, 10, 0);
    square(&r[0], 3, 3, 4, 1);              /* hole 4 x 4 */
    square(&r[1], 0, 0, 10, 0);
    square(&r[1], 2, 2, 4, 1);              /* hole moved: crosses the one below */
    double z[3] = {0, 1, 2};
    sr_mesh m = {0};
    assert_int_equal(sr_stack_mesh(r, z, 2, &m, NULL), SR_OK);
    check_closed(&m);
    assert_near(sr_mesh_volume(&m), 2 * (100 - 16), 1e-6);
    for (int i = 0; i < 2; i++)
        sr_poly2_release(&r[i]);
    sr_mesh_release(&m);
}

/* The same stack gives the same mesh, triangle for triangle, whatever the heap held
 * before: the arrangement's faces are capped in its own order, not their addresses'
 * (the heap stirred three ways between). Three layers of islands and holes. */
static void a_stack_is_one_mesh_whatever_the_heap_held(void **state)
{
    (void)state;
    sr_poly2 r[3] = {{0}};
    square(&r[0], 0, 0, 10, 0);
    square(&r[0], 3, 3, 4, 1);
    square(&r[0], 12, 0, 3, 0);
    square(&r[1], 0, 0, 10, 0);
    square(&r[1], 2, 2, 4, 1);
    square(&r[1], 12.5, 0.5, 3, 0);
    square(&r[2], 1, 1, 8, 0);
    square(&r[2], 13, 1, 3, 0);
    double z[4] = {0, 1, 2, 3};
    sr_mesh first = {0};
    assert_int_equal(sr_stack_mesh(r, z, 3, &first, NULL), SR_OK);
    check_closed(&first);
    for (unsigned round = 0; round < 3; round++) {
        void **kept = test_heap_stir(round);
        sr_mesh again = {0};
        assert_int_equal(sr_stack_mesh(r, z, 3, &again, NULL), SR_OK);
        test_assert_same_mesh(&again, &first);
        sr_mesh_release(&again);
        test_heap_settle(kept);
    }
    for (int i = 0; i < 3; i++)
        sr_poly2_release(&r[i]);
    sr_mesh_release(&first);
}

static void separate_islands_and_empty_layers(void **state)
{
    (void)state;
    sr_poly2 r[3] = {{0}};
    square(&r[0], 0, 0, 2, 0);
    square(&r[0], 5, 0, 2, 0);
    /* r[1] empty */
    square(&r[2], 1, 1, 3, 0);
    double z[4] = {0, 1, 2, 3};
    sr_mesh m = {0};
    assert_int_equal(sr_stack_mesh(r, z, 3, &m, NULL), SR_OK);
    check_closed(&m);
    assert_near(sr_mesh_volume(&m), 4 + 4 + 9, 1e-9);
    for (int i = 0; i < 3; i++)
        sr_poly2_release(&r[i]);
    sr_mesh_release(&m);
}

/* Squares in neighbouring layers that touch only along an edge (or only at a corner)
 * give that edge four faces (that corner two cones): sr_stack_mesh refuses the stack,
 * sr_stack_mesh_pulled_in pulls the outlines in by 0.3 um and closes it, the volume
 * changing by at most perimeter x height x 0.6 um. */
static void layers_touching_along_an_edge_are_pulled_apart(void **state)
{
    (void)state;
    for (int corner = 0; corner <= 1; corner++) {
        sr_poly2 r[2] = {{0}};
        square(&r[0], 0, 0, 10, 0);
        square(&r[1], 10, corner ? 10 : 0, 10, 0);
        double z[3] = {0, 1, 2};
        sr_mesh m = {0};
        sr_err err = {{0}};
        assert_int_equal(sr_stack_mesh(r, z, 2, &m, &err), SR_E_INTERNAL);
        assert_msg_has(err, "not a closed manifold");
        assert_int_equal(sr_stack_mesh_pulled_in(r, z, 2, &m, NULL), SR_OK);
        check_closed(&m);
        sr_mesh_edges e;
        assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
        assert_int_equal(e.nonmanifold_vertices, 0);
        assert_near(sr_mesh_volume(&m), 200.0, 2 * 40.0 * 1.0 * 6e-4);
        assert_true(sr_mesh_volume(&m) < 200.0); /* pulled in, not pushed out */
        sr_mesh_release(&m);
        sr_poly2_release(&r[0]);
        sr_poly2_release(&r[1]);
    }
}

static void heights_must_increase(void **state)
{
    (void)state;
    sr_poly2 r = {0};
    square(&r, 0, 0, 1, 0);
    double z[2] = {1, 1};
    sr_mesh m = {0};
    sr_err err = {0};
    assert_int_equal(sr_stack_mesh(&r, z, 1, &m, &err), SR_E_RANGE);
    assert_msg_has(err, "layer heights");
    sr_poly2_release(&r);
}

/* ---- contour slicing ---- */

static void cylinder_contour_has_its_polygon_area(void **state)
{
    (void)state;
    sr_mesh cyl = {0};
    assert_int_equal(sr_shape_cylinder(5.0, 0.0, 10.0, 64, &cyl, NULL), SR_OK);
    double z[3] = {2.5, 5.0, 9.9};
    sr_contour_stack s = {0};
    assert_int_equal(sr_contour_slice(&cyl, z, 3, &s, NULL), SR_OK);
    assert_int_equal(s.open_chains, 0);
    double poly_area = 0.5 * 64 * 25.0 * sin(2 * M_PI / 64);
    for (int l = 0; l < 3; l++) {
        assert_int_equal(s.raw[l].contour_count, 1);
        /* counter-clockwise: positive area */
        assert_near(sr_poly2_area(&s.raw[l]), poly_area, 1e-9);
    }
    sr_contour_stack_release(&s);
    sr_mesh_release(&cyl);
}

static void box_with_a_hole_gives_a_clockwise_hole(void **state)
{
    (void)state;
    double lo[3] = {0, 0, 0}, hi[3] = {10, 10, 4}, hlo[3] = {3, 3, -1}, hhi[3] = {7, 7, 5};
    sr_mesh outer = {0}, hole = {0};
    assert_int_equal(sr_shape_box(lo, hi, &outer, NULL), SR_OK);
    assert_int_equal(sr_shape_box(hlo, hhi, &hole, NULL), SR_OK);
    sr_mesh_flip(&hole);            /* inward: a hole through the box (touching nothing) */
    /* clip the hole's height to the box by using planes inside it only */
    assert_int_equal(sr_mesh_append(&outer, &hole), SR_OK);
    double z[2] = {1.0, 3.0};
    sr_contour_stack s = {0};
    assert_int_equal(sr_contour_slice(&outer, z, 2, &s, NULL), SR_OK);
    for (int l = 0; l < 2; l++) {
        assert_int_equal(s.raw[l].contour_count, 2);
        assert_near(sr_poly2_area(&s.raw[l]), 100.0 - 16.0, 1e-9);
    }
    sr_contour_stack_release(&s);
    sr_mesh_release(&outer);
    sr_mesh_release(&hole);
}

static void planes_through_vertices_make_no_double_points(void **state)
{
    (void)state;
    double lo[3] = {0, 0, 0}, hi[3] = {2, 3, 4};
    sr_mesh box = {0};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    double z[3] = {0.0, 4.0, 2.0};  /* bottom face, top face, middle */
    sr_contour_stack s = {0};
    assert_int_equal(sr_contour_slice(&box, z, 3, &s, NULL), SR_OK);
    /* a vertex at the plane counts as above: the bottom face's plane cuts nothing,
     * the top face's plane cuts the side walls at their top edges */
    assert_int_equal(s.raw[0].contour_count, 0);
    assert_near(sr_poly2_area(&s.raw[1]), 6.0, 1e-12);
    assert_near(sr_poly2_area(&s.raw[2]), 6.0, 1e-12);
    assert_int_equal(s.open_chains, 0);
    sr_contour_stack_release(&s);
    sr_mesh_release(&box);
}

static void contour_slice_refuses_bad_input(void **state)
{
    (void)state;
    sr_mesh empty = {0};
    double z[1] = {NAN};
    sr_contour_stack s = {0};
    sr_err err = {0};
    assert_int_equal(sr_contour_slice(&empty, z, 1, &s, &err), SR_E_INVALID);
    assert_msg_has(err, "empty mesh");
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    sr_mesh box = {0};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    assert_int_equal(sr_contour_slice(&box, z, 1, &s, &err), SR_E_RANGE);
    assert_msg_has(err, "plane height 0");
    assert_int_equal(sr_contour_slice(&box, z, 0, &s, &err), SR_E_RANGE);
    sr_mesh_release(&box);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(one_square_layer_is_a_closed_box),
        cmocka_unit_test(identical_layers_leave_no_internal_faces),
        cmocka_unit_test(identical_layers_merge_into_runs),
        cmocka_unit_test(layers_that_differ_stay_apart),
        cmocka_unit_test(shifted_and_rotated_layers_stitch_closed),
        cmocka_unit_test(layers_with_holes_stitch_closed),
        cmocka_unit_test(a_stack_is_one_mesh_whatever_the_heap_held),
        cmocka_unit_test(separate_islands_and_empty_layers),
        cmocka_unit_test(layers_touching_along_an_edge_are_pulled_apart),
        cmocka_unit_test(heights_must_increase),
        cmocka_unit_test(cylinder_contour_has_its_polygon_area),
        cmocka_unit_test(box_with_a_hole_gives_a_clockwise_hole),
        cmocka_unit_test(planes_through_vertices_make_no_double_points),
        cmocka_unit_test(contour_slice_refuses_bad_input),
    };
    /* SYMREC_TEST_FILTER/_SKIP: make valgrind leaves the heaviest cases to ASan */
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
