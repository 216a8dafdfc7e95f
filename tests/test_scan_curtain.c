/*
 * test_scan_curtain.c: sr_scan_hang_curtains (src/mesh/scan_curtain.c) and its use by
 * sr_scan_close_peeling, on meshes with known answers. A square tube (a 4-sided solid
 * of revolution, rings at z = 0, 5 and 10: outer corners 30 from the axis, the bore's
 * 10: 2 (30^2 - 10^2) 10 = 16000 mm^3), the face it stood on (z = 0) left off as a
 * scanner leaves it, and a triangle at the foot of one face of the bore taken out too
 * (a scanner's hole in the bore's wall at its foot). The bore's mouth then walks up the
 * wall and back: not planar. Hung back, the wall gets exactly that triangle again (one
 * excursion, one triangle, no new vertex: the excursion's top lies over the rim's own
 * corner), the mouth lies in the plane, and the closing is the tube with its bore open,
 * to the cubic millimetre. A rim that leaves its plane both ways is not hung, nor one
 * whose excursion runs up a face sloping at 45 degrees (the bore's corners 16 from the
 * axis at z = 0 narrowing to 2 at z = 10: a countersink's cone, not a wall).
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
#include "support/assert_near.h"
#include "support/open_face.h"

#define TUBE_MM3 (2.0 * (30.0 * 30.0 - 10.0 * 10.0) * 10.0)

static double tube_outer(double theta, size_t ring, void *user)
{
    (void)theta, (void)ring, (void)user;
    return 30;
}

static double tube_bore(double theta, size_t ring, void *user)
{
    (void)theta;
    return ((const double *)user)[ring];
}

/* Removes triangle t of m (the rest keep their order). */
static void drop_triangle(sr_mesh *m, size_t t)
{
    memmove(m->tri + 3 * t, m->tri + 3 * (t + 1), 3 * (m->tri_count - t - 1) * sizeof *m->tri);
    m->tri_count--;
}

/* The square tube whose bore's corners lie bore[ring] from the axis at z = 0, 5, 10,
 * without its base and the foot of one face of its bore. */
static void tube_scan(const double bore[3], sr_mesh *scan)
{
    const double z[3] = {0, 5, 10};
    sr_revolve_opts o = {4, 3, z, tube_outer, tube_bore, (void *)bore};
    assert_int_equal(sr_shape_revolve(&o, scan, NULL), SR_OK);
    assert_true(test_drop_face_at(scan, 0) > 0);
    size_t foot = SIZE_MAX; /* a triangle of the bore with two corners at z = 0 */
    for (size_t t = 0; t < scan->tri_count && foot == SIZE_MAX; t++) {
        int low = 0, in = 0;
        for (int k = 0; k < 3; k++) {
            const double *p = scan->xyz + 3 * (size_t)scan->tri[3 * t + k];
            low += fabs(p[2]) < 1e-12;
            in += fabs(p[0]) + fabs(p[1]) < 20;
        }
        foot = low == 2 && in == 3 ? t : foot;
    }
    assert_true(foot != SIZE_MAX);
    drop_triangle(scan, foot);
}

static const double STRAIGHT[3] = {10, 10, 10}, SLOPING[3] = {16, 9, 2};

static bool closed_manifold(const sr_mesh *m)
{
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    return e.boundary_edges == 0 && e.nonmanifold_edges == 0 && e.misoriented_edges == 0;
}

static void the_foot_of_a_bore_wall_is_hung_back(void **state)
{
    (void)state;
    sr_mesh scan;
    tube_scan(STRAIGHT, &scan);
    size_t nt = scan.tri_count, nv = scan.vertex_count;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 2); /* the outer rim and the bore's mouth */
    size_t hung = 0;
    assert_int_equal(sr_scan_hang_curtains(&scan, &d, &hung, NULL), SR_OK);
    assert_int_equal(hung, 1);
    assert_int_equal(scan.tri_count, nt + 1); /* the wall's foot again */
    assert_int_equal(scan.vertex_count, nv);
    sr_scan_desc_release(&d);
    /* both rims now lie in z = 0 */
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 2);
    for (size_t i = 0; i < d.loop_count; i++)
        for (size_t e = 0; e < d.loops[i].edges; e++)
            assert_near(scan.xyz[3 * (size_t)d.loop_verts[d.loops[i].first + e] + 2], 0, 1e-12);
    sr_scan_desc_release(&d);
    sr_mesh_release(&scan);
}

static void the_bore_stays_open_when_the_scan_is_closed(void **state)
{
    (void)state;
    sr_mesh scan;
    tube_scan(STRAIGHT, &scan);
    sr_scan_desc d;
    sr_scan_closing *how = NULL;
    size_t peeled = SIZE_MAX;
    assert_int_equal(sr_scan_close_peeling(&scan, &d, &how, &peeled, NULL), SR_OK);
    assert_int_equal(peeled, 0);
    assert_int_equal(d.loop_count, 2);
    for (size_t i = 0; i < d.loop_count; i++)
        assert_int_equal(how[i], SR_SCAN_IN_PLANE); /* a face with a hole, not a fan */
    assert_true(closed_manifold(&scan));
    assert_near(sr_mesh_volume(&scan), TUBE_MM3, 1e-6);
    free(how);
    sr_scan_desc_release(&d);
    sr_mesh_release(&scan);
}

/* Describes scan (two loops) and checks that no loop of it is hung: the mesh unchanged;
 * releases scan. */
static void assert_nothing_hung(sr_mesh *scan)
{
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(scan, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 2);
    size_t nt = scan->tri_count, nv = scan->vertex_count, hung = SIZE_MAX;
    assert_int_equal(sr_scan_hang_curtains(scan, &d, &hung, NULL), SR_OK);
    assert_int_equal(hung, 0);
    assert_int_equal(scan->tri_count, nt);
    assert_int_equal(scan->vertex_count, nv);
    sr_scan_desc_release(&d);
    sr_mesh_release(scan);
}

/* A rim that leaves the plane of the other rim both ways is not hung (a corner of the
 * bore's mouth moved 3 mm below the face: the mouth runs up the wall and down under the
 * face, no wall's foot). */
static void a_rim_leaving_its_plane_both_ways_is_not_hung(void **state)
{
    (void)state;
    sr_mesh scan;
    tube_scan(STRAIGHT, &scan);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    const sr_scan_loop *mouth = d.loops[0].span_mm < d.loops[1].span_mm ? &d.loops[0] : &d.loops[1];
    uint32_t v = UINT32_MAX;
    for (size_t e = 0; e < mouth->edges && v == UINT32_MAX; e++) {
        uint32_t u = d.loop_verts[mouth->first + e];
        if (fabs(scan.xyz[3 * (size_t)u + 2]) < 1e-12)
            v = u;
    }
    assert_true(v != UINT32_MAX);
    scan.xyz[3 * (size_t)v + 2] = -3;
    sr_scan_desc_release(&d);
    assert_nothing_hung(&scan);
}

static void an_excursion_up_a_sloping_face_is_not_hung(void **state)
{
    (void)state;
    sr_mesh scan;
    tube_scan(SLOPING, &scan);
    assert_nothing_hung(&scan);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_foot_of_a_bore_wall_is_hung_back),
        cmocka_unit_test(the_bore_stays_open_when_the_scan_is_closed),
        cmocka_unit_test(a_rim_leaving_its_plane_both_ways_is_not_hung),
        cmocka_unit_test(an_excursion_up_a_sloping_face_is_not_hung),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
