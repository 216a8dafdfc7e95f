/*
 * inspect_volume.c: the volumes of an inspection (inspect.h), exact by CGAL booleans
 * (bridge/boolean.h) on the scan in the model's frame: per section the under-fill,
 * patch \ scan; the over-build, scan \ restored model cut into its connected pieces
 * (triangles joined through shared vertices), each piece given to the section most of
 * its vertices lie over, or to the outside when none of them does.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "bridge/boolean.h"
#include "inspect/inspect_int.h"

static uint32_t root_of(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

/* Splits `extra` (scan \ restored) into pieces and adds each one's volume to the
 * section most of its vertices lie over, to the outside when none does. (A piece of
 * stock can be joined to hair-thin slivers along the rest of the surface, where a
 * registered scan crosses the model: their vertices must not outvote it.) */
static sr_status assign_pieces(const sr_mesh *extra, ins_where *w, sr_inspect_result *r)
{
    size_t nv = extra->vertex_count, ns = r->section_count;
    uint32_t *parent = malloc((nv ? nv : 1) * sizeof *parent);
    double *vol = calloc(nv ? nv : 1, sizeof *vol);
    long *vote = calloc((nv ? nv : 1) * (ns + 1), sizeof *vote);
    if (!parent || !vol || !vote) {
        free(parent);
        free(vol);
        free(vote);
        return SR_E_NOMEM;
    }
    for (size_t v = 0; v < nv; v++)
        parent[v] = (uint32_t)v;
    for (size_t t = 0; t < extra->tri_count; t++) {
        const uint32_t *f = extra->tri + 3 * t;
        for (int k = 1; k < 3; k++) {
            uint32_t a = root_of(parent, f[0]), b = root_of(parent, f[k]);
            if (a != b)
                parent[a] = b;
        }
    }
    for (size_t t = 0; t < extra->tri_count; t++) {
        const uint32_t *f = extra->tri + 3 * t;
        const double *a = extra->xyz + 3 * f[0], *b = extra->xyz + 3 * f[1],
                     *c = extra->xyz + 3 * f[2];
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        vol[root_of(parent, f[0])] += det / 6;
    }
    for (size_t v = 0; v < nv; v++) {
        int s = ins_section_of(w, extra->xyz + 3 * v, NULL);
        vote[root_of(parent, (uint32_t)v) * (ns + 1) + (s < 0 ? ns : (size_t)s)]++;
    }
    r->outside_overbuild_mm3 = 0;
    for (size_t k = 0; k < ns; k++)
        r->sections[k].overbuild_mm3 = 0;
    for (size_t v = 0; v < nv; v++) {
        if (parent[v] != v)
            continue;
        const long *votes = vote + v * (ns + 1);
        size_t best = ns;
        for (size_t k = 0; k < ns; k++)
            if (votes[k] > 0 && (best == ns || votes[k] > votes[best]))
                best = k;
        if (best == ns)
            r->outside_overbuild_mm3 += vol[v];
        else
            r->sections[best].overbuild_mm3 += vol[v];
    }
    free(parent);
    free(vol);
    free(vote);
    return SR_OK;
}

sr_status ins_volumes(const sr_run *run, const sr_mesh *solids, size_t solid_count, ins_where *w,
                      sr_inspect_result *r, sr_err *err)
{
    r->volumes_exact = 0;
    if (!sr_mesh_is_closed(&r->scan)) {
        snprintf(r->volume_note, sizeof r->volume_note, "the scan is not closed");
        return SR_OK;
    }
    sr_err berr;
    sr_err_clear(&berr);
    size_t ns = r->section_count;
    double *under = calloc(ns ? ns : 1, sizeof *under);
    if (!under)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    sr_mesh d;
    sr_mesh_init(&d);
    for (size_t k = 0; k < ns; k++) {
        const sr_mesh *patch = &run->sections[k].patch;
        if (sr_boolean_compute(SR_BOOLEAN_DIFFERENCE, patch, "patch", &r->scan, "scan", &d,
                               &berr) != SR_OK) {
            snprintf(r->volume_note, sizeof r->volume_note, "%s", berr.msg);
            free(under);
            return SR_OK;
        }
        /* exact under-fill even when the over-build below cannot be had */
        r->sections[k].underfill_mm3 = d.tri_count ? sr_mesh_volume(&d) : 0;
        under[k] = d.tri_count ? sr_mesh_volume(&d) : 0;
        sr_mesh_release(&d);
    }
    /* scan \ restored, one solid after the other */
    sr_status st = SR_OK;
    for (size_t k = 0; k < solid_count; k++) {
        sr_mesh next;
        sr_mesh_init(&next);
        if (sr_boolean_compute(SR_BOOLEAN_DIFFERENCE, k ? &d : &r->scan, "scan", &solids[k],
                               "restored mesh", &next, &berr) != SR_OK) {
            snprintf(r->volume_note, sizeof r->volume_note, "%s", berr.msg);
            sr_mesh_release(&d);
            free(under);
            return SR_OK;
        }
        sr_mesh_release(&d);
        d = next;
        if (d.tri_count == 0)
            break;
    }
    st = assign_pieces(&d, w, r);
    sr_mesh_release(&d);
    if (st != SR_OK) {
        free(under);
        return sr_err_set(err, st, "out of memory");
    }
    for (size_t k = 0; k < ns; k++)
        r->sections[k].underfill_mm3 = under[k];
    free(under);
    r->volumes_exact = 1;
    return SR_OK;
}
