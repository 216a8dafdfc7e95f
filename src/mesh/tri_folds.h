/*
 * tri_folds.h: folds, two triangles lying back to back across an edge (their normals
 * turned onto each other), flipped flat (tri_folds.c). A fill that triangulates a hole
 * across a sharp edge of the part may take the other diagonal of the quad that had the
 * edge: its two triangles then stand off the surface as a fin of no volume (a plate's
 * open base, closed, held one 1.4 mm high from a bore's wall to the base's rim; the
 * mender's fills leave them too). Flipping the fin's edge brings the sharp edge back.
 * Pure C: no I/O.
 */
#ifndef SR_MESH_TRI_FOLDS_H
#define SR_MESH_TRI_FOLDS_H

#include <stdbool.h>
#include <stddef.h>

#include "mesh/mesh.h"

/* Where two triangles t1 = (u, v, a) and t2 = (v, u, b) of m, both with pick[t], meet
 * across the edge u v alone (no third triangle of m on it) with their normals more than about 154 degrees apart
 * (cosine below -0.9), and the edge a b is in no triangle of m, they become (a, u, b)
 * and (b, v, a) when both have an area and their normals are at most 120 degrees
 * apart (a sharp edge of the part, 90, comes back; a fold that stays one is left).
 * Each triangle is flipped at most once a call; at most 256 folds are looked at. The
 * triangles are rewritten in place (the vertices, the count and every other triangle
 * stay). Returns how many edges were flipped; SIZE_MAX when out of memory (m
 * untouched). */
size_t sr_tri_folds_flip(sr_mesh *m, const bool *pick);

#endif
