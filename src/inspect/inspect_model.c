/*
 * inspect_model.c: the reference an inspection measures against, as solids. A run
 * reconstructed with --no-union keeps its restored mesh as the scan and the patches
 * side by side, separate closed shells whose faces meet on the fracture surface. Those
 * hidden faces are no surface of the restored part: a scan of the part left damaged
 * lies on them (measured on the gouged bushing: a pass, 0 mm deep). Their union by
 * CGAL is refused there (the image method's patch touches the scan along its rim), so
 * the shells are kept apart and measured as a union without building it: the signed
 * distance to a union of solids is the least of the signed distances to each (exact
 * outside them; inside, the depth below the nearest shell's surface, which is the
 * depth below the restored surface but where a patch is thinner than the depth), and
 * scan \ (A u B) = (scan \ A) \ B for the volumes.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "align/surface_query.h"
#include "inspect/inspect_int.h"

static uint32_t root_of(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

typedef struct shell {
    uint32_t root;
    size_t tris;
    double volume;
} shell;

static int by_volume_desc(const void *pa, const void *pb)
{
    const shell *a = pa, *b = pb;
    return a->volume < b->volume ? 1 : a->volume > b->volume ? -1 : 0;
}

/* The triangles of m whose root is `root`, with the vertices they use, into *out. */
static sr_status shell_mesh(const sr_mesh *m, uint32_t *parent, uint32_t root, size_t tris,
                            uint32_t *map, sr_mesh *out)
{
    size_t nv = 0;
    for (size_t v = 0; v < m->vertex_count; v++)
        map[v] = root_of(parent, (uint32_t)v) == root ? (uint32_t)nv++ : UINT32_MAX;
    sr_status st = sr_mesh_alloc(out, nv, tris);
    if (st != SR_OK)
        return st;
    for (size_t v = 0; v < m->vertex_count; v++)
        if (map[v] != UINT32_MAX)
            memcpy(out->xyz + 3 * map[v], m->xyz + 3 * v, 3 * sizeof *m->xyz);
    size_t t = 0;
    for (size_t k = 0; k < m->tri_count; k++) {
        const uint32_t *f = m->tri + 3 * k;
        if (root_of(parent, f[0]) != root)
            continue;
        for (int i = 0; i < 3; i++)
            out->tri[3 * t + (size_t)i] = map[f[i]];
        t++;
    }
    return SR_OK;
}

sr_status ins_solid_shells(const sr_mesh *restored, sr_mesh **shells, size_t *count, sr_err *err)
{
    *shells = NULL;
    *count = 0;
    size_t nv = restored->vertex_count;
    uint32_t *parent = malloc((nv ? nv : 1) * sizeof *parent);
    uint32_t *map = malloc((nv ? nv : 1) * sizeof *map);
    shell *tab = calloc(nv ? nv : 1, sizeof *tab), *sh = calloc(nv ? nv : 1, sizeof *sh);
    if (!parent || !map || !tab || !sh) {
        free(tab);
        free(parent);
        free(map);
        free(sh);
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    }
    for (size_t v = 0; v < nv; v++)
        parent[v] = (uint32_t)v;
    for (size_t t = 0; t < restored->tri_count; t++) {
        const uint32_t *f = restored->tri + 3 * t;
        for (int k = 1; k < 3; k++) {
            uint32_t a = root_of(parent, f[0]), b = root_of(parent, f[k]);
            if (a != b)
                parent[a] = b;
        }
    }
    /* per root: triangles and enclosed volume (slot = the root's index) */
    for (size_t t = 0; t < restored->tri_count; t++) {
        const uint32_t *f = restored->tri + 3 * t;
        const double *a = restored->xyz + 3 * f[0], *b = restored->xyz + 3 * f[1],
                     *c = restored->xyz + 3 * f[2];
        uint32_t r = root_of(parent, f[0]);
        tab[r].root = r;
        tab[r].tris++;
        tab[r].volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                          a[2] * (b[0] * c[1] - b[1] * c[0])) /
                         6;
    }
    size_t n = 0;
    for (size_t v = 0; v < nv; v++)
        if (tab[v].tris > 0 && tab[v].volume > 0)
            sh[n++] = tab[v];
    sr_status st = SR_OK;
    sr_mesh *out = NULL;
    if (n >= 2) {
        qsort(sh, n, sizeof *sh, by_volume_desc);
        out = calloc(n, sizeof *out);
        st = out ? SR_OK : SR_E_NOMEM;
        for (size_t k = 0; st == SR_OK && k < n; k++)
            st = shell_mesh(restored, parent, sh[k].root, sh[k].tris, map, &out[k]);
        if (st == SR_OK) {
            *shells = out;
            *count = n;
        } else {
            for (size_t k = 0; out && k < n; k++)
                sr_mesh_release(&out[k]);
            free(out);
        }
    }
    free(parent);
    free(map);
    free(tab);
    free(sh);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory");
    return SR_OK;
}

/* 1 when p lies inside the closed, outward-oriented mesh m: its winding number about
 * p (the triangles' solid angles, Van Oosterom and Strackee 1983) above one half. Not
 * from the closest triangle's normal, which at the sharp rim of a thin patch can point
 * away from points far behind it. O(m's triangles); lo, hi its bounding box. */
static bool inside_solid(const sr_mesh *m, const double lo[3], const double hi[3],
                         const double p[3])
{
    for (int k = 0; k < 3; k++)
        if (p[k] < lo[k] || p[k] > hi[k])
            return false;
    double w = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = m->xyz[3 * f[0] + k] - p[k];
            b[k] = m->xyz[3 * f[1] + k] - p[k];
            c[k] = m->xyz[3 * f[2] + k] - p[k];
        }
        double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        double dab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        double dbc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
        double dca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
        w += 2 * atan2(det, la * lb * lc + dab * lc + dbc * la + dca * lb);
    }
    return w / (4 * M_PI) > 0.5;
}

sr_status ins_visible_surface(const sr_mesh *solids, size_t n, sr_mesh *out, sr_err *err)
{
    sr_mesh_init(out);
    sr_surface_query **q = calloc(n, sizeof *q);
    double(*box)[6] = calloc(n, sizeof *box);
    size_t verts = 0, tris = 0, built = 0;
    sr_status st = q && box ? SR_OK : sr_err_set(err, SR_E_NOMEM, "out of memory");
    for (; st == SR_OK && built < n; built++) {
        st = sr_surface_query_build(&solids[built], &q[built], err);
        sr_mesh_bbox(&solids[built], box[built], box[built] + 3);
        verts += solids[built].vertex_count;
        tris += solids[built].tri_count;
    }
    if (st == SR_OK && sr_mesh_alloc(out, verts, tris) != SR_OK)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory");
    size_t nv = 0, nt = 0;
    for (size_t k = 0; st == SR_OK && k < n; k++) {
        const sr_mesh *m = &solids[k];
        memcpy(out->xyz + 3 * nv, m->xyz, 3 * m->vertex_count * sizeof *m->xyz);
        const double *lo = box[k], *hi = box[k] + 3;
        /* on another solid's surface: within rounding of the solid's size */
        double on =
            1e-6 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                        (hi[2] - lo[2]) * (hi[2] - lo[2])) +
            1e-9;
        for (size_t t = 0; t < m->tri_count; t++) {
            const uint32_t *f = m->tri + 3 * t;
            double c[3];
            for (int i = 0; i < 3; i++)
                c[i] = (m->xyz[3 * f[0] + i] + m->xyz[3 * f[1] + i] + m->xyz[3 * f[2] + i]) / 3;
            bool hidden = false;
            for (size_t j = 0; j < n && !hidden; j++) {
                double d, sd;
                if (j == k || !sr_surface_query_closest(q[j], c, INFINITY, NULL, &d, &sd))
                    continue;
                /* the largest solid (the scan) signed by its closest triangle, as one
                 * restored surface is; the patches by their winding number */
                hidden =
                    d <= on || (j == 0 ? sd < 0 : inside_solid(&solids[j], box[j], box[j] + 3, c));
            }
            if (hidden)
                continue;
            for (int i = 0; i < 3; i++)
                out->tri[3 * nt + (size_t)i] = f[i] + (uint32_t)nv;
            nt++;
        }
        nv += m->vertex_count;
    }
    for (size_t k = 0; k < built; k++)
        sr_surface_query_free(q[k]);
    free(q);
    free(box);
    if (st != SR_OK) {
        sr_mesh_release(out);
        return st;
    }
    out->tri_count = nt;
    return SR_OK;
}
