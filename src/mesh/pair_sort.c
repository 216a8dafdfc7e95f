/*
 * pair_sort.c: sr_pair32_sort (pair_sort.h).
 */
#include "mesh/pair_sort.h"

#include <stdbool.h>
#include <stdlib.h>

/* Lists longer than this go to qsort. */
#define SHORT_LIST 24

static int pair_cmp(const void *pa, const void *pb)
{
    const sr_pair32 *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->tag > b->tag) - (a->tag < b->tag);
}

static bool before(sr_pair32 a, sr_pair32 b)
{
    return a.key != b.key ? a.key < b.key : a.tag < b.tag;
}

void sr_pair32_sort(sr_pair32 *p, size_t n)
{
    if (n > SHORT_LIST) {
        qsort(p, n, sizeof *p, pair_cmp);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        sr_pair32 x = p[i];
        size_t j = i;
        for (; j > 0 && before(x, p[j - 1]); j--)
            p[j] = p[j - 1];
        p[j] = x;
    }
}
