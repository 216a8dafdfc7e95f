/*
 * slice.h: layers and sectors of an aligned model (paper Algorithms 1 and 2).
 *
 * The model is cut by planes z = L(l), l = 0..layers-1, at layer centres
 * L(l) = z_init + (l + 1/2) dz (ALGORITHMS.md), and each layer is divided into
 * `sectors` polar wedges around the z axis: sector k holds angles
 * [k, k+1) * 2pi/sectors with the angle atan2(y, x) mapped to [0, 2pi). For every
 * (layer, sector) cell the grid keeps the surface point farthest from the z axis.
 *
 * Algorithm 2 (accurate) is exact for a triangle mesh: a triangle's cut segment
 * contributes to every sector it crosses, with the per-sector maximum taken at the ends
 * of the part of the segment clipped to the wedge (distance from the axis is convex
 * along a line). All layers are done in one pass over the triangles: each triangle
 * visits only the layers its z-extent spans, so the cost grows with the triangles and
 * the crossings, never with layers x triangles. The paper's literal per-layer loop
 * over all triangles is kept for the benchmark and as a cross-check in the tests.
 */
#ifndef SR_SLICE_H
#define SR_SLICE_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

typedef struct sr_layer_grid {
    size_t layers, sectors;
    double z_init;      /* z of the bottom of layer 0 */
    double dz;          /* layer spacing; layer l's plane is z_init + (l + 0.5) dz */
    double *r;          /* layers by sectors: farthest distance from the z axis, 0 = none */
    double *pt;         /* layers by sectors by 3: that farthest point (x, y, z) */
} sr_layer_grid;

typedef struct sr_slice_opts {
    size_t layers;      /* N_layers >= 1 */
    size_t sectors;     /* N_sectors >= 3 */
    double z_min, z_max;/* slab to slice; both 0: the mesh's z extent (Z_init, H_axis) */
} sr_slice_opts;

/* Plane height of layer l. */
double sr_layer_z(const sr_layer_grid *grid, size_t l);

/* Sector of a point (x, y); SIZE_MAX when the point is on the axis (r < 1e-12). */
size_t sr_sector_of(double x, double y, size_t sectors);

/* Angle of the centre of sector k, radians. */
double sr_sector_angle(size_t k, size_t sectors);

/* Algorithm 2, all layers in one pass. *out only on success (release it). */
sr_status sr_slice_accurate(const sr_mesh *mesh, const sr_slice_opts *opts,
                            sr_layer_grid *out, sr_err *err);

/* Algorithm 2 as the paper loops: for every layer, every triangle. Same result as
 * sr_slice_accurate (tests check it); only for the benchmark. */
sr_status sr_slice_accurate_literal(const sr_mesh *mesh, const sr_slice_opts *opts,
                                    sr_layer_grid *out, sr_err *err);

/* Algorithm 1 (fast, vertex votes): vertices with |z - L| < dz/2 vote for their sector. */
sr_status sr_slice_fast(const sr_mesh *mesh, const sr_slice_opts *opts, sr_layer_grid *out,
                        sr_err *err);

/* Contributes a segment a-b lying in layer l's plane to every sector it crosses (the
 * per-sector farthest point, as Algorithm 2 does for a cut triangle); used to put a
 * 2D outline (a restored cross-section) on the sector grid. */
void sr_layer_grid_add_segment(sr_layer_grid *grid, size_t l, const double a[2],
                               const double b[2]);

/* Allocates a zeroed grid. */
sr_status sr_layer_grid_alloc(sr_layer_grid *out, size_t layers, size_t sectors,
                              double z_init, double dz);

/* Frees; accepts NULL and a zeroed grid. */
void sr_layer_grid_release(sr_layer_grid *grid);

#endif
