/*
 * cmd_check.c: `symrec check FILE`: what a mesh file holds, before it goes into the
 * catalogue or a reconstruction (mesh_facts.h): size, volume, area, closed and oriented
 * or not, degenerate and duplicate triangles, pieces, and the unit its size suggests.
 * Exit 0 when the file reads; the verdict line says whether it is a closed solid.
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"
#include "mesh/mesh_facts.h"

static const char usage[] =
    "usage: symrec check FILE [--units U] [--json]\n"
    "\n"
    "Reads a mesh file (.stl .obj .ply .off .gltf .glb) and prints what it holds, in mm\n"
    "(the file read in --units, scaled to mm): vertices and triangles,\n"
    "the bounding box, volume and area, whether it is a closed solid (every edge shared\n"
    "by two triangles, consistently oriented, facing outward), degenerate and duplicate\n"
    "triangles, the connected pieces, and the unit its size suggests for a machined\n"
    "part (a guess on the numbers as written in the file: a part 2.5 long is more likely\n"
    "2.5 in than 2.5 mm); a size outside 5 mm .. 3 m is warned about on stderr.\n"
    "A mesh that is open or in several pieces is described as a scanner's output: its\n"
    "openings (boundary loops, longest first, edges and length), its components, the\n"
    "share of the surface that is open and its strays (pieces far smaller than the part\n"
    "and off its surface, which reconstruct drops).\n"
    "\n" CLI_UNITS_HELP
    "  --json         one JSON object with the same facts (lengths in mm, volume mm³, area\n"
    "                 mm²; \"units\": the unit read in)\n";

static void print_json(const char *path, sr_unit unit, const sr_mesh_facts *f,
                       const sr_scan_desc *scan)
{
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_key(&j, "path");
    json_string(&j, path);
    json_key(&j, "units");
    json_string(&j, sr_unit_name(unit));
    json_key(&j, "vertices");
    json_int(&j, (int64_t)f->vertices);
    json_key(&j, "triangles");
    json_int(&j, (int64_t)f->triangles);
    json_key(&j, "bbox_min");
    json_array_begin(&j);
    for (int k = 0; k < 3; k++)
        json_number(&j, f->bbox_min[k]);
    json_array_end(&j);
    json_key(&j, "bbox_max");
    json_array_begin(&j);
    for (int k = 0; k < 3; k++)
        json_number(&j, f->bbox_max[k]);
    json_array_end(&j);
    json_key(&j, "volume");
    json_number(&j, f->volume);
    json_key(&j, "area");
    json_number(&j, f->area);
    json_key(&j, "closed");
    json_bool(&j, f->closed);
    json_key(&j, "oriented");
    json_bool(&j, f->oriented);
    json_key(&j, "outward");
    json_bool(&j, f->outward);
    json_key(&j, "boundary_edges");
    json_int(&j, (int64_t)f->edges.boundary_edges);
    json_key(&j, "nonmanifold_edges");
    json_int(&j, (int64_t)f->edges.nonmanifold_edges);
    json_key(&j, "misoriented_edges");
    json_int(&j, (int64_t)f->edges.misoriented_edges);
    json_key(&j, "degenerate_triangles");
    json_int(&j, (int64_t)f->degenerate_triangles);
    json_key(&j, "duplicate_triangles");
    json_int(&j, (int64_t)f->duplicate_triangles);
    json_key(&j, "components");
    json_int(&j, (int64_t)f->components);
    json_key(&j, "largest_component_triangles");
    json_int(&j, (int64_t)f->largest_component);
    json_key(&j, "likely_unit");
    json_string(&j, f->likely_unit);
    json_key(&j, "scan"); /* read as a scan: openings, components, strays */
    json_scan(&j, scan);
    json_object_end(&j);
    json_finish(&j);
}

static void print_text(const char *path, sr_unit unit, const sr_mesh_facts *f,
                       const sr_scan_desc *scan)
{
    printf("%s\n", cli_tx(path));
    printf("  read in             %s (numbers below in mm)\n", sr_unit_name(unit));
    printf("  vertices            %zu\n", f->vertices);
    printf("  triangles           %zu\n", f->triangles);
    printf("  bounding box        %.4g .. %.4g x %.4g .. %.4g x %.4g .. %.4g\n", f->bbox_min[0],
           f->bbox_max[0], f->bbox_min[1], f->bbox_max[1], f->bbox_min[2], f->bbox_max[2]);
    printf("  size                %.4g x %.4g x %.4g\n", f->bbox_max[0] - f->bbox_min[0],
           f->bbox_max[1] - f->bbox_min[1], f->bbox_max[2] - f->bbox_min[2]);
    printf("  volume              %.6g%s\n", f->volume,
           f->closed ? "" : " (not closed: not meaningful)");
    printf("  area                %.6g\n", f->area);
    printf("  edges               %zu: %zu boundary, %zu non-manifold, %zu misoriented\n",
           f->edges.edge_count, f->edges.boundary_edges, f->edges.nonmanifold_edges,
           f->edges.misoriented_edges);
    printf("  degenerate          %zu triangles\n", f->degenerate_triangles);
    printf("  duplicate           %zu triangles\n", f->duplicate_triangles);
    printf("  pieces              %zu (largest %zu triangles)\n", f->components,
           f->largest_component);
    printf("  likely unit         %s (largest side %.4g as read)\n", f->likely_unit,
           f->largest_extent);
    if (!cli_scan_is_plain(scan))
        cli_scan_print(scan);
    if (f->outward)
        printf("a closed solid, facing outward\n");
    else if (f->oriented)
        printf("closed but facing inward (volume < 0): its triangles are turned\n");
    else if (f->closed)
        printf("closed but not consistently oriented\n");
    else
        printf("not a closed solid: %zu boundary and %zu non-manifold edges: read as a scan\n",
               f->edges.boundary_edges, f->edges.nonmanifold_edges);
}

int cmd_check(const cli_ctx *ctx, int argc, char **argv)
{
    (void)ctx;
    bool json = false;
    const char *units = NULL;
    const cli_opt opts[] = {{"--json", NULL, &json}, {"--units", &units, NULL}, {NULL, NULL, NULL}};
    const cli_spec spec = {"check", usage, opts, 1, 1, "FILE"};
    const char *path;
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, &path, NULL, &rc))
        return rc;
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    sr_mesh_facts f;
    sr_scan_desc scan;
    memset(&scan, 0, sizeof scan);
    sr_status st = cli_mesh_read(path, unit, &mesh, &unit, &err);
    if (st == SR_OK)
        st = sr_mesh_facts_get(&mesh, &f, &err);
    if (st == SR_OK)
        st = sr_scan_describe(&mesh, NULL, &scan, &err);
    sr_mesh_release(&mesh);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json)
        print_json(path, unit, &f, &scan);
    else
        print_text(path, unit, &f, &scan);
    sr_scan_desc_release(&scan);
    return CLI_OK;
}
