/*
 * test_cli_import.c: golden tests of what the command line does with a mesh file that
 * import refuses (issue 17 items 1 and 6): the reproducers of ../shared/repro/ through
 * the very commands its README names (compare, reconstruct --mesh, instance add), a
 * coordinate outside the physical envelope, a part smaller than a micrometre, and a
 * file over the 2 GiB limit. Each must fail with exit 1 (never a signal), exactly one
 * line "symrec: error: cannot read 'FILE': ..." on stderr, nothing on stdout, and the
 * catalogue unchanged. The repro cases are skipped when ../shared/repro is absent.
 *
 * The binary is $SYMREC_BIN (default build/debug/symrec), run under $SYMREC_WRAP when
 * set (tests/support/run_cmd.h); run from the repository root.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/run_cmd.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

#define REPRO_DIR "../shared/repro"

typedef struct env {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    char part[TMPDIR_PATH_MAX]; /* a 20 mm box, added as part P */
} env;

static int setup(void **state)
{
    env *e = calloc(1, sizeof *e);
    if (!e || tmpdir_make(&e->dir) != 0) {
        free(e);
        return -1;
    }
    tmpdir_join(&e->dir, "cat.db", e->db);
    tmpdir_join(&e->dir, "box.stl", e->part);
    sr_mesh m = {0};
    const double lo[3] = {0, 0, 0}, hi[3] = {20, 20, 20};
    if (sr_shape_box(lo, hi, &m, NULL) != SR_OK || sr_mesh_write(e->part, &m, NULL, NULL) != SR_OK)
        return -1;
    sr_mesh_release(&m);
    *state = e;
    return 0;
}

static int teardown(void **state)
{
    env *e = *state;
    tmpdir_remove(&e->dir);
    free(e);
    return 0;
}

typedef struct result {
    int code;
    char *out, *err;
} result;

static void result_free(result *r)
{
    free(r->out);
    free(r->err);
}

static void run_words(result *r, const char *const *words)
{
    const char *argv[32];
    size_t n = 0;
    argv[n++] = sr_test_bin();
    for (size_t i = 0; words[i]; i++) {
        assert_true(n < 31);
        argv[n++] = words[i];
    }
    argv[n] = NULL;
    r->code = sr_test_run(argv, NULL, &r->out, &r->err);
    if (r->code < 0)
        fail_msg("cannot run %s (set SYMREC_BIN)", argv[0]);
}

#define RUN(r, ...)                                                                                \
    do {                                                                                           \
        const char *const words_[] = {__VA_ARGS__, NULL};                                          \
        run_words((r), words_);                                                                    \
    } while (0)

/* Exit 1 (not a signal, not a crash), one line "symrec: error: cannot read 'file': "
 * containing needle, nothing on stdout. */
static void expect_refusal(const result *r, const char *file, const char *needle)
{
    if (r->code != 1)
        fail_msg("expected exit 1, got %d; stderr: %s", r->code, r->err);
    char head[TMPDIR_PATH_MAX + 64];
    snprintf(head, sizeof head, "symrec: error: cannot read '%s': ", file);
    if (strncmp(r->err, head, strlen(head)) != 0)
        fail_msg("stderr does not start with \"%s\": %s", head, r->err);
    const char *nl = strchr(r->err, '\n');
    if (!nl || nl[1] != '\0')
        fail_msg("stderr is not exactly one line: %s", r->err);
    if (!strstr(r->err, needle))
        fail_msg("stderr lacks '%s': %s", needle, r->err);
    assert_string_equal(r->out, "");
}

static void init_catalog(const env *e)
{
    result r;
    RUN(&r, "--db", e->db, "catalog", "init");
    if (r.code != 0)
        fail_msg("catalog init: exit %d: %s", r.code, r.err);
    result_free(&r);
}

static void add_part(const env *e)
{
    result r;
    init_catalog(e);
    RUN(&r, "--db", e->db, "part", "add", "--number", "P", "--name", "box", "--material", "C45",
        "--mesh", e->part);
    if (r.code != 0)
        fail_msg("part add: exit %d: %s", r.code, r.err);
    result_free(&r);
}

/* The instance list as JSON (to show that a refusal stored nothing). */
static char *instances(const env *e)
{
    result r;
    RUN(&r, "--db", e->db, "instance", "list", "--json");
    assert_int_equal(r.code, 0);
    free(r.err);
    return r.out;
}

static int have_repro(void)
{
    struct stat st;
    return stat(REPRO_DIR "/brkt.stl", &st) == 0;
}

static const char ENVELOPE[] = "is outside the physical envelope (|coordinate| <= 1e6 mm)";

/* ---- the reproducers, by the commands of ../shared/repro/README.md ----------------------- */

static void compare_refuses_the_gmp_crash_reproducers(void **state)
{
    if (!have_repro()) {
        skip();
        return;
    }
    env *e = *state;
    static const char *const files[] = {REPRO_DIR "/crash_ply_3d58290a253f.ply",
                                        REPRO_DIR "/crash_ply_95af06b092fa.ply"};
    for (size_t i = 0; i < 2; i++) {
        result r;
        RUN(&r, "--db", e->db, "compare", files[i], REPRO_DIR "/brkt.stl");
        expect_refusal(&r, files[i], ENVELOPE);
        result_free(&r);
    }
}

static void reconstruct_refuses_the_segfault_reproducers(void **state)
{
    if (!have_repro()) {
        skip();
        return;
    }
    env *e = *state;
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", REPRO_DIR "/min_ply_double_1e155.ply",
        "--symmetry", "axial", "--layers", "20", "--sectors", "24");
    expect_refusal(&r, REPRO_DIR "/min_ply_double_1e155.ply",
                   "vertex 3 coordinate z = 1e+155 is outside the physical envelope");
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", REPRO_DIR "/recon_axial_ply_003.ply",
        "--symmetry", "axial", "--layers", "24", "--sectors", "24", "--method", "paper");
    expect_refusal(&r, REPRO_DIR "/recon_axial_ply_003.ply", ENVELOPE);
    result_free(&r);
}

static void instance_add_refuses_a_double_beyond_float_range(void **state)
{
    if (!have_repro()) {
        skip();
        return;
    }
    env *e = *state;
    add_part(e);
    char *before = instances(e);
    result r;
    RUN(&r, "--db", e->db, "instance", "add", "--part", "P", "--mesh",
        REPRO_DIR "/min_ply_double_1e39.ply");
    expect_refusal(&r, REPRO_DIR "/min_ply_double_1e39.ply",
                   "vertex 3 coordinate z = 1e+39 "
                   "is outside the physical envelope");
    result_free(&r);
    char *after = instances(e);
    assert_string_equal(before, after);
    free(before);
    free(after);
}

/* ---- made here ----------------------------------------------------------------------------- */

static void part_add_refuses_parts_outside_the_envelope(void **state)
{
    env *e = *state;
    init_catalog(e);
    char far[TMPDIR_PATH_MAX], tiny[TMPDIR_PATH_MAX];
    tmpdir_join(&e->dir, "far.obj", far);
    tmpdir_join(&e->dir, "tiny.glb", tiny);
    sr_mesh m = {0};
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 10, 10}, hi_tiny[3] = {1e-30, 1e-30, 1e-30};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    m.xyz[3 * 4] = 1e30;
    assert_int_equal(sr_mesh_write(far, &m, NULL, NULL), SR_OK);
    sr_mesh_release(&m);
    assert_int_equal(sr_shape_box(lo, hi_tiny, &m, NULL), SR_OK);
    assert_int_equal(sr_mesh_write(tiny, &m, NULL, NULL), SR_OK);
    sr_mesh_release(&m);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "F", "--name", "far", "--material", "C45",
        "--mesh", far);
    expect_refusal(&r, far, "vertex 4 coordinate x = 1e+30 is outside the physical envelope");
    result_free(&r);
    RUN(&r, "--db", e->db, "part", "add", "--number", "T", "--name", "tiny", "--material", "C45",
        "--mesh", tiny);
    expect_refusal(&r, tiny, "is below the physical envelope (bounding box >= 1e-3 mm)");
    result_free(&r);
    RUN(&r, "--db", e->db, "compare", far, e->part);
    expect_refusal(&r, far, ENVELOPE);
    result_free(&r);
    RUN(&r, "--db", e->db, "part", "list", "--json");
    assert_int_equal(r.code, 0);
    assert_string_equal(r.out, "[]\n"); /* nothing was stored */
    result_free(&r);
}

static void a_file_over_2_gib_is_refused_unread(void **state)
{
    env *e = *state;
    init_catalog(e);
    char big[TMPDIR_PATH_MAX];
    tmpdir_join(&e->dir, "big.stl", big);
    int fd = open(big, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)3 << 30), 0); /* 3 GiB, sparse */
    close(fd);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "B", "--name", "big", "--material", "C45",
        "--mesh", big);
    expect_refusal(&r, big, "file too large (3221225472 bytes; mesh files are limited to 2 GiB");
    result_free(&r);
}

#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)

int main(void)
{
    struct CMUnitTest tests[] = {
        T(compare_refuses_the_gmp_crash_reproducers),
        T(reconstruct_refuses_the_segfault_reproducers),
        T(instance_add_refuses_a_double_beyond_float_range),
        T(part_add_refuses_parts_outside_the_envelope),
        T(a_file_over_2_gib_is_refused_unread),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
