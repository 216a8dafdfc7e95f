/*
 * mesh_edit.h: vertices and triangles added to a test mesh by hand, as a scanner's
 * defects add them (the scan tests: test_scan_peel.c, test_scan_seal.c).
 */
#ifndef SR_TEST_MESH_EDIT_H
#define SR_TEST_MESH_EDIT_H

#include <stdint.h>

#include "mesh/mesh.h"

/* Appends a vertex at p to m; returns its index (fails the test when out of memory). */
uint32_t test_add_vertex(sr_mesh *m, const double p[3]);

/* Appends the triangle (a, b, c) of m's vertices. */
void test_add_triangle(sr_mesh *m, uint32_t a, uint32_t b, uint32_t c);

#endif
