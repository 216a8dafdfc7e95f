/*
 * check_common.c: what the format checks of file_check.h share (see check_int.h): the
 * message of every refusal ("cannot read 'name': ..."), growing arrays, the line reader
 * and tokenizer of the text formats, strict decimal numbers, and collected faces.
 *
 * Text formats are read line by line; numbers must be plain decimal (or the words
 * nan/inf, which are recognised only to be refused).
 */
#include "io/check_int.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- messages ---------------------------------------------------------------------- */

sr_status fc_fail(sr_err *err, sr_status status, const char *name, const char *fmt, ...)
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
    free(facts->corners);
    free(facts->face_size);
    free(facts->face_index);
    memset(facts, 0, sizeof *facts);
}

/* Grows *ptr (elements of elem bytes, capacity *cap) to hold at least need elements. */
int fc_grow(void **ptr, size_t *cap, size_t need, size_t elem)
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
size_t fc_first_binary_byte(const unsigned char *data, size_t size)
{
    for (size_t i = 0; i < size; i++) {
        unsigned char c = data[i];
        if ((c < 0x20 && !(c >= '\t' && c <= '\r')) || c == 0x7f)
            return i;
    }
    return size;
}

int fc_next_line(fc_line_reader *r, const char **s, const char **e)
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
int fc_next_token(const char **p, const char *e, const char **ts, const char **te,
                         int hash_comments)
{
    const char *q = *p;
    while (q < e && fc_blank((unsigned char)*q))
        q++;
    if (q >= e || (hash_comments && *q == '#')) {
        *p = e;
        return 0;
    }
    *ts = q;
    while (q < e && !fc_blank((unsigned char)*q))
        q++;
    *te = q;
    *p = q;
    return 1;
}

/* Copies a token for messages (shortened, NUL-terminated). */
const char *fc_token_str(const char *s, const char *e, char buf[40])
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
int fc_parse_real(const char *s, const char *e, double *out)
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
int fc_parse_int(const char *s, const char *e, long long *out)
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

/* ---- faces ---------------------------------------------------------------------------- */

int fc_add_face(sr_file_facts *f, fc_face_acc *a, const uint32_t *idx, size_t k)
{
    if (!fc_grow((void **)&f->face_size, &a->size_cap, f->face_count + 1, sizeof *f->face_size) ||
        !fc_grow((void **)&f->face_index, &a->index_cap, a->index_count + k,
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
