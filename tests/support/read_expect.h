/*
 * read_expect.h: the assertions the mesh-reading tests share (test_mesh_io,
 * test_mesh_envelope, test_fuzz_replay): a message contains a phrase, and a read fails
 * with a given status and one line "cannot read 'path': ..." leaving its output
 * untouched. For cmocka tests only (they fail the running test).
 */
#ifndef SR_TEST_READ_EXPECT_H
#define SR_TEST_READ_EXPECT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>
#include <cmocka.h>

#include "base/status.h"

/* Asserts that msg contains part. */
#define assert_has(msg, part)                                                                      \
    do {                                                                                           \
        if (!strstr((msg), (part))) {                                                              \
            print_error("message '%s' lacks '%s'\n", (msg), (part));                               \
            fail();                                                                                \
        }                                                                                          \
    } while (0)

/* sr_mesh_read(path) must fail with status st and one line (no '\n') naming the file
 * ("cannot read 'path': ") and containing part; its output mesh stays untouched. */
void expect_read_error(const char *path, sr_status st, const char *part);

#endif
