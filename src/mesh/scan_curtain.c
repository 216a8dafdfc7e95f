/*
 * scan_curtain.c: the walls a scan lost beside a plane opening, hung back down to the
 * plane before the openings are closed (scan_describe.h, sr_scan_hang_curtains).
 *
 * A scanner's occlusion hole that reaches the face the part stood on (a hole in a bolt
 * hole's wall, in a bore, between gear teeth, right at the bottom) joins the base's
 * opening: the rim of that bore or tooth, which lay in the base's plane, now runs up the
 * wall round the hole and back. Such a rim is no longer planar, so the plane's fill took
 * no notice of it (the bore's mouth was filled over as if it were face) and it was closed
 * by a fan from its centroid: a cone up the bore, millimetres off the part (a flange's
 * bolt holes, a collar's bore: 2.8 and 5.1 mm of Hausdorff). Where a rim lies in the
 * plane of a planar rim of the scan for at least a third of its vertices, and leaves it
 * only to one side, each excursion off the plane is hung down to it: its vertices
 * projected onto the plane, and a strip of triangles between the excursion and its
 * projection (the wall the hole took, straight down as walls along a base mostly run).
 * The rim then lies in the plane and closes with it, a bore's mouth as a hole in the
 * face. A rim whose projection would have no area (a hole in a wall seen edge on) is
 * left as it is.
 */
#include "mesh/scan_describe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "mesh/scan_int.h"

/* a rim's projection must enclose at least this share of the area of a circle with its
 * perimeter (a sliver is a wall's hole seen edge on, not a mouth in the face) */
#define CURTAIN_MIN_ROUNDNESS 0.05

/* An excursion runs up a wall standing on the plane when at WALL_SHARE of its vertices
 * the scan faces within 30 degrees of sideways to it (cosine with the plane's normal at
 * most WALL_COS): a bore's, a bolt hole's, a tooth's flank (a slit up a bore that runs
 * round its top edge too still does). A hole in a countersink beside the face slopes
 * at 45 degrees: hung, its projection was a lid across the cone, 1.2 mm off the part. */
#define WALL_COS 0.5
#define WALL_SHARE 0.75

static double height(const double *p, const double c[3], const double n[3])
{
    return (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2];
}

static int u32_cmp(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Whether loop l walks through a vertex twice (its vertices sorted into scratch). */
static bool walks_twice(const sr_scan_desc *d, const sr_scan_loop *l, uint32_t *scratch)
{
    memcpy(scratch, d->loop_verts + l->first, l->edges * sizeof *scratch);
    qsort(scratch, l->edges, sizeof *scratch, u32_cmp);
    for (size_t i = 1; i < l->edges; i++)
        if (scratch[i] == scratch[i - 1])
            return true;
    return false;
}

/* The number of loop l's vertices on the plane (c, n), or 0 when the rim does not leave
 * the plane, leaves it both ways, or its projection onto the plane is a sliver. */
static size_t fits_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                         const double c[3], const double n[3])
{
    const uint32_t *lv = d->loop_verts + l->first;
    size_t on = 0, up = 0, down = 0;
    double ss = 0;
    for (size_t e = 0; e < l->edges; e++) {
        double h = height(mesh->xyz + 3 * (size_t)lv[e], c, n);
        if (fabs(h) <= SR_SCAN_PLANE_MAX_MM) {
            on++;
            ss += h * h;
        } else {
            up += h > 0;
            down += h < 0;
        }
    }
    if (on < 3 || 3 * on < l->edges || (up > 0) == (down > 0) ||
        sqrt(ss / (double)on) > SR_SCAN_PLANE_RMS_MM)
        return 0;
    /* the projection's area (twice, Newell's along n) and perimeter */
    double a2 = 0, per = 0;
    for (size_t e = 0; e < l->edges; e++) {
        const double *p = mesh->xyz + 3 * (size_t)lv[e];
        const double *q = mesh->xyz + 3 * (size_t)lv[(e + 1) % l->edges];
        double hp = height(p, c, n), hq = height(q, c, n), pp[3], qq[3], x[3];
        for (int k = 0; k < 3; k++) {
            pp[k] = p[k] - hp * n[k];
            qq[k] = q[k] - hq * n[k];
        }
        x[0] = pp[1] * qq[2] - pp[2] * qq[1];
        x[1] = pp[2] * qq[0] - pp[0] * qq[2];
        x[2] = pp[0] * qq[1] - pp[1] * qq[0];
        a2 += x[0] * n[0] + x[1] * n[1] + x[2] * n[2];
        per += sqrt((qq[0] - pp[0]) * (qq[0] - pp[0]) + (qq[1] - pp[1]) * (qq[1] - pp[1]) +
                    (qq[2] - pp[2]) * (qq[2] - pp[2]));
    }
    double area = 0.5 * fabs(a2);
    if (!(per > 0) || area < CURTAIN_MIN_ROUNDNESS * per * per / (4 * M_PI))
        return 0;
    return on;
}

typedef struct added {
    double *xyz;
    size_t nv, cap_v;
    uint32_t *tri;
    size_t nt, cap_t;
} added;

static bool add_vertex(added *a, const double p[3])
{
    double(*x)[3] = sr_grow(a->xyz, a->nv, &a->cap_v, sizeof *x);
    if (!x)
        return false;
    a->xyz = (double *)x;
    memcpy(a->xyz + 3 * a->nv++, p, 3 * sizeof *p);
    return true;
}

static bool add_tri(added *a, uint32_t x, uint32_t y, uint32_t z)
{
    uint32_t(*t)[3] = sr_grow(a->tri, a->nt, &a->cap_t, sizeof *t);
    if (!t)
        return false;
    a->tri = (uint32_t *)t;
    t[a->nt][0] = x;
    t[a->nt][1] = y;
    t[a->nt++][2] = z;
    return true;
}

/* Douglas-Peucker on the projections q[0..n) (q[0] and q[n-1] kept): keep[i] set for the
 * points farther than tol from the chord of the points kept around them. */
static void simplify(const double *q, size_t lo, size_t hi, double tol, bool *keep)
{
    if (hi <= lo + 1)
        return;
    const double *a = q + 3 * lo, *b = q + 3 * hi;
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2], far = -1;
    size_t at = lo;
    for (size_t i = lo + 1; i < hi; i++) {
        const double *p = q + 3 * i;
        double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double t = l2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2 : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
        double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (dd > far) {
            far = dd;
            at = i;
        }
    }
    if (far <= tol * tol)
        return;
    keep[at] = true;
    simplify(q, lo, at, tol, keep);
    simplify(q, at, hi, tol, keep);
}

/* Hangs one excursion w[0..n) (w[0] and w[n-1] on the plane, the rest off it, in walk
 * order) down to the plane: the projections, simplified within the plane's tolerance
 * (a wall's side projects to one point, back and forth with the noise), are the new
 * rim, and each edge of the excursion is fanned to the kept projection before it, each
 * step of the new rim to the excursion's vertex above it. The rim walks a -> b as the
 * scan's triangle on that edge does; the strip walks b -> a. dry: nothing is added,
 * *walls counts the excursion's vertices (between its feet) where the scan faces
 * sideways to the plane, *steps all of them (vn: the scan's area normals summed at the
 * rims' vertices, slot: each vertex's place in vn). */
static bool hang_one(const sr_mesh *mesh, const uint32_t *w, size_t n, const double c[3],
                     const double n3[3], size_t base_v, bool dry, const double *vn,
                     const uint32_t *slot, size_t *walls, size_t *steps, added *a)
{
    double *q = malloc(3 * n * sizeof *q);
    bool *keep = calloc(n, sizeof *keep);
    uint32_t *qid = malloc(n * sizeof *qid);
    bool ok = q && keep && qid;
    for (size_t i = 0; ok && i < n; i++) {
        const double *p = mesh->xyz + 3 * (size_t)w[i];
        double h = height(p, c, n3);
        for (int k = 0; k < 3; k++)
            q[3 * i + k] = p[k] - h * n3[k];
    }
    if (ok) {
        keep[0] = keep[n - 1] = true;
        simplify(q, 0, n - 1, SR_SCAN_PLANE_MAX_MM, keep);
        /* kept only while they run on from the first to the last along the chord: one
         * turning back (the noise at a wall's foot, projected) would cross the rim */
        const double *qa = q, *qb = q + 3 * (n - 1);
        double ab[3] = {qb[0] - qa[0], qb[1] - qa[1], qb[2] - qa[2]};
        double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2], last = 0;
        for (size_t i = 1; i + 1 < n; i++) {
            if (!keep[i])
                continue;
            const double *p = q + 3 * i;
            double t =
                l2 > 0
                    ? ((p[0] - qa[0]) * ab[0] + (p[1] - qa[1]) * ab[1] + (p[2] - qa[2]) * ab[2]) /
                          l2
                    : -1;
            if (t > last && t < 1)
                last = t;
            else
                keep[i] = false;
        }
        qid[0] = w[0];
        qid[n - 1] = w[n - 1];
    }
    for (size_t i = 1; ok && dry && i + 1 < n; i++) {
        const double *v = vn + 3 * (size_t)slot[w[i]];
        double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        (*steps)++;
        *walls += len > 0 && fabs(v[0] * n3[0] + v[1] * n3[1] + v[2] * n3[2]) <= WALL_COS * len;
    }
    for (size_t i = 1; ok && !dry && i + 1 < n; i++)
        if (keep[i]) {
            qid[i] = (uint32_t)(base_v + a->nv);
            ok = add_vertex(a, q + 3 * i);
        }
    size_t j = 0; /* the kept projection the current edge fans to */
    for (size_t i = 0; ok && !dry && i + 1 < n; i++) {
        if (qid[j] != w[i]) /* not the rim vertex itself (the excursion's first) */
            ok = add_tri(a, w[i + 1], w[i], qid[j]);
        if (ok && keep[i + 1]) { /* the new rim steps on under w[i + 1] */
            if (qid[i + 1] != w[i + 1])
                ok = add_tri(a, w[i + 1], qid[j], qid[i + 1]);
            j = i + 1;
        }
    }
    free(q);
    free(keep);
    free(qid);
    return ok;
}

/* Hangs loop l's excursions off the plane (c, n) down to it (vertices of the mesh from
 * base_v on are the added ones) when they ran up walls standing on it: WALL_SHARE of
 * their vertices where the scan faces sideways. 1 hung, 0 not, -1 out of memory. */
static int hang(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                const double c[3], const double n[3], size_t base_v, const double *vn,
                const uint32_t *slot, uint32_t *w, added *a)
{
    const uint32_t *lv = d->loop_verts + l->first;
    size_t m = l->edges, s0 = 0;
    while (s0 < m && fabs(height(mesh->xyz + 3 * (size_t)lv[s0], c, n)) > SR_SCAN_PLANE_MAX_MM)
        s0++;
    bool wall = true;
    size_t walls = 0, steps = 0;
    for (int dry = 1; dry >= 0 && wall; dry--, wall = walls >= WALL_SHARE * (double)steps)
        for (size_t k = 0; k < m;) { /* k: steps from s0; lv[s0 + k] on the plane */
            size_t j = k + 1;
            while (j < m && fabs(height(mesh->xyz + 3 * (size_t)lv[(s0 + j) % m], c, n)) >
                                SR_SCAN_PLANE_MAX_MM)
                j++;
            if (j > k + 1) { /* lv[s0 + k .. s0 + j]: off the plane between (j = m: back at s0) */
                for (size_t i = k; i <= j; i++)
                    w[i - k] = lv[(s0 + i) % m];
                if (!hang_one(mesh, w, j - k + 1, c, n, base_v, dry, vn, slot, &walls, &steps, a))
                    return -1;
            }
            k = j;
        }
    return wall && steps > 0 ? 1 : 0;
}

sr_status sr_scan_hang_curtains(sr_mesh *mesh, const sr_scan_desc *d, size_t *hung, sr_err *err)
{
    *hung = 0;
    size_t nl = d->loop_count, np = 0, maxe = 0;
    double(*planes)[6] = malloc((nl + 1) * sizeof *planes);
    for (size_t i = 0; i < nl; i++)
        maxe = d->loops[i].edges > maxe ? d->loops[i].edges : maxe;
    uint32_t *scratch = malloc((maxe + 2) * sizeof *scratch);
    added a = {0};
    sr_status st = SR_OK;
    /* the scan's area normals summed at the rims' vertices */
    uint32_t *slot = malloc((mesh->vertex_count + 1) * sizeof *slot);
    double *vn = calloc(3 * (d->boundary_edges + 1), sizeof *vn);
    if (!planes || !scratch || !slot || !vn) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory hanging the scan's lost walls");
        goto out;
    }
    for (size_t v = 0; v < mesh->vertex_count; v++)
        slot[v] = UINT32_MAX;
    size_t ns = 0;
    for (size_t i = 0; i < nl; i++)
        for (size_t e = 0; e < d->loops[i].edges; e++) {
            uint32_t v = d->loop_verts[d->loops[i].first + e];
            if (slot[v] == UINT32_MAX && ns < d->boundary_edges)
                slot[v] = (uint32_t)ns++;
        }
    for (size_t t = 0; t < mesh->tri_count; t++) {
        const uint32_t *tv = mesh->tri + 3 * t;
        if (slot[tv[0]] == UINT32_MAX && slot[tv[1]] == UINT32_MAX && slot[tv[2]] == UINT32_MAX)
            continue;
        double nt[3];
        sr_mesh_tri_normal(mesh, t, nt);
        for (int k = 0; k < 3; k++)
            if (slot[tv[k]] != UINT32_MAX)
                for (int j = 0; j < 3; j++)
                    vn[3 * (size_t)slot[tv[k]] + j] += nt[j];
    }
    for (size_t i = 0; i < nl; i++) { /* the planes of the planar rims */
        const sr_scan_loop *l = &d->loops[i];
        double c[3], n[3];
        if (sr_scan_loop_eligible(l, 0) && sr_scan_loop_plane(mesh, d, l, c, n) &&
            sr_scan_loop_on_plane(mesh, d, l, c, n)) {
            memcpy(planes[np], c, sizeof c);
            memcpy(planes[np++] + 3, n, sizeof n);
        }
    }
    size_t base_v = mesh->vertex_count;
    for (size_t i = 0; np > 0 && i < nl; i++) {
        const sr_scan_loop *l = &d->loops[i];
        double c[3], n[3];
        if (!sr_scan_loop_eligible(l, 0) ||
            (sr_scan_loop_plane(mesh, d, l, c, n) && sr_scan_loop_on_plane(mesh, d, l, c, n)) ||
            walks_twice(d, l, scratch))
            continue;
        size_t best = 0, pick = 0;
        for (size_t k = 0; k < np; k++) {
            size_t on = fits_plane(mesh, d, l, planes[k], planes[k] + 3);
            if (on > best) {
                best = on;
                pick = k;
            }
        }
        if (best == 0)
            continue;
        int h = hang(mesh, d, l, planes[pick], planes[pick] + 3, base_v, vn, slot, scratch, &a);
        if (h < 0) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory hanging the scan's lost walls");
            goto out;
        }
        *hung += (size_t)h;
    }
    if (a.nt == 0)
        goto out;
    if (base_v + a.nv > SR_MESH_MAX_COUNT || mesh->tri_count + a.nt > SR_MESH_MAX_COUNT) {
        st = sr_err_set(err, SR_E_RANGE, "too many vertices to hang the scan's lost walls");
        *hung = 0;
        goto out;
    }
    double *xyz = realloc(mesh->xyz, 3 * (base_v + a.nv) * sizeof *xyz);
    if (!xyz) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory hanging the scan's lost walls");
        *hung = 0;
        goto out;
    }
    mesh->xyz = xyz;
    uint32_t *tri = realloc(mesh->tri, 3 * (mesh->tri_count + a.nt) * sizeof *tri);
    if (!tri) { /* the vertices' room grew, nothing else: the mesh is as it was */
        st = sr_err_set(err, SR_E_NOMEM, "out of memory hanging the scan's lost walls");
        *hung = 0;
        goto out;
    }
    mesh->tri = tri;
    if (a.nv > 0) /* a wall's foot over the rim's own corners adds no vertex */
        memcpy(xyz + 3 * base_v, a.xyz, 3 * a.nv * sizeof *xyz);
    memcpy(tri + 3 * mesh->tri_count, a.tri, 3 * a.nt * sizeof *tri);
    mesh->vertex_count = base_v + a.nv;
    mesh->tri_count += a.nt;
out:
    free(planes);
    free(scratch);
    free(slot);
    free(vn);
    free(a.xyz);
    free(a.tri);
    return st;
}
