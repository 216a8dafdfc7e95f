/*
 * cmd_convert.c: `symrec convert IN OUT`: a mesh file rewritten in another format, by
 * the same checked readers and atomic writers as every other command (mesh_io.h).
 */
#include <stdio.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"

static const char usage[] =
    "usage: symrec convert IN OUT [--units U] [--out-units U] [--json]\n"
    "\n"
    "Reads mesh file IN and writes it to OUT, each format from its extension: .stl\n"
    "(binary), .obj, .ply (binary), .off, .gltf or .glb. IN is checked as every input\n"
    "is (one line naming the file when it is bad); OUT is replaced atomically. A glTF\n"
    "scene's meshes become one mesh. IN is read in --units and scaled to mm; OUT is\n"
    "written in --out-units (.stl .obj .ply .off) or, as glTF means, in metres with Y up\n"
    "(.gltf .glb: one root node scales symrec's mm, Z up, to that), so a viewer shows\n"
    "it at its true size.\n"
    "\n" CLI_UNITS_HELP
    "  --out-units U  the unit OUT's numbers are written in: mm (default), cm, m or in;\n"
    "                 .stl .obj .ply .off only (a glTF is in metres by definition)\n"
    "  --json         print {\"in\", \"out\", \"format\", \"units\", \"out_units\",\n"
    "                 \"vertices\", \"triangles\"} as JSON (units: what IN was read in)\n";

int cmd_convert(const cli_ctx *ctx, int argc, char **argv)
{
    (void)ctx;
    bool json = false;
    const char *units = NULL, *out_units = NULL;
    const cli_opt opts[] = {{"--json", NULL, &json},
                            {"--units", &units, NULL},
                            {"--out-units", &out_units, NULL},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"convert", usage, opts, 2, 2, "IN OUT"};
    const char *pos[2];
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, NULL, &rc))
        return rc;
    sr_unit unit, out_unit;
    if (!cli_parse_units("--units", units, &unit) ||
        !cli_parse_units("--out-units", out_units, &out_unit))
        return CLI_USAGE;
    sr_format out_fmt = sr_format_from_path(pos[1]);
    if (out_fmt == SR_FMT_UNKNOWN)
        return cli_usage_error("bad OUT '%s': expected a file ending in .stl, .obj, .ply, "
                               ".off, .gltf or .glb",
                               pos[1]);
    bool gltf = out_fmt == SR_FMT_GLTF || out_fmt == SR_FMT_GLB;
    if (gltf && out_unit != SR_UNIT_DEFAULT && out_unit != SR_UNIT_M)
        return cli_usage_error("--out-units applies to .stl .obj .ply .off: a glTF is in "
                               "metres, as '%s' will be",
                               pos[1]);
    if (out_unit == SR_UNIT_DEFAULT)
        out_unit = gltf ? SR_UNIT_M : SR_UNIT_MM;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    sr_status st = cli_mesh_read(pos[0], unit, &mesh, &unit, &err);
    if (st == SR_OK && !gltf && out_unit != SR_UNIT_MM) {
        double per_mm = 1.0 / sr_unit_mm(out_unit);
        for (size_t i = 0; i < 3 * mesh.vertex_count; i++)
            mesh.xyz[i] *= per_mm;
    }
    if (st == SR_OK)
        st = sr_mesh_write(pos[1], &mesh, NULL, &err);
    if (st != SR_OK) {
        sr_mesh_release(&mesh);
        return cli_fail(st, &err);
    }
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "in");
        json_string(&j, pos[0]);
        json_key(&j, "out");
        json_string(&j, pos[1]);
        json_key(&j, "format");
        json_string(&j, sr_format_name(out_fmt));
        json_key(&j, "units");
        json_string(&j, sr_unit_name(unit));
        json_key(&j, "out_units");
        json_string(&j, sr_unit_name(out_unit));
        json_key(&j, "vertices");
        json_int(&j, (int64_t)mesh.vertex_count);
        json_key(&j, "triangles");
        json_int(&j, (int64_t)mesh.tri_count);
        json_object_end(&j);
        rc = json_finish(&j);
    } else {
        printf("wrote '%s' (%s, %zu vertices, %zu triangles)\n", cli_tx(pos[1]),
               sr_format_name(out_fmt), mesh.vertex_count, mesh.tri_count);
        rc = CLI_OK;
    }
    sr_mesh_release(&mesh);
    return rc;
}
