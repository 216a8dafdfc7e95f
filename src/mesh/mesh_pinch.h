/*
 * mesh_pinch.h: a mesh's pinched vertices split (mesh_pinch.c): a vertex whose triangles
 * form more than one fan (two cones touching at their tips, two rims of a scan closed
 * where they touch) gets one copy per fan, so every vertex of a closed mesh has one disc
 * of triangles around it, as a boolean or a polyhedron needs. Pure C: no I/O.
 */
#ifndef SR_MESH_PINCH_H
#define SR_MESH_PINCH_H

#include <stddef.h>

#include "base/status.h"
#include "mesh/mesh.h"

/* Gives each fan but the first of every pinched vertex of mesh (triangles joined across
 * the edges they share at the vertex, sr_mesh_edge_stats) a new vertex at the same
 * place, appended; triangles keep their order and corners. *added (may be NULL) gets the
 * vertices added. SR_E_RANGE past SR_MESH_MAX_COUNT, SR_E_NOMEM: mesh unchanged. */
sr_status sr_mesh_split_pinches(sr_mesh *mesh, size_t *added, sr_err *err);

#endif
