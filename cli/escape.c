/*
 * escape.c: what catalogue text may do on a terminal or in a spreadsheet. Part names,
 * serials, notes, rule and parameter-set names are the user's text and reach
 * stdout: a raw ESC sequence in one would act on the terminal (clear it, retitle
 * it), an embedded newline would forge a line of output, and a CSV cell starting
 * with '=' is run by a spreadsheet as a formula.
 *
 * Terminal text (cli_tx, and every table cell and cli_print_field value): C0 controls
 * (U+0000-U+001F, with \n \r \t by name), DEL and the C1 controls U+0080-U+009F are
 * written as escapes ("\x1b", "\n", "\u009b"); a byte that is not part of valid UTF-8
 * as "\xHH". Printable UTF-8, a backslash included, is left as it is. JSON output has
 * its own escaping (json_out.c).
 *
 * CSV cells (RFC 4180 quoting): a text cell starting with '=', '+', '-', '@', TAB or
 * CR gets a leading "'" (the OWASP rule against CSV injection), so a spreadsheet shows
 * it as text; numeric cells are written as they are (a negative number stays a
 * number).
 */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* Length of the valid UTF-8 sequence at p (1..4), 0 if it is not one. Checks the
 * continuation bytes, overlong forms, surrogates and the U+10FFFF limit. */
static size_t utf8_len(const unsigned char *p)
{
    unsigned char b = p[0];
    size_t n = b >= 0xc2 && b <= 0xdf   ? 2
               : b >= 0xe0 && b <= 0xef ? 3
               : b >= 0xf0 && b <= 0xf4 ? 4
                                        : 0;
    for (size_t i = 1; i < n; i++)
        if ((p[i] & 0xc0) != 0x80)
            return 0;
    if ((b == 0xe0 && p[1] < 0xa0) || (b == 0xed && p[1] > 0x9f) || (b == 0xf0 && p[1] < 0x90) ||
        (b == 0xf4 && p[1] > 0x8f))
        return 0;
    return n;
}

/* Writes the terminal form of s into out (size bytes, NUL-terminated, truncated to
 * fit) and returns its full length without the NUL, like snprintf. */
static size_t escape_into(const char *s, char *out, size_t size)
{
    static const char hex[] = "0123456789abcdef";
    const unsigned char *p = (const unsigned char *)s;
    size_t o = 0;
    while (*p) {
        char tmp[8];
        size_t tn = 0, take = 1;
        const char *src = tmp;
        if (*p < 0x20 || *p == 0x7f) {
            tmp[tn++] = '\\';
            if (*p == '\n' || *p == '\r' || *p == '\t') {
                tmp[tn++] = *p == '\n' ? 'n' : *p == '\r' ? 'r' : 't';
            } else {
                tmp[tn++] = 'x';
                tmp[tn++] = hex[*p >> 4];
                tmp[tn++] = hex[*p & 15];
            }
        } else if (*p < 0x80) {
            src = (const char *)p;
            tn = 1;
        } else if ((take = utf8_len(p)) == 0) {
            take = 1;
            tmp[tn++] = '\\';
            tmp[tn++] = 'x';
            tmp[tn++] = hex[*p >> 4];
            tmp[tn++] = hex[*p & 15];
        } else if (take == 2 && p[0] == 0xc2 && p[1] <= 0x9f) { /* C1: U+0080-U+009F */
            memcpy(tmp, "\\u00", 4);
            tn = 4;
            tmp[tn++] = hex[p[1] >> 4];
            tmp[tn++] = hex[p[1] & 15];
        } else {
            src = (const char *)p;
            tn = take;
        }
        for (size_t i = 0; i < tn; i++, o++)
            if (o + 1 < size)
                out[o] = src[i];
        p += take;
    }
    if (size)
        out[o < size ? o : size - 1] = '\0';
    return o;
}

/* Whether s holds anything escape_into would change. */
static bool needs_escape(const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++)
        if (*p < 0x20 || *p >= 0x7f)
            return true;
    return false;
}

const char *cli_tx(const char *s)
{
    enum { SLOTS = 8, SLOT_SIZE = 6 * 1100 };
    static char slots[SLOTS][SLOT_SIZE];
    static unsigned next;
    if (!s || !needs_escape(s))
        return s;
    char *out = slots[next++ % SLOTS];
    /* plain UTF-8 beyond 0x7f needs no copy: only build one when something changes */
    if (escape_into(s, out, SLOT_SIZE) == strlen(s) && strcmp(out, s) == 0)
        return s;
    return out;
}

char *cli_tx_dup(const char *s)
{
    size_t n = escape_into(s, NULL, 0);
    char *out = malloc(n + 1);
    if (out)
        escape_into(s, out, n + 1);
    return out;
}

/* ---- CSV ---- */

static void csv_cell(FILE *f, const char *s, bool formula_guard, bool last)
{
    bool guard = formula_guard && s[0] && strchr("=+-@\t\r", s[0]);
    if (guard || strpbrk(s, ",\"\r\n")) {
        fputc('"', f);
        if (guard)
            fputc('\'', f);
        for (const char *p = s; *p; p++) {
            if (*p == '"')
                fputc('"', f);
            fputc(*p, f);
        }
        fputc('"', f);
    } else {
        fputs(s, f);
    }
    fputs(last ? "\r\n" : ",", f);
}

void cli_csv_text(FILE *f, const char *s, bool last)
{
    csv_cell(f, s, true, last);
}

void cli_csv_number(FILE *f, const char *s, bool last)
{
    csv_cell(f, s, false, last);
}
