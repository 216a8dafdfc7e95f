/*
 * test_layer_flats.c: flat-face area at the robust method's layer planes
 * (layer_flats.h) on solids with known faces: planes away from every face across z
 * read none, side walls crossing them count for nothing; a plane on a shoulder, exact
 * or noisy, reads the shoulder's area; a glide's image plane one shift away counts as
 * the layer's own; bad options are refused and leave the output alone.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "robust/layer_flats.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

#define MARGIN 0.2
#define SEGMENTS 48

static double step_radius(double theta, size_t ring, void *user)
{
    (void)theta;
    (void)user;
    return ring < 2 ? 10.0 : 6.0;
}

/* A stepped shaft: radius 10 for z 0..5, radius 6 for z 5..10 (a shoulder at z = 5),
 * as 48-gons. */
static void stepped_shaft(sr_mesh *m)
{
    static const double z[4] = {0, 5, 5, 10};
    sr_revolve_opts o = {.segments = SEGMENTS, .ring_count = 4, .ring_z = z, .outer = step_radius};
    assert_int_equal(sr_shape_revolve(&o, m, NULL), SR_OK);
}

/* Area of a regular n-gon of circumradius r. */
static double ngon(double r) { return SEGMENTS / 2.0 * r * r * sin(2 * M_PI / SEGMENTS); }

static void planes_away_from_flat_faces_read_none(void **state)
{
    (void)state;
    sr_mesh m = {0};
    double lo[3] = {-3, -2, 0}, hi[3] = {3, 2, 10};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    /* planes 0.5 .. 9.5: the end faces are 0.5 away, the side walls cross every plane */
    sr_layer_flats_opts o = {.z_init = 0, .dz = 1.0, .layers = 10, .margin_mm = MARGIN};
    double a[10];
    assert_int_equal(sr_layer_flats_area(&m, &o, a, NULL), SR_OK);
    for (size_t l = 0; l < 10; l++)
        assert_true(a[l] == 0);
    /* the end faces do count once a plane comes within the margin of them */
    /* planes -0.1 .. 9.9 */
    sr_layer_flats_opts near = {.z_init = -0.35, .dz = 0.5, .layers = 21, .margin_mm = MARGIN};
    double b[21];
    assert_int_equal(sr_layer_flats_area(&m, &near, b, NULL), SR_OK);
    assert_near(b[0], 24.0, 1e-9);
    assert_near(b[20], 24.0, 1e-9);
    for (size_t l = 1; l < 20; l++)
        assert_true(b[l] == 0);
    sr_mesh_release(&m);
}

/* Nine layers over z 0..10: layer 4's plane is the shoulder itself (z = 5). */
static void a_plane_on_a_shoulder_reads_its_area(void **state)
{
    (void)state;
    sr_mesh m = {0};
    stepped_shaft(&m);
    sr_layer_flats_opts o = {.z_init = 0, .dz = 10.0 / 9, .layers = 9, .margin_mm = MARGIN};
    double a[9];
    assert_int_equal(sr_layer_flats_area(&m, &o, a, NULL), SR_OK);
    assert_near(a[4], ngon(10) - ngon(6), 1e-9);
    for (size_t l = 0; l < 9; l++)
        if (l != 4)
            assert_true(a[l] == 0);
    sr_mesh_release(&m);
}

/* The same shoulder with every vertex on it lifted or lowered by up to 0.03 mm (a noisy
 * scan of it): still read whole (its triangles tilt by well under 18 degrees). */
static void a_plane_on_a_noisy_shoulder_reads_its_area(void **state)
{
    (void)state;
    sr_mesh m = {0};
    stepped_shaft(&m);
    unsigned s = 12345;
    for (size_t v = 0; v < m.vertex_count; v++)
        if (fabs(m.xyz[3 * v + 2] - 5.0) < 1e-9) {
            s = s * 1103515245u + 12345u;
            m.xyz[3 * v + 2] += 0.03 * ((double)(s >> 16 & 0x7fff) / 16383.5 - 1.0);
        }
    sr_layer_flats_opts o = {.z_init = 0, .dz = 10.0 / 9, .layers = 9, .margin_mm = MARGIN};
    double a[9];
    assert_int_equal(sr_layer_flats_area(&m, &o, a, NULL), SR_OK);
    assert_near(a[4], ngon(10) - ngon(6), 0.01 * (ngon(10) - ngon(6)));
    assert_true(a[3] == 0 && a[5] == 0);
    sr_mesh_release(&m);
}

/* A glide compares each layer with its images one shift above and below: a plane well
 * below the shoulder reads it when its image plane one shift up lands on it. */
static void an_image_plane_on_a_shoulder_counts_for_the_layer(void **state)
{
    (void)state;
    sr_mesh m = {0};
    stepped_shaft(&m);
    sr_layer_flats_opts o = {.z_init = 0, .dz = 10.0 / 9, .layers = 9, .margin_mm = MARGIN};
    double plane2 = 2.5 * o.dz; /* layer 2's plane */
    double shifts[2] = {5.0 - plane2, -(5.0 - plane2)};
    double alone[9], glide[9];
    assert_int_equal(sr_layer_flats_area(&m, &o, alone, NULL), SR_OK);
    o.shifts = shifts;
    o.shift_count = 2;
    assert_int_equal(sr_layer_flats_area(&m, &o, glide, NULL), SR_OK);
    assert_true(alone[2] == 0);
    assert_near(glide[2], ngon(10) - ngon(6), 1e-9);
    sr_mesh_release(&m);
}

/* margin_mm 0 is SR_LAYER_FLATS_MARGIN_MM: an end face 0.04 mm off a plane counts, one
 * 0.1 mm off does not (a margin reads up to one bin, margin / 4, further) */
static void a_zero_margin_is_the_default(void **state)
{
    (void)state;
    sr_mesh m = {0};
    double lo[3] = {-3, -2, 0}, hi[3] = {3, 2, 10};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    sr_layer_flats_opts o = {.z_init = -0.54, .dz = 1.0, .layers = 1}; /* plane -0.04 */
    double a = -1;
    assert_int_equal(sr_layer_flats_area(&m, &o, &a, NULL), SR_OK);
    assert_near(a, 24.0, 1e-9);
    o.z_init = -0.6; /* plane -0.1 */
    assert_int_equal(sr_layer_flats_area(&m, &o, &a, NULL), SR_OK);
    assert_true(a == 0);
    o.margin_mm = SR_LAYER_FLATS_MARGIN_MM;
    assert_int_equal(sr_layer_flats_area(&m, &o, &a, NULL), SR_OK);
    assert_true(a == 0);
    sr_mesh_release(&m);
}

static void bad_options_are_refused(void **state)
{
    (void)state;
    sr_mesh m = {0};
    stepped_shaft(&m);
    double a[4] = {1, 2, 3, 4}, before[4];
    memcpy(before, a, sizeof a);
    sr_err err = {{0}};
    sr_layer_flats_opts zero_dz = {.z_init = 0, .dz = 0, .layers = 4, .margin_mm = MARGIN};
    assert_int_equal(sr_layer_flats_area(&m, &zero_dz, a, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "dz 0 mm"));
    sr_layer_flats_opts no_layers = {.z_init = 0, .dz = 1, .layers = 0, .margin_mm = MARGIN};
    assert_int_equal(sr_layer_flats_area(&m, &no_layers, a, &err), SR_E_RANGE);
    sr_layer_flats_opts nan_margin = {.z_init = 0, .dz = 1, .layers = 4, .margin_mm = NAN};
    assert_int_equal(sr_layer_flats_area(&m, &nan_margin, a, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "margin"));
    assert_memory_equal(a, before, sizeof a);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(planes_away_from_flat_faces_read_none),
        cmocka_unit_test(a_plane_on_a_shoulder_reads_its_area),
        cmocka_unit_test(a_plane_on_a_noisy_shoulder_reads_its_area),
        cmocka_unit_test(an_image_plane_on_a_shoulder_counts_for_the_layer),
        cmocka_unit_test(a_zero_margin_is_the_default),
        cmocka_unit_test(bad_options_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
