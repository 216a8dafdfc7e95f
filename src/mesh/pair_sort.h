/*
 * pair_sort.h: (key, tag) pairs of 32-bit integers sorted by key, then tag
 * (pair_sort.c). The lists round one vertex of a mesh (its edges, its corners'
 * neighbours) are a dozen long: sorted in place, without qsort's calls, which cost a
 * two-million-triangle scan a third of a second a pass. Pure C: no I/O.
 */
#ifndef SR_MESH_PAIR_SORT_H
#define SR_MESH_PAIR_SORT_H

#include <stddef.h>
#include <stdint.h>

typedef struct sr_pair32 {
    uint32_t key, tag;
} sr_pair32;

/* p[0..n) in (key, tag) order: insertion sort for short lists, qsort for long ones (a
 * fan's centre). */
void sr_pair32_sort(sr_pair32 *p, size_t n);

#endif
