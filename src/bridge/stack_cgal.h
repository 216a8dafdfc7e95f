/*
 * stack_cgal.h: the exact-arithmetic core of stack_mesh.h behind the C++ bridge
 * (stack_cgal.cpp): for a stack of extruded planar regions, the triangles of the walls
 * and of the caps between layers, conforming at every interface.
 *
 * At each interface the contour edges of the layer below and of the layer above go into
 * one CGAL 2D arrangement of segments over an exact kernel (Epeck), each arrangement edge
 * remembering which input edges it came from. Faces are classified by walking from the
 * unbounded face and toggling "inside below" / "inside above" across the edges; faces
 * inside exactly one of the two become caps (up where only the layer below has material,
 * down where only the layer above has), triangulated by a constrained Delaunay
 * triangulation of their boundary (no new points); every input edge is cut at the
 * arrangement vertices lying on it, and the walls are strips between those bottom and
 * top points. Every point is rounded to double once from its exact value, so the same
 * point has the same coordinates in walls and caps.
 */
#ifndef SR_STACK_CGAL_H
#define SR_STACK_CGAL_H

#include <stddef.h>
#include <stdint.h>

#include "bridge/polygon.h"
#include "base/status.h"

/* Triangle soup of the stack (vertices not shared between faces; weld by exact
 * coordinates): *xyz (3 doubles per vertex) and *tri (3 indices per triangle), both
 * malloc'ed, outward oriented when the regions are oriented (outer contours
 * counter-clockwise). z has layers + 1 increasing heights. */
sr_status sr_stack_soup(const sr_poly2 *regions, const double *z, size_t layers, double **xyz,
                        size_t *vertex_count, uint32_t **tri, size_t *tri_count, sr_err *err);

#endif
