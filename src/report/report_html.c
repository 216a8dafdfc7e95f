/*
 * report_html.c: the self-contained HTML report of a run (report_html.h).
 *
 * The page is written into one growing buffer (report_text.c): the head with the
 * inline stylesheet (report.css), the static tables (run facts, missing sections,
 * advice, parameters, alignment, timings) made here with every text HTML-escaped, the
 * layer selector, then the data as one JSON block (<script type="application/json">,
 * with '<', '>' and '&' written as \u escapes so no text can end the element; meshes
 * and outlines compact, report_data.c), three.js, and the inline scripts:
 * report_view.js draws the 3D view in WebGL, report.js the outlines of the selected
 * layer as SVG with the build plans of the sections over them (report_plans.c). The
 * feature and advice cells are report_cells.c's. No address of any kind appears in the
 * page outside three.js's own text (XML namespace names): it works from one file,
 * offline.
 *
 * Meshes over the display budget are reduced by vertex clustering (decimate.c); the
 * page states the stored and shown triangle counts.
 */
#include "report/report_int.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/json_scan.h"
#include "base/symmetry.h"
#include "report/report_assets.h"

#define DEFAULT_BUDGET 60000

/* ---- tables ---- */

static const char *sym_text(const sr_symmetry *s, char *buf, size_t size)
{
    switch (s->kind) {
    case SR_SYM_AXIAL:
        if (s->order)
            snprintf(buf, size, "axial, %d-fold", s->order);
        else
            snprintf(buf, size, "axial, continuous");
        break;
    case SR_SYM_MIRROR:
        snprintf(buf, size, "mirror");
        break;
    case SR_SYM_GLIDE:
        snprintf(buf, size, "glide, shift %g mm", s->shift_mm);
        break;
    default:
        snprintf(buf, size, "-");
    }
    return buf;
}

static void fact(sb *b, const char *label, const char *value)
{
    sb_put(b, "<tr><th>");
    sb_html(b, label);
    sb_put(b, "</th><td>");
    sb_html(b, value && *value ? value : "-");
    sb_put(b, "</td></tr>\n");
}

/* One timing member as a table row; a value that is not a number spoils the table. */
typedef struct timing_acc {
    sb rows;
    bool bad;
} timing_acc;

static void timing_member(const char *k, size_t klen, const char *val, const char *end,
                          void *user)
{
    timing_acc *acc = user;
    char *stop;
    double v = strtod(val, &stop);
    if (stop == val || stop != end) {
        acc->bad = true;
        return;
    }
    char key[128];
    snprintf(key, sizeof key, "%.*s", (int)(klen < 127 ? klen : 127), k);
    sb_put(&acc->rows, "<tr><th>");
    sb_html(&acc->rows, key);
    sb_printf(&acc->rows, "</th><td class=\"n\">%.3f</td></tr>\n", v);
}

/* The timings object ({"phase": seconds, ...}) as table rows; false when it is not a
 * flat object of numbers (then the caller shows the text). */
static bool timing_rows(sb *b, const char *json)
{
    timing_acc acc = {{0}, false};
    bool ok = sr_json_for_members(json, timing_member, &acc) && !acc.bad && !acc.rows.failed;
    if (ok && acc.rows.p)
        sb_put(b, acc.rows.p);
    free(acc.rows.p);
    return ok;
}

/* Counter-clockwise end of an axial arc in [0, 360], as `run show` prints it. */
static double arc_end(const sr_run_section *s)
{
    if (s->angle_to_deg - s->angle_from_deg >= 360)
        return s->angle_from_deg + 360;
    return s->angle_to_deg > 360 ? s->angle_to_deg - 360 : s->angle_to_deg;
}

static void section_table(sb *b, const sr_run *r)
{
    sb_put(b, "<section id=\"sections\"><h2>Missing sections</h2>\n");
    if (r->section_count == 0) {
        sb_put(b, "<p>No missing section was found: nothing to repair.</p></section>\n");
        return;
    }
    sb_put(b, "<table id=\"feature-table\"><thead><tr><th>#</th><th>class</th>"
              "<th>layers</th><th>z from (mm)</th><th>z to (mm)</th>"
              "<th>angular range (deg) / side</th><th>depth max (mm)</th>"
              "<th>depth mean (mm)</th><th>volume (mm³)</th><th>area (mm²)</th>"
              "<th>further features</th></tr></thead><tbody>\n");
    for (size_t i = 0; i < r->section_count; i++) {
        const sr_run_section *s = &r->sections[i];
        sb_printf(b, "<tr class=\"section\" id=\"section-%zu\"><td class=\"n\">%zu</td><td>",
                  s->index + 1, s->index + 1);
        sb_html(b, s->damage_class);
        sb_printf(b,
                  "</td><td class=\"n\">%zu–%zu</td><td class=\"n\">%.2f</td>"
                  "<td class=\"n\">%.2f</td><td>",
                  s->layer_first, s->layer_last, s->z_min_mm, s->z_max_mm);
        if (s->has_angles)
            sb_printf(b, "%.1f° to %.1f° (%.1f° arc)", s->angle_from_deg, arc_end(s),
                      s->angle_to_deg - s->angle_from_deg);
        else if (s->side)
            sb_printf(b, "side %+d of the plane", s->side);
        else
            sb_put(b, "-");
        sb_printf(b,
                  "</td><td class=\"n\">%.2f</td><td class=\"n\">%.2f</td>"
                  "<td class=\"n\">%.1f</td><td class=\"n\">%.1f</td><td>",
                  s->depth_max_mm, s->depth_mean_mm, s->volume_mm3, s->area_mm2);
        rp_feature_cell(b, s->features_json);
        sb_put(b, "</td></tr>\n");
    }
    sb_put(b, "</tbody></table></section>\n");
}

static void advice_table(sb *b, const sr_run *r)
{
    sb_put(b, "<section id=\"advice\"><h2>Advice</h2>\n");
    if (r->advice_count == 0) {
        sb_put(b, "<p>No advice was recorded with this run.</p></section>\n");
        return;
    }
    sb_put(b, "<table id=\"advice-table\"><thead><tr><th>section</th><th>process</th>"
              "<th>rule</th><th>reason</th><th>parameters and rules fired</th></tr></thead>"
              "<tbody>\n");
    for (size_t i = 0; i < r->advice_count; i++) {
        const sr_run_advice *a = &r->advice[i];
        sb_put(b, "<tr class=\"advice\"><td>");
        if (a->section_index >= 0)
            sb_printf(b, "%ld", a->section_index + 1);
        else
            sb_put(b, "whole part");
        sb_put(b, "</td><td>");
        sb_html(b, a->process);
        sb_put(b, "</td><td>");
        if (a->rule_name[0])
            sb_html(b, a->rule_name);
        else if (a->rule_id)
            sb_printf(b, "rule %lld (deleted)", (long long)a->rule_id);
        else
            sb_put(b, "built in");
        sb_put(b, "</td><td>");
        sb_html(b, a->reason);
        sb_put(b, "</td><td class=\"details\">");
        rp_advice_cell(b, a->details_json);
        sb_put(b, "</td></tr>\n");
    }
    sb_put(b, "</tbody></table></section>\n");
}

static void params_tables(sb *b, const sr_run *r)
{
    const sr_params *p = &r->params;
    char sym[64];
    sb_put(b, "<section id=\"parameters\"><h2>Parameters</h2>\n<table id=\"params-table\">\n");
    fact(b, "parameter set", p->name);
    fact(b, "symmetry", sym_text(&r->symmetry, sym, sizeof sym));
    fact(b, "method", r->method);
    sb_printf(b, "<tr><th>layers</th><td class=\"n\">%d</td></tr>\n", p->layers);
    sb_printf(b, "<tr><th>sectors</th><td class=\"n\">%d</td></tr>\n", p->sectors);
    sb_printf(b, "<tr><th>gamma_axis</th><td class=\"n\">%g</td></tr>\n", p->gamma_axis);
    sb_printf(b, "<tr><th>gamma_plane</th><td class=\"n\">%g</td></tr>\n", p->gamma_plane);
    sb_printf(b, "<tr><th>delta_d</th><td class=\"n\">%g</td></tr>\n", p->delta_d);
    sb_printf(b, "<tr><th>min depth (mm)</th><td class=\"n\">%g</td></tr>\n", p->min_depth_mm);
    sb_printf(b, "<tr><th>min volume (mm³)</th><td class=\"n\">%g</td></tr>\n",
              p->min_volume_mm3);
    sb_put(b, "</table></section>\n");

    sb_put(b, "<section id=\"alignment\"><h2>Alignment</h2>\n");
    if (r->has_alignment) {
        sb_printf(b, "<p>Scan to aligned frame, 3×4 (rotation | translation in mm), %s.</p>\n",
                  r->alignment_given ? "given by the user" : "found by search");
        sb_put(b, "<table id=\"alignment-table\">\n");
        for (int i = 0; i < 3; i++) {
            sb_put(b, "<tr>");
            for (int j = 0; j < 4; j++)
                sb_printf(b, "<td class=\"n\">%.6f</td>", r->alignment[4 * i + j]);
            sb_put(b, "</tr>\n");
        }
        sb_put(b, "</table>\n");
    } else {
        sb_put(b, "<p>The run did not reach the alignment.</p>\n");
    }
    if (r->fit_quality >= 0)
        sb_printf(b, "<p>Fit quality: %.3f (fraction of layers found symmetric).</p>\n",
                  r->fit_quality);
    sb_put(b, "</section>\n");

    sb_put(b, "<section id=\"timings\"><h2>Timings (s)</h2>\n");
    if (!r->timings_json) {
        sb_put(b, "<p>No timings recorded.</p>\n");
    } else {
        sb_put(b, "<table id=\"timings-table\">\n");
        size_t mark = b->len;
        if (!timing_rows(b, r->timings_json)) {
            b->len = mark;
            if (b->p)
                b->p[mark] = '\0';
            sb_put(b, "<tr><td><code>");
            sb_html(b, r->timings_json);
            sb_put(b, "</code></td></tr>\n");
        }
        sb_put(b, "</table>\n");
    }
    sb_put(b, "</section>\n");
}

/* ---- the page ---- */

sr_status sr_report_html(const sr_run *run, const sr_report_opts *opts, char **out,
                         size_t *out_len, sr_report_info *info, sr_err *err)
{
    size_t budget = opts && opts->max_triangles ? opts->max_triangles : DEFAULT_BUDGET;

    /* display meshes: the restored part, the patches, then the scan when given */
    const sr_mesh *scan = opts && opts->scan && opts->scan->tri_count ? opts->scan : NULL;
    size_t stored = run->restored.tri_count;
    for (size_t i = 0; i < run->section_count; i++)
        stored += run->sections[i].patch.tri_count;
    size_t nm = run->section_count + 2;
    sr_mesh *shown = calloc(nm, sizeof *shown);
    if (!shown)
        return sr_err_set(err, SR_E_NOMEM, "out of memory building the report");
    sr_status st = SR_OK;
    size_t tri_shown = 0;
    bool decimated = false;
    for (size_t i = 0; i < nm && st == SR_OK; i++) {
        const sr_mesh *m = i == 0       ? &run->restored
                           : i < nm - 1 ? &run->sections[i - 1].patch
                                        : scan;
        if (!m || m->tri_count == 0)
            continue;
        /* the run's meshes share the budget; the scan, hidden at first, gets a quarter
         * of it on top, so showing it costs the restored part no detail */
        size_t cap = m == scan ? (m->tri_count < budget / 4 ? m->tri_count : budget / 4)
                     : stored <= budget
                         ? m->tri_count
                         : (size_t)((double)budget * (double)m->tri_count / (double)stored);
        if (cap < 64)
            cap = m->tri_count < 64 ? m->tri_count : 64;
        st = sr_report_decimate(m, cap, &shown[i], err);
        if (st == SR_OK && i < nm - 1) {
            tri_shown += shown[i].tri_count;
            decimated |= shown[i].tri_count < m->tri_count;
        }
    }
    report_plan *plans = NULL;
    if (st == SR_OK) {
        sr_plan_opts defaults;
        sr_plan_opts_init(&defaults);
        st = rp_plans_build(run, opts && opts->plan ? opts->plan : &defaults, &plans, err);
    }
    if (st != SR_OK) {
        for (size_t i = 0; i < nm; i++)
            sr_mesh_release(&shown[i]);
        free(shown);
        return st;
    }

    sb b = {0};
    char sym[64], title[256];
    snprintf(title, sizeof title, "symrec report: run %lld, part %s", (long long)run->id,
             run->part_number);
    sb_put(&b, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
               "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
               "<title>");
    sb_html(&b, title);
    sb_put(&b, "</title>\n<style>");
    sb_put(&b, sr_report_css);
    sb_put(&b, "</style>\n</head>\n<body>\n<header>\n<h1>");
    sb_html(&b, title);
    sb_printf(&b, "</h1>\n<p>Status: <strong class=\"%s\">%s</strong>", run->ok ? "ok" : "failed",
              run->ok ? "ok" : "failed");
    if (!run->ok) {
        sb_put(&b, ": ");
        sb_html(&b, run->error);
    }
    sb_put(&b, "</p>\n</header>\n");

    /* the run's facts */
    sb_put(&b, "<section id=\"run\"><h2>Run</h2>\n<table id=\"run-table\">\n");
    char num[64];
    snprintf(num, sizeof num, "%lld", (long long)run->id);
    fact(&b, "run", num);
    fact(&b, "part", run->part_number);
    if (opts && opts->part_name)
        fact(&b, "part name", opts->part_name);
    if (opts && opts->material)
        fact(&b, "material", opts->material);
    snprintf(num, sizeof num, "%lld", (long long)run->instance_id);
    fact(&b, "instance", num);
    if (opts && opts->serial)
        fact(&b, "serial", opts->serial);
    if (opts && opts->received)
        fact(&b, "received", opts->received);
    fact(&b, "symmetry", sym_text(&run->symmetry, sym, sizeof sym));
    fact(&b, "method", run->method);
    fact(&b, "started (UTC)", run->started_at);
    fact(&b, "finished (UTC)", run->finished_at);
    fact(&b, "symrec version", run->software_version);
    double total = 0;
    for (size_t i = 0; i < run->section_count; i++)
        total += run->sections[i].volume_mm3;
    snprintf(num, sizeof num, "%zu, %.1f mm³ missing in all", run->section_count, total);
    fact(&b, "missing sections", num);
    sb_put(&b, "</table></section>\n");

    /* 3D view (report_view.js) */
    sb_put(&b, "<section id=\"view3d\"><h2>Part and patches</h2>\n"
               "<p class=\"note\">The restored part (grey) with the patches that fill the "
               "missing sections (orange)");
    if (scan)
        sb_put(&b, " and the scan as received (blue, hidden at first)");
    sb_put(&b, ", in the scan frame, seen from outside the part looking at the largest "
               "missing section.<span class=\"controls\"> Drag to rotate, shift-drag or "
               "right-drag to pan, wheel to zoom.</span></p>\n<p class=\"controls\"><label><input "
               "type=\"checkbox\" "
               "id=\"show-part\" checked> restored part</label> <label><input "
               "type=\"checkbox\" id=\"show-patches\" checked> patches</label>");
    if (scan)
        sb_put(&b, " <label><input type=\"checkbox\" id=\"show-scan\"> scan</label>");
    sb_put(&b, " <button type=\"button\" id=\"reset-view\">view the damage</button></p>\n"
               "<div id=\"view-box\"><canvas id=\"view\" width=\"720\" height=\"480\">"
               "</canvas><p id=\"view-fallback\" hidden>The 3D view needs WebGL, which this "
               "browser does not offer: the tables and the outlines below are complete "
               "without it.</p></div>\n"
               "<p class=\"note\" id=\"view-note\">");
    if (stored == 0)
        sb_put(&b, "No meshes were stored with this run (or they were not read).");
    else if (decimated)
        sb_printf(&b, "Shown with %zu of the %zu stored triangles: meshes over the display "
                      "budget of %zu triangles were decimated by vertex clustering for this "
                      "view. All figures in the tables are from the stored meshes.",
                  tri_shown, stored, budget);
    else
        sb_printf(&b, "All %zu stored triangles shown.", stored);
    sb_put(&b, "</p>\n</section>\n");

    /* outlines */
    sb_put(&b, "<section id=\"layers\"><h2>Per-layer outlines</h2>\n");
    if (run->layer_count && run->sectors) {
        sb_put(&b, "<p class=\"note\">Damaged outline <span class=\"key\" "
                   "style=\"border-color:#b3261e\"></span> and restored outline <span "
                   "class=\"key\" style=\"border-color:#1f5fbf;border-top-style:dashed\">"
                   "</span> of one layer, in the aligned frame (mm); in a layer with a build "
                   "plan, the missing region<span class=\"swatch\"></span>, the deposit "
                   "region (allowance added) <span class=\"key\" style=\"border-color:"
                   "#8a5a00;border-top-style:dotted\"></span> and the deposition paths: "
                   "contour rings <span class=\"key\" style=\"border-color:#0b7a3e\">"
                   "</span> and raster <span class=\"key\" style=\"border-color:#6a1b9a\">"
                   "</span>.</p>\n"
                   "<p><label>Layer <select id=\"layer-select\">");
        size_t first = run->section_count ? run->sections[0].layer_first : 0;
        if (first >= run->layer_count)
            first = 0;
        for (size_t l = 0; l < run->layer_count; l++) {
            int in = 0;
            for (size_t s = 0; s < run->section_count; s++)
                if (l >= run->sections[s].layer_first && l <= run->sections[s].layer_last) {
                    in = (int)run->sections[s].index + 1;
                    break;
                }
            sb_printf(&b, "<option value=\"%zu\"%s>%zu, z %.2f mm", l, l == first ? " selected" : "",
                      l, run->layer_z[l]);
            if (in)
                sb_printf(&b, " (section %d)", in);
            sb_put(&b, "</option>");
        }
        sb_put(&b, "</select></label> <label><input type=\"checkbox\" id=\"plot-zoom\" "
                   "checked> zoom to the build plan</label></p>\n");
    } else {
        sb_put(&b, "<p class=\"note\">No per-layer outlines were stored with this run (or "
                   "they were not read).</p>\n");
    }
    sb_put(&b, "<div id=\"layer-plot\"></div>\n</section>\n");

    rp_plan_table(&b, run, plans);
    section_table(&b, run);
    rp_nominal_section(&b, run);
    rp_inspection_section(&b, opts ? opts->inspection : NULL);
    advice_table(&b, run);
    params_tables(&b, run);

    /* data */
    sb_printf(&b, "<footer class=\"note\"><p>Written by symrec %s from the catalogue's "
                  "record of run %lld.</p></footer>\n",
              run->software_version[0] ? run->software_version : "", (long long)run->id);
    sb_put(&b, "<script type=\"application/json\" id=\"report-data\">{\"run\":");
    sb_printf(&b, "%lld,\"part\":", (long long)run->id);
    sb_jstr(&b, run->part_number);
    sb_put(&b, ",\"restored\":");
    if (shown[0].tri_count)
        rp_put_mesh(&b, &shown[0]);
    else
        sb_put(&b, "null");
    sb_put(&b, ",\"scan\":");
    if (shown[nm - 1].tri_count)
        rp_put_mesh(&b, &shown[nm - 1]);
    else
        sb_put(&b, "null");
    sb_put(&b, ",\"patches\":[");
    bool first_patch = true;
    for (size_t i = 1; i + 1 < nm; i++) {
        if (!shown[i].tri_count)
            continue;
        sb_printf(&b, "%s{\"section\":%zu,\"volume_mm3\":", first_patch ? "" : ",",
                  run->sections[i - 1].index + 1);
        sb_jnum(&b, run->sections[i - 1].volume_mm3, "%.6g");
        sb_put(&b, ",\"mesh\":");
        rp_put_mesh(&b, &shown[i]);
        sb_put(&b, "}");
        first_patch = false;
    }
    /* scan -> aligned frame: the view takes the part's axis (aligned z) as up */
    sb_put(&b, "],\"alignment\":");
    if (run->has_alignment) {
        sb_put(&b, "[");
        for (int i = 0; i < 12; i++) {
            if (i)
                sb_put(&b, ",");
            sb_jnum(&b, run->alignment[i], "%.9g");
        }
        sb_put(&b, "]");
    } else {
        sb_put(&b, "null");
    }
    rp_put_layers(&b, run);
    /* the stored texts behind the feature and advice cells, for scripts */
    sb_put(&b, ",\"sections\":[");
    for (size_t i = 0; i < run->section_count; i++) {
        sb_printf(&b, "%s{\"section\":%zu,\"features\":", i ? "," : "", run->sections[i].index + 1);
        rp_put_json(&b, run->sections[i].features_json);
        sb_put(&b, "}");
    }
    sb_put(&b, "],\"advice\":[");
    for (size_t i = 0; i < run->advice_count; i++) {
        const sr_run_advice *a = &run->advice[i];
        sb_put(&b, i ? ",{\"section\":" : "{\"section\":");
        if (a->section_index >= 0)
            sb_printf(&b, "%ld", a->section_index + 1);
        else
            sb_put(&b, "null");
        sb_put(&b, ",\"process\":");
        sb_jstr(&b, a->process);
        sb_put(&b, ",\"details\":");
        rp_put_json(&b, a->details_json);
        sb_put(&b, "}");
    }
    sb_put(&b, "]");
    rp_put_plans(&b, run, plans);
    rp_put_inspection(&b, opts ? opts->inspection : NULL);
    sb_put(&b, "}</script>\n<script id=\"three-js\">\n");
    sb_put(&b, sr_report_three_js);
    sb_put(&b, "\n</script>\n<script>\n");
    sb_put(&b, sr_report_view_js);
    sb_put(&b, sr_report_js);
    sb_put(&b, "</script>\n</body>\n</html>\n");

    for (size_t i = 0; i < nm; i++)
        sr_mesh_release(&shown[i]);
    free(shown);
    size_t plan_sections = 0, plan_layers = 0, replace_sections = 0;
    for (size_t i = 0; plans && i < run->section_count; i++) {
        plan_sections += plans[i].built;
        plan_layers += plans[i].built ? plans[i].plan.layer_count : 0;
        replace_sections += plans[i].replace;
    }
    rp_plans_release(plans, run->section_count);
    if (b.failed || !b.p) {
        free(b.p);
        return sr_err_set(err, SR_E_NOMEM, "out of memory building the report");
    }
    if (info) {
        info->tri_stored = stored;
        info->tri_shown = tri_shown;
        info->decimated = decimated;
        info->plan_sections = plan_sections;
        info->plan_layers = plan_layers;
        info->replace_sections = replace_sections;
    }
    *out = b.p;
    *out_len = b.len;
    return SR_OK;
}
