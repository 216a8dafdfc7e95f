/*
 * status.c: names of the result codes and the sr_err helpers (see status.h).
 */
#include "base/status.h"

#include <stdarg.h>
#include <stdio.h>

static const char *const status_names[SR_STATUS_COUNT] = {
    [SR_OK] = "ok",
    [SR_E_IO] = "i/o error",
    [SR_E_FORMAT] = "malformed file",
    [SR_E_INVALID] = "invalid data",
    [SR_E_RANGE] = "value out of range",
    [SR_E_NOTFOUND] = "not found",
    [SR_E_EXISTS] = "already exists",
    [SR_E_DB] = "catalogue error",
    [SR_E_VERSION] = "wrong catalogue version",
    [SR_E_NOMEM] = "out of memory",
    [SR_E_UNSUPPORTED] = "unsupported",
    [SR_E_INTERNAL] = "internal error",
};

const char *sr_status_str(sr_status status)
{
    if ((unsigned)status >= SR_STATUS_COUNT)
        return "unknown status";
    return status_names[status];
}

sr_status sr_err_set(sr_err *err, sr_status status, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return status;
}

void sr_err_clear(sr_err *err)
{
    if (err)
        err->msg[0] = '\0';
}
