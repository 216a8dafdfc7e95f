/*
 * test_continuity.c: continuity along z for the planar symmetries (restore_continuity.h)
 * on blocks with exact answers: a skewed break through both sides of the mirror plane
 * is carried up to the block's own top face and no higher; an intact part and a hole
 * across the plane are left as the vote restored them; bad arguments are refused.
 * The layers come from the real pipeline steps: contour cuts (contour_slice.h) and the
 * mirror vote (restore_vote.h).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/boolean.h"
#include "bridge/polygon.h"
#include "slice/contour_slice.h"
#include "mesh/mesh.h"
#include "robust/restore_continuity.h"
#include "robust/restore_vote.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

#define LAYERS 136 /* z = 0.25, 0.35, .., 13.75: step 0.1 mm, so the carry stride is 5 */
#define OPEN_MM 0.05

static double layer_z(size_t l) { return 0.25 + 0.1 * (double)l; }

static size_t layer_at(double z) { return (size_t)lround((z - 0.25) / 0.1); }

static void box(double x0, double y0, double z0, double x1, double y1, double z1, sr_mesh *m)
{
    double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

static void subtract(sr_mesh *m, const sr_mesh *cut)
{
    sr_mesh out = {0};
    sr_err err = {{0}};
    sr_status st = sr_boolean_difference(m, cut, &out, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    sr_mesh_release(m);
    *m = out;
}

/* The half-space n . p > c as a big box whose bottom face lies on the plane. */
static void half_space(const double n[3], double c, sr_mesh *m)
{
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double N[3] = {n[0] / len, n[1] / len, n[2] / len};
    double U[3] = {N[1], -N[0], 0}; /* horizontal, normal to N */
    double ul = hypot(U[0], U[1]);
    U[0] /= ul;
    U[1] /= ul;
    double V[3] = {N[1] * U[2] - N[2] * U[1], N[2] * U[0] - N[0] * U[2],
                   N[0] * U[1] - N[1] * U[0]};
    double p0[3] = {N[0] * c / len, N[1] * c / len, N[2] * c / len};
    box(-100, -100, 0, 100, 100, 200, m);
    double t[12] = {U[0], V[0], N[0], p0[0], U[1], V[1], N[1], p0[1], U[2], V[2], N[2], p0[2]};
    sr_mesh_transform(m, t);
}

/* Block A (x -10..10, y 0..20, z 0..10) and the taller block B (y -30..-10, z 0..14),
 * so layers go on above A's top face. broken: A loses 0.25 x + 0.75 y + 0.6 z > 19, a
 * skewed break through both sides of x = 0 near its top +y edge. */
static void blocks(int broken, sr_mesh *m)
{
    sr_mesh b = {0};
    box(-10, 0, 0, 10, 20, 10, m);
    if (broken) {
        sr_mesh cut = {0};
        half_space((const double[3]){0.25, 0.75, 0.6}, 19.0, &cut);
        subtract(m, &cut);
        sr_mesh_release(&cut);
    }
    box(-10, -30, 0, 10, -10, 14, &b);
    assert_int_equal(sr_mesh_append(m, &b), SR_OK);
    sr_mesh_release(&b);
}

/* Area of A's doubly broken region at height z: y > (19 - 0.6 z + 0.25 |x|) / 0.75 up
 * to y = 20, a triangle of height t = 0.8 z - 16/3 and half-width 3t: 3 t^2. */
static double doubly_broken_area(double z)
{
    double t = 0.8 * z - 16.0 / 3.0;
    return t > 0 ? 3 * t * t : 0;
}

typedef struct layers {
    double z[LAYERS];
    sr_poly2 d[LAYERS], res[LAYERS], mis[LAYERS];
} layers;

/* Cut and vote (mirror x -> -x), as region_sections.c does. */
static layers *cut_and_vote(const sr_mesh *m)
{
    layers *s = calloc(1, sizeof *s);
    assert_non_null(s);
    for (size_t l = 0; l < LAYERS; l++)
        s->z[l] = layer_z(l);
    sr_contour_stack cs;
    assert_int_equal(sr_contour_slice(m, s->z, LAYERS, &cs, NULL), SR_OK);
    for (size_t l = 0; l < LAYERS; l++)
        assert_int_equal(sr_poly2_boolean(SR_POLY_UNION, &cs.raw[l], NULL, &s->d[l], NULL),
                         SR_OK);
    sr_contour_stack_release(&cs);
    sr_vote_opts vo = {.symmetry = {.kind = SR_SYM_MIRROR}, .open_mm = OPEN_MM};
    assert_int_equal(sr_vote_restore(s->d, NULL, NULL, LAYERS, &vo, s->res, s->mis, NULL),
                     SR_OK);
    return s;
}

static void layers_free(layers *s)
{
    for (size_t l = 0; l < LAYERS; l++) {
        sr_poly2_release(&s->d[l]);
        sr_poly2_release(&s->res[l]);
        sr_poly2_release(&s->mis[l]);
    }
    free(s);
}

static sr_continuity_opts mirror_opts(void)
{
    sr_continuity_opts o = {
        .symmetry = {.kind = SR_SYM_MIRROR}, .open_mm = OPEN_MM, .near_mm = 0.9};
    return o;
}

static sr_status extend(const sr_mesh *m, layers *s, size_t *carried, sr_err *err)
{
    sr_continuity_opts o = mirror_opts();
    return sr_continuity_extend(m, s->z, LAYERS, s->res, s->mis, &o, carried, err);
}

static void carries_a_break_through_both_sides_up_to_the_end_face(void **state)
{
    (void)state;
    sr_mesh m = {0};
    blocks(1, &m);
    layers *s = cut_and_vote(&m);
    size_t l = layer_at(9.45), above = layer_at(12.05);
    /* the vote alone misses the doubly broken triangle (14.88 mm^2 here) */
    assert_near(sr_poly2_area(&s->res[l]), 800.0 - doubly_broken_area(9.45), 0.05);
    size_t carried = 0;
    assert_int_equal(extend(&m, s, &carried, NULL), SR_OK);
    assert_true(carried > 0);
    /* carried from below (where the vote restored A whole) up to A's top face */
    for (double z = 7.05; z < 9.9; z += 0.5) {
        size_t k = layer_at(z);
        assert_near(sr_poly2_area(&s->res[k]), 800.0, 0.2);
        /* what is missing now: all A lost at that height */
        double lost = 400.0 - (sr_poly2_area(&s->d[k]) - 400.0);
        assert_near(sr_poly2_area(&s->mis[k]), lost, 0.2);
    }
    /* and no higher: above it only B, as the vote restored it */
    assert_near(sr_poly2_area(&s->res[above]), 400.0, 1e-6);
    assert_int_equal(s->mis[above].contour_count, 0);
    layers_free(s);
    sr_mesh_release(&m);
}

static void leaves_an_intact_part_as_the_vote_restored_it(void **state)
{
    (void)state;
    sr_mesh m = {0};
    blocks(0, &m);
    layers *s = cut_and_vote(&m);
    size_t carried = 99;
    assert_int_equal(extend(&m, s, &carried, NULL), SR_OK);
    assert_int_equal(carried, 0);
    for (size_t l = 0; l < LAYERS; l++) {
        assert_int_equal(s->mis[l].contour_count, 0);
        assert_near(sr_poly2_area(&s->res[l]), layer_z(l) < 10 ? 800.0 : 400.0, 1e-6);
    }
    layers_free(s);
    sr_mesh_release(&m);
}

/* A bolt hole along x (dia 4 at y = 12, z = 5) through both sides; the +x tip beyond
 * y = 9 broken off by a vertical cut. The vote restores the tip with its hole from the
 * -x side; the hole's own surface, which only the mirror image meets (the point
 * itself is broken away), must not carry the layer below into it. */
static void keeps_a_hole_across_the_plane_open(void **state)
{
    (void)state;
    sr_mesh m = {0}, cyl = {0}, cut = {0};
    box(-10, 0, 0, 10, 20, 10, &m);
    assert_int_equal(sr_shape_cylinder(2.0, -15, 15, 48, &cyl, NULL), SR_OK);
    double to_x[12] = {0, 0, 1, 0, 0, 1, 0, 12, -1, 0, 0, 5}; /* (x, y, z) -> (z, y + 12, 5 - x) */
    sr_mesh_transform(&cyl, to_x);
    subtract(&m, &cyl);
    box(4, 9, -5, 20, 30, 15, &cut);
    subtract(&m, &cut);
    layers *s = cut_and_vote(&m);
    double before[LAYERS];
    for (size_t l = 0; l < LAYERS; l++)
        before[l] = sr_poly2_area(&s->res[l]);
    /* the vote restored the tip with its hole: 400 minus the hole's 20 x chord */
    size_t mid = layer_at(5.05);
    assert_near(before[mid], 400.0 - 20.0 * 2 * sqrt(4.0 - 0.05 * 0.05), 0.5);
    assert_int_equal(extend(&m, s, NULL, NULL), SR_OK);
    for (size_t l = 0; l < LAYERS; l++)
        assert_near(sr_poly2_area(&s->res[l]), before[l], 1e-6);
    layers_free(s);
    sr_mesh_release(&m);
    sr_mesh_release(&cyl);
    sr_mesh_release(&cut);
}

/* sr_continuity_extend with o on a small box must fail with SR_E_RANGE naming `what`. */
static void assert_refused(sr_continuity_opts o, const char *what)
{
    sr_mesh m = {0};
    box(-1, -1, 0, 1, 1, 1, &m);
    double z[2] = {0.25, 0.75};
    sr_poly2 res[2] = {{0}}, mis[2] = {{0}};
    sr_err err = {{0}};
    size_t carried = 99;
    assert_int_equal(sr_continuity_extend(&m, z, 2, res, mis, &o, &carried, &err), SR_E_RANGE);
    assert_msg_has(err, what);
    assert_int_equal(carried, 99);
    sr_mesh_release(&m);
}

static void refuses_an_axial_symmetry(void **state)
{
    (void)state;
    sr_continuity_opts o = mirror_opts();
    o.symmetry.kind = SR_SYM_AXIAL;
    assert_refused(o, "needs a mirror or glide");
}

static void refuses_a_glide_without_a_shift(void **state)
{
    (void)state;
    sr_continuity_opts o = mirror_opts();
    o.symmetry.kind = SR_SYM_GLIDE;
    assert_refused(o, "glide shift must be > 0 mm");
}

/* near_mm 0 is the default, 3 layer spacings + 0.6 mm: here 0.9 mm as mirror_opts */
static void takes_a_zero_near_distance_as_three_layers_and_0_6_mm(void **state)
{
    (void)state;
    sr_mesh m = {0};
    blocks(1, &m);
    layers *given = cut_and_vote(&m), *zero = cut_and_vote(&m);
    sr_continuity_opts o = mirror_opts();
    size_t carried_given = 0, carried_zero = 0;
    assert_int_equal(sr_continuity_extend(&m, given->z, LAYERS, given->res, given->mis, &o,
                                          &carried_given, NULL),
                     SR_OK);
    o.near_mm = 0;
    assert_int_equal(
        sr_continuity_extend(&m, zero->z, LAYERS, zero->res, zero->mis, &o, &carried_zero, NULL),
        SR_OK);
    assert_true(carried_given > 0);
    assert_int_equal(carried_zero, carried_given);
    for (size_t l = 0; l < LAYERS; l++) {
        assert_near(sr_poly2_area(&zero->res[l]), sr_poly2_area(&given->res[l]), 1e-9);
        assert_near(sr_poly2_area(&zero->mis[l]), sr_poly2_area(&given->mis[l]), 1e-9);
    }
    layers_free(given);
    layers_free(zero);
    sr_mesh_release(&m);
}

static void refuses_a_negative_near_distance(void **state)
{
    (void)state;
    sr_continuity_opts o = mirror_opts();
    o.near_mm = -1;
    assert_refused(o, "bad option (open 0.05, near -1");
}

static void refuses_a_flat_angle_of_90_degrees(void **state)
{
    (void)state;
    sr_continuity_opts o = mirror_opts();
    o.flat_deg = 90;
    assert_refused(o, "flat 90 deg");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(carries_a_break_through_both_sides_up_to_the_end_face),
        cmocka_unit_test(leaves_an_intact_part_as_the_vote_restored_it),
        cmocka_unit_test(keeps_a_hole_across_the_plane_open),
        cmocka_unit_test(refuses_an_axial_symmetry),
        cmocka_unit_test(refuses_a_glide_without_a_shift),
        cmocka_unit_test(takes_a_zero_near_distance_as_three_layers_and_0_6_mm),
        cmocka_unit_test(refuses_a_negative_near_distance),
        cmocka_unit_test(refuses_a_flat_angle_of_90_degrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
