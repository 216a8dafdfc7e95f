/*
 * mesh_float.h: a mesh as a float format stores it (mesh_float.c). STL keeps each
 * corner as three floats and its readers weld corners at the same float position: two
 * vertices of a closed mesh closer than float precision (a micrometre sliver a union
 * left) become one, and the file then holds triangles that repeat a vertex and flaps
 * (two triangles on the same corners, walked opposite ways) whose edges are used four
 * times: the restored part of an open scan, closed in double precision, read back with
 * 24 non-manifold edges. Pure C: no I/O.
 */
#ifndef SR_MESH_FLOAT_H
#define SR_MESH_FLOAT_H

#include <stddef.h>

#include "base/status.h"
#include "mesh/mesh.h"

typedef struct sr_float_report {
    size_t welded;     /* vertices that share another's float position */
    size_t degenerate; /* triangles dropped: a corner repeated once welded */
    size_t flaps;      /* triangles dropped in pairs: same corners, opposite turns */
    size_t crowded;    /* further vertices welded: ends of an edge the weld crowded */
} sr_float_report;

/* How close (float steps in each coordinate) the ends of an edge that a weld leaves
 * used more than twice must lie to be welded as well. */
#define SR_FLOAT_NEIGHBOUR_STEPS 4

/* *out: m's vertices rounded to float, those at one position welded into the first,
 * then the ends of any edge that weld leaves used more than twice welded as well when
 * they lie within SR_FLOAT_NEIGHBOUR_STEPS float steps (three vertices within a few
 * micrometres: two at one float position, the third a step off), the triangles left
 * repeating a vertex and the flaps dropped (the rest in order, corner for corner);
 * unused vertices kept. When no two vertices share a float
 * position, *out is m rounded, every triangle kept. rep may be NULL. SR_E_NOMEM: out
 * untouched. */
sr_status sr_mesh_float_ready(const sr_mesh *m, sr_mesh *out, sr_float_report *rep);

/* How many of m's vertices share another's float position (what sr_mesh_float_ready
 * would weld), without a copy of m: 0 means m is written as float as it is. SIZE_MAX:
 * out of memory. */
size_t sr_mesh_float_welds(const sr_mesh *m);

#endif
