/*
 * scan_plane.c: the planes of a scan's openings (scan_int.h). A loop is planar when its
 * rim lies within the scanner's noise of the plane through its centroid with its
 * Newell normal; the loops on one plane (the rim of the face the part stood on with
 * the rims of the bores through it, the islands the scan kept in it) make one group,
 * closed together by scan_close.c and peeled of their folds first by scan_peel.c.
 */
#include <math.h>

#include "mesh/scan_int.h"

/* Another rim joins a plane's group only when its own plane is this close to parallel
 * (cosine): a small hole in a wall beside the base lies within the tolerances of the
 * base's plane, but across it (seen edge on: cosine near 0). A rim round an island
 * the scan kept in the base (a few noisy triangles tilted past the rest) is a hole in
 * the base's fill and must join it, though its own plane, over a millimetre, tilts
 * with the noise: 45 degrees still tells the two apart. */
#define SAME_PLANE_COS 0.7

bool sr_scan_loop_eligible(const sr_scan_loop *l, double max_span_mm2)
{
    return l->closed && l->edges >= 3 && (max_span_mm2 <= 0 || l->span_mm <= max_span_mm2);
}

bool sr_scan_loop_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                        double c[3], double n[3])
{
    const uint32_t *lv = d->loop_verts + l->first;
    c[0] = c[1] = c[2] = n[0] = n[1] = n[2] = 0;
    for (size_t e = 0; e < l->edges; e++)
        for (int k = 0; k < 3; k++)
            c[k] += mesh->xyz[3 * (size_t)lv[e] + k] / (double)l->edges;
    for (size_t e = 0; e < l->edges; e++) { /* Newell */
        const double *a = mesh->xyz + 3 * (size_t)lv[e];
        const double *b = mesh->xyz + 3 * (size_t)lv[(e + 1) % l->edges];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0))
        return false;
    for (int k = 0; k < 3; k++)
        n[k] /= len;
    return true;
}

void sr_scan_plane_frame(const double n[3], double e1[3], double e2[3])
{
    double ax[3] = {fabs(n[0]) < 0.9 ? 1 : 0, fabs(n[0]) < 0.9 ? 0 : 1, 0};
    e1[0] = ax[1] * n[2] - ax[2] * n[1];
    e1[1] = ax[2] * n[0] - ax[0] * n[2];
    e1[2] = ax[0] * n[1] - ax[1] * n[0];
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; k++)
        e1[k] /= l1;
    e2[0] = n[1] * e1[2] - n[2] * e1[1];
    e2[1] = n[2] * e1[0] - n[0] * e1[2];
    e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

bool sr_scan_loop_on_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                           const double c[3], const double n[3])
{
    const uint32_t *lv = d->loop_verts + l->first;
    double ss = 0;
    for (size_t e = 0; e < l->edges; e++) {
        const double *p = mesh->xyz + 3 * (size_t)lv[e];
        double h = (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2];
        if (fabs(h) > SR_SCAN_PLANE_MAX_MM)
            return false;
        ss += h * h;
    }
    return sqrt(ss / (double)l->edges) <= SR_SCAN_PLANE_RMS_MM;
}

/* Every plane loop goes to the plane, however small: a fan of a tiny loop (a triangle
 * left out along the base's rim) was seen to make the image method miss a plate's
 * damage (s3301p06); the fill's check guards them. */
size_t sr_scan_plane_group(const sr_mesh *mesh, const sr_scan_desc *d, size_t i,
                           const sr_scan_closing *done, double max_span_mm2, size_t *group,
                           double c[3], double n[3])
{
    const sr_scan_loop *l = &d->loops[i];
    if (!sr_scan_loop_eligible(l, max_span_mm2) || !sr_scan_loop_plane(mesh, d, l, c, n) ||
        !sr_scan_loop_on_plane(mesh, d, l, c, n))
        return 0;
    size_t count = 0;
    group[count++] = i;
    for (size_t j = i + 1; j < d->loop_count; j++) {
        double cj[3], nj[3];
        if ((!done || done[j] == SR_SCAN_LEFT_OPEN) &&
            sr_scan_loop_eligible(&d->loops[j], max_span_mm2) &&
            sr_scan_loop_plane(mesh, d, &d->loops[j], cj, nj) &&
            fabs(nj[0] * n[0] + nj[1] * n[1] + nj[2] * n[2]) >= SAME_PLANE_COS &&
            sr_scan_loop_on_plane(mesh, d, &d->loops[j], c, n))
            group[count++] = j;
    }
    return count;
}
