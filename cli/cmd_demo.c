/*
 * cmd_demo.c: `symrec demo`, the README's first command: fills the catalogue with the
 * built-in demo parts (src/shapes.h: each part's intact mesh, material and symmetry,
 * plus one damaged instance with its serial and what is broken), then prints the part
 * table and every demo part in full. Parts already present are skipped, so running it
 * twice adds nothing. Progress goes to stderr, the catalogue's contents to stdout.
 */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "shapes.h"

static const char usage[] =
    "usage: symrec [--db FILE] demo\n"
    "\n"
    "Builds the demo catalogue in FILE (created if missing): for each built-in demo\n"
    "part (a shaft, a gear, a bracket, ...) it adds the part with its intact mesh,\n"
    "material and symmetry, and one damaged instance with its scan. Parts already in\n"
    "the catalogue are skipped, so running it again adds nothing. Then it lists the\n"
    "parts and shows each demo part with its instances and the volume each is missing\n"
    "(mm³ and % of the intact part).\n";

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

int cmd_demo(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_opt opts[] = {{NULL, NULL, NULL}};
    const cli_spec spec = {"demo", usage, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, NULL, NULL, &rc))
        return rc;

    sr_catalog *cat;
    if (!cli_open(ctx, true, &cat))
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
    sr_catalog_close(cat);
    return rc;
}
