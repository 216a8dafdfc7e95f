/*
 * test_region_sections.c: the layer method's core (robust/region_sections.h) asked for a
 * region of interest and for chosen sections only, as the image method's continuation
 * across a mirror plane asks it. A mirror-symmetric block with a notch of known volume
 * on one side: the whole run finds it; a box holding the notch finds the same section
 * to the bit and makes no restored outline; a box that cuts the notch drops it (its
 * size is not known); a `want` that refuses gets no section, and the box it is shown
 * holds the section's patch. A block whose face is meshed in fine strips gets the
 * patch of the plain block.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/boolean.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "robust/region_sections.h"
#include "slice/slice.h"
#include "support/assert_near.h"

/* block [-10, 10] x [-10, 10] x [0, 10] (mirror plane x = 0) less the notch
 * [3, 8] x [6, 11] x [3, 7] in its y = 10 face: 5 x 4 x 4 = 80 mm^3 */
#define NOTCH_MM3 80.0

/* block (released here) less the notch, sliced into *grid */
static void notch_and_slice(sr_mesh *block, sr_mesh *out, sr_layer_grid *grid)
{
    sr_mesh notch;
    double nlo[3] = {3, 6, 3}, nhi[3] = {8, 11, 7};
    assert_int_equal(sr_shape_box(nlo, nhi, &notch, NULL), SR_OK);
    assert_int_equal(sr_boolean_difference(block, &notch, out, NULL), SR_OK);
    sr_slice_opts so = {.layers = 100, .sectors = 120};
    assert_int_equal(sr_slice_accurate(out, &so, grid, NULL), SR_OK);
    sr_mesh_release(block);
    sr_mesh_release(&notch);
}

static void notched_block(sr_mesh *out, sr_layer_grid *grid)
{
    sr_mesh block;
    double lo[3] = {-10, -10, 0}, hi[3] = {10, 10, 10};
    assert_int_equal(sr_shape_box(lo, hi, &block, NULL), SR_OK);
    notch_and_slice(&block, out, grid);
}

static sr_region_opts mirror_opts(void)
{
    sr_region_opts o = {.symmetry = {.kind = SR_SYM_MIRROR},
                        .open_mm = 0.05,
                        .min_depth_mm = 0.0, /* the boxes are what is tested */
                        .min_volume_mm3 = 1.0};
    return o;
}

static void run(const sr_mesh *m, const sr_layer_grid *g, const sr_region_opts *o,
                sr_analysis *an, sr_section **sec, size_t *n)
{
    sr_err err = {{0}};
    sr_status st = sr_region_reconstruct(m, g, o, an, sec, n, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
}

static void a_box_holding_the_notch_finds_the_same_section(void **state)
{
    (void)state;
    sr_mesh m;
    sr_layer_grid g;
    notched_block(&m, &g);
    sr_region_opts o = mirror_opts();
    sr_analysis whole = {0}, boxed = {0};
    sr_section *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    run(&m, &g, &o, &whole, &a, &na);
    assert_int_equal(na, 1);
    print_message("whole run: %.2f mm^3\n", a[0].volume_mm3);
    assert_near(a[0].volume_mm3, NOTCH_MM3, 0.05 * NOTCH_MM3);
    assert_non_null(whole.restored_r);

    o.have_roi = 1;
    double roi[6] = {-12, 2, 1, 12, 12, 9};
    memcpy(o.roi, roi, sizeof roi);
    run(&m, &g, &o, &boxed, &b, &nb);
    assert_int_equal(nb, 1);
    assert_true(b[0].volume_mm3 == a[0].volume_mm3);
    assert_int_equal(b[0].patch.tri_count, a[0].patch.tri_count);
    assert_null(boxed.restored_r); /* no outline asked for */
    sr_sections_release(a, na);
    sr_sections_release(b, nb);
    sr_analysis_release(&whole);
    sr_mesh_release(&m);
    sr_layer_grid_release(&g);
}

static void a_box_that_cuts_the_notch_drops_it(void **state)
{
    (void)state;
    sr_mesh m;
    sr_layer_grid g;
    notched_block(&m, &g);
    sr_region_opts o = mirror_opts();
    o.have_roi = 1;
    double roi[6] = {-12, 2, 1, 12, 12, 5}; /* z up to 5: the notch runs to 7 */
    memcpy(o.roi, roi, sizeof roi);
    sr_analysis an = {0};
    sr_section *s = NULL;
    size_t n = 9;
    run(&m, &g, &o, &an, &s, &n);
    assert_int_equal(n, 0);
    sr_sections_release(s, n);
    sr_mesh_release(&m);
    sr_layer_grid_release(&g);
}

typedef struct shown {
    int calls, answer;
    double box[6], volume;
} shown;

static int want_shown(const double box[6], double volume, void *ctx)
{
    shown *w = ctx;
    w->calls++;
    memcpy(w->box, box, sizeof w->box);
    w->volume = volume;
    return w->answer;
}

static void want_chooses_the_sections_that_get_a_patch(void **state)
{
    (void)state;
    sr_mesh m;
    sr_layer_grid g;
    notched_block(&m, &g);
    sr_region_opts o = mirror_opts();
    shown w = {0};
    o.want = want_shown;
    o.want_ctx = &w;
    sr_analysis an = {0};
    sr_section *s = NULL;
    size_t n = 0;
    run(&m, &g, &o, &an, &s, &n);
    assert_int_equal(w.calls, 1);
    assert_int_equal(n, 0);
    assert_near(w.volume, NOTCH_MM3, 0.05 * NOTCH_MM3);
    sr_sections_release(s, n);
    sr_analysis_release(&an);

    w.answer = 1;
    memset(&an, 0, sizeof an);
    run(&m, &g, &o, &an, &s, &n);
    assert_int_equal(n, 1);
    assert_true(s[0].volume_mm3 == w.volume);
    double lo[3], hi[3];
    sr_mesh_bbox(&s[0].patch, lo, hi);
    for (int a = 0; a < 3; a++) {
        assert_true(w.box[a] <= lo[a] + 1e-9);
        assert_true(w.box[3 + a] >= hi[a] - 1e-9);
    }
    sr_sections_release(s, n);
    sr_analysis_release(&an);
    sr_mesh_release(&m);
    sr_layer_grid_release(&g);
}

/* The notched block with its y = 10 face cut into 0.2 mm strips (101 collinear points
 * on every slice of it): the patch is built from the outline, not from how finely the
 * scan happens to be meshed, so it has as many triangles as the plain block's and the
 * same volume. */
static void collinear_points_do_not_weigh_on_the_patch(void **state)
{
    (void)state;
    double xy[2 * 104];
    size_t n = 0;
    double corners[] = {-10, -10, 10, -10};
    for (int i = 0; i < 4; i++)
        xy[n++] = corners[i];
    for (int i = 0; i <= 100; i++) { /* (10, 10) to (-10, 10) */
        xy[n++] = 10 - 0.2 * i;
        xy[n++] = 10;
    }
    sr_mesh prism, fine, plain;
    sr_layer_grid gf, gp;
    assert_int_equal(sr_shape_prism(xy, n / 2, 0, 10, &prism, NULL), SR_OK);
    notch_and_slice(&prism, &fine, &gf);
    notched_block(&plain, &gp);
    sr_region_opts o = mirror_opts();
    sr_analysis af = {0}, ap = {0};
    sr_section *f = NULL, *p = NULL;
    size_t nf = 0, np = 0;
    run(&fine, &gf, &o, &af, &f, &nf);
    run(&plain, &gp, &o, &ap, &p, &np);
    assert_int_equal(nf, 1);
    assert_int_equal(np, 1);
    print_message("patch: %zu triangles (fine mesh), %zu (plain)\n", f[0].patch.tri_count,
                  p[0].patch.tri_count);
    assert_int_equal(f[0].patch.tri_count, p[0].patch.tri_count);
    assert_near(sr_mesh_volume(&f[0].patch), sr_mesh_volume(&p[0].patch), 1e-6);
    sr_sections_release(f, nf);
    sr_sections_release(p, np);
    sr_analysis_release(&af);
    sr_analysis_release(&ap);
    sr_mesh_release(&fine);
    sr_mesh_release(&plain);
    sr_layer_grid_release(&gf);
    sr_layer_grid_release(&gp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_box_holding_the_notch_finds_the_same_section),
        cmocka_unit_test(a_box_that_cuts_the_notch_drops_it),
        cmocka_unit_test(want_chooses_the_sections_that_get_a_patch),
        cmocka_unit_test(collinear_points_do_not_weigh_on_the_patch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
