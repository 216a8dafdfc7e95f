/*
 * test_cli_symmetry.c: `symrec symmetry` and `reconstruct --symmetry auto` as a user
 * runs them, on a hexagonal prism (axial, 6-fold: its mirror planes too, but the
 * higher symmetry is proposed): the proposal printed and in --json; an instance
 * reconstructed with auto records the proposal, which `run show` (+ --json) prints,
 * and a kind given overrides the fit and records none; every usage and error path.
 * The reconstruction cases are in the Makefile's VALGRIND_SKIP (they run under ASan).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "mesh/shapes.h"
#include "support/cli_case.h"
#include "support/json_query.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    char hex[TMPDIR_PATH_MAX];
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "hex.stl", f->hex);
    double xy[12];
    for (int k = 0; k < 6; k++) {
        xy[2 * k] = 12 * cos(M_PI / 3 * k + 0.2);
        xy[2 * k + 1] = 12 * sin(M_PI / 3 * k + 0.2);
    }
    sr_mesh m = {0};
    assert_int_equal(sr_shape_prism(xy, 6, 0, 10, &m, NULL), SR_OK);
    assert_int_equal(sr_mesh_write(f->hex, &m, NULL, NULL), SR_OK);
    sr_mesh_release(&m);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    tmpdir_remove(&f->dir);
    free(f);
    return 0;
}

static void expect_text(const char *json, const char *path, const char *want)
{
    char *t = jq_text(json, path);
    if (!t || strcmp(t, want) != 0)
        fail_msg("%s: '%s', want '%s' in %s", path, t ? t : "(null)", want, json);
    free(t);
}

static void symmetry_of_a_mesh_file_is_proposed(void **state)
{
    const fixture *f = *state;
    cli_result r;
    CLI_RUN(&r, "symmetry", "--mesh", f->hex, "--json");
    cli_expect_ok(&r);
    assert_true(jq_valid(r.out));
    expect_text(r.out, "$.symmetry_fit.proposal.kind", "axial");
    assert_int_equal((int)jq_num(r.out, "$.symmetry_fit.proposal.order"), 6);
    expect_text(r.out, "$.symmetry_fit.ambiguous", "0");
    assert_true(jq_num(r.out, "$.symmetry_fit.consistency.axial_nfold") > 0.95);
    assert_true(jq_num(r.out, "$.symmetry_fit.consistency.axial") < 0.8);
    assert_true(jq_num(r.out, "$.symmetry_fit.confidence") > 0.5);
    assert_int_equal((int)jq_num(r.out, "$.symmetry_fit.samples"), 3000);
    assert_true(jq_num(r.out, "$.symmetry_fit.tolerance_mm") > 0);
    cli_result_free(&r);
    CLI_RUN(&r, "symmetry", "--mesh", f->hex);
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "  proposal:    axial, 6-fold\n");
    cli_expect_contains(r.out, "    axial, 6-fold      1.000\n");
    cli_expect_contains(r.err, "fitting the symmetry of");
    cli_result_free(&r);
}

static void symmetry_refuses_bad_arguments(void **state)
{
    const fixture *f = *state;
    cli_result r;
    CLI_RUN(&r, "symmetry");
    assert_int_equal(r.code, 2);
    cli_expect_contains(r.err, "symrec: usage: 'symmetry' needs an INSTANCE id or --mesh FILE");
    cli_result_free(&r);
    CLI_RUN(&r, "symmetry", "1", "--mesh", f->hex);
    assert_int_equal(r.code, 2);
    cli_result_free(&r);
    CLI_RUN(&r, "symmetry", "--mesh", f->hex, "--order", "6");
    assert_int_equal(r.code, 2);
    cli_result_free(&r);
    CLI_RUN(&r, "symmetry", "x1");
    assert_int_equal(r.code, 2);
    cli_result_free(&r);
    char missing[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "missing.stl", missing);
    CLI_RUN(&r, "symmetry", "--mesh", missing);
    cli_expect_error(&r, "missing.stl");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "catalog", "init");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "symmetry", "7");
    cli_expect_error(&r, "7");
    cli_result_free(&r);
    CLI_RUN(&r, "symmetry", "--help");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "usage: symrec [--db FILE] symmetry (INSTANCE | --mesh FILE [--units U])");
    cli_result_free(&r);
    /* auto takes no order or shift */
    CLI_RUN(&r, "reconstruct", "--mesh", f->hex, "--symmetry", "auto", "--order", "6");
    assert_int_equal(r.code, 2);
    cli_expect_contains(r.err, "--order and --shift need --symmetry axial|glide, not auto");
    cli_result_free(&r);
    CLI_RUN(&r, "reconstruct", "--mesh", f->hex, "--symmetry", "round");
    assert_int_equal(r.code, 2);
    cli_result_free(&r);
}

static void reconstruct_symmetry_auto_records_the_proposal(void **state)
{
    const fixture *f = *state;
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "catalog", "init");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "H1", "--name", "hex bar", "--material",
            "C45", "--mesh", f->hex);
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "H1", "--mesh", f->hex);
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "reconstruct", "1", "--symmetry", "auto", "--layers", "20",
            "--sectors", "120", "--no-union", "--json");
    cli_expect_ok(&r);
    expect_text(r.out, "$.symmetry.kind", "axial");
    assert_int_equal((int)jq_num(r.out, "$.symmetry.order"), 6);
    assert_int_equal((int)jq_num(r.out, "$.symmetry_fit.proposal.order"), 6);
    assert_int_equal((int)jq_num(r.out, "$.run_id"), 1);
    cli_expect_contains(r.err, "symrec: symmetry proposed: axial, 6-fold, confidence ");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "run", "show", "1", "--json");
    cli_expect_ok(&r);
    expect_text(r.out, "$.symmetry_fit.proposal.kind", "axial");
    assert_int_equal((int)jq_num(r.out, "$.symmetry_fit.order_found"), 6);
    cli_expect_contains(r.out, "\"summary\":\"axial, 6-fold, confidence ");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "run", "show", "1");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "  symmetry:    axial, 6-fold\n"
                               "  proposed:    by --symmetry auto: axial, 6-fold, confidence ");
    cli_result_free(&r);
    /* a kind given is used as given: no fit, nothing proposed */
    CLI_RUN(&r, "--db", f->db, "reconstruct", "1", "--symmetry", "mirror", "--layers", "20",
            "--sectors", "120", "--no-union", "--json");
    cli_expect_ok(&r);
    expect_text(r.out, "$.symmetry.kind", "mirror");
    assert_null(jq_text(r.out, "$.symmetry_fit"));
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "run", "show", "2", "--json");
    cli_expect_ok(&r);
    assert_null(jq_text(r.out, "$.symmetry_fit"));
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "run", "show", "2");
    cli_expect_ok(&r);
    assert_null(strstr(r.out, "proposed:"));
    cli_result_free(&r);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(symmetry_of_a_mesh_file_is_proposed),
        T(symmetry_refuses_bad_arguments),
        T(reconstruct_symmetry_auto_records_the_proposal),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
