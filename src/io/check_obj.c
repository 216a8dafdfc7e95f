/*
 * check_obj.c: checks of an OBJ file (see file_check.h): `v` lines with three finite
 * numbers, `f` lines with at least three vertex references in range (negative ones
 * relative, positive ones possibly forward); and the commenting out of `mtllib` lines
 * so that a reader opens no other file.
 *
 * The shared tokenizer, numbers and messages are in check_common.c (check_int.h).
 */
#include "io/check_int.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* After a vertex reference's index: nothing, "/t", "/t/n" or "//n" with integers t, n. */
static int obj_ref_tail(const char *slash, const char *e)
{
    long long v;
    if (!slash)
        return 1;
    const char *s2 = memchr(slash + 1, '/', (size_t)(e - slash - 1));
    if (!s2)
        return fc_parse_int(slash + 1, e, &v);
    return (s2 == slash + 1 || fc_parse_int(slash + 1, s2, &v)) && fc_parse_int(s2 + 1, e, &v);
}

sr_status sr_file_check_obj(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    size_t bad = fc_first_binary_byte(data, size);
    if (bad < size)
        return fc_fail(err, SR_E_FORMAT, name, "not a text OBJ file (byte 0x%02x at offset %zu)",
                       data[bad], bad);
    sr_file_facts f = {0};
    fc_face_acc acc = {0};
    fc_corner_buf cb = {0};
    size_t xyz_cap = 0;
    long long max_ref = 0;
    size_t max_ref_line = 0;
    sr_status st = SR_OK;
    fc_line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    char tok[40];
    while (fc_next_line(&r, &s, &e)) {
        const char *p = s;
        if (!fc_next_token(&p, e, &ts, &te, 1))
            continue;
        if (fc_token_eq(ts, te, "v")) {
            if (f.vertex_count >= UINT32_MAX) {
                st = fc_fail(err, SR_E_FORMAT, name, "more than %u vertices", UINT32_MAX);
                goto out;
            }
            if (!fc_grow((void **)&f.xyz, &xyz_cap, 3 * (f.vertex_count + 1), sizeof *f.xyz)) {
                st = fc_fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
                goto out;
            }
            for (int j = 0; j < 3; j++) {
                double v;
                if (!fc_next_token(&p, e, &ts, &te, 1) || !fc_parse_real(ts, te, &v)) {
                    st = fc_fail(err, SR_E_FORMAT, name, "line %zu: 'v' needs three numbers",
                                 r.number);
                    goto out;
                }
                if (!isfinite(v)) {
                    st = fc_fail(err, SR_E_INVALID, name,
                                 "vertex %zu has %s coordinate (line %zu)", f.vertex_count,
                                 fc_nonfinite_word(v), r.number);
                    goto out;
                }
                f.xyz[3 * f.vertex_count + j] = v;
            }
            f.vertex_count++;
        } else if (fc_token_eq(ts, te, "f")) {
            size_t k = 0;
            while (fc_next_token(&p, e, &ts, &te, 1)) {
                const char *slash = memchr(ts, '/', (size_t)(te - ts));
                long long i;
                if (!fc_parse_int(ts, slash ? slash : te, &i) || !obj_ref_tail(slash, te)) {
                    st = fc_fail(err, SR_E_FORMAT, name, "line %zu: bad vertex reference '%s'",
                                 r.number, fc_token_str(ts, te, tok));
                    goto out;
                }
                if (i == 0) {
                    st = fc_fail(err, SR_E_INVALID, name,
                                 "face on line %zu uses vertex index 0 (OBJ counts from 1)",
                                 r.number);
                    goto out;
                }
                if (i < 0) {
                    i += (long long)f.vertex_count;   /* relative to vertices so far */
                    if (i < 0) {
                        st = fc_fail(err, SR_E_INVALID, name,
                                     "face on line %zu refers to vertex %s before the first one",
                                     r.number, fc_token_str(ts, te, tok));
                        goto out;
                    }
                } else {
                    if (i > max_ref) {
                        max_ref = i;
                        max_ref_line = r.number;
                    }
                    if (i > (long long)UINT32_MAX) {
                        st = fc_fail(err, SR_E_INVALID, name,
                                     "face on line %zu uses vertex %lld, beyond any vertex count",
                                     r.number, i);
                        goto out;
                    }
                    i -= 1;
                }
                if (!fc_grow((void **)&cb.v, &cb.cap, k + 1, sizeof *cb.v)) {
                    st = fc_fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
                    goto out;
                }
                cb.v[k++] = (uint32_t)i;
            }
            if (k < 3) {
                st = fc_fail(err, SR_E_FORMAT, name, "face on line %zu has only %zu vertices",
                             r.number, k);
                goto out;
            }
            if (!fc_add_face(&f, &acc, cb.v, k)) {
                st = fc_fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
                goto out;
            }
        }
        /* vt, vn, vp, l, p, o, g, s, usemtl, mtllib and unknown lines carry no faces. */
    }
    if (max_ref > (long long)f.vertex_count) {
        st = fc_fail(err, SR_E_INVALID, name, "face on line %zu uses vertex %lld, file has %zu",
                     max_ref_line, max_ref, f.vertex_count);
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

void sr_file_obj_drop_mtllib(unsigned char *data, size_t size)
{
    fc_line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    while (fc_next_line(&r, &s, &e)) {
        const char *p = s;
        if (fc_next_token(&p, e, &ts, &te, 1) && fc_token_eq(ts, te, "mtllib"))
            data[ts - (const char *)data] = '#';
    }
}
