/*
 * inspect_int.h: the private interface between the files of src/inspect/.
 *
 *   inspect.c         the entry point: checks, registration, samples and their
 *                     signed distances, statistics and verdicts
 *   inspect_volume.c  the volumes: under-fill (patch \ scan) and over-build (scan \
 *                     restored model, by connected piece) with CGAL booleans
 *   inspect_model.c   the solid shells of a restored mesh that is several (a
 *                     --no-union run's scan and patches), measured as their union
 */
#ifndef SR_INSPECT_INT_H
#define SR_INSPECT_INT_H

#include "inspect/inspect.h"

/* Where a point lies (inspect.c): the restored surface and the section patches. */
typedef struct ins_where ins_where;

/* The section slot (index into the result's sections) whose patch holds the closest
 * restored point of p, -1 = none; *signed_dist (may be NULL) its signed distance to
 * the restored surface (positive outside). */
int ins_section_of(ins_where *w, const double p[3], double *signed_dist);

/* Fills r->sections[k].underfill_mm3 and overbuild_mm3 and r->outside_overbuild_mm3
 * by booleans of r->scan (model frame) with the run's patches and the restored solids
 * (solid_count of them: scan \ restored by one difference after the other), and
 * sets r->volumes_exact = 1. Returns SR_OK with r->volumes_exact 0, the reason in
 * r->volume_note and the volumes untouched (the under-fills of the sections whose
 * boolean ran excepted) when the scan is not closed or a boolean refuses it (the caller then keeps
 * its estimates); SR_E_NOMEM. */
sr_status ins_volumes(const sr_run *run, const sr_mesh *solids, size_t solid_count, ins_where *w,
                      sr_inspect_result *r, sr_err *err);

/* The solid shells of the restored mesh (closed shells of positive volume), largest
 * first, as separate meshes into *shells (*count of them, the caller's to release each
 * and free) when there are two or more: a --no-union run's scan and patches side by
 * side. *shells NULL and *count 0 when there are fewer: the mesh is one solid (voids
 * within it included) and is used as it is. SR_E_NOMEM. */
sr_status ins_solid_shells(const sr_mesh *restored, sr_mesh **shells, size_t *count, sr_err *err);

/* The surface of the union of solids[0 .. n) (n >= 2, largest first) without
 * building it: their triangles that lie neither inside another solid nor on its
 * surface (each triangle judged by its centroid), concatenated into *out. A triangle
 * straddling the rim where two solids meet is kept or dropped whole. SR_E_NOMEM. */
sr_status ins_visible_surface(const sr_mesh *solids, size_t n, sr_mesh *out, sr_err *err);

#endif
