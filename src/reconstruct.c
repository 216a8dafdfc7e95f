/*
 * reconstruct.c: the reconstruction pipeline for one scan (see reconstruct.h).
 */
#include "reconstruct.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bridge/boolean.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
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

/* restored = aligned scan ∪ every patch (aligned frame), or concatenation on failure. */
static sr_status unite(const sr_mesh *aligned, sr_recon_result *r, sr_err *err)
{
    sr_mesh acc;
    sr_status st = sr_mesh_copy(&acc, aligned);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory copying the scan");
    r->restored_by_union = 1;
    for (size_t i = 0; i < r->section_count; i++) {
        sr_mesh next;
        sr_err uerr = {{0}};
        if (r->restored_by_union &&
            sr_boolean_union(&acc, &r->sections[i].patch, &next, &uerr) == SR_OK) {
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
    sr_analyse_opts an = {sym, opts->gamma_axis, opts->gamma_plane, opts->min_depth_mm, 1};
    st = sr_analyse(&r.grid, &an, &r.analysis, err);
    if (st != SR_OK)
        goto fail;
    r.timings.analyse_s = now_s() - t;
    t = now_s();

    st = sr_patch_build(&r.grid, &r.analysis, &r.sections, &r.section_count, err);
    if (st != SR_OK)
        goto fail;
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
