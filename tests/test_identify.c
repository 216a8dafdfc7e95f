/*
 * test_identify.c: the shape descriptor (src/align/shape_descriptor.h), its storage in
 * the catalogue (sql/006_part_descriptor.sql: stored at `part add`, backfilled by the
 * first identification of a writable catalogue, computed without storing on a
 * read-only one) and sr_catalog_identify (src/catalog/catalog_identify.c) on a
 * catalogue of the nine shared intact parts (../shared/parts, skipped when absent)
 * with distractors made from them: each scaled by 0.8 and 1.25 and stretched by 1.15
 * along one axis, so similar shapes of other sizes. Known answers: the descriptor
 * of a moved mesh equals the original's; a posed damaged scan and a noisy scan are
 * identified as their own part, first, with a margin; the scan with its part
 * removed gets no match; two identical parts are one design under two numbers (a
 * match naming both, the margin taken to the next design); a part whose mesh is the
 * scan's own broken shape beside the intact one is too close to call.
 *
 * The cases that register (identify_*) are in the Makefile's VALGRIND_SKIP.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "align/identify.h"
#include "align/shape_descriptor.h"
#include "bridge/boolean.h"
#include "bridge/mesh_io.h"
#include "catalog/catalog_identify.h"
#include "catalog/catalog_int.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

#define PARTS_DIR "../shared/parts"

static const char *const shared[] = {
    "bracket_broken_ear", "bushing_gouged",     "flange_broken_rim",      "keyed_shaft_dent",
    "lever_posed",        "rail_glide_chipped", "shaft_chipped_shoulder", "spur_gear_broken_tooth",
    "u_clamp_broken_arm",
};
#define NSHARED (sizeof shared / sizeof shared[0])

static bool read_part_file(const char *part, const char *file, sr_mesh *out)
{
    char path[512];
    snprintf(path, sizeof path, PARTS_DIR "/%s/%s", part, file);
    if (access(path, R_OK) != 0)
        return false;
    sr_err err;
    if (sr_mesh_read(path, out, &err) != SR_OK)
        fail_msg("%s", err.msg);
    return true;
}

/* A rotation by `deg` about the unit axis (x, y, z), then a move. */
static void rigid(double deg, double x, double y, double z, const double t[3], double m[12])
{
    double n = sqrt(x * x + y * y + z * z), a = deg * M_PI / 180, c = cos(a), s = sin(a);
    x /= n, y /= n, z /= n;
    double r[9] = {c + x * x * (1 - c),     x * y * (1 - c) - z * s, x * z * (1 - c) + y * s,
                   y * x * (1 - c) + z * s, c + y * y * (1 - c),     y * z * (1 - c) - x * s,
                   z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            m[4 * i + j] = r[3 * i + j];
        m[4 * i + 3] = t[i];
    }
}

/* ---- the descriptor ---- */

static void descriptor_is_the_same_in_any_pose(void **state)
{
    (void)state;
    sr_mesh m, moved;
    if (!read_part_file("bracket_broken_ear", "intact.stl", &m))
        skip();
    assert_int_equal(sr_mesh_copy(&moved, &m), SR_OK);
    double xf[12], t[3] = {120, -35, 410};
    rigid(73, 0.3, -1, 0.4, t, xf);
    sr_mesh_transform(&moved, xf);
    sr_shape_descriptor a, b;
    sr_err err;
    assert_int_equal(sr_shape_descriptor_compute(&m, "a", &a, &err), SR_OK);
    assert_int_equal(sr_shape_descriptor_compute(&moved, "b", &b, &err), SR_OK);
    assert_true(fabs(a.area_mm2 - b.area_mm2) < 1e-9 * a.area_mm2);
    for (int k = 0; k < 3; k++)
        assert_true(fabs(a.spread_mm[k] - b.spread_mm[k]) < 1e-9 * a.spread_mm[0]);
    assert_true(a.spread_mm[0] >= a.spread_mm[1] && a.spread_mm[1] >= a.spread_mm[2]);
    double sum = 0;
    for (int k = 0; k < SR_SHAPE_D2_BINS; k++)
        sum += a.d2[k];
    assert_true(fabs(sum - 1) < 1e-12);
    /* rounding may move a pair across a bin edge, no more */
    assert_true(sr_shape_descriptor_distance(&a, &b) < 1e-4);
    assert_true(sr_shape_descriptor_distance(&a, &a) == 0);
    sr_mesh_release(&m);
    sr_mesh_release(&moved);
}

static void descriptor_keeps_scale(void **state)
{
    (void)state;
    sr_mesh m, big;
    if (!read_part_file("lever_posed", "intact.stl", &m))
        skip();
    assert_int_equal(sr_mesh_copy(&big, &m), SR_OK);
    const double xf[12] = {1.25, 0, 0, 0, 0, 1.25, 0, 0, 0, 0, 1.25, 0};
    sr_mesh_transform(&big, xf);
    sr_shape_descriptor a, b;
    assert_int_equal(sr_shape_descriptor_compute(&m, "a", &a, NULL), SR_OK);
    assert_int_equal(sr_shape_descriptor_compute(&big, "b", &b, NULL), SR_OK);
    /* a uniform scaling by s: every distance and spread times s, |log2 s| octaves */
    double d = sr_shape_descriptor_distance(&a, &b), want = log2(1.25);
    assert_true(fabs(d - want) < 0.02);
    assert_true(fabs(sr_shape_descriptor_distance(&b, &a) - d) < 1e-12);
    assert_true(fabs(b.spread_mm[0] / a.spread_mm[0] - 1.25) < 1e-9);
    sr_mesh_release(&m);
    sr_mesh_release(&big);
}

static void descriptor_round_trips_and_refuses_bad_blobs(void **state)
{
    (void)state;
    sr_shape_descriptor d, back;
    memset(&d, 0, sizeof d);
    d.area_mm2 = 1234.5;
    d.spread_mm[0] = 30, d.spread_mm[1] = 20, d.spread_mm[2] = 5;
    d.d2[40] = 0.25, d.d2[41] = 0.75;
    unsigned char blob[SR_CAT_DESCRIPTOR_BYTES];
    sr_cat_descriptor_pack(&d, blob);
    assert_int_equal(sr_cat_descriptor_unpack(blob, sizeof blob, &back, NULL), SR_OK);
    assert_memory_equal(&d, &back, sizeof d);
    sr_err err;
    assert_int_equal(sr_cat_descriptor_unpack(blob, sizeof blob - 8, &back, &err), SR_E_FORMAT);
    assert_non_null(strstr(err.msg, "bytes"));
    unsigned char bad[sizeof blob];
    memcpy(bad, blob, sizeof bad);
    bad[6] ^= 0x10; /* the version's exponent */
    assert_int_equal(sr_cat_descriptor_unpack(bad, sizeof bad, &back, &err), SR_E_FORMAT);
    assert_non_null(strstr(err.msg, "version"));
    memcpy(bad, blob, sizeof bad);
    memset(bad + 40 + 8 * 3, 0xff, 8); /* a share that is NaN */
    assert_int_equal(sr_cat_descriptor_unpack(bad, sizeof bad, &back, &err), SR_E_FORMAT);
    assert_non_null(strstr(err.msg, "finite"));
}

/* ---- the catalogue ---- */

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    sr_catalog *cat;
    bool have_parts;
} fixture;

static void add_part(sr_catalog *cat, const char *number, const sr_mesh *m)
{
    sr_err err;
    sr_part_new p = {.number = number, .name = number, .mesh = m};
    if (sr_catalog_part_add(cat, &p, NULL, &err) != SR_OK)
        fail_msg("%s", err.msg);
}

/* The nine intact parts, and each scaled by 0.8 and 1.25 and stretched by 1.15. */
static int group_setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    assert_int_equal(sr_catalog_open(f->db, SR_CATALOG_CREATE, &f->cat, NULL), SR_OK);
    f->have_parts = true;
    for (size_t i = 0; i < NSHARED && f->have_parts; i++) {
        sr_mesh m;
        if (!read_part_file(shared[i], "intact.stl", &m)) {
            f->have_parts = false;
            break;
        }
        add_part(f->cat, shared[i], &m);
        static const double s[3][3] = {{0.8, 0.8, 0.8}, {1.25, 1.25, 1.25}, {1.15, 1, 1}};
        static const char *const tag[3] = {"small", "large", "long"};
        for (int v = 0; v < 3; v++) {
            sr_mesh c;
            assert_int_equal(sr_mesh_copy(&c, &m), SR_OK);
            const double xf[12] = {s[v][0], 0, 0, 0, 0, s[v][1], 0, 0, 0, 0, s[v][2], 0};
            sr_mesh_transform(&c, xf);
            char number[64];
            snprintf(number, sizeof number, "%s-%s", shared[i], tag[v]);
            add_part(f->cat, number, &c);
            sr_mesh_release(&c);
        }
        sr_mesh_release(&m);
    }
    *state = f;
    return 0;
}

static int group_teardown(void **state)
{
    fixture *f = *state;
    sr_catalog_close(f->cat);
    tmpdir_remove(&f->dir);
    free(f);
    return 0;
}

static long long count_rows(sr_catalog *cat, const char *sql)
{
    sqlite3_stmt *st = NULL;
    assert_int_equal(sqlite3_prepare_v2(cat->db, sql, -1, &st, NULL), SQLITE_OK);
    assert_int_equal(sqlite3_step(st), SQLITE_ROW);
    long long n = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    return n;
}

static void part_add_stores_the_descriptor(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    assert_int_equal(count_rows(f->cat, "SELECT count(*) FROM mesh_descriptors"), 4 * NSHARED);
    sr_part_info p;
    assert_int_equal(sr_catalog_part_find(f->cat, "flange_broken_rim", &p, NULL), SR_OK);
    sr_shape_descriptor stored, fresh;
    assert_int_equal(sr_catalog_mesh_descriptor(f->cat, p.mesh_id, &stored, NULL), SR_OK);
    sr_mesh m;
    assert_int_equal(sr_catalog_part_mesh(f->cat, p.id, &m, NULL), SR_OK);
    assert_int_equal(sr_shape_descriptor_compute(&m, "m", &fresh, NULL), SR_OK);
    sr_mesh_release(&m);
    assert_memory_equal(&stored, &fresh, sizeof stored);
    sr_err err;
    assert_int_equal(sr_catalog_mesh_descriptor(f->cat, 999999, &stored, &err), SR_E_NOTFOUND);
}

/* The identification of one shared part's file; checks it names `want` first with a
 * margin, or (want NULL) that it is no match. */
static void expect_identified(fixture *f, const char *part, const char *file, const char *want)
{
    sr_mesh scan;
    if (!read_part_file(part, file, &scan))
        skip();
    sr_identify_result res;
    sr_err err;
    if (sr_catalog_identify(f->cat, &scan, NULL, &res, &err) != SR_OK)
        fail_msg("%s", err.msg);
    sr_mesh_release(&scan);
    assert_true(res.count >= 2);
    if (want) {
        if (res.verdict != SR_IDENTIFY_MATCH || strcmp(res.cand[0].number, want) != 0)
            fail_msg("%s/%s: verdict %d, first '%s' (%.3f), second '%s' (%.3f)", part, file,
                     (int)res.verdict, res.cand[0].number, res.cand[0].fit.score,
                     res.cand[1].number, res.cand[1].fit.score);
        assert_true(res.cand[0].fit.score - res.cand[1].fit.score > 0.3);
        assert_true(res.cand[0].fit.coverage > 0.85);
        assert_true(res.cand[0].fit.lacking < 0.25);
        assert_true(res.cand[0].fit.rms_mm < 0.2 * res.tol_mm);
    } else {
        if (res.verdict != SR_IDENTIFY_NO_MATCH)
            fail_msg("%s/%s: verdict %d, first '%s' (%.3f: coverage %.3f, lacking %.3f, RMS "
                     "%.3f of tol %.3f mm)",
                     part, file, (int)res.verdict, res.cand[0].number, res.cand[0].fit.score,
                     res.cand[0].fit.coverage, res.cand[0].fit.lacking, res.cand[0].fit.rms_mm,
                     res.tol_mm);
    }
    sr_identify_result_release(&res);
}

static void identify_names_posed_scans_first_with_a_margin(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    expect_identified(f, "bracket_broken_ear", "damaged_posed.stl", "bracket_broken_ear");
    expect_identified(f, "lever_posed", "damaged_posed.stl", "lever_posed");
    expect_identified(f, "rail_glide_chipped", "damaged_posed.stl", "rail_glide_chipped");
}

static void identify_names_a_noisy_scan(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    expect_identified(f, "spur_gear_broken_tooth", "damaged_scan.stl", "spur_gear_broken_tooth");
}

static void identify_backfills_descriptors_when_writable(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    /* as after migration 006: parts without descriptors */
    assert_int_equal(sqlite3_exec(f->cat->db, "DELETE FROM mesh_descriptors", NULL, NULL, NULL),
                     SQLITE_OK);
    sr_mesh scan;
    assert_true(read_part_file("keyed_shaft_dent", "damaged_posed.stl", &scan));
    /* read-only: computed, not stored */
    sr_catalog *ro;
    assert_int_equal(sr_catalog_open(f->db, SR_CATALOG_READONLY, &ro, NULL), SR_OK);
    sr_identify_result res;
    assert_int_equal(sr_catalog_identify(ro, &scan, NULL, &res, NULL), SR_OK);
    assert_int_equal(res.parts, 4 * NSHARED);
    assert_int_equal(res.described, 4 * NSHARED);
    assert_int_equal(res.stored, 0);
    assert_int_equal(res.verdict, SR_IDENTIFY_MATCH);
    assert_string_equal(res.cand[0].number, "keyed_shaft_dent");
    sr_identify_result_release(&res);
    sr_catalog_close(ro);
    assert_int_equal(count_rows(f->cat, "SELECT count(*) FROM mesh_descriptors"), 0);
    /* writable: stored once */
    assert_int_equal(sr_catalog_identify(f->cat, &scan, NULL, &res, NULL), SR_OK);
    assert_int_equal(res.described, 4 * NSHARED);
    assert_int_equal(res.stored, 4 * NSHARED);
    sr_identify_result_release(&res);
    assert_int_equal(count_rows(f->cat, "SELECT count(*) FROM mesh_descriptors"), 4 * NSHARED);
    sr_identify_opts o = {0, 1};
    assert_int_equal(sr_catalog_identify(f->cat, &scan, &o, &res, NULL), SR_OK);
    assert_int_equal(res.described, 0);
    assert_int_equal(res.count, 1);
    assert_string_equal(res.cand[0].number, "keyed_shaft_dent");
    sr_identify_result_release(&res);
    sr_mesh_release(&scan);
}

static void identify_refuses_bad_options_and_scans(void **state)
{
    fixture *f = *state;
    sr_mesh scan;
    sr_mesh_init(&scan);
    sr_identify_result res;
    sr_err err;
    assert_int_equal(sr_catalog_identify(f->cat, &scan, NULL, &res, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "scan"));
    sr_identify_opts o = {0, SR_IDENTIFY_TOP_MAX + 1};
    assert_int_equal(sr_catalog_identify(f->cat, &scan, &o, &res, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "top"));
    o.top = 1;
    o.tol_mm = -1;
    assert_int_equal(sr_catalog_identify(f->cat, &scan, &o, &res, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "tol"));
    /* an empty catalogue */
    tmpdir d;
    char db[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_make(&d), 0);
    tmpdir_join(&d, "empty.db", db);
    sr_catalog *cat;
    assert_int_equal(sr_catalog_open(db, SR_CATALOG_CREATE, &cat, NULL), SR_OK);
    const double xyz[] = {0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 10};
    const uint32_t tri[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    sr_mesh tet = {(double *)xyz, (uint32_t *)tri, 4, 4};
    assert_int_equal(sr_catalog_identify(cat, &tet, NULL, &res, &err), SR_E_NOTFOUND);
    assert_non_null(strstr(err.msg, "no part with an intact mesh"));
    sr_catalog_close(cat);
    tmpdir_remove(&d);
}

static void identify_says_no_match_without_the_part(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    /* the scans of two parts, each with its part (and its variants kept) removed */
    assert_int_equal(sr_catalog_part_remove(f->cat, "lever_posed", 0, NULL, NULL), SR_OK);
    assert_int_equal(sr_catalog_part_remove(f->cat, "flange_broken_rim", 0, NULL, NULL), SR_OK);
    expect_identified(f, "lever_posed", "damaged_posed.stl", NULL);
    expect_identified(f, "flange_broken_rim", "damaged_posed.stl", NULL);
    sr_mesh m;
    assert_true(read_part_file("lever_posed", "intact.stl", &m));
    add_part(f->cat, "lever_posed", &m);
    sr_mesh_release(&m);
    assert_true(read_part_file("flange_broken_rim", "intact.stl", &m));
    add_part(f->cat, "flange_broken_rim", &m);
    sr_mesh_release(&m);
}

static void identify_two_identical_parts_are_one_design(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    sr_mesh m;
    assert_true(read_part_file("u_clamp_broken_arm", "intact.stl", &m));
    add_part(f->cat, "u_clamp_copy", &m);
    sr_mesh_release(&m);
    sr_mesh scan;
    assert_true(read_part_file("u_clamp_broken_arm", "damaged_posed.stl", &scan));
    sr_identify_result res;
    sr_identify_opts one = {0, 1};
    assert_int_equal(sr_catalog_identify(f->cat, &scan, &one, &res, NULL), SR_OK);
    sr_mesh_release(&scan);
    assert_int_equal(res.verdict, SR_IDENTIFY_MATCH);
    assert_int_equal(res.same_design, 2);
    assert_int_equal(res.count, 2); /* --top 1: the design's two numbers */
    assert_int_equal(res.registered, SR_IDENTIFY_SHORTLIST);
    bool a = strcmp(res.cand[0].number, "u_clamp_broken_arm") == 0 &&
             strcmp(res.cand[1].number, "u_clamp_copy") == 0;
    bool b = strcmp(res.cand[1].number, "u_clamp_broken_arm") == 0 &&
             strcmp(res.cand[0].number, "u_clamp_copy") == 0;
    assert_true(a || b);
    assert_true(res.cand[2].fit.score < res.cand[0].fit.score - SR_IDENTIFY_MARGIN); /* held */
    sr_identify_result_release(&res);
    assert_int_equal(sr_catalog_part_remove(f->cat, "u_clamp_copy", 0, NULL, NULL), SR_OK);
}

/* A part that is the U clamp stretched by 0.8 % along x: the damaged scan fits it
 * almost as well as its own part (0.83 against 0.86), yet its sides stand farther than
 * the tolerance from the clamp's: another design, too close to call, the two named.
 * (Stretched by 0.5 % it stays within the tolerance: one design; by 1 %, the scan
 * tells them apart by more than the margin.) */
static void identify_two_designs_within_the_margin_are_too_close(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    const double k = 1.008;
    sr_mesh m;
    assert_true(read_part_file("u_clamp_broken_arm", "intact.stl", &m));
    const double xf[12] = {k, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    sr_mesh_transform(&m, xf);
    add_part(f->cat, "u_clamp_wider", &m);
    sr_mesh_release(&m);
    sr_mesh scan;
    assert_true(read_part_file("u_clamp_broken_arm", "damaged_posed.stl", &scan));
    sr_identify_result res;
    assert_int_equal(sr_catalog_identify(f->cat, &scan, NULL, &res, NULL), SR_OK);
    sr_mesh_release(&scan);
    assert_int_equal(res.verdict, SR_IDENTIFY_TOO_CLOSE);
    assert_int_equal(res.same_design, 1);
    bool a = strcmp(res.cand[0].number, "u_clamp_broken_arm") == 0 &&
             strcmp(res.cand[1].number, "u_clamp_wider") == 0;
    bool b = strcmp(res.cand[1].number, "u_clamp_broken_arm") == 0 &&
             strcmp(res.cand[0].number, "u_clamp_wider") == 0;
    assert_true(a || b);
    sr_identify_result_release(&res);
    assert_int_equal(sr_catalog_part_remove(f->cat, "u_clamp_wider", 0, NULL, NULL), SR_OK);
}

/* A shaft (r 10, 100 long) with a deep slit (2 mm wide, 18 deep, 60 long) cut in: the
 * slit's faces are a quarter of the scan's area, so only three quarters of the scan
 * lie on the part; the rest lies inside it. It is the part's scan all the same, and a
 * thicker shaft that could hold the whole scan is not. */
static void identify_counts_fracture_faces_inside_the_part(void **state)
{
    (void)state;
    sr_mesh shaft, thick, slit, scan;
    sr_err err;
    assert_int_equal(sr_shape_cylinder(10, 0, 100, 96, &shaft, &err), SR_OK);
    assert_int_equal(sr_shape_cylinder(13, -5, 105, 96, &thick, &err), SR_OK);
    const double lo[3] = {-8, -1, 20}, hi[3] = {11, 1, 80};
    assert_int_equal(sr_shape_box(lo, hi, &slit, &err), SR_OK);
    if (sr_boolean_difference(&shaft, &slit, &scan, &err) != SR_OK)
        fail_msg("%s", err.msg);
    double m[12];
    const double t[3] = {30, -20, 15};
    rigid(50, 1, 2, -1, t, m);
    sr_mesh_transform(&scan, m);
    sr_identify_scan *sc = NULL;
    assert_int_equal(sr_identify_scan_make(&scan, 0, &sc, &err), SR_OK);
    const sr_mesh *parts[2] = {&shaft, &thick};
    sr_identify_fit fit[2];
    assert_int_equal(sr_identify_fit_parts(sc, parts, 2, fit, &err), SR_OK);
    /* the slit's walls: 2 x 18 x 60, its floor and ends; the scan: the shaft's surface
     * less the slit's mouth, plus those */
    double walls = 2 * 18 * 60 + 2 * 60 + 2 * 2 * 18;
    double share = walls / (sr_mesh_area(&shaft) - 2 * 60 + walls);
    assert_true(share > 0.24);
    if (!(fit[0].coverage < 0.8 && fit[0].coverage > 1 - share - 0.05))
        fail_msg("coverage %.3f (the slit %.3f of the scan)", fit[0].coverage, share);
    if (!(fit[0].coverage + fit[0].inside > 0.97))
        fail_msg("coverage %.3f + inside %.3f", fit[0].coverage, fit[0].inside);
    assert_true(sr_identify_fit_matches(&fit[0]));
    assert_true(fit[0].lacking < 0.05);
    /* the thick shaft could hold the scan inside it, but lacks most of itself */
    assert_false(sr_identify_fit_matches(&fit[1]));
    assert_true(fit[0].score > fit[1].score + 0.3);
    sr_identify_scan_free(sc);
    sr_mesh_release(&shaft);
    sr_mesh_release(&thick);
    sr_mesh_release(&slit);
    sr_mesh_release(&scan);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(descriptor_is_the_same_in_any_pose),
        cmocka_unit_test(descriptor_keeps_scale),
        cmocka_unit_test(descriptor_round_trips_and_refuses_bad_blobs),
        cmocka_unit_test(part_add_stores_the_descriptor),
        cmocka_unit_test(identify_refuses_bad_options_and_scans),
        cmocka_unit_test(identify_names_posed_scans_first_with_a_margin),
        cmocka_unit_test(identify_names_a_noisy_scan),
        cmocka_unit_test(identify_backfills_descriptors_when_writable),
        cmocka_unit_test(identify_says_no_match_without_the_part),
        cmocka_unit_test(identify_two_identical_parts_are_one_design),
        cmocka_unit_test(identify_two_designs_within_the_margin_are_too_close),
        cmocka_unit_test(identify_counts_fracture_faces_inside_the_part),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, group_setup, group_teardown);
}
