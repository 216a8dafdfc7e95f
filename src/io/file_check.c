/*
 * file_check.c: byte-level checks of STL, OBJ, OFF, PLY and GLB files before a library
 * parses them (see file_check.h for the contract and shared/DEPENDENCY-NOTES.md for the
 * library faults each check exists for).
 *
 * Each checker walks the whole file once, in memory, never past `size`. Text formats
 * are read line by line with a small tokenizer; numbers must be plain decimal (or the
 * words nan/inf, which are recognised only to be refused). Counts declared in headers
 * are checked against the bytes that follow before anything is allocated from them.
 */
#include "io/file_check.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- messages ---------------------------------------------------------------------- */

static sr_status fail(sr_err *err, sr_status status, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static sr_status fail(sr_err *err, sr_status status, const char *name, const char *fmt, ...)
{
    if (err) {
        char detail[400];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(detail, sizeof detail, fmt, ap);
        va_end(ap);
        sr_err_set(err, status, "cannot read '%s': %s", name, detail);
    }
    return status;
}

void sr_file_facts_release(sr_file_facts *facts)
{
    if (!facts)
        return;
    free(facts->xyz);
    free(facts->face_size);
    free(facts->face_index);
    memset(facts, 0, sizeof *facts);
}

/* Grows *ptr (elements of elem bytes, capacity *cap) to hold at least need elements. */
static int grow(void **ptr, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return 1;
    size_t n = *cap ? *cap : 64;
    while (n < need) {
        if (n > SIZE_MAX / 2 / elem)
            return 0;
        n *= 2;
    }
    void *p = realloc(*ptr, n * elem);
    if (!p)
        return 0;
    *ptr = p;
    *cap = n;
    return 1;
}

/* ---- text helpers -------------------------------------------------------------------- */

/* Offset of the first byte that cannot be in a text file (controls other than
 * \t \n \v \f \r, and DEL), or size if there is none. Bytes >= 0x80 are text (UTF-8). */
static size_t first_binary_byte(const unsigned char *data, size_t size)
{
    for (size_t i = 0; i < size; i++) {
        unsigned char c = data[i];
        if ((c < 0x20 && !(c >= '\t' && c <= '\r')) || c == 0x7f)
            return i;
    }
    return size;
}

static int blank(int c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* A line [p, e) of the file and where the next one starts. */
typedef struct line_reader {
    const char *pos, *end;
    size_t number;     /* 1-based number of the line last returned */
} line_reader;

static int next_line(line_reader *r, const char **s, const char **e)
{
    if (r->pos >= r->end)
        return 0;
    const char *nl = memchr(r->pos, '\n', (size_t)(r->end - r->pos));
    *s = r->pos;
    *e = nl ? nl : r->end;
    r->pos = nl ? nl + 1 : r->end;
    r->number++;
    return 1;
}

/* Next whitespace-separated token of [*p, e); stops at '#' when hash_comments. */
static int next_token(const char **p, const char *e, const char **ts, const char **te,
                      int hash_comments)
{
    const char *q = *p;
    while (q < e && blank((unsigned char)*q))
        q++;
    if (q >= e || (hash_comments && *q == '#')) {
        *p = e;
        return 0;
    }
    *ts = q;
    while (q < e && !blank((unsigned char)*q))
        q++;
    *te = q;
    *p = q;
    return 1;
}

/* Token equals word, ignoring case (STL keywords). */
static int token_is(const char *s, const char *e, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(e - s) == n && strncasecmp(s, word, n) == 0;
}

/* Token equals word exactly (OBJ and PLY keywords: their readers are case-sensitive). */
static int token_eq(const char *s, const char *e, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(e - s) == n && memcmp(s, word, n) == 0;
}

/* Copies a token for messages (shortened, NUL-terminated). */
static const char *token_str(const char *s, const char *e, char buf[40])
{
    size_t n = (size_t)(e - s);
    if (n > 32) {
        memcpy(buf, s, 29);
        memcpy(buf + 29, "...", 4);
    } else {
        memcpy(buf, s, n);
        buf[n] = '\0';
    }
    return buf;
}

/* A decimal number [s, e): [+-] digits [. digits] [e [+-] digits], at least one digit,
 * or [+-] nan / inf / infinity (returned as such, for the caller to refuse). */
static int parse_real(const char *s, const char *e, double *out)
{
    char buf[128];
    size_t n = (size_t)(e - s);
    if (n == 0 || n >= sizeof buf)
        return 0;
    memcpy(buf, s, n);
    buf[n] = '\0';
    const char *q = buf;
    if (*q == '+' || *q == '-')
        q++;
    if (strcasecmp(q, "nan") == 0 || strcasecmp(q, "inf") == 0 ||
        strcasecmp(q, "infinity") == 0) {
        double v = (q[0] == 'n' || q[0] == 'N') ? NAN : INFINITY;
        *out = buf[0] == '-' ? -v : v;
        return 1;
    }
    int digits = 0;
    while (*q >= '0' && *q <= '9')
        q++, digits++;
    if (*q == '.') {
        q++;
        while (*q >= '0' && *q <= '9')
            q++, digits++;
    }
    if (!digits)
        return 0;
    if (*q == 'e' || *q == 'E') {
        q++;
        if (*q == '+' || *q == '-')
            q++;
        if (!(*q >= '0' && *q <= '9'))
            return 0;
        while (*q >= '0' && *q <= '9')
            q++;
    }
    if (*q)
        return 0;
    char *end = NULL;
    double v = strtod(buf, &end);
    if (end != buf + n)
        return 0;   /* e.g. a locale whose decimal point is not '.' */
    *out = v;
    return 1;
}

/* A decimal integer [s, e) with optional sign, |value| < 2^62. */
static int parse_int(const char *s, const char *e, long long *out)
{
    int neg = 0;
    if (s < e && (*s == '+' || *s == '-'))
        neg = *s++ == '-';
    if (s >= e || e - s > 18)
        return 0;
    long long v = 0;
    for (; s < e; s++) {
        if (*s < '0' || *s > '9')
            return 0;
        v = v * 10 + (*s - '0');
    }
    *out = neg ? -v : v;
    return 1;
}

static const char *nonfinite_word(double v)
{
    return isnan(v) ? "a NaN" : "an infinite";
}

/* ---- STL ------------------------------------------------------------------------------- */

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float lef32(const unsigned char *p)
{
    uint32_t u = le32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* OpenMesh's STL reader merges corners whose coordinates differ by at most FLT_MIN. */
static int same_point(const double *a, const double *b)
{
    return fabs(a[0] - b[0]) <= FLT_MIN && fabs(a[1] - b[1]) <= FLT_MIN &&
           fabs(a[2] - b[2]) <= FLT_MIN;
}

static int degenerate_facet(const double *c)
{
    return same_point(c, c + 3) || same_point(c, c + 6) || same_point(c + 3, c + 6);
}

static sr_status check_stl_binary(const unsigned char *data, size_t size, const char *name,
                                  sr_file_facts *out, sr_err *err)
{
    if (size < 84)
        return fail(err, SR_E_FORMAT, name,
                    "too short for a binary STL (%zu bytes, the header alone takes 84)", size);
    uint32_t n = le32(data + 80);
    unsigned long long expect = 84ull + 50ull * n;
    size_t holds = (size - 84) / 50;
    if (size < expect)
        return fail(err, SR_E_FORMAT, name,
                    "truncated binary STL (header says %u triangles, file holds %zu)", n, holds);
    if (size > expect) {
        if ((size - 84) % 50 == 0)
            return fail(err, SR_E_FORMAT, name,
                        "binary STL header says %u triangles, file holds %zu", n, holds);
        return fail(err, SR_E_FORMAT, name,
                    "binary STL has %llu trailing bytes after its %u triangles",
                    (unsigned long long)size - expect, n);
    }
    sr_file_facts f = {0};
    f.binary = 1;
    f.face_count = f.tri_count = n;
    f.vertex_count = 3 * (size_t)n;
    if (n) {
        f.xyz = malloc((size_t)n * 9 * sizeof *f.xyz);
        if (!f.xyz)
            return fail(err, SR_E_NOMEM, name, "out of memory for %u triangles", n);
    }
    for (size_t t = 0; t < n; t++) {
        const unsigned char *rec = data + 84 + 50 * t + 12;   /* skip the normal */
        double *c = f.xyz + 9 * t;
        for (int k = 0; k < 9; k++) {
            float v = lef32(rec + 4 * k);
            if (!isfinite(v)) {
                sr_file_facts_release(&f);
                return fail(err, SR_E_INVALID, name,
                            "binary STL triangle %zu has %s coordinate", t, nonfinite_word(v));
            }
            c[k] = v;
        }
        if (degenerate_facet(c))
            f.degenerate_tris++;
    }
    *out = f;
    return SR_OK;
}

static sr_status check_stl_ascii(const unsigned char *data, size_t size, const char *name,
                                 sr_file_facts *out, sr_err *err)
{
    sr_file_facts f = {0};
    size_t cap = 0;
    sr_status st = SR_OK;
    line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    char tok[40];
    while (next_line(&r, &s, &e)) {
        const char *p = s;
        if (!next_token(&p, e, &ts, &te, 0))
            continue;
        if (token_is(ts, te, "vertex")) {
            st = fail(err, SR_E_FORMAT, name, "line %zu: 'vertex' outside an 'outer loop'",
                      r.number);
            goto out;
        }
        if (!token_is(ts, te, "outer")) {
            /* facet/endloop/endfacet stay visible to the reader: no stray "outer" there. */
            int kept = token_is(ts, te, "facet") || token_is(ts, te, "endloop") ||
                       token_is(ts, te, "endfacet");
            for (const char *q = s; kept && q + 5 <= e; q++)
                if (memcmp(q, "outer", 5) == 0 || memcmp(q, "OUTER", 5) == 0) {
                    st = fail(err, SR_E_FORMAT, name, "line %zu: stray 'outer'", r.number);
                    goto out;
                }
            continue;
        }
        if (!next_token(&p, e, &ts, &te, 0) || !token_is(ts, te, "loop") ||
            next_token(&p, e, &ts, &te, 0)) {
            st = fail(err, SR_E_FORMAT, name, "line %zu: expected 'outer loop'", r.number);
            goto out;
        }
        size_t facet = f.face_count;
        if (!grow((void **)&f.xyz, &cap, 9 * (facet + 1), sizeof *f.xyz)) {
            st = fail(err, SR_E_NOMEM, name, "out of memory at facet %zu", facet);
            goto out;
        }
        double *c = f.xyz + 9 * facet;
        for (int k = 0; k < 3; k++) {
            if (!next_line(&r, &s, &e)) {
                st = fail(err, SR_E_FORMAT, name, "facet %zu is cut off after %d vertices",
                          facet, k);
                goto out;
            }
            p = s;
            if (!next_token(&p, e, &ts, &te, 0) || !token_is(ts, te, "vertex")) {
                st = fail(err, SR_E_FORMAT, name,
                          "line %zu: expected 'vertex x y z' in facet %zu", r.number, facet);
                goto out;
            }
            for (int j = 0; j < 3; j++) {
                double v;
                if (!next_token(&p, e, &ts, &te, 0) || !parse_real(ts, te, &v)) {
                    st = fail(err, SR_E_FORMAT, name, "line %zu: 'vertex' needs three numbers",
                              r.number);
                    goto out;
                }
                if (!isfinite(v)) {
                    st = fail(err, SR_E_INVALID, name, "facet %zu has %s coordinate (line %zu)",
                              facet, nonfinite_word(v), r.number);
                    goto out;
                }
                float fv = (float)v;
                if (!isfinite(fv)) {
                    st = fail(err, SR_E_INVALID, name,
                              "facet %zu has coordinate %s beyond float range (line %zu)", facet,
                              token_str(ts, te, tok), r.number);
                    goto out;
                }
                c[3 * k + j] = fv;
            }
            if (next_token(&p, e, &ts, &te, 0)) {
                st = fail(err, SR_E_FORMAT, name, "line %zu: 'vertex' needs three numbers",
                          r.number);
                goto out;
            }
        }
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
    while (i < size && (blank(data[i]) || data[i] == '\n'))
        i++;
    int solid = size - i >= 5 && strncasecmp((const char *)data + i, "solid", 5) == 0 &&
                (size - i == 5 || blank(data[i + 5]) || data[i + 5] == '\n');
    if (!solid)
        return check_stl_binary(data, size, name, out, err);
    /* "solid" can start the 80-byte header of a binary file too. */
    if (size >= 84) {
        uint32_t n = le32(data + 80);
        if (n > 0 && size == 84ull + 50ull * n)
            return check_stl_binary(data, size, name, out, err);
    }
    if (first_binary_byte(data, size) < size)
        return check_stl_binary(data, size, name, out, err);
    return check_stl_ascii(data, size, name, out, err);
}

void sr_file_stl_blank_names(unsigned char *data, size_t size)
{
    line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    while (next_line(&r, &s, &e)) {
        const char *p = s;
        if (!next_token(&p, e, &ts, &te, 0))
            continue;
        if (token_is(ts, te, "outer")) {
            for (const char *q = ts; q < te; q++)   /* OpenMesh knows "outer" and "OUTER" */
                data[q - (const char *)data] = (unsigned char)(*q | 0x20);
            continue;
        }
        if (token_is(ts, te, "facet") || token_is(ts, te, "vertex") ||
            token_is(ts, te, "endloop") || token_is(ts, te, "endfacet"))
            continue;
        for (const char *q = s; q < e; q++)
            if (*q != '\r')
                data[q - (const char *)data] = ' ';
    }
}

/* ---- OBJ ------------------------------------------------------------------------------- */

/* Faces being collected (OBJ, OFF, PLY). */
typedef struct face_acc {
    size_t size_cap, index_cap, index_count;
} face_acc;

static int add_face(sr_file_facts *f, face_acc *a, const uint32_t *idx, size_t k)
{
    if (!grow((void **)&f->face_size, &a->size_cap, f->face_count + 1, sizeof *f->face_size) ||
        !grow((void **)&f->face_index, &a->index_cap, a->index_count + k,
              sizeof *f->face_index))
        return 0;
    f->face_size[f->face_count++] = (uint32_t)k;
    memcpy(f->face_index + a->index_count, idx, k * sizeof *idx);
    a->index_count += k;
    f->tri_count += k - 2;
    /* A reader drops the whole face when a vertex repeats. */
    for (size_t i = 0; i < k; i++)
        for (size_t j = i + 1; j < k; j++)
            if (idx[i] == idx[j]) {
                f->degenerate_tris += k - 2;
                return 1;
            }
    return 1;
}

/* Face corners of one record, grown as needed. */
typedef struct corner_buf {
    uint32_t *v;
    size_t cap;
} corner_buf;

/* After a vertex reference's index: nothing, "/t", "/t/n" or "//n" with integers t, n. */
static int obj_ref_tail(const char *slash, const char *e)
{
    long long v;
    if (!slash)
        return 1;
    const char *s2 = memchr(slash + 1, '/', (size_t)(e - slash - 1));
    if (!s2)
        return parse_int(slash + 1, e, &v);
    return (s2 == slash + 1 || parse_int(slash + 1, s2, &v)) && parse_int(s2 + 1, e, &v);
}

sr_status sr_file_check_obj(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    size_t bad = first_binary_byte(data, size);
    if (bad < size)
        return fail(err, SR_E_FORMAT, name, "not a text OBJ file (byte 0x%02x at offset %zu)",
                    data[bad], bad);
    sr_file_facts f = {0};
    face_acc acc = {0};
    corner_buf cb = {0};
    size_t xyz_cap = 0;
    long long max_ref = 0;
    size_t max_ref_line = 0;
    sr_status st = SR_OK;
    line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    char tok[40];
    while (next_line(&r, &s, &e)) {
        const char *p = s;
        if (!next_token(&p, e, &ts, &te, 1))
            continue;
        if (token_eq(ts, te, "v")) {
            if (f.vertex_count >= UINT32_MAX) {
                st = fail(err, SR_E_FORMAT, name, "more than %u vertices", UINT32_MAX);
                goto out;
            }
            if (!grow((void **)&f.xyz, &xyz_cap, 3 * (f.vertex_count + 1), sizeof *f.xyz)) {
                st = fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
                goto out;
            }
            for (int j = 0; j < 3; j++) {
                double v;
                if (!next_token(&p, e, &ts, &te, 1) || !parse_real(ts, te, &v)) {
                    st = fail(err, SR_E_FORMAT, name, "line %zu: 'v' needs three numbers",
                              r.number);
                    goto out;
                }
                if (!isfinite(v)) {
                    st = fail(err, SR_E_INVALID, name,
                              "vertex %zu has %s coordinate (line %zu)", f.vertex_count,
                              nonfinite_word(v), r.number);
                    goto out;
                }
                f.xyz[3 * f.vertex_count + j] = v;
            }
            f.vertex_count++;
        } else if (token_eq(ts, te, "f")) {
            size_t k = 0;
            while (next_token(&p, e, &ts, &te, 1)) {
                const char *slash = memchr(ts, '/', (size_t)(te - ts));
                long long i;
                if (!parse_int(ts, slash ? slash : te, &i) || !obj_ref_tail(slash, te)) {
                    st = fail(err, SR_E_FORMAT, name, "line %zu: bad vertex reference '%s'",
                              r.number, token_str(ts, te, tok));
                    goto out;
                }
                if (i == 0) {
                    st = fail(err, SR_E_INVALID, name,
                              "face on line %zu uses vertex index 0 (OBJ counts from 1)",
                              r.number);
                    goto out;
                }
                if (i < 0) {
                    i += (long long)f.vertex_count;   /* relative to vertices so far */
                    if (i < 0) {
                        st = fail(err, SR_E_INVALID, name,
                                  "face on line %zu refers to vertex %s before the first one",
                                  r.number, token_str(ts, te, tok));
                        goto out;
                    }
                } else {
                    if (i > max_ref) {
                        max_ref = i;
                        max_ref_line = r.number;
                    }
                    if (i > (long long)UINT32_MAX) {
                        st = fail(err, SR_E_INVALID, name,
                                  "face on line %zu uses vertex %lld, beyond any vertex count",
                                  r.number, i);
                        goto out;
                    }
                    i -= 1;
                }
                if (!grow((void **)&cb.v, &cb.cap, k + 1, sizeof *cb.v)) {
                    st = fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
                    goto out;
                }
                cb.v[k++] = (uint32_t)i;
            }
            if (k < 3) {
                st = fail(err, SR_E_FORMAT, name, "face on line %zu has only %zu vertices",
                          r.number, k);
                goto out;
            }
            if (!add_face(&f, &acc, cb.v, k)) {
                st = fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
                goto out;
            }
        }
        /* vt, vn, vp, l, p, o, g, s, usemtl, mtllib and unknown lines carry no faces. */
    }
    if (max_ref > (long long)f.vertex_count) {
        st = fail(err, SR_E_INVALID, name, "face on line %zu uses vertex %lld, file has %zu",
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
    line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *ts, *te;
    while (next_line(&r, &s, &e)) {
        const char *p = s;
        if (next_token(&p, e, &ts, &te, 1) && token_eq(ts, te, "mtllib"))
            data[ts - (const char *)data] = '#';
    }
}

/* ---- OFF ------------------------------------------------------------------------------- */

/* Next line holding a token (blank and '#' lines skipped); its first token in ts/te. */
static int next_content_line(line_reader *r, const char **p, const char **e, const char **ts,
                             const char **te)
{
    const char *s;
    while (next_line(r, &s, e)) {
        *p = s;
        if (next_token(p, *e, ts, te, 1))
            return 1;
    }
    return 0;
}

sr_status sr_file_check_off(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    size_t bad = first_binary_byte(data, size);
    line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *p, *e, *ts, *te;
    char tok[40];
    if (!next_content_line(&r, &p, &e, &ts, &te))
        return fail(err, SR_E_FORMAT, name, "no OFF header");
    /* [ST][C][N][4][n]OFF */
    const char *k = ts;
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
    if (!token_is(k, te, "OFF") || memcmp(k, "OFF", 3) != 0)
        return fail(err, SR_E_FORMAT, name, "not an OFF file (starts with '%s')",
                    token_str(ts, te, tok));
    if (dim4 || dimn)
        return fail(err, SR_E_UNSUPPORTED, name, "'%s' (4D or n-D OFF) is not supported",
                    token_str(ts, te, tok));
    long long cnt[3];
    int have = 0;
    if (next_token(&p, e, &ts, &te, 1)) {
        if (token_is(ts, te, "BINARY"))
            return fail(err, SR_E_UNSUPPORTED, name, "binary OFF is not supported");
        if (!parse_int(ts, te, &cnt[0]))
            return fail(err, SR_E_FORMAT, name, "line %zu: bad OFF count '%s'", r.number,
                        token_str(ts, te, tok));
        have = 1;
    } else if (!next_content_line(&r, &p, &e, &ts, &te) || !parse_int(ts, te, &cnt[0])) {
        return fail(err, SR_E_FORMAT, name, "OFF header has no vertex/face/edge counts");
    } else {
        have = 1;
    }
    while (have < 3 && next_token(&p, e, &ts, &te, 1) && parse_int(ts, te, &cnt[have]))
        have++;
    if (have < 3 || next_token(&p, e, &ts, &te, 1))
        return fail(err, SR_E_FORMAT, name,
                    "line %zu: OFF counts need three numbers (vertices faces edges)", r.number);
    if (bad < size)
        return fail(err, SR_E_FORMAT, name, "not a text OFF file (byte 0x%02x at offset %zu)",
                    data[bad], bad);
    if (cnt[0] < 0 || cnt[1] < 0 || cnt[2] < 0)
        return fail(err, SR_E_FORMAT, name, "negative OFF count on line %zu", r.number);
    /* The shortest vertex line is "0 0 0\n" (6 bytes), the shortest face "3 0 1 2\n". */
    size_t rest = (size_t)(r.end - r.pos);
    if (cnt[0] > (long long)UINT32_MAX || cnt[1] > (long long)UINT32_MAX ||
        (unsigned long long)cnt[0] * 6 + (unsigned long long)cnt[1] * 8 > rest + 1)
        return fail(err, SR_E_FORMAT, name,
                    "OFF header declares %lld vertices and %lld faces, more than the %zu bytes "
                    "after it can hold", cnt[0], cnt[1], rest);
    sr_file_facts f = {0};
    face_acc acc = {0};
    corner_buf cb = {0};
    sr_status st = SR_OK;
    size_t nv = (size_t)cnt[0], nf = (size_t)cnt[1];
    if (nv) {
        f.xyz = malloc(nv * 3 * sizeof *f.xyz);
        if (!f.xyz)
            return fail(err, SR_E_NOMEM, name, "out of memory for %zu vertices", nv);
    }
    for (size_t v = 0; v < nv; v++) {
        if (!next_content_line(&r, &p, &e, &ts, &te)) {
            st = fail(err, SR_E_FORMAT, name, "OFF file ends after %zu of %zu vertices", v, nv);
            goto out;
        }
        for (int j = 0; j < 3; j++) {
            double x;
            if ((j > 0 && !next_token(&p, e, &ts, &te, 1)) || !parse_real(ts, te, &x)) {
                st = fail(err, SR_E_FORMAT, name, "line %zu: vertex %zu needs three numbers",
                          r.number, v);
                goto out;
            }
            if (!isfinite(x)) {
                st = fail(err, SR_E_INVALID, name, "vertex %zu has %s coordinate (line %zu)", v,
                          nonfinite_word(x), r.number);
                goto out;
            }
            f.xyz[3 * v + j] = x;
        }
    }
    f.vertex_count = nv;
    for (size_t i = 0; i < nf; i++) {
        long long n;
        if (!next_content_line(&r, &p, &e, &ts, &te)) {
            st = fail(err, SR_E_FORMAT, name, "OFF file ends after %zu of %zu faces", i, nf);
            goto out;
        }
        if (!parse_int(ts, te, &n) || n < 3 || n > (long long)(e - p) / 2 + 1) {
            st = fail(err, SR_E_FORMAT, name, "line %zu: face %zu has a bad corner count '%s'",
                      r.number, i, token_str(ts, te, tok));
            goto out;
        }
        if (!grow((void **)&cb.v, &cb.cap, (size_t)n, sizeof *cb.v)) {
            st = fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
            goto out;
        }
        for (long long c = 0; c < n; c++) {
            long long idx;
            if (!next_token(&p, e, &ts, &te, 1) || !parse_int(ts, te, &idx)) {
                st = fail(err, SR_E_FORMAT, name, "line %zu: face %zu needs %lld indices",
                          r.number, i, n);
                goto out;
            }
            if (idx < 0 || (unsigned long long)idx >= nv) {
                st = fail(err, SR_E_INVALID, name,
                          "face %zu (line %zu) uses vertex %lld, file has %zu", i, r.number, idx,
                          nv);
                goto out;
            }
            cb.v[c] = (uint32_t)idx;
        }
        if (!add_face(&f, &acc, cb.v, (size_t)n)) {
            st = fail(err, SR_E_NOMEM, name, "out of memory at line %zu", r.number);
            goto out;
        }
    }
    free(cb.v);
    *out = f;
    return SR_OK;
out:
    free(cb.v);
    sr_file_facts_release(&f);
    return st;
}

/* ---- PLY ------------------------------------------------------------------------------- */

typedef enum ply_type { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

static const struct {
    const char *name;
    ply_type type;
} ply_type_names[] = {
    {"char", T_I8},   {"int8", T_I8},     {"uchar", T_U8},  {"uint8", T_U8},
    {"short", T_I16}, {"int16", T_I16},   {"ushort", T_U16}, {"uint16", T_U16},
    {"int", T_I32},   {"int32", T_I32},   {"uint", T_U32},  {"uint32", T_U32},
    {"float", T_F32}, {"float32", T_F32}, {"double", T_F64}, {"float64", T_F64},
};

static const size_t ply_type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

static ply_type ply_type_of(const char *s, const char *e)
{
    for (size_t i = 0; i < sizeof ply_type_names / sizeof ply_type_names[0]; i++)
        if ((size_t)(e - s) == strlen(ply_type_names[i].name) &&
            memcmp(s, ply_type_names[i].name, (size_t)(e - s)) == 0)
            return ply_type_names[i].type;
    return T_NONE;
}

#define PLY_MAX_ELEMENTS 32
#define PLY_MAX_PROPS 256
#define PLY_NAME 32

typedef struct ply_prop {
    ply_type type;        /* scalar type, or the list's item type */
    ply_type count_type;  /* T_NONE for a scalar */
    char count_name[PLY_NAME];   /* the list length's type as written */
    char name[PLY_NAME];
} ply_prop;

typedef struct ply_elem {
    char name[PLY_NAME];
    unsigned long long count;
    size_t first_prop, prop_count;
} ply_elem;

enum { PLY_ASCII, PLY_LE, PLY_BE };

typedef struct ply_header {
    int format;
    size_t elem_count, prop_count;
    ply_elem elem[PLY_MAX_ELEMENTS];
    ply_prop prop[PLY_MAX_PROPS];
    size_t body;          /* offset of the first body byte */
} ply_header;

static int copy_name(char dst[PLY_NAME], const char *s, const char *e)
{
    if ((size_t)(e - s) >= PLY_NAME)
        return 0;
    memcpy(dst, s, (size_t)(e - s));
    dst[e - s] = '\0';
    return 1;
}

static sr_status ply_read_header(const unsigned char *data, size_t size, const char *name,
                                 ply_header *h, sr_err *err)
{
    line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *p, *ts, *te;
    char tok[40];
    memset(h, 0, sizeof *h);
    h->format = -1;
    if (!next_line(&r, &s, &e) || !(p = s, next_token(&p, e, &ts, &te, 0)) ||
        !token_eq(ts, te, "ply") || next_token(&p, e, &ts, &te, 0))
        return fail(err, SR_E_FORMAT, name, "not a PLY file (first line is not 'ply')");
    for (;;) {
        if (!next_line(&r, &s, &e))
            return fail(err, SR_E_FORMAT, name, "PLY header has no end_header");
        size_t ln = r.number;
        p = s;
        if (!next_token(&p, e, &ts, &te, 0))
            return fail(err, SR_E_FORMAT, name, "PLY header line %zu is blank", ln);
        if (token_eq(ts, te, "comment") || token_eq(ts, te, "obj_info"))
            continue;
        if (token_eq(ts, te, "end_header")) {
            if (next_token(&p, e, &ts, &te, 0))
                return fail(err, SR_E_FORMAT, name, "PLY header line %zu: text after end_header",
                            ln);
            break;
        }
        if (token_eq(ts, te, "format")) {
            const char *fs, *fe, *vs, *ve;
            if (h->format >= 0 || h->elem_count)
                return fail(err, SR_E_FORMAT, name, "PLY header line %zu: misplaced 'format'", ln);
            if (!next_token(&p, e, &fs, &fe, 0) || !next_token(&p, e, &vs, &ve, 0) ||
                next_token(&p, e, &ts, &te, 0))
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: 'format' needs a type and a version", ln);
            if (token_eq(fs, fe, "ascii"))
                h->format = PLY_ASCII;
            else if (token_eq(fs, fe, "binary_little_endian"))
                h->format = PLY_LE;
            else if (token_eq(fs, fe, "binary_big_endian"))
                h->format = PLY_BE;
            else
                return fail(err, SR_E_FORMAT, name, "PLY header line %zu: unknown format '%s'",
                            ln, token_str(fs, fe, tok));
            if (!token_eq(vs, ve, "1.0"))
                return fail(err, SR_E_UNSUPPORTED, name, "PLY version '%s' (only 1.0)",
                            token_str(vs, ve, tok));
            continue;
        }
        if (h->format < 0)
            return fail(err, SR_E_FORMAT, name, "PLY header line %zu: 'format' must come first",
                        ln);
        if (token_eq(ts, te, "element")) {
            const char *ns, *ne, *cs, *ce;
            long long count;
            if (!next_token(&p, e, &ns, &ne, 0) || !next_token(&p, e, &cs, &ce, 0) ||
                next_token(&p, e, &ts, &te, 0))
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: 'element' needs a name and a count", ln);
            if (*cs == '-' || *cs == '+' || !parse_int(cs, ce, &count) ||
                count > (long long)UINT32_MAX)
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: element count '%s' is not a number", ln,
                            token_str(cs, ce, tok));
            if (h->elem_count == PLY_MAX_ELEMENTS)
                return fail(err, SR_E_FORMAT, name, "PLY header has more than %d elements",
                            PLY_MAX_ELEMENTS);
            ply_elem *el = &h->elem[h->elem_count];
            if (!copy_name(el->name, ns, ne))
                return fail(err, SR_E_FORMAT, name, "PLY header line %zu: element name too long",
                            ln);
            for (size_t i = 0; i < h->elem_count; i++)
                if (strcmp(h->elem[i].name, el->name) == 0)
                    return fail(err, SR_E_FORMAT, name, "PLY header repeats element '%s'",
                                el->name);
            el->count = (unsigned long long)count;
            el->first_prop = h->prop_count;
            el->prop_count = 0;
            h->elem_count++;
            continue;
        }
        if (token_eq(ts, te, "property")) {
            if (!h->elem_count)
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: 'property' before any element", ln);
            if (h->prop_count == PLY_MAX_PROPS)
                return fail(err, SR_E_FORMAT, name, "PLY header has more than %d properties",
                            PLY_MAX_PROPS);
            ply_prop *pr = &h->prop[h->prop_count];
            const char *as, *ae;
            if (!next_token(&p, e, &as, &ae, 0))
                return fail(err, SR_E_FORMAT, name, "PLY header line %zu: 'property' needs a type",
                            ln);
            pr->count_type = T_NONE;
            if (token_eq(as, ae, "list")) {
                const char *cs2, *ce2, *is, *ie;
                if (!next_token(&p, e, &cs2, &ce2, 0) || !next_token(&p, e, &is, &ie, 0))
                    return fail(err, SR_E_FORMAT, name,
                                "PLY header line %zu: 'property list' needs two types", ln);
                pr->count_type = ply_type_of(cs2, ce2);
                pr->type = ply_type_of(is, ie);
                if (pr->count_type != T_NONE)
                    copy_name(pr->count_name, cs2, ce2);
                if (pr->count_type == T_NONE || pr->count_type >= T_F32 || pr->type == T_NONE)
                    return fail(err, SR_E_FORMAT, name,
                                "PLY header line %zu: bad list types '%s'", ln,
                                token_str(cs2, ie, tok));
            } else {
                pr->type = ply_type_of(as, ae);
                if (pr->type == T_NONE)
                    return fail(err, SR_E_FORMAT, name,
                                "PLY header line %zu: unknown property type '%s'", ln,
                                token_str(as, ae, tok));
            }
            const char *ns, *ne;
            if (!next_token(&p, e, &ns, &ne, 0))
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: 'property' is missing its name", ln);
            if (next_token(&p, e, &ts, &te, 0))
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: text after the property name", ln);
            if (!copy_name(pr->name, ns, ne))
                return fail(err, SR_E_FORMAT, name,
                            "PLY header line %zu: property name too long", ln);
            h->prop_count++;
            h->elem[h->elem_count - 1].prop_count++;
            continue;
        }
        return fail(err, SR_E_FORMAT, name, "PLY header line %zu: unknown keyword '%s'", ln,
                    token_str(ts, te, tok));
    }
    if (h->format < 0)
        return fail(err, SR_E_FORMAT, name, "PLY header has no 'format' line");
    h->body = (size_t)(r.pos - (const char *)data);
    return SR_OK;
}

/* Reads the next value of a PLY body into *out and advances b->pos: 1 done, 0 the body
 * ended, -1 an ASCII token that is not a number of that type. Integers come back exactly
 * (every PLY integer type fits a double). */
typedef struct ply_body {
    const unsigned char *data;
    size_t pos, size;
    int format;
    const char *bad_s, *bad_e;   /* ASCII: the token that failed to parse */
} ply_body;

static int ply_next(ply_body *b, ply_type t, double *out)
{
    if (b->format == PLY_ASCII) {
        const char *p = (const char *)b->data + b->pos, *e = (const char *)b->data + b->size;
        while (p < e && (blank((unsigned char)*p) || *p == '\n'))
            p++;
        const char *s = p;
        while (p < e && !blank((unsigned char)*p) && *p != '\n')
            p++;
        if (s == p)
            return 0;
        b->bad_s = s;
        b->bad_e = p;
        if (t >= T_F32) {
            if (!parse_real(s, p, out))
                return -1;
        } else {
            long long v;
            if (!parse_int(s, p, &v))
                return -1;
            *out = (double)v;
        }
        b->pos = (size_t)(p - (const char *)b->data);
        return 1;
    }
    size_t n = ply_type_size[t];
    if (b->size - b->pos < n)
        return 0;
    unsigned char c[8];
    for (size_t i = 0; i < n; i++)
        c[i] = b->data[b->pos + (b->format == PLY_LE ? i : n - 1 - i)];
    b->pos += n;
    uint32_t u32 = (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16 |
                   (uint32_t)c[3] << 24;
    switch (t) {
    case T_I8: *out = (int8_t)c[0]; break;
    case T_U8: *out = c[0]; break;
    case T_I16: *out = (int16_t)(uint16_t)(c[0] | c[1] << 8); break;
    case T_U16: *out = (uint16_t)(c[0] | c[1] << 8); break;
    case T_I32: *out = (int32_t)u32; break;
    case T_U32: *out = u32; break;
    case T_F32: {
        float f;
        memcpy(&f, &u32, 4);
        *out = f;
        break;
    }
    case T_F64: {
        uint64_t u64 = (uint64_t)u32 | (uint64_t)((uint32_t)c[4] | (uint32_t)c[5] << 8 |
                                                  (uint32_t)c[6] << 16 | (uint32_t)c[7] << 24)
                                           << 32;
        double d;
        memcpy(&d, &u64, 8);
        *out = d;
        break;
    }
    default: return -1;
    }
    return 1;
}

sr_status sr_file_check_ply(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    ply_header *h = malloc(sizeof *h);
    if (!h)
        return fail(err, SR_E_NOMEM, name, "out of memory");
    sr_file_facts f = {0};
    face_acc acc = {0};
    corner_buf cb = {0};
    sr_status st = ply_read_header(data, size, name, h, err);
    if (st)
        goto out;
    /* Roles: x, y, z of `vertex`; the index list of `face`. */
    long vertex_el = -1, face_el = -1, face_list = -1, coord[3] = {-1, -1, -1};
    for (size_t i = 0; i < h->elem_count; i++) {
        ply_elem *el = &h->elem[i];
        if (el->count && !el->prop_count) {
            st = fail(err, SR_E_FORMAT, name, "PLY element '%s' has no properties", el->name);
            goto out;
        }
        if (strcmp(el->name, "vertex") == 0) {
            vertex_el = (long)i;
            for (size_t k = 0; k < el->prop_count; k++) {
                ply_prop *pr = &h->prop[el->first_prop + k];
                static const char *const axis[3] = {"x", "y", "z"};
                for (int j = 0; j < 3; j++)
                    if (pr->count_type == T_NONE && strcmp(pr->name, axis[j]) == 0)
                        coord[j] = (long)(el->first_prop + k);
            }
        } else if (strcmp(el->name, "face") == 0) {
            face_el = (long)i;
            if (vertex_el < 0) {
                st =
                    fail(err, SR_E_UNSUPPORTED, name, "PLY face element before the vertex element");
                goto out;
            }
            for (size_t k = 0; k < el->prop_count; k++) {
                ply_prop *pr = &h->prop[el->first_prop + k];
                if (pr->count_type != T_NONE && (strcmp(pr->name, "vertex_indices") == 0 ||
                                                 strcmp(pr->name, "vertex_index") == 0))
                    face_list = (long)(el->first_prop + k);
            }
            if (face_list < 0 || h->prop[face_list].type >= T_F32) {
                st = fail(err, SR_E_FORMAT, name,
                          "PLY face element has no integer list 'vertex_indices'");
                goto out;
            }
            /* OpenMesh 9 knows only these names for a list length ("Unsupported Index
             * type for property list"), not even their synonyms int8 or int32. */
            const char *cn = h->prop[face_list].count_name;
            if (strcmp(cn, "uchar") != 0 && strcmp(cn, "uint8") != 0 && strcmp(cn, "int") != 0) {
                st =
                    fail(err, SR_E_UNSUPPORTED, name,
                         "PLY face list length type '%s' (OpenMesh reads uchar, uint8 or int)", cn);
                goto out;
            }
        }
    }
    if (vertex_el < 0 || coord[0] < 0 || coord[1] < 0 || coord[2] < 0) {
        st = fail(err, SR_E_FORMAT, name, "PLY has no vertex element with x, y and z");
        goto out;
    }
    /* Counts against the body size: the shortest row of each element. */
    size_t body = size - h->body;
    unsigned long long need = 0;
    for (size_t i = 0; i < h->elem_count; i++) {
        ply_elem *el = &h->elem[i];
        unsigned long long row = 0;
        for (size_t k = 0; k < el->prop_count; k++) {
            ply_prop *pr = &h->prop[el->first_prop + k];
            row += h->format == PLY_ASCII ? 2
                   : ply_type_size[pr->count_type != T_NONE ? pr->count_type : pr->type];
        }
        need += el->count * row;
        if (need > (unsigned long long)body + 1) {
            st =
                fail(err, SR_E_FORMAT, name,
                     "PLY header declares %llu '%s' elements, more than the %zu-byte body can hold",
                     el->count, el->name, body);
            goto out;
        }
    }
    size_t nv = (size_t)h->elem[vertex_el].count;
    if (nv) {
        f.xyz = malloc(nv * 3 * sizeof *f.xyz);
        if (!f.xyz) {
            st = fail(err, SR_E_NOMEM, name, "out of memory for %zu vertices", nv);
            goto out;
        }
    }
    f.vertex_count = nv;
    f.binary = h->format != PLY_ASCII;
    ply_body b = {data, h->body, size, h->format, NULL, NULL};
    for (size_t i = 0; i < h->elem_count; i++) {
        ply_elem *el = &h->elem[i];
        for (unsigned long long row = 0; row < el->count; row++) {
            int got = 1;
            for (size_t k = 0; k < el->prop_count; k++) {
                size_t pi = el->first_prop + k;
                ply_prop *pr = &h->prop[pi];
                double v;
                if (pr->count_type == T_NONE) {
                    got = ply_next(&b, pr->type, &v);
                    if (got <= 0)
                        goto body_error;
                    if ((long)i == vertex_el) {
                        for (int j = 0; j < 3; j++)
                            if ((long)pi == coord[j]) {
                                if (!isfinite(v)) {
                                    st = fail(err, SR_E_INVALID, name,
                                              "PLY vertex %llu has %s coordinate", row,
                                              nonfinite_word(v));
                                    goto out;
                                }
                                f.xyz[3 * row + j] = v;
                            }
                    }
                    continue;
                }
                got = ply_next(&b, pr->count_type, &v);
                if (got <= 0)
                    goto body_error;
                size_t item = h->format == PLY_ASCII ? 2 : ply_type_size[pr->type];
                if (v < 0 || v * (double)item > (double)(b.size - b.pos) + 1) {
                    st = fail(err, SR_E_FORMAT, name, "PLY %s %llu has a bad list length %.0f",
                              el->name, row, v);
                    goto out;
                }
                size_t n = (size_t)v;
                int is_face = (long)pi == face_list;
                if (is_face && n < 3) {
                    st = fail(err, SR_E_FORMAT, name, "PLY face %llu has %zu vertices", row, n);
                    goto out;
                }
                if (is_face && !grow((void **)&cb.v, &cb.cap, n, sizeof *cb.v)) {
                    st = fail(err, SR_E_NOMEM, name, "out of memory at face %llu", row);
                    goto out;
                }
                for (size_t c = 0; c < n; c++) {
                    got = ply_next(&b, pr->type, &v);
                    if (got <= 0)
                        goto body_error;
                    if (is_face) {
                        if (!(v >= 0 && v < (double)nv)) {
                            st = fail(err, SR_E_INVALID, name,
                                      "PLY face %llu uses vertex %.0f, file has %zu", row, v, nv);
                            goto out;
                        }
                        cb.v[c] = (uint32_t)v;
                    }
                }
                if (is_face && !add_face(&f, &acc, cb.v, n)) {
                    st = fail(err, SR_E_NOMEM, name, "out of memory at face %llu", row);
                    goto out;
                }
            }
            continue;
        body_error:
            if (got == 0) {
                st = fail(err, SR_E_FORMAT, name, "PLY body ends inside %s %llu of %llu",
                          el->name, row, el->count);
            } else {
                char tok[40];
                st = fail(err, SR_E_FORMAT, name, "PLY %s %llu: bad value '%s'", el->name, row,
                          token_str(b.bad_s, b.bad_e, tok));
            }
            goto out;
        }
    }
    if (h->format == PLY_ASCII) {
        for (size_t i = b.pos; i < size; i++)
            if (!blank(data[i]) && data[i] != '\n') {
                st = fail(err, SR_E_FORMAT, name, "text after the last PLY element (offset %zu)",
                          i);
                goto out;
            }
    } else if (b.pos < size) {
        st = fail(err, SR_E_FORMAT, name, "%zu bytes after the last PLY element", size - b.pos);
        goto out;
    }
    (void)face_el;
    free(cb.v);
    free(h);
    *out = f;
    return SR_OK;
out:
    free(cb.v);
    free(h);
    sr_file_facts_release(&f);
    return st;
}

/* ---- GLB and JSON ------------------------------------------------------------------- */

#define GLB_JSON 0x4E4F534Au
#define GLB_BIN 0x004E4942u

sr_status sr_file_check_glb(const unsigned char *data, size_t size, const char *name,
                            sr_glb_layout *out, sr_err *err)
{
    if (size < 12 || memcmp(data, "glTF", 4) != 0)
        return fail(err, SR_E_FORMAT, name, "not a GLB file (no 'glTF' magic)");
    uint32_t version = le32(data + 4), length = le32(data + 8);
    if (version != 2)
        return fail(err, SR_E_UNSUPPORTED, name, "GLB version %u (only 2 is supported)", version);
    if (length != size)
        return fail(err, SR_E_FORMAT, name, "GLB header says %u bytes, file holds %zu", length,
                    size);
    if (size < 20)
        return fail(err, SR_E_FORMAT, name, "GLB has no JSON chunk");
    uint32_t json_len = le32(data + 12), json_type = le32(data + 16);
    if (json_type != GLB_JSON)
        return fail(err, SR_E_FORMAT, name, "first GLB chunk is not JSON");
    if (json_len == 0 || json_len > size - 20)
        return fail(err, SR_E_FORMAT, name,
                    "GLB JSON chunk length %u does not fit the %zu bytes after its header",
                    json_len, size - 20);
    sr_glb_layout g = {20, json_len, 0, 0, 0};
    size_t pos = 20 + (size_t)json_len;
    for (int chunk = 1; pos < size; chunk++) {
        if (size - pos < 8)
            return fail(err, SR_E_FORMAT, name, "GLB has %zu stray bytes after chunk %d",
                        size - pos, chunk - 1);
        uint32_t len = le32(data + pos), type = le32(data + pos + 4);
        const char *what = type == GLB_BIN ? "BIN" : type == GLB_JSON ? "JSON" : "unknown";
        if (len > size - pos - 8)
            return fail(err, SR_E_FORMAT, name,
                        "GLB %s chunk length %u runs past the end of the file (%zu bytes after "
                        "its 8-byte header)", what, len, size - pos - 8);
        if (chunk == 1 && type == GLB_BIN) {
            g.has_bin = 1;
            g.bin_offset = pos + 8;
            g.bin_size = len;
        } else if (type == GLB_BIN || type == GLB_JSON) {
            return fail(err, SR_E_FORMAT, name, "GLB chunk %d is a misplaced %s chunk", chunk,
                        what);
        }
        pos += 8 + (size_t)len;
    }
    *out = g;
    return SR_OK;
}

sr_status sr_file_check_json_depth(const unsigned char *text, size_t size, size_t max_depth,
                                   const char *name, sr_err *err)
{
    size_t depth = 0;
    int in_string = 0;
    for (size_t i = 0; i < size; i++) {
        unsigned char c = text[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = 0;
        } else if (c == '"') {
            in_string = 1;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth)
                return fail(err, SR_E_FORMAT, name, "JSON nests deeper than %zu levels",
                            max_depth);
        } else if ((c == ']' || c == '}') && depth) {
            depth--;
        }
    }
    return SR_OK;
}
