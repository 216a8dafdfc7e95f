/*
 * cmd_reconstruct.c: `symrec reconstruct`: restores a damaged instance from the
 * catalogue (or a mesh file) by its symmetry and writes the restored part, the patches
 * and a GLB scene that overlay the input scan.
 *
 * Pipeline: src/reconstruct.h (align, slice, analyse, patches, union). This file only
 * parses arguments, loads the input and the parameter set, calls it, writes the
 * results, describes the run and records it in the catalogue (src/run/run_build.h, then
 * src/catalog/catalog_record.h: features, advice and, for an INSTANCE input, the record
 * in one transaction) and prints, the run's features and advice included.
 *
 * Order after a successful reconstruction: output files, then the run record, then
 * stdout; a failure at any step prints one error line, exits 1 and records nothing (a
 * failed reconstruction is not recorded either: the catalogue only holds runs that
 * finished, each complete).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "progress.h"
#include "json_out.h"
#include "outset.h"
#include "reconstruct.h"
#include "catalog/catalog_record.h"
#include "run/params_default.h"
#include "run/run_build.h"

static const char usage[] =
    "usage: symrec [--db FILE] reconstruct (INSTANCE | --mesh FILE [--units U])\n"
    "              --symmetry axial|mirror|glide|auto [--order N|auto] [--shift MM]\n"
    "              [--params NAME] [--layers N] [--sectors N] [--gamma G]\n"
    "              [--gamma-axis G] [--gamma-plane G]\n"
    "              [--min-depth MM] [--out DIR] [--format stl|obj|ply|off]\n"
    "              [--method image|robust|paper] [--no-union] [--no-record] [--json]\n"
    "              [--reference symmetry|nominal] [--no-nominal]\n"
    "\n"
    "Aligns the damaged scan with its symmetry axis or plane, slices it into layers,\n"
    "finds what is missing layer by layer, builds a closed patch mesh for every missing\n"
    "section and the restored part (scan united with the patches).\n"
    "\n"
    "Method 'image' (default) votes in 3D: the scan's symmetry images (mirror/glide\n"
    "images, the rotations of an n-fold part, turns of a continuous axis) on a voxel\n"
    "grid at the scan's resolution say where material is missing, and each section's\n"
    "patch is an image of the scan itself, clipped and united with it by one exact\n"
    "boolean, so the patch is exactly what was missing (keys, bores, bolt holes, slots\n"
    "and teeth are kept). Method 'robust' works on each layer's real cross-section\n"
    "(closed contours with holes) restored by the same vote per layer. Method 'paper'\n"
    "is the paper's Algorithms 1-6 on the farthest point per sector (the baseline).\n"
    "\n"
    "  INSTANCE        a damaged instance id from the catalogue (its symmetry is the\n"
    "                  default for --symmetry)\n"
    "  --mesh FILE     reconstruct a mesh file instead (STL, OBJ, PLY, OFF, glTF, GLB;\n"
    "                  at most 2 GiB, |coordinate| <= 1e6 mm, extent >= 1e-3 mm)\n"
    "  --units U       --mesh only: the unit FILE is drawn in: mm, cm, m or in\n"
    "                  (default: mm for .stl .obj .ply .off, m for .gltf .glb); the\n"
    "                  run and its outputs are in mm\n"
    "  --symmetry K    axial, mirror or glide; 'auto' fits every kind first and uses\n"
    "                  the one proposed, as 'symrec symmetry' prints it (the order\n"
    "                  of an axial part, the shift of a glide found; \"ambiguous\"\n"
    "                  uses the first of the two); the run records the proposal\n"
    "                  (JSON: \"symmetry_fit\"). A kind given is used as given\n"
    "  --order N       axial: n-fold order (2..360); default continuous. 'auto'\n"
    "                  finds it from the aligned layers (a gear's tooth count; 0 for\n"
    "                  a round part) and records the order found\n"
    "  --shift MM      glide: the shift along the plane in mm; default: searched\n"
    "  --params NAME   the named parameter set to run with (see 'symrec params list');\n"
    "                  default 'default' (320 layers, 240 sectors, gamma 0.95, min\n"
    "                  depth 0.1 mm as seeded). With --mesh and no --params the\n"
    "                  seeded 'default' values are used without opening a catalogue\n"
    "  --layers N      number of layers (overrides the set's)\n"
    "  --sectors N     number of sectors (overrides the set's)\n"
    "  --gamma G       the analysis threshold, gamma_axis and gamma_plane, in (0, 1]\n"
    "                  (overrides the set's)\n"
    "  --gamma-axis G, --gamma-plane G  one of the two alone, as 'params set' names them\n"
    "  --min-depth MM  smallest depth counted as damage, mm (overrides the set's)\n"
    "  --out DIR       write restored.<fmt>, patches.<fmt> and result.glb into DIR,\n"
    "                  all in the frame of the input scan (restored and patches in\n"
    "                  mm; result.glb in metres, Y up, as glTF means), as a set: DIR is a new\n"
    "                  folder, an empty one or one symrec wrote, replaced at once\n"
    "                  (a folder holding other files is refused before the run)\n"
    "  --format F      format of restored/patches (default stl)\n"
    "  --method M      image (default), robust or paper\n"
    "  --no-union      restored = scan + patches as separate shells (no boolean)\n"
    "  --no-record     do not record the run in the catalogue\n"
    "  --json          print one JSON object: alignment, sections, timings, run_id,\n"
    "                  nominal\n"
    "  --reference R   symmetry (default): the restoration is the symmetry's, the\n"
    "                  part's intact mesh a second opinion; nominal: the intact mesh\n"
    "                  registered to the scan is the restoration (patches = registered\n"
    "                  intact - scan), the symmetry's sections still reported as the\n"
    "                  check; refused when the intact mesh does not fit the scan\n"
    "  --no-nominal    skip the second opinion\n"
    "\n"
    "The second opinion: when the instance's part has an intact mesh, it is registered\n"
    "to the scan (robust, trimmed: the damage does not pull it) and registered intact -\n"
    "scan (slivers thinner than 3 x the registration's RMS dropped) is the nominal's\n"
    "missing material, measured by cells of a grid (exact volume per cell; a fraction\n"
    "of a second) or, with --reference nominal, by one exact boolean whose pieces are\n"
    "the patches (refused when it cannot be built: a scan that crosses itself); the\n"
    "run records which (JSON \"method\": exact|cells, \"cell_mm\", \"exact_note\").\n"
    "It is given section by section beside the\n"
    "symmetry's: both volumes (mm³), their disagreement (mm³, %) and the surface\n"
    "deviation of the patch from the nominal's piece (mean and max, mm).\n"
    "Pieces only the nominal sees and sections only the symmetry sees are listed. A\n"
    "nominal that covers under 75 % of the scan, or leaves more scan material outside\n"
    "it than the scan's area x the registration tolerance, is flagged: \"the nominal\n"
    "model does not fit this scan\". A --mesh run has no part: \"no nominal\".\n"
    "\n"
    "A reconstruction of an INSTANCE is recorded in the catalogue as a run (one\n"
    "transaction: the symmetry and every parameter as used, the alignment, the layer\n"
    "outlines, the sections with their patch meshes, the restored mesh, the timings);\n"
    "it prints \"run N recorded\" (JSON: \"run_id\"). See 'symrec run list' and\n"
    "'symrec run show N'. A --mesh reconstruction is not recorded (a run belongs to\n"
    "an instance: add the scan with 'symrec instance add' first), nor is one that\n"
    "fails. Every run prints the features of each missing section and the repair\n"
    "advice (JSON: each section's \"class\" and \"features\", and \"advice\"), drawn\n"
    "from the catalogue's rules and the part's material; a --mesh run has no part, so\n"
    "no material, and takes the rules of the --db catalogue (read only) when the file\n"
    "exists, else the built-in seeded rules.\n"
    "Sections smaller than the parameter set's min_volume_mm3 are dropped (0 = the\n"
    "'default' set's 1 mm³).\n"
    "An open scan (a mesh with holes, the face it stood on not seen) is closed first:\n"
    "its openings are scan gaps, not damage. Where a gap's fill lies under the surface\n"
    "the scanner did not see (a hole on a curve or over an edge), what is found behind\n"
    "it (its patch lying for 20 % or more of its surface on the fill) is restored but\n"
    "reported as a gap sag (JSON \"gap_sags\"; the run's \"sags\" and \"sag_mm3\"),\n"
    "not a section: no advice.\n"
    "A fit score below 0.5 (the share of the surface the symmetry maps onto itself)\n"
    "is reported as a poor fit: the part may not have that symmetry.\n"
    "Lengths in mm, areas mm², volumes mm³, angles degrees.\n";

/* An axial run's alignment has no plane normal: the misfit's place is a radius. */
static int misfit_axial(const sr_recon_result *r)
{
    const double *n = r->alignment.plane_normal;
    return n[0] == 0 && n[1] == 0 && n[2] == 0;
}

/* Below this fit score the symmetry kind probably does not suit the part. */
#define POOR_FIT_SCORE 0.5

/* The input's own steps, before the method's phases: reading the mesh (file or
 * catalogue) and describing and closing it as a scan (cli_scan_input), seconds. */
typedef struct input_time {
    double read_s, scan_s;
} input_time;

static void print_human(const sr_recon_result *r, const sr_run *run, const char *source,
                        const sr_params *p, int64_t run_id, const char *why_no_nominal,
                        const sr_scan_desc *scan, input_time in)
{
    const sr_alignment *a = &r->alignment;
    printf("reconstruction of %s\n", cli_tx(source));
    cli_scan_summary(scan, run->scan);
    printf("  method:     %s", sr_recon_method_name(r->method));
    if (r->method == SR_METHOD_ROBUST)
        printf(" (noise %.3f mm estimated from the fit, slivers under %.3f mm filtered)",
               r->noise_mm, 2 * r->open_mm);
    if (r->method == SR_METHOD_IMAGE)
        printf(" (voxel pitch %.3f mm, %.1f M voxels; vote %.3f s, patches %.3f s)",
               r->image.pitch_mm, (double)r->image.voxels / 1e6, r->image.vote_s, r->image.patch_s);
    printf("\n");
    if (r->unfold_pairs)
        printf("  scan folds: %zu crossing triangle pairs, %zu sliver triangles collapsed, %zu"
               " vertices moved (at most %.3f mm), %zu pairs left to mend\n",
               r->unfold_pairs, r->unfold_sliver_tris, r->unfold_vertices, r->unfold_max_mm,
               r->unfold_left);
    if (r->repair_note[0])
        printf("  note:       %s\n", r->repair_note);
    printf("  parameters: set '%s', %d layers x %d sectors, gamma %g/%g, min depth %g mm\n",
           p->name, p->layers, p->sectors, p->gamma_axis, p->gamma_plane, p->min_depth_mm);
    printf("  alignment: axis point (%.3f, %.3f, %.3f) mm, direction (%.5f, %.5f, %.5f)\n",
           a->axis_point[0], a->axis_point[1], a->axis_point[2], a->axis_dir[0], a->axis_dir[1],
           a->axis_dir[2]);
    printf("             fit rms %.4f mm, score %.3f\n", a->fit_rms_mm, a->fit_score);
    cli_symfit_print_line("  symmetry:   proposed by auto: ", run->symmetry_fit_json);
    if (a->fit_score < POOR_FIT_SCORE)
        printf("  poor fit: score %.3f < %.1f: only %.0f%% of the surface fits this symmetry; "
               "the part may not have it\n",
               a->fit_score, POOR_FIT_SCORE, 100.0 * a->fit_score);
    if (r->order_auto && r->order_found.order > 0)
        printf("  order:      %d-fold, found (mismatch turned by %.2f deg: %.3f mm; by turns no "
               "order repeats: %.3f mm)\n",
               r->order, 360.0 / r->order, r->order_found.mismatch_mm, r->order_found.base_mm);
    else if (r->order_auto)
        printf("  order:      continuous, found (%s: mismatch %.3f mm at turns no order "
               "repeats)\n",
               r->order_found.round ? "round" : "no order 2..360 matches", r->order_found.base_mm);
    printf("  grid: %zu layers x %zu sectors, dz %.4f mm\n", r->grid.layers, r->grid.sectors,
           r->grid.dz);
    if (r->method == SR_METHOD_IMAGE && r->image.poor_fit) {
        printf("  poor fit:   %.1f%% of the scan is not in its images under this symmetry, "
               "the sections explain %.1f%%: the part does not fit it%s\n",
               100.0 * r->image.misfit,
               r->scan_volume_mm3 > 0 ? 100.0 * r->patch_volume_mm3 / r->scan_volume_mm3 : 0,
               r->order >= 2 && !r->order_auto ? " (try --order auto)"
               : r->order_auto && r->order >= 2
                   ? " (the order found is the outer profile's: a region inside may have "
                     "another)"
                   : "");
        if (r->image.misfit_located)
            printf("              mostly %s %.1f..%.1f mm, z %.1f..%.1f mm (aligned frame)\n",
                   misfit_axial(r) ? "at radius" : "from the plane", r->image.misfit_where[0],
                   r->image.misfit_where[1], r->image.misfit_where[2], r->image.misfit_where[3]);
    }
    if (r->method == SR_METHOD_IMAGE && r->image.continued)
        printf("  continued:  %zu section(s) broken through the plane, carried on along z "
               "from the layers below/above (no image holds them)\n",
               r->image.continued);
    if (r->method == SR_METHOD_IMAGE && r->image.features_kept)
        printf("  kept:       %zu recess(es) whose walls all run along the axis's frame "
               "(holes, slots, keyways of the design), not filled\n",
               r->image.features_kept);
    if (r->method == SR_METHOD_IMAGE && r->image.unbuilt)
        printf("  not built:  %zu section(s) found missing, about %.1f mm³ by voxels, gave no "
               "closed patch: not restored and not listed below (the scan may not be closed "
               "there)\n",
               r->image.unbuilt, r->image.unbuilt_mm3);
    if (r->section_count == 0) {
        printf("  nothing to repair: no missing section found\n");
    } else {
        printf("  %zu missing section(s):\n", r->section_count);
        for (size_t i = 0; i < r->section_count; i++) {
            const sr_section *s = &r->sections[i];
            printf("  %2zu. z %.2f..%.2f mm, angle %.1f..%.1f deg, depth max %.3f mean %.3f "
                   "mm, volume %.1f mm³\n",
                   i + 1, s->z_min, s->z_max, s->angle_min_deg, s->angle_max_deg, s->depth_max_mm,
                   s->depth_mean_mm, s->volume_mm3);
        }
    }
    printf("  scan volume %.1f mm³, restored %.1f mm³ (%s), patches %.1f mm³\n", r->scan_volume_mm3,
           r->restored_volume_mm3, r->restored_by_union ? "boolean union" : "separate shells",
           r->patch_volume_mm3);
    if (!r->restored_by_union && r->union_note[0])
        printf("  union:      %s\n", r->union_note);
    const char *phase[SR_RECON_PHASES];
    double sec[SR_RECON_PHASES];
    size_t np = sr_recon_timings_list(&r->timings, phase, sec);
    printf("  time %.3f s (", r->timings.total_s);
    for (size_t i = 0, shown = 0; i + 1 < np; i++)
        if (sec[i] >= 0.0005 || i < 2) /* align and slice always; the rest where they ran */
            printf("%s%s %.3f", shown++ ? ", " : "", phase[i], sec[i]);
    printf(")\n  input: read %.3f s, described and closed as a scan %.3f s (before the above)\n",
           in.read_s, in.scan_s);
    cli_nominal_print(run->nominal, why_no_nominal);
    cli_run_advice_print(run);
    if (run_id > 0)
        printf("run %lld recorded\n", (long long)run_id);
}

static int print_json(const sr_recon_result *r, const sr_run *run, const char *mesh_file,
                      int64_t instance_id, const char *source, const sr_symmetry *sym,
                      const sr_params *p, int64_t run_id, const sr_scan_desc *scan, input_time in)
{
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_key(&j, "source"); /* the file's path, or "instance N (part P, serial S)" */
    json_string(&j, mesh_file ? mesh_file : source);
    json_key(&j, "mesh_file");
    json_string(&j, mesh_file);
    json_key(&j, "instance_id");
    if (mesh_file)
        json_null(&j);
    else
        json_int(&j, instance_id);
    json_key(&j, "scan"); /* the input read as a scan: openings, components, strays dropped */
    json_scan(&j, scan);
    json_key(&j, "scan_gaps"); /* the openings closed, as recorded: not sections; null = none */
    json_run_scan(&j, run->scan);
    json_key(&j, "symmetry"); /* as used: an order found by --order auto */
    sr_symmetry used = *sym;
    if (used.kind == SR_SYM_AXIAL)
        used.order = r->order;
    json_symmetry(&j, &used);
    json_key(&j, "symmetry_fit"); /* --symmetry auto: the proposal; else null */
    cli_symfit_json(&j, run->symmetry_fit_json);
    json_key(&j, "order_detection");
    if (r->order_auto) {
        json_object_begin(&j);
        json_key(&j, "order");
        json_int(&j, r->order_found.order);
        json_key(&j, "round");
        json_bool(&j, r->order_found.round);
        json_key(&j, "mismatch_mm");
        json_number(&j, r->order_found.mismatch_mm);
        json_key(&j, "base_mismatch_mm");
        json_number(&j, r->order_found.base_mm);
        json_key(&j, "layers_used");
        json_int(&j, (int64_t)r->order_found.layers_used);
        json_object_end(&j);
    } else {
        json_null(&j);
    }
    json_key(&j, "params");
    json_params(&j, p);
    json_key(&j, "method");
    json_string(&j, sr_recon_method_name(r->method));
    json_key(&j, "noise_mm");
    json_number(&j, r->noise_mm);
    json_key(&j, "image");
    if (r->method == SR_METHOD_IMAGE) {
        json_object_begin(&j);
        json_key(&j, "voxel_pitch_mm");
        json_number(&j, r->image.pitch_mm);
        json_key(&j, "voxels");
        json_int(&j, (int64_t)r->image.voxels);
        json_key(&j, "features_kept");
        json_int(&j, (int64_t)r->image.features_kept);
        json_key(&j, "unbuilt_sections"); /* found by the vote, no patch built: not listed */
        json_int(&j, (int64_t)r->image.unbuilt);
        json_key(&j, "unbuilt_mm3");
        json_number(&j, r->image.unbuilt_mm3);
        json_key(&j, "misfit");
        json_number(&j, r->image.misfit);
        json_key(&j, "poor_fit");
        json_bool(&j, r->image.poor_fit);
        if (r->image.misfit_located) {
            json_key(&j, "misfit_where");
            json_object_begin(&j);
            json_key(&j, misfit_axial(r) ? "radius_from_mm" : "from_plane_from_mm");
            json_number(&j, r->image.misfit_where[0]);
            json_key(&j, misfit_axial(r) ? "radius_to_mm" : "from_plane_to_mm");
            json_number(&j, r->image.misfit_where[1]);
            json_key(&j, "z_from_mm");
            json_number(&j, r->image.misfit_where[2]);
            json_key(&j, "z_to_mm");
            json_number(&j, r->image.misfit_where[3]);
            json_object_end(&j);
        }
        json_key(&j, "continued_across_plane");
        json_int(&j, (int64_t)r->image.continued);
        json_key(&j, "vote_s");
        json_number(&j, r->image.vote_s);
        json_key(&j, "patch_s");
        json_number(&j, r->image.patch_s);
        json_object_end(&j);
    } else {
        json_null(&j);
    }
    json_key(&j, "run_id");
    if (run_id > 0)
        json_int(&j, run_id);
    else
        json_null(&j);
    json_key(&j, "layers");
    json_int(&j, (int64_t)r->grid.layers);
    json_key(&j, "sectors");
    json_int(&j, (int64_t)r->grid.sectors);
    json_key(&j, "alignment");
    json_object_begin(&j);
    json_key(&j, "transform");
    json_array_begin(&j);
    for (int i = 0; i < 12; i++)
        json_number(&j, r->alignment.xform[i]);
    json_array_end(&j);
    json_key(&j, "axis_point_mm");
    json_array_begin(&j);
    for (int i = 0; i < 3; i++)
        json_number(&j, r->alignment.axis_point[i]);
    json_array_end(&j);
    json_key(&j, "axis_dir");
    json_array_begin(&j);
    for (int i = 0; i < 3; i++)
        json_number(&j, r->alignment.axis_dir[i]);
    json_array_end(&j);
    json_key(&j, "plane_normal");
    json_array_begin(&j);
    for (int i = 0; i < 3; i++)
        json_number(&j, r->alignment.plane_normal[i]);
    json_array_end(&j);
    json_key(&j, "glide_shift_mm");
    json_number(&j, r->alignment.glide_shift_mm);
    json_key(&j, "fit_rms_mm");
    json_number(&j, r->alignment.fit_rms_mm);
    json_key(&j, "fit_score");
    json_number(&j, r->alignment.fit_score);
    json_key(&j, "fit_poor");
    json_bool(&j, r->alignment.fit_score < POOR_FIT_SCORE);
    json_object_end(&j);
    json_key(&j, "gap_sags"); /* restored behind gap fills, not sections: no advice */
    json_array_begin(&j);
    for (size_t i = 0; i < r->gap_sag_count; i++) {
        const sr_gap_sag *g = &r->gap_sags[i];
        json_object_begin(&j);
        json_key(&j, "volume_mm3");
        json_number(&j, g->volume_mm3);
        json_key(&j, "depth_max_mm"); /* from the fill out to the restored surface */
        json_number(&j, g->depth_max_mm);
        json_key(&j, "fill_share"); /* of its surface lying on the fills */
        json_number(&j, g->fill_share);
        json_key(&j, "centre"); /* of its face on the fill, scan frame, mm */
        json_array_begin(&j);
        for (int k = 0; k < 3; k++)
            json_number(&j, g->centre[k]);
        json_array_end(&j);
        json_object_end(&j);
    }
    json_array_end(&j);
    json_key(&j, "sections");
    json_array_begin(&j);
    for (size_t i = 0; i < r->section_count; i++) {
        const sr_section *s = &r->sections[i];
        json_object_begin(&j);
        json_key(&j, "index");
        json_int(&j, (int64_t)i + 1);
        json_key(&j, "layer_first");
        json_int(&j, (int64_t)s->layer_first);
        json_key(&j, "layer_last");
        json_int(&j, (int64_t)s->layer_last);
        json_key(&j, "z_min_mm");
        json_number(&j, s->z_min);
        json_key(&j, "z_max_mm");
        json_number(&j, s->z_max);
        json_key(&j, "angle_min_deg");
        json_number(&j, s->angle_min_deg);
        json_key(&j, "angle_max_deg");
        json_number(&j, s->angle_max_deg);
        json_key(&j, "cells");
        json_int(&j, (int64_t)s->cell_count);
        json_key(&j, "depth_max_mm");
        json_number(&j, s->depth_max_mm);
        json_key(&j, "depth_mean_mm");
        json_number(&j, s->depth_mean_mm);
        json_key(&j, "volume_mm3");
        json_number(&j, s->volume_mm3);
        json_key(&j, "area_mm2");
        json_number(&j, s->area_mm2);
        json_key(&j, "patch_triangles");
        json_int(&j, (int64_t)s->patch.tri_count);
        json_key(&j, "class");
        json_string(&j, run->sections[i].damage_class);
        json_key(&j, "features");
        json_run_features(&j, &run->sections[i]);
        json_object_end(&j);
    }
    json_array_end(&j);
    json_key(&j, "advice");
    json_run_advice(&j, run);
    json_key(&j, "nominal");
    json_run_nominal(&j, run->nominal);
    json_key(&j, "scan_volume_mm3");
    json_number(&j, r->scan_volume_mm3);
    json_key(&j, "restored_volume_mm3");
    json_number(&j, r->restored_volume_mm3);
    json_key(&j, "patch_volume_mm3");
    json_number(&j, r->patch_volume_mm3);
    json_key(&j, "restored_by_union");
    json_bool(&j, r->restored_by_union);
    if (r->union_note[0]) {
        json_key(&j, "union_note");
        json_string(&j, r->union_note);
    }
    if (r->repair_note[0]) {
        json_key(&j, "repair_note");
        json_string(&j, r->repair_note);
    }
    if (r->method == SR_METHOD_IMAGE) {
        json_key(&j, "scan_folds");
        json_object_begin(&j);
        json_key(&j, "crossing_pairs");
        json_int(&j, (int64_t)r->unfold_pairs);
        json_key(&j, "sliver_triangles_collapsed");
        json_int(&j, (int64_t)r->unfold_sliver_tris);
        json_key(&j, "vertices_moved");
        json_int(&j, (int64_t)r->unfold_vertices);
        json_key(&j, "max_move_mm");
        json_number(&j, r->unfold_max_mm);
        json_key(&j, "pairs_left");
        json_int(&j, (int64_t)r->unfold_left);
        json_object_end(&j);
    }
    json_key(&j, "timings");
    json_object_begin(&j);
    const char *phase[SR_RECON_PHASES];
    double sec[SR_RECON_PHASES];
    size_t np = sr_recon_timings_list(&r->timings, phase, sec);
    for (size_t i = 0; i < np; i++) {
        char key[32];
        snprintf(key, sizeof key, "%s_s", phase[i]);
        json_key(&j, key);
        json_number(&j, sec[i]);
    }
    json_key(&j, "read_s"); /* the input's steps, before the method: not in total_s */
    json_number(&j, in.read_s);
    json_key(&j, "scan_s");
    json_number(&j, in.scan_s);
    json_object_end(&j);
    json_object_end(&j);
    return json_finish(&j);
}

/* The files reconstruct writes (outset.h: what may be replaced in an existing DIR). */
static const char *const out_names[] = {"restored.*", "patches.*", "result.glb", NULL};

/* Writes restored, patches (when there are sections) and result.glb into dir (the
 * staging folder of the --out set). */
static int write_outputs(const char *dir, const char *fmt, const sr_mesh *scan,
                         const sr_recon_result *r, const sr_mesh *nominal_patches)
{
    char path[4096];
    sr_err err;
    sr_err_clear(&err);
    snprintf(path, sizeof path, "%s/restored.%s", dir, fmt);
    sr_status st = sr_mesh_write(path, &r->restored, NULL, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    sr_mesh all;
    sr_mesh_init(&all);
    for (size_t i = 0; i < r->section_count && st == SR_OK && !nominal_patches->tri_count; i++)
        st = sr_mesh_append(&all, &r->sections[i].patch);
    if (st == SR_OK && nominal_patches->tri_count)
        st = sr_mesh_append(&all, nominal_patches);
    snprintf(path, sizeof path, "%s/patches.%s", dir, fmt);
    if (st == SR_OK && all.tri_count > 0)
        st = sr_mesh_write(path, &all, NULL, &err);
    sr_mesh_release(&all);
    if (st != SR_OK)
        return cli_fail(st, &err);

    size_t n = r->section_count + 1;
    sr_scene_mesh items[256];
    char names[256][32];
    if (n > 256)
        n = 256;
    items[0] = (sr_scene_mesh){"damaged", scan, {0.62f, 0.64f, 0.68f, 1.0f}};
    for (size_t i = 1; i < n; i++) {
        snprintf(names[i], sizeof names[i], "patch %zu", i);
        items[i] = (sr_scene_mesh){names[i], &r->sections[i - 1].patch, {0.1f, 0.75f, 0.95f, 1.0f}};
    }
    snprintf(path, sizeof path, "%s/result.glb", dir);
    st =
        sr_scene_write(path, items, n,
                       "{\"units\":\"m\",\"up\":\"Y\",\"generator\":\"symrec reconstruct\"}", &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    return CLI_OK;
}

/* The catalogue a run that is not recorded takes its rules and material from: *cat
 * when one is open already, else ctx's file read-only when it exists, else a catalogue
 * in memory with the seeded rules (a file that cannot be opened is noted and left). */
static sr_status advice_catalog(const cli_ctx *ctx, sr_catalog **cat, sr_err *err)
{
    if (*cat)
        return SR_OK;
    struct stat sb;
    if (stat(ctx->db_path, &sb) == 0) {
        sr_status st = sr_catalog_open(ctx->db_path, SR_CATALOG_READONLY, cat, err);
        if (st == SR_OK)
            return SR_OK;
        cli_note("advice from the built-in rules: %s", err->msg[0] ? err->msg : sr_status_str(st));
        sr_err_clear(err);
    }
    return sr_catalog_open_memory(cat, err);
}

/* The run record of `r` (features and advice worked out by catalog_record.h from the
 * catalogue's rules and, for an instance, its part's material and intact volume),
 * recorded in one transaction when `record`. *run and *run_id only on success. */
static sr_status describe_run(const cli_ctx *ctx, sr_catalog **cat, const sr_recon_result *r,
                              int64_t instance_id, const sr_symmetry *sym, const sr_params *p,
                              const char *started, char *fit_json, bool record,
                              sr_run_nominal *nominal, sr_run_scan *scan, sr_run *run,
                              int64_t *run_id, sr_err *err)
{
    sr_run made;
    sr_status st =
        sr_run_from_result(r, instance_id, sym, p, sr_recon_method_name(r->method), &made, err);
    if (st != SR_OK) {
        free(fit_json);
        sr_run_nominal_free(nominal);
        sr_run_scan_free(scan);
        return st;
    }
    made.symmetry_fit_json = fit_json; /* the run's now */
    made.nominal = nominal;
    made.scan = scan;
    if (strcmp(started, made.finished_at) <= 0)
        snprintf(made.started_at, sizeof made.started_at, "%s", started);
    int64_t id = 0;
    if (record)
        st = sr_catalog_run_record(*cat, &made, &id, err);
    else if ((st = advice_catalog(ctx, cat, err)) == SR_OK)
        st = sr_catalog_run_describe(*cat, &made, err);
    if (st != SR_OK) {
        sr_run_release(&made);
        return st;
    }
    *run = made;
    *run_id = id;
    return SR_OK;
}

int cmd_reconstruct(const cli_ctx *ctx, int argc, char **argv)
{
    const char *mesh_file = NULL, *kind = NULL, *order = NULL, *shift = NULL, *layers = NULL,
               *sectors = NULL, *gamma = NULL, *min_depth = NULL, *out = NULL, *fmt = "stl",
               *params_name = NULL, *method = NULL, *gamma_axis = NULL, *gamma_plane = NULL,
               *units = NULL;
    const char *reference = "symmetry";
    bool json = false, no_union = false, no_record = false, sym_auto = false, no_nominal = false;
    const cli_opt opts[] = {{"--mesh", &mesh_file, NULL},
                            {"--units", &units, NULL},
                            {"--symmetry", &kind, NULL},
                            {"--order", &order, NULL},
                            {"--shift", &shift, NULL},
                            {"--params", &params_name, NULL},
                            {"--layers", &layers, NULL},
                            {"--sectors", &sectors, NULL},
                            {"--gamma", &gamma, NULL},
                            {"--min-depth", &min_depth, NULL},
                            {"--gamma-axis", &gamma_axis, NULL},
                            {"--gamma-plane", &gamma_plane, NULL},
                            {"--out", &out, NULL},
                            {"--format", &fmt, NULL},
                            {"--method", &method, NULL},
                            {"--no-union", NULL, &no_union},
                            {"--no-record", NULL, &no_record},
                            {"--no-nominal", NULL, &no_nominal},
                            {"--reference", &reference, NULL},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"reconstruct", usage, opts, 0, 1, "INSTANCE"};
    const char *pos[1];
    int npos = 0, rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, &npos, &rc))
        return rc;
    if ((npos == 1) == (mesh_file != NULL))
        return cli_usage_error("'reconstruct' needs an INSTANCE id or --mesh FILE, not both "
                               "(see 'symrec reconstruct --help')");
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;
    if (units && !mesh_file)
        return cli_usage_error("--units applies to --mesh FILE only (a catalogue instance is "
                               "stored in mm)");
    /* Every option is checked before anything is opened. */
    int layers_v = 0, sectors_v = 0;
    double gamma_v = 0, gamma_axis_v = 0, gamma_plane_v = 0, min_depth_v = 0;
    if (layers && !cli_parse_int("--layers", layers, 1, 100000, "an integer 1..100000", &layers_v))
        return CLI_USAGE;
    if (sectors &&
        !cli_parse_int("--sectors", sectors, 3, 100000, "an integer 3..100000", &sectors_v))
        return CLI_USAGE;
    if (gamma && !cli_parse_double("--gamma", gamma, 1e-6, 1, "a number in (0, 1]", &gamma_v))
        return CLI_USAGE;
    if (gamma_axis &&
        !cli_parse_double("--gamma-axis", gamma_axis, 1e-6, 1, "a number in (0, 1]", &gamma_axis_v))
        return CLI_USAGE;
    if (gamma_plane && !cli_parse_double("--gamma-plane", gamma_plane, 1e-6, 1,
                                         "a number in (0, 1]", &gamma_plane_v))
        return CLI_USAGE;
    if (min_depth &&
        !cli_parse_double("--min-depth", min_depth, 0, 1000, "a depth 0..1000 mm", &min_depth_v))
        return CLI_USAGE;
    if (params_name && !*params_name)
        return cli_usage_error("bad --params '': expected the name of a parameter set");
    if (strcmp(fmt, "stl") && strcmp(fmt, "obj") && strcmp(fmt, "ply") && strcmp(fmt, "off"))
        return cli_usage_error("bad --format '%s': expected stl, obj, ply or off", fmt);
    if (strcmp(reference, "symmetry") && strcmp(reference, "nominal"))
        return cli_usage_error("bad --reference '%s': expected symmetry or nominal", reference);
    bool ref_nominal = strcmp(reference, "nominal") == 0;
    if (ref_nominal && (no_nominal || mesh_file))
        return cli_usage_error("--reference nominal needs an INSTANCE whose part has an intact "
                               "mesh, and no --no-nominal");
    sr_recon_opts ro;
    memset(&ro, 0, sizeof ro);
    ro.skip_union = no_union;
    if (method) {
        sr_err merr;
        sr_err_clear(&merr);
        if (sr_recon_method_parse(method, "--method", &ro.method, &merr) != SR_OK)
            return cli_usage_error("%s", merr.msg);
    }
    if (kind && strcmp(kind, "auto") == 0) {
        if (order || shift)
            return cli_usage_error("--order and --shift need --symmetry axial|glide, not auto");
        sym_auto = true;
    } else if (kind && !cli_parse_symmetry(kind, order, shift, 1, &ro.symmetry))
        return CLI_USAGE;
    if (!kind && (order || shift))
        return cli_usage_error("--order and --shift need --symmetry");
    if (mesh_file && !kind)
        return cli_usage_error("'reconstruct --mesh' needs --symmetry axial|mirror|glide|auto");
    int64_t id = 0;
    if (!mesh_file && !cli_parse_id("INSTANCE", pos[0], &id))
        return CLI_USAGE;

    sr_mesh scan;
    sr_mesh_init(&scan);
    sr_err err;
    sr_err_clear(&err);
    sr_status st = SR_OK;
    sr_catalog *cat = NULL;
    sr_params params; /* --mesh without --params: the core's copy of 'default' */
    sr_params_default(&params);
    char source[4200];
    sr_instance_info inst;
    memset(&inst, 0, sizeof inst);
    if (!mesh_file || params_name) {
        /* a run to record checks now, before the time is spent, that it can be */
        bool record = !mesh_file && !no_record;
        if (!cli_open(ctx, record ? CLI_WRITE : CLI_READ, "record the run", &cat))
            return CLI_FAIL;
        st = sr_catalog_params_get(cat, params_name ? params_name : "default", &params, &err);
    }
    input_time in = {0, 0};
    double t_in = cli_now_s();
    if (st == SR_OK && mesh_file) {
        st = cli_mesh_read(mesh_file, unit, &scan, NULL, &err);
        snprintf(source, sizeof source, "'%s'", mesh_file);
    } else if (st == SR_OK) {
        st = sr_catalog_instance_get(cat, id, &inst, &err);
        if (st == SR_OK)
            st = sr_catalog_instance_mesh(cat, id, &scan, &err);
        if (st == SR_OK && !kind && !sym_auto) {
            if (inst.symmetry.kind == SR_SYM_NONE) {
                sr_catalog_close(cat);
                sr_mesh_release(&scan);
                return cli_usage_error("instance %lld has no symmetry in the catalogue: give "
                                       "--symmetry axial|mirror|glide",
                                       (long long)id);
            }
            ro.symmetry = inst.symmetry;
        }
        if (st == SR_OK)
            snprintf(source, sizeof source, "instance %lld (part %s, serial %s)", (long long)id,
                     inst.part_number, inst.serial[0] ? inst.serial : "-");
    }
    sr_scan_desc scan_desc; /* the input read as a scan; its strays dropped from scan */
    memset(&scan_desc, 0, sizeof scan_desc);
    sr_run_scan *scan_rec = NULL; /* its gaps for the run record (the run's once described) */
    in.read_s = cli_now_s() - t_in;
    t_in = cli_now_s();
    if (st == SR_OK)
        st = cli_scan_input(&scan, &scan_desc, &scan_rec, &err);
    in.scan_s = cli_now_s() - t_in;
    if (st != SR_OK) {
        sr_catalog_close(cat);
        sr_mesh_release(&scan);
        return cli_fail(st, &err);
    }
    ro.gap_fills = &scan_desc.fills;
    if (layers)
        params.layers = layers_v;
    if (sectors)
        params.sectors = sectors_v;
    if (gamma)
        params.gamma_axis = params.gamma_plane = gamma_v;
    if (gamma_axis)
        params.gamma_axis = gamma_axis_v;
    if (gamma_plane)
        params.gamma_plane = gamma_plane_v;
    if (min_depth)
        params.min_depth_mm = min_depth_v;
    ro.layers = (size_t)params.layers;
    ro.sectors = (size_t)params.sectors;
    ro.gamma_axis = params.gamma_axis;
    ro.gamma_plane = params.gamma_plane;
    ro.delta_d = params.delta_d;
    ro.min_depth_mm = params.min_depth_mm;
    ro.min_volume_mm3 = params.min_volume_mm3;

    /* --out is checked (and its staging folder made) before the time is spent */
    cli_outset set = {0};
    if (out && !cli_outset_begin(&set, out, "reconstruct", out_names)) {
        sr_catalog_close(cat);
        sr_mesh_release(&scan);
        sr_scan_desc_release(&scan_desc);
        sr_run_scan_free(scan_rec);
        return CLI_FAIL;
    }
    char *fit_json = NULL;
    if (sym_auto && !cli_symfit_auto(&scan, source, &ro.symmetry, &fit_json)) {
        cli_outset_abort(&set);
        sr_catalog_close(cat);
        sr_mesh_release(&scan);
        sr_scan_desc_release(&scan_desc);
        sr_run_scan_free(scan_rec);
        return CLI_FAIL;
    }
    cli_note("reconstructing %s (%zu triangles)...", cli_tx(source), scan.tri_count);
    char started[32];
    sr_run_utc_time(0, started);
    sr_recon_result r;
    cli_progress *prog = cli_progress_begin(ctx->quiet, "reconstruct");
    ro.progress = cli_progress_sink(prog);
    /* handed over: a noisy scan is unfolded in place, not copied (a 1.09M-triangle
     * scan held once); scan is then the one the reconstruction used, which the GLB
     * shows and the nominal is registered to */
    st = sr_reconstruct_owned(&scan, &ro, &r, &err);
    cli_progress_end(prog);
    if (st == SR_OK && r.method == SR_METHOD_IMAGE && r.image.unbuilt) /* even with --json */
        cli_note("warning: %zu section(s) found missing (about %.1f mm³) gave no closed patch "
                 "and are not restored: the scan may not be closed there",
                 r.image.unbuilt, r.image.unbuilt_mm3);
    if (st != SR_OK) {
        free(fit_json);
        cli_outset_abort(&set);
        sr_catalog_close(cat);
        sr_mesh_release(&scan);
        sr_scan_desc_release(&scan_desc);
        sr_run_scan_free(scan_rec);
        return cli_fail(st, &err);
    }
    for (size_t i = 0; scan_rec && i < r.gap_sag_count; i++) {
        scan_rec->sags++;
        scan_rec->sag_mm3 += r.gap_sags[i].volume_mm3;
    }
    sr_run_nominal *nominal = NULL;
    sr_mesh nominal_patches;
    sr_mesh_init(&nominal_patches);
    char why_no_nominal[600];
    rc = cli_nominal_step(cat, mesh_file ? 0 : inst.part_id, &scan, &r, params.min_volume_mm3,
                          no_nominal, ref_nominal, &nominal, &nominal_patches, why_no_nominal,
                          sizeof why_no_nominal);
    if (rc != CLI_OK)
        cli_outset_abort(&set);
    if (rc == CLI_OK && out) {
        cli_heap_give_back(); /* the outputs' buffers in the phases' holes */
        rc = write_outputs(set.stage, fmt, &scan, &r, &nominal_patches);
        if (rc != CLI_OK)
            cli_outset_abort(&set);
        else if (!cli_outset_commit(&set))
            rc = CLI_FAIL;
    }
    int64_t run_id = 0;
    sr_run run;
    memset(&run, 0, sizeof run);
    if (rc == CLI_OK) {
        st = describe_run(ctx, &cat, &r, mesh_file ? 0 : id, &ro.symmetry, &params, started,
                          fit_json, !mesh_file && !no_record, nominal, scan_rec, &run, &run_id,
                          &err);
        fit_json = NULL; /* the run's, or freed with it */
        nominal = NULL;
        scan_rec = NULL;
        if (st != SR_OK)
            rc = cli_fail(st, &err);
    }
    if (rc == CLI_OK) {
        if (json)
            rc = print_json(&r, &run, mesh_file, id, source, &ro.symmetry, &params, run_id,
                            &scan_desc, in);
        else
            print_human(&r, &run, source, &params, run_id, why_no_nominal, &scan_desc, in);
    }
    free(fit_json);
    sr_run_nominal_free(nominal);
    sr_mesh_release(&nominal_patches);
    sr_run_release(&run);
    sr_recon_result_release(&r);
    sr_mesh_release(&scan);
    sr_scan_desc_release(&scan_desc);
    sr_run_scan_free(scan_rec);
    sr_catalog_close(cat);
    return rc;
}
