/*
 * test_fold_slivers.c: the needles a union leaves, folded away where they are
 * (recon_fold_slivers, src/reconstruct_slivers.c). Known answers: a solid of
 * revolution (radius 10, rings every 5 mm from z 0 to 30, 128 sides) whose edge between
 * two vertices of the ring at z 15 is split 2 micrometres from one end, as a union leaves
 * a fin: closed, the same volume, one edge of 2 micrometres. The fold collapses it (1
 * edge), leaves no edge under 5 micrometres, the mesh closed with the same volume and
 * the triangles it had before the split; only the triangles a few rings round it went
 * through the collapse, so every vertex before the needle's keeps its place and
 * number. A needle in the middle of an edge of a box (16 triangles) is folded on the
 * whole mesh: 14 triangles, the box's volume.
 * A mesh with no short edge is left as it is.
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
#include "mesh/shapes.h"
#include "reconstruct_int.h"
#include "support/assert_near.h"
#include "support/mesh_edit.h"

static double radius(double theta, size_t ring, void *user)
{
    (void)theta, (void)ring, (void)user;
    return 10;
}

static void rod(sr_mesh *m)
{
    static const double z[7] = {0, 5, 10, 15, 20, 25, 30};
    sr_revolve_opts o = {0};
    o.segments = 128;
    o.ring_count = 7;
    o.ring_z = z;
    o.outer = radius;
    assert_int_equal(sr_shape_revolve(&o, m, NULL), SR_OK);
}

/* Splits the edge a -> b of m (used by two triangles, once each way) at `at` mm from a:
 * the two triangles become four. Returns the new vertex. */
static uint32_t split_edge(sr_mesh *m, uint32_t a, uint32_t b, double at)
{
    const double *pa = m->xyz + 3 * (size_t)a, *pb = m->xyz + 3 * (size_t)b;
    double len = sqrt((pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]) +
                      (pb[2] - pa[2]) * (pb[2] - pa[2]));
    double p[3];
    for (int k = 0; k < 3; k++)
        p[k] = pa[k] + (pb[k] - pa[k]) * at / len;
    uint32_t v = test_add_vertex(m, p);
    size_t n = m->tri_count, found = 0;
    for (size_t t = 0; t < n; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t *c = m->tri + 3 * t;
            uint32_t x = c[k], y = c[(k + 1) % 3], w = c[(k + 2) % 3];
            if ((x == a && y == b) || (x == b && y == a)) {
                c[0] = x, c[1] = v, c[2] = w;
                test_add_triangle(m, v, y, w);
                found++;
                break;
            }
        }
    assert_int_equal(found, 2);
    return v;
}

static double shortest_edge(const sr_mesh *m)
{
    double best = INFINITY;
    for (size_t t = 0; t < m->tri_count; t++)
        for (int k = 0; k < 3; k++) {
            const double *a = m->xyz + 3 * (size_t)m->tri[3 * t + k];
            const double *b = m->xyz + 3 * (size_t)m->tri[3 * t + (k + 1) % 3];
            best = fmin(best, sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                   (a[2] - b[2]) * (a[2] - b[2])));
        }
    return best;
}

/* The two vertices of the ring at z: the first two found, neighbours round the ring. */
static void ring_edge(const sr_mesh *m, double z, uint32_t *a, uint32_t *b)
{
    for (size_t t = 0; t < m->tri_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t x = m->tri[3 * t + k], y = m->tri[3 * t + (k + 1) % 3];
            if (m->xyz[3 * (size_t)x + 2] == z && m->xyz[3 * (size_t)y + 2] == z &&
                hypot(m->xyz[3 * (size_t)x], m->xyz[3 * (size_t)x + 1]) > 9) {
                *a = x;
                *b = y;
                return;
            }
        }
    fail_msg("no edge on the ring at z %g", z);
}

static void a_needle_is_folded_where_it_is(void **state)
{
    (void)state;
    sr_mesh m, before;
    rod(&m);
    size_t tris = m.tri_count;
    double volume = sr_mesh_volume(&m);
    uint32_t a = 0, b = 0;
    ring_edge(&m, 15, &a, &b);
    split_edge(&m, a, b, 0.002);
    assert_true(sr_mesh_is_closed(&m));
    assert_near(shortest_edge(&m), 0.002, 1e-9);
    assert_near(sr_mesh_volume(&m), volume, 1e-9);
    assert_int_equal(sr_mesh_copy(&before, &m), SR_OK);
    size_t looked = 0;
    assert_int_equal(recon_fold_slivers(&m, &looked), 1);
    assert_true(looked > 4 && looked < before.tri_count / 8); /* the rings round it */
    assert_true(sr_mesh_is_closed(&m));
    assert_true(shortest_edge(&m) > 0.005);
    assert_near(sr_mesh_volume(&m), volume, 1e-2); /* the ends met halfway */
    assert_int_equal(m.tri_count, tris);
    /* the vertices before the needle's ends keep their places and numbers */
    uint32_t first = a < b ? a : b;
    assert_memory_equal(m.xyz, before.xyz, 3 * (size_t)first * sizeof(double));

    sr_mesh_release(&before);
    sr_mesh_release(&m);
}

static void a_needle_on_a_small_mesh_is_folded_on_the_whole(void **state)
{
    (void)state;
    sr_mesh m;
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    /* the needle in the middle of an edge, so its ends meet on the edge */
    uint32_t a = m.tri[0], b = m.tri[1];
    uint32_t mid = split_edge(&m, a, b, 10);
    split_edge(&m, mid, b, 0.002);
    assert_int_equal(m.tri_count, 16);
    size_t looked = 0;
    assert_int_equal(recon_fold_slivers(&m, &looked), 1);
    assert_int_equal(looked, 16);
    assert_int_equal(m.tri_count, 14);
    assert_true(sr_mesh_is_closed(&m));
    assert_near(sr_mesh_volume(&m), 6000, 1e-9);
    assert_true(shortest_edge(&m) > 0.005);
    sr_mesh_release(&m);
}

static void a_mesh_without_needles_is_left_alone(void **state)
{
    (void)state;
    sr_mesh m, before;
    rod(&m);
    assert_int_equal(sr_mesh_copy(&before, &m), SR_OK);
    size_t looked = 1;
    assert_int_equal(recon_fold_slivers(&m, &looked), 0);
    assert_int_equal(looked, 0);
    assert_int_equal(m.tri_count, before.tri_count);
    assert_memory_equal(m.tri, before.tri, 3 * m.tri_count * sizeof(uint32_t));
    assert_memory_equal(m.xyz, before.xyz, 3 * m.vertex_count * sizeof(double));
    sr_mesh_release(&before);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_needle_is_folded_where_it_is),
        cmocka_unit_test(a_needle_on_a_small_mesh_is_folded_on_the_whole),
        cmocka_unit_test(a_mesh_without_needles_is_left_alone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
