/*
 * test_tri_folds.c: sr_tri_folds_flip (src/mesh/tri_folds.c) on triangles with known
 * answers: two triangles folded back to back across an edge (normals opposite) have
 * their edge flipped into the other diagonal, after which they face the same way, the
 * area they span is the quad's and every other triangle is as it was; a fold is left
 * when one of its triangles is not picked, when the other diagonal is an edge already,
 * when its edge has a third triangle, or when a flip would give a triangle of no area;
 * a 90-degree crease is no fold; only the picked triangles are rewritten.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "mesh/tri_folds.h"
#include "support/assert_near.h"

/* u = 0, v = 1 along x; a = 2 and b = 3 both on the +y side of u v, so (u v a) and
 * (v u b) lie back to back; 4 and 5 make a third triangle (a, 4, 5) elsewhere. */
static void fold(sr_mesh *m, double b_y)
{
    assert_int_equal(sr_mesh_alloc(m, 6, 3), SR_OK);
    const double xyz[18] = {0, 0, 0, 10, 0, 0, 5, 1, 0, 5, b_y, 0, 20, 20, 0, 21, 20, 0};
    const uint32_t tri[9] = {0, 1, 2, 1, 0, 3, 2, 4, 5};
    memcpy(m->xyz, xyz, sizeof xyz);
    memcpy(m->tri, tri, sizeof tri);
}

static double normal_z(const sr_mesh *m, size_t t)
{
    double n[3];
    sr_mesh_tri_normal(m, t, n);
    return n[2] / sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

static bool has_corners(const uint32_t *t, uint32_t a, uint32_t b, uint32_t c)
{
    bool x[3] = {false, false, false};
    uint32_t want[3] = {a, b, c};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            x[k] |= t[i] == want[k];
    return x[0] && x[1] && x[2];
}

static void a_fold_is_flipped_into_the_other_diagonal(void **state)
{
    (void)state;
    sr_mesh m;
    fold(&m, 2);
    assert_true(normal_z(&m, 0) * normal_z(&m, 1) < -0.99); /* back to back */
    bool pick[3] = {true, true, false};
    uint32_t third[3];
    memcpy(third, m.tri + 6, sizeof third);
    assert_int_equal(sr_tri_folds_flip(&m, pick), 1);
    /* (a u b) and (b v a): the edge a b, u v gone, both facing -z */
    assert_true(has_corners(m.tri, 2, 0, 3));
    assert_true(has_corners(m.tri + 3, 3, 1, 2));
    assert_near(normal_z(&m, 0), -1, 1e-12);
    assert_near(normal_z(&m, 1), -1, 1e-12);
    assert_memory_equal(m.tri + 6, third, sizeof third);
    /* the quad u a v b (b beyond a): the two triangles now cover it once */
    double area = 0;
    for (size_t t = 0; t < 2; t++) {
        double n[3];
        sr_mesh_tri_normal(&m, t, n);
        area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    assert_near(area, 0.5 * 10 * 2 - 0.5 * 10 * 1, 1e-12);
    /* flipped once is enough: a second call finds nothing */
    assert_int_equal(sr_tri_folds_flip(&m, pick), 0);
    sr_mesh_release(&m);
}

static void a_fold_that_may_not_flip_is_left(void **state)
{
    (void)state;
    sr_mesh m;
    uint32_t was[9];
    /* one of the two not picked */
    fold(&m, 2);
    memcpy(was, m.tri, sizeof was);
    bool one[3] = {true, false, false};
    assert_int_equal(sr_tri_folds_flip(&m, one), 0);
    assert_memory_equal(m.tri, was, sizeof was);
    /* the other diagonal an edge already (the third triangle on a and b) */
    m.tri[6] = 2, m.tri[7] = 3, m.tri[8] = 5;
    memcpy(was, m.tri, sizeof was);
    bool both[3] = {true, true, false};
    assert_int_equal(sr_tri_folds_flip(&m, both), 0);
    assert_memory_equal(m.tri, was, sizeof was);
    /* a third triangle on the fold's own edge */
    m.tri[6] = 0, m.tri[7] = 1, m.tri[8] = 5;
    memcpy(was, m.tri, sizeof was);
    assert_int_equal(sr_tri_folds_flip(&m, both), 0);
    assert_memory_equal(m.tri, was, sizeof was);
    sr_mesh_release(&m);
    /* b where a is: the flip would give triangles of no area */
    fold(&m, 1);
    memcpy(was, m.tri, sizeof was);
    assert_int_equal(sr_tri_folds_flip(&m, both), 0);
    assert_memory_equal(m.tri, was, sizeof was);
    sr_mesh_release(&m);
}

/* A base (z = 0) and a wall (x = 0) meeting at 90 degrees along the y axis: a crease. */
static void a_crease_is_no_fold(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_mesh_alloc(&m, 4, 2), SR_OK);
    const double xyz[12] = {0, 0, 0, 0, 10, 0, 5, 5, 0, 0, 5, 5};
    const uint32_t tri[6] = {1, 0, 2, 0, 1, 3};
    memcpy(m.xyz, xyz, sizeof xyz);
    memcpy(m.tri, tri, sizeof tri);
    bool pick[2] = {true, true};
    assert_int_equal(sr_tri_folds_flip(&m, pick), 0);
    assert_memory_equal(m.tri, tri, sizeof tri);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_fold_is_flipped_into_the_other_diagonal),
        cmocka_unit_test(a_fold_that_may_not_flip_is_left),
        cmocka_unit_test(a_crease_is_no_fold),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
