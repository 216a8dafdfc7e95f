/*
 * grow.h: the one growable-array step of the project: room for one more element in an
 * array that doubles when full. Callers keep (pointer, count, capacity) themselves, in
 * their own typed struct; this only does the doubling.
 */
#ifndef SR_GROW_H
#define SR_GROW_H

#include <stddef.h>

/* v holds count elements of elem bytes and room for *cap. Returns v when there is room
 * for one more, else the array reallocated to twice the room (16 the first time) with
 * *cap updated; NULL when out of memory (v and *cap are kept as they were). */
void *sr_grow(void *v, size_t count, size_t *cap, size_t elem);

#endif
