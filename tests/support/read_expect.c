/*
 * read_expect.c: the shared assertions of the mesh-reading tests (see read_expect.h).
 */
#include "support/read_expect.h"

#include <stdio.h>

#include "bridge/mesh_io.h"
#include "mesh/mesh.h"

void expect_read_error(const char *path, sr_status st, const char *part)
{
    sr_mesh m = {(double *)1, (uint32_t *)1, 77, 77}; /* sentinel: must not be written */
    sr_err err = {{0}};
    sr_status got = sr_mesh_read(path, &m, &err);
    if (got != st)
        print_error("status %d (%s), expected %d; message '%s'\n", got, sr_status_str(got), st,
                    err.msg);
    assert_int_equal(got, st);
    assert_ptr_equal(m.xyz, (double *)1);
    assert_int_equal(m.vertex_count, 77);
    char quoted[1100];
    snprintf(quoted, sizeof quoted, "cannot read '%s': ", path);
    assert_has(err.msg, quoted);
    assert_has(err.msg, part);
    assert_null(strchr(err.msg, '\n'));
}
