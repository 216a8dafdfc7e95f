/*
 * test_cli_catalog.c: correcting the catalogue from the command line (issue 18, item
 * 5): an unknown material is refused with the known ones listed, `materials add|set`,
 * `part set|remove`, `instance set|remove` (refused while runs refer to the row unless
 * --with-runs, the history summary consistent afterwards), `catalog backup` and
 * `catalog check`. Every case checks the catalogue afterwards, through the CLI or a
 * raw sqlite3 connection, and every refusal that it changed nothing.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support/cli_case.h"
#include "support/json_query.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    char cyl[TMPDIR_PATH_MAX];
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "cyl.stl", f->cyl);
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

/* One integer from `sql` on a plain sqlite3 connection (foreign keys off, as the
 * sqlite3 shell). */
static long long raw_int(const char *db, const char *sql)
{
    sqlite3 *h = NULL;
    sqlite3_stmt *st = NULL;
    assert_int_equal(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL), SQLITE_OK);
    if (sqlite3_prepare_v2(h, sql, -1, &st, NULL) != SQLITE_OK)
        fail_msg("%s: %s", sql, sqlite3_errmsg(h));
    assert_int_equal(sqlite3_step(st), SQLITE_ROW);
    long long n = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    sqlite3_close(h);
    return n;
}

static void raw_exec(const char *db, const char *sql)
{
    sqlite3 *h = NULL;
    assert_int_equal(sqlite3_open_v2(db, &h, SQLITE_OPEN_READWRITE, NULL), SQLITE_OK);
    char *msg = NULL;
    if (sqlite3_exec(h, sql, NULL, NULL, &msg) != SQLITE_OK)
        fail_msg("%s: %s", sql, msg ? msg : "?");
    sqlite3_close(h);
}

/* stdout of a command that must succeed (the caller frees). */
static char *out_of(const char *const *words)
{
    cli_result r;
    cli_case_run(&r, words);
    cli_expect_ok(&r);
    char *out = r.out;
    r.out = NULL;
    cli_result_free(&r);
    return out;
}

#define OUT_OF(...) out_of((const char *const[]){__VA_ARGS__, NULL})

/* The string at path in json is want. */
static void expect_text(const char *json, const char *path, const char *want)
{
    char *got = jq_text(json, path);
    if (!got || strcmp(got, want) != 0)
        fail_msg("%s is '%s', expected '%s' in: %s", path, got ? got : "(none)", want, json);
    free(got);
}

/* Exit 2 with one "symrec: usage: " line containing needle, nothing on stdout. */
static void expect_usage(const cli_result *r, const char *needle)
{
    if (r->code != 2)
        fail_msg("expected exit 2, got %d; stderr: %s", r->code, r->err);
    assert_string_equal(r->out, "");
    assert_true(strncmp(r->err, "symrec: usage: ", 15) == 0);
    assert_non_null(strchr(r->err, '\n'));
    assert_string_equal(strchr(r->err, '\n'), "\n");
    cli_expect_contains(r->err, needle);
}

/* The whole catalogue as the CLI lists it: parts, instances, runs, materials. */
static char *snapshot(const fixture *f)
{
    char *parts = OUT_OF("--db", f->db, "part", "list", "--json");
    char *instances = OUT_OF("--db", f->db, "instance", "list", "--json");
    char *runs = OUT_OF("--db", f->db, "run", "list", "--json");
    char *materials = OUT_OF("--db", f->db, "materials", "list", "--json");
    size_t n = strlen(parts) + strlen(instances) + strlen(runs) + strlen(materials) + 1;
    char *all = malloc(n);
    assert_non_null(all);
    snprintf(all, n, "%s%s%s%s", parts, instances, runs, materials);
    free(parts);
    free(instances);
    free(runs);
    free(materials);
    return all;
}

static void expect_unchanged(const fixture *f, const char *before)
{
    char *now = snapshot(f);
    assert_string_equal(now, before);
    free(now);
}

/* ---- materials ---- */

static void part_add_refuses_an_unknown_material_and_lists_the_known_ones(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    char *before = snapshot(f);
    long long materials = raw_int(f->db, "SELECT count(*) FROM materials");
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "P2", "--name", "x", "--material",
            "unobtainium", "--mesh", f->cyl);
    cli_expect_error(&r, "unknown material 'unobtainium' (known: 42CrMo4, C45, CuSn12, ");
    cli_expect_contains(r.err, ", steel, Ti-6Al-4V, X5CrNi18-10; add it with 'symrec materials "
                               "add unobtainium --density G_CM3')");
    cli_result_free(&r);
    expect_unchanged(f, before);
    assert_int_equal(raw_int(f->db, "SELECT count(*) FROM materials"), materials);
    free(before);

    /* once added with its density, the part takes it */
    CLI_RUN(&r, "--db", f->db, "materials", "add", "Unobtainium", "--density", "12.5", "--family",
            "nickel", "--notes", "from the test", "--json");
    cli_expect_ok(&r);
    assert_true(jq_num(r.out, "$.density_g_cm3") == 12.5);
    expect_text(r.out, "$.family", "nickel");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "P2", "--name", "x", "--material",
            "unobtainium", "--mesh", f->cyl, "--json");
    cli_expect_ok(&r);
    expect_text(r.out, "$.material", "Unobtainium");
    cli_result_free(&r);
    assert_int_equal(raw_int(f->db, "SELECT count(*) FROM materials"), materials + 1);
}

/* A shop with many materials: the refusal lists the first 20 and counts the rest, on
 * one line. */
static void an_unknown_material_among_many_lists_twenty_and_counts_the_rest(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    raw_exec(f->db, "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 30)"
                    " INSERT INTO materials (name, density_g_cm3)"
                    " SELECT printf('Alloy-%02d', i), 8.0 FROM n");
    long long total = raw_int(f->db, "SELECT count(*) FROM materials");
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "P2", "--name", "x", "--material",
            "brass", "--mesh", f->cyl);
    cli_expect_error(&r, "unknown material 'brass' (known: 42CrMo4, Alloy-01, Alloy-02, ");
    char more[96];
    snprintf(more, sizeof more, ", Alloy-19 and %lld more (see 'symrec materials list'); add it",
             total - 20);
    cli_expect_contains(r.err, more);
    cli_result_free(&r);
}

static void materials_add_refuses_bad_values_and_duplicates(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    char *before = snapshot(f);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "materials", "add", "STEEL", "--density", "7.8");
    cli_expect_error(&r, "material 'STEEL' is already in the catalogue");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "add", "brass");
    expect_usage(&r, "'materials add' needs --density");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "add", "brass", "--density", "0");
    expect_usage(&r, "bad --density '0'");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "add", "brass", "--density", "nan");
    expect_usage(&r, "bad --density 'nan'");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "add", "brass", "--density", "8.5", "--family",
            "brass");
    expect_usage(&r, "bad --family 'brass': expected one of steel, stainless_steel");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "add", "--density", "8.5");
    expect_usage(&r, "");
    cli_result_free(&r);
    expect_unchanged(f, before);
    free(before);
}

static void materials_set_gives_an_old_material_its_density(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    /* as an older symrec left it: created by name, no density, no family */
    raw_exec(f->db, "INSERT INTO materials (name) VALUES ('brass')");
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "materials", "list");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "\nbrass              -  -");
    cli_result_free(&r);
    /* catalog check notes it (not a problem: exit 0) */
    CLI_RUN(&r, "--db", f->db, "catalog", "check");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "ok: ");
    assert_string_equal(r.err, "symrec: note: 1 material has no density, so no deposit mass (see "
                               "'symrec materials list'; give one with 'symrec materials set NAME "
                               "--density G_CM3')\n");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "set", "BRASS", "--density", "8.5", "--family",
            "copper");
    cli_expect_ok(&r);
    assert_string_equal(r.out, "changed material 'brass': 8.5 g/cm³, family copper\n");
    cli_result_free(&r);
    assert_int_equal(raw_int(f->db, "SELECT count(*) FROM materials WHERE name = 'brass'"
                                    " AND density_g_cm3 = 8.5 AND family = 'copper'"),
                     1);
    CLI_RUN(&r, "--db", f->db, "materials", "set", "brass", "--notes", "CuZn39Pb3", "--json");
    cli_expect_ok(&r);
    assert_true(jq_num(r.out, "$.density_g_cm3") == 8.5); /* kept */
    expect_text(r.out, "$.notes", "CuZn39Pb3");
    cli_result_free(&r);

    char *check = OUT_OF("--db", f->db, "catalog", "check", "--json");
    assert_true(jq_num(check, "$.materials_without_density") == 0);
    free(check);
    CLI_RUN(&r, "--db", f->db, "materials", "set", "brass");
    expect_usage(&r, "'materials set' needs --density, --family or --notes");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "set", "bronze", "--density", "8.7");
    cli_expect_error(&r, "no material 'bronze' in the catalogue");
    cli_result_free(&r);
}

/* ---- part set / instance set ---- */

static void part_set_changes_the_part_and_prints_it(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--name", "drive shaft", "--material", "c45",
            "--notes", "re-measured", "--symmetry", "axial", "--order", "6", "--json");
    cli_expect_ok(&r);
    expect_text(r.out, "$.number", "P1");
    expect_text(r.out, "$.name", "drive shaft");
    expect_text(r.out, "$.material", "C45");
    expect_text(r.out, "$.notes", "re-measured");
    assert_true(jq_num(r.out, "$.symmetry.order") == 6);
    assert_true(jq_num(r.out, "$.instance_count") == 1);
    cli_result_free(&r);

    /* by id, a new number; the instance and the run follow; symmetry none clears it */
    CLI_RUN(&r, "--db", f->db, "part", "set", "1", "--number", "P1-A", "--symmetry", "none");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "part P1-A (id 1)\n  name:       drive shaft\n");
    cli_expect_contains(r.out, "  symmetry:   -\n");
    cli_result_free(&r);
    char *inst = OUT_OF("--db", f->db, "instance", "show", "1", "--json");
    expect_text(inst, "$.part_number", "P1-A");
    free(inst);
    char *hist = OUT_OF("--db", f->db, "history", "--part", "P1-A", "--json");
    assert_int_equal(jq_len(hist, "$.runs"), 1);
    free(hist);
    assert_int_equal(raw_int(f->db, "SELECT count(*) FROM symmetries WHERE part_id = 1"), 0);
}

static void part_set_refusals_change_nothing(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "P2", "--name", "x", "--material", "C45",
            "--mesh", f->cyl);
    cli_expect_ok(&r);
    cli_result_free(&r);
    char *before = snapshot(f);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1");
    expect_usage(&r, "'part set' needs something to change");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--order", "6");
    expect_usage(&r, "--order needs --symmetry");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--symmetry", "none", "--order", "6");
    expect_usage(&r, "not none");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--name", "");
    expect_usage(&r, "bad --name ''");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P9", "--name", "x");
    cli_expect_error(&r, "no part 'P9' in the catalogue");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--name", "x", "--material", "unobtainium");
    cli_expect_error(&r, "unknown material 'unobtainium' (known: 42CrMo4, ");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--number", "p2");
    cli_expect_error(&r, "part 'p2' is already in the catalogue");
    cli_result_free(&r);
    expect_unchanged(f, before);
    free(before);
}

static void instance_set_changes_serial_date_and_notes(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "instance", "set", "1", "--serial", "SN-77", "--received",
            "2024-02-29", "--notes", "gouge at the key way", "--json");
    cli_expect_ok(&r);
    assert_true(jq_num(r.out, "$.id") == 1);
    expect_text(r.out, "$.serial", "SN-77");
    expect_text(r.out, "$.received", "2024-02-29");
    expect_text(r.out, "$.notes", "gouge at the key way");
    cli_result_free(&r);
    /* "" makes the date unknown; the serial stays */
    CLI_RUN(&r, "--db", f->db, "instance", "set", "1", "--received", "");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "  serial:     SN-77\n  received:   -\n");
    cli_result_free(&r);
    assert_int_equal(raw_int(f->db, "SELECT count(*) FROM instances WHERE id = 1"
                                    " AND received IS NULL AND serial = 'SN-77'"),
                     1);

    char *before = snapshot(f);
    CLI_RUN(&r, "--db", f->db, "instance", "set", "1", "--received", "2023-02-29");
    expect_usage(&r, "bad --received '2023-02-29': expected a date YYYY-MM-DD");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "set", "1", "--received", "29.02.2024");
    expect_usage(&r, "bad --received '29.02.2024'");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "set", "1");
    expect_usage(&r, "'instance set' needs --serial, --received or --notes");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "set", "x1", "--serial", "a");
    expect_usage(&r, "bad ID 'x1'");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "set", "9", "--serial", "a");
    cli_expect_error(&r, "no instance 9 in the catalogue");
    cli_result_free(&r);
    expect_unchanged(f, before);
    free(before);
}

/* ---- removal ---- */

static void part_remove_is_refused_while_runs_refer_to_it_then_takes_them(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    char *before = snapshot(f);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "remove", "P1");
    cli_expect_error(&r, "part 'P1' has 1 instance and 1 run; nothing removed (--with-runs "
                         "removes them too)");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "remove", "1");
    cli_expect_error(&r, "instance 1 has 1 run; nothing removed (--with-runs removes them too)");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "remove", "P9");
    cli_expect_error(&r, "no part 'P9' in the catalogue");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "remove", "9", "--with-runs");
    cli_expect_error(&r, "no instance 9 in the catalogue");
    cli_result_free(&r);
    expect_unchanged(f, before);
    free(before);
    assert_true(raw_int(f->db, "SELECT count(*) FROM sections") > 0);

    CLI_RUN(&r, "--db", f->db, "part", "remove", "P1", "--with-runs");
    cli_expect_ok(&r);
    assert_string_equal(r.out, "removed part P1 (id 1) with 1 instance and 1 run\n");
    cli_result_free(&r);
    static const char *const tables[] = {
        "parts",  "instances",  "runs",   "run_layers",    "sections",
        "advice", "symmetries", "meshes", "history_cells", "history_class_cells"};
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; i++) {
        char sql[96];
        snprintf(sql, sizeof sql, "SELECT count(*) FROM %s", tables[i]);
        if (raw_int(f->db, sql) != 0)
            fail_msg("%s keeps rows after the part's removal", tables[i]);
    }
    assert_int_equal(raw_int(f->db, "SELECT count(*) FROM materials WHERE name = 'steel'"), 1);
    char *list = OUT_OF("--db", f->db, "part", "list");
    assert_string_equal(list, "no parts\n");
    free(list);
    char *check = OUT_OF("--db", f->db, "catalog", "check");
    cli_expect_contains(check, "ok: ");
    free(check);
}

/* Instance 1 (the synthetic run, two sections) and instance 2 (a reconstruction of the
 * intact cylinder): removing instance 1 with its run leaves a history summary equal to
 * the one computed from instance 2's runs alone. */
static void instance_remove_with_runs_keeps_the_history_summary_consistent(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "P1", "--mesh", f->cyl, "--serial",
            "S2");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "reconstruct", "2", "--params", "coarse");
    cli_result_free(&r); /* recorded, whatever it found */
    char *sum = OUT_OF("--db", f->db, "history", "--summary", "--json");
    assert_true(jq_num(sum, "$.summary.runs") == 2);
    free(sum);

    CLI_RUN(&r, "--db", f->db, "instance", "remove", "1", "--with-runs", "--json");
    cli_expect_ok(&r);
    assert_true(jq_num(r.out, "$.instance") == 1);
    expect_text(r.out, "$.part", "P1");
    assert_true(jq_num(r.out, "$.runs") == 1);
    assert_true(jq_num(r.out, "$.meshes") >= 1);
    cli_result_free(&r);

    /* the whole history (read from the summary cells) and instance 2's (read from its
     * runs: one instance is not a question the cells answer) are the same */
    char *all = OUT_OF("--db", f->db, "history", "--summary", "--json");
    char *one = OUT_OF("--db", f->db, "history", "--summary", "--json", "--instance", "2");
    assert_true(jq_num(all, "$.summary.runs") == 1);
    assert_string_equal(all, one);
    free(all);
    free(one);
    char *text = OUT_OF("--db", f->db, "history", "--summary");
    cli_expect_contains(text, "runs: 1 ");
    free(text);
    assert_int_equal(raw_int(f->db, "SELECT sum(runs) FROM history_cells"), 1);
    char *check = OUT_OF("--db", f->db, "catalog", "check");
    cli_expect_contains(check, "ok: ");
    free(check);

    /* an instance without runs goes without --with-runs */
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "P1", "--mesh", f->cyl);
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "remove", "3");
    cli_expect_ok(&r);
    assert_string_equal(r.out, "removed instance 3 of part P1\n");
    cli_result_free(&r);
}

/* ---- backup and check ---- */

static void backup_writes_a_copy_that_lists_the_same(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    char copy[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "copy.db", copy);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "catalog", "backup", copy);
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "backed up '");
    cli_result_free(&r);
    char *orig = OUT_OF("--db", f->db, "part", "list");
    char *back = OUT_OF("--db", copy, "part", "list");
    assert_string_equal(back, orig);
    free(orig);
    free(back);
    orig = OUT_OF("--db", f->db, "run", "show", "1", "--json");
    back = OUT_OF("--db", copy, "run", "show", "1", "--json");
    assert_string_equal(back, orig);
    free(orig);
    free(back);
    char *check = OUT_OF("--db", copy, "catalog", "check");
    cli_expect_contains(check, "ok: ");
    free(check);

    /* an existing file is refused and left as it was; --force replaces it */
    CLI_RUN(&r, "--db", f->db, "part", "set", "P1", "--name", "renamed");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "catalog", "backup", copy);
    cli_expect_error(&r, "already exists (replace it with --force)");
    cli_result_free(&r);
    back = OUT_OF("--db", copy, "part", "show", "P1", "--json");
    expect_text(back, "$.name", "shaft");
    free(back);
    CLI_RUN(&r, "--db", f->db, "catalog", "backup", copy, "--force");
    cli_expect_ok(&r);
    cli_result_free(&r);
    back = OUT_OF("--db", copy, "part", "show", "P1", "--json");
    expect_text(back, "$.name", "renamed");
    free(back);
    CLI_RUN(&r, "--db", f->db, "catalog", "backup", f->db, "--force");
    cli_expect_error(&r, "is the catalogue itself");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "catalog", "backup");
    expect_usage(&r, "");
    cli_result_free(&r);

    /* reading is all a backup needs: a read-only catalogue is backed up too */
    char second[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "second.db", second);
    CLI_RUN(&r, "--read-only", "--db", f->db, "catalog", "backup", second);
    cli_expect_ok(&r);
    cli_result_free(&r);
    assert_int_equal(raw_int(second, "SELECT count(*) FROM parts WHERE name = 'renamed'"), 1);
}

static void check_names_each_problem_and_fails(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "catalog", "check", "--json");
    cli_expect_ok(&r);
    assert_true(jq_num(r.out, "$.ok") == 1); /* true */
    assert_int_equal(jq_len(r.out, "$.problems"), 0);
    assert_true(jq_num(r.out, "$.application_id") == 0x53594d52);
    cli_result_free(&r);

    /* a plain sqlite3 connection, foreign keys off: a part whose material is gone, and
     * a history cell edited by hand */
    raw_exec(f->db, "UPDATE parts SET material_id = 999 WHERE number = 'P1'");
    raw_exec(f->db, "UPDATE history_cells SET runs = runs + 2");
    CLI_RUN(&r, "--db", f->db, "catalog", "check");
    assert_int_equal(r.code, 1);
    /* one line per problem; the month is the run's (the day the test runs) */
    const char *second = strchr(r.out, '\n');
    assert_non_null(second);
    assert_true(strncmp(r.out,
                        "foreign key: parts row 1: material_id refers to a missing "
                        "materials row\n",
                        (size_t)(second - r.out + 1)) == 0);
    assert_true(strncmp(second + 1, "history summary: part id 1, month ", 34) == 0);
    cli_expect_contains(second + 1, ": the cells count 3 runs, the runs table 1\n");
    assert_string_equal(strchr(second + 1, '\n'), "\n");
    cli_expect_contains(r.err, "symrec: error: catalogue '");
    cli_expect_contains(r.err, "' has 2 problems\n");
    assert_string_equal(strchr(r.err, '\n'), "\n");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "catalog", "check", "--json");
    assert_int_equal(r.code, 1);
    assert_true(jq_num(r.out, "$.ok") == 0); /* false */
    assert_int_equal(jq_len(r.out, "$.problems"), 2);
    cli_result_free(&r);
}

/* ---- every write refused on a read-only catalogue; every command has --help ---- */

static void writes_are_refused_on_a_read_only_catalogue(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    char *before = snapshot(f);
    static const char *const cmds[][6] = {
        {"materials", "add", "brass", "--density", "8.5", "cannot add the material"},
        {"materials", "set", "steel", "--density", "7.9", "cannot change the material"},
        {"part", "set", "P1", "--name", "x", "cannot change the part"},
        {"part", "remove", "P1", "--with-runs", NULL, "cannot remove the part"},
        {"instance", "set", "1", "--serial", "x", "cannot change the instance"},
        {"instance", "remove", "1", "--with-runs", NULL, "cannot remove the instance"},
    };
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        const char *words[] = {"--read-only", "--db",     f->db,      cmds[i][0], cmds[i][1],
                               cmds[i][2],    cmds[i][3], cmds[i][4], NULL};
        cli_result r;
        cli_case_run(&r, words);
        cli_expect_error(&r, cmds[i][5]);
        cli_expect_contains(r.err, "is read-only (--read-only)");
        cli_result_free(&r);
    }
    expect_unchanged(f, before);
    free(before);
}

static void every_new_command_has_help(void **state)
{
    (void)state;
    static const char *const cmds[][2] = {
        {"materials", "add"}, {"materials", "set"},   {"part", "set"},       {"part", "remove"},
        {"instance", "set"},  {"instance", "remove"}, {"catalog", "backup"}, {"catalog", "check"},
    };
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        const char *words[] = {cmds[i][0], cmds[i][1], "--help", NULL};
        cli_result r;
        cli_case_run(&r, words);
        cli_expect_ok(&r);
        char want[64];
        snprintf(want, sizeof want, "%s %s ", cmds[i][0], cmds[i][1]);
        cli_expect_contains(r.out, want);
        assert_string_equal(r.err, "");
        cli_result_free(&r);
        /* and the group's usage names it */
        const char *group[] = {cmds[i][0], "--help", NULL};
        cli_case_run(&r, group);
        cli_expect_ok(&r);
        cli_expect_contains(r.out, want);
        cli_result_free(&r);
    }
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(part_add_refuses_an_unknown_material_and_lists_the_known_ones),
        T(an_unknown_material_among_many_lists_twenty_and_counts_the_rest),
        T(materials_add_refuses_bad_values_and_duplicates),
        T(materials_set_gives_an_old_material_its_density),
        T(part_set_changes_the_part_and_prints_it),
        T(part_set_refusals_change_nothing),
        T(instance_set_changes_serial_date_and_notes),
        T(part_remove_is_refused_while_runs_refer_to_it_then_takes_them),
        T(instance_remove_with_runs_keeps_the_history_summary_consistent),
        T(backup_writes_a_copy_that_lists_the_same),
        T(check_names_each_problem_and_fails),
        T(writes_are_refused_on_a_read_only_catalogue),
        T(every_new_command_has_help),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
