/*
 * run_nominal.c: the nominal's second opinion (nominal.h's sr_nominal_result) turned
 * into the part of the run record the catalogue stores (run.h's sr_run_nominal):
 * plain figures, no meshes (the pieces are kept by their volume, thickness, section
 * and the share near no section with its centroid; the registered nominal can be made again from the part and the transform).
 */
#include "run/run_build.h"

#include <stdlib.h>
#include <string.h>
#include <stdio.h>

sr_status sr_run_nominal_from(const sr_nominal_result *nr, const char *reference,
                              sr_run_nominal **out, sr_err *err)
{
    if (strcmp(reference, "symmetry") != 0 && strcmp(reference, "nominal") != 0)
        return sr_err_set(err, SR_E_RANGE, "bad reference '%s': expected symmetry or nominal",
                          reference);
    sr_run_nominal *n = calloc(1, sizeof *n);
    if (!n)
        return sr_err_set(err, SR_E_NOMEM, "out of memory recording the nominal");
    if (nr->section_count)
        n->sections = calloc(nr->section_count, sizeof *n->sections);
    if (nr->piece_count)
        n->pieces = calloc(nr->piece_count, sizeof *n->pieces);
    if ((nr->section_count && !n->sections) || (nr->piece_count && !n->pieces)) {
        sr_run_nominal_free(n);
        return sr_err_set(err, SR_E_NOMEM, "out of memory recording the nominal");
    }
    snprintf(n->reference, sizeof n->reference, "%s", reference);
    memcpy(n->transform, nr->reg.mat, sizeof n->transform);
    n->coverage = nr->reg.coverage;
    n->rms_mm = nr->reg.rms_mm;
    n->tol_mm = nr->reg.tol_mm;
    n->nominal_mm3 = nr->nominal_mm3;
    n->symmetry_mm3 = nr->symmetry_mm3;
    n->diff_mm3 = nr->diff_mm3;
    n->diff_pct = nr->diff_pct;
    n->sliver_mm = nr->sliver_mm;
    n->sliver_mm3 = nr->sliver_mm3;
    n->min_volume_mm3 = nr->min_volume_mm3;
    n->slivers = nr->slivers;
    n->extra_mm3 = nr->extra_mm3;
    n->extra_limit_mm3 = nr->extra_limit_mm3;
    n->poor = nr->poor;
    snprintf(n->note, sizeof n->note, "%s", nr->note);
    n->seconds = nr->seconds;
    snprintf(n->method, sizeof n->method, "%s", nr->by_cells ? "cells" : "exact");
    n->cell_mm = nr->by_cells ? nr->cell_mm : 0;
    snprintf(n->exact_note, sizeof n->exact_note, "%s", nr->exact_note);
    n->section_count = nr->section_count;
    for (size_t i = 0; i < nr->section_count; i++) {
        const sr_nominal_section *s = &nr->sections[i];
        n->sections[i] =
            (sr_run_nominal_section){i,           s->symmetry_mm3, s->nominal_mm3, s->diff_mm3,
                                     s->diff_pct, s->dev_mean_mm,  s->dev_max_mm,  s->pieces};
    }
    n->piece_count = nr->piece_count;
    for (size_t i = 0; i < nr->piece_count; i++) {
        const sr_nominal_piece *p = &nr->pieces[i];
        sr_run_nominal_piece *q = &n->pieces[i];
        q->volume_mm3 = p->volume_mm3;
        q->thickness_mm = p->thickness_mm;
        q->section = p->section;
        q->outside_mm3 = p->outside_mm3;
        memcpy(q->centroid, p->centroid, sizeof q->centroid);
    }
    *out = n;
    return SR_OK;
}
