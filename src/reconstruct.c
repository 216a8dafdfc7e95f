/*
 * reconstruct.c: the reconstruction pipeline for one scan (see reconstruct.h).
 */
#include "reconstruct.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bridge/boolean.h"
#include "region_sections.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *sr_recon_method_name(sr_recon_method m)
{
    return m == SR_METHOD_PAPER ? "paper" : "robust";
}

sr_status sr_recon_method_parse(const char *text, const char *field, sr_recon_method *out,
                                sr_err *err)
{
    if (text && strcmp(text, "robust") == 0)
        *out = SR_METHOD_ROBUST;
    else if (text && strcmp(text, "paper") == 0)
        *out = SR_METHOD_PAPER;
    else
        return sr_err_set(err, SR_E_RANGE, "bad %s '%s': expected robust or paper", field,
                          text ? text : "");
    return SR_OK;
}

void sr_recon_result_release(sr_recon_result *r)
{
    if (!r)
        return;
    sr_layer_grid_release(&r->grid);
    sr_analysis_release(&r->analysis);
    sr_sections_release(r->sections, r->section_count);
    sr_mesh_release(&r->restored);
    memset(r, 0, sizeof *r);
}

/* restored = aligned scan ∪ every patch (aligned frame). A union refused as invalid is
 * retried once after sr_mesh_repair of both (zero-area triangles removed); if it still
 * fails (e.g. a noisy scan crossing itself where the patch goes), the patches are
 * concatenated and union_note says why. */
static sr_status unite(const sr_mesh *aligned, sr_recon_result *r, sr_err *err)
{
    sr_mesh acc;
    sr_status st = sr_mesh_copy(&acc, aligned);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory copying the scan");
    r->restored_by_union = 1;
    int scan_repaired = 0;
    for (size_t i = 0; i < r->section_count; i++) {
        sr_mesh next = {0};
        sr_err uerr = {{0}};
        sr_status us = SR_E_INVALID;
        if (r->restored_by_union) {
            us = sr_boolean_union(&acc, &r->sections[i].patch, &next, &uerr);
            if (us == SR_E_INVALID) {
                sr_repair_report ra = {0}, rb = {0};
                sr_mesh patch = {0};
                sr_err rerr = {{0}};
                if (sr_mesh_copy(&patch, &r->sections[i].patch) == SR_OK &&
                    sr_mesh_repair(&acc, 1, &ra, &rerr) == SR_OK &&
                    sr_mesh_repair(&patch, 0, &rb, &rerr) == SR_OK && (ra.changed || rb.changed)) {
                    if (ra.changed && !scan_repaired) {
                        scan_repaired = 1;
                        snprintf(r->repair_note, sizeof r->repair_note,
                                 "scan repaired for the union: %zu zero-area triangles removed",
                                 ra.degenerate_removed);
                    }
                    us = sr_boolean_union(&acc, &patch, &next, &uerr);
                }
                sr_mesh_release(&patch);
            }
        }
        if (us == SR_OK) {
            sr_mesh_release(&acc);
            acc = next;
            continue;
        }
        if (r->restored_by_union)
            snprintf(r->union_note, sizeof r->union_note, "section %zu: %s", i + 1, uerr.msg);
        r->restored_by_union = 0;
        st = sr_mesh_append(&acc, &r->sections[i].patch);
        if (st != SR_OK) {
            sr_mesh_release(&acc);
            return sr_err_set(err, st, "out of memory joining patches");
        }
    }
    r->restored = acc;
    return SR_OK;
}

sr_status sr_reconstruct(const sr_mesh *scan, const sr_recon_opts *opts, sr_recon_result *out,
                         sr_err *err)
{
    sr_status st = sr_mesh_validate(scan, "scan", NULL, err);
    if (st != SR_OK)
        return st;
    st = sr_symmetry_check(&opts->symmetry, err);
    if (st != SR_OK)
        return st;
    sr_recon_result r;
    memset(&r, 0, sizeof r);
    sr_mesh aligned = {0};
    double t0 = now_s(), t = t0;

    if (opts->have_alignment) {
        r.alignment = opts->alignment;
    } else {
        sr_align_opts ao = {0};
        ao.delta_d = opts->delta_d;
        st = sr_align(scan, &opts->symmetry, &ao, &r.alignment, err);
        if (st != SR_OK)
            goto fail;
    }
    st = sr_mesh_copy(&aligned, scan);
    if (st != SR_OK) {
        sr_err_set(err, st, "out of memory copying the scan");
        goto fail;
    }
    sr_mesh_transform(&aligned, r.alignment.xform);
    r.timings.align_s = now_s() - t;
    t = now_s();

    sr_slice_opts so = {opts->layers ? opts->layers : 320, opts->sectors ? opts->sectors : 240,
                        0, 0};
    st = sr_slice_accurate(&aligned, &so, &r.grid, err);
    if (st != SR_OK)
        goto fail;
    r.timings.slice_s = now_s() - t;
    t = now_s();

    sr_symmetry sym = opts->symmetry;
    if (sym.kind == SR_SYM_GLIDE && sym.shift_mm == 0)
        sym.shift_mm = r.alignment.glide_shift_mm;
    r.method = opts->method;
    if (opts->method == SR_METHOD_PAPER) {
        sr_analyse_opts an = {sym, opts->gamma_axis, opts->gamma_plane, opts->min_depth_mm, 1};
        st = sr_analyse(&r.grid, &an, &r.analysis, err);
        if (st != SR_OK)
            goto fail;
        r.timings.analyse_s = now_s() - t;
        t = now_s();
        st = sr_patch_build(&r.grid, &r.analysis, &r.sections, &r.section_count, err);
        if (st != SR_OK)
            goto fail;
    } else {
        /* noise: the symmetry fit's RMS is about sqrt(2) sigma for independent noise on
         * a surface and its image; slivers up to 3 sigma each side are filtered */
        r.noise_mm = r.alignment.fit_rms_mm / sqrt(2.0);
        r.open_mm = opts->open_mm > 0 ? opts->open_mm : fmax(0.05, 3.0 * r.noise_mm);
        sr_region_opts ro = {sym, r.open_mm, opts->min_depth_mm,
                             opts->min_volume_mm3 > 0 ? opts->min_volume_mm3 : 1.0, 0};
        st = sr_region_reconstruct(&aligned, &r.grid, &ro, &r.analysis, &r.sections,
                                   &r.section_count, err);
        if (st != SR_OK)
            goto fail;
        r.timings.analyse_s = now_s() - t;  /* contours, vote, sections and patches */
        t = now_s();
    }
    r.timings.patch_s = now_s() - t;
    t = now_s();

    if (opts->skip_union) {
        st = sr_mesh_copy(&r.restored, &aligned);
        for (size_t i = 0; st == SR_OK && i < r.section_count; i++)
            st = sr_mesh_append(&r.restored, &r.sections[i].patch);
        if (st != SR_OK) {
            sr_err_set(err, st, "out of memory joining patches");
            goto fail;
        }
        snprintf(r.union_note, sizeof r.union_note, "union skipped on request");
    } else {
        st = unite(&aligned, &r, err);
        if (st != SR_OK)
            goto fail;
    }
    r.timings.union_s = now_s() - t;

    /* back to the scan's frame */
    double inv[12];
    sr_xform_rigid_inverse(inv, r.alignment.xform);
    for (size_t i = 0; i < r.section_count; i++) {
        sr_mesh_transform(&r.sections[i].patch, inv);
        r.patch_volume_mm3 += r.sections[i].volume_mm3;
    }
    sr_mesh_transform(&r.restored, inv);
    r.scan_volume_mm3 = sr_mesh_volume(scan);
    r.restored_volume_mm3 = sr_mesh_volume(&r.restored);
    r.timings.total_s = now_s() - t0;
    sr_mesh_release(&aligned);
    *out = r;
    return SR_OK;
fail:
    sr_mesh_release(&aligned);
    sr_recon_result_release(&r);
    return st;
}
