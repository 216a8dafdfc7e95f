/*
 * scan_peel.c: the folds of a scan peeled off the planes of its openings when closing
 * them as they are does not close it (scan_describe.h: sr_scan_peel_folds, and
 * sr_scan_close_peeling, which describes, closes and drops strays, and peels and closes
 * again only when the first closing left edges used other than twice or fanned a plane
 * loop). Where the face a
 * part stood on is cut away, the scanner keeps what it saw of it at a slant: slivers of
 * that face lying in its plane but facing sideways or into the part (a few hundredths of
 * a millimetre wide, turned over by the noise), in strips joined to the rest of the
 * surface at a vertex, so no island. The plane's fill would have to cover such a strip
 * twice, which no triangulation of the rims does: the face was then closed by a fan
 * from its centroid, and the rim walked through the strip's vertex twice made the fan's
 * edges there used four times (the generated flange s60221409p13, whose chip reached
 * its base: 11 non-manifold edges; the image method's boolean refused the scan, so no
 * section was found). A sliver lying in the plane holds no volume whichever way it
 * faces, so it goes: each triangle on the rim of a planar group (scan_int.h) whose
 * corners all lie within the rims' noise of its plane and whose normal turns more than
 * FACING_DEG off the way the plane's fill faces (into the part), then the next such triangle on the rim
 * so grown. First only the planes whose fill failed (their first loop fanned), then
 * every plane (a fill that fits can still run along a fold's edge); a peeled closing
 * is kept when it leaves fewer edges used other than twice, or as few and no plane
 * loop fanned.
 * A face the scan kept facing out, and every wall standing off the plane, stay.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/scan_int.h"

/* A triangle in a plane facing farther than this off the fill's outward normal is a
 * fold (degrees): a sliver of the face turned into the part by the noise, not the face
 * (45, peeling the slivers turned sideways too, also peeled walls' slivers at the base
 * of a spline, 3292 triangles, and cost its restoration 2.9 mm of Hausdorff). */
#define FACING_DEG 90.0
/* sr_scan_peel_plane_rims: a triangle in a plane facing within this many degrees of
 * either way across it is a scrap of the face (kept scraps were seen tilted up to 84
 * degrees by the noise, on triangles of a few hundredths of a mm^2); one turned further
 * (sideways) is a wall's, whose lowest row lies within the rims' noise of the plane too,
 * and stays (peeled, the rim of a collar's bore rose off the plane and was fanned). */
#define FLAT_DEG 80.0
/* The rims' noise: a triangle lies in a plane when its corners lie within this many
 * times the rms distance of the group's rim vertices from it (at least
 * SR_SCAN_PLANE_RMS_MM, at most SR_SCAN_PLANE_MAX_MM). */
#define NOISE_TIMES 3.0

typedef struct plane {
    double c[3], out[3]; /* a point, the fill's outward unit normal */
    double tol;          /* mm */
    double span_mm2;     /* the openings of its group */
    double peeled_mm2;   /* the area peeled off it */
} plane;

typedef struct edge_use {
    uint64_t key; /* lo << 32 | hi */
    uint32_t t;   /* triangle */
} edge_use;

static bool stray(const sr_scan_desc *d, size_t t)
{
    return t < d->triangles && d->components[d->tri_component[t]].stray;
}

/* The plane of group (count loops, plane c, n): its fill faces against the rims' walk,
 * that is against the sum of the loops' vector areas (an outer rim's against its bores'). */
static bool group_plane(const sr_mesh *mesh, const sr_scan_desc *d, const size_t *group,
                        size_t count, const double c[3], const double n[3], plane *p)
{
    double area = 0, ss = 0;
    size_t nv = 0;
    for (size_t k = 0; k < count; k++) {
        const sr_scan_loop *l = &d->loops[group[k]];
        double ck[3], nk[3];
        if (sr_scan_loop_plane(mesh, d, l, ck, nk))
            area += (nk[0] * n[0] + nk[1] * n[1] + nk[2] * n[2] > 0 ? 1 : -1) * l->span_mm;
        for (size_t e = 0; e < l->edges; e++) {
            const double *q = mesh->xyz + 3 * (size_t)d->loop_verts[l->first + e];
            double h = (q[0] - c[0]) * n[0] + (q[1] - c[1]) * n[1] + (q[2] - c[2]) * n[2];
            ss += h * h;
            nv++;
        }
    }
    if (area == 0 || nv == 0)
        return false;
    memcpy(p->c, c, sizeof p->c);
    for (int k = 0; k < 3; k++)
        p->out[k] = area > 0 ? -n[k] : n[k];
    p->tol =
        fmin(SR_SCAN_PLANE_MAX_MM, fmax(SR_SCAN_PLANE_RMS_MM, NOISE_TIMES * sqrt(ss / (double)nv)));
    return true;
}

/* How a triangle lying in a plane is peeled: when the cosine of its normal with the
 * fill's outward normal is below `below` (facing into the part), or when its magnitude
 * is at least `flat` (facing either way across the plane, not sideways as a wall's).
 * capped: a plane is peeled only when what comes off it is smaller than its openings
 * (scraps of a face the scanner lost; peeled from the rims of a few pinholes in a face
 * it saw, a gear's whole top face went, and was fanned: 9.9 mm of Hausdorff). */
typedef struct facing_rule {
    double below, flat;
    bool capped;
    bool by_vertex; /* grown through corners, not only across edges left on the rim: the
                     * scraps are joined to the rim and to one another at vertices, and a
                     * strip of them one sliver wide was seen left between two peeled
                     * ones, walked out and back by the rim, its fill then failing */
} facing_rule;

/* 1 + the plane of pl that triangle t lies in facing as rule peels; 0: none. */
static uint32_t folded(const sr_mesh *mesh, size_t t, const plane *pl, size_t np, facing_rule rule)
{
    double nt[3];
    sr_mesh_tri_normal(mesh, t, nt);
    double len = sqrt(nt[0] * nt[0] + nt[1] * nt[1] + nt[2] * nt[2]);
    for (size_t i = 0; i < np; i++) {
        const plane *p = &pl[i];
        bool in = true;
        for (int k = 0; k < 3 && in; k++) {
            const double *q = mesh->xyz + 3 * (size_t)mesh->tri[3 * t + k];
            in = fabs((q[0] - p->c[0]) * p->out[0] + (q[1] - p->c[1]) * p->out[1] +
                      (q[2] - p->c[2]) * p->out[2]) <= p->tol;
        }
        double facing =
            len > 0 ? (nt[0] * p->out[0] + nt[1] * p->out[1] + nt[2] * p->out[2]) / len : 0;
        if (in && (facing < rule.below || fabs(facing) >= rule.flat))
            return (uint32_t)i + 1;
    }
    return 0;
}

/* The index of key in the n sorted keys, n when absent. */
static size_t key_at(const uint64_t *keys, size_t n, uint64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (keys[mid] < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && keys[lo] == key ? lo : n;
}

/* sr_scan_peel_folds and sr_scan_peel_plane_rims: the triangles lying in a chosen plane
 * and facing as rule peels, peeled from its rim. Only those triangles (the folds, a
 * few thousand of a million) are indexed: their edges, each edge's uses by folds, and
 * how many triangles of the scan use it; a scan of a million triangles indexed all of
 * its edges four times over (190 MB) for them. */
static sr_status peel(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                      facing_rule rule, size_t *peeled, sr_err *err)
{
    size_t nt = mesh->tri_count, nv = mesh->vertex_count, np = 0, removed = 0, nq = 0, nf = 0;
    sr_status st = SR_OK;
    sr_scan_closing *done = calloc(d->loop_count + 1, sizeof *done);
    size_t *group = malloc((d->loop_count + 1) * sizeof *group);
    plane *pl = malloc((d->loop_count + 1) * sizeof *pl);
    bool *gone = calloc(nt + 1, sizeof *gone);
    uint32_t *fold = calloc(nt + 1, sizeof *fold); /* 1 + the plane a triangle peels off */
    bool *rimv = calloc(nv + 1, sizeof *rimv);     /* the chosen groups' rims */
    bool *queued = calloc(nt + 1, sizeof *queued);
    uint32_t *folds = NULL, *queue = NULL, *live = NULL, *vt = NULL;
    edge_use *use = NULL;
    uint64_t *key = NULL;
    size_t *first = NULL, *tri_edge = NULL, *vt_first = NULL, *local = NULL;
    bool *at_fold = NULL;
    if (!done || !group || !pl || !gone || !fold || !rimv || !queued) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory peeling the scan's folds");
        goto out;
    }
    for (size_t i = 0; i < d->loop_count; i++) {
        double c[3], n[3];
        bool chosen = done[i] == SR_SCAN_LEFT_OPEN && (!how || how[i] == SR_SCAN_BY_FAN);
        size_t count = chosen ? sr_scan_plane_group(mesh, d, i, done, 0, group, c, n) : 0;
        double span = 0;
        for (size_t k = 0; k < count; k++) {
            const sr_scan_loop *l = &d->loops[group[k]];
            span += l->span_mm;
            done[group[k]] = SR_SCAN_IN_PLANE;
            for (size_t e = 0; e < l->edges; e++)
                rimv[d->loop_verts[l->first + e]] = true;
        }
        if (count > 0 && group_plane(mesh, d, group, count, c, n, &pl[np])) {
            pl[np].span_mm2 = span;
            pl[np++].peeled_mm2 = 0;
        }
    }
    if (np == 0)
        goto out;
    for (size_t t = 0; t < nt; t++)
        if (!stray(d, t) && (fold[t] = folded(mesh, t, pl, np, rule)) != 0)
            nf++;
    if (nf == 0)
        goto out;
    /* the folds (in order), their edges' uses sorted by edge then triangle, the edges */
    folds = malloc(nf * sizeof *folds);
    local = malloc((nt + 1) * sizeof *local); /* a fold's place in folds */
    use = malloc(3 * nf * sizeof *use);
    key = malloc(3 * nf * sizeof *key);
    first = malloc((3 * nf + 1) * sizeof *first); /* each edge's first use */
    live = calloc(3 * nf + 1, sizeof *live);      /* per edge: the scan's triangles on it */
    tri_edge = malloc(3 * nf * sizeof *tri_edge);
    queue = malloc((5 * nf + 1) * sizeof *queue); /* in once, once per edge, once by corner */
    at_fold = calloc(nv + 1, sizeof *at_fold);    /* a corner of a fold */
    if (!folds || !local || !use || !key || !first || !live || !tri_edge || !queue || !at_fold) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory peeling the scan's folds");
        goto out;
    }
    size_t nu = 0;
    for (size_t t = 0, f = 0; t < nt; t++) {
        if (!fold[t])
            continue;
        local[t] = f;
        folds[f++] = (uint32_t)t;
        for (int k = 0; k < 3; k++) {
            uint64_t a = mesh->tri[3 * t + k], b = mesh->tri[3 * t + (k + 1) % 3];
            at_fold[a] = true;
            use[nu++] = (edge_use){a < b ? a << 32 | b : b << 32 | a, (uint32_t)t};
        }
    }
    st = sr_scan_sort_edges(use, nu, sizeof *use, nv); /* by key, then t */
    if (st != SR_OK) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory peeling the scan's folds");
        goto out;
    }
    size_t ne = 0;
    for (size_t u = 0; u < nu; u++)
        if (u == 0 || use[u].key != use[u - 1].key) {
            first[ne] = u;
            key[ne++] = use[u].key;
        }
    first[ne] = nu;
    /* how many of the scan's triangles (strays aside) use each such edge */
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *c = mesh->tri + 3 * t;
        if (stray(d, t) || !(at_fold[c[0]] || at_fold[c[1]] || at_fold[c[2]]))
            continue;
        for (int k = 0; k < 3; k++) {
            uint64_t a = c[k], b = c[(k + 1) % 3];
            size_t e = key_at(key, ne, a < b ? a << 32 | b : b << 32 | a);
            if (e < ne)
                live[e]++;
        }
    }
    /* each fold's three edges, in the order of the edges */
    size_t *fill = calloc(nf + 1, sizeof *fill);
    if (!fill) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory peeling the scan's folds");
        goto out;
    }
    for (size_t e = 0; e < ne; e++)
        for (size_t u = first[e]; u < first[e + 1]; u++) {
            size_t f = local[use[u].t];
            if (fill[f] < 3)
                tri_edge[3 * f + fill[f]++] = e;
        }
    for (size_t f = 0; f < nf; f++) {
        size_t t = folds[f];
        bool rim = false; /* an edge on a chosen group's rim (by_vertex: a corner) */
        for (int k = 0; fill[f] == 3 && k < 3; k++) {
            uint64_t ek = key[tri_edge[3 * f + k]];
            rim |= rule.by_vertex
                       ? rimv[mesh->tri[3 * t + k]]
                       : live[tri_edge[3 * f + k]] == 1 && rimv[ek >> 32] && rimv[ek & UINT32_MAX];
        }
        if (rim) {
            queue[nq++] = (uint32_t)t;
            queued[t] = true;
        }
    }
    free(fill);
    if (rule.by_vertex) { /* each vertex's folds, in order */
        vt_first = calloc(nv + 2, sizeof *vt_first);
        vt = malloc((3 * nf + 1) * sizeof *vt);
        size_t *vt_fill = calloc(nv + 1, sizeof *vt_fill);
        if (!vt_first || !vt || !vt_fill) {
            free(vt_fill);
            st = sr_err_set(err, SR_E_NOMEM, "out of memory peeling the scan's folds");
            goto out;
        }
        for (size_t f = 0; f < nf; f++)
            for (int k = 0; k < 3; k++)
                vt_first[mesh->tri[3 * (size_t)folds[f] + k] + 1]++;
        for (size_t v = 0; v < nv; v++)
            vt_first[v + 1] += vt_first[v];
        for (size_t f = 0; f < nf; f++)
            for (int k = 0; k < 3; k++) {
                uint32_t v = mesh->tri[3 * (size_t)folds[f] + k];
                vt[vt_first[v] + vt_fill[v]++] = folds[f];
            }
        free(vt_fill);
    }
    while (nq > 0) {
        uint32_t t = queue[--nq];
        if (gone[t])
            continue;
        gone[t] = true;
        removed++;
        double a[3];
        sr_mesh_tri_normal(mesh, t, a);
        pl[fold[t] - 1].peeled_mm2 += 0.5 * sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (int k = 0; k < 3; k++) {
            size_t e = tri_edge[3 * local[t] + k];
            if (--live[e] != 1 || rule.by_vertex)
                continue;
            for (size_t u = first[e]; u < first[e + 1]; u++) /* its neighbour now on the rim */
                if (!gone[use[u].t])
                    queue[nq++] = use[u].t;
        }
        for (int k = 0; rule.by_vertex && k < 3; k++) { /* every fold at its corners */
            uint32_t v = mesh->tri[3 * (size_t)t + k];
            for (size_t j = vt_first[v]; j < vt_first[v + 1]; j++)
                if (!gone[vt[j]] && !queued[vt[j]]) {
                    queued[vt[j]] = true;
                    queue[nq++] = vt[j];
                }
        }
    }
    for (size_t t = 0; rule.capped && t < nt; t++)
        if (gone[t] && pl[fold[t] - 1].peeled_mm2 > pl[fold[t] - 1].span_mm2) {
            gone[t] = false; /* more than its openings: a face the scanner saw */
            removed--;
        }
    if (removed > 0)
        st = sr_scan_drop_triangles(mesh, gone, err);
out:
    if (st == SR_OK && peeled)
        *peeled = removed;
    free(done);
    free(group);
    free(pl);
    free(gone);
    free(fold);
    free(rimv);
    free(queued);
    free(folds);
    free(local);
    free(use);
    free(key);
    free(first);
    free(live);
    free(tri_edge);
    free(queue);
    free(at_fold);
    free(vt_first);
    free(vt);
    return st;
}

sr_status sr_scan_peel_folds(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                             size_t *peeled, sr_err *err)
{
    return peel(mesh, d, how, (facing_rule){cos(FACING_DEG * M_PI / 180), 2, false, false}, peeled,
                err);
}

sr_status sr_scan_peel_plane_rims(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                                  size_t *peeled, sr_err *err)
{
    return peel(mesh, d, how,
                (facing_rule){cos(FACING_DEG * M_PI / 180), cos(FLAT_DEG * M_PI / 180), true, true},
                peeled, err);
}

/* a plane loop fanned under this share of the largest opening's span is a speck */
#define SPECK_SHARE 0.01

/* What a closing left wrong, worst first: edges of the result used other than twice
 * (once each way), loops lying in a plane closed by a fan (the plane's fill did not fit;
 * specks not counted) with their span, and the span of every loop closed by a fan
 * (mm^2: a fan strays from the part as far as its opening is wide; a base fanned cost a
 * gear 9.9 mm of Hausdorff, a dozen pinholes fanned cost nothing). */
typedef sr_scan_closing_cost closing_cost;

/* mesh described, closed (every opening) and rid of its strays, in place, with the walls
 * lost beside its planes hung back first when hang (*hung: the loops so hung); *c gets
 * what the closing left wrong (closing_cost). On error d and *how are freed. */
static sr_status close_as(sr_mesh *mesh, bool hang, sr_mesh *unhung, sr_scan_desc *d,
                          sr_scan_closing **how, closing_cost *c, size_t *hung_out, sr_err *err)
{
    *how = NULL;
    sr_status st = sr_scan_describe(mesh, NULL, d, err);
    if (st != SR_OK)
        return st;
    size_t hung = 0, nv = mesh->vertex_count, nt = mesh->tri_count;
    if (hang)
        st = sr_scan_hang_curtains(mesh, d, &hung, err);
    /* the walls hung are appended: the mesh before them is the first nv vertices and nt
     * triangles (copied only when a wall was hung, not ahead of every closing) */
    if (st == SR_OK && hung > 0 && unhung) {
        st = sr_mesh_alloc(unhung, nv, nt);
        if (st == SR_OK) {
            memcpy(unhung->xyz, mesh->xyz, 3 * nv * sizeof *mesh->xyz);
            memcpy(unhung->tri, mesh->tri, 3 * nt * sizeof *mesh->tri);
        } else {
            st = sr_err_set(err, st, "out of memory closing the scan's openings");
        }
    }
    *hung_out = hung;
    if (st == SR_OK && hung > 0) { /* the walls hung change the loops */
        sr_scan_desc_release(d);
        st = sr_scan_describe(mesh, NULL, d, err);
        if (st != SR_OK)
            return st;
    }
    if (st != SR_OK) {
        sr_scan_desc_release(d);
        return st;
    }
    *how = calloc(d->loop_count + 1, sizeof **how);
    if (!*how)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    if (st == SR_OK)
        st = sr_scan_close_openings_how(mesh, d, 0, NULL, *how, err);
    size_t *group = st == SR_OK ? malloc((d->loop_count + 1) * sizeof *group) : NULL;
    if (st == SR_OK && !group)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    /* plane loops fanned: their fill did not fit (the loops' vertices kept); a fan of a
     * speck (under a hundredth of the largest opening's span: a hole's few triangles
     * left beside a wall hung back) costs the part nothing */
    double top = 0;
    for (size_t i = 0; i < d->loop_count; i++)
        top = d->loops[i].span_mm > top ? d->loops[i].span_mm : top;
    *c = (closing_cost){0, 0, 0, 0};
    for (size_t i = 0; st == SR_OK && i < d->loop_count; i++) {
        double pc[3], pn[3];
        c->fan_mm2 += (*how)[i] == SR_SCAN_BY_FAN ? d->loops[i].span_mm : 0;
        bool plane_fan = (*how)[i] == SR_SCAN_BY_FAN && d->loops[i].span_mm >= SPECK_SHARE * top &&
                         sr_scan_plane_group(mesh, d, i, NULL, 0, group, pc, pn) > 0;
        c->plane_fans += plane_fan;
        c->plane_fan_mm2 += plane_fan ? d->loops[i].span_mm : 0;
    }
    free(group);
    if (st == SR_OK)
        st = sr_scan_drop_strays(mesh, d, err);
    sr_mesh_edges es = {0};
    if (st == SR_OK && sr_mesh_edge_stats(mesh, &es) != SR_OK)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
    if (st != SR_OK) {
        sr_scan_desc_release(d);
        free(*how);
        *how = NULL;
        return st;
    }
    c->bad_edges = es.boundary_edges + es.nonmanifold_edges + es.misoriented_edges;
    return SR_OK;
}

/* close_as with the lost walls hung back, kept when that leaves no more edges bad and
 * fans less than the closing without them (a wall hung from a hole beside a
 * small face can make that face's fill fail, where its fans cost nothing). */
static sr_status close_once(sr_mesh *mesh, sr_scan_desc *d, sr_scan_closing **how, closing_cost *c,
                            sr_err *err)
{
    sr_mesh plain = {0}; /* the mesh as given, when close_as hung walls */
    size_t hung = 0, unused = 0;
    sr_status st = close_as(mesh, true, &plain, d, how, c, &hung, err);
    if (st == SR_OK && hung > 0) {
        sr_scan_desc d2 = {0};
        sr_scan_closing *h2 = NULL;
        closing_cost c2;
        st = close_as(&plain, false, NULL, &d2, &h2, &c2, &unused, err);
        if (st == SR_OK && (c2.bad_edges < c->bad_edges ||
                            (c2.bad_edges == c->bad_edges && c2.fan_mm2 <= c->fan_mm2))) {
            sr_mesh_release(mesh);
            *mesh = plain;
            plain = (sr_mesh){0};
            sr_scan_desc_release(d);
            free(*how);
            *d = d2;
            *how = h2;
            *c = c2;
        } else {
            sr_scan_desc_release(&d2);
            free(h2);
        }
        if (st != SR_OK) {
            sr_scan_desc_release(d);
            free(*how);
            *how = NULL;
        }
    }
    sr_mesh_release(&plain);
    return st;
}

/* One pass of sr_scan_close_peeling: the scan as it came (orig, described d0, closed
 * first as h0 says) copied and peeled (pass 0: the folds off the planes whose fill
 * failed, 1: off every plane, 2: the plane rims' scraps) or untwisted (-1). Made again
 * rather than kept when close_untwisting needs it once more: a mesh's copy fewer through
 * the closing (a 1.85M-triangle open scan's peak). *n: the triangles peeled (vertices
 * merged for -1). */
typedef struct peel_pass {
    const sr_mesh *orig;
    const sr_scan_desc *d0;
    const sr_scan_closing *h0;
    int pass;
} peel_pass;

static sr_status peel_pass_make(const peel_pass *p, sr_mesh *m, size_t *n, sr_err *err)
{
    sr_status st = sr_mesh_copy(m, p->orig);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory closing the scan's openings");
    return p->pass == 2   ? sr_scan_peel_plane_rims(m, p->d0, p->h0, n, err)
           : p->pass == 1 ? sr_scan_peel_folds(m, p->d0, NULL, n, err)
           : p->pass == 0 ? sr_scan_peel_folds(m, p->d0, p->h0, n, err)
                          : sr_scan_uncurl_rims(m, p->d0, p->h0, n, err);
}

/* close_once on mesh (pass p's, as peel_pass_make made it), and when a plane's fill still
 * failed, that mesh made again, untwisted (sr_scan_uncurl_rims, on every plane's rims)
 * and closed again, kept when that is better: fewer edges left bad, or as few and fewer
 * plane loops fanned. *uncurled gets the vertices merged away in what is kept. */
static sr_status close_untwisting(sr_mesh *mesh, const peel_pass *p, sr_scan_desc *d,
                                  sr_scan_closing **h, closing_cost *c, size_t *uncurled,
                                  sr_err *err)
{
    sr_mesh m = {0};
    sr_scan_desc dm = {0}, d2 = {0};
    sr_scan_closing *h2 = NULL;
    closing_cost c2 = {0, 0, 0, 0};
    size_t merged = 0, peeled = 0;
    *uncurled = 0;
    sr_status st = close_once(mesh, d, h, c, err);
    if (st == SR_OK && c->plane_fans > 0) {
        st = peel_pass_make(p, &m, &peeled, err);
        if (st == SR_OK)
            st = sr_scan_describe(&m, NULL, &dm, err);
        if (st == SR_OK)
            st = sr_scan_uncurl_rims(&m, &dm, NULL, &merged, err);
        if (st == SR_OK && merged > 0)
            st = close_once(&m, &d2, &h2, &c2, err);
        if (st == SR_OK && merged > 0 &&
            (c2.bad_edges < c->bad_edges ||
             (c2.bad_edges == c->bad_edges && c2.plane_fans < c->plane_fans))) {
            sr_mesh_release(mesh);
            *mesh = m;
            m = (sr_mesh){0};
            sr_scan_desc_release(d);
            free(*h);
            *d = d2;
            *h = h2;
            d2 = (sr_scan_desc){0};
            h2 = NULL;
            *c = c2;
            *uncurled = merged;
        }
    }
    sr_mesh_release(&m);
    sr_scan_desc_release(&dm);
    sr_scan_desc_release(&d2);
    free(h2);
    return st;
}

/* One pass made and closed (peel_pass_make, then close_once for -1, close_untwisting for
 * the peels), with what it left wrong; st and err its outcome. */
typedef struct pass_result {
    peel_pass pp;
    sr_mesh m;
    sr_scan_desc d;
    sr_scan_closing *h;
    closing_cost bad;
    size_t n, un; /* triangles peeled (vertices merged for -1); vertices uncurled */
    sr_status st;
    sr_err err;
} pass_result;

static void run_pass(pass_result *r)
{
    r->st = peel_pass_make(&r->pp, &r->m, &r->n, &r->err);
    r->un = r->pp.pass < 0 ? r->n : 0;
    if (r->st == SR_OK && r->n > 0)
        r->st = r->pp.pass < 0
                    ? close_once(&r->m, &r->d, &r->h, &r->bad, &r->err)
                    : close_untwisting(&r->m, &r->pp, &r->d, &r->h, &r->bad, &r->un, &r->err);
}

bool sr_scan_peel_kept(int pass, const sr_scan_closing_cost *was, const sr_scan_closing_cost *now,
                       double top_mm2)
{
    if (pass >= 2)
        return now->plane_fans == 0 && now->bad_edges <= was->bad_edges &&
               now->fan_mm2 < was->fan_mm2;
    /* fewer edges left bad, but not by fanning an opening that was filled: a peel that
     * lifted a base's rim off its plane had the whole base fanned (2,717 mm^2, across
     * its bores) to mend one edge, 9.7 mm of Hausdorff (s1346269p06, open) */
    bool fans_more = now->fan_mm2 > was->fan_mm2 + SPECK_SHARE * top_mm2;
    return (now->bad_edges < was->bad_edges && !fans_more) ||
           (now->bad_edges == was->bad_edges && now->plane_fans == 0 && was->plane_fans > 0 &&
            now->fan_mm2 < was->fan_mm2 - 0.5 * was->plane_fan_mm2);
}

sr_status sr_scan_close_peeling(sr_mesh *mesh, sr_scan_desc *out, sr_scan_closing **how,
                                size_t *peeled, sr_err *err)
{
    sr_mesh orig = {0};
    sr_scan_desc d = {0};
    sr_scan_closing *h = NULL;
    closing_cost bad = {0, 0, 0, 0};
    size_t n_kept = 0;
    sr_status st = sr_mesh_copy(&orig, mesh);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory closing the scan's openings");
    st = close_once(mesh, &d, &h, &bad, err);
    sr_scan_closing *h0 = NULL; /* the first closing's, for the passes on the scan as it came */
    const bool plane_failed =
        bad.plane_fans > 0; /* the rim peel's planes are the first closing's */
    if (st == SR_OK && (bad.bad_edges > 0 || bad.plane_fans > 0)) {
        h0 = malloc((d.loop_count + 1) * sizeof *h0);
        if (!h0)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory closing the scan's openings");
        else
            memcpy(h0, h, d.loop_count * sizeof *h0);
    }
    /* not closed, or a plane's fill failed (its loops fanned, over the folds): the folds
     * peeled off the planes whose fill failed, then off every plane (a fill that fits
     * may still run along a fold's edge); kept when fewer edges are left used other
     * than twice, or as few and every plane then filled, the span fanned falling by at
     * least half the span the planes fanned (a peel that leaves some plane fanned still
     * was seen to cost a spline's restoration 2.9 mm of Hausdorff; one that lifted a
     * gear's base rim off its plane was not counted a plane fanned, and its fan across
     * the bore cost 1.4 mm: s16180p05, open); last,
     * when a plane's fill still fails, every scrap lying in the planes whose fill failed
     * peeled off their rims, whichever way it faces, kept only when then every plane
     * fills, no more edges are left bad and fewer rim edges are fanned (peeled up its
     * walls, a rail's whole base was fanned, closer to manifold, and the rail read as
     * not fitting its glide: s1123581p03). Before them all, when a plane's fill failed,
     * the rims of those planes untwisted alone (sr_scan_uncurl_rims), kept as the peels
     * are; each peel's closing is itself untwisted when a plane still fails
     * (close_untwisting). */
    sr_scan_desc d0 = {0};
    size_t uncurled = 0;
    int passes[4], np = 0;
    for (int pass = -1; pass < 3; pass++)
        if (plane_failed || (pass != 2 && pass >= 0)) /* else nothing to untwist, no rim */
            passes[np++] = pass;
    bool open = bad.bad_edges > 0 || bad.plane_fans > 0;
    if (st == SR_OK && open) /* the scan as it came, described once for every pass */
        st = sr_scan_describe(&orig, NULL, &d0, err);
    double top = 0; /* the largest opening of the scan as it came */
    for (size_t i = 0; st == SR_OK && open && i < d0.loop_count; i++)
        top = d0.loops[i].span_mm > top ? d0.loops[i].span_mm : top;
    for (int i = 0; st == SR_OK && open && i < np; i++) {
        pass_result r;
        memset(&r, 0, sizeof r);
        r.pp = (peel_pass){&orig, &d0, h0, passes[i]};
        run_pass(&r);
        st = r.st;
        if (st != SR_OK && err)
            *err = r.err;
        if (st == SR_OK && r.n > 0 && sr_scan_peel_kept(r.pp.pass, &bad, &r.bad, top)) {
            sr_mesh_release(mesh);
            *mesh = r.m;
            r.m = (sr_mesh){0};
            sr_scan_desc_release(&d);
            free(h);
            d = r.d;
            h = r.h;
            r.d = (sr_scan_desc){0};
            r.h = NULL;
            bad = r.bad;
            n_kept = r.pp.pass < 0 ? 0 : r.n;
            uncurled = r.un;
        }
        open = bad.bad_edges > 0 || bad.plane_fans > 0;
        sr_mesh_release(&r.m);
        sr_scan_desc_release(&r.d);
        free(r.h);
    }
    sr_scan_desc_release(&d0);
    free(h0);
    size_t sealed = 0;
    if (st == SR_OK && bad.bad_edges > 0)
        st = sr_scan_seal(mesh, &sealed, err);
    d.sealed_triangles = sealed;
    d.uncurled_vertices = uncurled;
    if (st == SR_OK && d.loop_count > 0)
        st = sr_scan_fill_triangles(&orig, mesh, &d.fills, err);
    sr_mesh_release(&orig);
    if (st != SR_OK) {
        sr_scan_desc_release(&d);
        free(h);
        return st;
    }
    *out = d;
    *how = h;
    if (peeled)
        *peeled = n_kept;
    return SR_OK;
}
