/*
 * cmd_catalog.c: `symrec catalog init` (create the catalogue or bring its schema up to
 * date; running it again changes nothing), `symrec catalog info` (where it is, its
 * schema version, and how much it holds), `symrec catalog backup FILE` (a consistent
 * copy while others write) and `symrec catalog check` (is the file sound).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
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
    "       symrec [--db FILE] catalog backup COPY [--force]\n"
    "       symrec [--db FILE] catalog check [--json]\n"
    "\n"
    "  backup  write a consistent copy of the catalogue to COPY\n"
    "  check   check the file: integrity, foreign keys, identity, history summary\n";

static const char usage_backup[] =
    "usage: symrec [--db FILE] catalog backup COPY [--force]\n"
    "\n"
    "Writes a copy of the catalogue to COPY, as one consistent state even while other\n"
    "processes write to it (SQLite's online backup). The copy is written beside COPY\n"
    "and moved into place when complete, so COPY is never half written; it opens as a\n"
    "catalogue like the original ('symrec --db COPY part list'). Works on a read-only\n"
    "catalogue.\n"
    "\n"
    "  --force   replace COPY if it exists (otherwise refused)\n";

static const char usage_check[] =
    "usage: symrec [--db FILE] catalog check [--json]\n"
    "\n"
    "Checks the catalogue file: SQLite's integrity check, every foreign key, the\n"
    "application id and schema version, and that the history summary's running totals\n"
    "agree with the runs. Prints \"ok\" and exits 0 when all is well; otherwise one line\n"
    "per problem on stdout and exit status 1. Materials without a density (which older\n"
    "versions created) are noted on stderr, not counted as problems.\n"
    "\n"
    "  --json   one JSON object: {\"path\", \"ok\", \"application_id\",\n"
    "           \"schema_version\", \"schema_latest\", \"materials_without_density\",\n"
    "           \"problems\": [...]}\n";

static const char usage_init[] =
    "usage: symrec [--db FILE] catalog init [--json]\n"
    "\n"
    "Creates the catalogue FILE (default $SYMREC_DB, else " CLI_DEFAULT_DB ") if it does\n"
    "not exist (or is an empty file), or migrates an existing one to the current schema.\n"
    "Prints what it did and the schema version. Running it again changes nothing.\n"
    "\n"
    "  --json   one JSON object: {\"path\", \"action\" (\"created\", \"initialised\" (an\n"
    "           empty file), \"migrated\" or \"unchanged\"), \"schema_before\" (null when\n"
    "           created), \"schema_version\"}\n";

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
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
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
    int before = sr_catalog_schema_opened(cat), now = sr_catalog_schema_version(cat);
    const char *action = was_empty      ? "initialised"
                         : !existed     ? "created"
                         : before < now ? "migrated"
                                        : "unchanged";
    rc = CLI_OK;
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "path");
        json_string(&j, sr_catalog_path(cat));
        json_key(&j, "action");
        json_string(&j, action);
        json_key(&j, "schema_before");
        if (existed && !was_empty)
            json_int(&j, before);
        else
            json_null(&j);
        json_key(&j, "schema_version");
        json_int(&j, now);
        json_object_end(&j);
        rc = json_finish(&j);
    } else if (was_empty) {
        printf("initialised empty file '%s' as a catalogue (schema version %d)\n",
               sr_catalog_path(cat), now);
    } else if (before < now && existed) {
        printf("migrated catalogue '%s' from schema version %d to %d\n", sr_catalog_path(cat),
               before, now);
    } else if (existed) {
        printf("catalogue '%s' already exists (schema version %d)\n", sr_catalog_path(cat), now);
    } else {
        printf("created catalogue '%s' (schema version %d)\n", sr_catalog_path(cat), now);
    }
    sr_catalog_close(cat);
    return rc;
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

static int catalog_backup(const cli_ctx *ctx, int argc, char **argv)
{
    bool force = false;
    const cli_opt opts[] = {{"--force", NULL, &force}, {NULL, NULL, NULL}};
    const cli_spec spec = {"catalog backup", usage_backup, opts, 1, 1, "a file to write"};
    const char *path;
    int rc;
    if (!cli_parse(&spec, argc, argv, &path, NULL, &rc))
        return rc;
    if (!*path)
        return cli_usage_error("'catalog backup' needs a file name");
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_backup(cat, path, force, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    printf("backed up '%s' to '%s'\n", cli_tx(ctx->db_path), cli_tx(path));
    return CLI_OK;
}

typedef struct problem_list {
    char **v;
    size_t count;
    bool nomem;
} problem_list;

static int push_problem(const char *what, void *user)
{
    problem_list *pl = user;
    char **v = realloc(pl->v, (pl->count + 1) * sizeof *v);
    char *copy = v ? strdup(what) : NULL;
    if (v)
        pl->v = v;
    if (!copy) {
        pl->nomem = true;
        return 1;
    }
    pl->v[pl->count++] = copy;
    return 0;
}

static int catalog_check(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"catalog check", usage_check, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    problem_list pl = {NULL, 0, false};
    sr_check_info info;
    sr_status st = sr_catalog_check(cat, push_problem, &pl, &info, &err);
    if (st == SR_OK && pl.nomem)
        st = sr_err_set(&err, SR_E_NOMEM, "out of memory checking the catalogue");
    if (st != SR_OK) {
        rc = cli_fail(st, &err);
    } else if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "path");
        json_string(&j, sr_catalog_path(cat));
        json_key(&j, "ok");
        json_bool(&j, pl.count == 0);
        json_key(&j, "application_id");
        json_int(&j, info.application_id);
        json_key(&j, "schema_version");
        json_int(&j, info.schema_version);
        json_key(&j, "schema_latest");
        json_int(&j, sr_catalog_schema_latest());
        json_key(&j, "materials_without_density");
        json_int(&j, info.no_density);
        json_key(&j, "problems");
        json_array_begin(&j);
        for (size_t i = 0; i < pl.count; i++)
            json_string(&j, pl.v[i]);
        json_array_end(&j);
        json_object_end(&j);
        rc = json_finish(&j);
        if (rc == CLI_OK && pl.count)
            rc = CLI_FAIL;
    } else if (pl.count == 0) {
        printf("ok: '%s' (schema version %d): integrity, foreign keys and history summary\n",
               cli_tx(sr_catalog_path(cat)), info.schema_version);
        rc = CLI_OK;
    } else {
        for (size_t i = 0; i < pl.count; i++)
            printf("%s\n", cli_tx(pl.v[i]));
        cli_error("catalogue '%s' has %zu problem%s", cli_tx(sr_catalog_path(cat)), pl.count,
                  pl.count == 1 ? "" : "s");
        rc = CLI_FAIL;
    }
    if (st == SR_OK && !json && info.no_density > 0)
        cli_note("note: %lld material%s no density, so no deposit mass (see 'symrec materials "
                 "list'; give one with 'symrec materials set NAME --density G_CM3')",
                 (long long)info.no_density, info.no_density == 1 ? " has" : "s have");
    for (size_t i = 0; i < pl.count; i++)
        free(pl.v[i]);
    free(pl.v);
    sr_catalog_close(cat);
    return rc;
}

int cmd_catalog(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"init", catalog_init},
                                          {"info", catalog_info},
                                          {"backup", catalog_backup},
                                          {"check", catalog_check},
                                          {NULL, NULL}};
    return cli_run_subcommand(ctx, "catalog", usage_catalog, subs, argc, argv);
}
