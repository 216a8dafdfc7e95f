/*
 * same_surface.h: the tests' check that two closed meshes are one surface (the local
 * booleans against the whole-mesh ones): both closed with one fan at every vertex,
 * equal volumes, as many triangles and vertices, and equal triangle sets up to order;
 * where CGAL split a flat polygon along other diagonals the triangles may differ, the
 * surfaces must then coincide within 1e-9 of their size both ways. Fails the running
 * cmocka test otherwise; returns how many triangles differ.
 */
#ifndef SR_TEST_SAME_SURFACE_H
#define SR_TEST_SAME_SURFACE_H

#include <stddef.h>

#include "mesh/mesh.h"

size_t assert_same_surface(const sr_mesh *x, const sr_mesh *y);

#endif
