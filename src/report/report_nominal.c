/*
 * report_nominal.c: the report's "symmetry vs nominal" section: the part's intact
 * mesh as a second opinion on the run (run.h's sr_run_nominal, src/nominal.h): the
 * registration, the totals, the flag when the nominal does not fit the scan, one row
 * per symmetry section (both volumes, the disagreement, the deviation of the patch
 * from the nominal) and what only the nominal sees. Nothing when the run has none, so
 * a run without it reports as before.
 */
#include "report/report_int.h"

void rp_nominal_section(sb *b, const sr_run *r)
{
    const sr_run_nominal *n = r->nominal;
    if (!n)
        return;
    sb_put(b, "<section id=\"nominal\"><h2>Symmetry vs nominal</h2>\n");
    sb_printf(b,
              "<p>The part's intact mesh registered to the scan: %.1f %% within %.3f mm "
              "(RMS %.4f mm). Missing by the nominal %.1f mm³, by the symmetry %.1f mm³: "
              "disagreement %+.1f mm³ (%+.1f %%). The restoration is the %s's.</p>\n",
              100.0 * n->coverage, n->tol_mm, n->rms_mm, n->nominal_mm3, n->symmetry_mm3,
              n->diff_mm3, n->diff_pct, n->reference[0] == 'n' ? "nominal" : "symmetry");
    char how[320];
    sr_run_nominal_method_text(n, how, sizeof how);
    sb_put(b, "<p>The nominal's missing material was measured ");
    sb_html(b, how);
    sb_put(b, ".</p>\n");
    if (n->poor) {
        sb_put(b, "<p class=\"warn\"><strong>");
        sb_html(b, n->note);
        sb_put(b, "</strong></p>\n");
    }
    if (n->section_count) {
        sb_put(b, "<table id=\"nominal-table\"><thead><tr><th>#</th><th>symmetry (mm³)</th>"
                  "<th>nominal (mm³)</th><th>disagreement (mm³)</th><th>disagreement (%)</th>"
                  "<th>deviation of the patch mean / max (mm)</th></tr></thead><tbody>\n");
        for (size_t i = 0; i < n->section_count; i++) {
            const sr_run_nominal_section *s = &n->sections[i];
            sb_printf(b,
                      "<tr><td class=\"n\">%zu</td><td class=\"n\">%.1f</td>"
                      "<td class=\"n\">%.1f</td><td class=\"n\">%+.1f</td>"
                      "<td class=\"n\">%+.1f</td><td>",
                      s->index + 1, s->symmetry_mm3, s->nominal_mm3, s->diff_mm3, s->diff_pct);
            if (s->pieces)
                sb_printf(b, "%.3f / %.3f", s->dev_mean_mm, s->dev_max_mm);
            else
                sb_put(b, "only the symmetry sees it");
            sb_put(b, "</td></tr>\n");
        }
        sb_put(b, "</tbody></table>\n");
    }
    for (size_t i = 0; i < n->piece_count; i++) {
        const sr_run_nominal_piece *p = &n->pieces[i];
        if (p->outside_mm3 >= n->min_volume_mm3)
            sb_printf(b,
                      "<p>Only the nominal sees %.1f mm³ around (%.1f, %.1f, %.1f) mm (scan "
                      "frame), near no section.</p>\n",
                      p->outside_mm3, p->centroid[0], p->centroid[1], p->centroid[2]);
    }
    sb_put(b, "</section>\n");
}
