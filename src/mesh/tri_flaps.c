/*
 * tri_flaps.c: sr_tri_flaps_pair (tri_flaps.h). Each picked triangle is keyed by its
 * corners sorted and its turn (whether its corners run as an even or an odd
 * permutation of them); after a sort by key, the triangles on one set of corners are
 * neighbours and are paired by opposite turns.
 */
#include "mesh/tri_flaps.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct corner_key {
    uint32_t v[3]; /* corners sorted */
    uint32_t t;    /* triangle */
    int turn;      /* +1: an even permutation of v, -1: odd */
} corner_key;

static int corner_key_cmp(const void *pa, const void *pb)
{
    const corner_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k])
            return a->v[k] < b->v[k] ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

size_t sr_tri_flaps_pair(const sr_mesh *m, const bool *pick, size_t first_new, bool *gone)
{
    size_t n = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        n += pick[t];
    corner_key *k = malloc((n + 1) * sizeof *k);
    if (!k)
        return SIZE_MAX;
    n = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        if (!pick[t])
            continue;
        const uint32_t *c = m->tri + 3 * t;
        size_t s = 0; /* the rotation starting at the smallest corner */
        for (size_t j = 1; j < 3; j++)
            if (c[j] < c[s])
                s = j;
        uint32_t b = c[(s + 1) % 3], d = c[(s + 2) % 3];
        k[n++] = (corner_key){{c[s], b < d ? b : d, b < d ? d : b}, (uint32_t)t, b < d ? 1 : -1};
    }
    qsort(k, n, sizeof *k, corner_key_cmp);
    size_t paired = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && memcmp(k[j].v, k[i].v, sizeof k[i].v) == 0)
            j++;
        for (size_t x = i; x < j; x++)
            for (size_t y = i; y < j && k[x].t >= first_new && !gone[k[x].t]; y++)
                if (y != x && !gone[k[y].t] && k[y].turn == -k[x].turn) {
                    gone[k[x].t] = gone[k[y].t] = true;
                    paired += 2;
                }
        i = j;
    }
    free(k);
    return paired;
}
