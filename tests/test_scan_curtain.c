/*
 * test_scan_curtain.c: sr_scan_hang_curtains (src/mesh/scan_curtain.c) and its use by
 * sr_scan_close_peeling, on a mesh with known answers. A block 20 x 20 x 10 with a
 * square bore 6 x 6 through it (x, y 7..13: 4000 - 360 = 3640 mm^3), the face it stood
 * on (z = 0) left off as a scanner leaves it, and the triangle of the bore's wall
 * x = 7 that runs along that face taken out too (a scanner's hole in the bore's wall at
 * its foot). The bore's mouth then walks up the wall and back: not planar. Hung back,
 * the wall gets exactly that triangle again (one excursion, one triangle, no new
 * vertex: the excursion's foot is the rim's own corner), the mouth lies in the plane,
 * and the closing is the block with its bore open, to the cubic millimetre. A rim that
 * leaves its plane both ways is not hung.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bridge/boolean.h"
#include "mesh/mesh.h"
#include "mesh/scan_describe.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/open_face.h"

#define BORED_MM3 (20.0 * 20.0 * 10.0 - 6.0 * 6.0 * 10.0)

static void box(sr_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

/* Removes triangle t of m (the rest keep their order). */
static void drop_triangle(sr_mesh *m, size_t t)
{
    memmove(m->tri + 3 * t, m->tri + 3 * (t + 1), 3 * (m->tri_count - t - 1) * sizeof *m->tri);
    m->tri_count--;
}

/* The first triangle of m lying in the plane x = x0 with two corners at z = 0. */
static size_t wall_foot(const sr_mesh *m, double x0)
{
    for (size_t t = 0; t < m->tri_count; t++) {
        int in = 0, low = 0;
        for (int k = 0; k < 3; k++) {
            const double *p = m->xyz + 3 * (size_t)m->tri[3 * t + k];
            in += fabs(p[0] - x0) < 1e-12;
            low += fabs(p[2]) < 1e-12;
        }
        if (in == 3 && low == 2)
            return t;
    }
    fail_msg("no triangle of the wall x = %g along z = 0", x0);
    return 0;
}

/* The bored block without its base, the foot of the bore's wall x = 7 taken out. */
static void bored_scan(sr_mesh *scan)
{
    sr_mesh block, bore;
    box(&block, 0, 0, 0, 20, 20, 10);
    box(&bore, 7, 7, -1, 13, 13, 11);
    sr_err err = {{0}};
    assert_int_equal(sr_boolean_difference(&block, &bore, scan, &err), SR_OK);
    assert_near(sr_mesh_volume(scan), BORED_MM3, 1e-6);
    assert_true(test_drop_face_at(scan, 0) > 0);
    drop_triangle(scan, wall_foot(scan, 7));
    sr_mesh_release(&block);
    sr_mesh_release(&bore);
}

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
    bored_scan(&scan);
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
    bored_scan(&scan);
    sr_scan_desc d;
    sr_scan_closing *how = NULL;
    size_t peeled = SIZE_MAX;
    assert_int_equal(sr_scan_close_peeling(&scan, &d, &how, &peeled, NULL), SR_OK);
    assert_int_equal(peeled, 0);
    assert_int_equal(d.loop_count, 2);
    for (size_t i = 0; i < d.loop_count; i++)
        assert_int_equal(how[i], SR_SCAN_IN_PLANE); /* a face with a hole, not a fan */
    assert_true(closed_manifold(&scan));
    assert_near(sr_mesh_volume(&scan), BORED_MM3, 1e-6);
    free(how);
    sr_scan_desc_release(&d);
    sr_mesh_release(&scan);
}

/* A rim that leaves the plane of the other rim both ways is not hung (a corner of the
 * bore's mouth moved 3 mm below the face: the mouth runs up the wall and down under the
 * face, no wall's foot). */
static void a_rim_leaving_its_plane_both_ways_is_not_hung(void **state)
{
    (void)state;
    sr_mesh scan;
    bored_scan(&scan);
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
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    size_t nt = scan.tri_count, hung = SIZE_MAX;
    assert_int_equal(sr_scan_hang_curtains(&scan, &d, &hung, NULL), SR_OK);
    assert_int_equal(hung, 0);
    assert_int_equal(scan.tri_count, nt);
    sr_scan_desc_release(&d);
    sr_mesh_release(&scan);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_foot_of_a_bore_wall_is_hung_back),
        cmocka_unit_test(the_bore_stays_open_when_the_scan_is_closed),
        cmocka_unit_test(a_rim_leaving_its_plane_both_ways_is_not_hung),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
