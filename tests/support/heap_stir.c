/*
 * heap_stir.c: the heap stirred and meshes compared to the bit (heap_stir.h).
 */
#include "support/heap_stir.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

enum { BLOCKS = 4000 };

void **test_heap_stir(unsigned seed)
{
    void **hold = calloc(BLOCKS, sizeof *hold);
    assert_non_null(hold);
    seed = seed * 7919u + 1u;
    for (size_t i = 0; i < BLOCKS; i++) {
        seed = seed * 1103515245u + 12345u;
        hold[i] = malloc(64 + (seed >> 8) % 20000);
        assert_non_null(hold[i]);
    }
    for (size_t i = 0; i < BLOCKS; i++) {
        seed = seed * 1103515245u + 12345u;
        if ((seed >> 9) & 1) {
            free(hold[i]);
            hold[i] = NULL;
        }
    }
    return hold;
}

void test_heap_settle(void **kept)
{
    for (size_t i = 0; kept && i < BLOCKS; i++)
        free(kept[i]);
    free(kept);
}

void test_assert_same_mesh(const sr_mesh *a, const sr_mesh *b)
{
    assert_int_equal(a->vertex_count, b->vertex_count);
    assert_int_equal(a->tri_count, b->tri_count);
    assert_memory_equal(a->xyz, b->xyz, 3 * a->vertex_count * sizeof *a->xyz);
    assert_memory_equal(a->tri, b->tri, 3 * a->tri_count * sizeof *a->tri);
}
