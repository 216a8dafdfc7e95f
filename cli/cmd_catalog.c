/*
 * cmd_catalog.c: `symrec catalog init` (create the catalogue or bring its schema up to
 * date; running it again changes nothing) and `symrec catalog info` (where it is, its
 * schema version, and how much it holds).
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "catalog/catalog_runs.h"
#include "cli.h"
#include "json_out.h"

static const char usage_catalog[] =
    "usage: symrec [--db FILE] catalog init\n"
    "       symrec [--db FILE] catalog info [--json]\n"
    "\n"
    "  init    create the catalogue FILE if it does not exist and bring its schema up\n"
    "          to date; safe to run again\n"
    "  info    the catalogue's path, schema version and counts of parts, instances\n"
    "          and reconstruction runs\n";

static const char usage_init[] =
    "usage: symrec [--db FILE] catalog init\n"
    "\n"
    "Creates the catalogue FILE (default $SYMREC_DB, else " CLI_DEFAULT_DB ") if it does\n"
    "not exist (or is an empty file), or migrates an existing one to the current schema.\n"
    "Prints what it did and the schema version. Running it again changes nothing.\n";

static const char usage_info[] =
    "usage: symrec [--db FILE] catalog info [--json]\n"
    "\n"
    "Prints the catalogue's path, schema version and the number of parts, damaged\n"
    "instances and recorded reconstruction runs it holds.\n"
    "\n"
    "  --json   one JSON object: {\"path\", \"schema_version\", \"schema_latest\", \"parts\",\n"
    "           \"instances\", \"runs\"}\n";

static int catalog_init(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_opt opts[] = {{NULL, NULL, NULL}};
    const cli_spec spec = {"catalog init", usage_init, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;

    /* what was there before decides the message: nothing, an empty file (SQLite takes
     * a 0-byte file as an empty database, which init fills), or a catalogue */
    struct stat st;
    bool existed = stat(ctx->db_path, &st) == 0;
    bool was_empty = existed && S_ISREG(st.st_mode) && st.st_size == 0;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_CREATE, "create the catalogue", &cat))
        return CLI_FAIL;
    if (was_empty)
        printf("initialised empty file '%s' as a catalogue (schema version %d)\n",
               sr_catalog_path(cat), sr_catalog_schema_version(cat));
    else if (existed)
        printf("catalogue '%s' already exists (schema version %d)\n", sr_catalog_path(cat),
               sr_catalog_schema_version(cat));
    else
        printf("created catalogue '%s' (schema version %d)\n", sr_catalog_path(cat),
               sr_catalog_schema_version(cat));
    sr_catalog_close(cat);
    return CLI_OK;
}

static int count_part(const sr_part_info *p, void *user)
{
    (*(int64_t *)user)++;
    return 0;
}

static int count_instance(const sr_instance_info *in, void *user)
{
    (*(int64_t *)user)++;
    return 0;
}

static int catalog_info(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"catalog info", usage_info, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    int64_t parts = 0, instances = 0, runs = 0;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_part_list(cat, NULL, count_part, &parts, &err);
    if (st == SR_OK)
        st = sr_catalog_instance_list(cat, NULL, count_instance, &instances, &err);
    if (st == SR_OK)
        st = sr_catalog_run_count(cat, &runs, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "path");
        json_string(&j, sr_catalog_path(cat));
        json_key(&j, "schema_version");
        json_int(&j, sr_catalog_schema_version(cat));
        json_key(&j, "schema_latest");
        json_int(&j, sr_catalog_schema_latest());
        json_key(&j, "parts");
        json_int(&j, parts);
        json_key(&j, "instances");
        json_int(&j, instances);
        json_key(&j, "runs");
        json_int(&j, runs);
        json_object_end(&j);
        rc = json_finish(&j);
    } else {
        rc = CLI_OK;
        printf("catalogue:       %s\n", sr_catalog_path(cat));
        printf("schema version:  %d\n", sr_catalog_schema_version(cat));
        printf("parts:           %lld\n", (long long)parts);
        printf("instances:       %lld\n", (long long)instances);
        printf("runs:            %lld\n", (long long)runs);
    }
    sr_catalog_close(cat);
    return rc;
}

int cmd_catalog(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"init", catalog_init}, {"info", catalog_info}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "catalog", usage_catalog, subs, argc, argv);
}
