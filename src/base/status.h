/*
 * status.h: the one table of result codes every fallible symrec call returns, and
 * sr_err, the optional one-line detail that names the file or field at fault.
 *
 * Convention (as in cgltf/H3): a fallible function returns sr_status and writes its
 * result through a trailing out-pointer only on SR_OK; on failure it frees all it built
 * and, if the caller passed a non-NULL sr_err, fills err->msg with one lower-case line
 * without a full stop, subject in quotes, e.g.
 *   cannot read 'x.stl': truncated binary STL (header says 5000 triangles, file holds 12)
 * The CLI prints it as "symrec: error: <msg>".
 */
#ifndef SR_STATUS_H
#define SR_STATUS_H

#include <stddef.h>

typedef enum sr_status {
    SR_OK = 0,
    SR_E_IO,          /* a file cannot be opened, read or written */
    SR_E_FORMAT,      /* a file's content is malformed, truncated or of the wrong format */
    SR_E_INVALID,     /* data fails validation: empty mesh, NaN/Inf, index out of range */
    SR_E_RANGE,       /* a parameter is out of its allowed range */
    SR_E_NOTFOUND,    /* an id, number or name that is not in the catalogue */
    SR_E_EXISTS,      /* a unique key that is already taken */
    SR_E_DB,          /* the catalogue refused an operation (SQLite error, busy, corrupt) */
    SR_E_VERSION,     /* a catalogue that is not symrec's or from a newer schema */
    SR_E_NOMEM,       /* out of memory, or a declared size too large to allocate */
    SR_E_UNSUPPORTED, /* a format or option this build does not handle */
    SR_E_INTERNAL,    /* a library failed in a way that is a bug (caught exception) */
    SR_STATUS_COUNT
} sr_status;

/* Short English name of a status ("i/o error", "malformed file", ...); never NULL. */
const char *sr_status_str(sr_status status);

/* One line of detail. Fixed size so it can live on the stack and never fails. */
typedef struct sr_err {
    char msg[512];
} sr_err;

/* printf-style: sets err->msg (truncating). err may be NULL (then it does nothing).
 * Returns `status` so callers can write `return sr_err_set(err, SR_E_IO, "...")`. */
sr_status sr_err_set(sr_err *err, sr_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Clears err->msg; err may be NULL. */
void sr_err_clear(sr_err *err);

#endif
