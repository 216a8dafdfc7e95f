/*
 * scan_uncurl.c: the twists of a scan's rims undone before their plane is filled
 * (sr_scan_uncurl_rims, scan_describe.h). Where the face a part stood on is cut away, a
 * noisy rim can fold back on itself for an edge or two: the walk runs up an edge, back
 * down a nearly coincident one and up again (a Z of edges a tenth of a millimetre
 * apart), so in the plane two edges of the same rim cross. No triangulation of the
 * rims fills across such a crossing with every rim edge walked once the other way, so
 * the whole face was fanned from its centroid, and the rims of the bores through it
 * were then filled alone, closing their mouths (a clamp's foot holes: 2.9 mm of
 * Hausdorff on an open scan). The vertices the walk visits between two crossing edges
 * a few steps apart are merged into one at the crossing; the triangles that become
 * degenerate go.
 */
#include <math.h>
#include <stdlib.h>

#include "mesh/scan_int.h"

/* A twist spans at most this many rim vertices between the two edges that cross: the
 * rim's own scale (its noise folding an edge or a few over, or tangling where scraps of
 * the face it stood on were kept), not a bay of the outline. */
#define CURL_VERTICES 6

/* Where segments a-b and c-d cross properly in the plane: true, with the parameters
 * along each (0..1). */
static bool crossing(const double a[2], const double b[2], const double c[2], const double d[2],
                     double *s, double *t)
{
    double r[2] = {b[0] - a[0], b[1] - a[1]}, q[2] = {d[0] - c[0], d[1] - c[1]};
    double den = r[0] * q[1] - r[1] * q[0];
    if (den == 0)
        return false;
    double w[2] = {c[0] - a[0], c[1] - a[1]};
    *s = (w[0] * q[1] - w[1] * q[0]) / den;
    *t = (w[0] * r[1] - w[1] * r[0]) / den;
    return *s > 0 && *s < 1 && *t > 0 && *t < 1;
}

/* The twists of loop l (plane frame e1, e2), each merged into to[] (a vertex's
 * representative, itself when untouched) with its position written into xyz; returns
 * how many vertices were merged away. */
static size_t uncurl_loop(double *xyz, const sr_scan_desc *d, const sr_scan_loop *l,
                          const double e1[3], const double e2[3], uint32_t *to, double *uv)
{
    size_t m = l->edges, merged = 0;
    const uint32_t *w = d->loop_verts + l->first;
    if (m < CURL_VERTICES + 4)
        return 0;
    for (size_t e = 0; e < m; e++) {
        const double *p = xyz + 3 * (size_t)w[e];
        uv[2 * e] = p[0] * e1[0] + p[1] * e1[1] + p[2] * e1[2];
        uv[2 * e + 1] = p[0] * e2[0] + p[1] * e2[1] + p[2] * e2[2];
    }
    for (size_t i = 0; i < m; i++) {
        size_t i1 = (i + 1) % m;
        if (to[w[i]] != w[i] || to[w[i1]] != w[i1])
            continue;
        for (size_t k = 2; k <= CURL_VERTICES; k++) {
            size_t j = (i + k) % m, j1 = (j + 1) % m;
            bool free_walk = true; /* none of the walk's vertices merged already */
            for (size_t u = 1; u <= k && free_walk; u++)
                free_walk = to[w[(i + u) % m]] == w[(i + u) % m];
            if (!free_walk)
                break;
            double s, t;
            if (!crossing(uv + 2 * i, uv + 2 * i1, uv + 2 * j, uv + 2 * j1, &s, &t))
                continue;
            const double *a = xyz + 3 * (size_t)w[i], *b = xyz + 3 * (size_t)w[i1];
            const double *c = xyz + 3 * (size_t)w[j], *dd = xyz + 3 * (size_t)w[j1];
            uint32_t keep = w[i1];
            for (int q = 0; q < 3; q++)
                xyz[3 * (size_t)keep + q] =
                    0.5 * (a[q] + s * (b[q] - a[q]) + c[q] + t * (dd[q] - c[q]));
            for (size_t u = 2; u <= k; u++) {
                to[w[(i + u) % m]] = keep;
                merged++;
            }
            i += k - 1; /* on past the twist */
            break;
        }
    }
    return merged;
}

sr_status sr_scan_uncurl_rims(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                              size_t *merged, sr_err *err)
{
    size_t nv = mesh->vertex_count, nt = mesh->tri_count, longest = 0, n_merged = 0;
    for (size_t i = 0; i < d->loop_count; i++)
        longest = d->loops[i].edges > longest ? d->loops[i].edges : longest;
    uint32_t *to = malloc((nv + 1) * sizeof *to);
    size_t *group = malloc((d->loop_count + 1) * sizeof *group);
    bool *seen = calloc(d->loop_count + 1, sizeof *seen);
    double *uv = malloc((2 * longest + 1) * sizeof *uv);
    if (!to || !group || !seen || !uv) {
        free(to);
        free(group);
        free(seen);
        free(uv);
        return sr_err_set(err, SR_E_NOMEM, "out of memory untwisting the scan's rims");
    }
    for (size_t v = 0; v < nv; v++)
        to[v] = (uint32_t)v;
    for (size_t i = 0; i < d->loop_count; i++) {
        double c[3], n[3];
        if ((how && how[i] != SR_SCAN_BY_FAN) || seen[i])
            continue;
        size_t count = sr_scan_plane_group(mesh, d, i, NULL, 0, group, c, n);
        double e1[3], e2[3];
        if (count > 0)
            sr_scan_plane_frame(n, e1, e2);
        for (size_t k = 0; k < count; k++) {
            if (seen[group[k]])
                continue;
            seen[group[k]] = true;
            n_merged += uncurl_loop(mesh->xyz, d, &d->loops[group[k]], e1, e2, to, uv);
        }
    }
    free(group);
    free(seen);
    free(uv);
    sr_status st = SR_OK;
    if (n_merged > 0) {
        bool *gone = calloc(nt + 1, sizeof *gone);
        if (!gone) {
            free(to);
            return sr_err_set(err, SR_E_NOMEM, "out of memory untwisting the scan's rims");
        }
        for (size_t t = 0; t < nt; t++) {
            uint32_t *tr = mesh->tri + 3 * t;
            for (int k = 0; k < 3; k++)
                tr[k] = to[tr[k]];
            gone[t] = tr[0] == tr[1] || tr[1] == tr[2] || tr[2] == tr[0];
        }
        st = sr_scan_drop_triangles(mesh, gone, err);
        free(gone);
    }
    free(to);
    if (merged)
        *merged = n_merged;
    return st;
}
