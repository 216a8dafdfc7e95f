/*
 * scan_fills.c: which triangles of a closed scan its closing made (sr_scan_fill_triangles):
 * the fills of its openings, told from the triangles the scanner delivered by their
 * corners' positions, whatever the closing, peeling and sealing did to the indices in
 * between. The image method reads a section lying behind them as a scan gap's, not
 * damage (reconstruct_gaps.c). Pure C on plain arrays.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/scan_int.h"

/* A 64-bit key of a triangle's corner positions (their bits, exactly), the same
 * whichever corner the triangle starts at (not across a flip: a turned triangle is not
 * the scanner's). */
static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdULL;
    return h ^ (h >> 33);
}

static int corner_cmp(const double *a, const double *b)
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static uint64_t tri_key(const sr_mesh *m, size_t t)
{
    const double *c[3];
    for (int k = 0; k < 3; k++)
        c[k] = m->xyz + 3 * (size_t)m->tri[3 * t + k];
    int first = 0;
    for (int k = 1; k < 3; k++)
        if (corner_cmp(c[k], c[first]) < 0)
            first = k;
    uint64_t h = 0x84222325cbf29ce4ULL;
    for (int k = 0; k < 3; k++) {
        const double *p = c[(first + k) % 3];
        for (int j = 0; j < 3; j++) {
            double x = p[j] == 0 ? 0.0 : p[j]; /* -0 and +0 alike */
            uint64_t bits;
            memcpy(&bits, &x, sizeof bits);
            h = mix(h, bits);
        }
    }
    return h;
}

/* An open-addressing set of keys (0 stands for an empty slot: a key of 0 is kept as 1,
 * the odds of two triangles then meeting being those of any two keys). */
typedef struct key_set {
    uint64_t *slot;
    size_t mask;
} key_set;

static uint64_t nonzero(uint64_t k)
{
    return k ? k : 1;
}

static void key_put(key_set *s, uint64_t k)
{
    k = nonzero(k);
    for (size_t i = (size_t)(k >> 17) & s->mask;; i = (i + 1) & s->mask) {
        if (s->slot[i] == k)
            return;
        if (!s->slot[i]) {
            s->slot[i] = k;
            return;
        }
    }
}

static bool key_has(const key_set *s, uint64_t k)
{
    k = nonzero(k);
    for (size_t i = (size_t)(k >> 17) & s->mask;; i = (i + 1) & s->mask) {
        if (s->slot[i] == k)
            return true;
        if (!s->slot[i])
            return false;
    }
}

sr_status sr_scan_fill_triangles(const sr_mesh *before, const sr_mesh *after, sr_mesh *fills,
                                 sr_err *err)
{
    size_t room = 16;
    while (room < 2 * before->tri_count)
        room *= 2;
    key_set keys = {calloc(room, sizeof(uint64_t)), room - 1};
    uint8_t *made = calloc(after->tri_count + 1, 1);
    sr_status st = SR_OK;
    if (!keys.slot || !made) {
        st = SR_E_NOMEM;
        goto done;
    }
    for (size_t t = 0; t < before->tri_count; t++)
        key_put(&keys, tri_key(before, t));
    for (size_t t = 0; t < after->tri_count; t++)
        made[t] = !key_has(&keys, tri_key(after, t));
    sr_mesh out = {0};
    st = sr_mesh_subset(after, made, &out, NULL);
    if (st != SR_OK)
        goto done;
    sr_mesh_release(fills);
    *fills = out;
done:
    free(keys.slot);
    free(made);
    return st == SR_OK ? SR_OK : sr_err_set(err, st, "out of memory finding the scan's fills");
}
