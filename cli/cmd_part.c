/*
 * cmd_part.c: `symrec part add|list|show`: parts are the shop's models, each with a
 * unique part number, a name, a material, its intact mesh and the symmetry it is
 * restored by. Also the part table and the full part view that `demo` prints.
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"

static const char usage_part[] =
    "usage: symrec [--db FILE] part add --number P --name N --material M --mesh FILE\n"
    "                               [--notes T] [--symmetry axial|mirror|glide]\n"
    "                               [--order N] [--shift MM] [--json]\n"
    "       symrec [--db FILE] part list [--name S] [--number S] [--material M] [--json]\n"
    "       symrec [--db FILE] part show P [--json]\n"
    "\n"
    "  add     add a part with its intact mesh; prints the new id\n"
    "  list    a table of parts, optionally filtered\n"
    "  show    one part in full (P = part number or id) with its instances\n";

static const char usage_add[] =
    "usage: symrec [--db FILE] part add --number P --name N --material M --mesh FILE\n"
    "                               [--notes T] [--symmetry axial|mirror|glide]\n"
    "                               [--order N] [--shift MM] [--json]\n"
    "\n"
    "Adds a part (a model) with its intact mesh and prints the new part's id.\n"
    "\n"
    "  --number P     the part number, unique in the catalogue (1..63 characters)\n"
    "  --name N       what the part is called (1..127 characters)\n"
    "  --material M   its material, e.g. 42CrMo4\n"
    "  --mesh FILE    the intact mesh: .stl .obj .ply .off .gltf .glb, in mm; at most\n"
    "                 2 GiB, |coordinate| <= 1e6 mm, largest extent >= 1e-3 mm\n"
    "  --notes T      free text\n"
    "  --symmetry K   how the part is restored: axial, mirror or glide\n"
    "  --order N      axial only: n-fold order 2..360, or 0 for continuous (default 0)\n"
    "  --shift MM     glide only: the shift along the plane in mm (default 0 = search)\n"
    "  --json         print the new part as a JSON object instead of its id\n";

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
    "mesh size, bounding box (mm), area (mm²), volume (mm³) and its damaged instances.\n"
    "\n"
    "  --json   one JSON object, with an \"instances\" array\n";

static int part_add(const cli_ctx *ctx, int argc, char **argv)
{
    const char *number = NULL, *name = NULL, *material = NULL, *mesh_path = NULL;
    const char *notes = NULL, *sym_kind = NULL, *order = NULL, *shift = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--number", &number, NULL},   {"--name", &name, NULL},
        {"--material", &material, NULL}, {"--mesh", &mesh_path, NULL},
        {"--notes", &notes, NULL},     {"--symmetry", &sym_kind, NULL},
        {"--order", &order, NULL},     {"--shift", &shift, NULL},
        {"--json", NULL, &json},       {NULL, NULL, NULL},
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

    sr_catalog *cat;
    if (!cli_open(ctx, false, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    sr_part_info info;
    int64_t id = 0;
    sr_status st = sr_mesh_read(mesh_path, &mesh, &err);
    if (st == SR_OK) {
        sr_part_new part = {
            .number = number, .name = name, .material = material, .notes = notes,
            .mesh = &mesh, .source_file = mesh_path, .symmetry = sym,
        };
        st = sr_catalog_part_add(cat, &part, &id, &err);
    }
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, number, &info, &err);
    sr_mesh_release(&mesh);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    cli_note("added part '%s' (id %lld): %zu triangles, %.1f mm³", info.number,
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
    printf("part %s (id %lld)\n", p->number, (long long)p->id);
    cli_print_field(stdout, "  name:       ", p->name);
    cli_print_field(stdout, "  material:   ", p->material[0] ? p->material : "-");
    if (p->notes[0])
        cli_print_field(stdout, "  notes:      ", p->notes);
    printf("  symmetry:   %s\n", cli_sym_str(&p->symmetry, sym, sizeof sym));
    if (p->mesh_id) {
        printf("  mesh:       %zu vertices, %zu triangles\n", p->vertex_count, p->tri_count);
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
    if (!cli_open(ctx, false, &cat))
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
    if (!cli_open(ctx, false, &cat))
        return CLI_FAIL;
    rc = cli_part_show_print(cat, key, json);
    sr_catalog_close(cat);
    return rc;
}

int cmd_part(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"add", part_add}, {"list", part_list}, {"show", part_show}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "part", usage_part, subs, argc, argv);
}
