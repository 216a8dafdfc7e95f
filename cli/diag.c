/*
 * diag.c: the CLI's diagnostics on stderr, each exactly one line:
 *   symrec: error: <what failed>     (exit 1)
 *   symrec: usage: <what was wrong>  (exit 2)
 *   symrec: <progress note>
 * A message that holds a newline (a library or a user string could) has it replaced
 * by a space, so scripts can rely on one line per diagnostic.
 */
#include <stdarg.h>
#include <stdio.h>

#include "cli.h"
#include "progress.h"

static bool quiet_notes;

void cli_set_quiet(bool quiet)
{
    quiet_notes = quiet;
}

static void vline(const char *prefix, const char *fmt, va_list ap)
{
    char msg[1024];
    vsnprintf(msg, sizeof msg, fmt, ap);
    for (char *p = msg; *p; p++)
        if (*p == '\n' || *p == '\r')
            *p = ' ';
    fflush(stdout);     /* keep stdout and stderr in order on a shared terminal */
    cli_progress_interrupt(); /* a progress bar's line first */
    fprintf(stderr, "symrec: %s%s\n", prefix, msg);
}

int cli_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vline("error: ", fmt, ap);
    va_end(ap);
    return CLI_FAIL;
}

int cli_usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vline("usage: ", fmt, ap);
    va_end(ap);
    return CLI_USAGE;
}

void cli_note(const char *fmt, ...)
{
    if (quiet_notes)
        return;
    va_list ap;
    va_start(ap, fmt);
    vline("", fmt, ap);
    va_end(ap);
}

int cli_fail(sr_status status, const sr_err *err)
{
    if (err && err->msg[0])
        return cli_error("%s", err->msg);
    return cli_error("%s", sr_status_str(status));
}
