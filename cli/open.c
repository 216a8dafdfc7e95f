/*
 * open.c: how every command opens the catalogue named by --db / $SYMREC_DB. Only
 * `catalog init` and `demo` create a missing file: any other command on a path that
 * does not exist says so and how to create it, so a typo in --db never leaves a stray
 * empty catalogue behind.
 */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

bool cli_open(const cli_ctx *ctx, bool create, sr_catalog **out)
{
    struct stat st;
    if (!create && stat(ctx->db_path, &st) != 0) {
        if (errno == ENOENT) {
            cli_error("no catalogue '%s' (create it with 'symrec --db %s catalog init')",
                      ctx->db_path, ctx->db_path);
        } else {
            cli_error("cannot open catalogue '%s': %s", ctx->db_path, strerror(errno));
        }
        return false;
    }
    sr_err err;
    sr_err_clear(&err);
    sr_status st_open = sr_catalog_open(ctx->db_path, create ? SR_CATALOG_CREATE : 0, out, &err);
    if (st_open != SR_OK) {
        cli_fail(st_open, &err);
        return false;
    }
    return true;
}
