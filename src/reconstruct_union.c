/*
 * reconstruct_union.c: the restored part from the scan and the patches, for the
 * pipeline's driver (reconstruct.c; reconstruct_int.h): the scan united with every
 * patch (recon_unite; the image method's split union, whose patches are exactly what
 * it added, recon_unite_images), the patches as separate shells when a union is
 * refused or skipped (recon_concatenate), the patches' own crossings mended
 * (recon_mend_patches), the paper method's patches for the union
 * (recon_paper_union_patches), and what was repaired on the way (recon_note_repairs).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/boolean.h"
#include "bridge/mend.h"
#include "mesh/mesh_shells.h"
#include "reconstruct_int.h"

/* out = `scan` (or any mesh in its frame) followed by the patches (aligned frame,
 * mapped back by the inverse of xf; xf NULL: in the scan's frame already) as separate
 * shells, allocated once at its final size. */
sr_status recon_concatenate(const sr_mesh *scan, const double xf[12], const sr_section *secs,
                            size_t count, sr_mesh *out)
{
    size_t nv = scan->vertex_count, nt = scan->tri_count;
    for (size_t i = 0; i < count; i++) {
        nv += secs[i].patch.vertex_count;
        nt += secs[i].patch.tri_count;
    }
    sr_mesh m;
    sr_status st = sr_mesh_alloc(&m, nv, nt);
    if (st != SR_OK)
        return st;
    memcpy(m.xyz, scan->xyz, scan->vertex_count * 3 * sizeof(double));
    memcpy(m.tri, scan->tri, scan->tri_count * 3 * sizeof(uint32_t));
    double inv[12];
    if (xf)
        sr_xform_rigid_inverse(inv, xf);
    else
        sr_xform_identity(inv);
    size_t v0 = scan->vertex_count, t0 = scan->tri_count;
    for (size_t i = 0; i < count; i++) {
        const sr_mesh *p = &secs[i].patch;
        for (size_t v = 0; v < p->vertex_count; v++)
            sr_xform_apply(inv, p->xyz + 3 * v, m.xyz + 3 * (v0 + v));
        for (size_t k = 0; k < 3 * p->tri_count; k++)
            m.tri[3 * t0 + k] = p->tri[k] + (uint32_t)v0;
        v0 += p->vertex_count;
        t0 += p->tri_count;
    }
    *out = m;
    return SR_OK;
}

/* What was repaired in the scan for the unions and what the union left behind, as
 * repair_note. */
void recon_note_repairs(sr_recon_result *r, size_t degenerate, size_t mended,
                        size_t patch_mended, const sr_void_report *voids)
{
    char *p = r->repair_note;
    size_t room = sizeof r->repair_note;
    int n = 0;
    if (degenerate || mended)
        n = snprintf(p, room, "scan repaired for the union:");
    if (degenerate && n >= 0 && (size_t)n < room)
        n += snprintf(p + n, room - (size_t)n, " %zu zero-area triangles removed%s",
                      degenerate, mended ? "," : "");
    if (mended && n >= 0 && (size_t)n < room)
        n += snprintf(p + n, room - (size_t)n,
                      " %zu triangles replaced where it crossed itself", mended);
    if (patch_mended && n >= 0 && (size_t)n < room)
        n += snprintf(p + n, room - (size_t)n,
                      "%s%zu patch triangles replaced where a patch crossed itself",
                      n ? "; " : "", patch_mended);
    if (voids && voids->voids_dropped && n >= 0 && (size_t)n < room)
        n += snprintf(p + n, room - (size_t)n,
                      "%s%zu void(s) trapped between the patches and the scan filled "
                      "(%.4f mm3)",
                      n ? "; " : "", voids->voids_dropped, voids->void_volume_mm3);
}

/* Every reported patch free of crossings: a stacked patch is exact until it is rounded
 * to double, and near-coincident points of its walls can then cross (measured: the
 * posed bushing's 110,002-triangle patch, two zero-area triangles once mapped to
 * another frame, and refused by every boolean). Such a patch gets its zero-area
 * triangles removed (sr_mesh_repair) and its crossings undone (sr_image_uncross: moved
 * apart, else cut out and filled); it is replaced only when the result is closed,
 * crosses nowhere and holds the same volume. Returns the patch triangles replaced (at
 * least 1 for a patch whose vertices were only moved); a patch that cannot be mended
 * is left for recon_unite()'s retry. */
size_t recon_mend_patches(sr_section *sections, size_t count)
{
    size_t replaced = 0;
    for (size_t i = 0; i < count; i++) {
        int crosses = 0;
        if (sr_mesh_self_intersects(&sections[i].patch, &crosses, NULL) != SR_OK || !crosses)
            continue;
        sr_mesh p = {0};
        sr_repair_report rr = {0};
        /* a mend that changes what the patch holds is no mend (measured: a broken clamp
         * arm's patch mended from 1977 to 1046 mm^3) */
        if (sr_mesh_copy(&p, &sections[i].patch) == SR_OK &&
            sr_mesh_repair(&p, &rr, NULL) == SR_OK && sr_image_uncross(&p, 1e-3)) {
            size_t before = sections[i].patch.tri_count;
            sr_mesh_release(&sections[i].patch);
            sections[i].patch = p;
            replaced += before > p.tri_count ? before - p.tri_count : 1;
            continue;
        }
        sr_mesh_release(&p);
    }
    return replaced;
}

/* restored = scan ∪ every patch, in the scan's frame. The patches are in the aligned
 * frame (xf: scan -> aligned); each union is local (sr_boolean_union_local: only the
 * scan's triangles near the patch go through CGAL, mapped into the aligned frame, and
 * the scan's other vertices keep their coordinates); the first makes the restored mesh,
 * the next ones grow it in place, so the scan is never copied twice. Where the scan
 * crosses itself near a patch (a noisy scan folded over at the fracture's edges) its
 * neighbourhood is mended first (sr_boolean_union_local_mending). A union refused as
 * invalid is retried once after sr_mesh_repair of both (zero-area triangles removed)
 * and the patch's own crossings mended (sr_mesh_mend_crossings);
 * if it still fails (e.g. crossings that cannot be mended), that
 * patch and the ones after it are concatenated to what was united so far and
 * union_note says why. After the unions, voids of the restored part up to
 * max_void_mm3 are removed (sr_mesh_drop_voids). */
sr_status recon_unite(const sr_mesh *scan, const double xf[12], sr_recon_result *r,
                      const sr_mesh *upatches, double max_void_mm3, size_t patch_mended,
                      sr_err *err)
{
    sr_mesh acc = {0};
    int owned = 0; /* acc holds the restored mesh so far; until then it is the scan */
    int scan_repaired = 0;
    size_t mended = 0;     /* scan triangles replaced where the scan crossed itself */
    /* patch_mended: patch triangles replaced where a patch crossed itself (before:
     * mend_patches; here: the retry below) */
    size_t degenerate = 0; /* zero-area scan triangles removed */
    sr_status st;
    r->restored_by_union = 1;
    for (size_t i = 0; i < r->section_count; i++) {
        sr_err uerr = {{0}};
        const sr_mesh *up = upatches ? &upatches[i] : &r->sections[i].patch;
        sr_mesh next = {0};
        sr_local_union_info info;
        sr_status us = sr_boolean_union_local_mending(owned ? &acc : scan, NULL, xf, up, NULL,
                                                      0, owned ? &acc : &next, &info, &uerr);
        if (us == SR_OK)
            mended += info.mended_tris;
        if (us == SR_OK && !owned) {
            acc = next;
            owned = 1;
        }
        if (us == SR_E_INVALID) {
            sr_repair_report ra = {0}, rb = {0};
            sr_mesh patch = {0};
            sr_err rerr = {{0}};
            if (!owned) {
                st = sr_mesh_copy(&acc, scan);
                if (st != SR_OK)
                    return sr_err_set(err, st, "out of memory copying the scan");
                owned = 1;
            }
            sr_mend_report pm = {0};
            int ready = sr_mesh_copy(&patch, up) == SR_OK &&
                        sr_mesh_repair(&acc, &ra, &rerr) == SR_OK &&
                        sr_mesh_repair(&patch, &rb, &rerr) == SR_OK;
            /* a patch crossing itself (near-coincident points of its exact stack
             * rounded to double) is mended; a failed mend leaves it as it was */
            if (ready && sr_mesh_mend_crossings(&patch, NULL, &pm, NULL) != SR_OK)
                pm.removed_tris = 0;
            if (ready && (ra.changed || rb.changed || pm.removed_tris)) {
                if (ra.changed && !scan_repaired) {
                    scan_repaired = 1;
                    degenerate = ra.degenerate_removed;
                }
                us = sr_boolean_union_local_mending(&acc, NULL, xf, &patch, NULL, 0, &acc,
                                                    &info, &uerr);
                if (us == SR_OK) {
                    mended += info.mended_tris;
                    patch_mended += pm.removed_tris;
                }
            }
            sr_mesh_release(&patch);
        }
        if (us == SR_OK)
            continue;
        snprintf(r->union_note, sizeof r->union_note, "section %zu: %s", i + 1, uerr.msg);
        r->restored_by_union = 0;
        recon_note_repairs(r, degenerate, mended, patch_mended, NULL);
        st = recon_concatenate(owned ? &acc : scan, xf, r->sections + i, r->section_count - i,
                               &next);
        sr_mesh_release(&acc);
        if (st != SR_OK)
            return sr_err_set(err, st, "out of memory joining patches");
        r->restored = next;
        return SR_OK;
    }
    if (!owned) { /* nothing to unite: the scan itself */
        st = sr_mesh_copy(&acc, scan);
        if (st != SR_OK)
            return sr_err_set(err, st, "out of memory copying the scan");
    }
    /* pockets the patches closed off against the fracture (layer steps against a
     * noisy surface) are voids of the restored part no scan could have shown */
    sr_void_report voids = {0};
    if (r->section_count) {
        st = sr_mesh_drop_voids(&acc, max_void_mm3, &voids, err);
        if (st != SR_OK) {
            sr_mesh_release(&acc);
            return st;
        }
    }
    recon_note_repairs(r, degenerate, mended, patch_mended, &voids);
    r->restored = acc;
    return SR_OK;
}

static int cmp_section_volume(const void *pa, const void *pb)
{
    const sr_section *a = pa, *b = pb;
    return a->volume_mm3 < b->volume_mm3 ? 1 : a->volume_mm3 > b->volume_mm3 ? -1 : 0;
}

/* A section's figures (image_restore.h) from its patch, given in the scan's frame. */
static void image_figures(const sr_layer_grid *grid, const double xf[12], sr_section *sec)
{
    sr_mesh copy = {0};
    if (sr_mesh_copy(&copy, &sec->patch) != SR_OK)
        return;
    sr_mesh_transform(&copy, xf);
    sr_mesh keep = sec->patch;
    sec->patch = copy;
    sr_image_section_figures(grid, sec);
    sec->patch = keep;
    sr_mesh_release(&copy);
}

/* Image method: restored = scan ∪ every section's clipped image Q (aligned frame, the
 * section's patch on entry), and each section's patch becomes exactly what that union
 * added, Q \ (scan ∪ the images before it), from the same corefinement
 * (sr_boolean_union_local_split), so patches.stl holds the missing volume and nothing
 * of the scan. Shells under a quarter of min_vol (where an image lies a noise above
 * the scan) are dropped from the patch; a section left under min_vol is dropped. A
 * union that is refused leaves the rest as separate shells (union_note says why). */
sr_status recon_unite_images(const sr_mesh *scan, const double xf[12], sr_recon_result *r,
                             double min_vol, sr_err *err)
{
    double inv[12];
    sr_xform_rigid_inverse(inv, xf);
    sr_mesh acc = {0};
    int owned = 0;
    size_t mended = 0, kept = 0;
    sr_status st;
    r->restored_by_union = 1;
    for (size_t i = 0; i < r->section_count; i++) {
        sr_section *sec = &r->sections[i];
        sr_mesh next = {0}, patch = {0};
        sr_local_union_info info;
        sr_err uerr = {{0}};
        sr_status us = sr_boolean_union_local_split(owned ? &acc : scan, "scan", xf,
                                                    &sec->patch, "section's image", 0,
                                                    owned ? &acc : &next, &patch, &info,
                                                    &uerr);
        if (us == SR_E_INVALID && owned) {
            /* zero-area triangles a previous union left: removed, tried again */
            sr_repair_report ra = {0};
            int changed = sr_mesh_repair(&acc, &ra, NULL) == SR_OK && ra.changed;
            changed |= recon_fold_slivers(&acc, NULL) > 0; /* needles CGAL would not collapse */
            if (changed)
                us = sr_boolean_union_local_split(&acc, "scan", xf, &sec->patch,
                                                  "section's image", 0, &acc, &patch, &info,
                                                  &uerr);
        }
        if (us != SR_OK) {
            snprintf(r->union_note, sizeof r->union_note, "section %zu: %s", i + 1,
                     uerr.msg);
            r->restored_by_union = 0;
            /* what was united so far, then the remaining patches as shells, each its
             * image less the scan by a whole-mesh boolean (an image that overlaps the
             * scan is never written as a patch: one that cannot be cut is dropped) */
            size_t rest = 0;
            sr_mesh al = {0};
            if (sr_mesh_copy(&al, scan) == SR_OK) {
                sr_mesh_transform(&al, xf);
                for (size_t k = i; k < r->section_count; k++) {
                    sr_mesh p = {0};
                    sr_section *sk = &r->sections[k];
                    if (sr_image_patch_alone(&sk->patch, &al, &p, &mended, NULL) == SR_OK &&
                        p.tri_count && sr_mesh_volume(&p) >= min_vol) {
                        sr_mesh_release(&sk->patch);
                        sk->patch = p;
                        sk->volume_mm3 = sr_mesh_volume(&p);
                        sr_image_section_figures(&r->grid, sk);
                        sr_mesh_transform(&sk->patch, inv); /* to the scan's frame */
                        r->sections[kept + rest++] = *sk;
                    } else {
                        sr_mesh_release(&p);
                        sr_mesh_release(&sk->patch);
                    }
                }
            }
            sr_mesh_release(&al);
            r->section_count = kept + rest;
            recon_note_repairs(r, 0, mended, 0, NULL);
            st = recon_concatenate(owned ? &acc : scan, NULL, r->sections + kept, rest, &next);
            sr_mesh_release(&acc);
            if (st != SR_OK)
                return sr_err_set(err, st, "out of memory joining patches");
            r->restored = next;
            return SR_OK;
        }
        mended += info.mended_tris;
        if (!owned) {
            acc = next;
            owned = 1;
        }
        /* the patch stays in the scan's frame, as the split gave it (a move there and
         * back rounds touching faces into crossing ones); its figures from a copy in
         * the aligned frame */
        sr_mesh_drop_small_shells(&patch, 0.25 * min_vol, NULL, NULL);
        sr_mesh_release(&sec->patch);
        sec->patch = patch;
        sec->volume_mm3 = sr_mesh_volume(&patch);
        if (patch.tri_count == 0 || sec->volume_mm3 < min_vol) {
            sr_mesh_release(&sec->patch);
            continue;
        }
        image_figures(&r->grid, xf, sec);
        r->sections[kept++] = *sec;
    }
    r->section_count = kept;
    qsort(r->sections, r->section_count, sizeof *r->sections, cmp_section_volume);
    if (!owned) {
        st = sr_mesh_copy(&acc, scan);
        if (st != SR_OK)
            return sr_err_set(err, st, "out of memory copying the scan");
    }
    sr_void_report voids = {0};
    size_t degenerate = 0;
    if (r->section_count) {
        st = sr_mesh_drop_voids(&acc, min_vol, &voids, err);
        if (st != SR_OK) {
            sr_mesh_release(&acc);
            return st;
        }
        /* images meeting the scan along a line (the axis, where a chip's wedge ends)
         * leave zero-area triangles there */
        sr_repair_report rr = {0};
        if (sr_mesh_repair(&acc, &rr, NULL) == SR_OK)
            degenerate = rr.degenerate_removed;
        degenerate += recon_fold_slivers(&acc, NULL);
        for (size_t i = 0; i < r->section_count; i++) {
            sr_mesh_repair(&r->sections[i].patch, &rr, NULL);
            recon_fold_slivers(&r->sections[i].patch, NULL);
        }
    }
    recon_note_repairs(r, degenerate, mended, 0, &voids);
    r->restored = acc;
    return SR_OK;
}

/* Paper method: the patches the union uses. Alg. 6's blocks have their inner face at the
 * damaged radius sampled at the layer's centre, a staircase that weaves through the
 * fracture surface between the samples: uniting it with the scan cuts tens of thousands
 * of fine scan triangles (2 s on a 1M-triangle scan) and leaves slivers of the fracture
 * surface and thin voids between the steps in the restored part. For the union each
 * damaged cell's inner radius is taken down to the least damaged radius of its 3 x 3
 * neighbourhood less 0.01 mm (never by more than the cell's depth), so the inner face
 * lies inside the material and only the rim of the patch cuts the scan. The reported
 * patches and volumes stay Alg. 6's. *out[i] pairs with sections[i]; on failure the
 * caller unites the reported patches. */
sr_status recon_paper_union_patches(const sr_layer_grid *grid, const sr_analysis *an,
                                    const sr_section *sections, size_t count,
                                    sr_mesh **out)
{
    size_t L = grid->layers, N = grid->sectors, cells = L * N;
    double *r = malloc((cells ? cells : 1) * sizeof *r);
    if (!r)
        return SR_E_NOMEM;
    for (size_t l = 0; l < L; l++)
        for (size_t j = 0; j < N; j++) {
            size_t c = l * N + j;
            r[c] = grid->r[c];
            if (!an->damaged[c] || !(grid->r[c] > 0))
                continue;
            double lo = grid->r[c];
            for (long dl = -1; dl <= 1; dl++)
                for (long dj = -1; dj <= 1; dj++) {
                    long ll = (long)l + dl, jj = ((long)j + dj + (long)N) % (long)N;
                    if (ll < 0 || ll >= (long)L)
                        continue;
                    double v = grid->r[(size_t)ll * N + (size_t)jj];
                    if (v > 0 && v < lo)
                        lo = v;
                }
            double depth = an->restored_r[c] - grid->r[c];
            double want = lo - 0.01;
            if (want < grid->r[c] - depth)
                want = grid->r[c] - depth;
            r[c] = want > 0 ? want : grid->r[c];
        }
    sr_layer_grid g2 = *grid;
    g2.r = r;
    sr_section *secs = NULL;
    size_t n = 0;
    sr_status st = sr_patch_build(&g2, an, &secs, &n, NULL);
    free(r);
    if (st != SR_OK)
        return st;
    sr_mesh *m = calloc(count ? count : 1, sizeof *m);
    if (!m || n != count) {
        free(m);
        sr_sections_release(secs, n);
        return m ? SR_E_INTERNAL : SR_E_NOMEM;
    }
    /* same cells, other volumes: pair them by their cells, not by their order */
    for (size_t i = 0; i < count; i++)
        for (size_t k = 0; k < n; k++)
            if (secs[k].patch.tri && secs[k].layer_first == sections[i].layer_first &&
                secs[k].sector_first == sections[i].sector_first &&
                secs[k].cell_count == sections[i].cell_count) {
                m[i] = secs[k].patch;
                memset(&secs[k].patch, 0, sizeof secs[k].patch);
                break;
            }
    sr_sections_release(secs, n);
    for (size_t i = 0; i < count; i++)
        if (!m[i].tri) {
            for (size_t k = 0; k < count; k++)
                sr_mesh_release(&m[k]);
            free(m);
            return SR_E_INTERNAL;
        }
    *out = m;
    return SR_OK;
}
