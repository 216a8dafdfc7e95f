/*
 * heap_stir.h: what the tests of outputs that must not follow the heap's history share
 * (test_boolean.c, test_stack_mesh.c, test_image.c): the heap stirred, and two meshes
 * compared to the bit.
 */
#ifndef SR_TEST_HEAP_STIR_H
#define SR_TEST_HEAP_STIR_H

#include "mesh/mesh.h"

/* Allocates 4000 blocks of 64 B to 20 kB (sizes from seed) and frees about half of
 * them, so that the next allocations come back in another order of addresses. Returns
 * the blocks kept, for test_heap_settle. */
void **test_heap_stir(unsigned seed);

/* Frees what test_heap_stir kept. */
void test_heap_settle(void **kept);

/* a and b are the same mesh: the same vertices and triangles, in the same order, to
 * the bit. */
void test_assert_same_mesh(const sr_mesh *a, const sr_mesh *b);

#endif
