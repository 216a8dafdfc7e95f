/*
 * mesh_edit.c: vertices and triangles added to a test mesh by hand (mesh_edit.h).
 */
#include "support/mesh_edit.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

uint32_t test_add_vertex(sr_mesh *m, const double p[3])
{
    sr_mesh v;
    assert_int_equal(sr_mesh_alloc(&v, 1, 0), SR_OK);
    memcpy(v.xyz, p, 3 * sizeof *p);
    uint32_t at = (uint32_t)m->vertex_count;
    assert_int_equal(sr_mesh_append(m, &v), SR_OK);
    sr_mesh_release(&v);
    return at;
}

void test_add_triangle(sr_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t *tri = realloc(m->tri, 3 * (m->tri_count + 1) * sizeof *tri);
    assert_non_null(tri);
    m->tri = tri;
    tri += 3 * m->tri_count++;
    tri[0] = a;
    tri[1] = b;
    tri[2] = c;
}
