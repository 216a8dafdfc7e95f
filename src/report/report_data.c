/*
 * report_data.c: the bulky parts of the report's data block, compactly (report_int.h):
 * the layer outlines and the meshes of the 3D view, as base64 text that report.js and
 * report_view.js decode into typed arrays.
 *
 * Outlines ("layers": {"n": sectors, "q": quantum mm, "z": [heights], "enc": base64}):
 * every coordinate is an integer count of q (RP_OUTLINE_QUANTUM, 1 µm: far below the
 * slicing grid's spacing) coded against a prediction, in one stream of unsigned LEB128
 * varints. The points come layer by layer, in each layer the restored outline's n points
 * and then the damaged outline's n. A point is predicted by its reference point, the
 * same sector of the layer below for a restored point and of the same layer's restored
 * outline for a damaged one, when that exists; else by the last point present in the
 * same outline; else (0, 0). Each point is one token t:
 *   t = 0      the point is missing (NaN in the run);
 *   t = 1, k   this point and the k after it equal their predictions (k >= 0);
 *   t >= 2, u  dx = unzigzag(t - 2), dy = unzigzag(u): the point is prediction + (dx, dy).
 * (zigzag: 0, -1, 1, -2, ... as 0, 1, 2, 3, ...). Where the part does not change from one
 * layer to the next, or the damaged outline follows the restored one, the layer costs a
 * few bytes: the demo run's outlines, 2.5 MB as decimal text, take 20 kB; those of a
 * run on a noisy scan (the shared spur gear's) 0.22 MB.
 *
 * Meshes: {"nv", "nt", "v": base64 of the nv x 3 coordinates as float32, "t": base64
 * of the nt x 3 corner indices as uint32}, both little-endian as every browser is.
 */
#include "report/report_int.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- base64 ---- */

static void put_base64(sb *b, const unsigned char *p, size_t n)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char out[4 * 256 + 1];
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t w = (uint32_t)p[i] << 16;
        if (i + 1 < n)
            w |= (uint32_t)p[i + 1] << 8;
        if (i + 2 < n)
            w |= p[i + 2];
        out[o++] = abc[(w >> 18) & 63];
        out[o++] = abc[(w >> 12) & 63];
        out[o++] = i + 1 < n ? abc[(w >> 6) & 63] : '=';
        out[o++] = i + 2 < n ? abc[w & 63] : '=';
        if (o == sizeof out - 1) {
            sb_putn(b, out, o);
            o = 0;
        }
    }
    sb_putn(b, out, o);
}

/* ---- outlines ---- */

/* A growing byte buffer; out of memory is sticky. */
typedef struct bytes {
    unsigned char *p;
    size_t len, cap;
    bool failed;
} bytes;

static void put_varint(bytes *o, uint64_t v)
{
    if (o->failed)
        return;
    if (o->len + 10 > o->cap) {
        size_t cap = o->cap ? 2 * o->cap : 65536;
        unsigned char *p = realloc(o->p, cap);
        if (!p) {
            o->failed = true;
            return;
        }
        o->p = p;
        o->cap = cap;
    }
    do {
        unsigned char c = v & 0x7f;
        v >>= 7;
        o->p[o->len++] = v ? (unsigned char)(c | 0x80) : c;
    } while (v);
}

static uint64_t zigzag(int64_t v)
{
    return v < 0 ? ((uint64_t)(-(v + 1)) << 1) | 1 : (uint64_t)v << 1;
}

/* A point on the grid; present = false for a missing one. */
typedef struct qpt {
    int64_t x, y;
    bool present;
} qpt;

static qpt quantise(const double *xy)
{
    qpt q = {0, 0, false};
    /* beyond +-1e12 quanta (a million km) a coordinate is not a part's */
    if (isfinite(xy[0]) && isfinite(xy[1]) && fabs(xy[0]) < 1e9 && fabs(xy[1]) < 1e9) {
        q.x = llround(xy[0] / RP_OUTLINE_QUANTUM);
        q.y = llround(xy[1] / RP_OUTLINE_QUANTUM);
        q.present = true;
    }
    return q;
}

/* The token stream of all layers (the header comment's format). */
static void encode_outlines(const sr_run *r, bytes *o)
{
    size_t n = r->sectors, run = 0;
    /* the pending run of points equal to their prediction */
    qpt *below = calloc(n, sizeof *below), *rest = calloc(n, sizeof *rest);
    if (!below || !rest) {
        o->failed = true;
        free(below);
        free(rest);
        return;
    }
    for (size_t l = 0; l < r->layer_count; l++) {
        for (int kind = 0; kind < 2; kind++) {
            const double *xy = (kind == 0 ? r->restored_xy : r->damaged_xy) + 2 * l * n;
            qpt last = {0, 0, false};
            for (size_t k = 0; k < n; k++) {
                qpt q = quantise(xy + 2 * k);
                qpt ref = kind == 0 ? below[k] : rest[k];
                qpt pred = ref.present ? ref : last;
                if (!pred.present)
                    pred.x = pred.y = 0;
                if (q.present && q.x == pred.x && q.y == pred.y) {
                    run++;
                } else {
                    if (run) {
                        put_varint(o, 1);
                        put_varint(o, run - 1);
                        run = 0;
                    }
                    if (!q.present) {
                        put_varint(o, 0);
                    } else {
                        put_varint(o, 2 + zigzag(q.x - pred.x));
                        put_varint(o, zigzag(q.y - pred.y));
                    }
                }
                if (q.present)
                    last = q;
                if (kind == 0)
                    rest[k] = q;
            }
        }
        memcpy(below, rest, n * sizeof *below);
    }
    if (run) {
        put_varint(o, 1);
        put_varint(o, run - 1);
    }
    free(below);
    free(rest);
}

void rp_put_layers(sb *b, const sr_run *r)
{
    sb_printf(b, ",\"layers\":{\"n\":%zu,\"q\":%g,\"z\":[", r->layer_count ? r->sectors : 0,
              RP_OUTLINE_QUANTUM);
    for (size_t l = 0; l < r->layer_count && r->sectors; l++) {
        if (l)
            sb_put(b, ",");
        sb_jnum(b, r->layer_z[l], "%.4f");
    }
    sb_put(b, "],\"enc\":\"");
    if (r->layer_count && r->sectors) {
        bytes o = {0};
        encode_outlines(r, &o);
        if (o.failed)
            b->failed = true;
        else
            put_base64(b, o.p, o.len);
        free(o.p);
    }
    sb_put(b, "\"}");
}

/* ---- meshes ---- */

/* 32-bit words written as base64, little-endian, through a buffer of whole 3-byte
 * groups (so the chunks' base64 joins up). */
typedef struct words {
    sb *b;
    unsigned char chunk[3 * 256 * 4];
    size_t fill;
} words;

static void put_word(words *w, uint32_t v)
{
    for (int k = 0; k < 4; k++)
        w->chunk[w->fill++] = (unsigned char)(v >> (8 * k));
    if (w->fill == sizeof w->chunk) {
        put_base64(w->b, w->chunk, w->fill);
        w->fill = 0;
    }
}

static void flush_words(words *w)
{
    put_base64(w->b, w->chunk, w->fill);
    w->fill = 0;
}

/* n values as float32 words, flushed. */
static void put_f32(words *w, const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        float f = (float)v[i];
        uint32_t u;
        memcpy(&u, &f, 4);
        put_word(w, u);
    }
    flush_words(w);
}

void rp_put_mesh(sb *b, const sr_mesh *m)
{
    sb_printf(b, "{\"nv\":%zu,\"nt\":%zu,\"v\":\"", m->vertex_count, m->tri_count);
    words *w = malloc(sizeof *w);
    if (!w) {
        b->failed = true;
        return;
    }
    w->b = b;
    w->fill = 0;
    put_f32(w, m->xyz, 3 * m->vertex_count);
    sb_put(b, "\",\"t\":\"");
    for (size_t i = 0; i < 3 * m->tri_count; i++)
        put_word(w, m->tri[i]);
    flush_words(w);
    free(w);
    sb_put(b, "\"}");
}

void rp_put_floats(sb *b, const double *v, size_t n)
{
    words *w = malloc(sizeof *w);
    if (!w) {
        b->failed = true;
        return;
    }
    w->b = b;
    w->fill = 0;
    put_f32(w, v, n);
    free(w);
}
