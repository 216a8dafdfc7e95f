/*
 * cmd_demo.c: `symrec demo`, the README's first command: fills the catalogue with the
 * built-in demo parts (src/mesh/shapes.h: each part's intact mesh, material and symmetry,
 * plus one damaged instance with its serial and what is broken), then prints the part
 * table and every demo part in full. Parts already present are skipped, so running it
 * twice adds nothing. Progress goes to stderr, the catalogue's contents to stdout.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "cli.h"
#include "json_out.h"
#include "mesh/shapes.h"

static const char usage[] =
    "usage: symrec [--db FILE] demo [--out DIR] [--part NUMBER] [--catalog-only] [--json]\n"
    "\n"
    "Builds the demo catalogue in FILE (created if missing): for each built-in demo\n"
    "part (a shaft, a gear, a bracket, ...) it adds the part with its intact mesh,\n"
    "material and symmetry, and one damaged instance with its scan. Parts already in\n"
    "the catalogue are skipped, so running it again adds nothing. Then it lists the\n"
    "parts and shows each demo part with its instances and the volume each is missing\n"
    "(mm³ and % of the intact part).\n"
    "\n"
    "Then the whole job on one broken part, as a repair engineer runs it: looks the part\n"
    "up, reconstructs its damaged instance by the part's symmetry (recording the run),\n"
    "shows the run with the feature description of each missing section and the repair\n"
    "advice, writes the build plan (plan.json, layer SVGs, G-code) and the HTML report,\n"
    "and shows the part's repair history.\n"
    "\n"
    "  --out DIR        where the run's files go (default ./symrec-demo)\n"
    "  --part NUMBER    the demo part to repair (default SR-SHAFT-01)\n"
    "  --catalog-only   only build and show the catalogue\n"
    "  --json           print one JSON object instead of the listings and the job's\n"
    "                   output: {\"path\", \"schema_version\", \"parts_added\",\n"
    "                   \"instances_added\", \"parts\": [{\"number\", \"id\",\n"
    "                   \"instance_ids\"}], \"job\": {\"part\", \"instance_id\", \"run_id\",\n"
    "                   \"out\", \"plan\", \"report\"} (null with --catalog-only)}\n";

/* The demo parts' materials that sql/002_rules.sql does not seed, with their densities:
 * a part may name only a material in the catalogue, and the deposit mass needs the
 * density. Added when missing; one already there (an older symrec created it without
 * a density) is left as the shop has it ('materials set' corrects it). */
static const sr_material_new demo_materials[] = {
    {"AlSi10Mg", 2.67, "aluminium",
     "EN 1706 EN AC-43000 cast aluminium alloy, also a common powder for additive manufacturing"},
    {"S355", 7.85, "steel", "EN 10025-2 non-alloy structural steel"},
};

static sr_status add_demo_material(sr_catalog *cat, const char *name, sr_err *err)
{
    for (size_t i = 0; i < sizeof demo_materials / sizeof demo_materials[0]; i++) {
        if (strcmp(demo_materials[i].name, name) != 0)
            continue;
        sr_material m;
        sr_status st = sr_catalog_material_get(cat, name, &m, err);
        if (st != SR_E_NOTFOUND)
            return st;
        sr_err_clear(err);
        st = sr_catalog_material_add(cat, &demo_materials[i], NULL, err);
        if (st == SR_OK)
            cli_note("demo: added material %s (%g g/cm³)", name, demo_materials[i].density_g_cm3);
        return st;
    }
    return SR_OK;
}

/* Adds demo part i and/or its damaged instance, whichever is not there yet. Counts
 * what it added. */
static sr_status add_demo_part(sr_catalog *cat, size_t i, int *parts_added,
                               int *instances_added, sr_err *err)
{
    const sr_demo_part *dp = sr_demo_part_get(i);
    sr_part_info info;
    sr_status st = sr_catalog_part_find(cat, dp->number, &info, err);
    bool have_part = st == SR_OK;
    if (st != SR_OK && st != SR_E_NOTFOUND)
        return st;
    sr_err_clear(err);
    if (have_part && info.instance_count > 0) {
        cli_note("demo: %s already in the catalogue, skipped", dp->number);
        return SR_OK;
    }
    sr_mesh intact, damaged;
    sr_mesh_init(&intact);
    sr_mesh_init(&damaged);
    st = have_part ? SR_OK : add_demo_material(cat, dp->material, err);
    if (st == SR_OK)
        st = sr_demo_part_build(i, &intact, &damaged, err);
    if (st == SR_OK && !have_part) {
        sr_part_new part = {
            .number = dp->number,
            .name = dp->name,
            .material = dp->material,
            .notes = dp->notes,
            .mesh = &intact,
            .source_file = "demo",
            .symmetry = {(sr_sym_kind)dp->sym_kind, dp->sym_order, dp->sym_shift_mm},
        };
        int64_t id;
        st = sr_catalog_part_add(cat, &part, &id, err);
        if (st == SR_OK) {
            (*parts_added)++;
            cli_note("demo: added part %s '%s' (id %lld, %zu triangles)", dp->number, dp->name,
                     (long long)id, intact.tri_count);
        }
    }
    if (st == SR_OK) {
        sr_instance_new inst = {
            .part = dp->number,
            .mesh = &damaged,
            .serial = dp->serial,
            .notes = dp->damage_notes,
            .source_file = "demo",
        };
        int64_t id;
        st = sr_catalog_instance_add(cat, &inst, &id, err);
        if (st == SR_OK) {
            (*instances_added)++;
            cli_note("demo: added damaged instance %lld of %s, serial %s (%zu triangles)",
                     (long long)id, dp->number, dp->serial, damaged.tri_count);
        }
    }
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);
    return st;
}

/* Runs one command of this CLI as if typed: words up to NULL. With `silent` (demo
 * --json) what it prints to stdout goes to /dev/null, so stdout holds only the JSON;
 * its errors still reach stderr. */
static int run_words(const cli_ctx *ctx, cli_fn fn, const char *const *words, bool silent)
{
    char *argv[24];
    int argc = 0;
    for (; argc < 23 && words[argc]; argc++)
        argv[argc] = (char *)words[argc];
    argv[argc] = NULL;
    if (!silent) {
        fprintf(stdout, "\n$ symrec --db %s", ctx->db_path);
        for (int i = 0; i < argc; i++)
            fprintf(stdout, " %s", words[i]);
        fprintf(stdout, "\n");
        fflush(stdout);
        return fn(ctx, argc, argv);
    }
    fflush(stdout);
    int saved = dup(STDOUT_FILENO), null_fd = open("/dev/null", O_WRONLY);
    if (saved < 0 || null_fd < 0 || dup2(null_fd, STDOUT_FILENO) < 0) {
        if (saved >= 0)
            close(saved);
        if (null_fd >= 0)
            close(null_fd);
        return cli_error("cannot silence the output of '%s': %s", words[0], strerror(errno));
    }
    close(null_fd);
    int rc = fn(ctx, argc, argv);
    fflush(stdout);
    if (dup2(saved, STDOUT_FILENO) < 0)
        rc = cli_error("cannot restore stdout: %s", strerror(errno));
    close(saved);
    return rc;
}

static int newest_run(const sr_run_summary *run, void *user)
{
    *(int64_t *)user = run->id;
    return 1;
}

/* What the whole job made, for demo --json. */
typedef struct job_done {
    int64_t instance_id, run_id;
    char out[1024], plan[1024], report[1024];
} job_done;

/* The whole job on the demo part `number`'s damaged instance; silent: its commands'
 * output is not shown (demo --json), what it made goes into *done. */
static int whole_job(const cli_ctx *ctx, sr_catalog *cat, const char *number, const char *dir,
                     bool silent, job_done *done)
{
    cli_instances list = {0};
    sr_err err;
    sr_err_clear(&err);
    sr_status st = cli_instances_load(cat, number, &list, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (list.count == 0) {
        cli_instances_release(&list);
        return cli_error("demo part %s has no damaged instance", number);
    }
    char inst[32], run[32], out[1024], plan[1024], report[1024];
    snprintf(inst, sizeof inst, "%lld", (long long)list.v[0].id);
    cli_instances_release(&list);
    snprintf(out, sizeof out, "%s/run", dir);
    snprintf(plan, sizeof plan, "%s/plan", dir);
    snprintf(report, sizeof report, "%s/report.html", dir);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return cli_error("cannot create '%s': %s", dir, strerror(errno));

    if (!silent)
        printf("\n== The whole job on %s, instance %s ==\n", number, inst);
    const char *look[] = {"part", "show", number, NULL};
    int rc = silent ? CLI_OK : run_words(ctx, cmd_part, look, false);
    const char *rec[] = {"reconstruct", inst, "--out", out, NULL};
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_reconstruct, rec, silent);
    int64_t run_id = 0;
    sr_run_filter f = {0};
    f.part = number;
    if (rc == CLI_OK && (st = sr_catalog_run_list(cat, &f, newest_run, &run_id, &err)) != SR_OK)
        return cli_fail(st, &err);
    if (rc != CLI_OK)
        return rc;
    snprintf(run, sizeof run, "%lld", (long long)run_id);
    const char *show[] = {"run", "show", run, NULL};
    const char *pl[] = {"plan", run, "--out", plan, NULL};
    const char *rep[] = {"report", run, "--out", report, NULL};
    const char *hist[] = {"history", "--part", number, NULL};
    if (rc == CLI_OK && !silent)
        rc = run_words(ctx, cmd_run, show, false);
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_plan, pl, silent);
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_report, rep, silent);
    if (rc == CLI_OK && !silent)
        rc = run_words(ctx, cmd_history, hist, false);
    done->instance_id = atoll(inst);
    done->run_id = run_id;
    snprintf(done->out, sizeof done->out, "%s", out);
    snprintf(done->plan, sizeof done->plan, "%s", plan);
    snprintf(done->report, sizeof done->report, "%s", report);
    if (rc == CLI_OK && !silent)
        printf("\nfiles: %s/ (restored, patches, result.glb), %s/ (plan.json, layer SVGs, "
               "plan.gcode), %s\n", out, plan, report);
    return rc;
}

/* demo --json: the catalogue, the demo parts with their instances, and the job (NULL
 * job_part: none was run). */
static int print_json(sr_catalog *cat, int parts_added, int instances_added, const char *job_part,
                      const job_done *done)
{
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_key(&j, "path");
    json_string(&j, sr_catalog_path(cat));
    json_key(&j, "schema_version");
    json_int(&j, sr_catalog_schema_version(cat));
    json_key(&j, "parts_added");
    json_int(&j, parts_added);
    json_key(&j, "instances_added");
    json_int(&j, instances_added);
    json_key(&j, "parts");
    json_array_begin(&j);
    for (size_t i = 0; i < sr_demo_part_count(); i++) {
        const char *number = sr_demo_part_get(i)->number;
        sr_err err;
        sr_err_clear(&err);
        sr_part_info p;
        cli_instances list = {0};
        sr_status st = sr_catalog_part_find(cat, number, &p, &err);
        if (st == SR_OK)
            st = cli_instances_load(cat, number, &list, &err);
        if (st != SR_OK) {
            json_discard(&j);
            return cli_fail(st, &err);
        }
        json_object_begin(&j);
        json_key(&j, "number");
        json_string(&j, number);
        json_key(&j, "id");
        json_int(&j, p.id);
        json_key(&j, "instance_ids");
        json_array_begin(&j);
        for (size_t k = 0; k < list.count; k++)
            json_int(&j, list.v[k].id);
        json_array_end(&j);
        json_object_end(&j);
        cli_instances_release(&list);
    }
    json_array_end(&j);
    json_key(&j, "job");
    if (!job_part) {
        json_null(&j);
    } else {
        json_object_begin(&j);
        json_key(&j, "part");
        json_string(&j, job_part);
        json_key(&j, "instance_id");
        json_int(&j, done->instance_id);
        json_key(&j, "run_id");
        json_int(&j, done->run_id);
        json_key(&j, "out");
        json_string(&j, done->out);
        json_key(&j, "plan");
        json_string(&j, done->plan);
        json_key(&j, "report");
        json_string(&j, done->report);
        json_object_end(&j);
    }
    json_object_end(&j);
    return json_finish(&j);
}

int cmd_demo(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = "./symrec-demo", *part = "SR-SHAFT-01";
    bool catalog_only = false, json = false;
    const cli_opt opts[] = {{"--out", &out, NULL},
                            {"--part", &part, NULL},
                            {"--catalog-only", NULL, &catalog_only},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"demo", usage, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, NULL, NULL, &rc))
        return rc;
    bool known = false;
    for (size_t i = 0; i < sr_demo_part_count(); i++)
        known = known || strcmp(sr_demo_part_get(i)->number, part) == 0;
    if (!known)
        return cli_usage_error("bad --part '%s': expected a demo part number, e.g. %s", part,
                               sr_demo_part_get(0)->number);

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_CREATE, "add the demo parts", &cat))
        return CLI_FAIL;
    cli_note("demo: catalogue '%s' (schema version %d)", sr_catalog_path(cat),
             sr_catalog_schema_version(cat));
    sr_err err;
    sr_err_clear(&err);
    size_t count = sr_demo_part_count();
    int parts_added = 0, instances_added = 0;
    for (size_t i = 0; i < count; i++) {
        sr_status st = add_demo_part(cat, i, &parts_added, &instances_added, &err);
        if (st != SR_OK) {
            sr_catalog_close(cat);
            return cli_fail(st, &err);
        }
    }
    cli_note("demo: added %d parts and %d damaged instances (%zu demo parts in all)",
             parts_added, instances_added, count);

    job_done done;
    memset(&done, 0, sizeof done);
    if (json) {
        rc = catalog_only ? CLI_OK : whole_job(ctx, cat, part, out, true, &done);
        if (rc == CLI_OK)
            rc = print_json(cat, parts_added, instances_added, catalog_only ? NULL : part, &done);
        sr_catalog_close(cat);
        return rc;
    }
    printf("Catalogue '%s'\n\n", sr_catalog_path(cat));
    rc = cli_part_list_print(cat, NULL, false);
    for (size_t i = 0; i < count && rc == CLI_OK; i++) {
        printf("\n");
        rc = cli_part_show_print(cat, sr_demo_part_get(i)->number, false);
    }
    if (rc == CLI_OK && !catalog_only) {
        fflush(stdout);
        rc = whole_job(ctx, cat, part, out, false, &done);
    }
    sr_catalog_close(cat);
    return rc;
}
