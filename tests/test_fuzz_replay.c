/*
 * test_fuzz_replay.c: the fuzz targets' inputs replayed in `make check` (issue 17 item
 * 2). The seed corpus of `make fuzz` is written afresh by the project's writers into a
 * temporary folder (tests/support/fuzz_seeds.c: a box, a cylinder and a two-mesh scene
 * in every format and variant), and every file of ../shared/repro/ (the reproducers of
 * crashes found by outside fuzzing; skipped when the folder is absent) is read, each
 * through sr_mesh_read_memory, the entry point of the fuzz targets (tests/fuzz/), in
 * its own format and in every other one. Every outcome must be clean, as the fuzz
 * targets demand: a valid mesh inside the physical envelope, or a refusal of one line
 * "cannot read 'NAME': ..." that is not SR_E_INTERNAL, with the output untouched. The
 * seeds themselves must read in their own format; the reproducers other than brkt.stl
 * must be refused. The inputs the fuzz targets found (tests/fuzz/found/, one file each,
 * named for the fault) are replayed the same way.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "io/envelope.h"
#include "mesh/mesh.h"
#include "support/fuzz_seeds.h"
#include "support/read_expect.h"
#include "support/tmpdir.h"

#define REPRO_DIR "../shared/repro"
/* inputs the fuzz targets found that once hung or crashed (kept in the project) */
#define FOUND_DIR "tests/fuzz/found"

static const sr_format all_formats[] = {SR_FMT_STL, SR_FMT_OBJ,  SR_FMT_PLY,
                                        SR_FMT_OFF, SR_FMT_GLTF, SR_FMT_GLB};

/* One input through one format: a clean outcome or a failed test. Returns the status. */
static sr_status replay_one(const unsigned char *data, size_t size, sr_format fmt, const char *name)
{
    sr_mesh m = {(double *)1, (uint32_t *)1, 77, 77}; /* untouched on failure */
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_mesh_read_memory(data, size, fmt, name, &m, &err);
    if (st == SR_OK) {
        assert_int_equal(sr_mesh_validate(&m, name, NULL, NULL), SR_OK);
        assert_int_equal(
            sr_envelope_check_mesh(m.xyz, m.vertex_count, m.tri, m.tri_count, name, NULL), SR_OK);
        sr_mesh_release(&m);
        return st;
    }
    if (st == SR_E_INTERNAL)
        fail_msg("%s as %s: internal error: %s", name, sr_format_name(fmt), err.msg);
    char head[1100];
    snprintf(head, sizeof head, "cannot read '%s': ", name);
    if (strncmp(err.msg, head, strlen(head)) != 0 || strchr(err.msg, '\n'))
        fail_msg("%s as %s: not one line naming the file: '%s'", name, sr_format_name(fmt),
                 err.msg);
    assert_ptr_equal(m.xyz, (double *)1);
    assert_int_equal(m.vertex_count, 77);
    return st;
}

/* Every regular file of dir through every format; `own` gets the status of each file
 * read in the format its extension names (checked by the caller through `expect`). */
typedef void (*own_check)(const char *file, sr_status st);

static size_t replay_dir(const char *dir, own_check expect)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    size_t files = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char path[TMPDIR_PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        size_t size;
        unsigned char *data = tmpdir_read_file(path, &size);
        if (!data)
            continue; /* a folder */
        sr_format own = sr_format_from_path(e->d_name);
        for (size_t f = 0; f < sizeof all_formats / sizeof all_formats[0]; f++) {
            sr_status st = replay_one(data, size, all_formats[f], e->d_name);
            if (all_formats[f] == own && expect)
                expect(e->d_name, st);
        }
        free(data);
        files++;
    }
    closedir(d);
    return files;
}

static void seed_reads(const char *file, sr_status st)
{
    if (st != SR_OK)
        fail_msg("seed %s does not read in its own format (status %d)", file, st);
}

static void seed_corpus_replays_cleanly(void **state)
{
    const tmpdir *d = *state;
    int n = sr_fuzz_write_seeds(d->path);
    assert_true(n >= 18);
    size_t files = 0;
    for (size_t f = 0; sr_fuzz_formats[f]; f++) {
        char sub[TMPDIR_PATH_MAX];
        tmpdir_join(d, sr_fuzz_formats[f], sub);
        files += replay_dir(sub, seed_reads);
    }
    assert_int_equal(files, (size_t)n);
}

static void repro_refused(const char *file, sr_status st)
{
    if (strcmp(file, "brkt.stl") == 0)
        assert_int_equal(st, SR_OK);
    else if (sr_format_from_path(file) != SR_FMT_UNKNOWN && st == SR_OK)
        fail_msg("reproducer %s was accepted", file);
}

static void repro_files_replay_cleanly(void **state)
{
    (void)state;
    DIR *probe = opendir(REPRO_DIR);
    if (!probe) {
        skip();
        return;
    }
    closedir(probe);
    assert_true(replay_dir(REPRO_DIR, repro_refused) >= 6);
}

static void fuzz_finds_replay_cleanly(void **state)
{
    (void)state;
    assert_true(replay_dir(FOUND_DIR, NULL) >= 1);
}

/* Truncations and single-byte changes of each seed, in its own format: the cheapest
 * mutations, deterministic, as a floor under what the fuzz targets explore. */
static void cut_and_flipped_seeds_replay_cleanly(void **state)
{
    const tmpdir *d = *state;
    assert_true(sr_fuzz_write_seeds(d->path) > 0);
    static const char *const seeds[] = {"stl/box.stl",   "stl/box_ascii.stl", "obj/box.obj",
                                        "ply/box.ply",   "ply/box_ascii.ply", "off/box.off",
                                        "gltf/box.gltf", "glb/box.glb"};
    for (size_t i = 0; i < sizeof seeds / sizeof seeds[0]; i++) {
        char path[TMPDIR_PATH_MAX];
        size_t size;
        unsigned char *data = tmpdir_read_file(tmpdir_join(d, seeds[i], path), &size);
        assert_non_null(data);
        sr_format fmt = sr_format_from_path(path);
        size_t step = size / 97 + 1;
        for (size_t cut = 0; cut < size; cut += step)
            replay_one(data, cut, fmt, seeds[i]);
        for (size_t at = 0; at < size; at += step) {
            unsigned char keep = data[at];
            static const unsigned char subst[] = {0x00, 0xff, '9', '-', '\n', 'e'};
            for (size_t k = 0; k < sizeof subst; k++) {
                data[at] = subst[k];
                replay_one(data, size, fmt, seeds[i]);
            }
            data[at] = keep;
        }
        free(data);
    }
}

#define T(name) cmocka_unit_test_setup_teardown(name, tmpdir_setup, tmpdir_teardown)

int main(void)
{
    const struct CMUnitTest tests[] = {
        T(seed_corpus_replays_cleanly),
        T(repro_files_replay_cleanly),
        T(fuzz_finds_replay_cleanly),
        T(cut_and_flipped_seeds_replay_cleanly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
