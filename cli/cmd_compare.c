/*
 * cmd_compare.c: `symrec compare A B`: how far two meshes are apart, so a user can check
 * a restoration against a reference part: both volumes and their difference, the
 * surface deviation both ways (max, mean, RMS) and the Hausdorff distance. A and B are
 * mesh files or stored meshes (instance:N, part:P, run:N). The figures come from
 * src/mesh/compare.h; this file loads the inputs and prints.
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_runs.h"
#include "align/register.h"
#include "cli.h"
#include "progress.h"
#include "mesh/compare.h"
#include "json_out.h"

static const char usage[] =
    "usage: symrec [--db FILE] compare A B [--units U] [--samples N] [--align | --no-align]\n"
    "                                [--json]\n"
    "\n"
    "Compares mesh B with mesh A (the reference): the volume of each (mm³, meaningful\n"
    "for closed meshes), the volume difference B - A (mm³ and % of A), the surface\n"
    "deviation of B from A and of A from B (max, mean and RMS distance in mm from\n"
    "sample points of one surface to the nearest point of the other) and the\n"
    "Hausdorff distance (the larger maximum).\n"
    "\n"
    "  A, B          a mesh file (.stl .obj .ply .off .gltf .glb, read in --units into\n"
    "                mm; at most 2 GiB, |coordinate| <= 1e6 mm, largest extent >= 1e-3\n"
    "                mm), or a mesh\n"
    "                stored in the catalogue:\n"
    "                  instance:N  the scan of damaged instance N\n"
    "                  part:P      the intact mesh of part P (number or id)\n"
    "                  run:N       the restored mesh of reconstruction run N\n"
    "                (write ./instance:3 for a file of that name)\n"
    "  --units U     the unit the file operands are drawn in: mm, cm, m or in\n"
    "                (default: each file's format's own: mm for .stl .obj .ply .off, m\n"
    "                for .gltf .glb); stored meshes are in mm already\n"
    "  --samples N   at least N sample points per surface, spread by area (default:\n"
    "                the vertices and triangle centroids). Deviations are measured at\n"
    "                the samples, so the maxima are lower bounds; more samples tighten\n"
    "                them (up to 20000000; the distance queries run on every core:\n"
    "                about 1.2 s per million samples on 2 cores)\n"
    "  --align       register B to A first (a rigid transform; robust, so a damaged\n"
    "                scan or extra stock does not pull it), whatever their frames\n"
    "  --no-align    compare B as it is placed\n"
    "                Default: B is registered to A when they are not in the same frame\n"
    "                (under half of B's surface within 0.5 % of A's size of A), as a run's\n"
    "                restored mesh (the scan's pose) and its catalogue part are not.\n"
    "                The output says which, the transform and how much of B lies on A.\n"
    "  --json        one JSON object: {\"a\", \"b\", \"registration\",\n"
    "                \"volume_diff_mm3\", \"volume_diff_pct\", \"a_to_b\", \"b_to_a\",\n"
    "                \"hausdorff_mm\"}\n";

/* Opens the catalogue on first use. */
static bool need_catalog(const cli_ctx *ctx, sr_catalog **cat)
{
    return *cat || cli_open(ctx, CLI_READ, NULL, cat);
}

/* Loads `ref` into *out and describes it in `what`. Returns an exit code; on failure
 * the error or usage line is printed. */
static int load(const cli_ctx *ctx, sr_catalog **cat, const char *ref, sr_unit unit, sr_mesh *out,
                char *what, size_t what_size)
{
    sr_err err;
    sr_err_clear(&err);
    sr_status st;
    int64_t id;
    if (strncmp(ref, "instance:", 9) == 0) {
        if (!cli_parse_id("instance:N", ref + 9, &id))
            return CLI_USAGE;
        if (!need_catalog(ctx, cat))
            return CLI_FAIL;
        st = sr_catalog_instance_mesh(*cat, id, out, &err);
        snprintf(what, what_size, "instance %lld", (long long)id);
    } else if (strncmp(ref, "part:", 5) == 0) {
        if (!ref[5])
            return cli_usage_error("bad 'part:': expected part:P with a part number or id");
        if (!need_catalog(ctx, cat))
            return CLI_FAIL;
        sr_part_info p;
        st = sr_catalog_part_find(*cat, ref + 5, &p, &err);
        if (st == SR_OK)
            st = sr_catalog_part_mesh(*cat, p.id, out, &err);
        snprintf(what, what_size, "part %s", ref + 5);
    } else if (strncmp(ref, "run:", 4) == 0) {
        if (!cli_parse_id("run:N", ref + 4, &id))
            return CLI_USAGE;
        if (!need_catalog(ctx, cat))
            return CLI_FAIL;
        st = sr_catalog_run_restored_mesh(*cat, id, out, &err);
        snprintf(what, what_size, "run %lld", (long long)id);
    } else {
        st = cli_mesh_read(ref, unit, out, NULL, &err);
        snprintf(what, what_size, "%s", ref);
    }
    if (st != SR_OK)
        return cli_fail(st, &err);
    return CLI_OK;
}

static void json_side(json_out *j, const char *what, const sr_mesh *m, double volume,
                      double area, int closed)
{
    json_object_begin(j);
    json_key(j, "source");
    json_string(j, what);
    json_key(j, "vertices");
    json_int(j, (int64_t)m->vertex_count);
    json_key(j, "triangles");
    json_int(j, (int64_t)m->tri_count);
    json_key(j, "closed");
    json_bool(j, closed);
    json_key(j, "volume_mm3");
    json_number(j, volume);
    json_key(j, "area_mm2");
    json_number(j, area);
    json_object_end(j);
}

static void json_dev(json_out *j, const sr_deviation *d)
{
    json_object_begin(j);
    json_key(j, "max_mm");
    json_number(j, d->max_mm);
    json_key(j, "mean_mm");
    json_number(j, d->mean_mm);
    json_key(j, "rms_mm");
    json_number(j, d->rms_mm);
    json_key(j, "samples");
    json_int(j, (int64_t)d->samples);
    json_object_end(j);
}

static void print_side(const char *label, const char *what, const sr_mesh *m, double volume,
                       double area, int closed)
{
    printf("%s %s: %zu vertices, %zu triangles, %s\n", label, cli_tx(what), m->vertex_count,
           m->tri_count, closed ? "closed" : "not closed (volume not meaningful)");
    printf("   volume %.3f mm³, area %.3f mm²\n", volume, area);
}

/* Whether and how B was registered to A. */
typedef struct registration {
    bool applied;
    const char *why;             /* "asked", "not in the same frame", "same frame", "off" */
    sr_register_result in_place; /* how B lies on A as given */
    sr_register_result reg;      /* the registration (when applied) */
    double bbox_overlap;
} registration;

/* Registers b to a (moving b) as asked: align 1 = always, 0 = never, -1 = when b is not
 * in a's frame. Returns an exit code (errors printed). */
static int register_b(sr_mesh *b, const sr_mesh *a, int align, registration *g)
{
    memset(g, 0, sizeof *g);
    g->bbox_overlap = sr_bbox_overlap(a, b);
    sr_err err;
    sr_err_clear(&err);
    sr_status st = SR_OK;
    if (align != 0)
        st = sr_register_check(b, a, NULL, &g->in_place, &err);
    if (st == SR_OK) {
        if (align == 0) {
            g->why = "off";
        } else if (align == 1) {
            g->why = "asked";
        } else {
            g->why = g->in_place.coverage >= 0.5 ? "same frame" : "not in the same frame";
        }
        g->applied = align == 1 || (align < 0 && g->in_place.coverage < 0.5);
    }
    if (st == SR_OK && g->applied)
        st = sr_register(b, a, NULL, &g->reg, &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (g->applied)
        sr_mesh_transform(b, g->reg.mat);
    return CLI_OK;
}

static void json_registration(json_out *j, const registration *g)
{
    json_object_begin(j);
    json_key(j, "applied");
    json_bool(j, g->applied);
    json_key(j, "why");
    json_string(j, g->why);
    json_key(j, "bbox_overlap");
    json_number(j, g->bbox_overlap);
    if (strcmp(g->why, "off") != 0) {
        json_key(j, "in_place_coverage");
        json_number(j, g->in_place.coverage);
    }
    if (g->applied) {
        json_key(j, "matrix");
        json_array_begin(j);
        for (int i = 0; i < 12; i++)
            json_number(j, g->reg.mat[i]);
        json_array_end(j);
        json_key(j, "rotation_deg");
        json_number(j, g->reg.rotation_deg);
        json_key(j, "translation_mm");
        json_number(j, g->reg.translation_mm);
        json_key(j, "coverage");
        json_number(j, g->reg.coverage);
        json_key(j, "rms_mm");
        json_number(j, g->reg.rms_mm);
        json_key(j, "tol_mm");
        json_number(j, g->reg.tol_mm);
    }
    json_object_end(j);
}

static void print_registration(const registration *g)
{
    if (g->bbox_overlap < 0.5)
        printf("note: the bounding boxes of A and B overlap by %.0f %% (of the smaller): "
               "not in the same frame\n",
               100 * g->bbox_overlap);
    if (g->applied) {
        printf("B registered to A (%s): rotated %.2f deg, moved %.3f mm; %.1f %% of B "
               "within %.3f mm of A (RMS %.4f mm)\n",
               g->why, g->reg.rotation_deg, g->reg.translation_mm, 100 * g->reg.coverage,
               g->reg.tol_mm, g->reg.rms_mm);
        if (g->reg.coverage < 0.5)
            printf("warning: only %.0f %% of B lies on A after registration: are they the "
                   "same part?\n",
                   100 * g->reg.coverage);
    } else if (strcmp(g->why, "same frame") == 0) {
        printf("B is in A's frame (%.1f %% of B within %.3f mm of A): not registered "
               "(--align to register it)\n",
               100 * g->in_place.coverage, g->in_place.tol_mm);
    }
}

int cmd_compare(const cli_ctx *ctx, int argc, char **argv)
{
    const char *samples_text = NULL, *units = NULL;
    bool json = false, align = false, no_align = false;
    const cli_opt opts[] = {
        {"--samples", &samples_text, NULL}, {"--units", &units, NULL}, {"--align", NULL, &align},
        {"--no-align", NULL, &no_align},    {"--json", NULL, &json},   {NULL, NULL, NULL}};
    const cli_spec spec = {"compare", usage, opts, 2, 2, "mesh (file or instance:N, part:P, run:N)"};
    const char *pos[2];
    int npos = 0, rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, &npos, &rc))
        return rc;
    if (align && no_align)
        return cli_usage_error("'compare' takes --align or --no-align, not both");
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;
    sr_compare_opts co = {0};
    if (samples_text) {
        int n;
        if (!cli_parse_int("--samples", samples_text, 1, (long)SR_COMPARE_MAX_SAMPLES,
                           "an integer 1..20000000", &n))
            return CLI_USAGE;
        co.samples = (size_t)n;
    }
    sr_catalog *cat = NULL;
    sr_mesh a, b;
    sr_mesh_init(&a);
    sr_mesh_init(&b);
    char what_a[4200], what_b[4200];
    rc = load(ctx, &cat, pos[0], unit, &a, what_a, sizeof what_a);
    if (rc == CLI_OK)
        rc = load(ctx, &cat, pos[1], unit, &b, what_b, sizeof what_b);
    if (rc != CLI_OK)
        goto done;
    sr_catalog_close(cat);
    cat = NULL;
    registration g;
    cli_progress *prog = cli_progress_begin(ctx->quiet, "compare");
    cli_progress_phase(prog, "register", 0, 2);
    rc = register_b(&b, &a, align ? 1 : no_align ? 0 : -1, &g);
    if (rc != CLI_OK) {
        cli_progress_end(prog);
        goto done;
    }
    sr_err err;
    sr_err_clear(&err);
    sr_compare_result r;
    cli_progress_phase(prog, "deviations", 1, 2);
    sr_status st = sr_compare_meshes(&a, what_a, &b, what_b, &co, &r, &err);
    cli_progress_end(prog);
    if (st != SR_OK) {
        rc = cli_fail(st, &err);
        goto done;
    }
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "a");
        json_side(&j, what_a, &a, r.volume_a_mm3, r.area_a_mm2, r.closed_a);
        json_key(&j, "b");
        json_side(&j, what_b, &b, r.volume_b_mm3, r.area_b_mm2, r.closed_b);
        json_key(&j, "registration");
        json_registration(&j, &g);
        json_key(&j, "volume_diff_mm3");
        json_number(&j, r.volume_diff_mm3);
        json_key(&j, "volume_diff_pct");
        json_number(&j, r.volume_diff_pct);
        json_key(&j, "a_to_b");
        json_dev(&j, &r.a_to_b);
        json_key(&j, "b_to_a");
        json_dev(&j, &r.b_to_a);
        json_key(&j, "hausdorff_mm");
        json_number(&j, r.hausdorff_mm);
        json_object_end(&j);
        rc = json_finish(&j);
    } else {
        rc = CLI_OK;
        print_side("A", what_a, &a, r.volume_a_mm3, r.area_a_mm2, r.closed_a);
        print_side("B", what_b, &b, r.volume_b_mm3, r.area_b_mm2, r.closed_b);
        print_registration(&g);
        if (r.volume_diff_pct == r.volume_diff_pct)
            printf("volume difference B - A: %.3f mm³ (%+.4f %% of A)\n", r.volume_diff_mm3,
                   r.volume_diff_pct);
        else
            printf("volume difference B - A: %.3f mm³\n", r.volume_diff_mm3);
        printf("deviation A -> B: max %.4f mm, mean %.4f mm, rms %.4f mm (%zu samples)\n",
               r.a_to_b.max_mm, r.a_to_b.mean_mm, r.a_to_b.rms_mm, r.a_to_b.samples);
        printf("deviation B -> A: max %.4f mm, mean %.4f mm, rms %.4f mm (%zu samples)\n",
               r.b_to_a.max_mm, r.b_to_a.mean_mm, r.b_to_a.rms_mm, r.b_to_a.samples);
        printf("Hausdorff distance: %.4f mm (at the samples)\n", r.hausdorff_mm);
    }
done:
    sr_catalog_close(cat);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
    return rc;
}
