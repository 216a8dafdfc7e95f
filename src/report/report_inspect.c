/*
 * report_inspect.c: the report's inspection section (report_int.h; issue 20): the
 * latest inspection of the run, its verdict and reasons, the scan after repair in 3D
 * coloured by its signed deviation from the restored model (report_view.js draws it),
 * the colour scale as a legend in mm with the tolerance band marked, and the figures of
 * each section. The scale is inspect.h's list of (deviation, colour) stops (the GLB's
 * vertex colours use it too), written both into the legend's CSS gradient here and
 * into the data block for the script, so the picture and its legend cannot disagree.
 */
#include "report/report_int.h"

#include <math.h>
#include <stdio.h>

#define NSTOPS SR_INSPECT_SCALE_STOPS

/* The stops in mm, left to right, and their colours as CSS (inspect.h's scale). */
static void stops(const sr_report_inspection *ins, double at[NSTOPS], char col[NSTOPS][8])
{
    unsigned c[NSTOPS];
    sr_inspect_scale(ins->tolerance_mm, ins->allowance_mm, at, c);
    for (int i = 0; i < NSTOPS; i++)
        snprintf(col[i], sizeof col[i], "#%06x", c[i] & 0xffffffu);
}

double rp_inspection_range(const sr_report_inspection *ins)
{
    return sr_inspect_scale_range(ins->tolerance_mm, ins->allowance_mm);
}

static double percent(double v, double r)
{
    return 50.0 + 50.0 * v / r;
}

static void legend(sb *b, const sr_report_inspection *ins)
{
    double at[NSTOPS], r = rp_inspection_range(ins), t = ins->tolerance_mm;
    char col[NSTOPS][8];
    stops(ins, at, col);
    sb_put(b, "<div id=\"inspect-scale\" class=\"scale\"><div class=\"scale-bar\" "
              "style=\"background:linear-gradient(to right");
    for (int i = 0; i < NSTOPS; i++)
        sb_printf(b, ",%s %.2f%%", col[i], percent(at[i], r));
    sb_printf(b,
              ")\"><div id=\"inspect-band\" class=\"scale-band\" style=\"left:%.2f%%;"
              "width:%.2f%%\" title=\"tolerance band\"></div></div>\n"
              "<div class=\"scale-ticks\">",
              percent(-t, r), percent(t, r) - percent(-t, r));
    const double ticks[] = {-r, -t, 0, t, r};
    for (int i = 0; i < 5; i++)
        sb_printf(b, "<span class=\"tick\" style=\"left:%.2f%%\">%+.2f</span>",
                  percent(ticks[i], r), ticks[i]);
    sb_printf(b,
              "</div><p class=\"note\">Signed deviation from the restored surface, mm: "
              "below it (material short, blue) to above it (stock, red); the tolerance "
              "band ±%.2f mm (green, framed) counts as on the surface; beyond ±%.2f mm "
              "the end colours. Allowance %.2f mm.</p></div>\n",
              t, r, ins->allowance_mm);
}

void rp_inspection_section(sb *b, const sr_report_inspection *ins)
{
    if (!ins)
        return;
    sb_put(b, "<section id=\"inspection\"><h2>Inspection after repair</h2>\n<p>");
    sb_printf(b, "Inspection %lld, ", ins->id);
    sb_html(b, ins->inspected_at);
    sb_put(b, " (UTC): <strong class=\"verdict-");
    sb_html(b, ins->verdict);
    sb_put(b, "\">");
    sb_html(b, ins->verdict);
    sb_put(b, "</strong>");
    if (ins->reasons && *ins->reasons) {
        sb_put(b, ": ");
        sb_html(b, ins->reasons);
    }
    sb_put(b, "</p>\n");
    if (ins->scan && ins->scan->tri_count && ins->deviation) {
        sb_printf(b,
                  "<p class=\"note\">The scan after repair (%zu triangles shown), in the "
                  "restored model's frame, coloured by its signed deviation.</p>\n"
                  "<div class=\"view-box\"><canvas id=\"inspect-view\" width=\"720\" "
                  "height=\"480\"></canvas></div>\n",
                  ins->scan->tri_count);
        legend(b, ins);
    } else {
        sb_put(b, "<p class=\"note\">The scan after repair was not kept with this "
                  "inspection: the figures only.</p>\n");
    }
    sb_put(b, "<table id=\"inspection-table\"><thead><tr><th>section</th><th>verdict</th>"
              "<th>under-fill (mm³)</th><th>under-fill depth (mm)</th>"
              "<th>over-build (mm³)</th><th>stock min (mm)</th><th>stock max (mm)</th>"
              "<th>deviation mean / RMS (mm)</th><th>reasons</th></tr></thead><tbody>\n");
    for (size_t i = 0; i < ins->section_count; i++) {
        const sr_inspect_section *s = &ins->sections[i];
        sb_printf(b, "<tr class=\"inspection\"><td class=\"n\">%zu</td><td>", s->index + 1);
        sb_html(b, sr_inspect_verdict_str(s->verdict));
        sb_printf(b,
                  "</td><td class=\"n\">%.1f</td><td class=\"n\">%.3f</td>"
                  "<td class=\"n\">%.1f</td><td class=\"n\">%.3f</td><td class=\"n\">%.3f</td>"
                  "<td class=\"n\">%+.3f / %.3f</td><td>",
                  s->underfill_mm3, s->underfill_depth_mm, s->overbuild_mm3, s->stock_min_mm,
                  s->stock_max_mm, s->dev_mean_mm, s->dev_rms_mm);
        sb_html(b, s->reasons[0] ? s->reasons : "-");
        sb_put(b, "</td></tr>\n");
    }
    sb_put(b, "</tbody></table></section>\n");
}

void rp_put_inspection(sb *b, const sr_report_inspection *ins)
{
    if (!ins)
        return;
    double at[NSTOPS];
    char col[NSTOPS][8];
    stops(ins, at, col);
    sb_printf(b, ",\"inspection\":{\"id\":%lld,\"verdict\":", ins->id);
    sb_jstr(b, ins->verdict);
    sb_put(b, ",\"tolerance_mm\":");
    sb_jnum(b, ins->tolerance_mm, "%.6g");
    sb_put(b, ",\"range_mm\":");
    sb_jnum(b, rp_inspection_range(ins), "%.6g");
    sb_put(b, ",\"stops\":[");
    for (int i = 0; i < NSTOPS; i++) {
        sb_put(b, i ? ",[" : "[");
        sb_jnum(b, at[i], "%.6g");
        sb_printf(b, ",\"%s\"]", col[i]);
    }
    sb_put(b, "],\"scan\":");
    if (ins->scan && ins->scan->tri_count && ins->deviation) {
        rp_put_mesh(b, ins->scan);
        sb_put(b, ",\"deviation\":\"");
        rp_put_floats(b, ins->deviation, ins->scan->vertex_count);
        sb_put(b, "\"");
    } else {
        sb_put(b, "null");
    }
    sb_put(b, "}");
}
