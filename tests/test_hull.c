/*
 * test_hull.c: sr_convex_hull (src/bridge/hull_cgal.cpp) on point sets with known hulls.
 * The 27 points of a 3 x 3 x 3 lattice of pitch 1 (a cube of side 2): 8 corners, 12
 * triangles, volume 8, closed. Every facet of the cube holds 9 coplanar points, so the
 * hull's own triangulation of it is a choice: the same points in other orders give the
 * same mesh, byte for byte (the vertices sorted, each square split from its least
 * corner). An octagonal prism (two regular octagons, radius 5, z = 0 and 4): its volume
 * 2 sqrt(2) 25 x 4, 16 vertices, 28 triangles, whatever the order. Fewer than 4 points,
 * or all in one plane: refused.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bridge/hull.h"
#include "mesh/mesh.h"
#include "support/assert_near.h"

/* The n points of pts (n by 3) in the order of a seeded shuffle, into out. */
static void shuffled(const double *pts, size_t n, unsigned seed, double *out)
{
    size_t *ord = malloc(n * sizeof *ord);
    assert_non_null(ord);
    for (size_t i = 0; i < n; i++)
        ord[i] = i;
    for (size_t i = n - 1; i > 0; i--) {
        seed = seed * 1103515245u + 12345u;
        size_t j = (seed >> 8) % (i + 1), t = ord[i];
        ord[i] = ord[j];
        ord[j] = t;
    }
    for (size_t i = 0; i < n; i++)
        memcpy(out + 3 * i, pts + 3 * ord[i], 3 * sizeof *out);
    free(ord);
}

/* The hulls of pts in its own order and in 20 shuffled ones are the same mesh. */
static void assert_order_free(const double *pts, size_t n, size_t verts, size_t tris, double volume)
{
    sr_mesh first;
    sr_mesh_init(&first);
    assert_int_equal(sr_convex_hull(pts, n, &first, NULL), SR_OK);
    assert_int_equal(first.vertex_count, verts);
    assert_int_equal(first.tri_count, tris);
    assert_true(sr_mesh_is_closed(&first));
    assert_near(sr_mesh_volume(&first), volume, 1e-9);
    double *again = malloc(3 * n * sizeof *again);
    assert_non_null(again);
    for (unsigned s = 1; s <= 20; s++) {
        shuffled(pts, n, s, again);
        sr_mesh h;
        sr_mesh_init(&h);
        assert_int_equal(sr_convex_hull(again, n, &h, NULL), SR_OK);
        assert_int_equal(h.vertex_count, first.vertex_count);
        assert_int_equal(h.tri_count, first.tri_count);
        assert_memory_equal(h.xyz, first.xyz, 3 * h.vertex_count * sizeof *h.xyz);
        assert_memory_equal(h.tri, first.tri, 3 * h.tri_count * sizeof *h.tri);
        sr_mesh_release(&h);
    }
    free(again);
    sr_mesh_release(&first);
}

static void a_lattice_cube_is_one_mesh_in_any_order(void **state)
{
    (void)state;
    double pts[27 * 3];
    size_t n = 0;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++, n++) {
                pts[3 * n] = i;
                pts[3 * n + 1] = j;
                pts[3 * n + 2] = k;
            }
    assert_order_free(pts, n, 8, 12, 8.0);
}

static void an_octagonal_prism_is_one_mesh_in_any_order(void **state)
{
    (void)state;
    double pts[16 * 3];
    for (int k = 0; k < 16; k++) {
        double a = 2.0 * M_PI * (k % 8) / 8.0;
        pts[3 * k] = 5.0 * cos(a);
        pts[3 * k + 1] = 5.0 * sin(a);
        pts[3 * k + 2] = k < 8 ? 0.0 : 4.0;
    }
    /* 8 triangles: 4 x 25 sin 45 deg = 50 sqrt 2 per octagon; 6 + 6 caps, 16 sides */
    assert_order_free(pts, 16, 16, 28, 50.0 * sqrt(2.0) * 4.0);
}

static void no_volume_is_refused(void **state)
{
    (void)state;
    double flat[5 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0.5, 0.5, 0};
    sr_mesh h;
    sr_mesh_init(&h);
    sr_err e = {{0}};
    assert_int_equal(sr_convex_hull(flat, 3, &h, &e), SR_E_INVALID);
    assert_non_null(strstr(e.msg, "no volume"));
    assert_int_equal(sr_convex_hull(flat, 5, &h, &e), SR_E_INVALID);
    assert_int_equal(h.tri_count, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_lattice_cube_is_one_mesh_in_any_order),
        cmocka_unit_test(an_octagonal_prism_is_one_mesh_in_any_order),
        cmocka_unit_test(no_volume_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
