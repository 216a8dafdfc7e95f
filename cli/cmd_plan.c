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
    "              [--density G_CM3] [--rate CM3_MIN] [--feed MM_MIN] [--rapid MM_MIN]\n"
    "              [--travel-height MM] [--on-code CODE] [--off-code CODE]\n"
    "              [--ignore-advice] [--json]\n"
    "\n"
    "Plans the rebuilding of one missing section of run RUN layer by layer (directed\n"
    "energy deposition or spray forming): per layer the missing region (restored minus\n"
    "damaged outline within the section), the deposit region (grown by the machining\n"
    "allowance, outside the damaged part) and a deposition path of contour rings and a\n"
    "zig-zag raster. The build direction is +z of the run's aligned frame (along the\n"
    "symmetry axis). Writes DIR/plan.json, DIR/layer_NNN.svg (one per layer) and\n"
    "DIR/plan.gcode (G21 mm, G90 absolute, aligned frame). Units: mm, mm², mm³, g, min.\n"
    "\n"
    "The plan follows the advice the run's rules gave the section: its process, layer\n"
    "height, step-over, machining allowance and deposition rate (the rule's\n"
    "deposition_rate_g_min x efficiency / density), and the preheat of the process on\n"
    "the part's material. An option given here overrides the advice. A section advised\n"
    "a process that builds nothing up (replace, inspect, manual_review) has no plan\n"
    "unless --ignore-advice. The build time is the time of the G-code's moves: the\n"
    "deposition path at the feed plus the travel moves at the rapid rate.\n"
    "\n"
    "  RUN                a run id from the catalogue\n"
    "  --out DIR          the folder of the plan's files, written as a set: a new\n"
    "                     folder, an empty one, or one symrec wrote (its files are\n"
    "                     all replaced at once; a folder holding other files is\n"
    "                     refused)\n"
    "  --section K        the section's number as 'run show' lists it (default 1)\n"
    "  --step-over MM     bead spacing (default: the advice's, else 1.0 mm)\n"
    "  --allowance MM     machining allowance (default: the advice's, else 0.5 mm)\n"
    "  --layer-mm MM      layer thickness (default: the advice's, else the run's layer\n"
    "                     spacing)\n"
    "  --pattern P        contour+raster (default), contour or raster\n"
    "  --raster-angle DEG raster angle of the first layer; +90 every other layer (0)\n"
    "  --density G_CM3    deposit density (default: the part's material's density from\n"
    "                     the catalogue, else 7.85 g/cm3, steel)\n"
    "  --rate CM3_MIN     deposition rate (default: the advice's, else 1.0 cm3/min)\n"
    "  --feed MM_MIN      deposition feed in the G-code (default: the rate laid down as\n"
    "                     beads, rate / (step-over x layer))\n"
    "  --rapid MM_MIN     speed of the travel moves, for the build time (default 5000)\n"
    "  --travel-height MM clearance above the layer for travel moves (default 5 mm)\n"
    "  --on-code CODE     code that starts deposition (default M3)\n"
    "  --off-code CODE    code that stops it (default M5)\n"
    "  --ignore-advice    plan with the defaults and the options given, whatever the\n"
    "                     advice says\n"
    "  --json             print the plan's figures as one JSON object\n";

/* The files a plan writes (outset.h: what may be replaced in an existing DIR). */
static const char *const plan_names[] = {"plan.json", "plan.gcode", "layer_[0-9][0-9][0-9]*.svg",
                                         NULL};

static void print_human(const sr_plan *p, const char *advice_note, const char *dir)
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
    printf("  missing %.1f mm³, deposit %.1f mm³ = %.2f g at %.3f g/cm³\n", p->missing_volume_mm3,
           p->deposit_volume_mm3, p->deposit_mass_g, p->opts.density_g_cm3);
    if (p->process[0])
        printf("  process %s, as advised by rule %s%s\n", p->process,
               p->rule[0] ? p->rule : "(unknown)", advice_note);
    if (isfinite(p->preheat_c))
        printf("  preheat the part to %.0f C\n", p->preheat_c);
    printf("  build time %.1f min: path %.1f mm at %.1f mm/min (%.1f min, deposition rate "
           "%.3f cm³/min), travel %.1f mm (%.1f min)\n",
           p->build_time_min, p->path_length_mm, p->feed_mm_min, p->deposit_time_min,
           p->opts.rate_cm3_min, p->travel_length_mm, p->travel_time_min);
    printf("  wrote %s/plan.json, %s/layer_001.svg..layer_%03zu.svg, %s/plan.gcode\n", dir,
           dir, p->layer_count, dir);
}

/* The settings an advice can give, by the names plan.json and --json use. */
static const struct {
    unsigned bit;
    const char *key;
} advice_keys[] = {{SR_PLAN_FROM_LAYER, "layer_mm"},
                   {SR_PLAN_FROM_STEP_OVER, "step_over_mm"},
                   {SR_PLAN_FROM_ALLOWANCE, "allowance_mm"},
                   {SR_PLAN_FROM_RATE, "rate_cm3_min"}};

static int print_json(const sr_plan *p, const sr_plan_machine *m, unsigned from_advice,
                      const char *dir)
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
    json_key(&j, "deposit_time_min");
    json_number(&j, p->deposit_time_min);
    json_key(&j, "travel_time_min");
    json_number(&j, p->travel_time_min);
    json_key(&j, "travel_length_mm");
    json_number(&j, p->travel_length_mm);
    json_key(&j, "rate_cm3_min");
    json_number(&j, p->opts.rate_cm3_min);
    json_key(&j, "process");
    if (p->process[0])
        json_string(&j, p->process);
    else
        json_null(&j);
    json_key(&j, "advised_by_rule");
    if (p->process[0])
        json_string(&j, p->rule);
    else
        json_null(&j);
    json_key(&j, "from_advice");
    json_array_begin(&j);
    for (size_t i = 0; i < sizeof advice_keys / sizeof advice_keys[0]; i++)
        if (from_advice & advice_keys[i].bit)
            json_string(&j, advice_keys[i].key);
    json_array_end(&j);
    json_key(&j, "path_length_mm");
    json_number(&j, p->path_length_mm);
    json_key(&j, "feed_mm_min");
    json_number(&j, p->feed_mm_min);
    json_key(&j, "rapid_mm_min");
    json_number(&j, m->rapid_mm_min);
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
    const char *out = NULL, *section = NULL, *step = NULL, *allowance = NULL, *layer_mm = NULL,
               *pattern = NULL, *angle = NULL, *density = NULL, *rate = NULL, *feed = NULL,
               *rapid = NULL, *travel = NULL, *on_code = NULL, *off_code = NULL;
    bool json = false, ignore_advice = false;
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
                            {"--rapid", &rapid, NULL},
                            {"--travel-height", &travel, NULL},
                            {"--on-code", &on_code, NULL},
                            {"--off-code", &off_code, NULL},
                            {"--ignore-advice", NULL, &ignore_advice},
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

    /* the options given, checked before anything is read; applied over the advice */
    sr_plan_opts given;
    sr_plan_opts_init(&given);
    sr_plan_machine m;
    sr_plan_machine_init(&m);
    sr_err err;
    sr_err_clear(&err);
    if (!number_opt("--step-over", step, 1e-3, 1e4, "a step-over > 0 mm", &given.step_over_mm) ||
        !number_opt("--allowance", allowance, 0, 1e4, "an allowance >= 0 mm",
                    &given.allowance_mm) ||
        !number_opt("--layer-mm", layer_mm, 1e-3, 1e4, "a thickness > 0 mm", &given.layer_mm) ||
        !number_opt("--raster-angle", angle, -360, 360, "an angle -360..360 deg",
                    &given.raster_angle_deg) ||
        !number_opt("--density", density, 1e-3, 100, "a density > 0 g/cm3", &given.density_g_cm3) ||
        !number_opt("--rate", rate, 1e-6, 1e6, "a rate > 0 cm3/min", &given.rate_cm3_min) ||
        !number_opt("--feed", feed, 1e-3, 1e6, "a feed > 0 mm/min", &m.feed_mm_min) ||
        !number_opt("--rapid", rapid, 1e-3, 1e6, "a speed > 0 mm/min", &m.rapid_mm_min) ||
        !number_opt("--travel-height", travel, 0, 1e4, "a height >= 0 mm", &m.travel_height_mm))
        return CLI_USAGE;
    if (pattern && sr_plan_pattern_parse(pattern, "--pattern", &given.pattern, &err) != SR_OK)
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
    sr_plan_opts po;
    sr_plan_opts_init(&po);
    po.pattern = given.pattern;
    po.raster_angle_deg = given.raster_angle_deg;
    po.density_g_cm3 = given.density_g_cm3;
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
    /* the advice's settings, then the options given over them */
    sr_plan_advice adv;
    memset(&adv, 0, sizeof adv);
    adv.preheat_c = NAN;
    if (!ignore_advice) {
        st = sr_plan_follow_advice(&run, (size_t)(k - 1), &po, &adv, &err);
        if (st == SR_OK && adv.found && !adv.builds)
            st = sr_err_set(&err, SR_E_INVALID,
                            "run %lld section %d was advised '%s' (rule %s): nothing to build "
                            "up, so no plan (plan it anyway with --ignore-advice)",
                            (long long)run_id, k, adv.process, adv.rule[0] ? adv.rule : "?");
        if (st != SR_OK) {
            sr_run_release(&run);
            return cli_fail(st, &err);
        }
    }
    unsigned taken = adv.taken;
    if (step)
        po.step_over_mm = given.step_over_mm, taken &= ~SR_PLAN_FROM_STEP_OVER;
    if (allowance)
        po.allowance_mm = given.allowance_mm, taken &= ~SR_PLAN_FROM_ALLOWANCE;
    if (layer_mm)
        po.layer_mm = given.layer_mm, taken &= ~SR_PLAN_FROM_LAYER;
    if (rate)
        po.rate_cm3_min = given.rate_cm3_min, taken &= ~SR_PLAN_FROM_RATE;
    sr_plan plan;
    st = sr_plan_build(&run, (size_t)(k - 1), &po, &plan, &err);
    sr_run_release(&run);
    if (st == SR_OK) {
        if (adv.builds) {
            snprintf(plan.process, sizeof plan.process, "%s", adv.process);
            snprintf(plan.rule, sizeof plan.rule, "%s", adv.rule);
        }
        plan.preheat_c = adv.builds ? adv.preheat_c : NAN;
        st = sr_plan_time(&plan, &m, &err);
        if (st != SR_OK)
            sr_plan_release(&plan);
    }
    if (st != SR_OK)
        return cli_fail(st, &err);
    char note[96] = "";
    if (adv.builds && adv.taken != taken)
        snprintf(note, sizeof note, " (options given override part of it)");
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
        rc = print_json(&plan, &m, taken, out);
    else
        print_human(&plan, note, out);
    sr_plan_release(&plan);
    return rc;
}
