/*
 * tmpdir.h: a fresh temporary directory per test and files with exact bytes in it.
 * Tests build their input files inline (never from shared data) and remove them after.
 *
 *   tmpdir d;
 *   assert_int_equal(tmpdir_make(&d), 0);          // mkdtemp("/tmp/symrec-test-XXXXXX")
 *   char path[TMPDIR_PATH_MAX];
 *   tmpdir_join(&d, "x.stl", path);                 // "<dir>/x.stl"
 *   assert_int_equal(tmpdir_write_file(path, bytes, n), 0);
 *   ...
 *   tmpdir_remove(&d);                              // the directory and all inside it
 *
 * Paths longer than TMPDIR_PATH_MAX - 1 are a test bug (tmpdir_join aborts).
 * Functions that can fail return 0 on success and -1 on failure (errno set).
 */
#ifndef SR_TEST_TMPDIR_H
#define SR_TEST_TMPDIR_H

#include <stddef.h>

#define TMPDIR_PATH_MAX 512

typedef struct tmpdir {
    char path[TMPDIR_PATH_MAX];   /* the directory; "" before tmpdir_make / after remove */
} tmpdir;

/* Creates a new, empty, private directory /tmp/symrec-test-XXXXXX. */
int tmpdir_make(tmpdir *dir);

/* Removes the directory with everything in it (no symlink is followed) and clears
 * dir->path. Accepts a directory never made or already removed. */
void tmpdir_remove(tmpdir *dir);

/* Writes "<dir>/<name>" into out (TMPDIR_PATH_MAX bytes) and returns out. name may
 * contain '/' (a subfolder) or be "" (the directory itself). */
char *tmpdir_join(const tmpdir *dir, const char *name, char out[TMPDIR_PATH_MAX]);

/* cmocka group set-up and tear-down: *state becomes a new tmpdir (made), removed and
 * freed after the test. Return 0, or -1 when the directory cannot be made. */
int tmpdir_setup(void **state);
int tmpdir_teardown(void **state);

/* Creates or truncates path and writes exactly size bytes to it. */
int tmpdir_write_file(const char *path, const void *bytes, size_t size);

/* tmpdir_write_file of a NUL-terminated string (without the NUL). */
int tmpdir_write_text(const char *path, const char *text);

/* Reads a whole file into a malloc'd buffer (NUL appended, not counted in *size).
 * Returns NULL on failure. The caller frees. */
unsigned char *tmpdir_read_file(const char *path, size_t *size);

#endif
