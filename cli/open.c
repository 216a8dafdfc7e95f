/*
 * open.c: how every command opens the catalogue named by --db / $SYMREC_DB, for
 * reading or for writing. Only `catalog init` and `demo` create a missing file: any
 * other command on a path that does not exist says so and how to create it, so a typo
 * in --db never leaves a stray empty catalogue behind.
 *
 * A command that only reads opens the file read-only, so a catalogue in a folder or
 * file this user cannot write (an archive, a colleague's copy) can still be listed
 * and exported (catalog.h: the immutable fallback); only an older schema is opened
 * read-write, once, to migrate it. A command that writes checks first that it can
 * (sr_catalog_check_writable) and otherwise refuses in one line: "catalogue 'X' is
 * read-only: cannot <what it would have done>". The global --read-only makes every
 * open read-only (and every write refused that way).
 */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

/* The one line of a write refused on a read-only catalogue. */
static bool refuse_readonly(const cli_ctx *ctx, const char *why)
{
    cli_error("catalogue '%s' is read-only%s: cannot %s", ctx->db_path,
              ctx->read_only ? " (--read-only)" : "", why ? why : "write to it");
    return false;
}

/* After a read-write open failed: whether the file opens read-only (then the failure
 * was the catalogue's being read-only, and the refusal says so). */
static bool opens_readonly(const cli_ctx *ctx)
{
    sr_catalog *cat = NULL;
    sr_err err;
    sr_err_clear(&err);
    bool ok = sr_catalog_open(ctx->db_path, SR_CATALOG_READONLY, &cat, &err) == SR_OK;
    sr_catalog_close(cat);
    return ok;
}

bool cli_open(const cli_ctx *ctx, cli_access access, const char *why, sr_catalog **out)
{
    struct stat st;
    if (access != CLI_CREATE && stat(ctx->db_path, &st) != 0) {
        if (errno == ENOENT) {
            cli_error("no catalogue '%s' (create it with 'symrec --db %s catalog init')",
                      ctx->db_path, ctx->db_path);
        } else {
            cli_error("cannot open catalogue '%s': %s", ctx->db_path, strerror(errno));
        }
        return false;
    }
    if (access == CLI_READ_CACHE) {
        sr_catalog *cat = NULL;
        bool readonly = true;
        if (!ctx->read_only && sr_catalog_open(ctx->db_path, 0, &cat, NULL) == SR_OK &&
            sr_catalog_check_writable(cat, &readonly, NULL) == SR_OK && !readonly) {
            *out = cat;
            return true;
        }
        sr_catalog_close(cat);
        access = CLI_READ; /* whatever failed, reading says why */
    }
    if (access != CLI_READ && ctx->read_only)
        return refuse_readonly(ctx, why);
    unsigned flags = access == CLI_CREATE ? SR_CATALOG_CREATE : 0;
    if (access == CLI_READ)
        flags = SR_CATALOG_READONLY | (ctx->read_only ? 0 : SR_CATALOG_UPGRADE);
    sr_catalog *cat = NULL;
    sr_err err;
    sr_err_clear(&err);
    sr_status st_open = sr_catalog_open(ctx->db_path, flags, &cat, &err);
    if (st_open != SR_OK) {
        if (access != CLI_READ && st_open != SR_E_VERSION && opens_readonly(ctx))
            return refuse_readonly(ctx, why);
        cli_fail(st_open, &err);
        return false;
    }
    if (access != CLI_READ) {
        bool readonly = true;
        st_open = sr_catalog_check_writable(cat, &readonly, &err);
        if (st_open != SR_OK || readonly) {
            sr_catalog_close(cat);
            if (st_open == SR_OK)
                return refuse_readonly(ctx, why);
            cli_fail(st_open, &err);
            return false;
        }
    }
    *out = cat;
    return true;
}
