/*
 * cmd_export.c: `symrec export part|instance ID --out FILE`: writes a stored mesh (a
 * part's intact mesh or an instance's scan) to a file whose extension picks the format:
 * stl (binary), obj, ply (binary), off, gltf or glb. The write is atomic (mesh_io).
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"

static const char usage[] =
    "usage: symrec [--db FILE] export part P --out FILE [--json]\n"
    "       symrec [--db FILE] export instance ID --out FILE [--json]\n"
    "\n"
    "Writes a stored mesh: a part's intact mesh (P = part number or id) or a damaged\n"
    "instance's scan. The format comes from FILE's extension: .stl (binary), .obj,\n"
    ".ply (binary), .off, .gltf or .glb. Coordinates are in mm.\n"
    "\n"
    "  --out FILE   where to write (replaced atomically if it exists)\n"
    "  --json       print {\"path\", \"format\", \"vertices\", \"triangles\"} as JSON\n";

int cmd_export(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--out", &out, NULL}, {"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"export", usage, opts, 2, 2, "'part P' or 'instance ID'"};
    const char *pos[2];
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, NULL, &rc))
        return rc;
    bool is_part = strcmp(pos[0], "part") == 0;
    if (!is_part && strcmp(pos[0], "instance") != 0)
        return cli_usage_error("bad 'export %s': expected 'export part P' or "
                               "'export instance ID'", pos[0]);
    int64_t inst_id = 0;
    if (!is_part && !cli_parse_id("ID", pos[1], &inst_id))
        return CLI_USAGE;
    if (!out)
        return cli_usage_error("'export' needs --out FILE (see 'symrec export --help')");
    sr_format fmt = sr_format_from_path(out);
    if (fmt == SR_FMT_UNKNOWN)
        return cli_usage_error("bad --out '%s': expected a file ending in .stl, .obj, .ply, "
                               ".off, .gltf or .glb", out);

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    sr_status st;
    char what[96];
    if (is_part) {
        sr_part_info p;
        st = sr_catalog_part_find(cat, pos[1], &p, &err);
        if (st == SR_OK)
            st = sr_catalog_part_mesh(cat, p.id, &mesh, &err);
        if (st == SR_OK)
            snprintf(what, sizeof what, "part %s", p.number);
    } else {
        st = sr_catalog_instance_mesh(cat, inst_id, &mesh, &err);
        snprintf(what, sizeof what, "instance %lld", (long long)inst_id);
    }
    if (st == SR_OK)
        st = sr_mesh_write(out, &mesh, NULL, &err);
    sr_catalog_close(cat);
    if (st != SR_OK) {
        sr_mesh_release(&mesh);
        return cli_fail(st, &err);
    }
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "path");
        json_string(&j, out);
        json_key(&j, "format");
        json_string(&j, sr_format_name(fmt));
        json_key(&j, "vertices");
        json_int(&j, (int64_t)mesh.vertex_count);
        json_key(&j, "triangles");
        json_int(&j, (int64_t)mesh.tri_count);
        json_object_end(&j);
        rc = json_finish(&j);
    } else {
        printf("wrote %s to '%s' (%s, %zu vertices, %zu triangles)\n", cli_tx(what), out,
               sr_format_name(fmt), mesh.vertex_count, mesh.tri_count);
        rc = CLI_OK;
    }
    sr_mesh_release(&mesh);
    return rc;
}
