/*
 * mesh_shells.c: shells of a mesh and the removal of small voids (see mesh_shells.h).
 * Shells by union-find over the vertices of each triangle (path halving, union by
 * index), each shell's signed volume summed from its triangles' tetrahedra against the
 * mesh's bounding-box centre (as sr_mesh_volume, so a shell's figure does not depend on
 * where the part sits). Linear in the mesh.
 */
#include "mesh/mesh_shells.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static uint32_t find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void join(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = find(parent, a);
    b = find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

/* Each vertex's shell (find(parent, v), its lowest vertex) and each root's signed
 * volume (volume[root]): both malloc'ed into *parent_out and *volume_out; false when out
 * of memory. */
static bool shells_of(const sr_mesh *mesh, uint32_t **parent_out, double **volume_out)
{
    size_t nv = mesh->vertex_count, nt = mesh->tri_count;
    uint32_t *parent = malloc((nv ? nv : 1) * sizeof *parent);
    double *volume = calloc(nv ? nv : 1, sizeof *volume);
    if (!parent || !volume) {
        free(parent);
        free(volume);
        return false;
    }
    for (size_t v = 0; v < nv; v++)
        parent[v] = (uint32_t)v;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *f = mesh->tri + 3 * t;
        join(parent, f[0], f[1]);
        join(parent, f[0], f[2]);
    }
    double lo[3], hi[3], c[3];
    sr_mesh_bbox(mesh, lo, hi);
    for (int k = 0; k < 3; k++)
        c[k] = 0.5 * (lo[k] + hi[k]);
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *f = mesh->tri + 3 * t;
        const double *pa = mesh->xyz + 3 * f[0], *pb = mesh->xyz + 3 * f[1],
                     *pc = mesh->xyz + 3 * f[2];
        double a[3] = {pa[0] - c[0], pa[1] - c[1], pa[2] - c[2]};
        double b[3] = {pb[0] - c[0], pb[1] - c[1], pb[2] - c[2]};
        double d[3] = {pc[0] - c[0], pc[1] - c[1], pc[2] - c[2]};
        volume[find(parent, f[0])] += (a[0] * (b[1] * d[2] - b[2] * d[1]) -
                                       a[1] * (b[0] * d[2] - b[2] * d[0]) +
                                       a[2] * (b[0] * d[1] - b[1] * d[0])) /
                                      6.0;
    }
    *parent_out = parent;
    *volume_out = volume;
    return true;
}

/* Drops every shell that is a void no larger than max_void_mm3 or a solid smaller
 * than min_solid_mm3; report counts what was dropped. */
static sr_status drop_shells(sr_mesh *mesh, double max_void_mm3, double min_solid_mm3,
                             sr_void_report *report, sr_err *err)
{
    size_t nv = mesh->vertex_count, nt = mesh->tri_count;
    if (nt == 0)
        return SR_OK;
    uint32_t *parent = NULL;
    double *volume = NULL;
    if (!shells_of(mesh, &parent, &volume))
        return sr_err_set(err, SR_E_NOMEM, "out of memory finding a mesh's shells");
    /* a shell's root is its lowest vertex; every vertex of a triangle finds it */
    int *drop = calloc(nv, sizeof *drop); /* per root: 1 = a void to remove */
    if (!drop) {
        free(parent);
        free(volume);
        return sr_err_set(err, SR_E_NOMEM, "out of memory finding a mesh's shells");
    }
    unsigned char *used = calloc(nv, 1);
    if (!used) {
        free(parent);
        free(volume);
        free(drop);
        return sr_err_set(err, SR_E_NOMEM, "out of memory finding a mesh's shells");
    }
    for (size_t t = 0; t < nt; t++)
        used[find(parent, mesh->tri[3 * t])] = 1;
    for (size_t v = 0; v < nv; v++) {
        if (!used[v])
            continue; /* not a root of a shell */
        report->shells++;
        if ((volume[v] < 0 && -volume[v] <= max_void_mm3) ||
            (volume[v] >= 0 && volume[v] < min_solid_mm3)) {
            drop[v] = 1;
            report->voids_dropped++;
            report->void_volume_mm3 += fabs(volume[v]);
        }
    }
    if (report->voids_dropped) {
        size_t w = 0;
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *f = mesh->tri + 3 * t;
            if (drop[find(parent, f[0])])
                continue;
            if (w != t)
                memmove(mesh->tri + 3 * w, f, 3 * sizeof *f);
            w++;
        }
        mesh->tri_count = w;
        /* vertices: keep those a kept triangle uses, in order (parent reused as map) */
        memset(used, 0, nv);
        for (size_t i = 0; i < 3 * w; i++)
            used[mesh->tri[i]] = 1;
        size_t kept = 0;
        for (size_t v = 0; v < nv; v++)
            if (used[v]) {
                if (kept != v)
                    memmove(mesh->xyz + 3 * kept, mesh->xyz + 3 * v, 3 * sizeof(double));
                parent[v] = (uint32_t)kept++;
            }
        for (size_t i = 0; i < 3 * w; i++)
            mesh->tri[i] = parent[mesh->tri[i]];
        mesh->vertex_count = kept;
    }
    free(parent);
    free(volume);
    free(drop);
    free(used);
    return SR_OK;
}

sr_status sr_mesh_drop_voids(sr_mesh *mesh, double max_void_mm3, sr_void_report *report,
                             sr_err *err)
{
    sr_void_report local;
    if (!report)
        report = &local;
    memset(report, 0, sizeof *report);
    if (!(max_void_mm3 >= 0) || !isfinite(max_void_mm3))
        return sr_err_set(err, SR_E_RANGE, "bad largest void %g mm^3: expected 0 or more",
                          max_void_mm3);
    return drop_shells(mesh, max_void_mm3, 0, report, err);
}

sr_status sr_mesh_drop_small_shells(sr_mesh *mesh, double min_volume_mm3,
                                    sr_void_report *report, sr_err *err)
{
    sr_void_report local;
    if (!report)
        report = &local;
    memset(report, 0, sizeof *report);
    if (!(min_volume_mm3 >= 0) || !isfinite(min_volume_mm3))
        return sr_err_set(err, SR_E_RANGE, "bad smallest shell %g mm^3: expected 0 or more",
                          min_volume_mm3);
    return drop_shells(mesh, min_volume_mm3, min_volume_mm3, report, err);
}

size_t sr_mesh_count_small_shells(const sr_mesh *mesh, double min_volume_mm3, size_t *shells)
{
    uint32_t *parent = NULL;
    double *volume = NULL;
    if (shells)
        *shells = 0;
    if (mesh->tri_count == 0)
        return 0;
    if (!shells_of(mesh, &parent, &volume))
        return SIZE_MAX;
    size_t small = 0, all = 0;
    for (size_t t = 0; t < mesh->tri_count; t++) {
        uint32_t r = find(parent, mesh->tri[3 * t]);
        if (volume[r] != INFINITY) { /* each shell counted once: its root marked */
            small += fabs(volume[r]) < min_volume_mm3;
            all++;
            volume[r] = INFINITY;
        }
    }
    free(parent);
    free(volume);
    if (shells)
        *shells = all;
    return small;
}
