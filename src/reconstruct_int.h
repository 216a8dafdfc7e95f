/*
 * reconstruct_int.h: the private interface between the files that implement
 * reconstruct.h. Not for use outside them.
 *
 *   reconstruct.c        the pipeline for one scan (sr_reconstruct): defaults, unfold,
 *                        align and slice, the method's sections and patches, figures
 *   reconstruct_union.c  the restored part: the scan united with the patches (or
 *                        joined to them as shells), the patches mended, the paper
 *                        method's patches for the union, the repair note
 *   reconstruct_gaps.c   the image method's sections lying behind a scan gap's fill
 *   reconstruct_slivers.c  the needles a union leaves, collapsed where they are
 */
#ifndef SR_RECONSTRUCT_INT_H
#define SR_RECONSTRUCT_INT_H

#include <stddef.h>

#include "mesh/mesh_shells.h"
#include "reconstruct.h"

/* *out = scan followed by the patches of secs[0..count) as separate shells, the patches
 * mapped back by the inverse of xf (NULL: in the scan's frame already). */
sr_status recon_concatenate(const sr_mesh *scan, const double xf[12], const sr_section *secs,
                            size_t count, sr_mesh *out);

/* r->repair_note from what was repaired in the scan for the unions (zero-area triangles
 * removed, triangles replaced where it crossed itself), the patch triangles replaced
 * and the voids filled (voids may be NULL). */
void recon_note_repairs(sr_recon_result *r, size_t degenerate, size_t mended,
                        size_t patch_mended, const sr_void_report *voids);

/* Mends the patches that cross themselves where that keeps them closed with their
 * volume; returns the patch triangles replaced. */
size_t recon_mend_patches(sr_section *sections, size_t count);

/* r->restored = scan ∪ every patch (upatches[i] instead of section i's patch when not
 * NULL), in the scan's frame (xf: scan -> aligned); a union refused leaves the rest as
 * shells (r->union_note); voids up to max_void_mm3 filled. */
sr_status recon_unite(const sr_mesh *scan, const double xf[12], sr_recon_result *r,
                      const sr_mesh *upatches, double max_void_mm3, size_t patch_mended,
                      sr_err *err);

/* Image method: r->restored = scan ∪ every section's clipped image, each section's
 * patch made what its union added (in the scan's frame), sections under min_vol
 * dropped. */
sr_status recon_unite_images(const sr_mesh *scan, const double xf[12], sr_recon_result *r,
                             double min_vol, sr_err *err);

/* Image method, patches in the scan's frame: every section whose patch lies on the
 * fills (the triangles the closing of an open scan made; NULL or empty: none) for a
 * good share of its surface is the gap's lens, moved from r->sections to r->gap_sags
 * (its patch freed; the restored part keeps it). SR_E_NOMEM. */
sr_status recon_split_gap_sags(sr_recon_result *r, const sr_mesh *fills, sr_err *err);

/* The fins of needles a union leaves (edges under 5 micrometres) collapsed where the
 * mesh stays closed with its volume: on the triangles a few rings round them when they
 * are under a quarter of m, else on all of m. Returns the edges collapsed (m replaced
 * or changed in place only then); *looked_at (may be NULL) the triangles that went
 * through the collapse (0: no short edge). */
size_t recon_fold_slivers(sr_mesh *m, size_t *looked_at);

/* Paper method: the patches the union uses, their inner faces taken inside the material;
 * (*out)[i] pairs with sections[i]. */
sr_status recon_paper_union_patches(const sr_layer_grid *grid, const sr_analysis *an,
                                    const sr_section *sections, size_t count,
                                    sr_mesh **out);

#endif
