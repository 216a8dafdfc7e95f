/*
 * test_rim_crossings.c: sr_scan_rim_crossings (src/mesh/rim_crossings.c) on loops with
 * known crossings: a square (none), a bow tie (one), two squares overlapping (two), a
 * pentagram (five; stopped at the limit), two combs laced through each other (n x n),
 * and loops that touch at a corner or share an edge's end (no proper crossing).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "mesh/scan_int.h"

static void a_square_does_not_cross_itself(void **state)
{
    (void)state;
    const double uv[] = {0, 0, 1, 0, 1, 1, 0, 1};
    const size_t start[] = {0, 4};
    assert_int_equal(sr_scan_rim_crossings(uv, start, 1, 100), 0);
}

static void a_bow_tie_crosses_once(void **state)
{
    (void)state;
    const double uv[] = {0, 0, 1, 1, 1, 0, 0, 1};
    const size_t start[] = {0, 4};
    assert_int_equal(sr_scan_rim_crossings(uv, start, 1, 100), 1);
}

static void two_squares_overlapping_cross_twice(void **state)
{
    (void)state;
    const double uv[] = {0, 0, 2, 0, 2, 2, 0, 2, 1, 1, 3, 1, 3, 3, 1, 3};
    const size_t start[] = {0, 4, 8};
    assert_int_equal(sr_scan_rim_crossings(uv, start, 2, 100), 2);
}

static void a_pentagram_crosses_five_times_counted_to_the_limit(void **state)
{
    (void)state;
    /* the points of a regular pentagon, taken every second one */
    const double uv[] = {0.0,      1.0,       -0.587785, -0.809017, 0.951057,
                         0.309017, -0.951057, 0.309017,  0.587785,  -0.809017};
    const size_t start[] = {0, 5};
    assert_int_equal(sr_scan_rim_crossings(uv, start, 1, 100), 5);
    assert_int_equal(sr_scan_rim_crossings(uv, start, 1, 2), 3); /* stopped past 2 */
}

/* A comb: a loop whose n teeth, each a thin slot, run along y (or, turned, along x). */
static size_t comb(double *uv, size_t n, int turned)
{
    size_t p = 0;
    for (size_t i = 0; i < n; i++) { /* up and down each tooth */
        double x = 2.0 * (double)i + 1;
        double pt[4][2] = {
            {x, 0}, {x, 2.0 * (double)n + 1}, {x + 0.5, 2.0 * (double)n + 1}, {x + 0.5, 0}};
        for (int k = 0; k < 4; k++, p++) {
            uv[2 * p] = turned ? pt[k][1] : pt[k][0];
            uv[2 * p + 1] = turned ? pt[k][0] : pt[k][1];
        }
    }
    return p;
}

static void two_combs_laced_cross_at_every_tooth(void **state)
{
    (void)state;
    enum { N = 12 };
    double uv[2 * 8 * N];
    size_t a = comb(uv, N, 0), b = comb(uv + 2 * a, N, 1);
    const size_t start[] = {0, a, a + b};
    /* each of a comb's 2N long edges crosses each of the other's 2N: the returns along
     * the base (y = 0 or x = 0) lie beyond the other's teeth */
    assert_int_equal(sr_scan_rim_crossings(uv, start, 2, 100000), 4 * N * N);
}

static void loops_touching_at_a_corner_do_not_cross(void **state)
{
    (void)state;
    const double uv[] = {0, 0, 1, 0, 1, 1, 0, 1, 1, 1, 2, 1, 2, 2, 1, 2};
    const size_t start[] = {0, 4, 8};
    assert_int_equal(sr_scan_rim_crossings(uv, start, 2, 100), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_square_does_not_cross_itself),
        cmocka_unit_test(a_bow_tie_crosses_once),
        cmocka_unit_test(two_squares_overlapping_cross_twice),
        cmocka_unit_test(a_pentagram_crosses_five_times_counted_to_the_limit),
        cmocka_unit_test(two_combs_laced_cross_at_every_tooth),
        cmocka_unit_test(loops_touching_at_a_corner_do_not_cross),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
