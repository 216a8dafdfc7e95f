/*
 * test_cli_outputs.c: output folders are written as a set (issue 17, item 3; rules in
 * cli/outset.h), and every output file has one mode (0666 & ~umask).
 *
 * A synthetic run with two dug sections, 10 and 3 layers deep, is stored through the
 * library (cli_case_synth_catalogue), so `plan --section 1` writes a long set and
 * `--section 2` a short one into the same folder. A failing write is simulated with
 * the SYMREC_TEST_OUTSET_FAIL hook (a full disk just before the set is put in place).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <signal.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "support/cli_case.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];  /* dir/cat.db with part P1, instance 1 and run 1 */
    char cyl[TMPDIR_PATH_MAX]; /* dir/cyl.stl: cylinder r 10, z 0..12 */
    char out[TMPDIR_PATH_MAX]; /* dir/out: the output folder under test */
} fixture;

static int setup(void **state)
{
    umask(022);
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "cyl.stl", f->cyl);
    tmpdir_join(&f->dir, "out", f->out);
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    unsetenv("SYMREC_TEST_OUTSET_FAIL");
    tmpdir_remove(&f->dir);
    free(f);
    return 0;
}

/* The names in folder `dir` (hidden ones too), sorted, one per line; "" if none. */
static void listing(const char *dir, char *out, size_t size)
{
    struct dirent **names;
    int n = scandir(dir, &names, NULL, alphasort);
    assert_true(n >= 0);
    out[0] = '\0';
    for (int i = 0; i < n; i++) {
        if (strcmp(names[i]->d_name, ".") != 0 && strcmp(names[i]->d_name, "..") != 0) {
            assert_true(strlen(out) + strlen(names[i]->d_name) + 2 < size);
            strcat(out, names[i]->d_name);
            strcat(out, "\n");
        }
        free(names[i]);
    }
    free(names);
}

/* The listing of a plan set of `layers` layers. */
static void plan_set(size_t layers, char *out, size_t size)
{
    int n = snprintf(out, size, ".symrec-set\n");
    for (size_t k = 1; k <= layers; k++)
        n += snprintf(out + n, size - (size_t)n, "layer_%03zu.svg\n", k);
    snprintf(out + n, size - (size_t)n, "plan.gcode\nplan.json\n");
}

static void plan_into(const fixture *f, const char *section)
{
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "plan", "1", "--out", f->out, "--section", section);
    cli_expect_ok(&r);
    cli_result_free(&r);
}

static void expect_no_staging_folder(const fixture *f)
{
    char names[4096];
    listing(f->dir.path, names, sizeof names);
    if (strstr(names, ".partial-"))
        fail_msg("a staging folder was left: %s", names);
}

static void a_shorter_plan_replaces_a_longer_one_as_a_whole(void **state)
{
    const fixture *f = *state;
    char got[4096], want[4096];
    plan_into(f, "1");
    listing(f->out, got, sizeof got);
    plan_set(10, want, sizeof want);
    assert_string_equal(got, want);
    plan_into(f, "2");
    listing(f->out, got, sizeof got);
    plan_set(3, want, sizeof want);
    assert_string_equal(got, want);
    expect_no_staging_folder(f);
    char path[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "out/.symrec-set", path);
    size_t size;
    char *manifest = (char *)tmpdir_read_file(path, &size);
    assert_non_null(manifest);
    cli_expect_contains(manifest, "symrec output set (plan)\n");
    cli_expect_contains(manifest, "\nlayer_003.svg\n");
    assert_null(strstr(manifest, "layer_004.svg"));
    free(manifest);
}

static void a_failed_write_leaves_the_previous_set_and_no_staging_folder(void **state)
{
    const fixture *f = *state;
    char before[4096], after[4096], path[TMPDIR_PATH_MAX];
    plan_into(f, "1");
    listing(f->out, before, sizeof before);
    tmpdir_join(&f->dir, "out/plan.json", path);
    size_t size0, size1;
    unsigned char *json0 = tmpdir_read_file(path, &size0);
    assert_non_null(json0);

    setenv("SYMREC_TEST_OUTSET_FAIL", "1", 1);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "plan", "1", "--out", f->out, "--section", "2");
    cli_expect_error(&r, "cannot write the output folder '");
    cli_expect_contains(r.err, f->out);
    cli_result_free(&r);
    /* the same for a reconstruction, whose folder is new: nothing appears */
    char run_out[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "run", run_out);
    CLI_RUN(&r, "--db", f->db, "reconstruct", "--mesh", f->cyl, "--symmetry", "axial", "--layers",
            "12", "--sectors", "36", "--method", "paper", "--no-union", "--out", run_out);
    assert_int_equal(r.code, 1);
    cli_expect_contains(r.err, "symrec: error: cannot write the output folder '");
    cli_result_free(&r);
    unsetenv("SYMREC_TEST_OUTSET_FAIL");
    assert_false(cli_path_exists(run_out));

    listing(f->out, after, sizeof after);
    assert_string_equal(after, before);
    unsigned char *json1 = tmpdir_read_file(path, &size1);
    assert_non_null(json1);
    assert_int_equal(size0, size1);
    assert_memory_equal(json0, json1, size0);
    free(json0);
    free(json1);
    expect_no_staging_folder(f);
}

static void a_folder_with_a_foreign_file_is_refused_and_left_alone(void **state)
{
    const fixture *f = *state;
    char before[4096], after[4096], path[TMPDIR_PATH_MAX];
    assert_int_equal(mkdir(f->out, 0777), 0);
    tmpdir_join(&f->dir, "out/notes.txt", path);
    assert_int_equal(tmpdir_write_text(path, "mine\n"), 0);
    tmpdir_join(&f->dir, "out/plan.json", path);
    assert_int_equal(tmpdir_write_text(path, "{}\n"), 0);
    listing(f->out, before, sizeof before);

    cli_result r;
    CLI_RUN(&r, "--db", f->db, "plan", "1", "--out", f->out);
    cli_expect_error(&r, "holds 'notes.txt', which symrec did not write");
    cli_expect_contains(r.err, f->out);
    cli_result_free(&r);
    /* reconstruct refuses before it runs: no progress note, only the error line */
    CLI_RUN(&r, "--db", f->db, "reconstruct", "1", "--params", "coarse", "--out", f->out);
    cli_expect_error(&r, "which symrec did not write"); /* plan.json is not its either */
    cli_result_free(&r);
    listing(f->out, after, sizeof after);
    assert_string_equal(after, before);
    size_t size;
    char *back = (char *)tmpdir_read_file(path, &size);
    assert_string_equal(back, "{}\n");
    free(back);
    expect_no_staging_folder(f);

    /* an empty folder is taken; a plain file is not a folder */
    char empty[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "empty", empty);
    assert_int_equal(mkdir(empty, 0777), 0);
    CLI_RUN(&r, "--db", f->db, "plan", "1", "--out", empty, "--section", "2");
    cli_expect_ok(&r);
    cli_result_free(&r);
    CLI_RUN(&r, "--db", f->db, "plan", "1", "--out", f->cyl);
    cli_expect_error(&r, "exists and is not a folder");
    cli_result_free(&r);
}

/* A process id that is not running. */
static long dead_pid(void)
{
    for (long pid = 4000000; pid > 1000; pid -= 7919)
        if (kill((pid_t)pid, 0) != 0 && errno == ESRCH)
            return pid;
    fail_msg("no unused process id found");
    return 0;
}

static void a_killed_runs_staging_folder_is_removed_by_the_next_write(void **state)
{
    const fixture *f = *state;
    char stale[TMPDIR_PATH_MAX], live[TMPDIR_PATH_MAX], name[64], path[TMPDIR_PATH_MAX];
    snprintf(name, sizeof name, ".out.partial-%ld-AbCdEf", dead_pid());
    tmpdir_join(&f->dir, name, stale);
    assert_int_equal(mkdir(stale, 0777), 0);
    snprintf(name, sizeof name, ".out.partial-%ld-AbCdEf/plan.json", dead_pid());
    tmpdir_join(&f->dir, name, path);
    assert_int_equal(tmpdir_write_text(path, "half"), 0);
    /* one whose process still runs (this test) is another write in progress */
    snprintf(name, sizeof name, ".out.partial-%ld-GhIjKl", (long)getpid());
    tmpdir_join(&f->dir, name, live);
    assert_int_equal(mkdir(live, 0777), 0);
    plan_into(f, "2");
    assert_false(cli_path_exists(stale));
    assert_true(cli_path_exists(live));
    rmdir(live);
}

static void output_files_are_0644_and_folders_0755_under_umask_022(void **state)
{
    const fixture *f = *state;
    char path[TMPDIR_PATH_MAX];
    plan_into(f, "2");
    assert_int_equal(cli_path_mode(f->out), 0755);
    static const char *const plan_files[] = {"out/plan.json", "out/layer_001.svg", "out/plan.gcode",
                                             "out/.symrec-set"};
    for (size_t i = 0; i < 4; i++) {
        tmpdir_join(&f->dir, plan_files[i], path);
        if (cli_path_mode(path) != 0644)
            fail_msg("%s has mode %o", path, cli_path_mode(path));
    }

    char run_out[TMPDIR_PATH_MAX];
    tmpdir_join(&f->dir, "run", run_out);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "reconstruct", "--mesh", f->cyl, "--symmetry", "axial", "--layers",
            "12", "--sectors", "36", "--method", "paper", "--no-union", "--out", run_out);
    cli_expect_ok(&r);
    cli_result_free(&r);
    assert_int_equal(cli_path_mode(run_out), 0755);
    static const char *const run_files[] = {"run/restored.stl", "run/result.glb"};
    for (size_t i = 0; i < 2; i++) {
        tmpdir_join(&f->dir, run_files[i], path);
        if (cli_path_mode(path) != 0644)
            fail_msg("%s has mode %o", path, cli_path_mode(path));
    }

    tmpdir_join(&f->dir, "p1.obj", path);
    CLI_RUN(&r, "--db", f->db, "export", "part", "P1", "--out", path);
    cli_expect_ok(&r);
    cli_result_free(&r);
    assert_int_equal(cli_path_mode(path), 0644);
    tmpdir_join(&f->dir, "report.html", path);
    CLI_RUN(&r, "--db", f->db, "report", "1", "--out", path);
    cli_expect_ok(&r);
    cli_result_free(&r);
    assert_int_equal(cli_path_mode(path), 0644);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(a_shorter_plan_replaces_a_longer_one_as_a_whole),
        T(a_failed_write_leaves_the_previous_set_and_no_staging_folder),
        T(a_folder_with_a_foreign_file_is_refused_and_left_alone),
        T(a_killed_runs_staging_folder_is_removed_by_the_next_write),
        T(output_files_are_0644_and_folders_0755_under_umask_022),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
