/*
 * cmd_inspect.c: `symrec inspect RUN --mesh SCAN`: the part after repair measured
 * against run RUN's restoration (src/inspect/inspect.h), recorded in the catalogue
 * (catalog_inspect.h), and printed: per section the under-fill, the stock to machine
 * and the deviation, outside the sections whether the part is unchanged, and the
 * verdicts. The allowance defaults to the one the run's advice planned with.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_inspect.h"
#include "catalog/catalog_runs.h"
#include "cli.h"
#include "inspect/inspect.h"
#include "json_out.h"
#include "plan/plan.h"

static const char usage[] =
    "usage: symrec [--db FILE] inspect RUN --mesh SCAN [--allowance MM] [--tolerance MM]\n"
    "                                [--units U] [--align | --no-align] [--glb FILE]\n"
    "                                [--json]\n"
    "\n"
    "Inspects a part after repair against the restoration of run RUN: the scan SCAN is\n"
    "taken onto the run's restored mesh (as it lies when it is in the run's frame, else\n"
    "registered with the repaired regions left out of the fit) and compared with it.\n"
    "Per section of the run: the under-fill (restored material the repair did not\n"
    "reach, mm³) and its largest depth, the over-build (material above the restored\n"
    "surface, mm³) with the stock's thickness (min, max, mean over the stock), and the\n"
    "signed deviation (mean, RMS, min, max; positive outside). Outside the sections:\n"
    "the share of the surface beyond the tolerance. Verdicts per section and overall:\n"
    "pass (within the tolerance), machine (stock to machine off; said when beyond the\n"
    "allowance), rework (under-filled, or the part changed outside the sections). The\n"
    "inspection is recorded with the scan; the run's outcome follows its latest.\n"
    "\n"
    "  RUN              a run id from the catalogue (its restored mesh and patches)\n"
    "  --mesh SCAN      the scan after repair (.stl .obj .ply .off .gltf .glb)\n"
    "  --allowance MM   machining stock expected (default: the largest allowance the\n"
    "                   run's advice planned its sections with, else 0.5 mm)\n"
    "  --tolerance MM   deviation within this is on the surface (default 0.1 mm)\n" CLI_UNITS_HELP
    "  --align          always register the scan to the restored mesh\n"
    "  --no-align       take the scan as it lies (in the run's frame)\n"
    "  --glb FILE       also write the scan, in the run's frame, with its deviation\n"
    "                   colours as vertex colours (COLOR_0; the report's scale: blue\n"
    "                   short, green within the tolerance, yellow to red stock) to\n"
    "                   FILE (.glb or .gltf)\n"
    "  --json           one JSON object: {\"inspection\", \"run\", \"verdict\",\n"
    "                   \"reasons\", \"allowance_mm\", \"tolerance_mm\", \"registered\",\n"
    "                   \"coverage\", \"volumes_exact\", \"volume_note\", \"model_note\",\n"
    "                   \"outside\", \"sections\"}\n";

/* The largest allowance the run's advice planned with; 0 when none builds. */
static double advised_allowance(const sr_run *run, char *process, size_t size)
{
    double best = 0;
    process[0] = '\0';
    for (size_t k = 0; k < run->section_count; k++) {
        sr_plan_opts o;
        sr_plan_opts_init(&o);
        sr_plan_advice a;
        memset(&a, 0, sizeof a);
        if (sr_plan_follow_advice(run, run->sections[k].index, &o, &a, NULL) != SR_OK ||
            !a.builds || !(a.taken & SR_PLAN_FROM_ALLOWANCE))
            continue;
        if (o.allowance_mm > best) {
            best = o.allowance_mm;
            snprintf(process, size, "%s", a.process);
        }
    }
    return best;
}

static void print_json(int64_t id, const sr_run *run, const sr_inspect_result *r)
{
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_key(&j, "inspection");
    json_int(&j, id);
    json_key(&j, "run");
    json_int(&j, run->id);
    json_key(&j, "verdict");
    json_string(&j, sr_inspect_verdict_str(r->verdict));
    json_key(&j, "reasons");
    json_string(&j, r->reasons);
    json_key(&j, "allowance_mm");
    json_number(&j, r->allowance_mm);
    json_key(&j, "tolerance_mm");
    json_number(&j, r->tolerance_mm);
    json_key(&j, "registered");
    json_bool(&j, r->registered);
    json_key(&j, "coverage");
    json_number(&j, r->coverage);
    json_key(&j, "volumes_exact");
    json_bool(&j, r->volumes_exact);
    json_key(&j, "volume_note");
    json_string(&j, r->volume_note);
    json_key(&j, "model_note");
    json_string(&j, r->model_note);
    json_key(&j, "outside");
    json_object_begin(&j);
    json_key(&j, "samples");
    json_int(&j, (int64_t)r->outside_samples);
    json_key(&j, "share_beyond");
    json_number(&j, r->outside_share);
    json_key(&j, "max_mm");
    json_number(&j, r->outside_max_mm);
    json_key(&j, "rms_mm");
    json_number(&j, r->outside_rms_mm);
    json_key(&j, "overbuild_mm3");
    json_number(&j, r->outside_overbuild_mm3);
    json_object_end(&j);
    json_key(&j, "sections");
    json_array_begin(&j);
    for (size_t k = 0; k < r->section_count; k++) {
        const sr_inspect_section *s = &r->sections[k];
        json_object_begin(&j);
        json_key(&j, "section");
        json_int(&j, (int64_t)s->index + 1);
        json_key(&j, "verdict");
        json_string(&j, sr_inspect_verdict_str(s->verdict));
        json_key(&j, "reasons");
        json_string(&j, s->reasons);
        const struct {
            const char *key;
            double v;
        } f[] = {
            {"patch_mm3", s->patch_mm3},
            {"underfill_mm3", s->underfill_mm3},
            {"underfill_depth_mm", s->underfill_depth_mm},
            {"overbuild_mm3", s->overbuild_mm3},
            {"stock_min_mm", s->stock_min_mm},
            {"stock_max_mm", s->stock_max_mm},
            {"stock_mean_mm", s->stock_mean_mm},
            {"stock_share", s->stock_share},
            {"under_share", s->under_share},
            {"dev_mean_mm", s->dev_mean_mm},
            {"dev_rms_mm", s->dev_rms_mm},
            {"dev_min_mm", s->dev_min_mm},
            {"dev_max_mm", s->dev_max_mm},
        };
        for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
            json_key(&j, f[i].key);
            json_number(&j, f[i].v);
        }
        json_key(&j, "samples");
        json_int(&j, (int64_t)s->samples);
        json_object_end(&j);
    }
    json_array_end(&j);
    json_object_end(&j);
    json_finish(&j);
}

static void print_text(int64_t id, const sr_run *run, const char *scan_path,
                       const sr_inspect_result *r, const char *allowance_from)
{
    printf("inspection %lld of run %lld: %s\n", (long long)id, (long long)run->id,
           sr_inspect_verdict_str(r->verdict));
    printf("  scan %s: %s, %.1f %% of it on the model outside the sections (within %.3g mm)\n",
           cli_tx(scan_path), r->registered ? "registered" : "taken as it lay", 100 * r->coverage,
           r->reg_tol_mm);
    printf("  allowance %.3g mm (%s), tolerance %.3g mm; volumes %s%s%s\n", r->allowance_mm,
           allowance_from, r->tolerance_mm,
           r->volumes_exact ? "exact (booleans)" : "estimated from the samples: ",
           r->volumes_exact ? "" : cli_tx(r->volume_note), "");
    if (r->model_note[0])
        printf("  reference: %s\n", cli_tx(r->model_note));
    for (size_t k = 0; k < r->section_count; k++) {
        const sr_inspect_section *s = &r->sections[k];
        printf("  section %zu: %s: %s\n", s->index + 1, sr_inspect_verdict_str(s->verdict),
               s->reasons);
        printf("    missing %.3f mm³; under-fill %.3f mm³, %.3f mm deep; over-build %.3f mm³",
               s->patch_mm3, s->underfill_mm3, s->underfill_depth_mm, s->overbuild_mm3);
        if (s->stock_share > 0)
            printf(", stock %.3f..%.3f mm (mean %.3f)", s->stock_min_mm, s->stock_max_mm,
                   s->stock_mean_mm);
        printf("\n    deviation mean %+.3f, RMS %.3f, min %+.3f, max %+.3f mm (%zu samples)\n",
               s->dev_mean_mm, s->dev_rms_mm, s->dev_min_mm, s->dev_max_mm, s->samples);
    }
    printf("  outside the sections: %.2f %% beyond %.3g mm, max %.3f mm, RMS %.3f mm\n",
           100 * r->outside_share, r->tolerance_mm, r->outside_max_mm, r->outside_rms_mm);
    printf("  verdict: %s: %s\n", sr_inspect_verdict_str(r->verdict), r->reasons);
}

/* The scan in the model's frame with its deviation colours (linear, as glTF's COLOR_0
 * is) to path. */
static sr_status write_coloured(const char *path, const sr_inspect_result *r, sr_err *err)
{
    size_t n = r->scan.vertex_count;
    float *rgb = malloc((n ? 3 * n : 1) * sizeof *rgb);
    if (!rgb)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    for (size_t v = 0; v < n; v++) {
        sr_inspect_colour(r->tolerance_mm, r->allowance_mm, r->deviation[v], rgb + 3 * v);
        for (int k = 0; k < 3; k++) {
            double c = rgb[3 * v + (size_t)k];
            rgb[3 * v + (size_t)k] =
                (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
        }
    }
    sr_scene_mesh m = {"scan after repair", &r->scan, {1.0f, 1.0f, 1.0f, 1.0f}};
    const float *cols[1] = {rgb};
    sr_status st = sr_scene_write_coloured(
        path, &m, cols, 1, "{\"symrec\":\"inspection: signed deviation colours\"}", err);
    free(rgb);
    return st;
}

int cmd_inspect(const cli_ctx *ctx, int argc, char **argv)
{
    const char *glb = NULL;
    const char *mesh_path = NULL, *allowance = NULL, *tolerance = NULL, *units = NULL;
    bool json = false, align = false, no_align = false;
    const cli_opt opts[] = {
        {"--mesh", &mesh_path, NULL},
        {"--allowance", &allowance, NULL},
        {"--tolerance", &tolerance, NULL},
        {"--units", &units, NULL},
        {"--align", NULL, &align},
        {"--no-align", NULL, &no_align},
        {"--json", NULL, &json},
        {"--glb", &glb, NULL},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"inspect", usage, opts, 1, 1, "RUN"};
    const char *pos[1];
    int npos = 0, rc = CLI_OK;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, &npos, &rc))
        return rc;
    int64_t run_id;
    sr_inspect_opts o = {0};
    sr_unit unit;
    if (!cli_parse_id("RUN", pos[0], &run_id) || !cli_parse_units("--units", units, &unit))
        return CLI_USAGE;
    if (!mesh_path)
        return cli_usage_error("inspect needs --mesh SCAN (the part after repair)");
    if (align && no_align)
        return cli_usage_error("--align and --no-align exclude each other");
    if (allowance &&
        !cli_parse_double("--allowance", allowance, 0, 1e4, "a length in mm", &o.allowance_mm))
        return CLI_USAGE;
    if (tolerance && !cli_parse_double("--tolerance", tolerance, 1e-6, 1e4, "a length in mm > 0",
                                       &o.tolerance_mm))
        return CLI_USAGE;
    o.register_mode = align      ? SR_INSPECT_REGISTER_ALWAYS
                      : no_align ? SR_INSPECT_REGISTER_NEVER
                                 : SR_INSPECT_REGISTER_AUTO;
    sr_catalog *cat = NULL;
    if (!cli_open(ctx, CLI_WRITE, "record the inspection", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_run run;
    memset(&run, 0, sizeof run);
    sr_mesh scan;
    sr_mesh_init(&scan);
    sr_inspect_result r;
    memset(&r, 0, sizeof r);
    int64_t id = 0;
    char process[64] = "", from[96] = "given";
    sr_status st = sr_catalog_run_get(cat, run_id, SR_RUN_WITH_MESHES, &run, &err);
    if (st == SR_OK)
        st = cli_mesh_read(mesh_path, unit, &scan, NULL, &err);
    if (st == SR_OK && !allowance) {
        double a = advised_allowance(&run, process, sizeof process);
        if (a > 0) {
            o.allowance_mm = a;
            snprintf(from, sizeof from, "the advice's, %s", process);
        } else {
            o.allowance_mm = SR_INSPECT_ALLOWANCE_MM;
            snprintf(from, sizeof from, "default: no advice builds up");
        }
    }
    if (st == SR_OK) {
        cli_note("inspecting run %lld against '%s'", (long long)run_id, cli_tx(mesh_path));
        st = sr_inspect_run(&run, &scan, &o, &r, &err);
    }
    if (st == SR_OK && glb)
        st = write_coloured(glb, &r, &err);
    if (st == SR_OK)
        st = sr_catalog_inspection_add(cat, run_id, &scan, mesh_path, &r, &id, &err);
    if (st != SR_OK)
        rc = cli_fail(st, &err);
    else if (json)
        print_json(id, &run, &r);
    else
        print_text(id, &run, mesh_path, &r, from);
    sr_inspect_release(&r);
    sr_mesh_release(&scan);
    sr_run_release(&run);
    sr_catalog_close(cat);
    return rc;
}
