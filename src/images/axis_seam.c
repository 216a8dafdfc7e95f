/*
 * axis_seam.c: closing the seam the turns' images leave on the axis (axis_seam.h).
 */
#include "images/axis_seam.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "bridge/boolean.h"
#include "images/voxels.h"
#include "mesh/shapes.h"

#define PIN_SIDES 8

/* Layer k of the 3 x 3 ring grid (bit 0: in Q, bit 1: in the scan) needs a pin. */
static int seam_at(const sr_voxels *g, size_t k)
{
    int in_q = 0, off_scan = 0;
    for (size_t j = 0; j < 3; j++)
        for (size_t i = 0; i < 3; i++) {
            if (i == 1 && j == 1)
                continue;
            uint8_t b = g->v[sr_voxel_index(g, i, j, k)];
            if (!(b & 3))
                return 0;
            in_q |= b & 1;
            off_scan |= !(b & 2);
        }
    return in_q && off_scan;
}

sr_status sr_axis_seam_close(sr_mesh *q, const sr_mesh *scan, double ring_mm, size_t *pins,
                             sr_err *err)
{
    size_t local = 0;
    if (!pins)
        pins = &local;
    *pins = 0;
    if (!(ring_mm > 0) || q->tri_count == 0)
        return SR_OK;
    double lo[3], hi[3];
    sr_mesh_bbox(q, lo, hi);
    /* the axis must pass through q's box with the ring inside it */
    if (lo[0] > -ring_mm || hi[0] < ring_mm || lo[1] > -ring_mm || hi[1] < ring_mm)
        return SR_OK;
    size_t n[3] = {3, 3, (size_t)ceil((hi[2] - lo[2]) / ring_mm)};
    if (n[2] == 0)
        return SR_OK;
    double origin[3] = {-ring_mm, -ring_mm, lo[2] + 0.5 * ring_mm};
    sr_voxels g = {0}, gs = {0};
    sr_status st = sr_voxels_alloc(&g, n, ring_mm, origin);
    if (st == SR_OK)
        st = sr_voxels_alloc(&gs, n, ring_mm, origin);
    if (st == SR_OK)
        st = sr_voxels_fill(&g, q, err);
    if (st == SR_OK)
        st = sr_voxels_fill(&gs, scan, err);
    if (st != SR_OK) {
        sr_voxels_release(&g);
        sr_voxels_release(&gs);
        return st == SR_E_NOMEM ? sr_err_set(err, st, "out of memory for the axis ring") : st;
    }
    /* bit 1: in the scan; the ring is closed where Q or the scan holds each of its
     * points, Q one at least and the scan not all (the loss reaches the axis there) */
    for (size_t v = 0; v < n[0] * n[1] * n[2]; v++)
        g.v[v] |= (uint8_t)((gs.v[v] & 1) << 1);
    sr_voxels_release(&gs);
    sr_mesh pinned = {0};
    st = sr_mesh_copy(&pinned, q);
    sr_repair_report rep = {0}; /* zero-area triangles: no boolean takes them */
    if (st == SR_OK)
        sr_mesh_repair(&pinned, &rep, NULL);
    size_t runs = 0;
    for (size_t k = 0; st == SR_OK && k < n[2];) {
        if (!seam_at(&g, k)) {
            k++;
            continue;
        }
        size_t k1 = k;
        while (k1 + 1 < n[2] && seam_at(&g, k1 + 1))
            k1++;
        /* the run's voxels span [k - 1/2, k1 + 1/2] pitches; the pin stays inside q's box */
        double z0 = fmax(lo[2], origin[2] + ((double)k - 0.5) * ring_mm);
        double z1 = fmin(hi[2], origin[2] + ((double)k1 + 0.5) * ring_mm);
        sr_mesh pin = {0}, both = {0};
        st = sr_shape_cylinder(0.5 * ring_mm, z0, z1, PIN_SIDES, &pin, err);
        if (st == SR_OK &&
            sr_boolean_compute(SR_BOOLEAN_UNION, &pinned, "image", &pin, "axis pin", &both,
                               NULL) == SR_OK) {
            sr_mesh_release(&pinned);
            pinned = both;
            runs++;
        }
        sr_mesh_release(&pin);
        k = k1 + 1;
    }
    sr_voxels_release(&g);
    if (st != SR_OK || runs == 0) {
        sr_mesh_release(&pinned);
        return st;
    }
    sr_mesh_release(q);
    *q = pinned;
    *pins = runs;
    return SR_OK;
}
