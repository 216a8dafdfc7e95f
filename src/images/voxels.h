/*
 * voxels.h: the occupancy of a closed mesh on a regular grid of voxel centres, the
 * image method's view of a scan (image_restore.h). A voxel is occupied when its centre
 * lies inside the mesh by the nonzero winding rule along +z (so two overlapping shells
 * are their union, and a flipped patch does not punch a hole through a solid).
 *
 * Layout: v is nx by ny by nz bytes, x fastest: v[(k * ny + j) * nx + i] is the voxel
 * whose centre is origin + (i, j, k) * h. Values are 0 (outside) or 1 (inside); callers
 * may use the other bits for their own marks.
 */
#ifndef SR_VOXELS_H
#define SR_VOXELS_H

#include <stddef.h>
#include <stdint.h>

#include "mesh/mesh.h"
#include "base/status.h"

typedef struct sr_voxels {
    size_t nx, ny, nz;
    double h;                /* pitch, mm */
    double origin[3];        /* centre of voxel (0, 0, 0), mm */
    uint8_t *v;              /* nx by ny by nz */
} sr_voxels;

/* Allocates a zeroed grid of n[0] x n[1] x n[2] voxels. */
sr_status sr_voxels_alloc(sr_voxels *g, const size_t n[3], double h, const double origin[3]);

/* Sets bit 0 of every voxel whose centre is inside `mesh` (closed, outward oriented).
 * Triangles whose projection along z has no area are skipped (vertical faces cross no
 * ray). Linear in the triangles plus the columns they cover. */
sr_status sr_voxels_fill(sr_voxels *g, const sr_mesh *mesh, sr_err *err);

static inline size_t sr_voxel_index(const sr_voxels *g, size_t i, size_t j, size_t k)
{
    return (k * g->ny + j) * g->nx + i;
}

/* Along one axis of a grid (first centre o, pitch h, n voxels): the index of the centre
 * nearest to coordinate p, -1 when p lies outside by more than half a pitch.
 * sr_voxels_locate is this on each axis; the vote's image tables (image_lookup.h) use
 * it too, so they round as the locate does. */
static inline long sr_voxel_axis_index(double p, double o, double h, size_t n)
{
    double f = (p - o) / h;
    if (!(f > -0.5 && f < (double)n - 0.5))
        return -1;
    size_t i = (size_t)(f + 0.5);
    return (long)(i >= n ? n - 1 : i);
}

/* The voxel nearest to point p; -1 when p lies outside the grid by more than half a
 * pitch. Inline: the vote calls it a hundred million times. */
static inline long sr_voxels_locate(const sr_voxels *g, const double p[3])
{
    long i = sr_voxel_axis_index(p[0], g->origin[0], g->h, g->nx),
         j = sr_voxel_axis_index(p[1], g->origin[1], g->h, g->ny),
         k = sr_voxel_axis_index(p[2], g->origin[2], g->h, g->nz);
    if (i < 0 || j < 0 || k < 0)
        return -1;
    return (long)sr_voxel_index(g, (size_t)i, (size_t)j, (size_t)k);
}

/* The voxels round v inside the grid (face, edge and corner neighbours: up to 26) into
 * out, k then j then i ascending; returns how many. */
static inline size_t sr_voxel_neighbours26(const sr_voxels *g, size_t v, size_t out[26])
{
    size_t nx = g->nx, ny = g->ny, nz = g->nz, n = 0;
    long i = (long)(v % nx), j = (long)((v / nx) % ny), k = (long)(v / (nx * ny));
    for (long dk = -1; dk <= 1; dk++)
        for (long dj = -1; dj <= 1; dj++)
            for (long di = -1; di <= 1; di++) {
                long ii = i + di, jj = j + dj, kk = k + dk;
                if ((di | dj | dk) == 0 || ii < 0 || jj < 0 || kk < 0 || ii >= (long)nx ||
                    jj >= (long)ny || kk >= (long)nz)
                    continue;
                out[n++] = sr_voxel_index(g, (size_t)ii, (size_t)jj, (size_t)kk);
            }
    return n;
}

void sr_voxels_release(sr_voxels *g);

#endif
