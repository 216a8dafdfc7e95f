/*
 * test_slice.c: Algorithms 1 and 2 on geometry with known outlines: a regular prism
 * has radius r in every sector and layer; a square's per-sector maximum sits exactly on
 * the sector borders (the clipped-segment ends), including across the ±pi and 0/2pi
 * seams; the one-pass sweep equals the paper's per-layer loop cell for cell.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "slice/slice.h"
#include "support/assert_near.h"

/* Regular n-gon prism, vertex i at angle phase + 2 pi i / n, radius r, z in [0, h]. */
static void make_prism(sr_mesh *m, int n, double r, double h, double phase)
{
    assert_int_equal(sr_mesh_alloc(m, 2 * n + 2, 4 * n), SR_OK);
    for (int i = 0; i < n; i++) {
        double a = phase + 2 * M_PI * i / n;
        double *p = m->xyz + 3 * i, *q = m->xyz + 3 * (n + i);
        p[0] = q[0] = r * cos(a);
        p[1] = q[1] = r * sin(a);
        p[2] = 0;
        q[2] = h;
    }
    double *c0 = m->xyz + 3 * (2 * n), *c1 = m->xyz + 3 * (2 * n + 1);
    c0[0] = c0[1] = c0[2] = 0;
    c1[0] = c1[1] = 0;
    c1[2] = h;
    uint32_t *t = m->tri;
    for (int i = 0; i < n; i++) {
        uint32_t a = i, b = (i + 1) % n, A = n + a, B = n + b;
        uint32_t tris[4][3] = {{a, b, B}, {a, B, A}, {2 * n, b, a}, {2 * n + 1, A, B}};
        memcpy(t, tris, sizeof tris);
        t += 12;
    }
}

static void sector_index_follows_atan2_and_wraps(void **state)
{
    assert_int_equal(sr_sector_of(1, 0, 8), 0);
    assert_int_equal(sr_sector_of(1, 1e-9, 8), 0);
    assert_int_equal(sr_sector_of(1, -1e-9, 8), 7);
    assert_int_equal(sr_sector_of(0, 1, 8), 2);
    assert_int_equal(sr_sector_of(-1, 0, 8), 4);
    assert_int_equal(sr_sector_of(-1, -1e-9, 8), 4);
    assert_int_equal(sr_sector_of(0, -1, 8), 6);
    assert_int_equal(sr_sector_of(0, 0, 8), SIZE_MAX);
}

static void prism_has_radius_r_in_every_sector_and_layer(void **state)
{
    sr_mesh m;
    make_prism(&m, 720, 20.0, 50.0, 0.0);
    sr_slice_opts o = {.layers = 40, .sectors = 60};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&m, &o, &g, NULL), SR_OK);
    assert_near(g.dz, 50.0 / 40, 1e-12);
    assert_near(sr_layer_z(&g, 0), 0.625, 1e-12);
    for (size_t i = 0; i < g.layers * g.sectors; i++) {
        assert_near(g.r[i], 20.0, 1e-9);
        size_t k = i % g.sectors;
        double a = atan2(g.pt[3 * i + 1], g.pt[3 * i]);
        if (a < 0)
            a += 2 * M_PI;
        double lo = 2 * M_PI * k / g.sectors, hi = 2 * M_PI * (k + 1) / g.sectors;
        assert_true(a >= lo - 1e-9 && a <= hi + 1e-9);
        assert_near(g.pt[3 * i + 2], sr_layer_z(&g, i / g.sectors), 1e-12);
    }
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

/* Distance from the axis of the square with vertices at 45 + 90k deg, circumradius R,
 * at polar angle phi. */
static double square_r(double R, double phi)
{
    double a = R / sqrt(2.0);
    double d = fmod(phi, M_PI / 2);
    if (d > M_PI / 4)
        d = M_PI / 2 - d;
    return a / cos(d);
}

static void square_maximum_is_at_clipped_segment_ends(void **state)
{
    sr_mesh m;
    const double R = 10;
    make_prism(&m, 4, R, 1.0, M_PI / 4);
    sr_slice_opts o = {.layers = 3, .sectors = 16};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&m, &o, &g, NULL), SR_OK);
    for (size_t k = 0; k < 16; k++) {
        double lo = 2 * M_PI * k / 16, hi = 2 * M_PI * (k + 1) / 16;
        double expect = fmax(square_r(R, lo), square_r(R, hi));
        /* corners (at 45 + 90j deg) inside the wedge are maxima too */
        for (int j = 0; j < 4; j++) {
            double c = M_PI / 4 + j * M_PI / 2;
            if (c >= lo && c <= hi)
                expect = R;
        }
        for (size_t l = 0; l < 3; l++)
            assert_near(g.r[l * 16 + k], expect, 1e-12);
    }
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

static void sweep_equals_literal_loop_cell_for_cell(void **state)
{
    sr_mesh m;
    make_prism(&m, 37, 13.0, 20.0, 0.3);
    /* tilt it so triangles cross many layers and sectors unevenly */
    double c = cos(0.4), s = sin(0.4);
    double rx[12] = {1, 0, 0, 0.7, 0, c, -s, -0.4, 0, s, c, 0};
    sr_mesh_transform(&m, rx);
    sr_slice_opts o = {.layers = 57, .sectors = 91};
    sr_layer_grid a, b;
    assert_int_equal(sr_slice_accurate(&m, &o, &a, NULL), SR_OK);
    assert_int_equal(sr_slice_accurate_literal(&m, &o, &b, NULL), SR_OK);
    assert_memory_equal(a.r, b.r, a.layers * a.sectors * sizeof(double));
    assert_memory_equal(a.pt, b.pt, a.layers * a.sectors * 3 * sizeof(double));
    size_t filled = 0;
    for (size_t i = 0; i < a.layers * a.sectors; i++)
        filled += a.r[i] > 0;
    assert_true(filled > a.layers * a.sectors / 2);
    sr_layer_grid_release(&a);
    sr_layer_grid_release(&b);
    sr_mesh_release(&m);
}

static void fast_slice_only_sees_vertices(void **state)
{
    /* the 4-gon has vertices only at 4 angles: Alg. 1 fills 4 of 16 sectors per layer,
     * and only in the layers holding the end vertices */
    sr_mesh m;
    make_prism(&m, 4, 10, 1.0, M_PI / 4);
    sr_slice_opts o = {.layers = 4, .sectors = 16};
    sr_layer_grid g;
    assert_int_equal(sr_slice_fast(&m, &o, &g, NULL), SR_OK);
    size_t filled = 0;
    for (size_t i = 0; i < 64; i++) {
        if (g.r[i] > 0) {
            filled++;
            assert_near(g.r[i], 10, 1e-12);
        }
    }
    assert_int_equal(filled, 8);
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

static void hollow_layer_leaves_no_point_on_axis(void **state)
{
    /* a ring: two prisms, inner one flipped, gives max = outer radius; a sector that
     * the model does not reach stays 0 */
    sr_mesh m;
    make_prism(&m, 64, 5, 2, 0);
    double shift[12] = {1, 0, 0, 20, 0, 1, 0, 0, 0, 0, 1, 0};
    sr_mesh_transform(&m, shift); /* a cylinder off the axis: only a few sectors hit */
    sr_slice_opts o = {.layers = 2, .sectors = 36};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&m, &o, &g, NULL), SR_OK);
    size_t empty = 0;
    for (size_t k = 0; k < 36; k++)
        empty += g.r[k] == 0;
    /* the disc of radius 5 at distance 20 spans asin(5/20) = 14.48 deg each side */
    assert_true(empty >= 36 - 4);
    assert_near(g.r[0], 25, 1e-9);
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

static void bad_options_are_refused(void **state)
{
    sr_mesh m;
    make_prism(&m, 8, 1, 1, 0);
    sr_layer_grid g;
    sr_err err = {{0}};
    sr_slice_opts o = {.layers = 0, .sectors = 10};
    assert_int_equal(sr_slice_accurate(&m, &o, &g, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "layers 0"));
    o.layers = 10;
    o.sectors = 2;
    assert_int_equal(sr_slice_accurate(&m, &o, &g, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "sectors 2"));
    /* a flat model has no height */
    o.sectors = 8;
    for (size_t v = 0; v < m.vertex_count; v++)
        m.xyz[3 * v + 2] = 0;
    assert_int_equal(sr_slice_accurate(&m, &o, &g, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "no height"));
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sector_index_follows_atan2_and_wraps),
        cmocka_unit_test(prism_has_radius_r_in_every_sector_and_layer),
        cmocka_unit_test(square_maximum_is_at_clipped_segment_ends),
        cmocka_unit_test(sweep_equals_literal_loop_cell_for_cell),
        cmocka_unit_test(fast_slice_only_sees_vertices),
        cmocka_unit_test(hollow_layer_leaves_no_point_on_axis),
        cmocka_unit_test(bad_options_are_refused),
    };
    return cmocka_run_group_tests_name("slice", tests, NULL, NULL);
}
