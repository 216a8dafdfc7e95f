/*
 * nominal_out.c: the nominal's second opinion on a run in the CLI: the step of
 * `reconstruct` that loads the part's intact mesh and runs src/nominal.h (and, with
 * --reference nominal, makes it the restoration), and the printing of the record
 * (run.h's sr_run_nominal), the same for `reconstruct` and `run show`: as text (a
 * table "symmetry vs nominal" per section) and as JSON.
 */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "json_out.h"
#include "nominal.h"
#include "reconstruct.h"
#include "run/run_build.h"

int cli_nominal_step(sr_catalog *cat, int64_t part_id, const sr_mesh *scan,
                     struct sr_recon_result *r, double min_volume_mm3, bool skip,
                     bool reference_nominal, sr_run_nominal **out, sr_mesh *patches, char *why,
                     size_t why_size)
{
    *out = NULL;
    sr_err err;
    sr_err_clear(&err);
    if (skip) {
        snprintf(why, why_size, "--no-nominal");
        return CLI_OK;
    }
    if (part_id <= 0 || !cat) {
        snprintf(why, why_size, "a mesh file has no part");
        return CLI_OK;
    }
    sr_mesh intact;
    sr_mesh_init(&intact);
    sr_status st = sr_catalog_part_mesh(cat, part_id, &intact, &err);
    if (st == SR_E_NOTFOUND) {
        snprintf(why, why_size, "the part has no intact mesh in the catalogue");
        if (!reference_nominal)
            return CLI_OK;
        fprintf(stderr, "symrec: error: --reference nominal: %s\n", why);
        return CLI_FAIL;
    }
    if (st != SR_OK)
        return cli_fail(st, &err);
    sr_nominal_opts o = {0};
    o.min_volume_mm3 = min_volume_mm3;
    o.alignment = &r->alignment;
    o.order = r->order;
    o.exact_pieces = reference_nominal; /* the patch is the pieces' meshes */
    sr_nominal_result nr;
    st = sr_nominal_compare(scan, &intact, r->sections, r->section_count, &o, &nr, &err);
    sr_mesh_release(&intact);
    if (st != SR_OK) {
        snprintf(why, why_size, "the comparison failed: %s",
                 err.msg[0] ? err.msg : sr_status_str(st));
        if (!reference_nominal)
            return CLI_OK;
        fprintf(stderr, "symrec: error: --reference nominal: %s\n", why);
        return CLI_FAIL;
    }
    if (reference_nominal && (nr.poor || nr.by_cells)) {
        if (nr.poor)
            fprintf(stderr, "symrec: error: --reference nominal: %s\n", nr.note);
        else
            fprintf(stderr,
                    "symrec: error: --reference nominal: the exact difference refused the scan "
                    "(%s), so the nominal's missing material was measured by cells and has no "
                    "patch mesh\n",
                    nr.exact_note);
        sr_nominal_result_release(&nr);
        return CLI_FAIL;
    }
    st = sr_run_nominal_from(&nr, reference_nominal ? "nominal" : "symmetry", out, &err);
    if (st == SR_OK && reference_nominal) {
        sr_mesh t = r->restored;
        r->restored = nr.registered;
        nr.registered = t;
        r->restored_volume_mm3 = sr_mesh_volume(&r->restored);
        r->restored_by_union = 1;
        r->patch_volume_mm3 = nr.nominal_mm3;
        *patches = nr.missing;
        sr_mesh_init(&nr.missing);
    }
    sr_nominal_result_release(&nr);
    if (st != SR_OK)
        return cli_fail(st, &err);
    return CLI_OK;
}

void cli_nominal_print(const sr_run_nominal *n, const char *why_none)
{
    if (!n) {
        printf("  nominal:    no nominal (%s)\n", why_none ? why_none : "none recorded");
        return;
    }
    printf("  nominal:    the part's intact mesh registered to the scan: %.1f %% within %.3f mm "
           "(RMS %.4f mm); reference %s\n",
           100.0 * n->coverage, n->tol_mm, n->rms_mm, n->reference);
    printf("              missing by the nominal %.1f mm³, by the symmetry %.1f mm³: "
           "disagreement %+.1f mm³ (%+.1f %%)\n",
           n->nominal_mm3, n->symmetry_mm3, n->diff_mm3, n->diff_pct);
    printf("              %zu sliver(s) thinner than %.3f mm dropped (%.1f mm³); scan outside "
           "the nominal %.1f mm³ (limit %.1f); %.2f s\n",
           n->slivers, n->sliver_mm, n->sliver_mm3, n->extra_mm3, n->extra_limit_mm3, n->seconds);
    char how[320];
    sr_run_nominal_method_text(n, how, sizeof how);
    printf("              measured %s\n", how);
    if (n->poor)
        printf("  NOMINAL POOR: %s\n", n->note);
    if (n->section_count) {
        printf("  symmetry vs nominal: section, symmetry mm³, nominal mm³, disagreement mm³ "
               "and %%, deviation of the patch from the nominal mean / max mm\n");
        for (size_t i = 0; i < n->section_count; i++) {
            const sr_run_nominal_section *s = &n->sections[i];
            printf("  %2zu. %10.1f %10.1f %+10.1f %+7.1f %%", s->index + 1, s->symmetry_mm3,
                   s->nominal_mm3, s->diff_mm3, s->diff_pct);
            if (s->pieces)
                printf("   %.3f / %.3f\n", s->dev_mean_mm, s->dev_max_mm);
            else
                printf("   only the symmetry sees it\n");
        }
    }
    for (size_t i = 0; i < n->piece_count; i++) {
        const sr_run_nominal_piece *p = &n->pieces[i];
        if (p->outside_mm3 < n->min_volume_mm3)
            continue;
        printf("  only the nominal sees: %.1f mm³ around (%.1f, %.1f, %.1f) mm (scan frame), "
               "near no section's patch\n",
               p->outside_mm3, p->centroid[0], p->centroid[1], p->centroid[2]);
    }
}

void json_run_nominal(json_out *j, const sr_run_nominal *n)
{
    if (!n) {
        json_null(j);
        return;
    }
    json_object_begin(j);
    json_key(j, "reference");
    json_string(j, n->reference);
    json_key(j, "transform");
    json_array_begin(j);
    for (int i = 0; i < 12; i++)
        json_number(j, n->transform[i]);
    json_array_end(j);
    json_key(j, "coverage");
    json_number(j, n->coverage);
    json_key(j, "rms_mm");
    json_number(j, n->rms_mm);
    json_key(j, "tol_mm");
    json_number(j, n->tol_mm);
    json_key(j, "nominal_mm3");
    json_number(j, n->nominal_mm3);
    json_key(j, "symmetry_mm3");
    json_number(j, n->symmetry_mm3);
    json_key(j, "diff_mm3");
    json_number(j, n->diff_mm3);
    json_key(j, "diff_pct");
    json_number(j, n->diff_pct);
    json_key(j, "sliver_mm");
    json_number(j, n->sliver_mm);
    json_key(j, "slivers");
    json_int(j, (int64_t)n->slivers);
    json_key(j, "sliver_mm3");
    json_number(j, n->sliver_mm3);
    json_key(j, "min_volume_mm3");
    json_number(j, n->min_volume_mm3);
    json_key(j, "scan_outside_mm3");
    json_number(j, n->extra_mm3);
    json_key(j, "scan_outside_limit_mm3");
    json_number(j, n->extra_limit_mm3);
    json_key(j, "poor");
    json_bool(j, n->poor);
    json_key(j, "note");
    json_string(j, n->note);
    json_key(j, "seconds");
    json_number(j, n->seconds);
    json_key(j, "method");
    if (n->method[0])
        json_string(j, n->method);
    else
        json_null(j);
    json_key(j, "cell_mm");
    if (strcmp(n->method, "cells") == 0)
        json_number(j, n->cell_mm);
    else
        json_null(j);
    json_key(j, "exact_note");
    json_string(j, n->exact_note);
    json_key(j, "sections");
    json_array_begin(j);
    for (size_t i = 0; i < n->section_count; i++) {
        const sr_run_nominal_section *s = &n->sections[i];
        json_object_begin(j);
        json_key(j, "index");
        json_int(j, (int64_t)s->index + 1);
        json_key(j, "symmetry_mm3");
        json_number(j, s->symmetry_mm3);
        json_key(j, "nominal_mm3");
        json_number(j, s->nominal_mm3);
        json_key(j, "diff_mm3");
        json_number(j, s->diff_mm3);
        json_key(j, "diff_pct");
        json_number(j, s->diff_pct);
        json_key(j, "pieces");
        json_int(j, (int64_t)s->pieces);
        json_key(j, "deviation_mean_mm");
        if (s->pieces)
            json_number(j, s->dev_mean_mm);
        else
            json_null(j);
        json_key(j, "deviation_max_mm");
        if (s->pieces)
            json_number(j, s->dev_max_mm);
        else
            json_null(j);
        json_object_end(j);
    }
    json_array_end(j);
    json_key(j, "pieces");
    json_array_begin(j);
    for (size_t i = 0; i < n->piece_count; i++) {
        const sr_run_nominal_piece *p = &n->pieces[i];
        json_object_begin(j);
        json_key(j, "volume_mm3");
        json_number(j, p->volume_mm3);
        json_key(j, "thickness_mm");
        json_number(j, p->thickness_mm);
        json_key(j, "section");
        if (p->section >= 0)
            json_int(j, (int64_t)p->section + 1);
        else
            json_null(j);
        json_key(j, "only_nominal_mm3");
        json_number(j, p->outside_mm3);
        json_key(j, "centroid_mm");
        json_array_begin(j);
        for (int k = 0; k < 3; k++)
            json_number(j, p->centroid[k]);
        json_array_end(j);
        json_object_end(j);
    }
    json_array_end(j);
    json_object_end(j);
}
