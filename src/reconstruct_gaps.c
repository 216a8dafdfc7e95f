/*
 * reconstruct_gaps.c: the image method's sections that lie behind a scan gap's fill,
 * told apart from damage (recon_split_gap_sags). An opening of an open scan is closed
 * flat (mesh/scan_describe.h); where the surface it lost was curved or ran over an
 * edge, the fill lies under it, and the images see the lens between them as missing.
 * That lens is restored (it is in the restored part), but it is the scan's gap, not
 * the part's damage: no section, no repair advice. Told by where its patch lies: a
 * patch is restored ∖ scan, so its faces are either on the restored surface or on the
 * scan's; a lens's scan side is the fill, a broken feature's the fracture the scanner
 * saw.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "align/surface_query.h"
#include "reconstruct_int.h"

/* A patch face lies on a fill when its centroid is this close to one (mm): the patch's
 * faces on the scan side are pieces of the scan's own triangles, exactly; the unfolding
 * of noise folds moves a few of them a little. */
#define ON_FILL_MM 0.02
/* A section is a gap's when at least this share of its patch's area lies on the fills.
 * A lens has up to half of it there (its other face is the restored surface; a ring of
 * the scan round the hole, which the noise leaves under the restored surface, takes
 * some); a broken feature's scan side is its fracture face, with no fill on it (the
 * gaps a scanner leaves are not on the damage), and a fill beside damage adds a small
 * share only. Measured on the open scans of 96 generated parts (six seeds): the 11
 * lenses 0.26 to 0.43, the 136 sections of damage 0.12 at most (a lever's). */
#define GAP_SHARE 0.2

/* The share of patch's area within ON_FILL_MM of the fills (q), and the centroid of
 * that part into c. */
static double share_on_fills(const sr_mesh *patch, sr_surface_query *q, double c[3])
{
    double total = 0, on = 0;
    c[0] = c[1] = c[2] = 0;
    for (size_t t = 0; t < patch->tri_count; t++) {
        const double *a = patch->xyz + 3 * (size_t)patch->tri[3 * t];
        const double *b = patch->xyz + 3 * (size_t)patch->tri[3 * t + 1];
        const double *d = patch->xyz + 3 * (size_t)patch->tri[3 * t + 2];
        double u[3], v[3], p[3];
        for (int k = 0; k < 3; k++) {
            u[k] = b[k] - a[k];
            v[k] = d[k] - a[k];
            p[k] = (a[k] + b[k] + d[k]) / 3.0;
        }
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
        double area = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        total += area;
        double dist;
        if (area > 0 && sr_surface_query_closest(q, p, ON_FILL_MM, NULL, &dist, NULL)) {
            on += area;
            for (int k = 0; k < 3; k++)
                c[k] += area * p[k];
        }
    }
    for (int k = 0; on > 0 && k < 3; k++)
        c[k] /= on;
    return total > 0 ? on / total : 0;
}

sr_status recon_split_gap_sags(sr_recon_result *r, const sr_mesh *fills, sr_err *err)
{
    if (!fills || fills->tri_count == 0 || r->section_count == 0)
        return SR_OK;
    sr_surface_query *q = NULL;
    sr_status st = sr_surface_query_build(fills, &q, NULL);
    if (st == SR_E_INVALID)
        return SR_OK; /* fills of no area: nothing lies on them */
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory reading the scan's fills");
    sr_gap_sag *sags = malloc(r->section_count * sizeof *sags);
    if (!sags) {
        sr_surface_query_free(q);
        return sr_err_set(err, SR_E_NOMEM, "out of memory reading the scan's fills");
    }
    size_t kept = 0, nsag = 0;
    for (size_t i = 0; i < r->section_count; i++) {
        sr_section *s = &r->sections[i];
        double c[3];
        double share = share_on_fills(&s->patch, q, c);
        if (share < GAP_SHARE) {
            r->sections[kept++] = *s;
            continue;
        }
        sr_gap_sag *g = &sags[nsag++];
        g->volume_mm3 = sr_mesh_volume(&s->patch);
        g->depth_max_mm = s->depth_max_mm;
        g->fill_share = share;
        memcpy(g->centre, c, sizeof g->centre);
        sr_mesh_release(&s->patch);
    }
    sr_surface_query_free(q);
    r->section_count = kept;
    free(r->gap_sags);
    r->gap_sags = nsag ? sags : NULL;
    r->gap_sag_count = nsag;
    if (!nsag)
        free(sags);
    return SR_OK;
}
