/*
 * check_off.c: checks of an ASCII OFF file (see file_check.h): the header keyword and
 * its variants, three counts checked against the file size before anything is sized by
 * them, then one vertex and one face record per line.
 *
 * The shared tokenizer, numbers and messages are in check_common.c (check_int.h).
 */
#include "io/check_int.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Next line holding a token (blank and '#' lines skipped); its first token in ts/te. */
static int next_content_line(fc_line_reader *r, const char **p, const char **e, const char **ts,
                             const char **te)
{
    const char *s;
    while (fc_next_line(r, &s, e)) {
        *p = s;
        if (fc_next_token(p, *e, ts, te, 1))
            return 1;
    }
    return 0;
}

sr_status sr_file_check_off(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    size_t bad = fc_first_binary_byte(data, size);
    fc_line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *p, *e, *ts, *te;
    char tok[40];
    if (!next_content_line(&r, &p, &e, &ts, &te))
        return fc_fail(err, SR_E_FORMAT, name, "no OFF header");
    /* [ST][C][N][4][n]OFF */
    const char *k = ts, *hdr = ts;
    if (te - k >= 2 && k[0] == 'S' && k[1] == 'T')
        k += 2;
    if (k < te && *k == 'C')
        k++;
    if (k < te && *k == 'N')
        k++;
    int dim4 = k < te && *k == '4';
    if (dim4)
        k++;
    int dimn = k < te && *k == 'n';
    if (dimn)
        k++;
    if (!fc_token_is(k, te, "OFF") || memcmp(k, "OFF", 3) != 0)
        return fc_fail(err, SR_E_FORMAT, name, "not an OFF file (starts with '%s')",
                       fc_token_str(ts, te, tok));
    if (dim4 || dimn)
        return fc_fail(err, SR_E_UNSUPPORTED, name, "'%s' (4D or n-D OFF) is not supported",
                       fc_token_str(ts, te, tok));
    long long cnt[3];
    int have = 0;
    if (fc_next_token(&p, e, &ts, &te, 1)) {
        if (fc_token_is(ts, te, "BINARY"))
            return fc_fail(err, SR_E_UNSUPPORTED, name, "binary OFF is not supported");
        /* OpenMesh 9 skips the rest of the header line and reads the counts from the
         * next: counts here made it read vertices as counts and, out of step, loop 4
         * billion times on a number taken for a face's corner count (fuzz_off). */
        return fc_fail(err, SR_E_FORMAT, name,
                       "line %zu: '%s' after '%.*s': the counts must be on the next line", r.number,
                       fc_token_str(ts, te, tok), (int)(k + 3 - hdr), hdr);
    } else if (!next_content_line(&r, &p, &e, &ts, &te) || !fc_parse_int(ts, te, &cnt[0])) {
        return fc_fail(err, SR_E_FORMAT, name, "OFF header has no vertex/face/edge counts");
    } else {
        have = 1;
    }
    while (have < 3 && fc_next_token(&p, e, &ts, &te, 1) && fc_parse_int(ts, te, &cnt[have]))
        have++;
    if (have < 3 || fc_next_token(&p, e, &ts, &te, 1))
        return fc_fail(err, SR_E_FORMAT, name,
                       "line %zu: OFF counts need three numbers (vertices faces edges)", r.number);
    if (bad < size)
        return fc_fail(err, SR_E_FORMAT, name, "not a text OFF file (byte 0x%02x at offset %zu)",
                       data[bad], bad);
    if (cnt[0] < 0 || cnt[1] < 0 || cnt[2] < 0)
        return fc_fail(err, SR_E_FORMAT, name, "negative OFF count on line %zu", r.number);
    /* The shortest vertex line is "0 0 0\n" (6 bytes), the shortest face "3 0 1 2\n". */
    size_t rest = (size_t)(r.end - r.pos);
    if (cnt[0] > (long long)UINT32_MAX || cnt[1] > (long long)UINT32_MAX ||
        (unsigned long long)cnt[0] * 6 + (unsigned long long)cnt[1] * 8 > rest + 1)
        return fc_fail(err, SR_E_FORMAT, name,
                       "OFF header declares %lld vertices and %lld faces, more than the %zu bytes "
                       "after it can hold", cnt[0], cnt[1], rest);
    sr_file_facts f = {0};
    fc_face_acc acc = {0};
    fc_corner_buf cb = {0};
    sr_status st = SR_OK;
    size_t nv = (size_t)cnt[0], nf = (size_t)cnt[1];
    if (nv) {
        f.xyz = malloc(nv * 3 * sizeof *f.xyz);
        if (!f.xyz)
            return fc_fail(err, SR_E_NOMEM, name, "out of memory for %zu vertices", nv);
    }
    for (size_t v = 0; v < nv; v++) {
        if (!next_content_line(&r, &p, &e, &ts, &te)) {
            st = fc_fail(err, SR_E_FORMAT, name, "OFF file ends after %zu of %zu vertices", v, nv);
            goto out;
        }
        for (int j = 0; j < 3; j++) {
            double x;
            if ((j > 0 && !fc_next_token(&p, e, &ts, &te, 1)) || !fc_parse_real(ts, te, &x)) {
                st = fc_fail(err, SR_E_FORMAT, name, "line %zu: vertex %zu needs three numbers",
                             r.number, v);
                goto out;
            }
            if (!isfinite(x)) {
                st = fc_fail(err, SR_E_INVALID, name, "vertex %zu has %s coordinate (line %zu)", v,
                             fc_nonfinite_word(x), r.number);
                goto out;
            }
            f.xyz[3 * v + j] = x;
        }
    }
    f.vertex_count = nv;
    for (size_t i = 0; i < nf; i++) {
        long long n;
        if (!next_content_line(&r, &p, &e, &ts, &te)) {
            st = fc_fail(err, SR_E_FORMAT, name, "OFF file ends after %zu of %zu faces", i, nf);
            goto out;
        }
        if (!fc_parse_int(ts, te, &n) || n < 3 || n > (long long)(e - p) / 2 + 1) {
            st = fc_fail(err, SR_E_FORMAT, name, "line %zu: face %zu has a bad corner count '%s'",
                         r.number, i, fc_token_str(ts, te, tok));
            goto out;
        }
        if (!fc_grow((void **)&cb.v, &cb.cap, (size_t)n, sizeof *cb.v)) {
            st = fc_fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
            goto out;
        }
        for (long long c = 0; c < n; c++) {
            long long idx;
            if (!fc_next_token(&p, e, &ts, &te, 1) || !fc_parse_int(ts, te, &idx)) {
                st = fc_fail(err, SR_E_FORMAT, name, "line %zu: face %zu needs %lld indices",
                             r.number, i, n);
                goto out;
            }
            if (idx < 0 || (unsigned long long)idx >= nv) {
                st = fc_fail(err, SR_E_INVALID, name,
                             "face %zu (line %zu) uses vertex %lld, file has %zu", i, r.number, idx,
                             nv);
                goto out;
            }
            cb.v[c] = (uint32_t)idx;
        }
        /* After a face's indices only its colour: up to four numbers (r g b [a], or a
         * colour-map index). OpenMesh never sees them (openmesh_io.cpp hands it a plain
         * restatement of what this check read): through the file itself it took them
         * for the next face's corner count (a fuzzed "3 3 6 7333...3" looped 4 billion
         * times: fuzz_off). */
        for (int extra = 0; fc_next_token(&p, e, &ts, &te, 1); extra++) {
            double cv;
            if (extra >= 4 || !fc_parse_real(ts, te, &cv) || !isfinite(cv)) {
                st = fc_fail(err, SR_E_FORMAT, name,
                             "line %zu: face %zu has '%s' after its %lld indices (at most a "
                             "colour of four numbers may follow)",
                             r.number, i, fc_token_str(ts, te, tok), n);
                goto out;
            }
        }
        if (!fc_add_face(&f, &acc, cb.v, (size_t)n)) {
            st = fc_fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
            goto out;
        }
    }
    /* Nothing but blank lines and comments after the last face: OpenMesh 9's OFF reader
     * looped forever on a file whose faces carried extra numbers followed by more lines
     * (found by tests/fuzz/fuzz_off.c). */
    if (next_content_line(&r, &p, &e, &ts, &te)) {
        st = fc_fail(err, SR_E_FORMAT, name,
                     "line %zu: more after the %zu faces the header declares", r.number, nf);
        goto out;
    }
    free(cb.v);
    *out = f;
    return SR_OK;
out:
    free(cb.v);
    sr_file_facts_release(&f);
    return st;
}
