/*
 * cmd_plan.c: `symrec plan`: the build plan of one missing section of a stored
 * reconstruction run, written as plan.json, layer_NNN.svg per layer and plan.gcode.
 *
 * The plan itself is src/plan/plan.h (regions, allowance, paths, figures) and its files
 * src/plan/plan_export.h; this file reads the run with its layer polylines from the
 * catalogue, passes the options on and prints the summary.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "catalog/catalog_runs.h"
#include "catalog/catalog_rules.h"
#include "cli.h"
#include "json_out.h"
#include "outset.h"
#include "plan/plan.h"
#include "plan/plan_export.h"

static const char usage[] =
    "usage: symrec [--db FILE] plan RUN --out DIR [--section K] [--step-over MM]\n"
    "              [--allowance MM] [--layer-mm MM] [--pattern P] [--raster-angle DEG]\n"
    "              [--density G_CM3] [--rate CM3_MIN] [--feed MM_MIN]\n"
    "              [--travel-height MM] [--on-code CODE] [--off-code CODE] [--json]\n"
    "\n"
    "Plans the rebuilding of one missing section of run RUN layer by layer (directed\n"
    "energy deposition or spray forming): per layer the missing region (restored minus\n"
    "damaged outline within the section), the deposit region (grown by the machining\n"
    "allowance, outside the damaged part) and a deposition path of contour rings and a\n"
    "zig-zag raster. The build direction is +z of the run's aligned frame (along the\n"
    "symmetry axis). Writes DIR/plan.json, DIR/layer_NNN.svg (one per layer) and\n"
    "DIR/plan.gcode (G21 mm, G90 absolute, aligned frame). Units: mm, mm2, mm3, g, min.\n"
    "\n"
    "  RUN                a run id from the catalogue\n"
    "  --out DIR          the folder of the plan's files, written as a set: a new\n"
    "                     folder, an empty one, or one symrec wrote (its files are\n"
    "                     all replaced at once; a folder holding other files is\n"
    "                     refused)\n"
    "  --section K        the section's number as 'run show' lists it (default 1)\n"
    "  --step-over MM     bead spacing (default 1.0 mm)\n"
    "  --allowance MM     machining allowance (default 0.5 mm)\n"
    "  --layer-mm MM      layer thickness (default: the run's layer spacing)\n"
    "  --pattern P        contour+raster (default), contour or raster\n"
    "  --raster-angle DEG raster angle of the first layer; +90 every other layer (0)\n"
    "  --density G_CM3    deposit density (default: the part's material's density from\n"
    "                     the catalogue, else 7.85 g/cm3, steel)\n"
    "  --rate CM3_MIN     deposition rate for the build time (default 1.0 cm3/min)\n"
    "  --feed MM_MIN      deposition feed in the G-code (default 600 mm/min)\n"
    "  --travel-height MM clearance above the layer for travel moves (default 5 mm)\n"
    "  --on-code CODE     code that starts deposition (default M3)\n"
    "  --off-code CODE    code that stops it (default M5)\n"
    "  --json             print the plan's figures as one JSON object\n";

/* The files a plan writes (outset.h: what may be replaced in an existing DIR). */
static const char *const plan_names[] = {"plan.json", "plan.gcode", "layer_[0-9][0-9][0-9]*.svg",
                                         NULL};

static void print_human(const sr_plan *p, const char *dir)
{
    printf("build plan of run %lld section %zu (%s)\n", (long long)p->run_id,
           p->section_index + 1, sr_sym_kind_name(p->kind));
    if (p->has_angles)
        printf("  section: z %.3f..%.3f mm, angle %.1f..%.1f deg\n", p->z_min_mm, p->z_max_mm,
               p->angle_from_deg, p->angle_to_deg);
    else
        printf("  section: z %.3f..%.3f mm, side %+d of the plane\n", p->z_min_mm,
               p->z_max_mm, p->side);
    printf("  build direction +z (along the symmetry axis), %zu layers of %.3f mm\n",
           p->layer_count, p->opts.layer_mm);
    printf("  pattern %s, step-over %.3f mm, machining allowance %.3f mm\n",
           sr_plan_pattern_name(p->opts.pattern), p->opts.step_over_mm,
           p->opts.allowance_mm);
    printf("  missing %.1f mm3, deposit %.1f mm3 = %.2f g at %.3f g/cm3\n",
           p->missing_volume_mm3, p->deposit_volume_mm3, p->deposit_mass_g,
           p->opts.density_g_cm3);
    printf("  estimated build time %.1f min at %.3f cm3/min, path %.1f mm\n",
           p->build_time_min, p->opts.rate_cm3_min, p->path_length_mm);
    printf("  wrote %s/plan.json, %s/layer_001.svg..layer_%03zu.svg, %s/plan.gcode\n", dir,
           dir, p->layer_count, dir);
}

static int print_json(const sr_plan *p, const sr_plan_machine *m, const char *dir)
{
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_key(&j, "run");
    json_int(&j, p->run_id);
    json_key(&j, "section");
    json_int(&j, (int64_t)p->section_index + 1);
    json_key(&j, "symmetry");
    json_string(&j, sr_sym_kind_name(p->kind));
    json_key(&j, "build_direction");
    json_string(&j, "+z");
    json_key(&j, "layer_mm");
    json_number(&j, p->opts.layer_mm);
    json_key(&j, "layer_count");
    json_int(&j, (int64_t)p->layer_count);
    json_key(&j, "pattern");
    json_string(&j, sr_plan_pattern_name(p->opts.pattern));
    json_key(&j, "step_over_mm");
    json_number(&j, p->opts.step_over_mm);
    json_key(&j, "allowance_mm");
    json_number(&j, p->opts.allowance_mm);
    json_key(&j, "density_g_cm3");
    json_number(&j, p->opts.density_g_cm3);
    json_key(&j, "missing_volume_mm3");
    json_number(&j, p->missing_volume_mm3);
    json_key(&j, "deposit_volume_mm3");
    json_number(&j, p->deposit_volume_mm3);
    json_key(&j, "deposit_mass_g");
    json_number(&j, p->deposit_mass_g);
    json_key(&j, "build_time_min");
    json_number(&j, p->build_time_min);
    json_key(&j, "path_length_mm");
    json_number(&j, p->path_length_mm);
    json_key(&j, "feed_mm_min");
    json_number(&j, m->feed_mm_min);
    json_key(&j, "out");
    json_string(&j, dir);
    json_object_end(&j);
    return json_finish(&j);
}

/* Parses one optional number option into *out (kept when the option is absent). */
static bool number_opt(const char *opt, const char *text, double min, double max,
                       const char *what, double *out)
{
    return !text || cli_parse_double(opt, text, min, max, what, out);
}

int cmd_plan(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = NULL, *section = NULL, *step = NULL, *allowance = NULL,
               *layer_mm = NULL, *pattern = NULL, *angle = NULL, *density = NULL,
               *rate = NULL, *feed = NULL, *travel = NULL, *on_code = NULL, *off_code = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--out", &out, NULL},
                            {"--section", &section, NULL},
                            {"--step-over", &step, NULL},
                            {"--allowance", &allowance, NULL},
                            {"--layer-mm", &layer_mm, NULL},
                            {"--pattern", &pattern, NULL},
                            {"--raster-angle", &angle, NULL},
                            {"--density", &density, NULL},
                            {"--rate", &rate, NULL},
                            {"--feed", &feed, NULL},
                            {"--travel-height", &travel, NULL},
                            {"--on-code", &on_code, NULL},
                            {"--off-code", &off_code, NULL},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"plan", usage, opts, 1, 1, "RUN"};
    const char *pos[1];
    int npos = 0, rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, &npos, &rc))
        return rc;
    int64_t run_id;
    if (!cli_parse_id("RUN", pos[0], &run_id))
        return CLI_USAGE;
    if (!out)
        return cli_usage_error("'plan' needs --out DIR (see 'symrec plan --help')");
    int k = 1;
    if (section && !cli_parse_int("--section", section, 1, 1000000, "a section number >= 1",
                                  &k))
        return CLI_USAGE;

    sr_plan_opts po;
    sr_plan_opts_init(&po);
    sr_plan_machine m;
    sr_plan_machine_init(&m);
    sr_err err;
    sr_err_clear(&err);
    if (!number_opt("--step-over", step, 1e-3, 1e4, "a step-over > 0 mm", &po.step_over_mm) ||
        !number_opt("--allowance", allowance, 0, 1e4, "an allowance >= 0 mm",
                    &po.allowance_mm) ||
        !number_opt("--layer-mm", layer_mm, 1e-3, 1e4, "a thickness > 0 mm", &po.layer_mm) ||
        !number_opt("--raster-angle", angle, -360, 360, "an angle -360..360 deg",
                    &po.raster_angle_deg) ||
        !number_opt("--density", density, 1e-3, 100, "a density > 0 g/cm3",
                    &po.density_g_cm3) ||
        !number_opt("--rate", rate, 1e-6, 1e6, "a rate > 0 cm3/min", &po.rate_cm3_min) ||
        !number_opt("--feed", feed, 1e-3, 1e6, "a feed > 0 mm/min", &m.feed_mm_min) ||
        !number_opt("--travel-height", travel, 0, 1e4, "a height >= 0 mm",
                    &m.travel_height_mm))
        return CLI_USAGE;
    if (pattern && sr_plan_pattern_parse(pattern, "--pattern", &po.pattern, &err) != SR_OK)
        return cli_usage_error("%s", err.msg);
    if (on_code)
        snprintf(m.on_code, sizeof m.on_code, "%s", on_code);
    if (off_code)
        snprintf(m.off_code, sizeof m.off_code, "%s", off_code);
    if ((on_code && strlen(on_code) >= sizeof m.on_code) ||
        (off_code && strlen(off_code) >= sizeof m.off_code) ||
        sr_plan_machine_check(&m, &err) != SR_OK)
        return cli_usage_error("bad --on-code/--off-code: %s",
                               err.msg[0] ? err.msg : "at most 31 characters");

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_run run;
    memset(&run, 0, sizeof run);
    sr_status st = sr_catalog_run_get(cat, run_id, SR_RUN_WITH_LAYERS, &run, &err);
    /* without --density, the density of the part's material when the catalogue knows it */
    if (st == SR_OK && !density) {
        sr_part_info part;
        sr_material mat;
        sr_err quiet;
        if (sr_catalog_part_find(cat, run.part_number, &part, &quiet) == SR_OK &&
            part.material[0] &&
            sr_catalog_material_get(cat, part.material, &mat, &quiet) == SR_OK &&
            isfinite(mat.density_g_cm3) && mat.density_g_cm3 > 0)
            po.density_g_cm3 = mat.density_g_cm3;
    }
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    sr_plan plan;
    st = sr_plan_build(&run, (size_t)(k - 1), &po, &plan, &err);
    sr_run_release(&run);
    if (st != SR_OK)
        return cli_fail(st, &err);
    cli_outset set;
    if (!cli_outset_begin(&set, out, "plan", plan_names)) {
        sr_plan_release(&plan);
        return CLI_FAIL;
    }
    st = sr_plan_export(&plan, &m, set.stage, &err);
    rc = CLI_OK;
    if (st != SR_OK) {
        cli_outset_abort(&set);
        rc = cli_fail(st, &err);
    } else if (!cli_outset_commit(&set)) {
        rc = CLI_FAIL;
    } else if (json)
        rc = print_json(&plan, &m, out);
    else
        print_human(&plan, out);
    sr_plan_release(&plan);
    return rc;
}
