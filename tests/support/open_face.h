/*
 * open_face.h: a face of a test mesh left off, as a scanner leaves the face a part stood
 * on (the scan tests: test_scan_describe.c, test_scan_peel.c; test_image.c leaves a
 * side off).
 */
#ifndef SR_TEST_OPEN_FACE_H
#define SR_TEST_OPEN_FACE_H

#include <stddef.h>

#include "mesh/mesh.h"

/* Removes from m every triangle whose three vertices lie at z = z0 (within 1e-12 mm);
 * the rest keep their order, the vertices stay. Returns how many went. */
size_t test_drop_face_at(sr_mesh *m, double z0);

/* The same for the face at coordinate `at` along axis (0 x, 1 y, 2 z). */
size_t test_drop_face_on(sr_mesh *m, int axis, double at);

#endif
