/*
 * open_face.h: a face of a test mesh left off, as a scanner leaves the face a part stood
 * on (the scan tests: test_scan_describe.c, test_scan_peel.c).
 */
#ifndef SR_TEST_OPEN_FACE_H
#define SR_TEST_OPEN_FACE_H

#include <stddef.h>

#include "mesh/mesh.h"

/* Removes from m every triangle whose three vertices lie at z = z0 (within 1e-12 mm);
 * the rest keep their order, the vertices stay. Returns how many went. */
size_t test_drop_face_at(sr_mesh *m, double z0);

#endif
