/*
 * stack_mesh.h: a closed triangle mesh from a stack of planar regions, each extruded
 * over its own slab [z[i], z[i+1]] (the patch of a missing section built from its
 * per-layer missing regions, or any 2.5D solid given as layers).
 *
 * The surface is: a vertical wall under every contour edge of every layer; at every
 * interface between slabs, an upward cap where the layer below has material and the
 * one above has none (below \ above), a downward cap for above \ below; nothing where
 * both or neither have material, so there are no internal faces. Watertight without
 * T-junctions by exact arithmetic (bridge/stack_cgal.h: per interface an arrangement of
 * both layers' edges; walls cut at its vertices, caps triangulated from its faces);
 * identical points are then welded and the result is checked.
 */
#ifndef SR_STACK_MESH_H
#define SR_STACK_MESH_H

#include <stddef.h>

#include "bridge/polygon.h"
#include "mesh/mesh.h"
#include "base/status.h"

/* Builds the mesh of `layers` regions; region i fills z in [z[i], z[i+1]] (z has
 * layers + 1 increasing heights). Empty regions are allowed. The result is checked:
 * SR_E_INTERNAL "... not a closed manifold (...)" when stitching failed
 * (e.g. two layers touching only along an edge). *out only on success; an all-empty
 * stack gives an empty mesh. */
sr_status sr_stack_mesh(const sr_poly2 *regions, const double *z, size_t layers, sr_mesh *out,
                        sr_err *err);

/* sr_stack_mesh, and where the stack does not close (outlines of neighbouring layers
 * touching along an edge or at a point, where the exact arrangement gives a wall edge
 * four faces) retried with every outline pulled in a little more: 0.3 then 0.6 um, a
 * volume change of perimeter x height x that (under 1e-3 of a 1 mm-thick patch). The
 * regions may be changed by that (hence not const); *out only on success. */
sr_status sr_stack_mesh_pulled_in(sr_poly2 *regions, const double *z, size_t layers,
                                  sr_mesh *out, sr_err *err);

/* Merges runs of identical layers into one layer each, in place: a layer whose region
 * is the region of the layer below it (their exclusive-or is empty; two empty regions
 * are identical) joins that layer's run, extruded from the run's bottom to its top.
 * regions[0 .. *layers) and z[0 .. *layers] are compacted, the merged regions released,
 * and *layers becomes the number of runs. The solid is the same; its walls are no
 * longer cut at every layer. On failure the stack is left as it was. */
sr_status sr_stack_merge_identical(sr_poly2 *regions, double *z, size_t *layers, sr_err *err);

#endif
