/*
 * planar_fill.h: the region bounded by a set of planar closed loops, triangulated (the
 * pure-C face of src/bridge/planar_fill_cgal.cpp, CGAL 5.5 Constrained_Delaunay_
 * triangulation_2 with the nesting-depth marking of CGAL's polygon example). Used to
 * close the face a scanned part stood on from its rims (mesh/scan_describe.h): an outer
 * rim with the rims of bores through it is one region with holes, a concave rim is
 * filled inside only.
 */
#ifndef SR_PLANAR_FILL_H
#define SR_PLANAR_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "base/status.h"

/* Triangulates the region inside an odd number of the loop_count closed loops (loop c
 * holds the points start[c] .. start[c+1]-1 of uv, u and v interleaved, start[0] = 0, the
 * closing edge implied). Crossing loops are cut where they cross: such a point gets an
 * index n + k (n = start[loop_count]) and its (u, v) as extra_uv[2k], [2k+1]; every other
 * triangle corner is an index into the input points (a point repeated takes the first
 * index). Triangles are counter-clockwise in (u, v). *tri (3 per triangle) and *extra_uv
 * are malloc'ed (freed by the caller, non-NULL on SR_OK). SR_E_INVALID for a non-finite
 * point, SR_E_NOMEM, SR_E_INTERNAL (named) when CGAL throws. */
sr_status sr_planar_fill(const double *uv, const size_t *start, size_t loop_count, uint32_t **tri,
                         size_t *tri_count, double **extra_uv, size_t *extra_count, sr_err *err);

#endif
