/*
 * scan_close.c: the openings of a scan closed (scan_describe.h, sr_scan_close_openings).
 * A loop whose rim lies in a plane (the face the part stood on, a hole in a flat face) is
 * closed in that plane together with every other rim in it, by the constrained
 * triangulation of the region they bound (bridge/planar_fill.h): an outer rim with the
 * rims of the bores through the base is one face with holes, a concave rim is filled
 * inside only, so the closed surface is the part's own face. Any other loop (a hole in a
 * curved face) is closed by a fan: a vertex at its centroid and one triangle per rim
 * edge, walked against the rim. The image method's voxels count crossings along z by
 * the winding rule (images/voxels.h): an open base or a hole lets a column miss a
 * crossing and fills or empties it from there on; closed, every column crosses a closed
 * surface again.
 */
#include "mesh/scan_describe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/planar_fill.h"

/* A rim is planar when its vertices lie this close to the plane through its centroid
 * with its area normal: root mean square and largest distance, mm (the scan's noise,
 * sigma up to 0.1 mm, stays inside both). */
#define PLANE_RMS_MM 0.15
#define PLANE_MAX_MM 0.5
/* Another rim joins a plane's group only when its own plane is this close to parallel
 * (cosine): a small hole in a wall beside the base lies within the tolerances of the
 * base's plane, but across it. */
#define SAME_PLANE_COS 0.95
/* A loop spanning less is fanned. 0: none is; a fan of a tiny loop (a triangle left
 * out along the base's rim) was seen to make the image method miss a plate's damage
 * (s3301p06), so tiny loops go to the plane too, guarded by the fill's check. mm^2 */
#define PLANE_MIN_MM2 0.0

/* What the closing appends: vertices and triangles, grown as needed. */
typedef struct grow {
    double *xyz;
    size_t nv, cap_v;
    uint32_t *tri;
    size_t nt, cap_t;
} grow;

static bool grow_room(grow *g, size_t add_v, size_t add_t)
{
    if (g->nv + add_v > g->cap_v) {
        size_t cap = 2 * (g->nv + add_v) + 16;
        double *p = realloc(g->xyz, 3 * cap * sizeof *p);
        if (!p)
            return false;
        g->xyz = p;
        g->cap_v = cap;
    }
    if (g->nt + add_t > g->cap_t) {
        size_t cap = 2 * (g->nt + add_t) + 16;
        uint32_t *p = realloc(g->tri, 3 * cap * sizeof *p);
        if (!p)
            return false;
        g->tri = p;
        g->cap_t = cap;
    }
    return true;
}

static bool eligible(const sr_scan_loop *l, double max_span_mm2)
{
    return l->closed && l->edges >= 3 && (max_span_mm2 <= 0 || l->span_mm <= max_span_mm2);
}

/* The fan of loop l: a new vertex (index base_v + its place in g) at the centroid. */
static bool fan(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l, size_t base_v,
                grow *g)
{
    if (!grow_room(g, 1, l->edges))
        return false;
    const uint32_t *lv = d->loop_verts + l->first;
    double c[3] = {0, 0, 0};
    for (size_t e = 0; e < l->edges; e++)
        for (int k = 0; k < 3; k++)
            c[k] += mesh->xyz[3 * (size_t)lv[e] + k] / (double)l->edges;
    uint32_t v = (uint32_t)(base_v + g->nv);
    memcpy(g->xyz + 3 * g->nv++, c, sizeof c);
    for (size_t e = 0; e < l->edges; e++) {
        uint32_t *t = g->tri + 3 * g->nt++;
        t[0] = lv[(e + 1) % l->edges]; /* the rim walks a -> b: the fan walks b -> a */
        t[1] = lv[e];
        t[2] = v;
    }
    return true;
}

/* Centroid c and unit area normal n of loop l; false when the loop has no area. */
static bool loop_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
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

/* Whether every vertex of loop l lies on the plane (c, n) within the tolerances. */
static bool on_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                     const double c[3], const double n[3])
{
    const uint32_t *lv = d->loop_verts + l->first;
    double ss = 0;
    for (size_t e = 0; e < l->edges; e++) {
        const double *p = mesh->xyz + 3 * (size_t)lv[e];
        double h = (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2];
        if (fabs(h) > PLANE_MAX_MM)
            return false;
        ss += h * h;
    }
    return sqrt(ss / (double)l->edges) <= PLANE_RMS_MM;
}

static int key_cmp(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static bool has_key(const uint64_t *keys, size_t n, uint64_t k)
{
    return bsearch(&k, keys, n, sizeof k, key_cmp) != NULL;
}

/* Whether the fill (nt triangles over the loops' points, turned against the rims)
 * closes the rims exactly: every rim edge a -> b met once as b -> a and never as
 * a -> b, no edge of the fill used twice the same way, and no other edge of the fill
 * on its border (in mesh vertices: vid of each point; no extra point). Two rim
 * vertices the triangulation merged, or a rim edge it split, fail. */
static bool fill_fits(const uint32_t *tri, size_t nt, const size_t *start, size_t count,
                      const uint32_t *vid)
{
    uint64_t *keys = malloc((3 * nt + 1) * sizeof *keys);
    if (!keys)
        return false;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            keys[3 * t + k] = (uint64_t)vid[tri[3 * t + k]] << 32 | vid[tri[3 * t + (k + 1) % 3]];
    size_t n = 3 * nt;
    qsort(keys, n, sizeof *keys, key_cmp);
    bool ok = true;
    for (size_t i = 1; ok && i < n; i++)
        ok = keys[i] != keys[i - 1];
    size_t border = 0, rim = 0;
    for (size_t i = 0; ok && i < n; i++)
        if (!has_key(keys, n, keys[i] << 32 | keys[i] >> 32))
            border++;
    for (size_t c = 0; ok && c < count; c++)
        for (size_t q = start[c]; ok && q < start[c + 1]; q++, rim++) {
            uint64_t a = vid[q], b = vid[q + 1 < start[c + 1] ? q + 1 : start[c]];
            ok = has_key(keys, n, b << 32 | a) && !has_key(keys, n, a << 32 | b);
        }
    free(keys);
    return ok && border == rim;
}

/* Closes the loops group[0..count) (all on the plane c, n) by the triangulation of the
 * region they bound. *done false (g unchanged in its counts) when the triangulation
 * gives nothing usable (then the caller fans them); SR_E_NOMEM. */
static sr_status plane_fill(const sr_mesh *mesh, const sr_scan_desc *d, const size_t *group,
                            size_t count, const double c[3], const double n[3], size_t base_v,
                            grow *g, bool *done, sr_err *err)
{
    *done = false;
    double e1[3], e2[3];
    double ax[3] = {fabs(n[0]) < 0.9 ? 1 : 0, fabs(n[0]) < 0.9 ? 0 : 1, 0};
    e1[0] = ax[1] * n[2] - ax[2] * n[1]; /* e1 = ax x n, e2 = n x e1 */
    e1[1] = ax[2] * n[0] - ax[0] * n[2];
    e1[2] = ax[0] * n[1] - ax[1] * n[0];
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; k++)
        e1[k] /= l1;
    e2[0] = n[1] * e1[2] - n[2] * e1[1];
    e2[1] = n[2] * e1[0] - n[0] * e1[2];
    e2[2] = n[0] * e1[1] - n[1] * e1[0];
    size_t pts = 0;
    for (size_t i = 0; i < count; i++)
        pts += d->loops[group[i]].edges;
    double *uv = malloc(2 * pts * sizeof *uv);
    size_t *start = malloc((count + 1) * sizeof *start);
    uint32_t *vid = malloc(pts * sizeof *vid);
    if (!uv || !start || !vid) {
        free(uv);
        free(start);
        free(vid);
        return sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    }
    size_t p = 0;
    for (size_t i = 0; i < count; i++) {
        const sr_scan_loop *l = &d->loops[group[i]];
        start[i] = p;
        for (size_t e = 0; e < l->edges; e++, p++) {
            vid[p] = d->loop_verts[l->first + e];
            const double *q = mesh->xyz + 3 * (size_t)vid[p];
            double r[3] = {q[0] - c[0], q[1] - c[1], q[2] - c[2]};
            uv[2 * p] = r[0] * e1[0] + r[1] * e1[1] + r[2] * e1[2];
            uv[2 * p + 1] = r[0] * e2[0] + r[1] * e2[1] + r[2] * e2[2];
        }
    }
    start[count] = p;
    uint32_t *tri = NULL;
    double *extra = NULL;
    size_t nt = 0, nx = 0;
    sr_err ferr;
    sr_status st = sr_planar_fill(uv, start, count, &tri, &nt, &extra, &nx, &ferr);
    if (st == SR_E_NOMEM) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    if (st != SR_OK || nt == 0) {
        st = SR_OK; /* fanned instead */
        goto out;
    }
    /* orientation: each rim edge a -> b of the scan must be walked b -> a by the fill;
     * the fill's triangles are all counter-clockwise in (u, v), so one vote decides */
    long agree = 0;
    for (size_t i = 0; i < count; i++)
        for (size_t q = start[i]; q < start[i + 1]; q++) {
            uint32_t a = (uint32_t)q, b = (uint32_t)(q + 1 < start[i + 1] ? q + 1 : start[i]);
            for (size_t t = 0; t < nt; t++)
                for (int k = 0; k < 3; k++) {
                    if (tri[3 * t + k] == a && tri[3 * t + (k + 1) % 3] == b)
                        agree--;
                    else if (tri[3 * t + k] == b && tri[3 * t + (k + 1) % 3] == a)
                        agree++;
                }
            if (q - start[i] > 8)
                break; /* a few edges of each loop suffice */
        }
    if (agree < 0)
        for (size_t t = 0; t < nt; t++) {
            uint32_t x = tri[3 * t];
            tri[3 * t] = tri[3 * t + 2];
            tri[3 * t + 2] = x;
        }
    if (agree == 0 || nx > 0 || !fill_fits(tri, nt, start, count, vid))
        goto out; /* the loops cross in the plane, or fold: fanned instead */
    if (!grow_room(g, nx, nt)) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    for (size_t k = 0; k < nx; k++) {
        double *v = g->xyz + 3 * (g->nv + k);
        for (int j = 0; j < 3; j++)
            v[j] = c[j] + extra[2 * k] * e1[j] + extra[2 * k + 1] * e2[j];
    }
    for (size_t t = 0; t < nt; t++) {
        uint32_t *o = g->tri + 3 * (g->nt + t);
        for (int k = 0; k < 3; k++) {
            uint32_t x = tri[3 * t + k];
            o[k] = x < pts ? vid[x] : (uint32_t)(base_v + g->nv + (x - pts));
        }
    }
    g->nv += nx;
    g->nt += nt;
    *done = true;
out:
    free(tri);
    free(extra);
    free(uv);
    free(start);
    free(vid);
    return st;
}

sr_status sr_scan_close_openings(sr_mesh *mesh, const sr_scan_desc *d, double max_span_mm2,
                                 size_t *closed, sr_err *err)
{
    return sr_scan_close_openings_how(mesh, d, max_span_mm2, closed, NULL, err);
}

sr_status sr_scan_close_openings_how(sr_mesh *mesh, const sr_scan_desc *d, double max_span_mm2,
                                     size_t *closed, sr_scan_closing *how, sr_err *err)
{
    size_t nv = mesh->vertex_count, nt = mesh->tri_count, n_closed = 0;
    grow g = {0};
    sr_scan_closing *done = calloc(d->loop_count + 1, sizeof *done); /* how, as it goes */
    size_t *group = malloc((d->loop_count + 1) * sizeof *group);
    sr_status st = SR_OK;
    if (!done || !group) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        goto out;
    }
    for (size_t i = 0; i < d->loop_count && st == SR_OK; i++) {
        const sr_scan_loop *l = &d->loops[i];
        if (done[i] != SR_SCAN_LEFT_OPEN || !eligible(l, max_span_mm2))
            continue;
        double c[3], n[3];
        bool filled = false;
        if (l->span_mm >= PLANE_MIN_MM2 && loop_plane(mesh, d, l, c, n) &&
            on_plane(mesh, d, l, c, n)) {
            size_t count = 0;
            group[count++] = i;
            for (size_t j = i + 1; j < d->loop_count; j++) {
                double cj[3], nj[3];
                if (done[j] == SR_SCAN_LEFT_OPEN && eligible(&d->loops[j], max_span_mm2) &&
                    d->loops[j].span_mm >= PLANE_MIN_MM2 &&
                    loop_plane(mesh, d, &d->loops[j], cj, nj) &&
                    fabs(nj[0] * n[0] + nj[1] * n[1] + nj[2] * n[2]) >= SAME_PLANE_COS &&
                    on_plane(mesh, d, &d->loops[j], c, n))
                    group[count++] = j;
            }
            st = plane_fill(mesh, d, group, count, c, n, nv, &g, &filled, err);
            if (filled) {
                for (size_t k = 0; k < count; k++)
                    done[group[k]] = SR_SCAN_IN_PLANE;
                n_closed += count;
            }
        }
        if (st == SR_OK && !filled) {
            if (!fan(mesh, d, l, nv, &g))
                st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            done[i] = SR_SCAN_BY_FAN;
            n_closed++;
        }
    }
    if (st != SR_OK)
        goto out;
    if (nv + g.nv > SR_MESH_MAX_COUNT || nt + g.nt > SR_MESH_MAX_COUNT) {
        st = sr_err_set(err, SR_E_RANGE, "too many vertices to close the scan's openings");
        goto out;
    }
    if (g.nt > 0) {
        double *xyz = realloc(mesh->xyz, 3 * (nv + g.nv) * sizeof *xyz);
        if (!xyz) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            goto out;
        }
        mesh->xyz = xyz; /* same vertices, more room: the mesh is unchanged so far */
        uint32_t *tri = realloc(mesh->tri, 3 * (nt + g.nt) * sizeof *tri);
        if (!tri) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
            goto out;
        }
        mesh->tri = tri;
        memcpy(xyz + 3 * nv, g.xyz, 3 * g.nv * sizeof *xyz);
        memcpy(tri + 3 * nt, g.tri, 3 * g.nt * sizeof *tri);
        mesh->vertex_count = nv + g.nv;
        mesh->tri_count = nt + g.nt;
    }
    if (closed)
        *closed = n_closed;
    if (how)
        memcpy(how, done, d->loop_count * sizeof *how);
out:
    free(g.xyz);
    free(g.tri);
    free(done);
    free(group);
    return st;
}
