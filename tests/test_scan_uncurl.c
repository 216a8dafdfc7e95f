/*
 * test_scan_uncurl.c: sr_scan_uncurl_rims (src/mesh/scan_uncurl.c) and its use in
 * sr_scan_close_peeling, on a cylinder with a known answer: r = 10 mm, z 0..30, 96
 * sides, its bottom face left off as a scanner leaves the face a part stood on. One
 * side triangle on the bottom rim is folded into a Z: the rim runs from a corner on
 * to a point near the next corner, back to a point near the first, and on to the next
 * corner, so two of its edges cross in the plane of the base. No fill of the base fits
 * that rim (the base is fanned); untwisted (the two points between the crossing edges
 * merged into one at the crossing), the base fills in its plane and the scan closes
 * with the cylinder's volume (less the sliver of the side the merge cuts off). A rim with no twist is left as it is.
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
#include "support/open_face.h"

#define SIDES 96
#define CYLINDER_MM3 (SIDES / 2.0 * 100.0 * sin(2 * M_PI / SIDES) * 30.0)

/* The cylinder without its bottom face. */
static void open_cylinder(sr_mesh *m)
{
    assert_int_equal(sr_shape_cylinder(10, 0, 30, SIDES, m, NULL), SR_OK);
    assert_true(test_drop_face_at(m, 0) > 0);
}

/* Folds the first side triangle with an edge on the bottom rim into a Z (see above):
 * its rim edge a -> b becomes a -> p -> q -> b, p near b and q near a, both a little
 * inside, so a -> p and q -> b cross. */
static void twist_rim(sr_mesh *m)
{
    for (size_t t = 0; t < m->tri_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3],
                     top = m->tri[3 * t + (k + 2) % 3];
            if (m->xyz[3 * a + 2] != 0 || m->xyz[3 * b + 2] != 0)
                continue;
            const double *pa = m->xyz + 3 * a, *pb = m->xyz + 3 * b;
            double mid[3] = {(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, 0};
            double r = hypot(mid[0], mid[1]), len = hypot(pb[0] - pa[0], pb[1] - pa[1]);
            double in[2] = {-mid[0] / r, -mid[1] / r}; /* toward the axis */
            double p[3], q[3];
            for (int c = 0; c < 2; c++) {
                p[c] = pa[c] + 0.9 * (pb[c] - pa[c]) + 0.05 * len * in[c];
                q[c] = pa[c] + 0.1 * (pb[c] - pa[c]) + 0.02 * len * in[c];
            }
            p[2] = q[2] = 0;
            uint32_t vp = test_add_vertex(m, p), vq = test_add_vertex(m, q);
            m->tri[3 * t] = a, m->tri[3 * t + 1] = vp, m->tri[3 * t + 2] = top;
            test_add_triangle(m, vp, vq, top);
            test_add_triangle(m, vq, b, top);
            return;
        }
    fail_msg("no side triangle on the bottom rim");
}

static bool closed_manifold(const sr_mesh *m)
{
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    return e.boundary_edges == 0 && e.nonmanifold_edges == 0 && e.misoriented_edges == 0;
}

static void a_rim_without_a_twist_is_left_as_it_is(void **state)
{
    (void)state;
    sr_mesh m;
    open_cylinder(&m);
    size_t nt = m.tri_count, nv = m.vertex_count;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    size_t merged = 99;
    assert_int_equal(sr_scan_uncurl_rims(&m, &d, NULL, &merged, NULL), SR_OK);
    assert_int_equal(merged, 0);
    assert_int_equal(m.tri_count, nt);
    assert_int_equal(m.vertex_count, nv);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_twisted_rim_is_not_filled_in_its_plane(void **state)
{
    (void)state;
    sr_mesh m;
    open_cylinder(&m);
    twist_rim(&m);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 1);
    assert_int_equal(d.loops[0].edges, SIDES + 2);
    sr_scan_closing how[1];
    assert_int_equal(sr_scan_close_openings_how(&m, &d, 0, NULL, how, NULL), SR_OK);
    assert_int_equal(how[0], SR_SCAN_BY_FAN);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_twist_is_merged_at_its_crossing(void **state)
{
    (void)state;
    sr_mesh m;
    open_cylinder(&m);
    twist_rim(&m);
    size_t nt = m.tri_count;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    size_t merged = 0;
    assert_int_equal(sr_scan_uncurl_rims(&m, &d, NULL, &merged, NULL), SR_OK);
    assert_int_equal(merged, 1);           /* p and q become one */
    assert_int_equal(m.tri_count, nt - 1); /* the triangle p q top is gone */
    sr_scan_desc d2;
    assert_int_equal(sr_scan_describe(&m, NULL, &d2, NULL), SR_OK);
    assert_int_equal(d2.loop_count, 1);
    assert_int_equal(d2.loops[0].edges, SIDES + 1);
    sr_scan_desc_release(&d2);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_twisted_scan_closes_in_its_plane(void **state)
{
    (void)state;
    sr_mesh m;
    open_cylinder(&m);
    twist_rim(&m);
    sr_scan_desc d;
    sr_scan_closing *how = NULL;
    assert_int_equal(sr_scan_close_peeling(&m, &d, &how, NULL, NULL), SR_OK);
    assert_int_equal(d.uncurled_vertices, 1);
    assert_int_equal(d.loop_count, 1);
    assert_int_equal(how[0], SR_SCAN_IN_PLANE);
    assert_true(closed_manifold(&m));
    /* the merged point lies inside the rim by at most p's 0.05 of a side's width: the
     * side loses at most the tetrahedron on a, that point, b and the top corner */
    double side = 2 * 10 * sin(M_PI / SIDES), lost = 0.5 * side * 0.05 * side * 30 / 3;
    double dv = sr_mesh_volume(&m) - CYLINDER_MM3;
    assert_true(dv <= 1e-9 && dv > -lost);
    free(how);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_rim_without_a_twist_is_left_as_it_is),
        cmocka_unit_test(a_twisted_rim_is_not_filled_in_its_plane),
        cmocka_unit_test(a_twist_is_merged_at_its_crossing),
        cmocka_unit_test(a_twisted_scan_closes_in_its_plane),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
