/*
 * check_stl.c: checks of a binary or ASCII STL (see file_check.h), and the blanking of an
 * ASCII STL's name lines before OpenMesh reads it.
 *
 * Binary: the size must match the header's triangle count exactly and every coordinate be
 * finite in float; the facets can be checked a run at a time (a file read in pieces).
 * ASCII: facet structure walked line by line, three vertices a loop; it returns each
 * facet's corners. Both hold every corner to the physical envelope (envelope.h) and
 * count the facets a reader drops as degenerate.
 *
 * The shared tokenizer, numbers and messages are in check_common.c (check_int.h).
 */
#include "io/check_int.h"
#include "io/envelope.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static float lef32(const unsigned char *p)
{
    uint32_t u = fc_le32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* OpenMesh's STL reader merges corners whose coordinates differ by at most FLT_MIN. */
static int same_point(const float *a, const float *b)
{
    return fabs((double)a[0] - b[0]) <= FLT_MIN && fabs((double)a[1] - b[1]) <= FLT_MIN &&
           fabs((double)a[2] - b[2]) <= FLT_MIN;
}

static int degenerate_facet(const float *c)
{
    return same_point(c, c + 3) || same_point(c, c + 6) || same_point(c + 3, c + 6);
}

sr_status sr_file_check_stl_facets(const unsigned char *records, size_t count, size_t first,
                                   const char *name, size_t *degenerate, sr_err *err)
{
    for (size_t i = 0; i < count; i++) {
        const unsigned char *rec = records + SR_STL_FACET_BYTES * i + 12; /* skip the normal */
        float c[9];
        for (int k = 0; k < 9; k++) {
            c[k] = lef32(rec + 4 * k);
            if (!isfinite(c[k]))
                return fc_fail(err, SR_E_INVALID, name, "binary STL triangle %zu has %s coordinate",
                               first + i, fc_nonfinite_word(c[k]));
        }
        sr_status st = sr_envelope_check_corners(c, 1, first + i, name, err);
        if (st != SR_OK)
            return st;
        if (degenerate_facet(c))
            ++*degenerate;
    }
    return SR_OK;
}

void sr_file_stl_facet(const unsigned char *record, float corners[9])
{
    for (int k = 0; k < 9; k++)
        corners[k] = lef32(record + 12 + 4 * k);
}

size_t sr_file_stl_binary_count(const unsigned char *header, size_t size)
{
    if (size < SR_STL_HEADER_BYTES)
        return 0;
    uint32_t n = fc_le32(header + 80);
    return n > 0 && size == SR_STL_HEADER_BYTES + (unsigned long long)SR_STL_FACET_BYTES * n ? n
                                                                                             : 0;
}

static sr_status check_stl_binary(const unsigned char *data, size_t size, const char *name,
                                  sr_file_facts *out, sr_err *err)
{
    if (size < SR_STL_HEADER_BYTES)
        return fc_fail(err, SR_E_FORMAT, name,
                       "too short for a binary STL (%zu bytes, the header alone takes 84)", size);
    uint32_t n = fc_le32(data + 80);
    unsigned long long expect = SR_STL_HEADER_BYTES + (unsigned long long)SR_STL_FACET_BYTES * n;
    size_t holds = (size - SR_STL_HEADER_BYTES) / SR_STL_FACET_BYTES;
    if (size < expect)
        return fc_fail(err, SR_E_FORMAT, name,
                       "truncated binary STL (header says %u triangles, file holds %zu)", n, holds);
    if (size > expect) {
        if ((size - SR_STL_HEADER_BYTES) % SR_STL_FACET_BYTES == 0)
            return fc_fail(err, SR_E_FORMAT, name,
                           "binary STL header says %u triangles, file holds %zu", n, holds);
        return fc_fail(err, SR_E_FORMAT, name,
                       "binary STL has %llu trailing bytes after its %u triangles",
                       (unsigned long long)size - expect, n);
    }
    sr_file_facts f = {0};
    f.binary = 1;
    f.face_count = f.tri_count = n;
    f.vertex_count = 3 * (size_t)n;
    sr_status st =
        sr_file_check_stl_facets(data + SR_STL_HEADER_BYTES, n, 0, name, &f.degenerate_tris, err);
    if (st != SR_OK)
        return st;
    *out = f;
    return SR_OK;
}

static sr_status check_stl_ascii(const unsigned char *data, size_t size, const char *name,
                                 sr_file_facts *out, sr_err *err)
{
    sr_file_facts f = {0};
    size_t cap = 0;
    sr_status st = SR_OK;
    fc_line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    char tok[40];
    while (fc_next_line(&r, &s, &e)) {
        const char *p = s;
        if (!fc_next_token(&p, e, &ts, &te, 0))
            continue;
        if (fc_token_is(ts, te, "vertex")) {
            st = fc_fail(err, SR_E_FORMAT, name, "line %zu: 'vertex' outside an 'outer loop'",
                         r.number);
            goto out;
        }
        if (!fc_token_is(ts, te, "outer")) {
            /* facet/endloop/endfacet stay visible to the reader: no stray "outer" there. */
            int kept = fc_token_is(ts, te, "facet") || fc_token_is(ts, te, "endloop") ||
                       fc_token_is(ts, te, "endfacet");
            for (const char *q = s; kept && q + 5 <= e; q++)
                if (memcmp(q, "outer", 5) == 0 || memcmp(q, "OUTER", 5) == 0) {
                    st = fc_fail(err, SR_E_FORMAT, name, "line %zu: stray 'outer'", r.number);
                    goto out;
                }
            continue;
        }
        if (!fc_next_token(&p, e, &ts, &te, 0) || !fc_token_is(ts, te, "loop") ||
            fc_next_token(&p, e, &ts, &te, 0)) {
            st = fc_fail(err, SR_E_FORMAT, name, "line %zu: expected 'outer loop'", r.number);
            goto out;
        }
        size_t facet = f.face_count;
        if (!fc_grow((void **)&f.corners, &cap, 9 * (facet + 1), sizeof *f.corners)) {
            st = fc_fail(err, SR_E_NOMEM, name, "out of memory at facet %zu", facet);
            goto out;
        }
        float *c = f.corners + 9 * facet;
        for (int k = 0; k < 3; k++) {
            if (!fc_next_line(&r, &s, &e)) {
                st = fc_fail(err, SR_E_FORMAT, name, "facet %zu is cut off after %d vertices",
                             facet, k);
                goto out;
            }
            p = s;
            if (!fc_next_token(&p, e, &ts, &te, 0) || !fc_token_is(ts, te, "vertex")) {
                st = fc_fail(err, SR_E_FORMAT, name,
                             "line %zu: expected 'vertex x y z' in facet %zu", r.number, facet);
                goto out;
            }
            for (int j = 0; j < 3; j++) {
                double v;
                if (!fc_next_token(&p, e, &ts, &te, 0) || !fc_parse_real(ts, te, &v)) {
                    st = fc_fail(err, SR_E_FORMAT, name, "line %zu: 'vertex' needs three numbers",
                                 r.number);
                    goto out;
                }
                if (!isfinite(v)) {
                    st = fc_fail(err, SR_E_INVALID, name, "facet %zu has %s coordinate (line %zu)",
                                 facet, fc_nonfinite_word(v), r.number);
                    goto out;
                }
                float fv = (float)v;
                if (!isfinite(fv)) {
                    st = fc_fail(err, SR_E_INVALID, name,
                                 "facet %zu has coordinate %s beyond float range (line %zu)", facet,
                                 fc_token_str(ts, te, tok), r.number);
                    goto out;
                }
                c[3 * k + j] = fv;
            }
            if (fc_next_token(&p, e, &ts, &te, 0)) {
                st = fc_fail(err, SR_E_FORMAT, name, "line %zu: 'vertex' needs three numbers",
                             r.number);
                goto out;
            }
        }
        st = sr_envelope_check_corners(c, 1, facet, name, err);
        if (st != SR_OK)
            goto out;
        if (degenerate_facet(c))
            f.degenerate_tris++;
        f.face_count++;
    }
    f.tri_count = f.face_count;
    f.vertex_count = 3 * f.face_count;
    *out = f;
    return SR_OK;
out:
    sr_file_facts_release(&f);
    return st;
}

sr_status sr_file_check_stl(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    size_t i = 0;
    while (i < size && (fc_blank(data[i]) || data[i] == '\n'))
        i++;
    int solid = size - i >= 5 && strncasecmp((const char *)data + i, "solid", 5) == 0 &&
                (size - i == 5 || fc_blank(data[i + 5]) || data[i + 5] == '\n');
    if (!solid)
        return check_stl_binary(data, size, name, out, err);
    /* "solid" can start the 80-byte header of a binary file too. */
    if (size >= 84) {
        uint32_t n = fc_le32(data + 80);
        if (n > 0 && size == 84ull + 50ull * n)
            return check_stl_binary(data, size, name, out, err);
    }
    /* A non-text byte inside the 84-byte header (its padding, the count) makes a binary
     * STL, right or wrong; after a header that is all text it is an ASCII STL with a
     * stray byte, whose "count" would be text ("rtex": 2019914866 triangles). */
    size_t bad = fc_first_binary_byte(data, size);
    if (bad < size) {
        if (bad < 84)
            return check_stl_binary(data, size, name, out, err);
        return fc_fail(err, SR_E_FORMAT, name,
                       "neither a binary STL (%zu bytes is not 84 + 50 x the header's triangle "
                       "count) nor ASCII STL text (byte 0x%02x at offset %zu)",
                       size, data[bad], bad);
    }
    return check_stl_ascii(data, size, name, out, err);
}

void sr_file_stl_blank_names(unsigned char *data, size_t size)
{
    fc_line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    while (fc_next_line(&r, &s, &e)) {
        const char *p = s;
        if (!fc_next_token(&p, e, &ts, &te, 0))
            continue;
        if (fc_token_is(ts, te, "outer")) {
            for (const char *q = ts; q < te; q++)   /* OpenMesh knows "outer" and "OUTER" */
                data[q - (const char *)data] = (unsigned char)(*q | 0x20);
            continue;
        }
        if (fc_token_is(ts, te, "facet") || fc_token_is(ts, te, "vertex") ||
            fc_token_is(ts, te, "endloop") || fc_token_is(ts, te, "endfacet"))
            continue;
        for (const char *q = s; q < e; q++)
            if (*q != '\r')
                data[q - (const char *)data] = ' ';
    }
}
