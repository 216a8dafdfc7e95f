/*
 * jsonbuf.c: the in-memory JSON builder of jsonbuf.h: a growable string, comma
 * bookkeeping per nesting level, string escaping with UTF-8 checking, shortest
 * round-trip numbers. The one JSON writer: the CLI's --json output (cli/json_out.c)
 * is built with it too.
 */
#include "base/jsonbuf.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sr_jsonbuf_init(sr_jsonbuf *jb)
{
    memset(jb, 0, sizeof *jb);
}

void sr_jsonbuf_release(sr_jsonbuf *jb)
{
    if (!jb)
        return;
    free(jb->s);
    sr_jsonbuf_init(jb);
}

static void append(sr_jsonbuf *jb, const char *s, size_t n)
{
    if (jb->nomem)
        return;
    if (jb->len + n + 1 > jb->cap) {
        size_t cap = jb->cap ? jb->cap : 256;
        while (cap < jb->len + n + 1)
            cap *= 2;
        char *p = realloc(jb->s, cap);
        if (!p) {
            jb->nomem = true;
            return;
        }
        jb->s = p;
        jb->cap = cap;
    }
    memcpy(jb->s + jb->len, s, n);
    jb->len += n;
    jb->s[jb->len] = '\0';
}

static void append_str(sr_jsonbuf *jb, const char *s)
{
    append(jb, s, strlen(s));
}

/* Comma before a value unless it follows a key or opens its container. */
static void before_value(sr_jsonbuf *jb)
{
    if (jb->after_key) {
        jb->after_key = false;
        return;
    }
    if (jb->need_comma[jb->depth])
        append(jb, ",", 1);
    jb->need_comma[jb->depth] = true;
}

static void open_level(sr_jsonbuf *jb, const char *bracket)
{
    before_value(jb);
    append_str(jb, bracket);
    if (jb->depth >= SR_JSONBUF_MAX_DEPTH) {
        jb->nomem = true;   /* a bug in the caller; refuse rather than overflow */
        return;
    }
    jb->need_comma[++jb->depth] = false;
}

static void close_level(sr_jsonbuf *jb, const char *bracket)
{
    if (jb->depth > 0)
        jb->depth--;
    append_str(jb, bracket);
}

void sr_jsonbuf_object_begin(sr_jsonbuf *jb) { open_level(jb, "{"); }
void sr_jsonbuf_object_end(sr_jsonbuf *jb) { close_level(jb, "}"); }
void sr_jsonbuf_array_begin(sr_jsonbuf *jb) { open_level(jb, "["); }
void sr_jsonbuf_array_end(sr_jsonbuf *jb) { close_level(jb, "]"); }

/* Number of bytes of the valid UTF-8 character at p, 0 if p does not start one. */
static size_t utf8_char(const unsigned char *p)
{
    static const uint32_t min_cp[5] = {0, 0, 0x80, 0x800, 0x10000};
    size_t n = p[0] < 0x80 ? 1 : (p[0] & 0xe0) == 0xc0 ? 2 : (p[0] & 0xf0) == 0xe0 ? 3
             : (p[0] & 0xf8) == 0xf0 ? 4 : 0;
    if (n <= 1)
        return n;
    uint32_t cp = p[0] & (0x7f >> n);
    for (size_t i = 1; i < n; i++) {
        if ((p[i] & 0xc0) != 0x80)
            return 0;
        cp = cp << 6 | (p[i] & 0x3f);
    }
    if (cp < min_cp[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    return n;
}

/* The letter of the two-character escape of c ('"' for '"', 'n' for '\n', ...), 0 if
 * c has none. */
static char short_escape(unsigned char c)
{
    switch (c) {
    case '"': return '"';
    case '\\': return '\\';
    case '\b': return 'b';
    case '\f': return 'f';
    case '\n': return 'n';
    case '\r': return 'r';
    case '\t': return 't';
    default: return 0;
    }
}

static void append_quoted(sr_jsonbuf *jb, const char *s)
{
    append(jb, "\"", 1);
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        char esc[8];
        if ((esc[1] = short_escape(*p)) != 0) {
            esc[0] = '\\';
            append(jb, esc, 2);
            p++;
        } else if (*p < 0x20 || *p == 0x7f) {
            snprintf(esc, sizeof esc, "\\u%04x", *p);
            append_str(jb, esc);
            p++;
        } else {
            size_t n = utf8_char(p);
            if (n == 0) {
                append_str(jb, "\\ufffd");
                p++;
            } else if (n == 2 && p[0] == 0xc2 && p[1] <= 0x9f) {
                /* a C1 control (U+0080-U+009F, e.g. CSI) acts on some terminals */
                snprintf(esc, sizeof esc, "\\u%04x", p[1]);
                append_str(jb, esc);
                p += 2;
            } else {
                append(jb, (const char *)p, n);
                p += n;
            }
        }
    }
    append(jb, "\"", 1);
}

void sr_jsonbuf_key(sr_jsonbuf *jb, const char *key)
{
    before_value(jb);
    append_quoted(jb, key);
    append(jb, ":", 1);
    jb->after_key = true;
}

void sr_jsonbuf_key_raw(sr_jsonbuf *jb, const char *key, size_t len)
{
    before_value(jb);
    append(jb, "\"", 1);
    append(jb, key, len);
    append(jb, "\":", 2);
    jb->after_key = true;
}

void sr_jsonbuf_string(sr_jsonbuf *jb, const char *s)
{
    before_value(jb);
    if (s)
        append_quoted(jb, s);
    else
        append_str(jb, "null");
}

const char *sr_jsonbuf_format_number(double v, char buf[SR_JSONBUF_NUMBER_SIZE])
{
    if (!isfinite(v))
        return strcpy(buf, "null");
    if (v == 0)
        return strcpy(buf, "0");   /* also -0: JSON readers differ on "-0" */
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, SR_JSONBUF_NUMBER_SIZE, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return buf;
}

void sr_jsonbuf_number(sr_jsonbuf *jb, double v)
{
    before_value(jb);
    char buf[SR_JSONBUF_NUMBER_SIZE];
    append_str(jb, sr_jsonbuf_format_number(v, buf));
}

void sr_jsonbuf_int(sr_jsonbuf *jb, int64_t v)
{
    before_value(jb);
    char buf[32];
    snprintf(buf, sizeof buf, "%" PRId64, v);
    append_str(jb, buf);
}

void sr_jsonbuf_bool(sr_jsonbuf *jb, bool v)
{
    before_value(jb);
    append_str(jb, v ? "true" : "false");
}

void sr_jsonbuf_null(sr_jsonbuf *jb)
{
    before_value(jb);
    append_str(jb, "null");
}

void sr_jsonbuf_raw(sr_jsonbuf *jb, const char *json)
{
    before_value(jb);
    append_str(jb, json && *json ? json : "null");
}

sr_status sr_jsonbuf_take(sr_jsonbuf *jb, char **out, sr_err *err)
{
    if (!jb->nomem && !jb->s)
        append(jb, "", 0);
    if (jb->nomem) {
        sr_jsonbuf_release(jb);
        return sr_err_set(err, SR_E_NOMEM, "out of memory building a JSON text");
    }
    *out = jb->s;
    jb->s = NULL;
    sr_jsonbuf_release(jb);
    return SR_OK;
}
