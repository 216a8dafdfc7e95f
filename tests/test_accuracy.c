/*
 * test_accuracy.c: the whole pipeline (sr_reconstruct) on the nine damaged parts in
 * ../shared/parts (see its README), judged against each part's truth.json. Run from the
 * repository root; every part case is skipped when ../shared/parts is absent.
 *
 * Each part's damaged_posed.stl is reconstructed at 120 sectors x 160 layers (a Table 2
 * setting of the paper, chosen to keep the suite fast under ASan), given only the
 * symmetry kind (+ the order for the gear; the glide shift is searched), and:
 *  - the status must be OK;
 *  - the alignment must be within per-part bounds of the true pose: the angle between
 *    the found and the true axis (axial) or plane normal (mirror, glide), and the
 *    offset of the found element from the true one at the part's centre. Each bound is
 *    set a little above what was measured (numbers in the table below), so a regression
 *    fails; the measured values are printed in the test output;
 *  - the patch volume against the true missing volume. Where the paper's method works,
 *    the ratio patch / missing must lie in a measured band. Where it is known to fail
 *    (issue 6, "Beyond the paper"), the failure itself is asserted, as what it is: a
 *    key inflating the restored radius, teeth read as damage, a non-star-shaped
 *    outline, damage straddling the mirror plane. These are known-limit tests: when
 *    issue 6 fixes a part, its case fails and must be moved to the "works" kind.
 * Plus: the intact shaft gives nothing (or next to nothing) to repair, and the
 * truth.json reader's own cases (tests/support/truth.c), which need no shared parts.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "bridge/boolean.h"
#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "reconstruct.h"
#include "mesh/compare.h"
#include "support/assert_near.h"
#include "support/test_select.h"
#include "support/truth.h"

#define PARTS_DIR "../shared/parts"
#define SECTORS 120
#define LAYERS 160

/* What the paper's method is expected to do on a part, judged by the ratio
 * patch volume / true missing volume. */
typedef enum expect_kind {
    RESTORES,     /* ratio within [lo, hi]: the method works here */
    OVERFILLS,    /* known limit: ratio > lo (restores far more than is missing) */
    UNDERFILLS,   /* known limit: ratio < hi (restores far less than is missing) */
} expect_kind;

typedef struct part_case {
    const char *name;
    double max_angle_deg;   /* measured value, then a margin */
    double max_offset_mm;
    expect_kind expect;
    double lo, hi;          /* bounds on patch / missing (see expect_kind) */
    const char *why;        /* the known weakness, for known-limit cases */
    double glide_period_mm; /* glide: shifts equal modulo this are equivalent */
    double max_shift_err_mm;/* glide: bound on the shift found */
    int skip_union;         /* 1: only the patches are built here (the gear: its 19
                             * full-height unions take two minutes under ASan;
                             * `make bench` runs them) */
} part_case;

/* Bounds measured at 120/160 from damaged_posed.stl (release and ASan builds agree);
 * the measured figures are in each comment (ratio = patch / missing). Alignment: every
 * part measured at most 0.0002 deg and 0.0001 mm (the posed files are exact rigid
 * copies), bound 0.005 deg / 0.005 mm (issue 6 asks for 0.1 deg / 0.05 mm). */
static const part_case cases[] = {
    /* chip on the shoulder edge: ratio 0.904 (the per-cell farthest point sits on the
     * chip's rim, so part of each damaged cell is not refilled) */
    {"shaft_chipped_shoulder", 0.005, 0.005, RESTORES, 0.87, 0.95, NULL, 0, 0, 0},
    /* gouge in a hollow bushing, bore kept empty: ratio 0.889 */
    {"bushing_gouged", 0.005, 0.005, RESTORES, 0.86, 0.93, NULL, 0, 0, 0},
    /* issue 6: the key (r = 19) sets D_max for every layer it spans, so the whole
     * dia-30 shaft there is "restored" to r = 19: ratio 16.33 */
    {"keyed_shaft_dent", 0.005, 0.005, OVERFILLS, 5.0, 0,
     "the key inflates the restored radius (D_max = 19 instead of 15)", 0, 0, 0},
    /* broken rim across many sectors: ratio 0.920 */
    {"flange_broken_rim", 0.005, 0.005, RESTORES, 0.89, 0.96, NULL, 0, 0, 0},
    /* issue 6: Alg. 4 restores every one of the 19 intact tooth gaps to the tip
     * radius: ratio 17.29 */
    {"spur_gear_broken_tooth", 0.005, 0.005, OVERFILLS, 5.0, 0,
     "the intact tooth gaps read as damage (restored to the tip radius all round)", 0, 0,
     1},
    /* issue 6: the ear is restored, but a farthest-radius outline has no holes, so the
     * ear's hole (pi 5^2 x 8 = 628 mm^3 = 0.24 of missing) is filled too: ratio 1.382 */
    {"bracket_broken_ear", 0.005, 0.005, OVERFILLS, 1.2, 0,
     "the restored ear's hole is filled (no holes in a farthest-radius outline)", 0, 0, 0},
    /* issue 6: the z axis lies in the open slot; rays towards +y meet nothing and the
     * arm is filled from the axis: ratio 1.927 */
    {"u_clamp_broken_arm", 0.005, 0.005, OVERFILLS, 1.5, 0,
     "the outline is not star-shaped around the z axis (filled through the slot)", 0, 0, 0},
    /* issue 6: the chip hides behind the wider foot in the farthest-radius outline:
     * ratio 0.836 */
    {"rail_glide_chipped", 0.005, 0.005, UNDERFILLS, 0, 0.88,
     "the chipped tooth hides behind the wider foot (one farthest radius per sector)",
     20.0, 0.5, 0},
    /* issue 6: the broken corner straddles the mirror plane, so its mirror image is
     * broken too and the cells on both sides stay missing: ratio 0.500 */
    {"lever_posed", 0.005, 0.005, UNDERFILLS, 0, 0.60,
     "the damage straddles the mirror plane (its mirror image is missing too)", 0, 0, 0},
};

static int parts_present(void)
{
    struct stat sb;
    return stat(PARTS_DIR, &sb) == 0 && S_ISDIR(sb.st_mode);
}

static void read_mesh(const char *part, const char *file, sr_mesh *m)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/%s", PARTS_DIR, part, file);
    sr_err err = {{0}};
    sr_status st = sr_mesh_read(path, m, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
}

static void read_truth(const char *part, sr_truth *t)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s/truth.json", PARTS_DIR, part);
    sr_err err = {{0}};
    sr_status st = sr_truth_read(path, t, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
}

/* Reconstructs `file` of `part` with the options *o; asserts it succeeded. */
static void reconstruct_part(const char *part, const char *file, const sr_recon_opts *o,
                             sr_recon_result *r)
{
    sr_mesh scan = {0};
    read_mesh(part, file, &scan);
    sr_err err = {{0}};
    sr_status st = sr_reconstruct(&scan, o, r, &err);
    if (st != SR_OK)
        print_error("%s %s: %s\n", part, file, err.msg);
    assert_int_equal(st, SR_OK);
    sr_mesh_release(&scan);
}

/* Reconstructs `file` of `part` by the robust method (the default) given only the
 * symmetry kind (and order) from its truth.json; asserts it succeeded. */
static void robust_reconstruct(const char *part, const char *file, int skip_union,
                               sr_truth *truth, sr_recon_result *r)
{
    read_truth(part, truth);
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry.kind = truth->symmetry.kind;
    o.symmetry.order = truth->symmetry.order;
    o.skip_union = skip_union;
    reconstruct_part(part, file, &o, r);
}

static void part_reconstructs_within_measured_bounds(void **state)
{
    const part_case *pc = *state;
    if (!parts_present())
        skip();
    sr_truth truth;
    read_truth(pc->name, &truth);
    sr_mesh scan = {0};
    read_mesh(pc->name, "damaged_posed.stl", &scan);

    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry.kind = truth.symmetry.kind;
    o.symmetry.order = truth.symmetry.order;
    o.symmetry.shift_mm = 0; /* glide: searched */
    o.sectors = SECTORS;
    o.layers = LAYERS;
    o.method = SR_METHOD_PAPER;
    o.skip_union = pc->skip_union;
    sr_recon_result r;
    sr_err err = {{0}};
    sr_status st = sr_reconstruct(&scan, &o, &r, &err);
    if (st != SR_OK)
        print_error("%s: %s\n", pc->name, err.msg);
    assert_int_equal(st, SR_OK);

    double lo[3], hi[3];
    sr_mesh_bbox(&scan, lo, hi);
    double centre[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    sr_truth_align_error ae;
    sr_truth_align_error_of(&truth, &r.alignment, centre, &ae);
    double ratio = r.patch_volume_mm3 / truth.missing_volume;
    double shift_err = 0;
    if (truth.symmetry.kind == SR_SYM_GLIDE) {
        /* the shift the analysis used; +-shift + k x period are the same symmetry */
        double a = fabs(remainder(r.analysis.shift_mm - truth.symmetry.shift_mm,
                                  pc->glide_period_mm));
        double b = fabs(remainder(r.analysis.shift_mm + truth.symmetry.shift_mm,
                                  pc->glide_period_mm));
        shift_err = fmin(a, b);
        print_message("%-23s glide shift found %.3f mm, used %.3f mm (truth %.1f, period "
                      "%.0f): error %.3f mm (bound %.2f)\n",
                      pc->name, r.alignment.glide_shift_mm, r.analysis.shift_mm,
                      truth.symmetry.shift_mm, pc->glide_period_mm, shift_err,
                      pc->max_shift_err_mm);
    }
    print_message("%-23s angle %.4f deg (bound %.3f), offset %.4f mm (bound %.3f), "
                  "%zu section(s), patch %.1f / missing %.1f mm^3 = %.3f, %.2f s\n",
                  pc->name, ae.angle_deg, pc->max_angle_deg, ae.offset_mm, pc->max_offset_mm,
                  r.section_count, r.patch_volume_mm3, truth.missing_volume, ratio,
                  r.timings.total_s);
    /* Alg. 6's patches are closed 2-manifolds, so the restored part is the union */
    if (!pc->skip_union) {
        if (!r.restored_by_union)
            print_error("%s: union fell back: %s\n", pc->name, r.union_note);
        assert_true(r.restored_by_union);
        sr_mesh_edges e;
        assert_int_equal(sr_mesh_edge_stats(&r.restored, &e), SR_OK);
        assert_int_equal(e.boundary_edges + e.nonmanifold_edges + e.misoriented_edges, 0);
        assert_true(r.restored_volume_mm3 > r.scan_volume_mm3);
    }
    sr_recon_result_release(&r);
    sr_mesh_release(&scan);

    assert_true(ae.angle_deg <= pc->max_angle_deg);
    assert_true(ae.offset_mm <= pc->max_offset_mm);
    if (truth.symmetry.kind == SR_SYM_GLIDE)
        assert_true(shift_err <= pc->max_shift_err_mm);
    switch (pc->expect) {
    case RESTORES:
        assert_true(ratio >= pc->lo);
        assert_true(ratio <= pc->hi);
        break;
    case OVERFILLS:
        /* known limit, issue 6: when this starts failing, the part is fixed */
        print_message("  known limit (issue 6): %s\n", pc->why);
        assert_true(ratio > pc->lo);
        break;
    case UNDERFILLS:
        /* known limit, issue 6: when this starts failing, the part is fixed */
        print_message("  known limit (issue 6): %s\n", pc->why);
        assert_true(ratio < pc->hi);
        break;
    }
}

/* The intact shaft, canonical frame: at the default min depth (0) the only "damage" is
 * the facets of its 2048-triangle tessellation between the sector samples. Measured:
 * see the printed figures; the bound is far below any real chip (1785 mm^3 here). */
static void intact_shaft_has_nothing_to_repair(void **state)
{
    if (!parts_present())
        skip();
    sr_mesh m = {0};
    read_mesh("shaft_chipped_shoulder", "intact.stl", &m);
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry.kind = SR_SYM_AXIAL;
    o.sectors = SECTORS;
    o.layers = LAYERS;
    o.method = SR_METHOD_PAPER;
    sr_recon_result r;
    sr_err err = {{0}};
    sr_status st = sr_reconstruct(&m, &o, &r, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    double depth = 0;
    for (size_t i = 0; i < r.section_count; i++)
        depth = fmax(depth, r.sections[i].depth_max_mm);
    print_message("intact shaft: %zu section(s), %.4f mm^3, deepest %.4f mm\n",
                  r.section_count, r.patch_volume_mm3, depth);
    assert_true(r.patch_volume_mm3 < 1.0);
    assert_true(depth < 0.05);
    sr_recon_result_release(&r);
    sr_mesh_release(&m);
}

/* The U clamp by the paper's method at 240/320: Alg. 6's patch (a closed 2-manifold)
 * has, once its exact stack is rounded to double, a few near-coincident points where
 * walls of neighbouring layers run along the same sector border; its union is refused
 * until those triangles are mended (measured: 4 replaced). The restored part must still
 * be the union, one closed surface, and the run must say what was mended. */
static void paper_patch_crossing_itself_is_mended_for_the_union(void **state)
{
    (void)state;
    if (!parts_present())
        skip();
    sr_mesh scan = {0};
    read_mesh("u_clamp_broken_arm", "damaged_posed.stl", &scan);
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry.kind = SR_SYM_MIRROR;
    o.method = SR_METHOD_PAPER; /* default grid: 240 sectors, 320 layers */
    sr_recon_result r;
    sr_err err = {{0}};
    sr_status st = sr_reconstruct(&scan, &o, &r, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    print_message("u clamp, paper, 240/320: union %d (%s), %s\n", r.restored_by_union,
                  r.union_note, r.repair_note);
    assert_true(r.restored_by_union);
    assert_non_null(strstr(r.repair_note, "patch triangles replaced"));
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&r.restored, &e), SR_OK);
    assert_int_equal(e.boundary_edges + e.nonmanifold_edges + e.misoriented_edges, 0);
    int crosses = -1;
    assert_int_equal(sr_mesh_self_intersects(&r.restored, &crosses, NULL), SR_OK);
    assert_int_equal(crosses, 0);
    sr_recon_result_release(&r);
    sr_mesh_release(&scan);
}

/* ---- the robust method (issue 6) ---- */

/* The default method, given only the symmetry kind (and the gear's order), at the
 * default grid (240 sectors, 320 layers), on each part's damaged_posed.stl and on its
 * noisy damaged_scan.stl (densified, sigma 0.02 mm), judged in the canonical frame by
 * issue 6's "done when" bounds: exactly one section (truth.json: every part has one;
 * noise makes no false section), each patch closed; patch volume within 5 % of the true
 * missing volume; patch volume outside the intact part <= 3 % and true missing volume
 * no patch covers <= 5 % (both of the missing volume, by CGAL booleans); the restored
 * part (the scan united with its patches) one closed surface within 1 % of the intact
 * volume, deviating from the intact part by mean <= 0.05 mm and max <= 1 mm both ways
 * (sr_compare_meshes). Measured figures: the printed lines, and `make bench` (README).
 * Before the issue's work the paper's method missed these by up to +2040 % (gear); the
 * lever's break straddles the mirror plane and needs continuity along z
 * (restore_continuity.h: -59 % without); the noisy rail read four false one-layer
 * sections at notch ends until the layer planes moved off flat faces (layer_planes.h). */
typedef struct robust_case {
    const char *name, *file;
} robust_case;

static const robust_case robust_cases[] = {
    {"shaft_chipped_shoulder", "damaged_posed.stl"}, {"shaft_chipped_shoulder", "damaged_scan.stl"},
    {"bushing_gouged", "damaged_posed.stl"},         {"bushing_gouged", "damaged_scan.stl"},
    {"keyed_shaft_dent", "damaged_posed.stl"},       {"keyed_shaft_dent", "damaged_scan.stl"},
    {"flange_broken_rim", "damaged_posed.stl"},      {"flange_broken_rim", "damaged_scan.stl"},
    {"spur_gear_broken_tooth", "damaged_posed.stl"}, {"spur_gear_broken_tooth", "damaged_scan.stl"},
    {"bracket_broken_ear", "damaged_posed.stl"},     {"bracket_broken_ear", "damaged_scan.stl"},
    {"u_clamp_broken_arm", "damaged_posed.stl"},     {"u_clamp_broken_arm", "damaged_scan.stl"},
    {"rail_glide_chipped", "damaged_posed.stl"},     {"rail_glide_chipped", "damaged_scan.stl"},
    {"lever_posed", "damaged_posed.stl"},            {"lever_posed", "damaged_scan.stl"},
};

/* r's restored part (from `file` of part `name`), mapped to the canonical frame by m,
 * held to the restored-vs-intact bounds above. */
static void assert_restored_matches_intact(const char *name, const char *file,
                                           sr_recon_result *r, const double m[12],
                                           const sr_mesh *intact)
{
    sr_err err = {{0}};
    if (!r->restored_by_union)
        print_error("%s %s: union fell back: %s\n", name, file, r->union_note);
    assert_true(r->restored_by_union);
    sr_mesh_transform(&r->restored, m);
    sr_compare_result c;
    assert_int_equal(sr_compare_meshes(intact, "intact", &r->restored, "restored", NULL, &c,
                                       &err),
                     SR_OK);
    print_message("%-23s %s restored vs intact: volume %+.3f %%, intact->restored max %.3f "
                  "mean %.4f mm, restored->intact max %.3f mean %.4f mm\n",
                  name, file, c.volume_diff_pct, c.a_to_b.max_mm, c.a_to_b.mean_mm,
                  c.b_to_a.max_mm, c.b_to_a.mean_mm);
    assert_true(c.closed_b);
    assert_true(fabs(c.volume_diff_pct) <= 1.0);
    assert_true(c.a_to_b.mean_mm <= 0.05 && c.b_to_a.mean_mm <= 0.05);
    assert_true(c.a_to_b.max_mm <= 1.0 && c.b_to_a.max_mm <= 1.0);
}

static void robust_part_is_restored_within_the_issue_bounds(void **state)
{
    const robust_case *rc = *state;
    if (!parts_present())
        skip();
    sr_truth truth;
    sr_recon_result r;
    robust_reconstruct(rc->name, rc->file, 0, &truth, &r);
    sr_mesh intact = {0}, missing = {0};
    read_mesh(rc->name, "intact.stl", &intact);
    read_mesh(rc->name, "missing.stl", &missing);
    double m[12];
    sr_truth_to_canonical(&truth, m);
    double outside, covered, mv = truth.missing_volume;
    sr_err err = {{0}};
    sr_status st = sr_truth_patch_overlap(r.sections, r.section_count, m, &intact, &missing,
                                          &outside, &covered, &err);
    if (st != SR_OK)
        print_error("%s %s: patch overlap: %s\n", rc->name, rc->file, err.msg);
    assert_int_equal(st, SR_OK);
    double rel = (r.patch_volume_mm3 - mv) / mv, out = outside / mv, missed = (mv - covered) / mv;
    print_message("%-23s %s robust: %zu section(s), patch %.1f / missing %.1f mm^3 = %+.2f %%, "
                  "out %.2f %%, missed %.2f %%, %.2f s\n",
                  rc->name, rc->file, r.section_count, r.patch_volume_mm3, mv, 100 * rel,
                  100 * out, 100 * missed, r.timings.total_s);
    for (size_t i = 0; i < r.section_count; i++)
        assert_true(sr_mesh_is_closed(&r.sections[i].patch));
    assert_int_equal(r.section_count, 1);
    assert_true(fabs(rel) <= 0.05);
    assert_true(out <= 0.03);
    assert_true(missed <= 0.05);
    assert_restored_matches_intact(rc->name, rc->file, &r, m, &intact);
    sr_recon_result_release(&r);
    sr_mesh_release(&intact);
    sr_mesh_release(&missing);
}

/* Issue 6 item 4, the order detected: the gear's posed scan given only "axial" and
 * --order auto is found 20-fold (not a divisor, not a neighbour), realigned with that
 * order and restored as with the order given: one section within 5 % (measured: -1.25 %,
 * the same as with order 20 given). */
static void gear_order_is_found_and_restores_the_tooth(void **state)
{
    (void)state;
    if (!parts_present())
        skip();
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry.kind = SR_SYM_AXIAL;
    o.symmetry.order = SR_ORDER_AUTO;
    o.skip_union = 1;
    sr_truth truth;
    read_truth("spur_gear_broken_tooth", &truth);
    sr_recon_result r;
    reconstruct_part("spur_gear_broken_tooth", "damaged_posed.stl", &o, &r);
    double rel = (r.patch_volume_mm3 - truth.missing_volume) / truth.missing_volume;
    print_message("gear, order auto: found %d (mismatch %.5f mm, base %.3f mm), %zu section(s), "
                  "patch %+.2f %%\n",
                  r.order, r.order_found.mismatch_mm, r.order_found.base_mm, r.section_count,
                  100 * rel);
    assert_true(r.order_auto);
    assert_int_equal(r.order, truth.symmetry.order);
    assert_int_equal(r.section_count, 1);
    assert_true(fabs(rel) <= 0.05);
    sr_recon_result_release(&r);
}

/* Issue 6: no section at all on any intact part (canonical frame, default settings). */
static void robust_finds_nothing_on_an_intact_part(void **state)
{
    const char *name = *state;
    if (!parts_present())
        skip();
    sr_truth truth;
    sr_recon_result r;
    robust_reconstruct(name, "intact.stl", 1, &truth, &r);
    print_message("%-23s intact: %zu section(s), %.2f mm^3\n", name, r.section_count,
                  r.patch_volume_mm3);
    size_t sections = r.section_count;
    sr_recon_result_release(&r);
    assert_int_equal(sections, 0);
}

/* ---- the truth.json reader (tests/support/truth.c) ---- */

typedef struct tmpdir {
    char path[64];
} tmpdir;

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(fputs(text, f) >= 0, 1);
    assert_int_equal(fclose(f), 0);
}

static const char minimal_truth[] =
    "{\n  \"name\": \"rail\",\n  \"symmetry\": \"glide\",\n  \"glide_shift_mm\": 10.0,\n"
    "  \"intact_volume\": 58610.0,\n  \"missing_volume\": 1322.4,\n"
    "  \"sections\": [ { \"volume\": 5.0 } ],\n"
    "  \"pose\": {\n    \"rotation_matrix_3x3\": [\n      [0.0, -1.0, 0.0],\n"
    "      [1.0, 0.0, 0.0],\n      [0.0, 0.0, 1.0]\n    ],\n"
    "    \"translation\": [10.0, -20.0, 30.0],\n"
    "    \"maps\": \"p_posed = R @ p_canonical + translation\"\n  }\n}\n";

static void truth_reader_reads_the_needed_fields(void **state)
{
    tmpdir d;
    snprintf(d.path, sizeof d.path, "/tmp/symrec-test-XXXXXX");
    assert_non_null(mkdtemp(d.path));
    char file[128];
    snprintf(file, sizeof file, "%s/truth.json", d.path);
    write_text(file, minimal_truth);
    sr_truth t;
    sr_err err = {{0}};
    assert_int_equal(sr_truth_read(file, &t, &err), SR_OK);
    assert_string_equal(t.name, "rail");
    assert_int_equal(t.symmetry.kind, SR_SYM_GLIDE);
    assert_int_equal(t.symmetry.order, 0);
    assert_near(t.symmetry.shift_mm, 10.0, 0);
    assert_near(t.intact_volume, 58610.0, 0);
    assert_near(t.missing_volume, 1322.4, 0);
    assert_near(t.R[1], -1.0, 0);
    assert_near(t.R[3], 1.0, 0);
    assert_near(t.t[2], 30.0, 0);
    /* posed -> canonical undoes the pose: posed point R (1, 2, 3) + t */
    double m[12], posed[3] = {-2 + 10.0, 1 - 20.0, 3 + 30.0}, can[3];
    sr_truth_to_canonical(&t, m);
    sr_xform_apply(m, posed, can);
    assert_near(can[0], 1, 1e-12);
    assert_near(can[1], 2, 1e-12);
    assert_near(can[2], 3, 1e-12);
    /* a found alignment equal to the truth has no error; one turned 10 deg about the
     * canonical z axis tilts the plane normal by 10 deg */
    sr_alignment a;
    memset(&a, 0, sizeof a);
    memcpy(a.xform, m, sizeof m);
    double centre[3] = {10, -20, 80};
    sr_truth_align_error ae;
    sr_truth_align_error_of(&t, &a, centre, &ae);
    assert_near(ae.angle_deg, 0, 1e-9);
    assert_near(ae.offset_mm, 0, 1e-9);
    double c = cos(10 * M_PI / 180), s = sin(10 * M_PI / 180);
    double rz[12] = {c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0};
    sr_xform_mul(a.xform, rz, m);
    sr_truth_align_error_of(&t, &a, centre, &ae);
    assert_near(ae.angle_deg, 10, 1e-9);
    assert_near(ae.offset_mm, 0, 1e-9);
    /* shifted 2 mm along canonical x: the plane is 2 mm off */
    double tx[12] = {1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0};
    sr_xform_mul(a.xform, tx, m);
    sr_truth_align_error_of(&t, &a, centre, &ae);
    assert_near(ae.angle_deg, 0, 1e-9);
    assert_near(ae.offset_mm, 2, 1e-9);
    assert_int_equal(unlink(file), 0);
    assert_int_equal(rmdir(d.path), 0);
}

static void truth_reader_reports_a_missing_key(void **state)
{
    tmpdir d;
    snprintf(d.path, sizeof d.path, "/tmp/symrec-test-XXXXXX");
    assert_non_null(mkdtemp(d.path));
    char file[128];
    snprintf(file, sizeof file, "%s/truth.json", d.path);
    /* the same file without the translation */
    char text[sizeof minimal_truth];
    memcpy(text, minimal_truth, sizeof text);
    char *p = strstr(text, "\"translation\"");
    assert_non_null(p);
    memcpy(p, "\"translatiom\"", 13);
    write_text(file, text);
    sr_truth t;
    memset(&t, 0x5a, sizeof t);
    sr_truth before = t;
    sr_err err = {{0}};
    assert_int_equal(sr_truth_read(file, &t, &err), SR_E_FORMAT);
    assert_non_null(strstr(err.msg, "pose.translation"));
    assert_non_null(strstr(err.msg, file));
    assert_memory_equal(&t, &before, sizeof t); /* untouched on failure */
    assert_int_equal(unlink(file), 0);
    assert_int_equal(rmdir(d.path), 0);
}

static void truth_reader_reports_a_missing_file(void **state)
{
    sr_truth t;
    sr_err err = {{0}};
    assert_int_equal(sr_truth_read("/nonexistent/symrec/truth.json", &t, &err), SR_E_IO);
    assert_non_null(strstr(err.msg, "'/nonexistent/symrec/truth.json'"));
}

int main(void)
{
    enum { NP = sizeof cases / sizeof cases[0], NR = sizeof robust_cases / sizeof robust_cases[0] };
    struct CMUnitTest tests[NP + NR + NP + 7];
    static char names[NP][96], rnames[NR][96], inames[NP][96];
    size_t n = 0;
    for (size_t i = 0; i < NP; i++) {
        snprintf(names[i], sizeof names[i], "%s_reconstructs_within_measured_bounds",
                 cases[i].name);
        tests[n++] = (struct CMUnitTest){names[i], part_reconstructs_within_measured_bounds,
                                         NULL, NULL, (void *)&cases[i]};
    }
    for (size_t i = 0; i < NR; i++) {
        snprintf(rnames[i], sizeof rnames[i], "%s_%s_robust_restored_within_bounds",
                 robust_cases[i].name, strstr(robust_cases[i].file, "scan") ? "scan" : "posed");
        tests[n++] = (struct CMUnitTest){rnames[i], robust_part_is_restored_within_the_issue_bounds,
                                         NULL, NULL, (void *)&robust_cases[i]};
    }
    for (size_t i = 0; i < NP; i++) {
        snprintf(inames[i], sizeof inames[i], "%s_robust_finds_nothing_on_intact",
                 cases[i].name);
        tests[n++] = (struct CMUnitTest){inames[i], robust_finds_nothing_on_an_intact_part,
                                         NULL, NULL, (void *)cases[i].name};
    }
    tests[n++] = (struct CMUnitTest)cmocka_unit_test(gear_order_is_found_and_restores_the_tooth);
    tests[n++] = (struct CMUnitTest)cmocka_unit_test(intact_shaft_has_nothing_to_repair);
    tests[n++] =
        (struct CMUnitTest)cmocka_unit_test(paper_patch_crossing_itself_is_mended_for_the_union);
    tests[n++] = (struct CMUnitTest)cmocka_unit_test(truth_reader_reads_the_needed_fields);
    tests[n++] = (struct CMUnitTest)cmocka_unit_test(truth_reader_reports_a_missing_key);
    tests[n++] = (struct CMUnitTest)cmocka_unit_test(truth_reader_reports_a_missing_file);
    /* SYMREC_TEST_FILTER=glob,glob,... runs only the cases matching one of the globs,
     * SYMREC_TEST_SKIP=glob,... all but those (support/test_select.h): tests/run_tests.sh
     * splits this binary into shards that run side by side, one per CPU */
    n = sr_test_select(tests, n);
    return _cmocka_run_group_tests("accuracy", tests, n, NULL, NULL);
}
