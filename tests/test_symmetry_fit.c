/*
 * test_symmetry_fit.c: the kind of symmetry proposed for a scan (symmetry_fit.h,
 * `--symmetry auto`).
 *
 * Geometry with a known answer, built here and moved by a random rigid pose, each
 * whole and with a chunk missing: a grooved cylinder is axial and continuous (not
 * mirror, though every plane through its axis is a mirror plane); a 12-toothed
 * wheel is axial of order 12 (not 6 or 24, not mirror); an angle bracket symmetric
 * about its middle is mirror; a bar with bumps alternating sides every 10 mm is a
 * glide with shift 10 (not mirror), and so is a toothed bar that is also a mirror
 * across its length, whole or gouged in the middle. The figures are checked to say so
 * (the proposal's consistency high, a wrong kind's low), a second run gives the same
 * answer, and an empty mesh is refused and leaves *out alone.
 *
 * Then two shared parts in their pose (../shared/parts/<part>/damaged_posed.stl,
 * skipped when absent) against the truth: the gear's order 20 and the rail's glide by
 * 10 (or an odd multiple). All nine, posed and noisy, are in `make bench`
 * (tests/bench/symmetry_bench.sh; a fit of a shared part takes a few seconds, too long
 * for `make check` nine times over); there the flange's truth, axial with no order,
 * also passes as 6-fold, which its six bolt holes make it.
 *
 * SYMREC_TEST_FILTER=<glob> runs only the matching cases (e.g. "symfit_part_*").
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "align/symmetry_fit.h"
#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/random_pose.h"
#include "support/truth.h"

#define PARTS_DIR "../shared/parts"

/* Removes the triangles whose centroid lies within `radius` of c: a chunk missing (the
 * fit needs no closed surface). */
static void cut_chunk(sr_mesh *m, const double c[3], double radius)
{
    size_t kept = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        double g[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                g[j] += m->xyz[3 * m->tri[3 * t + k] + j] / 3;
        double d2 = 0;
        for (int j = 0; j < 3; j++)
            d2 += (g[j] - c[j]) * (g[j] - c[j]);
        if (d2 > radius * radius) {
            memmove(m->tri + 3 * kept, m->tri + 3 * t, 3 * sizeof *m->tri);
            kept++;
        }
    }
    assert_true(kept < m->tri_count);
    m->tri_count = kept;
}

static void append_box(sr_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    sr_mesh b;
    assert_int_equal(sr_shape_box(lo, hi, &b, NULL), SR_OK);
    assert_int_equal(sr_mesh_append(m, &b), SR_OK);
    sr_mesh_release(&b);
}

/* Cylinder r 20, z 0..60, with a groove (r 17) at z 25..30; rings every 2.5 mm so a
 * chunk removes a patch, not a whole face. */
typedef struct rings {
    double z[32], r[32];
} rings;

static double radius_of_ring(double theta, size_t ring, void *user)
{
    (void)theta;
    return ((const rings *)user)->r[ring];
}

static void make_grooved(sr_mesh *m)
{
    rings g;
    size_t n = 0;
    for (int i = 0; i <= 24; i++) {
        double z = 2.5 * i;
        int in = z > 25.1 && z < 29.9;
        if (i == 10 || i == 12) { /* the groove's walls: two rings at one height */
            g.z[n] = z;
            g.r[n++] = i == 10 ? 20 : 17;
            g.z[n] = z;
            g.r[n++] = i == 10 ? 17 : 20;
        } else {
            g.z[n] = z;
            g.r[n++] = in ? 17 : 20;
        }
    }
    sr_revolve_opts o = {0};
    o.segments = 96;
    o.ring_count = n;
    o.ring_z = g.z;
    o.outer = radius_of_ring;
    o.user = &g;
    assert_int_equal(sr_shape_revolve(&o, m, NULL), SR_OK);
}

/* A 12-toothed wheel: tip radius 30, root 25, each tooth a trapezoid, z 0..15. */
static void make_wheel(sr_mesh *m)
{
    double xy[2 * 48];
    for (int k = 0; k < 12; k++)
        for (int j = 0; j < 4; j++) {
            static const double frac[4] = {0, 0.2, 0.45, 0.65}, rad[4] = {25, 30, 30, 25};
            double t = 2 * M_PI * (k + frac[j]) / 12;
            xy[2 * (4 * k + j)] = rad[j] * cos(t);
            xy[2 * (4 * k + j) + 1] = rad[j] * sin(t);
        }
    assert_int_equal(sr_shape_prism(xy, 48, 0, 15, m, NULL), SR_OK);
}

/* Angle bracket symmetric about x = 0: base 60 x 40 x 8, upright 60 x 8 x 40 at y 0..8,
 * ears 12 x 20 x 8 beyond x = +-30 (overlapping the base by 2 mm, so no two faces
 * coincide); `broken`: the +x ear broken off 4 mm out. Whole boxes: a chunk is made by
 * the geometry, not by removing (large) triangles. */
static void make_bracket_ears(sr_mesh *m, int broken)
{
    memset(m, 0, sizeof *m);
    append_box(m, -30, 0, 0, 30, 40, 8);
    append_box(m, -30, 0, 0, 30, 8, 40);
    append_box(m, -42, 10, 0, -28, 30, 8);
    append_box(m, 28, 10, 0, broken ? 34 : 42, 30, 8);
}

static void make_bracket(sr_mesh *m)
{
    make_bracket_ears(m, 0);
}

static void make_bracket_broken(sr_mesh *m)
{
    make_bracket_ears(m, 1);
}

/* Bar along z 0..200 with a foot on -y, bumps 6 mm on +x at z 20k+2..20k+10 and on -x
 * at z 20k+12..20k+20: a glide by 10 mm, no mirror. */
static void make_glide_bar(sr_mesh *m)
{
    memset(m, 0, sizeof *m);
    for (int k = 0; k < 20; k++) {
        append_box(m, -5, -3, 10.0 * k, 5, 3, 10.0 * k + 10);
        append_box(m, -10, -6, 10.0 * k, 10, -3, 10.0 * k + 10);
    }
    for (int k = 0; k < 10; k++) {
        append_box(m, 5, -3, 20.0 * k + 2, 11, 3, 20.0 * k + 10);
        append_box(m, -11, -3, 20.0 * k + 12, -5, 3, 20.0 * k + 20);
    }
}

/* A toothed bar whose teeth alternate sides: the outline in the x-z plane of a core
 * |x| <= 5, z 0..192, with ten teeth on +x (x to 11, z 20k+2..20k+10) and nine on -x
 * (z 20k+12..20k+20), extruded through y -3..3, and a foot (a separate box) under it:
 * a glide by 10 along z and, ends and all, a mirror across z = 96. `gouged`: the +x
 * side cut back to x = 2 over z 80..112 (two teeth and the core under them), damage
 * that the mirror across z = 96 maps onto itself. */
static void make_crossed_bar(sr_mesh *m, int gouged)
{
    double xz[2 * 96];
    size_t n = 0;
#define AT(x, z) (xz[2 * n] = (x), xz[2 * n + 1] = (z), n++)
    AT(-5, 0);
    AT(5, 0);
    for (int k = 0; k < 10; k++) {
        double z0 = 20.0 * k + 2, z1 = z0 + 8;
        if (gouged && k == 4) {
            AT(5, 80);
            AT(2, 80);
            AT(2, 112);
            AT(5, 112);
        }
        if (gouged && (k == 4 || k == 5))
            continue;
        AT(5, z0);
        AT(11, z0);
        AT(11, z1);
        AT(5, z1);
    }
    AT(5, 192);
    AT(-5, 192);
    for (int k = 8; k >= 0; k--) {
        double z1 = 20.0 * k + 20, z0 = z1 - 8;
        AT(-5, z1);
        AT(-11, z1);
        AT(-11, z0);
        AT(-5, z0);
    }
#undef AT
    sr_mesh bar, foot;
    assert_int_equal(sr_shape_prism(xz, n, -3, 3, &bar, NULL), SR_OK);
    for (size_t v = 0; v < bar.vertex_count; v++) { /* (x, z, y) -> (x, -y, z): a turn */
        double *p = bar.xyz + 3 * v, y = p[1];
        p[1] = -p[2];
        p[2] = y;
    }
    const double lo[3] = {-10, -6, 0}, hi[3] = {10, -3.5, 192};
    assert_int_equal(sr_shape_box(lo, hi, &foot, NULL), SR_OK);
    assert_int_equal(sr_mesh_append(&bar, &foot), SR_OK);
    sr_mesh_release(&foot);
    *m = bar;
}

static void make_crossed_bar_whole(sr_mesh *m)
{
    make_crossed_bar(m, 0);
}

static void make_crossed_bar_gouged(sr_mesh *m)
{
    make_crossed_bar(m, 1);
}

typedef void (*make_fn)(sr_mesh *m);

/* Fits `make`'s part moved by pose `seed` (chunk: a ball of radius r at c in the part's
 * own frame removed first) and returns the fit. */
static sr_symmetry_fit fit_posed(make_fn make, unsigned seed, const double *c, double r)
{
    sr_mesh m;
    make(&m);
    if (c)
        cut_chunk(&m, c, r);
    double pose[12];
    test_random_pose(seed, pose);
    sr_mesh_transform(&m, pose);
    sr_symmetry_fit f;
    sr_err err = {{0}};
    sr_status st = sr_symmetry_propose(&m, &f, &err);
    if (st != SR_OK) {
        print_error("%s\n", err.msg);
        fail();
    }
    sr_mesh_release(&m);
    print_message("  %s %d %.2f mm conf %.2f%s | axial %.3f, n-fold(%d) %.3f, mirror %.3f, "
                  "glide %.3f (%.2f mm)\n",
                  sr_sym_kind_name(f.proposal.kind), f.proposal.order, f.proposal.shift_mm,
                  f.confidence, f.ambiguous ? " ambiguous" : "", f.fig[SR_SYMFIT_ROUND].consistency,
                  f.order, f.fig[SR_SYMFIT_NFOLD].consistency, f.fig[SR_SYMFIT_MIRROR].consistency,
                  f.fig[SR_SYMFIT_GLIDE].consistency, f.glide_shift_mm);
    assert_true(f.confidence >= 0 && f.confidence <= 1);
    assert_true(f.tol_mm > 0 && f.samples == 3000);
    return f;
}

static void grooved_cylinder_is_continuous_axial(void **state)
{
    (void)state;
    const double chunk[3] = {20, 0, 45};
    for (int cut = 0; cut < 2; cut++) {
        sr_symmetry_fit f = fit_posed(make_grooved, 11 + cut, cut ? chunk : NULL, 8);
        assert_int_equal(f.proposal.kind, SR_SYM_AXIAL);
        assert_int_equal(f.proposal.order, 0);
        assert_false(f.ambiguous);
        assert_true(f.fig[SR_SYMFIT_ROUND].consistency > 0.9);
        assert_true(f.confidence > 0.5);
    }
}

static void toothed_wheel_is_axial_of_order_12(void **state)
{
    (void)state;
    const double chunk[3] = {30, 0, 15};
    for (int cut = 0; cut < 2; cut++) {
        sr_symmetry_fit f = fit_posed(make_wheel, 21 + cut, cut ? chunk : NULL, 7);
        assert_int_equal(f.proposal.kind, SR_SYM_AXIAL);
        assert_int_equal(f.proposal.order, 12);
        assert_true(f.fig[SR_SYMFIT_NFOLD].consistency > 0.9);
        /* turned by an angle no order repeats, the teeth miss */
        assert_true(f.fig[SR_SYMFIT_ROUND].consistency < 0.8);
    }
}

static void angle_bracket_is_mirror(void **state)
{
    (void)state;
    for (int cut = 0; cut < 2; cut++) {
        sr_symmetry_fit f = fit_posed(cut ? make_bracket_broken : make_bracket, 31 + cut, NULL, 0);
        assert_int_equal(f.proposal.kind, SR_SYM_MIRROR);
        assert_false(f.ambiguous);
        assert_true(f.fig[SR_SYMFIT_MIRROR].consistency > 0.9);
        assert_true(f.fig[SR_SYMFIT_ROUND].consistency < 0.5);
    }
}

static void bumped_bar_is_a_glide_by_10(void **state)
{
    (void)state;
    const double chunk[3] = {8, 0, 106}; /* the +x bump at z 102..110 */
    for (int cut = 0; cut < 2; cut++) {
        sr_symmetry_fit f = fit_posed(make_glide_bar, 41 + cut, cut ? chunk : NULL, 6);
        assert_int_equal(f.proposal.kind, SR_SYM_GLIDE);
        assert_false(f.ambiguous);
        /* 10 or an odd multiple (a glide by s is one by 3s, 5s ...) */
        double k = f.proposal.shift_mm / 10;
        assert_true(fabs(k - round(k)) < 0.01 && (long)round(k) % 2 == 1);
        assert_true(f.fig[SR_SYMFIT_GLIDE].consistency > f.fig[SR_SYMFIT_MIRROR].consistency);
    }
}

/* The toothed bar of make_crossed_bar, whole and gouged: a mirror across its length
 * (z = 96) fits it as well as the glide does, the gouged one better (the gouge maps
 * onto itself across that plane). The glide is proposed all the same: it beats the
 * mirror in its own plane, and a mirror across the length is a pattern's, no evidence
 * against the glide. */
static void gouged_glide_bar_is_a_glide(void **state)
{
    (void)state;
    for (int cut = 0; cut < 2; cut++) {
        sr_symmetry_fit f =
            fit_posed(cut ? make_crossed_bar_gouged : make_crossed_bar_whole, 51 + cut, NULL, 0);
        assert_int_equal(f.proposal.kind, SR_SYM_GLIDE);
        assert_false(f.ambiguous);
        double k = f.proposal.shift_mm / 10;
        assert_true(fabs(k - round(k)) < 0.01 && (long)round(k) % 2 == 1);
        assert_true(f.confidence > 0.3);
    }
}

static void the_fit_is_deterministic(void **state)
{
    (void)state;
    sr_symmetry_fit a = fit_posed(make_wheel, 5, NULL, 0);
    sr_symmetry_fit b = fit_posed(make_wheel, 5, NULL, 0);
    assert_int_equal(a.proposal.order, b.proposal.order);
    for (int c = 0; c < SR_SYMFIT_COUNT; c++)
        assert_true(a.fig[c].consistency == b.fig[c].consistency);
    assert_true(a.confidence == b.confidence);
}

static void an_empty_mesh_is_refused(void **state)
{
    (void)state;
    sr_mesh m = {0};
    sr_symmetry_fit f;
    memset(&f, 0x5a, sizeof f);
    sr_err err = {{0}};
    assert_int_equal(sr_symmetry_propose(&m, &f, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "mesh"));
    unsigned char *p = (unsigned char *)&f;
    for (size_t i = 0; i < sizeof f; i++)
        assert_int_equal(p[i], 0x5a);
}

/* ---------------------------------------------------------- shared parts ---- */

static void run_part(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, PARTS_DIR "/%s/truth.json", name);
    if (access(path, R_OK) != 0)
        skip();
    sr_truth truth;
    sr_err err = {{0}};
    assert_int_equal(sr_truth_read(path, &truth, &err), SR_OK);
    snprintf(path, sizeof path, PARTS_DIR "/%s/damaged_posed.stl", name);
    sr_mesh m;
    sr_mesh_init(&m);
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    sr_symmetry_fit f;
    assert_int_equal(sr_symmetry_propose(&m, &f, &err), SR_OK);
    sr_mesh_release(&m);
    print_message("  %s: %s order %d shift %.2f conf %.2f (%.2f s)\n", name,
                  sr_sym_kind_name(f.proposal.kind), f.proposal.order, f.proposal.shift_mm,
                  f.confidence, f.seconds);
    assert_int_equal(f.proposal.kind, truth.symmetry.kind);
    assert_false(f.ambiguous);
    if (truth.symmetry.kind == SR_SYM_AXIAL && truth.symmetry.order > 0)
        assert_int_equal(f.proposal.order, truth.symmetry.order);
    else if (truth.symmetry.kind == SR_SYM_AXIAL && strcmp(name, "flange_broken_rim") == 0)
        assert_true(f.proposal.order == 0 || f.proposal.order == 6);
    else if (truth.symmetry.kind == SR_SYM_AXIAL)
        assert_int_equal(f.proposal.order, 0);
    if (truth.symmetry.kind == SR_SYM_GLIDE) {
        double k = f.proposal.shift_mm / truth.symmetry.shift_mm;
        assert_true(fabs(k - round(k)) < 0.02 && (long)round(k) % 2 == 1);
    }
}

#define PART_TEST(fn, name)                                                                        \
    static void fn(void **state)                                                                   \
    {                                                                                              \
        (void)state;                                                                               \
        run_part(name);                                                                            \
    }
PART_TEST(symfit_part_spur_gear_broken_tooth, "spur_gear_broken_tooth")
PART_TEST(symfit_part_rail_glide_chipped, "rail_glide_chipped")

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(grooved_cylinder_is_continuous_axial),
        cmocka_unit_test(toothed_wheel_is_axial_of_order_12),
        cmocka_unit_test(angle_bracket_is_mirror),
        cmocka_unit_test(bumped_bar_is_a_glide_by_10),
        cmocka_unit_test(gouged_glide_bar_is_a_glide),
        cmocka_unit_test(the_fit_is_deterministic),
        cmocka_unit_test(an_empty_mesh_is_refused),
        cmocka_unit_test(symfit_part_spur_gear_broken_tooth),
        cmocka_unit_test(symfit_part_rail_glide_chipped),
    };
    /* SYMREC_TEST_FILTER=pattern runs only the matching cases (cmocka glob) */
    const char *filter = getenv("SYMREC_TEST_FILTER");
    if (filter && *filter)
        cmocka_set_test_filter(filter);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
