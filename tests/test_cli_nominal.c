/*
 * test_cli_nominal.c: `reconstruct`'s second opinion from the part's intact mesh
 * (cli/nominal_out.c, src/nominal.c) through the CLI, on the shared gouged bushing
 * (../shared/parts/bushing_gouged: truth.json's missing volume 2415.641 mm³; every
 * case is skipped when the folder is absent). One catalogue per test group: part BG
 * with the bushing's intact mesh and instance 1 its posed scan; part GEAR with the spur
 * gear's intact mesh and instance 2 the bushing's scan filed under it (the wrong
 * intact model). Known answers: with --reference nominal the nominal's missing volume
 * within 2 % of truth as the patches' volume, the intact volume restored, the record
 * read back by `run show --json` to the bit; the wrong model flagged with a large
 * disagreement and refused as the reference; "no nominal" for a mesh file and
 * --no-nominal; the usage errors. Where the symmetry's sections do not matter the
 * reconstruction runs coarse (paper method, 40 layers, 48 sectors) to save time.
 * These cases run reconstructions: they stay out of `make valgrind` (VALGRIND_SKIP).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <cmocka.h>

#include "support/json_query.h"
#include "support/run_cmd.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

#define PARTS "../shared/parts"
#define TRUTH_MM3 2415.641

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
} fixture;

typedef struct result {
    int code;
    char *out, *err;
} result;

static void run(result *r, const char *const argv[])
{
    r->code = sr_test_run(argv, NULL, &r->out, &r->err);
    assert_int_not_equal(r->code, -1);
}

static void result_free(result *r)
{
    free(r->out);
    free(r->err);
}

/* Runs a setting-up command, which must succeed. */
static void must(const char *const argv[])
{
    char *err = NULL;
    int code = sr_test_run_native(argv, NULL, NULL, &err);
    if (code != 0)
        fail_msg("%s %s failed (%d): %s", argv[3], argv[4] ? argv[4] : "", code, err);
    free(err);
}

static int setup(void **state)
{
    struct stat sb;
    if (stat(PARTS "/bushing_gouged/intact.stl", &sb) != 0) {
        *state = NULL;
        return 0;
    }
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    const char *bin = sr_test_bin();
    must((const char *[]){bin, "--db", f->db, "catalog", "init", NULL});
    must((const char *[]){bin, "-q", "--db", f->db, "part", "add", "--number", "BG", "--name",
                          "bushing", "--material", "C45", "--mesh",
                          PARTS "/bushing_gouged/intact.stl", "--symmetry", "axial", NULL});
    must((const char *[]){bin, "-q", "--db", f->db, "part", "add", "--number", "GEAR", "--name",
                          "gear", "--material", "C45", "--mesh",
                          PARTS "/spur_gear_broken_tooth/intact.stl", "--symmetry", "axial", NULL});
    must((const char *[]){bin, "-q", "--db", f->db, "instance", "add", "--part", "BG", "--mesh",
                          PARTS "/bushing_gouged/damaged_posed.stl", NULL});
    must((const char *[]){bin, "-q", "--db", f->db, "instance", "add", "--part", "GEAR", "--mesh",
                          PARTS "/bushing_gouged/damaged_posed.stl", NULL});
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    if (f) {
        tmpdir_remove(&f->dir);
        free(f);
    }
    return 0;
}

#define NEED_PARTS(f)                                                                              \
    do {                                                                                           \
        if (!(f))                                                                                  \
            skip();                                                                                \
    } while (0)

/* The quick run options for the cases where the symmetry's sections do not matter. */
#define FAST "--method", "paper", "--layers", "40", "--sectors", "48"

static void reference_nominal_restores_and_records_it(void **state)
{
    fixture *f = *state;
    NEED_PARTS(f);
    const char *bin = sr_test_bin();
    char out[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "out", out);
    result r;
    run(&r, (const char *[]){bin, "--db", f->db, "reconstruct", "1", "--reference", "nominal",
                             "--out", out, "--json", NULL});
    assert_int_equal(r.code, 0);
    double nominal = jq_num(r.out, "$.nominal.nominal_mm3");
    if (!(fabs(nominal - TRUTH_MM3) <= 0.02 * TRUTH_MM3))
        fail_msg("nominal %.3f mm³, truth %.3f", nominal, TRUTH_MM3);
    char *ref = jq_text(r.out, "$.nominal.reference");
    assert_string_equal(ref, "nominal");
    free(ref);
    assert_true(jq_num(r.out, "$.nominal.coverage") > 0.9);
    char *poor = jq_text(r.out, "$.nominal.poor");
    assert_string_equal(poor, "0");
    free(poor);
    /* the patch is the pieces' meshes: measured by the exact difference */
    char *method = jq_text(r.out, "$.nominal.method");
    assert_string_equal(method, "exact");
    free(method);
    char *whole = jq_text(r.out, "$.nominal"); /* no cells: cell_mm there, null */
    assert_non_null(strstr(whole, "\"cell_mm\":null"));
    free(whole);
    /* the symmetry's section beside it, as the check */
    assert_int_equal(jq_len(r.out, "$.sections"), 1);
    assert_int_equal(jq_len(r.out, "$.nominal.sections"), 1);
    assert_true(jq_num(r.out, "$.nominal.sections[0].pieces") == 1);
    assert_true(fabs(jq_num(r.out, "$.nominal.sections[0].diff_pct")) < 2);
    assert_true(jq_num(r.out, "$.nominal.sections[0].deviation_mean_mm") < 0.1);
    /* the patches are the nominal's, the restored part the intact one registered */
    assert_true(jq_num(r.out, "$.patch_volume_mm3") == nominal);
    assert_true(fabs(jq_num(r.out, "$.restored_volume_mm3") - 75213.025) < 0.01);
    char path[TMPDIR_PATH_MAX + 32];
    struct stat sb;
    snprintf(path, sizeof path, "%s/patches.stl", out);
    assert_int_equal(stat(path, &sb), 0);
    char *sections = jq_text(r.out, "$.nominal.sections");
    char *id = jq_text(r.out, "$.run_id");
    result_free(&r);

    /* the record: the same figures back */
    run(&r, (const char *[]){bin, "--db", f->db, "run", "show", id, "--json", NULL});
    assert_int_equal(r.code, 0);
    assert_true(jq_num(r.out, "$.nominal.nominal_mm3") == nominal);
    char *back = jq_text(r.out, "$.nominal.sections");
    assert_string_equal(back, sections);
    free(back);
    back = jq_text(r.out, "$.nominal.method");
    assert_string_equal(back, "exact");
    free(back);
    result_free(&r);
    run(&r, (const char *[]){bin, "--db", f->db, "run", "show", id, NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "measured by one exact difference"));
    assert_non_null(strstr(r.out, "symmetry vs nominal"));
    assert_non_null(strstr(r.out, "reference nominal"));
    result_free(&r);
    free(sections);
    free(id);
}

static void a_wrong_intact_model_is_flagged_and_refused(void **state)
{
    fixture *f = *state;
    NEED_PARTS(f);
    const char *bin = sr_test_bin();
    result r;
    /* the run with the symmetry as the reference flags it ... */
    run(&r, (const char *[]){bin, "--db", f->db, "reconstruct", "2", FAST, "--no-record", "--json",
                             NULL});
    assert_int_equal(r.code, 0);
    char *ref = jq_text(r.out, "$.nominal.reference");
    assert_string_equal(ref, "symmetry");
    free(ref);
    char *poor = jq_text(r.out, "$.nominal.poor");
    assert_string_equal(poor, "1");
    free(poor);
    char *note = jq_text(r.out, "$.nominal.note");
    assert_non_null(strstr(note, "the nominal model does not fit this scan"));
    free(note);
    /* ... with a large disagreement, not a silently small one */
    assert_true(fabs(jq_num(r.out, "$.nominal.diff_pct")) > 50);
    /* measured by cells (the default when the nominal is only the check), and says so */
    char *method = jq_text(r.out, "$.nominal.method");
    assert_string_equal(method, "cells");
    free(method);
    double cell = jq_num(r.out, "$.nominal.cell_mm");
    assert_true(cell > 0 && cell < 5);
    result_free(&r);
    /* and it cannot be the reference */
    run(&r, (const char *[]){bin, "--db", f->db, "reconstruct", "2", FAST, "--no-record",
                             "--reference", "nominal", NULL});
    assert_int_equal(r.code, 1);
    assert_string_equal(r.out, "");
    const char *line = strstr(r.err, "symrec: error: --reference nominal: the nominal model "
                                     "does not fit this scan");
    assert_non_null(line);
    assert_null(strchr(strchr(line, '\n') + 1, '\n')); /* one line */
    result_free(&r);
}

static void without_a_part_or_with_no_nominal_there_is_none(void **state)
{
    fixture *f = *state;
    NEED_PARTS(f);
    const char *bin = sr_test_bin();
    result r;
    run(&r,
        (const char *[]){bin, "reconstruct", "--mesh", PARTS "/bushing_gouged/damaged_posed.stl",
                         "--symmetry", "axial", FAST, NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "  nominal:    no nominal (a mesh file has no part)\n"));
    result_free(&r);
    run(&r, (const char *[]){bin, "--db", f->db, "reconstruct", "1", FAST, "--no-record",
                             "--no-nominal", "--json", NULL});
    assert_int_equal(r.code, 0);
    assert_null(jq_text(r.out, "$.nominal"));
    assert_true(jq_num(r.out, "$.patch_volume_mm3") > 0);
    result_free(&r);
}

static void bad_reference_options_are_usage_errors(void **state)
{
    fixture *f = *state;
    NEED_PARTS(f);
    const char *bin = sr_test_bin();
    result r;
    run(&r, (const char *[]){bin, "--db", f->db, "reconstruct", "1", "--reference", "cad", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "symrec: usage: bad --reference 'cad': expected symmetry or "
                                  "nominal"));
    result_free(&r);
    run(&r,
        (const char *[]){bin, "reconstruct", "--mesh", PARTS "/bushing_gouged/damaged_posed.stl",
                         "--symmetry", "axial", "--reference", "nominal", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "--reference nominal needs an INSTANCE"));
    result_free(&r);
    run(&r, (const char *[]){bin, "--db", f->db, "reconstruct", "1", "--reference", "nominal",
                             "--no-nominal", NULL});
    assert_int_equal(r.code, 2);
    result_free(&r);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(reference_nominal_restores_and_records_it),
        cmocka_unit_test(a_wrong_intact_model_is_flagged_and_refused),
        cmocka_unit_test(without_a_part_or_with_no_nominal_there_is_none),
        cmocka_unit_test(bad_reference_options_are_usage_errors),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, setup, teardown);
}
