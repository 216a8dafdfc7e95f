/*
 * test_planar_fill.c: sr_planar_fill (src/bridge/planar_fill_cgal.cpp) on loops with
 * known answers: a 4 x 4 square with a 2 x 2 square hole walked the other way (filled
 * 12 mm^2, every triangle turned against the outer loop, no point made); a bow tie
 * (0,0) (2,2) (2,0) (0,2), whose edges cross at (1,1): one point made there, both
 * crossing edges run through it, two lobes of 1 mm^2 wound in opposite senses and turned
 * so the fill walks every cut loop edge backwards; two squares walked the same way
 * around the same region (wound twice: kept once); a non-finite point refused.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "bridge/planar_fill.h"
#include "support/assert_near.h"

/* Signed area of triangle t of the fill (points: the input's, then the made ones). */
static double tri_signed(const sr_planar_fill_out *o, const double *uv, size_t n, size_t t)
{
    double p[3][2];
    for (int k = 0; k < 3; k++) {
        uint32_t i = o->tri[3 * t + k];
        const double *q = i < n ? uv + 2 * i : o->extra_uv + 2 * (i - n);
        p[k][0] = q[0];
        p[k][1] = q[1];
    }
    return 0.5 *
           ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
}

/* Whether some fill triangle walks a -> b. */
static bool walks(const sr_planar_fill_out *o, uint32_t a, uint32_t b)
{
    for (size_t t = 0; t < o->tri_count; t++)
        for (int k = 0; k < 3; k++)
            if (o->tri[3 * t + k] == a && o->tri[3 * t + (k + 1) % 3] == b)
                return true;
    return false;
}

static void a_square_with_a_hole_is_filled_around_the_hole(void **state)
{
    (void)state;
    const double uv[16] = {0, 0, 4, 0, 4, 4, 0, 4,  /* counter-clockwise */
                           1, 1, 1, 3, 3, 3, 3, 1}; /* clockwise */
    const size_t start[3] = {0, 4, 8};
    sr_planar_fill_out o;
    assert_int_equal(sr_planar_fill(uv, start, 2, &o, NULL), SR_OK);
    assert_int_equal(o.extra_count, 0);
    assert_int_equal(o.split_first[8], 0);
    double area = 0;
    for (size_t t = 0; t < o.tri_count; t++) {
        double a = tri_signed(&o, uv, 8, t);
        assert_true(a < 0); /* against the outer loop */
        area += a;
    }
    assert_near(area, -12, 1e-12);
    for (uint32_t c = 0; c < 2; c++)
        for (uint32_t i = 0; i < 4; i++)
            assert_true(walks(&o, 4 * c + (i + 1) % 4, 4 * c + i));
    sr_planar_fill_free(&o);
}

static void crossing_edges_are_cut_and_filled_by_their_winding(void **state)
{
    (void)state;
    const double uv[8] = {0, 0, 2, 2, 2, 0, 0, 2};
    const size_t start[2] = {0, 4};
    sr_planar_fill_out o;
    assert_int_equal(sr_planar_fill(uv, start, 1, &o, NULL), SR_OK);
    assert_int_equal(o.extra_count, 1);
    assert_near(o.extra_uv[0], 1, 1e-12);
    assert_near(o.extra_uv[1], 1, 1e-12);
    /* edges 0 -> 1 and 2 -> 3 run through the made point 4; 1 -> 2 and 3 -> 0 do not */
    const size_t first[5] = {0, 1, 1, 2, 2};
    for (size_t q = 0; q < 5; q++)
        assert_int_equal(o.split_first[q], first[q]);
    assert_int_equal(o.split[0], 4);
    assert_int_equal(o.split[1], 4);
    double pos = 0, neg = 0;
    for (size_t t = 0; t < o.tri_count; t++) {
        double a = tri_signed(&o, uv, 4, t);
        if (a > 0)
            pos += a;
        else
            neg -= a;
    }
    assert_near(pos, 1, 1e-12);
    assert_near(neg, 1, 1e-12);
    const uint32_t cut[6][2] = {{0, 4}, {4, 1}, {1, 2}, {2, 4}, {4, 3}, {3, 0}};
    for (int e = 0; e < 6; e++) {
        assert_true(walks(&o, cut[e][1], cut[e][0]));
        assert_false(walks(&o, cut[e][0], cut[e][1]));
    }
    sr_planar_fill_free(&o);
}

static void a_region_wound_twice_is_kept_once(void **state)
{
    (void)state;
    const double uv[16] = {0, 0, 3, 0, 3, 3, 0, 3, 1, 1, 2, 1, 2, 2, 1, 2};
    const size_t start[3] = {0, 4, 8};
    sr_planar_fill_out o;
    assert_int_equal(sr_planar_fill(uv, start, 2, &o, NULL), SR_OK);
    double area = 0;
    for (size_t t = 0; t < o.tri_count; t++)
        area += tri_signed(&o, uv, 8, t);
    assert_near(area, -9, 1e-12);
    sr_planar_fill_free(&o);
}

static void a_non_finite_point_is_refused(void **state)
{
    (void)state;
    const double uv[6] = {0, 0, 1, 0, NAN, 1};
    const size_t start[2] = {0, 3};
    sr_planar_fill_out o;
    memset(&o, 0x5a, sizeof o);
    sr_err err;
    sr_err_clear(&err);
    assert_int_equal(sr_planar_fill(uv, start, 1, &o, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "not finite"));
    assert_int_equal(o.tri_count, (size_t)0x5a5a5a5a5a5a5a5aULL); /* untouched */
    sr_planar_fill_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_square_with_a_hole_is_filled_around_the_hole),
        cmocka_unit_test(crossing_edges_are_cut_and_filled_by_their_winding),
        cmocka_unit_test(a_region_wound_twice_is_kept_once),
        cmocka_unit_test(a_non_finite_point_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
