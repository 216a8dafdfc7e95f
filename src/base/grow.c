/*
 * grow.c: sr_grow (grow.h), the doubling step of every growable array.
 */
#include "base/grow.h"

#include <stdint.h>
#include <stdlib.h>

void *sr_grow(void *v, size_t count, size_t *cap, size_t elem)
{
    if (count < *cap)
        return v;
    size_t want = *cap ? 2 * *cap : 16;
    if (elem == 0 || want > SIZE_MAX / elem)
        return NULL;
    void *nv = realloc(v, want * elem);
    if (!nv)
        return NULL;
    *cap = want;
    return nv;
}
