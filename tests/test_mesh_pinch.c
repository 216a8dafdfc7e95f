/*
 * test_mesh_pinch.c: sr_mesh_split_pinches (src/mesh/mesh_pinch.c) on meshes with known
 * answers: two tetrahedra (volume 1/6 each) sharing one vertex (pinched: one vertex
 * added, at the same place, taken by the second tetrahedron's three triangles; closed,
 * no pinch left, the volume unchanged); a closed box (nothing to split: unchanged);
 * sr_pair32_sort (src/mesh/pair_sort.c), which orders each vertex's neighbours here,
 * against qsort on pseudo-random lists, short (insertion) and long (qsort), with ties.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "mesh/mesh_pinch.h"
#include "mesh/pair_sort.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

static void two_tetrahedra_sharing_a_vertex_get_one_each(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_mesh_alloc(&m, 7, 8), SR_OK);
    const double xyz[21] = {0,  0, 0, 1, 0,  0, 0, 1, 0, 0, 0, 1, /* the first, at 0 */
                            -1, 0, 0, 0, -1, 0, 0, 0, -1};        /* the second: 0, 4, 5, 6 */
    const uint32_t tri[24] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3,
                              0, 4, 5, 0, 5, 6, 0, 6, 4, 4, 6, 5};
    memcpy(m.xyz, xyz, sizeof xyz);
    memcpy(m.tri, tri, sizeof tri);
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.nonmanifold_vertices, 1);
    double volume = sr_mesh_volume(&m);
    assert_near(volume, 2.0 / 6.0, 1e-12);
    size_t added = 0;
    assert_int_equal(sr_mesh_split_pinches(&m, &added, NULL), SR_OK);
    assert_int_equal(added, 1);
    assert_int_equal(m.vertex_count, 8);
    assert_int_equal(m.tri_count, 8);
    for (int k = 0; k < 3; k++)
        assert_true(m.xyz[21 + k] == 0);
    for (size_t t = 0; t < 4; t++) /* the first fan keeps vertex 0 */
        assert_int_equal(m.tri[3 * t], tri[3 * t]);
    for (size_t t = 4; t < 7; t++)
        assert_int_equal(m.tri[3 * t], 7);
    assert_int_equal(m.tri[21], 4);
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.nonmanifold_vertices, 0);
    assert_true(sr_mesh_is_closed(&m));
    assert_near(sr_mesh_volume(&m), volume, 1e-12);
    sr_mesh_release(&m);
}

static void a_box_is_left_as_it_is(void **state)
{
    (void)state;
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    sr_mesh m, copy;
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    assert_int_equal(sr_shape_box(lo, hi, &copy, NULL), SR_OK);
    size_t added = 99;
    assert_int_equal(sr_mesh_split_pinches(&m, &added, NULL), SR_OK);
    assert_int_equal(added, 0);
    assert_int_equal(m.vertex_count, copy.vertex_count);
    assert_memory_equal(m.tri, copy.tri, 3 * m.tri_count * sizeof *m.tri);
    assert_memory_equal(m.xyz, copy.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    sr_mesh_release(&m);
    sr_mesh_release(&copy);
}

static int by_key_then_tag(const void *pa, const void *pb)
{
    const sr_pair32 *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->tag > b->tag) - (a->tag < b->tag);
}

static void pairs_sort_as_qsort_does(void **state)
{
    (void)state;
    uint32_t x = 12345;
    sr_pair32 got[80], want[80];
    for (size_t n = 0; n <= 80; n++) {
        for (size_t i = 0; i < n; i++) {
            x = x * 1103515245u + 12345u;
            got[i].key = (x >> 16) % 7; /* few keys: ties broken by tag */
            x = x * 1103515245u + 12345u;
            got[i].tag = (x >> 16) % 50;
        }
        memcpy(want, got, n * sizeof *got);
        qsort(want, n, sizeof *want, by_key_then_tag);
        sr_pair32_sort(got, n);
        if (n > 0)
            assert_memory_equal(got, want, n * sizeof *got);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(two_tetrahedra_sharing_a_vertex_get_one_each),
        cmocka_unit_test(a_box_is_left_as_it_is),
        cmocka_unit_test(pairs_sort_as_qsort_does),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
