/*
 * test_order_detect.c: the cyclic order of an axial part found from its sector grid
 * (order_detect.h), on profiles with known answers: round (with noise, with a key)
 * gives 0; a 7-lobed profile (7 does not divide the 240 sectors), a hexagon and a
 * 20-tooth wheel with one tooth broken and noise give 7, 6 and 20, not a divisor and
 * not a neighbour; a single lobe has no order; a solid of revolution cut by the real
 * slicer gives its order; bad arguments are refused and leave *out alone.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "align/order_detect.h"
#include "mesh/shapes.h"
#include "slice/slice.h"

#define LAYERS 20
#define SECTORS 240
#define TOL 0.05

typedef double (*profile_fn)(double theta, size_t layer);

static unsigned rng = 2024;

/* Uniform in [-a, a], deterministic. */
static double jitter(double a)
{
    rng = rng * 1103515245u + 12345u;
    return a * ((double)(rng >> 16 & 0x7fff) / 16383.5 - 1.0);
}

/* A grid whose cell (l, k) holds profile(theta at the sector's centre) + noise. */
static void grid_of(profile_fn f, double noise, sr_layer_grid *g)
{
    assert_int_equal(sr_layer_grid_alloc(g, LAYERS, SECTORS, 0, 1), SR_OK);
    for (size_t l = 0; l < LAYERS; l++)
        for (size_t k = 0; k < SECTORS; k++)
            g->r[l * SECTORS + k] = f(sr_sector_angle(k, SECTORS), l) + jitter(noise);
}

static int detect(profile_fn f, double noise, sr_order_detection *o)
{
    sr_layer_grid g;
    grid_of(f, noise, &g);
    assert_int_equal(sr_order_detect(&g, TOL, o, NULL), SR_OK);
    sr_layer_grid_release(&g);
    return o->order;
}

static double round_profile(double t, size_t l) { (void)t; (void)l; return 15.0; }

/* a key on +y, 20 degrees wide, 4 mm proud */
static double keyed_profile(double t, size_t l)
{
    (void)l;
    return fabs(remainder(t - M_PI / 2, 2 * M_PI)) < 10 * M_PI / 180 ? 19.0 : 15.0;
}

static double lobed7_profile(double t, size_t l) { (void)l; return 10 + 1.5 * cos(7 * t); }

/* a regular hexagon of apothem 10 */
static double hex_profile(double t, size_t l)
{
    (void)l;
    double a = fmod(t, M_PI / 3) - M_PI / 6;
    return 10 / cos(a);
}

/* 20 teeth: tip radius 33 over the first half of each 18-degree period, root 27 over
 * the rest; the tooth at 0 degrees is broken down to the root in layers 5..14 */
static double gear_profile(double t, size_t l)
{
    double period = 2 * M_PI / 20, u = fmod(t, period) / period;
    int tooth = (int)(t / period);
    if (tooth == 0 && l >= 5 && l < 15)
        return 27.0;
    return u < 0.5 ? 33.0 : 27.0;
}

static double single_lobe_profile(double t, size_t l)
{
    (void)l;
    return 10 + 3 * fmax(0, cos(t));
}

static void a_round_part_is_continuous(void **state)
{
    (void)state;
    sr_order_detection o;
    assert_int_equal(detect(round_profile, 0.02, &o), 0);
    assert_int_equal(o.round, 1);
    assert_int_equal(o.layers_used, LAYERS);
    assert_true(o.base_mm <= TOL);
    /* a key on a few sectors is left out of the mismatch: still round */
    assert_int_equal(detect(keyed_profile, 0.02, &o), 0);
    assert_int_equal(o.round, 1);
}

static void lobes_hexagon_and_teeth_give_their_order(void **state)
{
    (void)state;
    sr_order_detection o;
    assert_int_equal(detect(lobed7_profile, 0, &o), 7);
    assert_int_equal(o.round, 0);
    assert_true(o.mismatch_mm < 0.05 && o.base_mm > 10 * o.mismatch_mm);
    assert_int_equal(detect(hex_profile, 0.01, &o), 6);
    /* a broken tooth and noise: 20, not its divisor 10 nor its neighbours 19 and 21 */
    assert_int_equal(detect(gear_profile, 0.03, &o), 20);
    assert_true(o.mismatch_mm <= TOL);
}

static void a_single_lobe_has_no_order(void **state)
{
    (void)state;
    sr_order_detection o;
    assert_int_equal(detect(single_lobe_profile, 0, &o), 0);
    assert_int_equal(o.round, 0);
    assert_true(o.base_mm > TOL);
}

static double lobed5_radius(double theta, size_t ring, void *user)
{
    (void)ring;
    (void)user;
    return 20 + 2 * cos(5 * theta);
}

/* A 5-lobed solid of revolution, 360 vertices per ring, cut by the real slicer at 80
 * layers x 120 sectors. */
static void a_sliced_five_lobed_solid_gives_five(void **state)
{
    (void)state;
    static const double z[2] = {0, 10};
    sr_revolve_opts ro = {.segments = 360, .ring_count = 2, .ring_z = z, .outer = lobed5_radius};
    sr_mesh m = {0};
    assert_int_equal(sr_shape_revolve(&ro, &m, NULL), SR_OK);
    sr_slice_opts so = {.layers = 80, .sectors = 120};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&m, &so, &g, NULL), SR_OK);
    sr_order_detection o;
    assert_int_equal(sr_order_detect(&g, TOL, &o, NULL), SR_OK);
    assert_int_equal(o.order, 5);
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

static void bad_arguments_are_refused(void **state)
{
    (void)state;
    sr_layer_grid g;
    grid_of(round_profile, 0, &g);
    sr_order_detection o, before;
    memset(&o, 0x5a, sizeof o);
    before = o;
    sr_err err = {{0}};
    assert_int_equal(sr_order_detect(&g, 0, &o, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "tolerance"));
    assert_int_equal(sr_order_detect(&g, NAN, &o, &err), SR_E_RANGE);
    /* no layer with a point in every sector (a bore seen alone, an open scan) */
    g.r[3] = 0;
    for (size_t l = 1; l < LAYERS; l++)
        g.r[l * SECTORS + 7] = 0;
    assert_int_equal(sr_order_detect(&g, TOL, &o, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "every sector"));
    sr_layer_grid_release(&g);
    sr_layer_grid tiny;
    assert_int_equal(sr_layer_grid_alloc(&tiny, 2, 3, 0, 1), SR_OK);
    assert_int_equal(sr_order_detect(&tiny, TOL, &o, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "3 sectors"));
    sr_layer_grid_release(&tiny);
    assert_memory_equal(&o, &before, sizeof o);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_round_part_is_continuous),
        cmocka_unit_test(lobes_hexagon_and_teeth_give_their_order),
        cmocka_unit_test(a_single_lobe_has_no_order),
        cmocka_unit_test(a_sliced_five_lobed_solid_gives_five),
        cmocka_unit_test(bad_arguments_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
