/*
 * test_cli_units.c: golden tests of units on the command line (issue 18, items 3 and
 * 9): --units on the commands that read a mesh file (a 1 in cube read in inches is
 * 16387.064 mm³; a bad unit is a usage error naming the flag), the one-line warning
 * when a file's size looks like another unit (and none for a mm part, none with
 * --quiet), the unit stored with each mesh and shown by part/instance show, a glTF
 * written by convert that reads back in mm, and --json on catalog init (created,
 * unchanged, migrated from schema 4) and demo.
 *
 * The binary is $SYMREC_BIN (default build/debug/symrec), run under $SYMREC_WRAP when
 * set (tests/support/cli_case.h); run from the repository root.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_int.h"
#include "catalog/sql_embedded.h"
#include "mesh/shapes.h"
#include "support/cli_case.h"
#include "support/json_query.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    char inch[TMPDIR_PATH_MAX]; /* a cube of side 1: 1 in, or 1 mm as read by default */
    char mm[TMPDIR_PATH_MAX];   /* a 40 x 30 x 20 box, a plausible mm part */
} fixture;

static void write_box(const char *path, double x, double y, double z)
{
    sr_mesh m = {0};
    const double lo[3] = {0, 0, 0}, hi[3] = {x, y, z};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    assert_int_equal(sr_mesh_write(path, &m, NULL, NULL), SR_OK);
    sr_mesh_release(&m);
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "inch.stl", f->inch);
    tmpdir_join(&f->dir, "box.stl", f->mm);
    write_box(f->inch, 1, 1, 1);
    write_box(f->mm, 40, 30, 20);
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

/* stdout of a command that must succeed with nothing on stderr (the caller frees). */
static char *out_of(const char *const *words)
{
    cli_result r;
    cli_case_run(&r, words);
    cli_expect_ok(&r);
    assert_string_equal(r.err, "");
    char *out = r.out;
    r.out = NULL;
    cli_result_free(&r);
    return out;
}

#define OUT_OF(...) out_of((const char *const[]){__VA_ARGS__, NULL})

static void expect_text(const char *json, const char *path, const char *want)
{
    char *got = jq_text(json, path);
    if (!got || strcmp(got, want) != 0)
        fail_msg("%s is '%s', expected '%s' in: %s", path, got ? got : "(none)", want, json);
    free(got);
}

static void expect_num(const char *json, const char *path, double want, double tol)
{
    double got = jq_num(json, path);
    if (!(fabs(got - want) <= tol))
        fail_msg("%s is %.17g, expected %.17g in: %s", path, got, want, json);
}

/* ---- reading in a unit ---- */

static void check_reads_an_inch_cube_in_inches_as_mm(void **state)
{
    const fixture *f = *state;
    char *out = OUT_OF("check", f->inch, "--units", "in", "--json");
    expect_text(out, "$.units", "in");
    expect_num(out, "$.volume", 16387.064, 1e-8);
    expect_num(out, "$.bbox_max[2]", 25.4, 0);
    free(out);
    /* text: the unit named, the numbers in mm */
    out = OUT_OF("check", f->inch, "--units=in");
    cli_expect_contains(out, "  read in             in (numbers below in mm)\n");
    cli_expect_contains(out, "  volume              16387.1\n");
    free(out);
    /* a cm file, by convert: read in cm, written in mm */
    char cm[TMPDIR_PATH_MAX], back[TMPDIR_PATH_MAX];
    write_box(tmpdir_join(&f->dir, "cm.obj", cm), 2, 3, 4);
    free(OUT_OF("convert", cm, tmpdir_join(&f->dir, "cm_in_mm.stl", back), "--units", "cm"));
    out = OUT_OF("check", back, "--json");
    expect_num(out, "$.volume", 24000, 1e-6);
    free(out);
}

static void the_size_warning_fires_on_an_inch_cube_read_as_mm(void **state)
{
    const fixture *f = *state;
    cli_result r;
    CLI_RUN(&r, "check", f->inch, "--json");
    cli_expect_ok(&r);
    char want[TMPDIR_PATH_MAX + 200];
    snprintf(want, sizeof want,
             "symrec: warning: '%s' is 1 mm across (largest side, read in mm): small for a "
             "machined part; if it was drawn in in, give --units in\n",
             f->inch);
    assert_string_equal(r.err, want);
    expect_num(r.out, "$.volume", 1, 1e-12); /* read as asked all the same */
    cli_result_free(&r);
    /* --quiet: no warning */
    CLI_RUN(&r, "--quiet", "check", f->inch);
    cli_expect_ok(&r);
    assert_string_equal(r.err, "");
    cli_result_free(&r);
    /* a mm part: none; nor the inch cube read in inches */
    free(OUT_OF("check", f->mm));
    free(OUT_OF("check", f->inch, "--units", "in"));
    /* a part drawn in mm, read as metres: 40 m */
    CLI_RUN(&r, "check", f->mm, "--units", "m");
    cli_expect_ok(&r);
    cli_expect_contains(r.err, "is 40 m across (largest side, read in m): large for a machined "
                               "part; if it was drawn in mm, give --units mm\n");
    cli_result_free(&r);
}

static void a_bad_unit_is_a_usage_error_naming_the_flag(void **state)
{
    const fixture *f = *state;
    char glb[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "x.glb", glb);
    const char *const cases[][12] = {
        {"check", f->mm, "--units", "furlong", NULL},
        {"convert", f->mm, glb, "--units", "furlong", NULL},
        {"--db", f->db, "part", "add", "--number", "P", "--name", "p", "--material", "C45",
         "--mesh", NULL},
        {"--db", f->db, "instance", "add", "--part", "P", "--mesh", f->mm, "--units", "furlong",
         NULL},
        {"--db", f->db, "reconstruct", "--mesh", f->mm, "--symmetry", "mirror", "--units",
         "furlong", NULL},
        {"--db", f->db, "compare", f->mm, f->inch, "--units", "furlong", NULL},
        {"--db", f->db, "identify", f->mm, "--units", "furlong", NULL},
        {"--db", f->db, "symmetry", "--mesh", f->mm, "--units", "furlong", NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *words[16];
        size_t n = 0;
        for (; cases[i][n]; n++)
            words[n] = cases[i][n];
        if (i == 2) { /* part add: the mesh and the unit after --mesh */
            words[n++] = f->mm;
            words[n++] = "--units";
            words[n++] = "furlong";
        }
        words[n] = NULL;
        cli_result r;
        cli_case_run(&r, words);
        if (r.code != 2)
            fail_msg("case %zu: exit %d, stderr %s", i, r.code, r.err);
        assert_string_equal(r.out, "");
        assert_string_equal(r.err,
                            "symrec: usage: bad --units 'furlong': expected mm, cm, m or in\n");
        cli_result_free(&r);
    }
    assert_false(cli_path_exists(f->db)); /* refused before the catalogue was opened */
    assert_false(cli_path_exists(glb));
    /* --units names a file's unit: not with a catalogue instance */
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "reconstruct", "1", "--symmetry", "mirror", "--units", "in");
    assert_int_equal(r.code, 2);
    cli_expect_contains(r.err, "--units applies to --mesh FILE only");
    cli_result_free(&r);
}

/* ---- the unit stored with the mesh ---- */

static void part_and_instance_keep_the_unit_read_in(void **state)
{
    const fixture *f = *state;
    free(OUT_OF("--db", f->db, "catalog", "init"));
    char *out =
        OUT_OF("--db", f->db, "--quiet", "part", "add", "--number", "CUBE-1", "--name", "inch cube",
               "--material", "C45", "--mesh", f->inch, "--units", "in", "--json");
    expect_text(out, "$.source_unit", "in");
    expect_num(out, "$.volume_mm3", 16387.064, 1e-8);
    free(out);
    out = OUT_OF("--db", f->db, "part", "show", "CUBE-1", "--json");
    expect_text(out, "$.source_unit", "in");
    expect_num(out, "$.bbox_max_mm[0]", 25.4, 0);
    free(out);
    out = OUT_OF("--db", f->db, "part", "show", "CUBE-1");
    cli_expect_contains(out, "  mesh:       8 vertices, 12 triangles, read in in\n");
    free(out);

    /* an instance from a metre glTF (convert wrote it; read by default in metres) and
     * one from a cm STL */
    char glb[TMPDIR_PATH_MAX], cm[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "scan.glb", glb);
    free(OUT_OF("convert", f->mm, glb));
    write_box(tmpdir_join(&f->dir, "scan_cm.stl", cm), 2.54, 2.54, 2.54);
    out =
        OUT_OF("--db", f->db, "-q", "instance", "add", "--part", "CUBE-1", "--mesh", glb, "--json");
    expect_text(out, "$.source_unit", "m");
    expect_num(out, "$.volume_mm3", 24000, 1e-6); /* 40 x 30 x 20 mm */
    free(out);
    out = OUT_OF("--db", f->db, "--quiet", "instance", "add", "--part", "CUBE-1", "--mesh", cm,
                 "--units", "cm", "--json");
    expect_text(out, "$.source_unit", "cm");
    free(out);
    out = OUT_OF("--db", f->db, "instance", "show", "2", "--json");
    expect_text(out, "$.source_unit", "cm");
    expect_num(out, "$.volume_mm3", 16387.064, 1e-2); /* 2.54 as float32 */
    free(out);
    out = OUT_OF("--db", f->db, "instance", "show", "1");
    cli_expect_contains(out, "  mesh:       8 vertices, 12 triangles, read in m\n");
    free(out);
}

/* ---- glTF out and back ---- */

static void convert_writes_a_glb_in_metres_that_reads_back_in_mm(void **state)
{
    const fixture *f = *state;
    char glb[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "box.glb", glb);
    char *out = OUT_OF("convert", f->mm, glb, "--json");
    expect_text(out, "$.units", "mm");
    free(out);
    out = OUT_OF("check", glb, "--json");
    expect_text(out, "$.units", "m");
    expect_num(out, "$.bbox_max[0]", 40, 0);
    expect_num(out, "$.bbox_max[1]", 30, 0);
    expect_num(out, "$.bbox_max[2]", 20, 0); /* Z up again, not -Y */
    expect_num(out, "$.bbox_min[1]", 0, 0);
    expect_num(out, "$.volume", 24000, 0);
    free(out);
}

static void convert_writes_another_unit_when_asked(void **state)
{
    const fixture *f = *state;
    char out_in[TMPDIR_PATH_MAX], glb[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "box_in.stl", out_in);
    char *out = OUT_OF("convert", f->mm, out_in, "--out-units", "in", "--json");
    expect_text(out, "$.out_units", "in");
    free(out);
    /* its numbers are inches: 40 mm is 1.5748 in; read back in inches it is 24000 mm³ */
    out = OUT_OF("check", out_in, "--units", "in", "--json");
    expect_num(out, "$.bbox_max[0]", 40, 1e-5);
    expect_num(out, "$.volume", 24000, 1e-2);
    free(out);
    cli_result r;
    CLI_RUN(&r, "--quiet", "check", out_in, "--json");
    cli_expect_ok(&r);
    expect_num(r.out, "$.bbox_max[0]", 40 / 25.4, 1e-6);
    cli_result_free(&r);
    /* a glTF is in metres: another --out-units is refused, nothing written */
    CLI_RUN(&r, "convert", f->mm, tmpdir_join(&f->dir, "x.glb", glb), "--out-units", "cm");
    assert_int_equal(r.code, 2);
    cli_expect_contains(r.err, "--out-units applies to .stl .obj .ply .off");
    assert_false(cli_path_exists(glb));
    cli_result_free(&r);
    CLI_RUN(&r, "convert", f->mm, out_in, "--out-units", "yard");
    assert_int_equal(r.code, 2);
    assert_string_equal(r.err, "symrec: usage: bad --out-units 'yard': expected mm, cm, m or in\n");
    cli_result_free(&r);
}

/* ---- --json on catalog init and demo ---- */

static void catalog_init_json_says_created_unchanged_and_migrated(void **state)
{
    const fixture *f = *state;
    char *out = OUT_OF("--db", f->db, "catalog", "init", "--json");
    expect_text(out, "$.action", "created");
    expect_text(out, "$.path", f->db);
    assert_null(jq_text(out, "$.schema_before"));
    expect_num(out, "$.schema_version", sr_catalog_schema_latest(), 0);
    free(out);
    out = OUT_OF("--db", f->db, "catalog", "init", "--json");
    expect_text(out, "$.action", "unchanged");
    expect_num(out, "$.schema_before", sr_catalog_schema_latest(), 0);
    free(out);

    /* a catalogue at schema 4 as that symrec left it (no source_unit), with a part:
     * made by the library with only the first four migrations */
    char v4db[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "v4.db", v4db);
    sr_sql_file v4[5];
    for (int i = 0; i < 4; i++)
        v4[i] = sr_sql_files[i];
    v4[4] = (sr_sql_file){NULL, NULL};
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_cat_open_with(v4db, SR_CATALOG_CREATE, v4, &cat, &err) != SR_OK)
        fail_msg("open at schema 4: %s", err.msg);
    sr_mesh box = {0};
    const double lo[3] = {0, 0, 0}, hi[3] = {40, 30, 20};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    sr_part_new p = {.number = "B", .name = "box", .material = "C45", .mesh = &box};
    int64_t id = 0;
    if (sr_catalog_part_add(cat, &p, &id, &err) != SR_OK)
        fail_msg("part add at schema 4: %s", err.msg);
    sr_mesh_release(&box);
    sr_catalog_close(cat);
    out = OUT_OF("--db", v4db, "catalog", "init", "--json");
    expect_text(out, "$.action", "migrated");
    expect_num(out, "$.schema_before", 4, 0);
    expect_num(out, "$.schema_version", sr_catalog_schema_latest(), 0);
    free(out);
    out = OUT_OF("--db", v4db, "part", "show", "B", "--json");
    expect_text(out, "$.source_unit", "mm");
    free(out);
}

static void demo_json_catalog_only_lists_the_parts_and_no_job(void **state)
{
    const fixture *f = *state;
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "demo", "--catalog-only", "--json");
    cli_expect_ok(&r);
    assert_true(jq_valid(r.out));
    expect_text(r.out, "$.path", f->db);
    expect_num(r.out, "$.schema_version", sr_catalog_schema_latest(), 0);
    expect_num(r.out, "$.parts_added", 4, 0);
    expect_num(r.out, "$.instances_added", 4, 0);
    assert_int_equal(jq_len(r.out, "$.parts"), 4);
    expect_text(r.out, "$.parts[0].number", "SR-SHAFT-01");
    expect_num(r.out, "$.parts[0].id", 1, 0);
    expect_num(r.out, "$.parts[0].instance_ids[0]", 1, 0);
    assert_null(jq_text(r.out, "$.job"));
    assert_non_null(strstr(r.out, "\"job\":null"));
    cli_result_free(&r);
    /* again: nothing added */
    CLI_RUN(&r, "--db", f->db, "demo", "--catalog-only", "--json");
    cli_expect_ok(&r);
    expect_num(r.out, "$.parts_added", 0, 0);
    cli_result_free(&r);
}

static void demo_json_runs_the_job_and_prints_only_json(void **state)
{
    const fixture *f = *state;
    char dir[TMPDIR_PATH_MAX], want[TMPDIR_PATH_MAX + 32];
    tmpdir_join(&f->dir, "demo", dir);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "--quiet", "demo", "--out", dir, "--part", "SR-BRKT-03", "--json");
    cli_expect_ok(&r);
    if (!jq_valid(r.out))
        fail_msg("not JSON: %s", r.out);
    expect_text(r.out, "$.job.part", "SR-BRKT-03");
    expect_num(r.out, "$.job.instance_id", 3, 0);
    expect_num(r.out, "$.job.run_id", 1, 0);
    snprintf(want, sizeof want, "%s/report.html", dir);
    expect_text(r.out, "$.job.report", want);
    assert_true(cli_path_exists(want));
    snprintf(want, sizeof want, "%s/run/result.glb", dir);
    assert_true(cli_path_exists(want));
    cli_result_free(&r);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(check_reads_an_inch_cube_in_inches_as_mm),
        T(the_size_warning_fires_on_an_inch_cube_read_as_mm),
        T(a_bad_unit_is_a_usage_error_naming_the_flag),
        T(part_and_instance_keep_the_unit_read_in),
        T(convert_writes_a_glb_in_metres_that_reads_back_in_mm),
        T(convert_writes_another_unit_when_asked),
        T(catalog_init_json_says_created_unchanged_and_migrated),
        T(demo_json_catalog_only_lists_the_parts_and_no_job),
        T(demo_json_runs_the_job_and_prints_only_json),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
