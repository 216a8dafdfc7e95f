/*
 * contour_slice.h: real cross-sections of a closed triangle mesh: for each layer plane
 * z = L the closed contours where the plane cuts the surface, as 2D polygons
 * (bridge/polygon.h). Unlike the sector grid of slice.h (one farthest point per
 * sector), a contour keeps everything: bores, holes, keys, teeth, open slots.
 *
 * A vertex counts as above the plane when z >= L, so every edge is cut at most once
 * and a vertex lying in the plane never makes a double point. Each crossing edge gives
 * one point, the same for both triangles that share the edge, and each cut triangle one
 * segment oriented by the triangle's winding (from the edge going down to the edge going
 * up), so an outward-oriented mesh gives outer contours counter-clockwise and holes
 * clockwise seen from +z. Segments are chained through their shared edges; a chain that
 * does not close (an open or non-manifold scan) is closed by its chord and counted.
 * All layers in one pass: each triangle visits only the layers its z-extent spans.
 */
#ifndef SR_CONTOUR_SLICE_H
#define SR_CONTOUR_SLICE_H

#include <stddef.h>

#include "bridge/polygon.h"
#include "mesh/mesh.h"
#include "base/status.h"

typedef struct sr_contour_stack {
    size_t layers;
    double *z;              /* plane height of each layer */
    sr_poly2 *raw;          /* per layer: the cut contours as chained, not cleaned */
    size_t open_chains;     /* chains closed by their chord (0 for a closed mesh) */
} sr_contour_stack;

/* Cuts `mesh` at each of the `layers` heights z[] (any order). *out only on success;
 * release with sr_contour_stack_release. */
sr_status sr_contour_slice(const sr_mesh *mesh, const double *z, size_t layers,
                           sr_contour_stack *out, sr_err *err);

void sr_contour_stack_release(sr_contour_stack *s);

#endif
