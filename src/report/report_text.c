/*
 * report_text.c: the growing text the HTML report is written into (report_int.h): one
 * heap string, out of memory sticky, with the two escapings the page needs, HTML
 * character data for the tables and JSON strings and numbers for the data block.
 */
#include "report/report_int.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool sb_room(sb *b, size_t n)
{
    if (b->failed)
        return false;
    if (b->len + n + 1 <= b->cap)
        return true;
    size_t cap = b->cap ? b->cap : 65536;
    while (cap < b->len + n + 1) {
        if (cap > SIZE_MAX / 2) {
            b->failed = true;
            return false;
        }
        cap *= 2;
    }
    char *p = realloc(b->p, cap);
    if (!p) {
        b->failed = true;
        return false;
    }
    b->p = p;
    b->cap = cap;
    return true;
}

void sb_putn(sb *b, const char *s, size_t n)
{
    if (!sb_room(b, n))
        return;
    memcpy(b->p + b->len, s, n);
    b->len += n;
    b->p[b->len] = '\0';
}

void sb_put(sb *b, const char *s)
{
    sb_putn(b, s, strlen(s));
}

void sb_printf(sb *b, const char *fmt, ...)
{
    char small[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->failed = true;
        return;
    }
    if ((size_t)n < sizeof small) {
        sb_putn(b, small, (size_t)n);
        return;
    }
    if (!sb_room(b, (size_t)n))
        return;
    va_start(ap, fmt);
    vsnprintf(b->p + b->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
}

/* Text as HTML character data or attribute value. */
void sb_html(sb *b, const char *s)
{
    if (!s)
        return;
    for (const char *p = s; *p; p++) {
        switch (*p) {
        case '&':
            sb_put(b, "&amp;");
            break;
        case '<':
            sb_put(b, "&lt;");
            break;
        case '>':
            sb_put(b, "&gt;");
            break;
        case '"':
            sb_put(b, "&quot;");
            break;
        case '\'':
            sb_put(b, "&#39;");
            break;
        default:
            sb_putn(b, p, 1);
        }
    }
}

/* A JSON string for the data block: quotes, backslashes and control characters
 * escaped, and '<', '>', '&' as \u escapes so the text cannot close the script. */
void sb_jstr(sb *b, const char *s)
{
    sb_put(b, "\"");
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; p++) {
        unsigned char c = *p;
        if (c == '"' || c == '\\') {
            char e[3] = {'\\', (char)c, 0};
            sb_put(b, e);
        } else if (c < 0x20 || c == '<' || c == '>' || c == '&') {
            sb_printf(b, "\\u%04x", c);
        } else {
            sb_putn(b, (const char *)p, 1);
        }
    }
    sb_put(b, "\"");
}

/* A number for the data block (null when not finite). */
void sb_jnum(sb *b, double v, const char *fmt)
{
    if (isfinite(v))
        sb_printf(b, fmt, v);
    else
        sb_put(b, "null");
}
