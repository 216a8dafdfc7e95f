/*
 * test_cli_inspect.c: `symrec inspect` (cli/cmd_inspect.c) on the shared gouged bushing
 * (../shared/parts/bushing_gouged; skipped when the folder is absent): one coarse
 * reconstruction of its damaged mesh, then the damaged mesh itself inspected as the
 * "repaired" part (the gouge left: rework, the whole patch under-filled, within 5 %)
 * and the restored mesh (a perfect repair: pass), each recorded; the run's outcome
 * follows the latest (`run show --json`, `history --verdict`, `history --summary`),
 * the allowance comes from the run's advice (ded's 0.8 mm); and the usage and
 * refusal lines. It runs a reconstruction: out of `make valgrind` (VALGRIND_SKIP).
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

#include "support/assert_near.h"
#include "support/cli_case.h"
#include "support/json_query.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

#define PARTS "../shared/parts/bushing_gouged"

static void inspect_records_the_verdict_and_the_run_follows_it(void **state)
{
    (void)state;
    struct stat sb;
    if (stat(PARTS "/damaged.stl", &sb) != 0)
        skip();
    tmpdir dir;
    assert_int_equal(tmpdir_make(&dir), 0);
    char db[TMPDIR_PATH_MAX], out[TMPDIR_PATH_MAX], restored[TMPDIR_PATH_MAX + 16];
    tmpdir_join(&dir, "cat.db", db);
    tmpdir_join(&dir, "out", out);
    snprintf(restored, sizeof restored, "%s/restored.stl", out);
    cli_result r;
    CLI_RUN(&r, "-q", "--db", db, "catalog", "init");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "-q", "--db", db, "part", "add", "--number", "BG", "--name", "bushing",
            "--material", "C45", "--mesh", PARTS "/intact.stl", "--symmetry", "axial");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "-q", "--db", db, "instance", "add", "--part", "BG", "--mesh",
            PARTS "/damaged.stl");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "-q", "--db", db, "reconstruct", "1", "--symmetry", "axial", "--no-nominal",
            "--out", out, "--json");
    cli_expect_ok(&r);
    double missing = jq_num(r.out, "$.sections[0].volume_mm3");
    cli_result_free(&r);

    /* the gouge left as it was: rework, the whole section under-filled */
    char glb[TMPDIR_PATH_MAX + 16];
    snprintf(glb, sizeof glb, "%s/dev.glb", out);
    CLI_RUN(&r, "-q", "--db", db, "inspect", "1", "--mesh", PARTS "/damaged.stl", "--glb", glb,
            "--json");
    cli_expect_ok(&r);
    char *v = jq_text(r.out, "$.verdict");
    assert_string_equal(v, "rework");
    free(v);
    double under = jq_num(r.out, "$.sections[0].underfill_mm3");
    if (!(fabs(under - missing) <= 0.05 * missing))
        fail_msg("under-fill %.3f mm³, the section's %.3f", under, missing);
    assert_true(jq_num(r.out, "$.sections[0].underfill_depth_mm") > 4);
    assert_true(fabs(jq_num(r.out, "$.allowance_mm") - 0.8) < 1e-12);
    assert_int_equal((int)jq_num(r.out, "$.inspection"), 1);
    cli_result_free(&r);
    /* the GLB: the scan with one float RGB colour per vertex as COLOR_0 */
    FILE *f = fopen(glb, "rb");
    assert_non_null(f);
    unsigned char head[20];
    assert_int_equal(fread(head, 1, 20, f), 20);
    size_t jlen =
        head[12] | (size_t)head[13] << 8 | (size_t)head[14] << 16 | (size_t)head[15] << 24;
    char *gj = calloc(jlen + 1, 1);
    assert_int_equal(fread(gj, 1, jlen, f), jlen);
    fclose(f);
    assert_near(jq_num(gj, "$.meshes[0].primitives[0].attributes.COLOR_0"), 2, 0);
    assert_near(jq_num(gj, "$.accessors[2].count"), jq_num(gj, "$.accessors[0].count"), 0);
    v = jq_text(gj, "$.accessors[2].type");
    assert_string_equal(v, "VEC3");
    free(v);
    free(gj);
    CLI_RUN(&r, "--db", db, "history", "--verdict", "rework");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, " rework\n");
    cli_result_free(&r);
    /* the report shows the latest inspection, with the scan's deviation colours */
    char html[TMPDIR_PATH_MAX + 16];
    snprintf(html, sizeof html, "%s/r.html", out);
    CLI_RUN(&r, "--db", db, "report", "1", "--out", html, "--json");
    cli_expect_ok(&r);
    assert_int_equal((int)jq_num(r.out, "$.inspection"), 1);
    cli_result_free(&r);

    /* the restored mesh: a perfect repair passes, and is the run's outcome now */
    CLI_RUN(&r, "-q", "--db", db, "inspect", "1", "--mesh", restored, "--tolerance", "0.05");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "inspection 2 of run 1: pass\n");
    cli_expect_contains(r.out, "allowance 0.8 mm (the advice's, ded), tolerance 0.05 mm");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "run", "show", "1", "--json");
    cli_expect_ok(&r);
    v = jq_text(r.out, "$.inspection.verdict");
    assert_string_equal(v, "pass");
    free(v);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "history", "--verdict", "rework");
    cli_expect_ok(&r);
    assert_string_equal(r.out, "no runs\n");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "history", "--summary");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "inspected: 1 pass, 0 machine, 0 rework");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "report", "1", "--out", html);
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "inspection 2 (pass) shown with the scan's deviation colours\n");
    cli_result_free(&r);

    /* refusals: exit 2 for usage, 1 for what the catalogue or the file refuses */
    CLI_RUN(&r, "--db", db, "inspect", "1");
    assert_int_equal(r.code, 2);
    assert_string_equal(r.err,
                        "symrec: usage: inspect needs --mesh SCAN (the part after repair)\n");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "inspect", "1", "--mesh", restored, "--tolerance", "-1");
    assert_int_equal(r.code, 2);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "inspect", "9", "--mesh", restored);
    cli_expect_error(&r, "no run 9 in the catalogue");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", db, "history", "--verdict", "fail");
    assert_int_equal(r.code, 2);
    assert_string_equal(r.err,
                        "symrec: usage: bad --verdict 'fail': expected pass, machine or rework\n");
    cli_result_free(&r);
    tmpdir_remove(&dir);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(inspect_records_the_verdict_and_the_run_follows_it),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("test_cli_inspect", tests, n, NULL, NULL);
}
