/*
 * tri_flaps.h: finds flaps, pairs of triangles on the same three corners walked
 * opposite ways (tri_flaps.c): two faces with no volume between them, whose edges a
 * closed surface would use four times. The closing of a scan (a fill folding back over
 * a rim triangle) and the float-precision weld of a mesh (two sheets a micrometre
 * apart made one) both leave them. Pure C: no I/O.
 */
#ifndef SR_MESH_TRI_FLAPS_H
#define SR_MESH_TRI_FLAPS_H

#include <stdbool.h>
#include <stddef.h>

#include "mesh/mesh.h"

/* Among the triangles t of m with pick[t], pairs each triangle of index >= first_new
 * with the first triangle on the same corners walked the other way that is not yet
 * paired (in index order), and sets gone[] of both. first_new 0 pairs any two. Returns
 * the triangles so paired (twice the pairs), SIZE_MAX when out of memory (gone[]
 * untouched). */
size_t sr_tri_flaps_pair(const sr_mesh *m, const bool *pick, size_t first_new, bool *gone);

#endif
