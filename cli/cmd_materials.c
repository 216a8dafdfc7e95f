/*
 * cmd_materials.c: `symrec materials list|add|set`: the materials of the catalogue
 * with their density, family and per-process limits (sql/002_rules.sql), as the repair
 * advice uses them (deposit mass, processes a material does not suit). A material
 * enters the catalogue only through `materials add`, with its density; `materials set`
 * corrects one, e.g. a material an older symrec created without a density. Also the
 * refusal of an unknown material that `part add` and `part set` print.
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
    "       symrec [--db FILE] materials add NAME --density G_CM3 [--family F] [--notes T]\n"
    "                                        [--json]\n"
    "       symrec [--db FILE] materials set NAME [--density G_CM3] [--family F]\n"
    "                                        [--notes T] [--json]\n"
    "\n"
    "  list    every material with its density (g/cm³), family and process limits\n"
    "  add     add a material with its density\n"
    "  set     correct a material's density, family or notes\n";

#define FAMILIES "steel, stainless_steel, cast_iron, aluminium, copper, titanium, nickel"

static const char usage_add[] =
    "usage: symrec [--db FILE] materials add NAME --density G_CM3 [--family F] [--notes T]\n"
    "                                        [--json]\n"
    "\n"
    "Adds material NAME (1..63 characters, unique ignoring case) with its density, so\n"
    "parts can name it (`part add --material NAME`) and the repair plan can weigh the\n"
    "deposit.\n"
    "\n"
    "  --density G_CM3  density in g/cm³ at room temperature, > 0 (steel 7.85)\n"
    "  --family F       one of " FAMILIES "\n"
    "                   (repair rules may be conditioned on it)\n"
    "  --notes T        free text: standard, supplier, heat treatment (up to 255 bytes)\n"
    "  --json           print the new material as a JSON object\n";

static const char usage_set[] =
    "usage: symrec [--db FILE] materials set NAME [--density G_CM3] [--family F]\n"
    "                                        [--notes T] [--json]\n"
    "\n"
    "Corrects material NAME (found ignoring case): for instance one an older symrec\n"
    "created without a density when a part first named it. At least one option.\n"
    "\n"
    "  --density G_CM3  density in g/cm³, > 0\n"
    "  --family F       one of " FAMILIES ",\n"
    "                   or \"\" for none\n"
    "  --notes T        free text (\"\" clears it)\n"
    "  --json           print the material as a JSON object\n";

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

/* Parses --density and --family of add/set into *m (density NaN when not given). */
static bool parse_material_opts(const char *density, const char *family, sr_material_new *m)
{
    m->density_g_cm3 = NAN;
    if (density && !cli_parse_double("--density", density, 1e-3, 100,
                                     "a density in g/cm³, 0.001..100", &m->density_g_cm3))
        return false;
    if (family && *family) {
        bool known = false;
        for (size_t i = 0; sr_material_families[i]; i++)
            known = known || strcmp(family, sr_material_families[i]) == 0;
        if (!known) {
            cli_usage_error("bad --family '%s': expected one of " FAMILIES, cli_tx(family));
            return false;
        }
    }
    m->family = family;
    return true;
}

/* Prints material `name` (after a change) as JSON, or a one-line note. */
static int print_material(sr_catalog *cat, const char *name, const char *did, bool json)
{
    sr_err err;
    sr_err_clear(&err);
    sr_material m;
    sr_status st = sr_catalog_material_get(cat, name, &m, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_material(&j, &m);
        return json_finish(&j);
    }
    printf("%s material '%s': %g g/cm³, family %s\n", did, cli_tx(m.name), m.density_g_cm3,
           m.family[0] ? m.family : "-");
    return CLI_OK;
}

static int materials_add(const cli_ctx *ctx, int argc, char **argv)
{
    const char *density = NULL, *family = NULL, *notes = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--density", &density, NULL}, {"--family", &family, NULL}, {"--notes", &notes, NULL},
        {"--json", NULL, &json},       {NULL, NULL, NULL},
    };
    const cli_spec spec = {"materials add", usage_add, opts, 1, 1, "a material name"};
    const char *name;
    int rc;
    if (!cli_parse(&spec, argc, argv, &name, NULL, &rc))
        return rc;
    if (!density)
        return cli_usage_error("'materials add' needs --density (see 'symrec materials add "
                               "--help')");
    sr_material_new m = {.name = name, .notes = notes};
    if (!parse_material_opts(density, family, &m))
        return CLI_USAGE;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "add the material", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_material_add(cat, &m, NULL, &err);
    rc = st == SR_OK ? print_material(cat, name, "added", json) : cli_fail(st, &err);
    sr_catalog_close(cat);
    return rc;
}

static int materials_set(const cli_ctx *ctx, int argc, char **argv)
{
    const char *density = NULL, *family = NULL, *notes = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--density", &density, NULL}, {"--family", &family, NULL}, {"--notes", &notes, NULL},
        {"--json", NULL, &json},       {NULL, NULL, NULL},
    };
    const cli_spec spec = {"materials set", usage_set, opts, 1, 1, "a material name"};
    const char *name;
    int rc;
    if (!cli_parse(&spec, argc, argv, &name, NULL, &rc))
        return rc;
    if (!density && !family && !notes)
        return cli_usage_error("'materials set' needs --density, --family or --notes (see "
                               "'symrec materials set --help')");
    sr_material_new m = {.notes = notes};
    if (!parse_material_opts(density, family, &m))
        return CLI_USAGE;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "change the material", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_material_set(cat, name, &m, &err);
    rc = st == SR_OK ? print_material(cat, name, "changed", json) : cli_fail(st, &err);
    sr_catalog_close(cat);
    return rc;
}

/* The names listed by the refusal of an unknown material: the first MAX_LISTED, then
 * how many more (a shop's own list can be long; the refusal stays one line). */
#define MAX_LISTED 20

typedef struct name_list {
    char *text;   /* "a, b, c", malloc'd */
    size_t count; /* names seen */
    bool nomem;
} name_list;

static int push_name(const sr_material *m, void *user)
{
    name_list *nl = user;
    if (nl->count++ >= MAX_LISTED)
        return 0;
    size_t len = nl->text ? strlen(nl->text) : 0, add = strlen(m->name) + 2;
    char *p = realloc(nl->text, len + add + 1);
    if (!p) {
        nl->nomem = true;
        return 1;
    }
    snprintf(p + len, add + 1, "%s%s", len ? ", " : "", m->name);
    nl->text = p;
    return 0;
}

bool cli_material_known(sr_catalog *cat, const char *name)
{
    sr_err err;
    sr_err_clear(&err);
    sr_material m;
    sr_status st = sr_catalog_material_get(cat, name, &m, &err);
    if (st == SR_OK)
        return true;
    if (st != SR_E_NOTFOUND) {
        cli_fail(st, &err);
        return false;
    }
    name_list nl = {NULL, 0, false};
    sr_err_clear(&err);
    st = sr_catalog_material_list(cat, push_name, &nl, &err);
    char *known = st == SR_OK && !nl.nomem && nl.text ? cli_tx_dup(nl.text) : NULL;
    char more[64] = "";
    if (known && nl.count > MAX_LISTED)
        snprintf(more, sizeof more, " and %zu more (see 'symrec materials list')",
                 nl.count - MAX_LISTED);
    cli_error("unknown material '%s' (known: %s%s; add it with 'symrec materials add %s "
              "--density G_CM3')",
              cli_tx(name),
              known      ? known
              : nl.count ? "see 'symrec materials list'"
                         : "none",
              more, cli_tx(name));
    free(known);
    free(nl.text);
    return false;
}

int cmd_materials(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {
        {"list", materials_list}, {"add", materials_add}, {"set", materials_set}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "materials", usage_materials, subs, argc, argv);
}
