/*
 * format.c: the CLI's human output: aligned text tables (cells escaped as escape.c
 * says), the one way a symmetry is written, and bounding boxes with their unit. Widths count UTF-8 characters, not
 * bytes, so a header like "volume mm³" lines up.
 */
#include <assert.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "cli.h"

const char *cli_sym_str(const sr_symmetry *sym, char *buf, size_t size)
{
    switch (sym->kind) {
    case SR_SYM_AXIAL:
        if (sym->order == 0)
            snprintf(buf, size, "axial, continuous");
        else
            snprintf(buf, size, "axial, %d-fold", sym->order);
        break;
    case SR_SYM_MIRROR:
        snprintf(buf, size, "mirror");
        break;
    case SR_SYM_GLIDE:
        if (sym->shift_mm == 0)
            snprintf(buf, size, "glide, shift by search");
        else
            snprintf(buf, size, "glide, shift %g mm", sym->shift_mm);
        break;
    default:
        snprintf(buf, size, "-");
        break;
    }
    return buf;
}

/* Display width of a UTF-8 string: one column per character. */
static size_t text_width(const char *s)
{
    size_t w = 0;
    for (const unsigned char *p = (const unsigned char *)s; *p; p++)
        if ((*p & 0xc0) != 0x80)
            w++;
    return w;
}

void cli_table_init(cli_table *t, size_t cols, const char *const *headers, const bool *right)
{
    memset(t, 0, sizeof *t);
    t->cols = cols;
    t->headers = headers;
    t->right = right;
}

void cli_table_cell(cli_table *t, const char *fmt, ...)
{
    if (t->failed)
        return;
    char **cells = sr_grow(t->cells, t->cell_count, &t->cell_cap, sizeof *cells);
    if (!cells) {
        t->failed = true;
        return;
    }
    t->cells = cells;
    va_list ap, ap2;
    va_start(ap, fmt);
    va_copy(ap2, ap);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (s)
        vsnprintf(s, (size_t)n + 1, fmt, ap2);
    va_end(ap2);
    if (!s) {
        t->failed = true;
        return;
    }
    /* A cell is one line of the table, and user text must not act on the terminal:
     * control characters become escapes (escape.c). */
    char *safe = cli_tx(s) == s ? s : cli_tx_dup(s);
    if (safe != s)
        free(s);
    if (!safe) {
        t->failed = true;
        return;
    }
    t->cells[t->cell_count++] = safe;
}

static void put_cell(FILE *f, const char *s, size_t width, bool right, bool last)
{
    size_t pad = width - text_width(s);
    if (right)
        fprintf(f, "%*s", (int)pad, "");
    fputs(s, f);
    if (!right && !last)
        fprintf(f, "%*s", (int)pad, "");
}

bool cli_table_print(const cli_table *t, FILE *f, int indent)
{
    if (t->failed) {
        cli_error("out of memory while building a table");
        return false;
    }
    assert(t->cols >= 1 && t->cols <= CLI_TABLE_MAX_COLS);
    size_t width[CLI_TABLE_MAX_COLS] = {0};
    size_t cols = t->cols;
    for (size_t c = 0; c < cols; c++)
        width[c] = text_width(t->headers[c]);
    for (size_t i = 0; i < t->cell_count; i++) {
        size_t w = text_width(t->cells[i]);
        if (w > width[i % t->cols])
            width[i % t->cols] = w;
    }
    fprintf(f, "%*s", indent, "");
    for (size_t c = 0; c < cols; c++) {
        put_cell(f, t->headers[c], width[c], t->right[c], c + 1 == cols);
        fputs(c + 1 == cols ? "\n" : "  ", f);
    }
    for (size_t i = 0; i < t->cell_count; i++) {
        size_t c = i % t->cols;
        if (c == 0)
            fprintf(f, "%*s", indent, "");
        put_cell(f, t->cells[i], width[c], t->right[c], c + 1 == cols);
        fputs(c + 1 == cols ? "\n" : "  ", f);
    }
    return true;
}

void cli_table_release(cli_table *t)
{
    for (size_t i = 0; i < t->cell_count; i++)
        free(t->cells[i]);
    free(t->cells);
    memset(t, 0, sizeof *t);
}

void cli_print_bbox(FILE *f, const char *label, const double min[3], const double max[3])
{
    fprintf(f, "%sx %.3f .. %.3f, y %.3f .. %.3f, z %.3f .. %.3f mm\n", label, min[0], max[0],
            min[1], max[1], min[2], max[2]);
    fprintf(f, "%*s(size %.3f x %.3f x %.3f mm)\n", (int)text_width(label), "",
            max[0] - min[0], max[1] - min[1], max[2] - min[2]);
}

void cli_print_field(FILE *f, const char *label, const char *value)
{
    char *safe = cli_tx_dup(value);
    fputs(label, f);
    fputs(safe ? safe : "(out of memory)", f);
    fputc('\n', f);
    free(safe);
}
