/*
 * cmd_materials.c: `symrec materials list`: the materials of the catalogue with their
 * density, family and per-process limits (sql/002_rules.sql), as the repair advice
 * uses them (deposit mass, processes a material does not suit).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "catalog/catalog_rules.h"
#include "cli.h"
#include "json_out.h"

static const char usage_materials[] =
    "usage: symrec [--db FILE] materials list [--json]\n"
    "\n"
    "  list    every material with its density (g/cm³), family and process limits\n";

static const char usage_list[] =
    "usage: symrec [--db FILE] materials list [--json]\n"
    "\n"
    "Lists the materials: density in g/cm³, family, and per repair process whether it\n"
    "suits the material ('-' = not suitable), with its depth limit in mm if any.\n"
    "\n"
    "  --json   one JSON array of material objects with their limits\n";

typedef struct material_vec {
    sr_material *v;
    size_t count, cap;
    bool nomem;
} material_vec;

static int push_material(const sr_material *m, void *user)
{
    material_vec *mv = user;
    sr_material *v = sr_grow(mv->v, mv->count, &mv->cap, sizeof *v);
    if (!v) {
        mv->nomem = true;
        return 1;
    }
    mv->v = v;
    mv->v[mv->count++] = *m;
    return 0;
}

static void json_material(json_out *j, const sr_material *m)
{
    json_object_begin(j);
    json_key(j, "name");
    json_string(j, m->name);
    json_key(j, "density_g_cm3");
    json_number(j, m->density_g_cm3);
    json_key(j, "family");
    json_string(j, m->family[0] ? m->family : NULL);
    json_key(j, "notes");
    json_string(j, m->notes);
    json_key(j, "limits");
    json_array_begin(j);
    for (size_t i = 0; i < m->limit_count; i++) {
        const sr_material_limit *l = &m->limits[i];
        json_object_begin(j);
        json_key(j, "process");
        json_string(j, l->process);
        json_key(j, "suitable");
        json_bool(j, l->suitable != 0);
        json_key(j, "max_depth_mm");
        json_number(j, l->max_depth_mm);
        json_key(j, "preheat_c");
        json_number(j, l->preheat_c);
        json_key(j, "notes");
        json_string(j, l->notes);
        json_key(j, "source");
        json_string(j, l->source);
        json_object_end(j);
    }
    json_array_end(j);
    json_object_end(j);
}

static void limits_str(const sr_material *m, char *out, size_t size)
{
    size_t o = 0;
    out[0] = '\0';
    for (size_t i = 0; i < m->limit_count && o + 1 < size; i++) {
        const sr_material_limit *l = &m->limits[i];
        char depth[32] = "";
        if (!isnan(l->max_depth_mm))
            snprintf(depth, sizeof depth, " <= %g mm", l->max_depth_mm);
        int n = snprintf(out + o, size - o, "%s%s%s%s", o ? ", " : "", l->suitable ? "" : "-",
                         l->process, depth);
        o = n < 0 ? o : (size_t)n + o >= size ? size - 1 : o + (size_t)n;
    }
}

static int materials_list(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"materials list", usage_list, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    material_vec mv = {NULL, 0, 0, false};
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_material_list(cat, push_material, &mv, &err);
    sr_catalog_close(cat);
    if (st == SR_OK && mv.nomem)
        st = sr_err_set(&err, SR_E_NOMEM, "out of memory listing materials");
    if (st != SR_OK) {
        free(mv.v);
        return cli_fail(st, &err);
    }
    rc = CLI_OK;
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_array_begin(&j);
        for (size_t i = 0; i < mv.count; i++)
            json_material(&j, &mv.v[i]);
        json_array_end(&j);
        rc = json_finish(&j);
    } else {
        static const char *const headers[] = {"name", "g/cm³", "family", "processes"};
        static const bool right[] = {false, true, false, false};
        cli_table t;
        cli_table_init(&t, 4, headers, right);
        for (size_t i = 0; i < mv.count; i++) {
            const sr_material *m = &mv.v[i];
            char lim[400];
            limits_str(m, lim, sizeof lim);
            cli_table_cell(&t, "%s", m->name);
            if (isnan(m->density_g_cm3))
                cli_table_cell(&t, "-");
            else
                cli_table_cell(&t, "%g", m->density_g_cm3);
            cli_table_cell(&t, "%s", m->family[0] ? m->family : "-");
            cli_table_cell(&t, "%s", lim[0] ? lim : "-");
        }
        rc = cli_table_print(&t, stdout, 0) ? CLI_OK : CLI_FAIL;
        cli_table_release(&t);
    }
    free(mv.v);
    return rc;
}

int cmd_materials(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"list", materials_list}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "materials", usage_materials, subs, argc, argv);
}
