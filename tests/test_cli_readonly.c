/*
 * test_cli_readonly.c: a catalogue that cannot be written can still be read (issue 17,
 * item 4), and what `catalog init` says it did (item 6).
 *
 * Commands that only read open the catalogue read-only: they work under the global
 * --read-only, on a read-only file and in a read-only folder (where SQLite cannot make
 * the -shm file of a WAL catalogue). Commands that write refuse in one line,
 * "catalogue 'X' is read-only: cannot ...", and `reconstruct` does so before it spends
 * the time. Permissions do not stop root: run as root (as in CI) the permission cases
 * run the binary as user nobody through setpriv(1), and are skipped with a message
 * when that is not possible; the --read-only cases run everywhere.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog.h"
#include "mesh/shapes.h"
#include "support/cli_case.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];  /* dir/cat.db */
    char cyl[TMPDIR_PATH_MAX]; /* dir/cyl.stl: cylinder r 10, z 0..20 */
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "cyl.stl", f->cyl);
    sr_mesh m;
    sr_mesh_init(&m);
    assert_int_equal(sr_shape_cylinder(10.0, 0.0, 20.0, 16, &m, NULL), SR_OK);
    assert_int_equal(sr_mesh_write(f->cyl, &m, NULL, NULL), SR_OK);
    sr_mesh_release(&m);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    chmod(f->dir.path, 0700); /* a case may have left it read-only */
    tmpdir_remove(&f->dir);
    free(f);
    return 0;
}

/* A catalogue with material steel, part P1 and its instance 1 (symmetry axial). */
static void fill_catalogue(const fixture *f)
{
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "catalog", "init");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "materials", "add", "steel", "--density", "7.85");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "P1", "--name", "shaft", "--material",
            "steel", "--mesh", f->cyl, "--symmetry", "axial");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "instance", "add", "--part", "P1", "--mesh", f->cyl, "--serial",
            "S1");
    cli_expect_ok(&r);
    cli_result_free(&r);
}

static void catalog_init_says_what_it_did_to_a_missing_an_empty_and_a_full_file(void **state)
{
    const fixture *f = *state;
    char want[TMPDIR_PATH_MAX + 100];
    int v = sr_catalog_schema_latest();
    assert_int_equal(tmpdir_write_text(f->db, ""), 0);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "catalog", "init");
    cli_expect_ok(&r);
    snprintf(want, sizeof want, "initialised empty file '%s' as a catalogue (schema version %d)\n",
             f->db, v);
    assert_string_equal(r.out, want);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "catalog", "init");
    cli_expect_ok(&r);
    snprintf(want, sizeof want, "catalogue '%s' already exists (schema version %d)\n", f->db, v);
    assert_string_equal(r.out, want);
    cli_result_free(&r);
    unlink(f->db);
    CLI_RUN(&r, "--db", f->db, "catalog", "init");
    cli_expect_ok(&r);
    snprintf(want, sizeof want, "created catalogue '%s' (schema version %d)\n", f->db, v);
    assert_string_equal(r.out, want);
    cli_result_free(&r);
}

static void read_only_flag_reads_and_refuses_every_write_in_one_line(void **state)
{
    const fixture *f = *state;
    fill_catalogue(f);
    char out[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "p1.obj", out);
    cli_result r;
    CLI_RUN(&r, "--read-only", "--db", f->db, "part", "list");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "P1");
    cli_result_free(&r);
    CLI_RUN(&r, "--read-only", "--db", f->db, "instance", "show", "1", "--json");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "\"S1\"");
    cli_result_free(&r);
    CLI_RUN(&r, "--read-only", "--db", f->db, "params", "list");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--read-only", "--db", f->db, "export", "part", "P1", "--out", out);
    cli_expect_ok(&r);
    cli_result_free(&r);
    assert_true(cli_path_exists(out));

    char want[TMPDIR_PATH_MAX + 100];
    snprintf(want, sizeof want, "catalogue '%s' is read-only (--read-only): cannot add the part",
             f->db);
    CLI_RUN(&r, "--read-only", "--db", f->db, "part", "add", "--number", "P2", "--name", "x",
            "--material", "steel", "--mesh", f->cyl);
    cli_expect_error(&r, want);
    cli_result_free(&r);
    CLI_RUN(&r, "--read-only", "--db", f->db, "params", "set", "default", "--layers", "10");
    cli_expect_error(&r, "is read-only (--read-only): cannot set the parameter set");
    cli_result_free(&r);
    /* refused before the reconstruction: no progress note, one line */
    CLI_RUN(&r, "--read-only", "--db", f->db, "reconstruct", "1");
    cli_expect_error(&r, "is read-only (--read-only): cannot record the run");
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "part", "list", "--json");
    cli_expect_ok(&r);
    assert_null(strstr(r.out, "P2"));
    cli_result_free(&r);
}

/* Runs symrec as user nobody when this is root (setpriv), as itself otherwise.
 * Returns false (after a skip message) when root cannot switch. */
static bool run_unprivileged(cli_result *r, const char *const *words)
{
    static const char *const drop[] = {"/usr/bin/setpriv", "--reuid", "65534", "--regid",
                                       "65534", "--clear-groups", NULL};
    if (geteuid() == 0 && access(drop[0], X_OK) != 0) {
        print_message("skipped: running as root and no /usr/bin/setpriv to drop to "
                      "nobody, so file permissions cannot make a catalogue read-only\n");
        return false;
    }
    cli_case_run_under(r, geteuid() == 0 ? drop : NULL, words);
    return true;
}

#define RUN_UNPRIV(ok, r, ...)                                                                     \
    do {                                                                                           \
        const char *const w_[] = {__VA_ARGS__, NULL};                                              \
        *(ok) = run_unprivileged((r), w_);                                                         \
    } while (0)

/* part list works, part add and reconstruct refuse in one line, nothing changes. */
static void expect_readable_not_writable(const fixture *f)
{
    cli_result r;
    bool ran;
    RUN_UNPRIV(&ran, &r, "--db", f->db, "part", "list");
    if (!ran)
        return;
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "P1");
    cli_result_free(&r);
    RUN_UNPRIV(&ran, &r, "--db", f->db, "run", "list");
    cli_expect_ok(&r);
    cli_result_free(&r);
    RUN_UNPRIV(&ran, &r, "--db", f->db, "part", "add", "--number", "P2", "--name", "x",
               "--material", "steel", "--mesh", f->cyl);
    cli_expect_error(&r, "is read-only: cannot add the part");
    cli_result_free(&r);
    RUN_UNPRIV(&ran, &r, "--db", f->db, "reconstruct", "1");
    cli_expect_error(&r, "is read-only: cannot record the run");
    cli_result_free(&r);
}

static void a_read_only_catalogue_file_can_be_read(void **state)
{
    const fixture *f = *state;
    fill_catalogue(f);
    /* root's files: nobody may enter the folder and write in it, not the file */
    assert_int_equal(chmod(f->dir.path, geteuid() == 0 ? 0777 : 0700), 0);
    assert_int_equal(chmod(f->db, 0444), 0);
    expect_readable_not_writable(f);
}

static void a_catalogue_in_a_read_only_folder_can_be_read(void **state)
{
    const fixture *f = *state;
    fill_catalogue(f);
    /* no -wal or -shm beside it (the last writer removed them): a reader cannot make
     * the -shm file, so this is the immutable path */
    char side[TMPDIR_PATH_MAX + 8];
    snprintf(side, sizeof side, "%s-shm", f->db);
    assert_false(cli_path_exists(side));
    assert_int_equal(chmod(f->dir.path, 0555), 0);
    expect_readable_not_writable(f);
    assert_false(cli_path_exists(side));
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(catalog_init_says_what_it_did_to_a_missing_an_empty_and_a_full_file),
        T(read_only_flag_reads_and_refuses_every_write_in_one_line),
        T(a_read_only_catalogue_file_can_be_read),
        T(a_catalogue_in_a_read_only_folder_can_be_read),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
