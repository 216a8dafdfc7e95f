/*
 * args.c: the CLI's strict argument parsing. Options are long only (`--name VALUE` or
 * `--name=VALUE`); a value that looks like another option (`--number --name X`) is
 * taken as a missing value rather than silently swallowed. Numbers must parse as a
 * whole, be finite and lie in range, and the usage error names the option:
 *   symrec: usage: bad --order 'x': expected an integer 2..360 (or 0 for continuous)
 */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const cli_opt *find_opt(const cli_opt *opts, const char *name, size_t len)
{
    for (const cli_opt *o = opts; o && o->name; o++)
        if (strlen(o->name) == len && strncmp(o->name, name, len) == 0)
            return o;
    return NULL;
}

bool cli_parse(const cli_spec *spec, int argc, char **argv, const char **pos, int *pos_count,
               int *rc)
{
    int npos = 0;
    bool options_done = false;
    for (int i = 0; i < argc; i++) {
        const char *arg = argv[i];
        if (!options_done && strcmp(arg, "--") == 0) {
            options_done = true;
            continue;
        }
        if (!options_done && (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)) {
            fputs(spec->usage, stdout);
            *rc = CLI_OK;
            return false;
        }
        if (!options_done && arg[0] == '-' && arg[1] != '\0') {
            const char *eq = strchr(arg, '=');
            size_t len = eq ? (size_t)(eq - arg) : strlen(arg);
            const cli_opt *o = arg[1] == '-' ? find_opt(spec->opts, arg, len) : NULL;
            if (!o) {
                *rc = cli_usage_error("unknown option '%.*s' for '%s' (see 'symrec %s --help')",
                                      (int)len, arg, spec->cmd, spec->cmd);
                return false;
            }
            if (!o->value) {
                if (eq) {
                    *rc = cli_usage_error("option '%s' takes no value", o->name);
                    return false;
                }
                *o->flag = true;
                continue;
            }
            if (eq) {
                *o->value = eq + 1;
                continue;
            }
            if (i + 1 >= argc || strncmp(argv[i + 1], "--", 2) == 0) {
                *rc = cli_usage_error("option '%s' needs a value", o->name);
                return false;
            }
            *o->value = argv[++i];
            continue;
        }
        if (npos >= spec->max_pos) {
            *rc = cli_usage_error("unexpected argument '%s' for '%s' (see 'symrec %s --help')",
                                  arg, spec->cmd, spec->cmd);
            return false;
        }
        pos[npos++] = arg;
    }
    if (npos < spec->min_pos) {
        *rc = cli_usage_error("'%s' needs %s (see 'symrec %s --help')", spec->cmd,
                              spec->pos_name ? spec->pos_name : "an argument", spec->cmd);
        return false;
    }
    if (pos_count)
        *pos_count = npos;
    return true;
}

/* A number's text: non-empty, no leading space (strtol/strtod would skip it). */
static bool number_text(const char *text)
{
    return text && text[0] != '\0' && !isspace((unsigned char)text[0]);
}

bool cli_parse_int(const char *opt, const char *text, long min, long max, const char *what,
                   int *out)
{
    char buf[64];
    if (!what) {
        snprintf(buf, sizeof buf, "an integer %ld..%ld", min, max);
        what = buf;
    }
    if (number_text(text)) {
        char *end;
        errno = 0;
        long v = strtol(text, &end, 10);
        if (errno == 0 && *end == '\0' && v >= min && v <= max && v >= INT_MIN &&
            v <= INT_MAX) {
            *out = (int)v;
            return true;
        }
    }
    cli_usage_error("bad %s '%s': expected %s", opt, text ? text : "", what);
    return false;
}

bool cli_parse_id(const char *opt, const char *text, int64_t *out)
{
    if (number_text(text) && text[0] != '-' && text[0] != '+') {
        char *end;
        errno = 0;
        long long v = strtoll(text, &end, 10);
        if (errno == 0 && *end == '\0' && v >= 1) {
            *out = (int64_t)v;
            return true;
        }
    }
    cli_usage_error("bad %s '%s': expected a positive integer id", opt, text ? text : "");
    return false;
}

bool cli_parse_double(const char *opt, const char *text, double min, double max,
                      const char *what, double *out)
{
    /* Decimal notation only: strtod would also take "nan", "inf" and hex floats. */
    bool ok = number_text(text) && strspn(text, "0123456789+-.eE") == strlen(text);
    if (ok) {
        char *end;
        errno = 0;
        double v = strtod(text, &end);
        if (errno == 0 && *end == '\0' && isfinite(v) && v >= min && v <= max) {
            *out = v;
            return true;
        }
    }
    cli_usage_error("bad %s '%s': expected %s", opt, text ? text : "", what);
    return false;
}

static bool digits(const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isdigit((unsigned char)s[i]))
            return false;
    return true;
}

bool cli_date_valid(const char *text)
{
    if (!text || strlen(text) != 10 || text[4] != '-' || text[7] != '-' || !digits(text, 4) ||
        !digits(text + 5, 2) || !digits(text + 8, 2))
        return false;
    int y = atoi(text), m = atoi(text + 5), d = atoi(text + 8);
    static const int mdays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (y < 1 || m < 1 || m > 12 || d < 1)
        return false;
    bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    int last = mdays[m - 1] + (m == 2 && leap);
    return d <= last;
}

bool cli_parse_symmetry(const char *kind, const char *order, const char *shift,
                        int allow_auto, sr_symmetry *out)
{
    sr_symmetry sym = {SR_SYM_NONE, 0, 0.0};
    if (!kind) {
        if (order || shift) {
            cli_usage_error("%s needs --symmetry", order ? "--order" : "--shift");
            return false;
        }
        *out = sym;
        return true;
    }
    sr_err err;
    sr_err_clear(&err);
    if (sr_sym_kind_parse(kind, "--symmetry", &sym.kind, &err) != SR_OK) {
        cli_usage_error("%s", err.msg);
        return false;
    }
    if (order) {
        if (sym.kind != SR_SYM_AXIAL) {
            cli_usage_error("--order applies to --symmetry axial only");
            return false;
        }
        const char *what = "an integer 2..360 (or 0 for continuous)";
        if (allow_auto && strcmp(order, "auto") == 0)
            sym.order = SR_ORDER_AUTO;
        else if (!cli_parse_int("--order", order, 0, 360, what, &sym.order))
            return false;
        if (sym.order == 1) {
            cli_usage_error("bad --order '%s': expected %s", order, what);
            return false;
        }
    }
    if (shift) {
        if (sym.kind != SR_SYM_GLIDE) {
            cli_usage_error("--shift applies to --symmetry glide only");
            return false;
        }
        if (!cli_parse_double("--shift", shift, 0.0, 1e6,
                              "a shift in mm, 0..1000000 (0 = find by search)", &sym.shift_mm))
            return false;
    }
    *out = sym;
    return true;
}

int cli_run_subcommand(const cli_ctx *ctx, const char *cmd, const char *usage,
                       const cli_subcommand *subs, int argc, char **argv)
{
    const char *sub = argc > 1 ? argv[1] : NULL;
    if (!sub)
        return cli_usage_error("'%s' needs a subcommand (see 'symrec %s --help')", cmd, cmd);
    if (strcmp(sub, "--help") == 0 || strcmp(sub, "-h") == 0) {
        fputs(usage, stdout);
        return CLI_OK;
    }
    for (const cli_subcommand *s = subs; s->name; s++)
        if (strcmp(sub, s->name) == 0)
            return s->run(ctx, argc - 2, argv + 2);
    return cli_usage_error("unknown subcommand '%s %s' (see 'symrec %s --help')", cmd, sub, cmd);
}
