/*
 * cmd_part.c: `symrec part add|list|show|set|remove`: parts are the shop's models,
 * each with a unique part number, a name, a material, its intact mesh and the symmetry
 * it is restored by; `set` corrects them, `remove` takes a part out (with its
 * instances and runs only when asked). Also the part table and the full part view
 * that `demo` prints.
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"

static const char usage_part[] =
    "usage: symrec [--db FILE] part add --number P --name N --material M --mesh FILE\n"
    "                               [--notes T] [--symmetry axial|mirror|glide]\n"
    "                               [--order N] [--shift MM] [--allow-open] [--json]\n"
    "       symrec [--db FILE] part list [--name S] [--number S] [--material M] [--json]\n"
    "       symrec [--db FILE] part show P [--json]\n"
    "       symrec [--db FILE] part set P [--number P2] [--name N] [--material M]\n"
    "                               [--notes T] [--symmetry K|none [--order N]\n"
    "                               [--shift MM]] [--json]\n"
    "       symrec [--db FILE] part remove P [--with-runs] [--json]\n"
    "\n"
    "  add     add a part with its intact mesh; prints the new id\n"
    "  list    a table of parts, optionally filtered\n"
    "  show    one part in full (P = part number or id) with its instances\n"
    "  set     correct a part's number, name, material, notes or symmetry\n"
    "  remove  remove a part (with its instances and runs only with --with-runs)\n";

static const char usage_set[] =
    "usage: symrec [--db FILE] part set P [--number P2] [--name N] [--material M]\n"
    "                               [--notes T] [--symmetry K|none [--order N]\n"
    "                               [--shift MM]] [--json]\n"
    "\n"
    "Corrects part P (its number, or its id) and prints it as changed. At least one\n"
    "option. Runs already recorded keep what they used.\n"
    "\n"
    "  --number P2    a new part number, not taken (1..63 characters)\n"
    "  --name N       a new name (1..127 characters)\n"
    "  --material M   a material in the catalogue (see 'symrec materials list')\n"
    "  --notes T      new notes (\"\" clears them)\n"
    "  --symmetry K   axial, mirror or glide, with --order / --shift as for 'part add';\n"
    "                 none removes the part's symmetry\n"
    "  --json         print the part as a JSON object\n";

static const char usage_remove[] =
    "usage: symrec [--db FILE] part remove P [--with-runs] [--json]\n"
    "\n"
    "Removes part P (its number, or its id) with its symmetry and its mesh, and says\n"
    "what went. While damaged instances or runs of it are in the catalogue it is\n"
    "refused, naming how many, and nothing changes.\n"
    "\n"
    "  --with-runs   remove its instances and all their runs (with their sections,\n"
    "                advice and meshes) too, in one transaction; the history summary\n"
    "                loses exactly those runs\n"
    "  --json        print what went as a JSON object: {\"part\", \"id\", \"instances\",\n"
    "                \"runs\", \"meshes\"}\n";

static const char usage_add[] =
    "usage: symrec [--db FILE] part add --number P --name N --material M --mesh FILE\n"
    "                               [--units U] [--notes T] [--symmetry axial|mirror|glide]\n"
    "                               [--order N] [--shift MM] [--allow-open] [--json]\n"
    "\n"
    "Adds a part (a model) with its intact mesh and prints the new part's id. The mesh\n"
    "must be a closed solid (every edge shared by two triangles, consistently oriented,\n"
    "enclosing a positive volume): otherwise the part is refused, naming what is wrong.\n"
    "\n"
    "  --number P     the part number, unique in the catalogue (1..63 characters)\n"
    "  --name N       what the part is called (1..127 characters)\n"
    "  --material M   its material, one in the catalogue (see 'symrec materials list';\n"
    "                 add one with 'symrec materials add M --density G_CM3')\n"
    "  --mesh FILE    the intact mesh: .stl .obj .ply .off .gltf .glb, read in --units\n"
    "                 and stored in mm with the unit noted; at most 2 GiB,\n"
    "                 |coordinate| <= 1e6 mm, largest extent >= 1e-3 mm once in mm\n"
    "  --notes T      free text\n"
    "  --symmetry K   how the part is restored: axial, mirror or glide\n"
    "  --order N      axial only: n-fold order 2..360, or 0 for continuous (default 0)\n"
    "  --shift MM     glide only: the shift along the plane in mm (default 0 = search)\n"
    "  --allow-open   store a mesh that is not a closed solid anyway, with a warning\n"
    "                 (its volume is then not meaningful)\n"
    "  --json         print the new part as a JSON object instead of its id\n" CLI_UNITS_HELP;

static const char usage_list[] =
    "usage: symrec [--db FILE] part list [--name S] [--number S] [--material M] [--json]\n"
    "\n"
    "Lists parts ordered by number: id, number, name, material, triangles, volume (mm³),\n"
    "number of instances and symmetry.\n"
    "\n"
    "  --name S       only names containing S (case-insensitive)\n"
    "  --number S     only numbers containing S (case-insensitive)\n"
    "  --material M   only parts of material M (case-insensitive)\n"
    "  --json         one JSON array of part objects\n";

static const char usage_show[] =
    "usage: symrec [--db FILE] part show P [--json]\n"
    "\n"
    "Shows part P (its number, or its id) in full: name, material, notes, symmetry,\n"
    "mesh size and the unit its file was read in, bounding box (mm), area (mm²),\n"
    "volume (mm³) and its damaged instances.\n"
    "\n"
    "  --json   one JSON object, with an \"instances\" array\n";

static int part_add(const cli_ctx *ctx, int argc, char **argv)
{
    const char *number = NULL, *name = NULL, *material = NULL, *mesh_path = NULL;
    const char *notes = NULL, *sym_kind = NULL, *order = NULL, *shift = NULL, *units = NULL;
    bool json = false, allow_open = false;
    const cli_opt opts[] = {
        {"--allow-open", NULL, &allow_open},
        {"--units", &units, NULL},
        {"--number", &number, NULL},
        {"--name", &name, NULL},
        {"--material", &material, NULL},
        {"--mesh", &mesh_path, NULL},
        {"--notes", &notes, NULL},
        {"--symmetry", &sym_kind, NULL},
        {"--order", &order, NULL},
        {"--shift", &shift, NULL},
        {"--json", NULL, &json},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"part add", usage_add, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    const char *missing = !number ? "--number" : !name ? "--name" : !material ? "--material"
                        : !mesh_path ? "--mesh" : NULL;
    if (missing)
        return cli_usage_error("'part add' needs %s (see 'symrec part add --help')", missing);
    sr_symmetry sym;
    if (!cli_parse_symmetry(sym_kind, order, shift, 0, &sym))
        return CLI_USAGE;
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "add the part", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    sr_part_info info;
    int64_t id = 0;
    /* The material first: an unknown one is refused before a large mesh is read. */
    if (!cli_material_known(cat, material)) {
        sr_catalog_close(cat);
        return CLI_FAIL;
    }
    sr_status st = cli_mesh_read(mesh_path, unit, &mesh, &unit, &err);
    if (st == SR_OK) {
        sr_part_new part = {
            .source_unit = unit,
            .number = number,
            .name = name,
            .material = material,
            .notes = notes,
            .mesh = &mesh,
            .source_file = mesh_path,
            .symmetry = sym,
            .allow_open = allow_open,
        };
        if (allow_open && !sr_mesh_is_closed(&mesh))
            cli_note(
                "warning: part '%s': '%s' is not a closed solid; stored as asked (--allow-open), "
                "its volume is not meaningful",
                number, mesh_path);
        st = sr_catalog_part_add(cat, &part, &id, &err);
    }
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, number, &info, &err);
    sr_mesh_release(&mesh);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    cli_note("added part '%s' (id %lld): %zu triangles, %.1f mm³", cli_tx(info.number),
             (long long)id, info.tri_count, info.volume_mm3);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_part(&j, &info);
        rc = json_finish(&j);
    } else {
        printf("%lld\n", (long long)id);
        rc = CLI_OK;
    }
    sr_catalog_close(cat);
    return rc;
}

int cli_part_list_print(sr_catalog *cat, const sr_part_filter *filter, bool json)
{
    cli_parts parts;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = cli_parts_load(cat, filter, &parts, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_array_begin(&j);
        for (size_t i = 0; i < parts.count; i++)
            json_part(&j, &parts.v[i]);
        json_array_end(&j);
        cli_parts_release(&parts);
        return json_finish(&j);
    }
    if (parts.count == 0) {
        printf("no parts\n");
        cli_parts_release(&parts);
        return CLI_OK;
    }
    static const char *const headers[] = {"id", "number", "name", "material", "triangles",
                                          "volume mm³", "instances", "symmetry"};
    static const bool right[] = {true, false, false, false, true, true, true, false};
    cli_table t;
    cli_table_init(&t, 8, headers, right);
    for (size_t i = 0; i < parts.count; i++) {
        const sr_part_info *p = &parts.v[i];
        char sym[64];
        cli_table_cell(&t, "%lld", (long long)p->id);
        cli_table_cell(&t, "%s", p->number);
        cli_table_cell(&t, "%s", p->name);
        cli_table_cell(&t, "%s", p->material[0] ? p->material : "-");
        if (p->mesh_id) {
            cli_table_cell(&t, "%zu", p->tri_count);
            cli_table_cell(&t, "%.1f", p->volume_mm3);
        } else {
            cli_table_cell(&t, "-");
            cli_table_cell(&t, "-");
        }
        cli_table_cell(&t, "%lld", (long long)p->instance_count);
        cli_table_cell(&t, "%s", cli_sym_str(&p->symmetry, sym, sizeof sym));
    }
    bool ok = cli_table_print(&t, stdout, 0);
    cli_table_release(&t);
    cli_parts_release(&parts);
    return ok ? CLI_OK : CLI_FAIL;
}

static void print_part_text(const sr_part_info *p)
{
    char sym[64];
    printf("part %s (id %lld)\n", cli_tx(p->number), (long long)p->id);
    cli_print_field(stdout, "  name:       ", p->name);
    cli_print_field(stdout, "  material:   ", p->material[0] ? p->material : "-");
    if (p->notes[0])
        cli_print_field(stdout, "  notes:      ", p->notes);
    printf("  symmetry:   %s\n", cli_sym_str(&p->symmetry, sym, sizeof sym));
    if (p->mesh_id) {
        printf("  mesh:       %zu vertices, %zu triangles, read in %s\n", p->vertex_count,
               p->tri_count, p->source_unit);
        cli_print_bbox(stdout, "  bbox:       ", p->bbox_min, p->bbox_max);
        printf("  area:       %.1f mm²\n", p->area_mm2);
        printf("  volume:     %.1f mm³\n", p->volume_mm3);
    } else {
        printf("  mesh:       none\n");
    }
    printf("  created:    %s\n", p->created_at);
    printf("  instances:  %lld\n", (long long)p->instance_count);
}

int cli_part_show_print(sr_catalog *cat, const char *key, bool json)
{
    sr_err err;
    sr_err_clear(&err);
    sr_part_info p;
    cli_instances list;
    sr_status st = sr_catalog_part_find(cat, key, &p, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    /* By number: the catalogue tries numbers before ids, so this is always p. */
    st = cli_instances_load(cat, p.number, &list, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    bool ok = true;
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_part_members(&j, &p);
        json_key(&j, "instances");
        json_array_begin(&j);
        for (size_t i = 0; i < list.count; i++)
            json_instance(&j, &list.v[i]);
        json_array_end(&j);
        json_object_end(&j);
        ok = json_finish(&j) == CLI_OK;
    } else {
        print_part_text(&p);
        if (list.count > 0)
            ok = cli_instance_table(cat, &list, false, 4);
        for (size_t i = 0; ok && i < list.count; i++) {
            if (!list.v[i].notes[0])
                continue;
            char label[48];
            snprintf(label, sizeof label, "    instance %lld: ", (long long)list.v[i].id);
            cli_print_field(stdout, label, list.v[i].notes);
        }
    }
    cli_instances_release(&list);
    return ok ? CLI_OK : CLI_FAIL;
}

static int part_list(const cli_ctx *ctx, int argc, char **argv)
{
    sr_part_filter filter = {NULL, NULL, NULL};
    bool json = false;
    const cli_opt opts[] = {
        {"--name", &filter.name, NULL},
        {"--number", &filter.number, NULL},
        {"--material", &filter.material, NULL},
        {"--json", NULL, &json},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"part list", usage_list, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    rc = cli_part_list_print(cat, &filter, json);
    sr_catalog_close(cat);
    return rc;
}

static int part_show(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"part show", usage_show, opts, 1, 1, "a part number or id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    rc = cli_part_show_print(cat, key, json);
    sr_catalog_close(cat);
    return rc;
}

static int part_set(const cli_ctx *ctx, int argc, char **argv)
{
    const char *number = NULL, *name = NULL, *material = NULL, *notes = NULL;
    const char *sym_kind = NULL, *order = NULL, *shift = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--number", &number, NULL},
        {"--name", &name, NULL},
        {"--material", &material, NULL},
        {"--notes", &notes, NULL},
        {"--symmetry", &sym_kind, NULL},
        {"--order", &order, NULL},
        {"--shift", &shift, NULL},
        {"--json", NULL, &json},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"part set", usage_set, opts, 1, 1, "a part number or id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    if (!number && !name && !material && !notes && !sym_kind && !order && !shift)
        return cli_usage_error("'part set' needs something to change (see 'symrec part set "
                               "--help')");
    sr_part_change ch = {.number = number, .name = name, .material = material, .notes = notes};
    if (sym_kind && strcmp(sym_kind, "none") == 0) {
        if (order || shift)
            return cli_usage_error("--%s applies to --symmetry axial or glide, not none",
                                   order ? "order" : "shift");
        ch.set_symmetry = true;
    } else if (sym_kind || order || shift) {
        if (!cli_parse_symmetry(sym_kind, order, shift, 0, &ch.symmetry))
            return CLI_USAGE;
        ch.set_symmetry = true;
    }
    if (number && !*number)
        return cli_usage_error("bad --number '': expected 1..63 characters");
    if (name && !*name)
        return cli_usage_error("bad --name '': expected 1..127 characters");

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "change the part", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_part_info before, info;
    sr_status st = sr_catalog_part_find(cat, key, &before, &err);
    if (st == SR_OK && material && !cli_material_known(cat, material)) {
        sr_catalog_close(cat);
        return CLI_FAIL;
    }
    if (st == SR_OK)
        st = sr_catalog_part_set(cat, before.number, &ch, &err);
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, number ? number : before.number, &info, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    cli_note("changed part '%s' (id %lld)", cli_tx(info.number), (long long)info.id);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_part(&j, &info);
        rc = json_finish(&j);
    } else {
        print_part_text(&info);
        rc = CLI_OK;
    }
    sr_catalog_close(cat);
    return rc;
}

/* "2 instances and 3 runs" style counts of what a removal took. */
void cli_removal_str(const sr_removal *r, bool instances, char *buf, size_t size)
{
    int n = 0;
    if (instances)
        n = snprintf(buf, size, "%lld instance%s and ", (long long)r->instances,
                     r->instances == 1 ? "" : "s");
    if (n >= 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, "%lld run%s", (long long)r->runs,
                 r->runs == 1 ? "" : "s");
}

static int part_remove(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false, with_runs = false;
    const cli_opt opts[] = {
        {"--with-runs", NULL, &with_runs}, {"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"part remove", usage_remove, opts, 1, 1, "a part number or id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "remove the part", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_part_info p;
    sr_removal r;
    sr_status st = sr_catalog_part_find(cat, key, &p, &err);
    if (st == SR_OK)
        st = sr_catalog_part_remove(cat, p.number, with_runs ? SR_CATALOG_WITH_RUNS : 0, &r, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "part");
        json_string(&j, p.number);
        json_key(&j, "id");
        json_int(&j, p.id);
        json_key(&j, "instances");
        json_int(&j, r.instances);
        json_key(&j, "runs");
        json_int(&j, r.runs);
        json_key(&j, "meshes");
        json_int(&j, r.meshes);
        json_object_end(&j);
        return json_finish(&j);
    }
    char what[96] = "";
    if (r.instances || r.runs) {
        memcpy(what, " with ", 7);
        cli_removal_str(&r, true, what + 6, sizeof what - 6);
    }
    printf("removed part %s (id %lld)%s\n", cli_tx(p.number), (long long)p.id, what);
    return CLI_OK;
}

int cmd_part(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"add", part_add},       {"list", part_list},
                                          {"show", part_show},     {"set", part_set},
                                          {"remove", part_remove}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "part", usage_part, subs, argc, argv);
}
