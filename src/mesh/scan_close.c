/*
 * scan_close.c: the openings of a scan closed by fans (scan_describe.h,
 * sr_scan_close_openings): a vertex at each loop's centroid and one triangle per rim
 * edge, walked against the rim. The image method's voxels count crossings along z by
 * the winding rule (images/voxels.h): an open base or a hole lets a column miss a
 * crossing and fills or empties it from there on; with the fans every column crosses a
 * closed surface again.
 */
#include "mesh/scan_describe.h"

#include <stdlib.h>
#include <string.h>

sr_status sr_scan_close_openings(sr_mesh *mesh, const sr_scan_desc *d, double max_span_mm2,
                                 size_t *closed, sr_err *err)
{
    size_t add_v = 0, add_t = 0;
    for (size_t i = 0; i < d->loop_count; i++) {
        const sr_scan_loop *l = &d->loops[i];
        if (l->closed && l->edges >= 3 && (max_span_mm2 <= 0 || l->span_mm <= max_span_mm2)) {
            add_v++;
            add_t += l->edges;
        }
    }
    if (closed)
        *closed = add_v;
    if (add_v == 0)
        return SR_OK;
    size_t nv = mesh->vertex_count, nt = mesh->tri_count;
    if (nv + add_v > SR_MESH_MAX_COUNT || nt + add_t > SR_MESH_MAX_COUNT)
        return sr_err_set(err, SR_E_RANGE, "too many vertices to close the scan's openings");
    double *xyz = realloc(mesh->xyz, 3 * (nv + add_v) * sizeof *xyz);
    if (!xyz)
        return sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    mesh->xyz = xyz; /* same vertices, more room: the mesh is unchanged so far */
    uint32_t *tri = realloc(mesh->tri, 3 * (nt + add_t) * sizeof *tri);
    if (!tri)
        return sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    mesh->tri = tri;
    size_t v = nv, t = nt;
    for (size_t i = 0; i < d->loop_count; i++) {
        const sr_scan_loop *l = &d->loops[i];
        if (!(l->closed && l->edges >= 3 && (max_span_mm2 <= 0 || l->span_mm <= max_span_mm2)))
            continue;
        const uint32_t *lv = d->loop_verts + l->first;
        double c[3] = {0, 0, 0};
        for (size_t e = 0; e < l->edges; e++)
            for (int k = 0; k < 3; k++)
                c[k] += xyz[3 * (size_t)lv[e] + k] / (double)l->edges;
        memcpy(xyz + 3 * v, c, sizeof c);
        for (size_t e = 0; e < l->edges; e++) {
            uint32_t a = lv[e], b = lv[(e + 1) % l->edges];
            tri[3 * t] = b; /* the rim walks a -> b: the fan walks b -> a */
            tri[3 * t + 1] = a;
            tri[3 * t + 2] = (uint32_t)v;
            t++;
        }
        v++;
    }
    mesh->vertex_count = v;
    mesh->tri_count = t;
    return SR_OK;
}
