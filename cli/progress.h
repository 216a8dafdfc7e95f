/*
 * progress.h: progress of long work on stderr (reconstruct, compare, demo). Nothing is
 * shown for work done within a second (SYMREC_PROGRESS_AFTER=S changes that delay;
 * tests use 0). Then:
 *   - on a terminal, one line redrawn in place ten times a second:
 *       symrec: reconstruct [########------------] 3/7 sections  12.4 s
 *     cleared when the work ends (or before any other message is printed);
 *   - otherwise (a pipe, a log file), one plain line per phase begun after the delay
 *     (and one for the phase running when the delay ends):
 *       symrec: reconstruct: sections (3/7) at 12.4 s
 *     and "symrec: reconstruct: done in 31.0 s" at the end;
 *   - with --quiet, nothing.
 * A helper thread does the drawing, so a phase that runs for minutes still shows its
 * clock; the work only stores where it is.
 */
#ifndef SR_CLI_PROGRESS_H
#define SR_CLI_PROGRESS_H

#include <stdbool.h>
#include <stddef.h>

#include "base/progress.h"

typedef struct cli_progress cli_progress;

/* Seconds on the monotonic clock (for timing a command's own steps). */
double cli_now_s(void);

/* Starts reporting `what` ("reconstruct"); NULL when quiet (every call below accepts
 * NULL). */
cli_progress *cli_progress_begin(bool quiet, const char *what);

/* The sink the library is given (NULL for a NULL progress). */
const sr_progress *cli_progress_sink(cli_progress *p);

/* Where the work is: phase, done of total steps (total 0: unknown). */
void cli_progress_phase(cli_progress *p, const char *phase, size_t done, size_t total);

/* Ends the report (clears the terminal line; the plain form says how long it took). */
void cli_progress_end(cli_progress *p);

/* Clears a bar drawn on the terminal before another message is printed (diag.c); the
 * next tick draws it again. */
void cli_progress_interrupt(void);

#endif
