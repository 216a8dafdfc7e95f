/*
 * test_cli_identify.c: `symrec identify` and `instance add --part auto` from the
 * command line (issue 19, item 1), golden cases on a small catalogue built through
 * the library: three shared intact parts (../shared/parts; the cases that need them
 * are skipped when it is absent) and the lever scaled by 0.8. Known answers: the
 * lever's posed damaged scan is the lever (table, JSON with its 3 x 4 matrix); the
 * bracket's, whose part is not in the catalogue, is "no match" with exit 0; `--part
 * auto` adds the instance to the lever, and refuses (exit 1, candidates listed, no
 * instance added) the rail's scan once a copy of the rail is in the catalogue, and the
 * bracket's. Every error path: no SCAN, a missing file, an empty catalogue, bad --top
 * and --tol, no catalogue.
 *
 * The cases that register are named identify_* / instance_add_part_auto_* (the
 * Makefile's VALGRIND_SKIP).
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
#include <unistd.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog.h"
#include "support/cli_case.h"
#include "support/json_query.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

#define PARTS_DIR "../shared/parts"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    char empty[TMPDIR_PATH_MAX];
    bool have_parts;
} fixture;

static bool read_part(const char *part, sr_mesh *m)
{
    char path[256];
    snprintf(path, sizeof path, PARTS_DIR "/%s/intact.stl", part);
    return access(path, R_OK) == 0 && sr_mesh_read(path, m, NULL) == SR_OK;
}

static void add(sr_catalog *cat, const char *number, const sr_mesh *m)
{
    sr_err err;
    sr_part_new p = {.number = number, .name = number, .mesh = m};
    if (sr_catalog_part_add(cat, &p, NULL, &err) != SR_OK)
        fail_msg("%s", err.msg);
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "empty.db", f->empty);
    sr_catalog *cat;
    assert_int_equal(sr_catalog_open(f->empty, SR_CATALOG_CREATE, &cat, NULL), SR_OK);
    sr_catalog_close(cat);
    assert_int_equal(sr_catalog_open(f->db, SR_CATALOG_CREATE, &cat, NULL), SR_OK);
    static const char *const parts[] = {"lever_posed", "rail_glide_chipped", "keyed_shaft_dent"};
    f->have_parts = true;
    for (size_t i = 0; i < 3 && f->have_parts; i++) {
        sr_mesh m;
        if (!read_part(parts[i], &m)) {
            f->have_parts = false;
            break;
        }
        add(cat, parts[i], &m);
        if (i == 0) {
            const double xf[12] = {0.8, 0, 0, 0, 0, 0.8, 0, 0, 0, 0, 0.8, 0};
            sr_mesh_transform(&m, xf);
            add(cat, "lever-small", &m);
        }
        sr_mesh_release(&m);
    }
    sr_catalog_close(cat);
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

#define SCAN(part) PARTS_DIR "/" part "/damaged_posed.stl"

static void identify_prints_the_ranking_and_the_match(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "identify", SCAN("lever_posed"));
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "against 4 parts, 4 registered (tolerance ");
    cli_expect_contains(r.out, "rank  part ");
    cli_expect_contains(r.out, "     1  lever_posed ");
    cli_expect_contains(r.out, "\nmatch: part 'lever_posed' (lever_posed), score 0.9");
    cli_result_free(&r);

    CLI_RUN(&r, "--db", f->db, "identify", SCAN("lever_posed"), "--json", "--top", "2", "--tol",
            "0.5");
    cli_expect_ok(&r);
    assert_true(jq_valid(r.out));
    char *s = jq_text(r.out, "$.verdict");
    assert_string_equal(s, "match");
    free(s);
    s = jq_text(r.out, "$.match");
    assert_string_equal(s, "lever_posed");
    free(s);
    assert_int_equal(jq_len(r.out, "$.same_design"), 0);
    assert_true(fabs(jq_num(r.out, "$.tol_mm") - 0.5) < 1e-12);
    assert_true(jq_num(r.out, "$.parts") == 4);
    assert_int_equal(jq_len(r.out, "$.candidates"), 2);
    assert_int_equal(jq_len(r.out, "$.candidates[0].matrix"), 3);
    assert_int_equal(jq_len(r.out, "$.candidates[0].matrix[2]"), 4);
    assert_true(jq_num(r.out, "$.candidates[0].coverage") > 0.85);
    assert_true(jq_num(r.out, "$.candidates[0].score") >
                jq_num(r.out, "$.candidates[1].score") + 0.3);
    /* the matrix is a rotation: its first row has unit length */
    double n = 0;
    for (int k = 0; k < 3; k++) {
        char path[64];
        snprintf(path, sizeof path, "$.candidates[0].matrix[0][%d]", k);
        n += jq_num(r.out, path) * jq_num(r.out, path);
    }
    assert_true(fabs(n - 1) < 1e-9);
    cli_result_free(&r);
}

static void identify_says_no_match_for_a_part_not_in_the_catalogue(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "identify", SCAN("bracket_broken_ear"));
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "\nno match: no part explains the scan (best: '");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "identify", SCAN("bracket_broken_ear"), "--json");
    cli_expect_ok(&r);
    char *s = jq_text(r.out, "$.verdict");
    assert_string_equal(s, "no_match");
    free(s);
    assert_null(jq_text(r.out, "$.match"));
    assert_int_equal(jq_len(r.out, "$.candidates"), 3);
    cli_result_free(&r);
}

static void instance_add_part_auto_picks_the_part(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "auto", "--mesh", SCAN("lever_posed"),
            "--serial", "L-1");
    cli_expect_ok(&r);
    assert_string_equal(r.out, "1\n");
    cli_expect_contains(r.err, "identified as part 'lever_posed' (score 0.9");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "show", "1", "--json");
    cli_expect_ok(&r);
    char *s = jq_text(r.out, "$.part_number");
    assert_non_null(s);
    assert_string_equal(s, "lever_posed");
    free(s);
    cli_result_free(&r);
}

static void instance_add_part_auto_refuses_without_a_clear_part(void **state)
{
    fixture *f = *state;
    if (!f->have_parts)
        skip();
    /* the bracket is not in the catalogue */
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "auto", "--mesh",
            SCAN("bracket_broken_ear"));
    assert_int_equal(r.code, 1);
    cli_expect_contains(r.out, "no match:");
    cli_expect_contains(r.err, "symrec: error: cannot pick the part of '");
    cli_expect_contains(r.err, "no part in the catalogue explains it");
    cli_result_free(&r);
    /* a second rail under another number: one design under two numbers, which the
     * user picks */
    sr_catalog *cat;
    assert_int_equal(sr_catalog_open(f->db, 0, &cat, NULL), SR_OK);
    sr_mesh m;
    assert_true(read_part("rail_glide_chipped", &m));
    add(cat, "rail-copy", &m);
    sr_mesh_release(&m);
    sr_catalog_close(cat);
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "auto", "--mesh",
            SCAN("rail_glide_chipped"));
    assert_int_equal(r.code, 1);
    cli_expect_contains(r.out, "match: part '");
    cli_expect_contains(r.out, "  the same design as part '");
    cli_expect_contains(r.out, " rail-copy ");
    cli_expect_contains(r.out, " rail_glide_chipped ");
    cli_expect_contains(r.err, "it is one design filed under 2 part numbers ('");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "identify", SCAN("rail_glide_chipped"), "--json");
    cli_expect_ok(&r);
    char *s = jq_text(r.out, "$.verdict");
    assert_string_equal(s, "match");
    free(s);
    assert_int_equal(jq_len(r.out, "$.same_design"), 1);
    cli_result_free(&r);
    /* nothing was added */
    CLI_RUN(&r, "--db", f->db, "instance", "list", "--json");
    cli_expect_ok(&r);
    assert_int_equal(jq_len(r.out, "$"), 0);
    cli_result_free(&r);
}

static void identify_errors_are_one_line(void **state)
{
    fixture *f = *state;
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "identify", "no-such-scan.stl");
    cli_expect_error(&r, "no-such-scan.stl");
    cli_result_free(&r);
    if (f->have_parts) {
        CLI_RUN(&r, "--db", f->empty, "identify", SCAN("lever_posed"));
        cli_expect_error(&r, "no part with an intact mesh in '");
        cli_result_free(&r);
    }
    char missing[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "none.db", missing);
    CLI_RUN(&r, "--db", missing, "identify", "x.stl");
    cli_expect_error(&r, "no catalogue '");
    cli_result_free(&r);
    assert_false(cli_path_exists(missing));
}

static void identify_usage_errors_exit_2(void **state)
{
    fixture *f = *state;
    static const char *const bad[][3] = {
        {"--top", "0", "bad --top '0'"},     {"--top", "21", "bad --top '21'"},
        {"--top", "two", "bad --top 'two'"}, {"--tol", "0", "bad --tol '0'"},
        {"--tol", "-1", "bad --tol '-1'"},   {"--frobnicate", NULL, "--frobnicate"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        cli_result r;
        if (bad[i][1])
            CLI_RUN(&r, "--db", f->db, "identify", "x.stl", bad[i][0], bad[i][1]);
        else
            CLI_RUN(&r, "--db", f->db, "identify", "x.stl", bad[i][0]);
        assert_int_equal(r.code, 2);
        assert_string_equal(r.out, "");
        cli_expect_contains(r.err, "symrec: usage: ");
        cli_expect_contains(r.err, bad[i][2]);
        cli_result_free(&r);
    }
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "identify");
    assert_int_equal(r.code, 2);
    cli_expect_contains(r.err, "symrec: usage: ");
    cli_result_free(&r);
    CLI_RUN(&r, "identify", "--help");
    cli_expect_ok(&r);
    cli_expect_contains(
        r.out, "usage: symrec [--db FILE] identify SCAN [--top K] [--tol MM] [--units U] [--json]");
    cli_expect_contains(r.out, "Exit 0 with an answer");
    cli_result_free(&r);
    CLI_RUN(&r, "instance", "add", "--help");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "--part P|auto");
    cli_result_free(&r);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(identify_prints_the_ranking_and_the_match),
        T(identify_says_no_match_for_a_part_not_in_the_catalogue),
        T(instance_add_part_auto_picks_the_part),
        T(instance_add_part_auto_refuses_without_a_clear_part),
        T(identify_errors_are_one_line),
        T(identify_usage_errors_exit_2),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
