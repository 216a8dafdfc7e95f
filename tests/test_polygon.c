/*
 * test_polygon.c: the Clipper bridge (src/bridge/polygon.h): booleans of squares with
 * areas known by hand, a square with a hole, offsets with the closed-form area of a
 * rounded square, point location, clipping a raster against a square with a hole,
 * components, cleaning an outline to a tolerance, empty inputs, and every refusal (NaN, coordinates out of range, bad
 * start arrays, bad operation, bad offset) with the caller's output left untouched.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "bridge/polygon.h"
#include "support/assert_near.h"

/* Axis-aligned rectangle [x0,x1] x [y0,y1] appended to p, counter-clockwise (ccw = 1)
 * or clockwise. */
static void add_rect(sr_poly2 *p, double x0, double y0, double x1, double y1, int ccw)
{
    double ccw_xy[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    double cw_xy[8] = {x0, y0, x0, y1, x1, y1, x1, y0};
    assert_int_equal(sr_poly2_add_contour(p, ccw ? ccw_xy : cw_xy, 4, NULL), SR_OK);
}

static double contour_area(const sr_poly2 *p, size_t c)
{
    sr_poly2 one = {p->xy + 2 * p->start[c], (size_t[]){0, p->start[c + 1] - p->start[c]}, 1};
    return sr_poly2_area(&one);
}

/* Two 2x2 squares overlapping in a 1x1 square: [0,2]^2 and [1,3]^2. */
static void two_squares(sr_poly2 *a, sr_poly2 *b)
{
    sr_poly2_init(a);
    sr_poly2_init(b);
    add_rect(a, 0, 0, 2, 2, 1);
    add_rect(b, 1, 1, 3, 3, 1);
}

static void union_of_overlapping_squares_has_area_7(void **state)
{
    sr_poly2 a, b, out;
    two_squares(&a, &b);
    sr_poly2_init(&out);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &a, &b, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 1);
    assert_int_equal(sr_poly2_point_count(&out), 8);
    assert_near(sr_poly2_area(&out), 7.0, 1e-9);
    sr_poly2_release(&a);
    sr_poly2_release(&b);
    sr_poly2_release(&out);
}

static void intersection_difference_xor_of_squares(void **state)
{
    sr_poly2 a, b, out;
    two_squares(&a, &b);
    sr_poly2_init(&out);
    assert_int_equal(sr_poly2_boolean(SR_POLY_INTERSECTION, &a, &b, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 1.0, 1e-9);
    assert_int_equal(sr_poly2_contains(&out, 1.5, 1.5), 1);
    assert_int_equal(sr_poly2_contains(&out, 0.5, 0.5), 0);
    assert_int_equal(sr_poly2_boolean(SR_POLY_DIFFERENCE, &a, &b, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 3.0, 1e-9);
    assert_int_equal(sr_poly2_contains(&out, 1.5, 1.5), 0);
    assert_int_equal(sr_poly2_contains(&out, 0.5, 0.5), 1);
    assert_int_equal(sr_poly2_boolean(SR_POLY_XOR, &a, &b, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 6.0, 1e-9);
    assert_int_equal(sr_poly2_contains(&out, 1.5, 1.5), 0);
    assert_int_equal(sr_poly2_contains(&out, 2.5, 2.5), 1);
    sr_poly2_release(&a);
    sr_poly2_release(&b);
    sr_poly2_release(&out);
}

/* out may be one of the inputs: the old arrays are released, the result replaces them */
static void boolean_output_may_alias_an_input(void **state)
{
    sr_poly2 a, b;
    two_squares(&a, &b);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &a, &b, &a, NULL), SR_OK);
    assert_near(sr_poly2_area(&a), 7.0, 1e-9);
    sr_poly2_release(&a);
    sr_poly2_release(&b);
}

/* [0,4]^2 with the hole [1,3]^2: area 16 - 4 = 12, outer CCW, hole CW */
static void square_with_hole_cleans_to_outer_ccw_and_hole_cw(void **state)
{
    sr_poly2 p, out;
    sr_poly2_init(&p);
    sr_poly2_init(&out);
    add_rect(&p, 0, 0, 4, 4, 1);
    add_rect(&p, 1, 1, 3, 3, 0);
    assert_near(sr_poly2_area(&p), 12.0, 1e-12);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &p, NULL, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 2);
    assert_near(sr_poly2_area(&out), 12.0, 1e-9);
    int outer = contour_area(&out, 0) > 0 ? 0 : 1;
    assert_near(contour_area(&out, (size_t)outer), 16.0, 1e-9);
    assert_near(contour_area(&out, (size_t)(1 - outer)), -4.0, 1e-9);
    assert_int_equal(sr_poly2_contains(&out, 2, 2), 0);     /* in the hole */
    assert_int_equal(sr_poly2_contains(&out, 0.5, 2), 1);   /* in the ring */
    assert_int_equal(sr_poly2_contains(&out, 1, 2), -1);    /* on the hole's edge */
    assert_int_equal(sr_poly2_contains(&out, 5, 2), 0);
    sr_poly2_release(&p);
    sr_poly2_release(&out);
}

/* Non-zero rule: a hole drawn the same way round as its outer contour is no hole. */
static void same_orientation_inner_contour_is_filled_by_nonzero_rule(void **state)
{
    sr_poly2 p, out;
    sr_poly2_init(&p);
    sr_poly2_init(&out);
    add_rect(&p, 0, 0, 4, 4, 1);
    add_rect(&p, 1, 1, 3, 3, 1);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &p, NULL, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 1);
    assert_near(sr_poly2_area(&out), 16.0, 1e-9);
    sr_poly2_release(&p);
    sr_poly2_release(&out);
}

static void clockwise_input_comes_out_counter_clockwise(void **state)
{
    sr_poly2 p, out;
    sr_poly2_init(&p);
    sr_poly2_init(&out);
    add_rect(&p, 0, 0, 3, 2, 0);
    assert_near(sr_poly2_area(&p), -6.0, 1e-12);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &p, NULL, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 6.0, 1e-9);
    assert_int_equal(sr_poly2_offset(&p, 0.5, 0, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 4.0 * 3.0, 1e-9);
    sr_poly2_release(&p);
    sr_poly2_release(&out);
}

/* Square of side 10 grown by d = 1: round joins (12)^2 - (4 - pi) d^2 within the chord
 * error of SR_POLY2_ARC_TOL_MM (about 0.004 mm^2 here); mitred 144 exactly. */
static void offset_of_square_matches_closed_form_areas(void **state)
{
    sr_poly2 p, out;
    sr_poly2_init(&p);
    sr_poly2_init(&out);
    add_rect(&p, 0, 0, 10, 10, 1);
    assert_int_equal(sr_poly2_offset(&p, 1.0, 1, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 1);
    assert_near(sr_poly2_area(&out), 144.0 - (4.0 - M_PI), 0.01);
    assert_true(sr_poly2_area(&out) < 144.0 - (4.0 - M_PI)); /* chords inside the arc */
    assert_int_equal(sr_poly2_offset(&p, 2.5, 1, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 225.0 - (4.0 - M_PI) * 6.25, 0.03);
    assert_int_equal(sr_poly2_offset(&p, 1.0, 0, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 144.0, 1e-9);
    assert_int_equal(sr_poly2_offset(&p, -1.0, 1, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 64.0, 1e-9);
    assert_int_equal(sr_poly2_offset(&p, 0.0, 1, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 100.0, 1e-9);
    sr_poly2_release(&p);
    sr_poly2_release(&out);
}

static void offset_shrinking_past_half_width_is_empty(void **state)
{
    sr_poly2 p, out;
    sr_poly2_init(&p);
    sr_poly2_init(&out);
    add_rect(&p, 0, 0, 10, 4, 1);
    assert_int_equal(sr_poly2_offset(&p, -2.5, 1, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_near(sr_poly2_area(&out), 0.0, 0);
    sr_poly2_release(&p);
    sr_poly2_release(&out);
}

/* Growing a ring shrinks its hole: [0,10]^2 minus [3,7]^2 grown by 1 mitred is
 * 12^2 - 2^2 = 140. */
static void offset_of_square_with_hole_shrinks_the_hole(void **state)
{
    sr_poly2 p, out;
    sr_poly2_init(&p);
    sr_poly2_init(&out);
    add_rect(&p, 0, 0, 10, 10, 1);
    add_rect(&p, 3, 3, 7, 7, 0);
    assert_int_equal(sr_poly2_offset(&p, 1.0, 0, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 2);
    assert_near(sr_poly2_area(&out), 140.0, 1e-9);
    assert_int_equal(sr_poly2_contains(&out, 3.5, 5), 1);
    assert_int_equal(sr_poly2_contains(&out, 5, 5), 0);
    sr_poly2_release(&p);
    sr_poly2_release(&out);
}

static void contains_reports_inside_outside_and_boundary(void **state)
{
    sr_poly2 p;
    sr_poly2_init(&p);
    add_rect(&p, 0, 0, 2, 2, 1);
    assert_int_equal(sr_poly2_contains(&p, 1, 1), 1);
    assert_int_equal(sr_poly2_contains(&p, 3, 1), 0);
    assert_int_equal(sr_poly2_contains(&p, 2, 1), -1);
    assert_int_equal(sr_poly2_contains(&p, 0, 0), -1);
    assert_int_equal(sr_poly2_contains(&p, 2 + 2e-6, 1), -1); /* rounds onto the edge */
    assert_int_equal(sr_poly2_contains(&p, 2 + 2e-5, 1), 0);
    assert_int_equal(sr_poly2_contains(&p, NAN, 1), 0);
    assert_int_equal(sr_poly2_contains(&p, 1, INFINITY), 0);
    sr_poly2_release(&p);
}

static void boundary_distance_and_bounds(void **state)
{
    sr_poly2 p;
    double box[4] = {0};
    sr_poly2_init(&p);
    assert_true(isinf(sr_poly2_boundary_distance(&p, 0, 0)));
    assert_int_equal(sr_poly2_bounds(&p, box), 0);
    add_rect(&p, 0, 0, 4, 2, 1);
    assert_near(sr_poly2_boundary_distance(&p, 1, 1), 1.0, 1e-12);
    assert_near(sr_poly2_boundary_distance(&p, 7, 6), 5.0, 1e-12); /* from (4,2) */
    assert_near(sr_poly2_boundary_distance(&p, 0.5, 1), 0.5, 1e-12); /* closing edge */
    assert_int_equal(sr_poly2_bounds(&p, box), 1);
    assert_near(box[0], 0, 0);
    assert_near(box[1], 0, 0);
    assert_near(box[2], 4, 0);
    assert_near(box[3], 2, 0);
    sr_poly2_release(&p);
}

/* Horizontal lines y = -1.5, -0.5, 0.5, 1.5 from x = -3 to 3 against [-2,2]^2 minus
 * [-1,1]^2: the outer two give one piece of length 4 each, the inner two two pieces of
 * length 1 each. */
static void raster_clipped_to_square_with_hole(void **state)
{
    sr_poly2 region, out;
    sr_poly2_init(&region);
    sr_poly2_init(&out);
    add_rect(&region, -2, -2, 2, 2, 1);
    add_rect(&region, -1, -1, 1, 1, 0);
    double xy[16];
    size_t start[5] = {0, 2, 4, 6, 8};
    for (int i = 0; i < 4; i++) {
        double y = -1.5 + i;
        xy[4 * i] = (i % 2) ? 3 : -3; /* zig-zag: alternate direction */
        xy[4 * i + 1] = y;
        xy[4 * i + 2] = (i % 2) ? -3 : 3;
        xy[4 * i + 3] = y;
    }
    assert_int_equal(sr_poly2_clip_lines(&region, xy, start, 4, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 6);
    double total = 0;
    size_t long_pieces = 0;
    for (size_t c = 0; c < out.contour_count; c++) {
        assert_int_equal(out.start[c + 1] - out.start[c], 2);
        const double *p = out.xy + 2 * out.start[c];
        double len = hypot(p[2] - p[0], p[3] - p[1]);
        assert_near(p[1], p[3], 1e-12); /* still horizontal */
        total += len;
        long_pieces += len > 3.9;
        assert_true(sr_poly2_contains(&region, p[0], p[1]) != 0);
        assert_true(sr_poly2_contains(&region, p[2], p[3]) != 0);
        assert_int_equal(sr_poly2_contains(&region, 0.5 * (p[0] + p[2]), p[1]), 1);
    }
    assert_near(total, 12.0, 1e-9);
    assert_int_equal(long_pieces, 2);
    sr_poly2_release(&region);
    sr_poly2_release(&out);
}

static void components_split_and_sort_by_area(void **state)
{
    sr_poly2 p, *parts = NULL;
    size_t count = 0;
    sr_poly2_init(&p);
    add_rect(&p, 20, 0, 21, 1, 1);        /* small island, area 1 */
    add_rect(&p, 0, 0, 10, 10, 1);        /* ring of area 100 - 16 */
    add_rect(&p, 3, 3, 7, 7, 0);
    add_rect(&p, 4, 4, 6, 6, 1);          /* island in the hole, area 4 */
    assert_int_equal(sr_poly2_components(&p, &parts, &count, NULL), SR_OK);
    assert_int_equal(count, 3);
    assert_int_equal(parts[0].contour_count, 2);
    assert_near(sr_poly2_area(&parts[0]), 84.0, 1e-9);
    assert_true(contour_area(&parts[0], 0) > 0);
    assert_true(contour_area(&parts[0], 1) < 0);
    assert_near(sr_poly2_area(&parts[1]), 4.0, 1e-9);
    assert_near(sr_poly2_area(&parts[2]), 1.0, 1e-9);
    sr_poly2_components_release(parts, count);
    sr_poly2_release(&p);
}

static void empty_inputs_give_empty_or_identity_results(void **state)
{
    sr_poly2 empty, a, out, *parts = (sr_poly2 *)&parts;
    size_t count = 99;
    sr_poly2_init(&empty);
    sr_poly2_init(&a);
    sr_poly2_init(&out);
    add_rect(&a, 0, 0, 1, 1, 1);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &empty, &empty, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_int_equal(sr_poly2_boolean(SR_POLY_DIFFERENCE, &a, &empty, &out, NULL), SR_OK);
    assert_near(sr_poly2_area(&out), 1.0, 1e-9);
    assert_int_equal(sr_poly2_boolean(SR_POLY_DIFFERENCE, &empty, &a, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_int_equal(sr_poly2_boolean(SR_POLY_INTERSECTION, &a, NULL, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_int_equal(sr_poly2_offset(&empty, 1.0, 1, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_near(sr_poly2_area(&empty), 0.0, 0);
    assert_int_equal(sr_poly2_contains(&empty, 0, 0), 0);
    assert_int_equal(sr_poly2_point_count(&empty), 0);
    double line[4] = {-1, 0.5, 2, 0.5};
    size_t start[2] = {0, 2};
    assert_int_equal(sr_poly2_clip_lines(&empty, line, start, 1, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_int_equal(sr_poly2_clip_lines(&a, NULL, NULL, 0, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 0);
    assert_int_equal(sr_poly2_components(&empty, &parts, &count, NULL), SR_OK);
    assert_null(parts);
    assert_int_equal(count, 0);
    sr_poly2_release(&a);
    sr_poly2_release(&out);
    sr_poly2_release(NULL);
}

static void from_contours_and_copy(void **state)
{
    const double xy[14] = {0, 0, 2, 0, 2, 2, 0, 2, 5, 5, 6, 5, 6, 6};
    const size_t start[3] = {0, 4, 7};
    sr_poly2 p, q;
    sr_poly2_init(&p);
    sr_poly2_init(&q);
    assert_int_equal(sr_poly2_from_contours(xy, start, 2, &p, NULL), SR_OK);
    assert_int_equal(p.contour_count, 2);
    assert_near(sr_poly2_area(&p), 4.5, 1e-12);
    assert_int_equal(sr_poly2_copy(&p, &q, NULL), SR_OK);
    assert_int_equal(sr_poly2_point_count(&q), 7);
    assert_near(sr_poly2_area(&q), 4.5, 1e-12);
    sr_poly2_release(&p);
    sr_poly2_release(&q);
}

static void nan_contour_refused_and_region_unchanged(void **state)
{
    sr_poly2 p;
    sr_err err = {{0}};
    sr_poly2_init(&p);
    add_rect(&p, 0, 0, 1, 1, 1);
    const double bad[6] = {0, 0, 1, NAN, 1, 1};
    assert_int_equal(sr_poly2_add_contour(&p, bad, 3, &err), SR_E_INVALID);
    assert_msg_has(err, "point 1: y is nan");
    assert_int_equal(p.contour_count, 1);
    assert_near(sr_poly2_area(&p), 1.0, 0);
    sr_poly2_release(&p);
}

static void short_contour_refused(void **state)
{
    sr_poly2 p;
    sr_err err = {{0}};
    sr_poly2_init(&p);
    const double two[4] = {0, 0, 1, 1};
    assert_int_equal(sr_poly2_add_contour(&p, two, 2, &err), SR_E_INVALID);
    assert_msg_has(err, "at least 3 points, got 2");
    assert_int_equal(p.contour_count, 0);
}

static void coordinate_beyond_range_refused_naming_value(void **state)
{
    sr_poly2 p;
    sr_err err = {{0}};
    sr_poly2_init(&p);
    const double far[6] = {0, 0, 2e9, 0, 1, 1};
    assert_int_equal(sr_poly2_add_contour(&p, far, 3, &err), SR_E_RANGE);
    assert_msg_has(err, "x = 2e+09 mm is beyond the polygon range");
    assert_int_equal(p.contour_count, 0);
}

/* A struct built by hand (bypassing add_contour) is checked again by every entry. */
static void nan_in_hand_built_region_refused_by_boolean(void **state)
{
    double xy[6] = {0, 0, 1, 0, NAN, 1};
    size_t start[2] = {0, 3};
    sr_poly2 bad = {xy, start, 1}, a, out;
    sr_err err = {{0}};
    sr_poly2_init(&a);
    sr_poly2_init(&out);
    add_rect(&a, 0, 0, 1, 1, 1);
    add_rect(&out, 5, 5, 6, 6, 1);
    assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &a, &bad, &out, &err), SR_E_INVALID);
    assert_msg_has(err, "'second region' contour 0 point 2: x is nan");
    assert_near(sr_poly2_area(&out), 1.0, 0); /* untouched */
    assert_int_equal(sr_poly2_offset(&bad, 1, 1, &out, &err), SR_E_INVALID);
    assert_msg_has(err, "'region'");
    assert_int_equal(sr_poly2_clip_lines(&a, xy, start, 1, &out, &err), SR_E_INVALID);
    assert_msg_has(err, "'lines'");
    assert_near(sr_poly2_area(&out), 1.0, 0);
    sr_poly2_release(&a);
    sr_poly2_release(&out);
}

static void malformed_start_array_refused(void **state)
{
    const double xy[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    const size_t bad_first[2] = {1, 4};
    const size_t decreasing[3] = {0, 4, 3};
    sr_poly2 out;
    sr_err err = {{0}};
    sr_poly2_init(&out);
    assert_int_equal(sr_poly2_from_contours(xy, bad_first, 1, &out, &err), SR_E_INVALID);
    assert_msg_has(err, "start[0] is 1");
    assert_int_equal(sr_poly2_from_contours(xy, decreasing, 2, &out, &err), SR_E_INVALID);
    assert_msg_has(err, "start[2] = 3 is less than start[1] = 4");
    const size_t one_point[2] = {0, 1};
    assert_int_equal(sr_poly2_clip_lines(NULL, xy, one_point, 1, &out, &err), SR_E_INVALID);
    assert_msg_has(err, "'lines' contour 0 has 1 points, needs at least 2");
    assert_int_equal(out.contour_count, 0);
}

static void bad_operation_and_offset_refused(void **state)
{
    sr_poly2 a, out;
    sr_err err = {{0}};
    sr_poly2_init(&a);
    sr_poly2_init(&out);
    add_rect(&a, 0, 0, 1, 1, 1);
    assert_int_equal(sr_poly2_boolean((sr_poly_op)7, &a, &a, &out, &err), SR_E_RANGE);
    assert_msg_has(err, "polygon operation 7");
    assert_int_equal(sr_poly2_offset(&a, NAN, 1, &out, &err), SR_E_RANGE);
    assert_msg_has(err, "offset distance nan mm");
    assert_int_equal(sr_poly2_offset(&a, 1e10, 1, &out, &err), SR_E_RANGE);
    assert_msg_has(err, "offset distance 1e+10 mm");
    assert_int_equal(out.contour_count, 0);
    sr_poly2_release(&a);
}

/* A 10 mm square whose bottom edge carries 99 collinear points and a notch 2 um deep,
 * and whose top edge a bump 0.1 mm high: cleaned at 5 um, the collinear points and the
 * notch go, the bump (20 times the tolerance) stays. */
static void clean_drops_what_moves_the_outline_less_than_the_tolerance(void **state)
{
    double xy[2 * 120];
    size_t n = 0;
    for (int i = 0; i < 100; i++) { /* (0,0) .. (9.9,0), a notch at x = 5 */
        xy[2 * n] = 0.1 * i;
        xy[2 * n + 1] = i == 50 ? -0.002 : 0;
        n++;
    }
    double rest[] = {10, 0, 10, 10, 6, 10, 5.5, 10.1, 5, 10, 0, 10};
    for (size_t i = 0; i < sizeof rest / sizeof rest[0]; i += 2, n++) {
        xy[2 * n] = rest[i];
        xy[2 * n + 1] = rest[i + 1];
    }
    sr_poly2 a, out;
    sr_poly2_init(&a);
    sr_poly2_init(&out);
    assert_int_equal(sr_poly2_add_contour(&a, xy, n, NULL), SR_OK);
    assert_int_equal(sr_poly2_clean(&a, 0.005, &out, NULL), SR_OK);
    assert_int_equal(out.contour_count, 1);
    assert_int_equal(sr_poly2_point_count(&out), 7); /* 4 corners and the bump's 3 */
    assert_near(sr_poly2_area(&out), 100.0 + 0.5 * 1.0 * 0.1, 1e-6);
    /* every kept point is a point of the input */
    for (size_t i = 0; i < sr_poly2_point_count(&out); i++)
        assert_true(sr_poly2_boundary_distance(&a, out.xy[2 * i], out.xy[2 * i + 1]) < 1e-5);
    /* at tolerance 0 only repeated points go: the notch stays */
    assert_int_equal(sr_poly2_clean(&a, 0, &out, NULL), SR_OK);
    assert_true(sr_poly2_point_count(&out) >= 9);
    sr_err err = {{0}};
    assert_int_equal(sr_poly2_clean(&a, -1, &out, &err), SR_E_RANGE);
    assert_msg_has(err, "clean tolerance -1 mm");
    assert_int_equal(sr_poly2_clean(&a, NAN, &out, &err), SR_E_RANGE);
    sr_poly2_release(&a);
    sr_poly2_release(&out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(union_of_overlapping_squares_has_area_7),
        cmocka_unit_test(intersection_difference_xor_of_squares),
        cmocka_unit_test(boolean_output_may_alias_an_input),
        cmocka_unit_test(square_with_hole_cleans_to_outer_ccw_and_hole_cw),
        cmocka_unit_test(same_orientation_inner_contour_is_filled_by_nonzero_rule),
        cmocka_unit_test(clockwise_input_comes_out_counter_clockwise),
        cmocka_unit_test(offset_of_square_matches_closed_form_areas),
        cmocka_unit_test(offset_shrinking_past_half_width_is_empty),
        cmocka_unit_test(offset_of_square_with_hole_shrinks_the_hole),
        cmocka_unit_test(contains_reports_inside_outside_and_boundary),
        cmocka_unit_test(boundary_distance_and_bounds),
        cmocka_unit_test(raster_clipped_to_square_with_hole),
        cmocka_unit_test(components_split_and_sort_by_area),
        cmocka_unit_test(empty_inputs_give_empty_or_identity_results),
        cmocka_unit_test(from_contours_and_copy),
        cmocka_unit_test(nan_contour_refused_and_region_unchanged),
        cmocka_unit_test(short_contour_refused),
        cmocka_unit_test(coordinate_beyond_range_refused_naming_value),
        cmocka_unit_test(nan_in_hand_built_region_refused_by_boolean),
        cmocka_unit_test(malformed_start_array_refused),
        cmocka_unit_test(bad_operation_and_offset_refused),
        cmocka_unit_test(clean_drops_what_moves_the_outline_less_than_the_tolerance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
