/*
 * cmd_demo.c: `symrec demo`, the README's first command: fills the catalogue with the
 * built-in demo parts (src/mesh/shapes.h: each part's intact mesh, material and symmetry,
 * plus one damaged instance with its serial and what is broken), then prints the part
 * table and every demo part in full. Parts already present are skipped, so running it
 * twice adds nothing. Progress goes to stderr, the catalogue's contents to stdout.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "cli.h"
#include "mesh/shapes.h"

static const char usage[] =
    "usage: symrec [--db FILE] demo [--out DIR] [--part NUMBER] [--catalog-only]\n"
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
    "  --catalog-only   only build and show the catalogue\n";

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

/* Runs one command of this CLI as if typed: words up to NULL. */
static int run_words(const cli_ctx *ctx, cli_fn fn, const char *const *words)
{
    char *argv[24];
    int argc = 0;
    fprintf(stdout, "\n$ symrec --db %s", ctx->db_path);
    for (; argc < 23 && words[argc]; argc++) {
        argv[argc] = (char *)words[argc];
        fprintf(stdout, " %s", words[argc]);
    }
    argv[argc] = NULL;
    fprintf(stdout, "\n");
    fflush(stdout);
    return fn(ctx, argc, argv);
}

static int newest_run(const sr_run_summary *run, void *user)
{
    *(int64_t *)user = run->id;
    return 1;
}

/* The whole job on the demo part `number`'s damaged instance. */
static int whole_job(const cli_ctx *ctx, sr_catalog *cat, const char *number, const char *dir)
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

    printf("\n== The whole job on %s, instance %s ==\n", number, inst);
    const char *look[] = {"part", "show", number, NULL};
    int rc = run_words(ctx, cmd_part, look);
    const char *rec[] = {"reconstruct", inst, "--out", out, NULL};
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_reconstruct, rec);
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
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_run, show);
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_plan, pl);
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_report, rep);
    if (rc == CLI_OK)
        rc = run_words(ctx, cmd_history, hist);
    if (rc == CLI_OK)
        printf("\nfiles: %s/ (restored, patches, result.glb), %s/ (plan.json, layer SVGs, "
               "plan.gcode), %s\n", out, plan, report);
    return rc;
}

int cmd_demo(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = "./symrec-demo", *part = "SR-SHAFT-01";
    bool catalog_only = false;
    const cli_opt opts[] = {{"--out", &out, NULL},
                            {"--part", &part, NULL},
                            {"--catalog-only", NULL, &catalog_only},
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

    printf("Catalogue '%s'\n\n", sr_catalog_path(cat));
    rc = cli_part_list_print(cat, NULL, false);
    for (size_t i = 0; i < count && rc == CLI_OK; i++) {
        printf("\n");
        rc = cli_part_show_print(cat, sr_demo_part_get(i)->number, false);
    }
    if (rc == CLI_OK && !catalog_only) {
        fflush(stdout);
        rc = whole_job(ctx, cat, part, out);
    }
    sr_catalog_close(cat);
    return rc;
}
