/*
 * run_scan.c: the run's record of its input read as a scan (run.h's sr_run_scan) made
 * from the scan's description (mesh/scan_describe.h) and how each opening was closed:
 * the openings are the scan's gaps, recorded apart from the sections.
 */
#include "run/run_scan.h"

#include <stdio.h>
#include <stdlib.h>

static const char *closing_name(sr_scan_closing c)
{
    return c == SR_SCAN_IN_PLANE ? "plane" : c == SR_SCAN_BY_FAN ? "fan" : "open";
}

sr_status sr_run_scan_from_desc(const sr_scan_desc *d, const sr_scan_closing *how,
                                sr_run_scan **out, sr_err *err)
{
    *out = NULL;
    if (!d || (d->loop_count == 0 && d->strays == 0 && d->sealed_triangles == 0 &&
               d->uncurled_vertices == 0))
        return SR_OK;
    sr_run_scan *s = calloc(1, sizeof *s);
    sr_run_scan_gap *g = calloc(d->loop_count ? d->loop_count : 1, sizeof *g);
    if (!s || !g) {
        free(s);
        free(g);
        return sr_err_set(err, SR_E_NOMEM, "out of memory recording the scan's gaps");
    }
    s->triangles = d->triangles;
    s->boundary_edges = d->boundary_edges;
    s->components = d->component_count;
    s->strays = d->strays;
    s->stray_triangles = d->stray_triangles;
    s->open_area_mm2 = d->open_area_mm2;
    s->open_share = d->open_share;
    s->stray_area_mm2 = d->stray_area_mm2;
    s->sealed_triangles = d->sealed_triangles;
    s->uncurled_vertices = d->uncurled_vertices;
    for (size_t i = 0; i < d->loop_count; i++) {
        const sr_scan_loop *l = &d->loops[i];
        g[i].edges = l->edges;
        g[i].length_mm = l->length_mm;
        g[i].area_mm2 = l->span_mm;
        for (int k = 0; k < 3; k++)
            g[i].centre[k] = l->centre[k];
        snprintf(g[i].closed_by, sizeof g[i].closed_by, "%s",
                 closing_name(how ? how[i] : SR_SCAN_LEFT_OPEN));
    }
    s->gaps = g;
    s->gap_count = d->loop_count;
    *out = s;
    return SR_OK;
}
