/*
 * cmd_export.c: `symrec export part|instance|run ID --out FILE`: writes a stored mesh (a
 * part's intact mesh, an instance's scan, a run's restored part or patches, or both as a
 * glTF scene) to a file whose extension picks the format:
 * stl (binary), obj, ply (binary), off, gltf or glb. The write is atomic (mesh_io).
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_runs.h"
#include "cli.h"
#include "json_out.h"

static const char usage[] =
    "usage: symrec [--db FILE] export part P --out FILE [--json]\n"
    "       symrec [--db FILE] export instance ID --out FILE [--json]\n"
    "       symrec [--db FILE] export run N --out FILE [--what restored|patches|both]\n"
    "                             [--section K] [--json]\n"
    "\n"
    "Writes a stored mesh: a part's intact mesh (P = part number or id), a damaged\n"
    "instance's scan, or what reconstruction run N made: its restored part, its\n"
    "patches (the missing sections, exactly the missing volume) or both. The format\n"
    "comes from FILE's extension: .stl (binary), .obj, .ply (binary), .off, .gltf or\n"
    ".glb. Coordinates are in mm, in the frame of the stored mesh (a run's meshes: the\n"
    "scan's frame, so they overlay it); a .gltf or .glb means metres with Y up, as glTF\n"
    "does: one root node scales and turns the mm, Z up, meshes to that, and symrec\n"
    "reads it back in mm, Z up.\n"
    "\n"
    "  --out FILE      where to write (replaced atomically if it exists)\n"
    "  --what W        run only: restored (default), patches (every section's patch\n"
    "                  as one mesh of separate shells; in glTF one node per section),\n"
    "                  or both (glTF/GLB only: the restored part and each patch as\n"
    "                  named nodes of one scene)\n"
    "  --section K     run only: the patch of section K alone (implies patches)\n"
    "  --json          print {\"path\", \"format\", \"vertices\", \"triangles\"} as JSON\n";

/* Colours of the exported scene: the restored part grey, the patches orange. */
static const float grey[4] = {0.7f, 0.7f, 0.72f, 1.0f}, orange[4] = {1.0f, 0.45f, 0.1f, 1.0f};

/* Run N's meshes as asked, into `out` (a file of one mesh) or, for glTF/GLB, a scene
 * with a node per mesh. *mesh gets what a one-mesh file holds (the counts printed). */
static sr_status export_run(sr_catalog *cat, int64_t id, const char *what, int section,
                            const char *out, sr_format fmt, sr_mesh *mesh, sr_err *err)
{
    sr_run run;
    memset(&run, 0, sizeof run);
    sr_status st = sr_catalog_run_get(cat, id, SR_RUN_WITH_MESHES, &run, err);
    if (st != SR_OK)
        return st;
    bool want_restored = strcmp(what, "restored") == 0 || strcmp(what, "both") == 0;
    bool want_patches = strcmp(what, "patches") == 0 || strcmp(what, "both") == 0;
    if (want_restored && run.restored.tri_count == 0)
        st = sr_err_set(err, SR_E_NOTFOUND,
                        "run %lld has no restored mesh (it failed, or "
                        "was recorded without one)",
                        (long long)id);
    if (st == SR_OK && section > 0 && (size_t)section > run.section_count)
        st = sr_err_set(err, SR_E_NOTFOUND, "run %lld has no section %d (it has %zu)",
                        (long long)id, section, run.section_count);
    if (st == SR_OK && want_patches && !want_restored && run.section_count == 0)
        st = sr_err_set(err, SR_E_NOTFOUND,
                        "run %lld has no missing section: no patch to "
                        "export",
                        (long long)id);
    size_t first = section > 0 ? (size_t)section - 1 : 0;
    size_t last = section > 0 ? (size_t)section : run.section_count;
    /* the scene: a node per mesh */
    size_t n = 0;
    sr_scene_mesh nodes[1 + 256];
    char names[1 + 256][32];
    if (st == SR_OK && want_restored) {
        snprintf(names[n], sizeof names[n], "restored");
        nodes[n] = (sr_scene_mesh){names[n], &run.restored, {grey[0], grey[1], grey[2], grey[3]}};
        st = sr_mesh_append(mesh, &run.restored);
        n++;
    }
    for (size_t i = first; st == SR_OK && want_patches && i < last; i++) {
        if (run.sections[i].patch.tri_count == 0)
            continue;
        if (n < sizeof nodes / sizeof nodes[0]) {
            snprintf(names[n], sizeof names[n], "section %zu", run.sections[i].index + 1);
            nodes[n] = (sr_scene_mesh){
                names[n], &run.sections[i].patch, {orange[0], orange[1], orange[2], orange[3]}};
            n++;
        }
        if (!want_restored)
            st = sr_mesh_append(mesh, &run.sections[i].patch);
    }
    if (st == SR_OK && mesh->tri_count == 0)
        st = sr_err_set(err, SR_E_NOTFOUND, "run %lld has no patch mesh stored for %s",
                        (long long)id, section > 0 ? "that section" : "its sections");
    if (st == SR_OK) {
        if (fmt == SR_FMT_GLTF || fmt == SR_FMT_GLB)
            st = sr_scene_write(out, nodes, n, "{\"units\":\"m\",\"up\":\"Y\"}", err);
        else
            st = sr_mesh_write(out, mesh, NULL, err);
    }
    sr_run_release(&run);
    return st;
}

int cmd_export(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = NULL, *what_opt = NULL, *section_opt = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--out", &out, NULL},
                            {"--what", &what_opt, NULL},
                            {"--section", &section_opt, NULL},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"export", usage, opts, 2, 2, "'part P', 'instance ID' or 'run N'"};
    const char *pos[2];
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, NULL, &rc))
        return rc;
    bool is_part = strcmp(pos[0], "part") == 0, is_run = strcmp(pos[0], "run") == 0;
    if (!is_part && !is_run && strcmp(pos[0], "instance") != 0)
        return cli_usage_error("bad 'export %s': expected 'export part P', "
                               "'export instance ID' or 'export run N'",
                               pos[0]);
    int64_t inst_id = 0;
    if (!is_part && !cli_parse_id(is_run ? "N" : "ID", pos[1], &inst_id))
        return CLI_USAGE;
    if (!out)
        return cli_usage_error("'export' needs --out FILE (see 'symrec export --help')");
    sr_format fmt = sr_format_from_path(out);
    if (fmt == SR_FMT_UNKNOWN)
        return cli_usage_error("bad --out '%s': expected a file ending in .stl, .obj, .ply, "
                               ".off, .gltf or .glb", out);
    if ((what_opt || section_opt) && !is_run)
        return cli_usage_error("--what and --section are for 'export run N'");
    int section = 0;
    if (section_opt &&
        !cli_parse_int("--section", section_opt, 1, 1000000, "a section number >= 1", &section))
        return CLI_USAGE;
    const char *what_run = what_opt ? what_opt : section ? "patches" : "restored";
    if (strcmp(what_run, "restored") != 0 && strcmp(what_run, "patches") != 0 &&
        strcmp(what_run, "both") != 0)
        return cli_usage_error("bad --what '%s': expected restored, patches or both", what_run);
    if (section && strcmp(what_run, "restored") == 0)
        return cli_usage_error("--section K exports a patch: not with --what restored");
    if (strcmp(what_run, "both") == 0 && fmt != SR_FMT_GLTF && fmt != SR_FMT_GLB)
        return cli_usage_error("--what both needs a .gltf or .glb file (one node per mesh); "
                               "a one-mesh format would merge the overlapping shells");

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    sr_status st;
    char what[96];
    if (is_run) {
        st = export_run(cat, inst_id, what_run, section, out, fmt, &mesh, &err);
        snprintf(what, sizeof what, "run %lld %s", (long long)inst_id,
                 section ? "patch" : what_run);
    } else if (is_part) {
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
    if (st == SR_OK && !is_run)
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
