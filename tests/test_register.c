/*
 * test_register.c: sr_register (src/align/register.c), rigid registration robust to
 * damage. Known answers: an L-shaped bar (no proper symmetry) moved by a known rigid
 * transform, whole and with a corner cut off, comes back to within micrometres of where
 * it was; every demo part's damaged mesh, turned and moved anywhere, lies back on its
 * intact mesh (any symmetric twin of the pose is as good: checked by distances); the
 * check without registration tells a moved mesh from one in place; bounding-box
 * overlap; refusals.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "align/register.h"
#include "bridge/boolean.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

/* An L: 60 x 40 outline, 12 mm legs, 15 mm thick. */
static void l_bar(sr_mesh *out)
{
    const double xy[] = {0, 0, 60, 0, 60, 12, 12, 12, 12, 40, 0, 40};
    assert_int_equal(sr_shape_prism(xy, 6, 0, 15, out, NULL), SR_OK);
}

/* A rigid transform: rotation by `deg` about the unit axis (ax, ay, az), then t. */
static void rigid(double deg, double ax, double ay, double az, double tx, double ty, double tz,
                  double m[12])
{
    double n = sqrt(ax * ax + ay * ay + az * az), k[3] = {ax / n, ay / n, az / n};
    double a = deg * M_PI / 180, c = cos(a), s = sin(a), v = 1 - c;
    double r[9] = {
        c + k[0] * k[0] * v,        k[0] * k[1] * v - k[2] * s, k[0] * k[2] * v + k[1] * s,
        k[1] * k[0] * v + k[2] * s, c + k[1] * k[1] * v,        k[1] * k[2] * v - k[0] * s,
        k[2] * k[0] * v - k[1] * s, k[2] * k[1] * v + k[0] * s, c + k[2] * k[2] * v};
    const double t[3] = {tx, ty, tz};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            m[4 * i + j] = r[3 * i + j];
        m[4 * i + 3] = t[i];
    }
}

/* Largest distance between where reg puts moved's vertices and where the original ones
 * are (moved = applied(original)). */
static double vertex_error(const sr_mesh *original, const double applied[12], const double reg[12])
{
    double worst = 0;
    for (size_t v = 0; v < original->vertex_count; v++) {
        double p[3], q[3];
        sr_xform_apply(applied, original->xyz + 3 * v, p);
        sr_xform_apply(reg, p, q);
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += (q[k] - original->xyz[3 * v + k]) * (q[k] - original->xyz[3 * v + k]);
        worst = fmax(worst, sqrt(d));
    }
    return worst;
}

static void a_moved_l_bar_comes_back(void **state)
{
    (void)state;
    sr_mesh bar, moved;
    l_bar(&bar);
    const double turns[][7] = {{0, 0, 0, 1, 0, 0, 0},       {37, 1, 2, 3, 100, -50, 20},
                               {170, 0, 1, 0, -300, 10, 5}, {95, -1, 0.5, 0.2, 0, 0, 400},
                               {180, 0, 0, 1, 30, 40, 50},  {250, 0.3, -1, 0.7, 1e3, 2e3, -5e2}};
    for (size_t i = 0; i < sizeof turns / sizeof turns[0]; i++) {
        const double *t = turns[i];
        double m[12];
        rigid(t[0], t[1], t[2], t[3], t[4], t[5], t[6], m);
        assert_int_equal(sr_mesh_copy(&moved, &bar), SR_OK);
        sr_mesh_transform(&moved, m);
        sr_register_result r;
        sr_err err = {{0}};
        assert_int_equal(sr_register(&moved, &bar, NULL, &r, &err), SR_OK);
        double e = vertex_error(&bar, m, r.mat);
        if (e > 1e-3)
            fail_msg("turn %zu: vertices land %.6f mm off (coverage %.3f)", i, e, r.coverage);
        assert_true(r.coverage > 0.999);
        assert_true(r.rms_mm < 1e-3);
        sr_mesh_release(&moved);
    }
    sr_mesh_release(&bar);
}

/* A fifth of the bar cut away (the end of the long leg): the rest still comes back,
 * and the coverage says what is left. */
static void a_damaged_l_bar_comes_back(void **state)
{
    (void)state;
    sr_mesh bar, cut, box, moved;
    l_bar(&bar);
    const double lo[3] = {45, -5, -5}, hi[3] = {70, 20, 20};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    sr_err err = {{0}};
    assert_int_equal(
        sr_boolean_compute(SR_BOOLEAN_DIFFERENCE, &bar, "bar", &box, "box", &cut, &err), SR_OK);
    double m[12];
    rigid(123, 0.2, 0.9, -0.4, 80, -20, 35, m);
    assert_int_equal(sr_mesh_copy(&moved, &cut), SR_OK);
    sr_mesh_transform(&moved, m);
    sr_register_result r;
    assert_int_equal(sr_register(&moved, &bar, NULL, &r, &err), SR_OK);
    double e = vertex_error(&cut, m, r.mat);
    if (e > 5e-3)
        fail_msg("the cut bar lands %.6f mm off (coverage %.3f)", e, r.coverage);
    /* the cut face (12 x 15 mm of about 5000 mm² of surface) is the only part off */
    assert_true(r.coverage > 0.95 && r.coverage < 0.99);
    sr_mesh_release(&moved);
    sr_mesh_release(&cut);
    sr_mesh_release(&box);
    sr_mesh_release(&bar);
}

/* Each demo part's damaged mesh, turned and moved, lies back on its intact mesh: a
 * symmetric part may come back as its symmetric twin, so the check is the distances. */
static void every_demo_part_lies_back_on_its_intact_mesh(void **state)
{
    (void)state;
    for (size_t i = 0; i < sr_demo_part_count(); i++) {
        sr_mesh intact, damaged;
        sr_err err = {{0}};
        assert_int_equal(sr_demo_part_build(i, &intact, &damaged, &err), SR_OK);
        double m[12];
        rigid(40.0 + 50.0 * (double)i, 1, -2, 0.5 + (double)i, 25, -60, 90, m);
        sr_mesh_transform(&damaged, m);
        sr_register_result before, r;
        assert_int_equal(sr_register_check(&damaged, &intact, NULL, &before, &err), SR_OK);
        assert_true(before.coverage < 0.2);
        assert_int_equal(sr_register(&damaged, &intact, NULL, &r, &err), SR_OK);
        if (!(r.coverage > 0.9 && r.median_mm < 0.01 * r.tol_mm))
            fail_msg("demo part %zu (%s): coverage %.3f, median %.4f mm, tol %.3f mm", i,
                     sr_demo_part_get(i)->number, r.coverage, r.median_mm, r.tol_mm);
        sr_mesh_release(&intact);
        sr_mesh_release(&damaged);
    }
}

static void the_check_tells_in_place_from_moved(void **state)
{
    (void)state;
    sr_mesh bar, moved;
    l_bar(&bar);
    sr_register_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_register_check(&bar, &bar, NULL, &r, &err), SR_OK);
    assert_near(r.coverage, 1.0, 0);
    assert_near(r.rotation_deg, 0, 0);
    assert_near(r.tol_mm, 0.005 * sqrt(60 * 60 + 40 * 40 + 15 * 15), 1e-9);
    double m[12];
    rigid(0, 0, 0, 1, 0, 0, 10, m);
    assert_int_equal(sr_mesh_copy(&moved, &bar), SR_OK);
    sr_mesh_transform(&moved, m);
    assert_int_equal(sr_register_check(&moved, &bar, NULL, &r, &err), SR_OK);
    assert_true(r.coverage < 0.5); /* only the walls' samples land on the bar */
    /* overlap of the boxes: 5 of 15 mm in z */
    assert_near(sr_bbox_overlap(&moved, &bar), 5.0 / 15.0, 1e-5);
    rigid(0, 0, 0, 1, 500, 0, 0, m);
    sr_mesh_transform(&moved, m);
    assert_near(sr_bbox_overlap(&moved, &bar), 0, 0);
    sr_mesh_release(&moved);
    sr_mesh_release(&bar);
}

static void a_mesh_without_area_is_refused(void **state)
{
    (void)state;
    double xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    uint32_t tri[] = {0, 1, 2};
    sr_mesh flat = {xyz, tri, 3, 1}, bar;
    l_bar(&bar);
    sr_register_result r;
    sr_err err = {{0}};
    assert_int_not_equal(sr_register(&flat, &bar, NULL, &r, &err), SR_OK);
    assert_true(err.msg[0] != 0);
    sr_mesh_release(&bar);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_moved_l_bar_comes_back),
        cmocka_unit_test(a_damaged_l_bar_comes_back),
        cmocka_unit_test(every_demo_part_lies_back_on_its_intact_mesh),
        cmocka_unit_test(the_check_tells_in_place_from_moved),
        cmocka_unit_test(a_mesh_without_area_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
