/*
 * report_plans.c: the build plans of the HTML report (report_int.h), made here with
 * plan.h (sr_plan_build, the options given or the defaults), one per section not
 * advised 'replace'; the page's "Build plans" table, and each plan's layers in the data
 * block: missing region, deposit region and deposition paths, which report.js draws
 * over the selected layer's outlines.
 */
#include "report/report_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* A region or a set of polylines as [[x,y,x,y,...],...], 1e-5 mm (the polygon grid). */
static void put_poly(sb *b, const sr_poly2 *p)
{
    sb_put(b, "[");
    for (size_t c = 0; c < p->contour_count; c++) {
        sb_put(b, c ? ",[" : "[");
        for (size_t i = p->start[c]; i < p->start[c + 1]; i++) {
            if (i > p->start[c])
                sb_put(b, ",");
            sb_jnum(b, p->xy[2 * i], "%.5f");
            sb_put(b, ",");
            sb_jnum(b, p->xy[2 * i + 1], "%.5f");
        }
        sb_put(b, "]");
    }
    sb_put(b, "]");
}

/* The advice for section `index` (0-based): replace when that section's or a
 * whole-part advice begins 'replace'; *process = the section's first advised process. */
static bool advised_replace(const sr_run *r, size_t index, const char **process)
{
    bool replace = false;
    *process = "";
    for (size_t i = 0; i < r->advice_count; i++) {
        const sr_run_advice *a = &r->advice[i];
        if (a->section_index >= 0 && (size_t)a->section_index != index)
            continue;
        if (a->section_index >= 0 && !**process)
            *process = a->process;
        if (strncasecmp(a->process, "replace", 7) == 0)
            replace = true;
    }
    return replace;
}

void rp_plans_release(report_plan *p, size_t n)
{
    for (size_t i = 0; p && i < n; i++)
        sr_plan_release(&p[i].plan);
    free(p);
}

/* One entry per section. SR_E_NOMEM only; a plan that cannot be made says why. */
sr_status rp_plans_build(const sr_run *r, const sr_plan_opts *opts, report_plan **out,
                         sr_err *err)
{
    *out = NULL;
    if (!r->section_count)
        return SR_OK;
    report_plan *p = calloc(r->section_count, sizeof *p);
    if (!p)
        return sr_err_set(err, SR_E_NOMEM, "out of memory building the report");
    for (size_t i = 0; i < r->section_count; i++) {
        p[i].section = &r->sections[i];
        p[i].replace = advised_replace(r, r->sections[i].index, &p[i].process);
        if (p[i].replace)
            continue;
        sr_err e;
        sr_err_clear(&e);
        /* the section's advice gives the settings, as `symrec plan` takes them */
        sr_plan_opts o;
        if (opts)
            o = *opts;
        else
            sr_plan_opts_init(&o);
        sr_plan_advice a;
        sr_status st = sr_plan_follow_advice(r, r->sections[i].index, &o, &a, &e);
        if (st == SR_OK && a.found && !a.builds) {
            snprintf(p[i].why, sizeof p[i].why, "the advice is '%s': nothing to build up",
                     a.process);
            continue;
        }
        if (st == SR_OK)
            st = sr_plan_build(r, r->sections[i].index, &o, &p[i].plan, &e);
        if (st == SR_OK && a.builds) {
            snprintf(p[i].plan.process, sizeof p[i].plan.process, "%s", a.process);
            snprintf(p[i].plan.rule, sizeof p[i].plan.rule, "%s", a.rule);
            p[i].plan.preheat_c = a.preheat_c;
        }
        if (st == SR_E_NOMEM) {
            rp_plans_release(p, r->section_count);
            return sr_err_set(err, SR_E_NOMEM, "out of memory building the report's plans");
        }
        p[i].built = st == SR_OK;
        if (!p[i].built)
            snprintf(p[i].why, sizeof p[i].why, "%s", e.msg[0] ? e.msg : sr_status_str(st));
    }
    *out = p;
    return SR_OK;
}

/* The build plan section: one row per section with the plan's figures, or why not. */
void rp_plan_table(sb *b, const sr_run *r, const report_plan *p)
{
    sb_put(b, "<section id=\"plans\"><h2>Build plans</h2>\n");
    if (r->section_count == 0) {
        sb_put(b, "<p>No missing section: no build plan.</p></section>\n");
        return;
    }
    bool all_replace = true;
    for (size_t i = 0; i < r->section_count; i++)
        all_replace = all_replace && p[i].replace;
    if (all_replace) {
        sb_put(b, "<p id=\"no-plan\">No build plan: the advice is to replace the part "
                  "(beyond repair).</p></section>\n");
        return;
    }
    const sr_plan *any = NULL;
    for (size_t i = 0; i < r->section_count && !any; i++)
        if (p[i].built)
            any = &p[i].plan;
    if (any)
        sb_printf(b,
                  "<p class=\"note\">Per section, layer by layer along +z of the aligned "
                  "frame, as <code>symrec plan RUN --section K</code> writes it, with the "
                  "settings of the section's advice (the first plan: pattern %s, "
                  "step-over %.3g mm, machining allowance %.3g mm, density %.3g g/cm³, "
                  "deposition rate %.3g cm³/min). The build time is the time of the "
                  "plan's tool path, travel moves included. The paths of the selected "
                  "layer are drawn in the plot above.</p>\n",
                  sr_plan_pattern_name(any->opts.pattern), any->opts.step_over_mm,
                  any->opts.allowance_mm, any->opts.density_g_cm3, any->opts.rate_cm3_min);
    sb_put(b, "<table id=\"plan-table\"><thead><tr><th>section</th><th>advice</th>"
              "<th>layers</th><th>layer (mm)</th><th>missing (mm³)</th>"
              "<th>deposit (mm³)</th><th>mass (g)</th><th>build time (min)</th>"
              "<th>path (mm)</th></tr></thead><tbody>\n");
    for (size_t i = 0; i < r->section_count; i++) {
        const report_plan *q = &p[i];
        sb_printf(b, "<tr class=\"plan\"><td class=\"n\">%zu</td><td>", q->section->index + 1);
        sb_html(b, q->process[0] ? q->process : "-");
        if (q->built) {
            const sr_plan *pl = &q->plan;
            sb_printf(b,
                      "</td><td class=\"n\">%zu</td><td class=\"n\">%.3f</td>"
                      "<td class=\"n\">%.1f</td><td class=\"n\">%.1f</td>"
                      "<td class=\"n\">%.2f</td><td class=\"n\">%.1f</td>"
                      "<td class=\"n\">%.0f</td></tr>\n",
                      pl->layer_count, pl->opts.layer_mm, pl->missing_volume_mm3,
                      pl->deposit_volume_mm3, pl->deposit_mass_g, pl->build_time_min,
                      pl->path_length_mm);
        } else {
            sb_put(b, "</td><td colspan=\"7\">No build plan: ");
            if (q->replace)
                sb_put(b, "the advice is to replace the part (beyond repair).");
            else
                sb_html(b, q->why);
            sb_put(b, "</td></tr>\n");
        }
    }
    sb_put(b, "</tbody></table></section>\n");
}

/* The plans in the data block: per section {"section", "replace", "why", and when
 * built "layer_mm", "allowance_mm", "step_over_mm", "layers": [{"zb", "z" (bottom and
 * top of the layer's slab, mm), "rf", "rl" (the run layers it was built from),
 * "m" (missing region), "g" (deposit region), "paths": [{"k": 1 ring | 2 raster,
 * "p": [x, y, ...]}]}]}. */
void rp_put_plans(sb *b, const sr_run *r, const report_plan *p)
{
    sb_put(b, ",\"plans\":[");
    for (size_t i = 0; i < r->section_count; i++) {
        const report_plan *q = &p[i];
        sb_printf(b, "%s{\"section\":%zu,\"replace\":%s,\"why\":", i ? "," : "",
                  q->section->index + 1, q->replace ? "true" : "false");
        if (q->built || q->replace)
            sb_put(b, "null");
        else
            sb_jstr(b, q->why);
        if (!q->built) {
            sb_put(b, ",\"layers\":[]}");
            continue;
        }
        const sr_plan *pl = &q->plan;
        sb_put(b, ",\"layer_mm\":");
        sb_jnum(b, pl->opts.layer_mm, "%.6g");
        sb_put(b, ",\"allowance_mm\":");
        sb_jnum(b, pl->opts.allowance_mm, "%.6g");
        sb_put(b, ",\"step_over_mm\":");
        sb_jnum(b, pl->opts.step_over_mm, "%.6g");
        sb_put(b, ",\"layers\":[");
        for (size_t k = 0; k < pl->layer_count; k++) {
            const sr_plan_layer *L = &pl->layers[k];
            sb_put(b, k ? ",{\"zb\":" : "{\"zb\":");
            sb_jnum(b, L->z_bottom_mm, "%.5f");
            sb_put(b, ",\"z\":");
            sb_jnum(b, L->z_top_mm, "%.5f");
            sb_printf(b, ",\"rf\":%zu,\"rl\":%zu,\"m\":", L->run_layer_first,
                      L->run_layer_last);
            put_poly(b, &L->missing);
            sb_put(b, ",\"g\":");
            put_poly(b, &L->region);
            sb_put(b, ",\"paths\":[");
            for (size_t c = 0; c < L->paths.contour_count; c++) {
                sb_printf(b, "%s{\"k\":%d,\"p\":[", c ? "," : "",
                          L->path_kind ? (int)L->path_kind[c] : 0);
                for (size_t j = L->paths.start[c]; j < L->paths.start[c + 1]; j++) {
                    if (j > L->paths.start[c])
                        sb_put(b, ",");
                    sb_jnum(b, L->paths.xy[2 * j], "%.5f");
                    sb_put(b, ",");
                    sb_jnum(b, L->paths.xy[2 * j + 1], "%.5f");
                }
                sb_put(b, "]}");
            }
            sb_put(b, "]}");
        }
        sb_put(b, "]}");
    }
    sb_put(b, "]");
}
