/*
 * inspect_int.h: the private interface between the files of src/inspect/.
 *
 *   inspect.c         the entry point: checks, registration, samples and their
 *                     signed distances, statistics and verdicts
 *   inspect_volume.c  the volumes: under-fill (patch \ scan) and over-build (scan \
 *                     restored model, by connected piece) with CGAL booleans
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
 * by booleans of r->scan (model frame) with the run's patches and restored mesh, and
 * sets r->volumes_exact = 1. Returns SR_OK with r->volumes_exact 0, the reason in
 * r->volume_note and the volumes untouched (the under-fills of the sections whose
 * boolean ran excepted) when the scan is not closed or a boolean refuses it (the caller then keeps
 * its estimates); SR_E_NOMEM. */
sr_status ins_volumes(const sr_run *run, ins_where *w, sr_inspect_result *r, sr_err *err);

#endif
