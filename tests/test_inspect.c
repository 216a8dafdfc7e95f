/*
 * test_inspect.c: sr_inspect_run (src/inspect/): a 20 x 20 x 10 mm box restored from
 * two corner chips (4 x 4 x 4 mm patches, 64 mm3 each), inspected against after-repair
 * scans built from it with known answers: a section built up 0.5 mm (machine, 27.125
 * mm3 of stock), one 0.3 mm short over 2 x 4 mm (rework, 2.4 mm3 under-fill), one left
 * damaged (rework, 64 mm3), a noisy scan of a perfect repair (pass), the built-up scan
 * moved away (registered back, the same figures), a --no-union run's separate shells
 * measured as their union, and the refusals.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include <stdio.h>
#include <sys/stat.h>

#include "align/surface_query.h"
#include "bridge/boolean.h"
#include "bridge/mesh_io.h"
#include "inspect/inspect.h"
#include "mesh/shapes.h"
#include "reconstruct.h"
#include "run/run_build.h"
#include "support/assert_near.h"
#include "support/random_pose.h"
#include "support/test_select.h"

/* One face of a box as an n_u x n_v grid of squares of side h; axis `a` is the
 * normal, side 0 = lo, 1 = hi. Coordinates are lo + i * h, so faces share their edge
 * vertices bit for bit (welded afterwards). */
static void grid_face(sr_mesh *m, size_t *nv, size_t *nt, const double lo[3], const int n[3],
                      double h, int a, int side)
{
    int u = (a + 1) % 3, v = (a + 2) % 3; /* (u, v, a) right-handed */
    size_t base = *nv;
    for (int j = 0; j <= n[v]; j++)
        for (int i = 0; i <= n[u]; i++) {
            double *p = m->xyz + 3 * (*nv)++;
            p[a] = lo[a] + side * n[a] * h;
            p[u] = lo[u] + i * h;
            p[v] = lo[v] + j * h;
        }
    for (int j = 0; j < n[v]; j++)
        for (int i = 0; i < n[u]; i++) {
            uint32_t c00 = (uint32_t)(base + (size_t)j * (n[u] + 1) + i), c10 = c00 + 1,
                     c01 = c00 + (uint32_t)(n[u] + 1), c11 = c01 + 1;
            uint32_t q[6] = {c00, c10, c11, c00, c11, c01};
            if (!side) {
                q[1] = c11, q[2] = c10, q[4] = c01, q[5] = c11;
            }
            memcpy(m->tri + 3 * (*nt), q, sizeof q);
            *nt += 2;
        }
}

/* The box lo .. lo + n * h as a closed grid mesh; each vertex then moved by up to
 * `noise` mm along each axis (deterministic). */
static void grid_box(const double lo[3], const int n[3], double h, double noise, sr_mesh *m)
{
    size_t verts = 0, tris = 0;
    for (int a = 0; a < 3; a++) {
        int u = (a + 1) % 3, v = (a + 2) % 3;
        verts += 2 * (size_t)(n[u] + 1) * (size_t)(n[v] + 1);
        tris += 4 * (size_t)n[u] * (size_t)n[v];
    }
    sr_mesh_init(m);
    assert_int_equal(sr_mesh_alloc(m, verts, tris), SR_OK);
    size_t nv = 0, nt = 0;
    for (int a = 0; a < 3; a++)
        for (int side = 0; side < 2; side++)
            grid_face(m, &nv, &nt, lo, n, h, a, side);
    assert_int_equal(sr_mesh_weld_exact(m), SR_OK);
    assert_true(sr_mesh_is_closed(m));
    uint64_t s = 12345;
    for (size_t i = 0; noise > 0 && i < 3 * m->vertex_count; i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        m->xyz[i] += noise * (2.0 * (double)(s >> 11) / 9007199254740992.0 - 1);
    }
}

static void box(double x0, double y0, double z0, double x1, double y1, double z1, sr_mesh *m)
{
    const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

static const double LO[3] = {0, 0, 0};
static const int N[3] = {20, 20, 10};

/* The run: restored box, section 1 chip at the (20, 20, 10) corner, section 2 at
 * (0, 0, 10). */
static void make_run(sr_run *run)
{
    memset(run, 0, sizeof *run);
    run->id = 7;
    grid_box(LO, N, 1.0, 0, &run->restored);
    run->section_count = 2;
    run->sections = calloc(2, sizeof *run->sections);
    assert_non_null(run->sections);
    run->sections[0].index = 0;
    box(16, 16, 6, 20, 20, 10, &run->sections[0].patch);
    run->sections[1].index = 1;
    box(0, 0, 6, 4, 4, 10, &run->sections[1].patch);
}

/* As make_run, but the part a pentagonal prism (no symmetry a registration could
 * confuse) with the section 1 chip at its (20, 20, 10) corner only. */
static void make_asymmetric_run(sr_run *run)
{
    memset(run, 0, sizeof *run);
    run->id = 8;
    const double xy[] = {0, 0, 20, 0, 20, 20, 6, 20, 0, 8};
    assert_int_equal(sr_shape_prism(xy, 5, 0, 10, &run->restored, NULL), SR_OK);
    run->section_count = 1;
    run->sections = calloc(1, sizeof *run->sections);
    assert_non_null(run->sections);
    box(16, 16, 6, 20, 20, 10, &run->sections[0].patch);
}

static void op(sr_boolean_op o, const sr_mesh *a, const sr_mesh *b, sr_mesh *out)
{
    sr_err err = {{0}};
    sr_status st = sr_boolean_compute(o, a, "a", b, "b", out, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
}

static void inspect(const sr_run *run, const sr_mesh *scan, int mode, sr_inspect_result *r)
{
    sr_inspect_opts o = {.allowance_mm = 1.0, .tolerance_mm = 0.1, .register_mode = mode};
    sr_err err = {{0}};
    sr_status st = sr_inspect_run(run, scan, &o, r, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
}

/* The section chip built up 0.5 mm on every face: 4.5^3 - 4^3 = 27.125 mm3 of stock. */
static void built_up_scan(const sr_run *run, sr_mesh *scan)
{
    sr_mesh b;
    box(16, 16, 6, 20.5, 20.5, 10.5, &b);
    op(SR_BOOLEAN_UNION, &run->restored, &b, scan);
    sr_mesh_release(&b);
}

static void check_built_up(const sr_inspect_result *r)
{
    assert_int_equal(r->verdict, SR_INSPECT_MACHINE);
    const sr_inspect_section *s = &r->sections[0];
    assert_int_equal(s->verdict, SR_INSPECT_MACHINE);
    assert_true(r->volumes_exact);
    assert_near(s->overbuild_mm3, 27.125, 0.05 * 27.125);
    assert_near(s->underfill_mm3, 0, 0.05);
    assert_true(s->stock_min_mm > 0.1 && s->stock_min_mm <= 0.5 + 1e-9);
    assert_true(s->stock_max_mm > 0.5 && s->stock_max_mm <= sqrt(0.75) + 0.02);
    assert_true(strstr(s->reasons, "stock") != NULL);
    if (r->section_count > 1)
        assert_int_equal(r->sections[1].verdict, SR_INSPECT_PASS);
    assert_near(r->outside_overbuild_mm3, 0, 0.05);
}

static void a_section_built_up_half_a_millimetre_is_to_machine(void **state)
{
    (void)state;
    sr_run run;
    make_run(&run);
    sr_mesh scan;
    built_up_scan(&run, &scan);
    sr_inspect_result r;
    inspect(&run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    assert_int_equal(r.registered, 0);
    check_built_up(&r);
    assert_near(r.sections[0].stock_mean_mm, 0.5, 0.05);
    /* the colours: a signed distance per scan vertex, the far corner of the stock
     * sqrt(3) x 0.5 mm out */
    double top = -1;
    for (size_t v = 0; v < r.scan.vertex_count; v++)
        top = fmax(top, r.deviation[v]);
    assert_near(top, sqrt(0.75), 1e-9);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_run_release(&run);
}

static void a_region_0_3_mm_short_is_rework_with_its_volume_and_depth(void **state)
{
    (void)state;
    sr_run run;
    make_run(&run);
    sr_mesh c, scan;
    box(16, 16, 9.7, 18, 20.5, 10.5, &c);
    op(SR_BOOLEAN_DIFFERENCE, &run.restored, &c, &scan);
    sr_mesh_release(&c);
    sr_inspect_result r;
    inspect(&run, &scan, SR_INSPECT_REGISTER_NEVER, &r);
    assert_int_equal(r.verdict, SR_INSPECT_REWORK);
    const sr_inspect_section *s = &r.sections[0];
    assert_int_equal(s->verdict, SR_INSPECT_REWORK);
    assert_near(s->underfill_mm3, 2.4, 0.05 * 2.4);
    assert_near(s->underfill_depth_mm, 0.3, 0.01);
    assert_near(s->overbuild_mm3, 0, 1e-6);
    assert_true(strstr(s->reasons, "under-fill 2.4 mm3") != NULL);
    assert_int_equal(r.sections[1].verdict, SR_INSPECT_PASS);
    assert_true(strstr(r.reasons, "section 1: rework") != NULL);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_run_release(&run);
}

static void a_section_left_damaged_is_rework_with_the_whole_patch_missing(void **state)
{
    (void)state;
    sr_run run;
    make_run(&run);
    sr_mesh scan;
    op(SR_BOOLEAN_DIFFERENCE, &run.restored, &run.sections[1].patch, &scan);
    sr_inspect_result r;
    inspect(&run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    assert_int_equal(r.verdict, SR_INSPECT_REWORK);
    assert_int_equal(r.sections[0].verdict, SR_INSPECT_PASS);
    const sr_inspect_section *s = &r.sections[1];
    assert_int_equal(s->verdict, SR_INSPECT_REWORK);
    assert_near(s->patch_mm3, 64, 1e-9);
    assert_near(s->underfill_mm3, 64, 0.05 * 64);
    assert_near(s->underfill_depth_mm, 4, 1e-9);
    assert_true(strstr(r.reasons, "section 2: rework") != NULL);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_run_release(&run);
}

static void a_noisy_scan_of_a_perfect_repair_passes(void **state)
{
    (void)state;
    sr_run run;
    make_run(&run);
    sr_mesh scan;
    grid_box(LO, N, 1.0, 0.03, &scan);
    sr_inspect_result r;
    inspect(&run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    assert_int_equal(r.verdict, SR_INSPECT_PASS);
    for (size_t k = 0; k < 2; k++) {
        const sr_inspect_section *s = &r.sections[k];
        assert_int_equal(s->verdict, SR_INSPECT_PASS);
        assert_true(s->underfill_mm3 < 0.05 * 64);
        assert_true(s->underfill_depth_mm <= 0.03 * sqrt(3) + 1e-9);
        assert_true(s->samples > 100);
    }
    assert_true(r.outside_max_mm <= 0.03 * sqrt(3) + 1e-9);
    assert_near(r.outside_share, 0, 1e-12);
    assert_true(strstr(r.reasons, "within 0.1 mm") != NULL);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_run_release(&run);
}

static void a_scan_in_another_frame_is_registered_with_the_same_figures(void **state)
{
    (void)state;
    sr_run run;
    make_asymmetric_run(&run);
    sr_mesh scan;
    built_up_scan(&run, &scan);
    double m[12];
    test_random_pose(20, m);
    sr_mesh_transform(&scan, m);
    sr_inspect_result r;
    inspect(&run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    assert_int_equal(r.registered, 1);
    assert_true(r.coverage > 0.9);
    check_built_up(&r);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_run_release(&run);
}

/* A --no-union run: the restored mesh is the damaged box and the two chips as separate
 * shells, whose faces meet on the fracture surfaces. The box left damaged at section 2
 * lies on those hidden faces: still rework with the whole chip under-filled, 4 mm
 * deep; a perfect repair still passes with no stock. */
static void a_no_union_run_is_measured_against_the_union_of_its_shells(void **state)
{
    (void)state;
    sr_run run;
    make_run(&run);
    sr_mesh damaged, tmp;
    op(SR_BOOLEAN_DIFFERENCE, &run.restored, &run.sections[0].patch, &tmp);
    op(SR_BOOLEAN_DIFFERENCE, &tmp, &run.sections[1].patch, &damaged);
    sr_mesh_release(&tmp);
    sr_mesh perfect;
    assert_int_equal(sr_mesh_copy(&perfect, &run.restored), SR_OK);
    sr_mesh_release(&run.restored);
    assert_int_equal(sr_mesh_copy(&run.restored, &damaged), SR_OK);
    for (size_t k = 0; k < 2; k++)
        assert_int_equal(sr_mesh_append(&run.restored, &run.sections[k].patch), SR_OK);
    sr_mesh scan;
    op(SR_BOOLEAN_DIFFERENCE, &perfect, &run.sections[1].patch, &scan);
    sr_inspect_result r;
    inspect(&run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    assert_int_equal(r.verdict, SR_INSPECT_REWORK);
    assert_true(strstr(r.model_note, "3 separate solids") != NULL);
    assert_true(r.volumes_exact);
    assert_int_equal(r.sections[0].verdict, SR_INSPECT_PASS);
    const sr_inspect_section *s = &r.sections[1];
    assert_int_equal(s->verdict, SR_INSPECT_REWORK);
    assert_near(s->underfill_mm3, 64, 0.05 * 64);
    assert_near(s->underfill_depth_mm, 4, 1e-9);
    assert_near(s->overbuild_mm3, 0, 1e-6);
    /* the report's colours: the same deviations, the deepest 4 mm */
    double *dev = calloc(scan.vertex_count, sizeof *dev), lo = 0;
    assert_non_null(dev);
    sr_err err = {{0}};
    assert_int_equal(sr_inspect_deviations(&run.restored, &scan, dev, &err), SR_OK);
    for (size_t v = 0; v < scan.vertex_count; v++)
        lo = fmin(lo, dev[v]);
    assert_near(lo, -4, 1e-9);
    free(dev);
    sr_inspect_release(&r);
    inspect(&run, &perfect, SR_INSPECT_REGISTER_AUTO, &r);
    assert_int_equal(r.verdict, SR_INSPECT_PASS);
    assert_near(r.sections[1].underfill_mm3, 0, 1e-6);
    assert_near(r.sections[1].overbuild_mm3, 0, 1e-6);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_mesh_release(&perfect);
    sr_mesh_release(&damaged);
    sr_run_release(&run);
}

/* ---- the shared gouged bushing (../shared/parts/bushing_gouged) ----
 * One reconstruction of its damaged mesh (about a second), kept for the cases below;
 * the after-repair scans are built from the run's restored model and section patch by
 * construction: the patch's outer surface S (its triangles on the restored surface)
 * extruded along its vertex normals, united (built up 0.5 mm) or cut off (0.3 mm
 * short over the part of S below its middle height); the expected volumes are those
 * of the meshes constructed (vol(scan) - vol(restored) and back), not the inspection's.
 * Skipped with a message when the folder is absent. */
#define BUSHING "../shared/parts/bushing_gouged"

static struct {
    int tried, ok;
    sr_run run;
    sr_mesh damaged;
} bushing;

static const sr_run *bushing_run(void)
{
    if (!bushing.tried) {
        bushing.tried = 1;
        struct stat sb;
        if (stat(BUSHING "/damaged.stl", &sb) != 0)
            return NULL;
        sr_err err = {{0}};
        sr_mesh_init(&bushing.damaged);
        assert_int_equal(sr_mesh_read(BUSHING "/damaged.stl", &bushing.damaged, &err), SR_OK);
        sr_recon_opts o;
        memset(&o, 0, sizeof o);
        o.symmetry = (sr_symmetry){SR_SYM_AXIAL, 0, 0};
        o.min_depth_mm = 0.1;
        o.threads = 1;
        sr_recon_result res;
        if (sr_reconstruct(&bushing.damaged, &o, &res, &err) != SR_OK)
            fail_msg("reconstruct: %s", err.msg);
        assert_int_equal(res.section_count, 1);
        assert_true(res.restored_by_union);
        sr_params p = {"test", 320, 240, 0.95, 0.95, 0.05, 0.1, 1.0, ""};
        assert_int_equal(sr_run_from_result(&res, 1, &o.symmetry, &p, "image", &bushing.run, &err),
                         SR_OK);
        sr_recon_result_release(&res);
        bushing.ok = 1;
    }
    if (!bushing.ok)
        print_message("skipped: %s is absent\n", BUSHING);
    return bushing.ok ? &bushing.run : NULL;
}

static int bushing_release(void **state)
{
    (void)state;
    sr_run_release(&bushing.run);
    sr_mesh_release(&bushing.damaged);
    return 0;
}

/* The section patch scaled about the run's axis (aligned frame: the z axis) so that
 * its outer surface, at the part's radius R, moves by dr mm: radially by (R + dr) / R,
 * z unchanged. A linear map: the copy crosses itself no more than the patch does, and
 * it keeps the patch's footprint (azimuth and height). */
static void patch_scaled(const sr_run *run, double dr, sr_mesh *out)
{
    const sr_mesh *patch = &run->sections[0].patch;
    double inv[12], s[12] = {0}, m[12];
    sr_xform_rigid_inverse(inv, run->alignment);
    double r_max = 0;
    for (size_t v = 0; v < patch->vertex_count; v++) {
        double q[3];
        sr_xform_apply(run->alignment, patch->xyz + 3 * v, q);
        r_max = fmax(r_max, hypot(q[0], q[1]));
    }
    double f = (r_max + dr) / r_max;
    s[0] = f;
    s[5] = f;
    s[10] = 1;
    sr_xform_mul(m, s, run->alignment);
    double full[12];
    sr_xform_mul(full, inv, m);
    assert_int_equal(sr_mesh_copy(out, patch), SR_OK);
    sr_mesh_transform(out, full);
}

/* Gaussian noise of sigma mm on every coordinate (deterministic). */
static void add_noise(sr_mesh *m, double sigma, uint64_t seed)
{
    for (size_t i = 0; i < 3 * m->vertex_count; i += 2) {
        double u[2];
        for (int k = 0; k < 2; k++) {
            seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
            u[k] = ((double)(seed >> 11) + 0.5) / 9007199254740992.0;
        }
        double r = sigma * sqrt(-2 * log(u[0]));
        m->xyz[i] += r * cos(2 * M_PI * u[1]);
        if (i + 1 < 3 * m->vertex_count)
            m->xyz[i + 1] += r * sin(2 * M_PI * u[1]);
    }
}

static void a_shared_part_built_up_half_a_millimetre_is_to_machine(void **state)
{
    (void)state;
    const sr_run *run = bushing_run();
    if (!run)
        skip();
    sr_mesh b, scan;
    patch_scaled(run, 0.5, &b);
    op(SR_BOOLEAN_UNION, &run->restored, &b, &scan);
    double built = sr_mesh_volume(&scan) - sr_mesh_volume(&run->restored);
    print_message("built up: %.3f mm3 constructed\n", built);
    sr_inspect_result r;
    inspect(run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    const sr_inspect_section *s = &r.sections[0];
    print_message("  inspected: %s, over-build %.3f mm3, stock %.3f..%.3f mm, outside %.4f\n",
                  sr_inspect_verdict_str(r.verdict), s->overbuild_mm3, s->stock_min_mm,
                  s->stock_max_mm, r.outside_share);
    assert_int_equal(r.verdict, SR_INSPECT_MACHINE);
    assert_int_equal(s->verdict, SR_INSPECT_MACHINE);
    assert_true(r.volumes_exact);
    assert_near(s->overbuild_mm3, built, 0.05 * built);
    assert_near(s->underfill_mm3, 0, 0.01 * s->patch_mm3);
    assert_near(s->stock_mean_mm, 0.5, 0.05);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_mesh_release(&b);
}

static void a_shared_part_0_3_mm_short_is_rework_with_its_volume_and_depth(void **state)
{
    (void)state;
    const sr_run *run = bushing_run();
    if (!run)
        skip();
    /* the layer 0.3 mm under the restored surface over the section, below the middle of
     * its height: (patch moved out 1 mm \ patch moved in 0.3 mm) n a box */
    double lo[3], hi[3];
    sr_mesh_bbox(&run->sections[0].patch, lo, hi);
    sr_mesh big, small, layer, half, c, scan;
    patch_scaled(run, 1.0, &big);
    patch_scaled(run, -0.3, &small);
    op(SR_BOOLEAN_DIFFERENCE, &big, &small, &layer);
    box(lo[0] - 5, lo[1] - 5, lo[2] - 5, hi[0] + 5, hi[1] + 5, (lo[2] + hi[2]) / 2, &half);
    op(SR_BOOLEAN_INTERSECTION, &layer, &half, &c);
    op(SR_BOOLEAN_DIFFERENCE, &run->restored, &c, &scan);
    sr_mesh_release(&big);
    sr_mesh_release(&small);
    sr_mesh_release(&layer);
    sr_mesh_release(&half);
    double short_mm3 = sr_mesh_volume(&run->restored) - sr_mesh_volume(&scan);
    print_message("0.3 mm short: %.3f mm3 constructed\n", short_mm3);
    sr_inspect_result r;
    inspect(run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    const sr_inspect_section *s = &r.sections[0];
    print_message("  inspected: %s, under-fill %.3f mm3, %.4f mm deep%s%s\n",
                  sr_inspect_verdict_str(r.verdict), s->underfill_mm3, s->underfill_depth_mm,
                  r.volumes_exact ? "" : "; estimated: ", r.volume_note);
    assert_int_equal(r.verdict, SR_INSPECT_REWORK);
    assert_int_equal(s->verdict, SR_INSPECT_REWORK);
    /* (exact from patch \ scan even when the scan a boolean made crosses itself for the
     * over-build's) */
    assert_near(s->underfill_mm3, short_mm3, 0.05 * short_mm3);
    assert_near(s->underfill_depth_mm, 0.3, 0.02);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_mesh_release(&c);
}

/* The damaged mesh's farthest vertex below the run's restored surface, mm. */
static double deepest_vertex(const sr_run *run)
{
    sr_surface_query *q = NULL;
    assert_int_equal(sr_surface_query_build(&run->restored, &q, NULL), SR_OK);
    double deepest = 0;
    for (size_t v = 0; v < bushing.damaged.vertex_count; v++) {
        double d, sd;
        if (sr_surface_query_closest(q, bushing.damaged.xyz + 3 * v, INFINITY, NULL, &d, &sd))
            deepest = fmax(deepest, -sd);
    }
    sr_surface_query_free(q);
    return deepest;
}

static void a_shared_part_left_damaged_is_rework_with_the_whole_section(void **state)
{
    (void)state;
    const sr_run *run = bushing_run();
    if (!run)
        skip();
    double missing = sr_mesh_volume(&run->restored) - sr_mesh_volume(&bushing.damaged);
    sr_inspect_result r;
    inspect(run, &bushing.damaged, SR_INSPECT_REGISTER_AUTO, &r);
    const sr_inspect_section *s = &r.sections[0];
    double depth = s->underfill_depth_mm;
    print_message("left damaged: %.3f mm3 missing; inspected %s, under-fill %.3f mm3, %.3f mm "
                  "deep\n",
                  missing, sr_inspect_verdict_str(r.verdict), s->underfill_mm3, depth);
    assert_int_equal(r.verdict, SR_INSPECT_REWORK);
    assert_int_equal(s->verdict, SR_INSPECT_REWORK);
    assert_true(r.volumes_exact);
    assert_near(s->underfill_mm3, missing, 0.05 * missing);
    double deepest = deepest_vertex(run);
    /* (samples between the vertices can lie a little deeper) */
    assert_true(depth >= deepest - 1e-9 && depth <= deepest + 0.01);
    sr_inspect_release(&r);
}

/* The damaged scan with noise (sigma 0.03 mm) in a random pose: registered, the
 * rotation about the axis (free on an axially symmetric part) not allowed to move the
 * damage off the section. */
static void a_noisy_posed_scan_of_an_axial_part_left_damaged_is_rework(void **state)
{
    (void)state;
    const sr_run *run = bushing_run();
    if (!run)
        skip();
    double missing = sr_mesh_volume(&run->restored) - sr_mesh_volume(&bushing.damaged);
    double deepest = deepest_vertex(run);
    sr_inspect_result r;
    const sr_inspect_section *s;
    const double sigma = 0.03;
    sr_mesh scan;
    assert_int_equal(sr_mesh_copy(&scan, &bushing.damaged), SR_OK);
    add_noise(&scan, sigma, 7);
    double m[12];
    test_random_pose(11, m);
    sr_mesh_transform(&scan, m);
    inspect(run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    s = &r.sections[0];
    /* taken back where it was: the registration after the pose within 0.5 degree and
     * 0.05 mm of the identity (landed turned end for end without the roll's search) */
    double e[12];
    sr_xform_mul(e, r.transform, m);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            assert_near(e[4 * i + j], i == j, 0.5 * M_PI / 180);
        assert_near(e[4 * i + 3], 0, 0.05);
    }
    print_message("  noisy, posed: %s, registered %d, under-fill %.3f mm3, %.3f mm deep, "
                  "outside %.4f\n",
                  sr_inspect_verdict_str(r.verdict), r.registered, s->underfill_mm3,
                  s->underfill_depth_mm, r.outside_share);
    assert_int_equal(r.registered, 1);
    assert_int_equal(r.verdict, SR_INSPECT_REWORK);
    assert_int_equal(s->verdict, SR_INSPECT_REWORK);
    assert_near(s->underfill_mm3, missing, 0.05 * missing);
    assert_near(s->underfill_depth_mm, deepest, 4 * sigma);
    assert_true(r.outside_share < 0.01);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
}

static void a_noisy_scan_of_a_shared_part_perfectly_repaired_passes(void **state)
{
    (void)state;
    const sr_run *run = bushing_run();
    if (!run)
        skip();
    const double sigma = 0.03;
    sr_mesh scan;
    assert_int_equal(sr_mesh_copy(&scan, &run->restored), SR_OK);
    add_noise(&scan, sigma, 3);
    sr_inspect_result r;
    inspect(run, &scan, SR_INSPECT_REGISTER_AUTO, &r);
    const sr_inspect_section *s = &r.sections[0];
    print_message("noisy perfect repair: %s, under-fill %.3f mm3, %.3f mm deep, outside %.4f\n",
                  sr_inspect_verdict_str(r.verdict), s->underfill_mm3, s->underfill_depth_mm,
                  r.outside_share);
    assert_int_equal(r.verdict, SR_INSPECT_PASS);
    assert_int_equal(s->verdict, SR_INSPECT_PASS);
    assert_true(s->underfill_mm3 < 0.05 * s->patch_mm3);
    assert_true(s->underfill_depth_mm < 5 * sigma);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
}

static void refusals_name_what_is_wrong(void **state)
{
    (void)state;
    sr_run run;
    make_run(&run);
    sr_inspect_result r;
    sr_err err = {{0}};
    sr_inspect_opts o = {.tolerance_mm = -1};
    assert_int_equal(sr_inspect_run(&run, &run.restored, &o, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "tolerance must be >= 0 mm, got -1");
    o = (sr_inspect_opts){.allowance_mm = NAN};
    assert_int_equal(sr_inspect_run(&run, &run.restored, &o, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "allowance");
    sr_mesh_release(&run.sections[1].patch);
    assert_int_equal(sr_inspect_run(&run, &run.restored, NULL, &r, &err), SR_E_INVALID);
    assert_msg_has(err, "run 7 keeps no patch of section 2");
    sr_mesh_release(&run.restored);
    assert_int_equal(sr_inspect_run(&run, &run.restored, NULL, &r, &err), SR_E_INVALID);
    assert_msg_has(err, "run 7 has no restored mesh");
    sr_run_release(&run);
}

static void verdict_names_round_trip(void **state)
{
    (void)state;
    for (int v = SR_INSPECT_PASS; v <= SR_INSPECT_REWORK; v++)
        assert_int_equal(sr_inspect_verdict_parse(sr_inspect_verdict_str((sr_inspect_verdict)v)),
                         v);
    assert_int_equal(sr_inspect_verdict_parse("fail"), -1);
    assert_int_equal(sr_inspect_verdict_parse(NULL), -1);
}

/* The deviation colour scale (the report's and the GLB's): range max(2 x 0.5, 5 x 0.1)
 * = 1 mm; the stops' colours at the stops, green across the band, halfway between
 * yellow and red at 0.55 mm, the end colours beyond the range. */
static void deviation_colours_follow_the_scale(void **state)
{
    (void)state;
    assert_near(sr_inspect_scale_range(0.1, 0.5), 1.0, 1e-15);
    assert_near(sr_inspect_scale_range(0.1, 0), 0.5, 1e-15);
    float c[3];
    const struct {
        double d;
        double rgb[3];
    } want[] = {
        {-5, {0x1c, 0x3f, 0x9e}}, {-1, {0x1c, 0x3f, 0x9e}},  {-0.1, {0x8f, 0xc1, 0xf0}},
        {0, {0x36, 0xa8, 0x52}},  {0.1, {0x36, 0xa8, 0x52}}, {0.55, {223.5, 123.5, 64.5}},
        {1, {0xc0, 0x26, 0x1b}},  {9, {0xc0, 0x26, 0x1b}},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        sr_inspect_colour(0.1, 0.5, want[i].d, c);
        for (int k = 0; k < 3; k++)
            assert_near(c[k], want[i].rgb[k] / 255.0, 1e-6);
    }
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(a_section_built_up_half_a_millimetre_is_to_machine),
        cmocka_unit_test(a_region_0_3_mm_short_is_rework_with_its_volume_and_depth),
        cmocka_unit_test(a_section_left_damaged_is_rework_with_the_whole_patch_missing),
        cmocka_unit_test(a_noisy_scan_of_a_perfect_repair_passes),
        cmocka_unit_test(a_scan_in_another_frame_is_registered_with_the_same_figures),
        cmocka_unit_test(a_no_union_run_is_measured_against_the_union_of_its_shells),
        cmocka_unit_test(a_shared_part_built_up_half_a_millimetre_is_to_machine),
        cmocka_unit_test(a_shared_part_0_3_mm_short_is_rework_with_its_volume_and_depth),
        cmocka_unit_test(a_shared_part_left_damaged_is_rework_with_the_whole_section),
        cmocka_unit_test(a_noisy_posed_scan_of_an_axial_part_left_damaged_is_rework),
        cmocka_unit_test(a_noisy_scan_of_a_shared_part_perfectly_repaired_passes),
        cmocka_unit_test(refusals_name_what_is_wrong),
        cmocka_unit_test(verdict_names_round_trip),
        cmocka_unit_test(deviation_colours_follow_the_scale),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("test_inspect", tests, n, NULL, bushing_release);
}
