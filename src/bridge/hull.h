/*
 * hull.h: the convex hull of a point set as a closed triangle mesh, the pure-C face of
 * src/bridge/hull_cgal.cpp (CGAL 5.5 convex_hull_3, GPL-3.0-or-later like boolean.h).
 * The image method (images/image_restore.h) clips a symmetry image of the scan to the
 * hull of a section's voxels.
 */
#ifndef SR_HULL_H
#define SR_HULL_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

/* *out = the convex hull of the n points xyz (n by 3), closed, outward oriented,
 * triangulated. SR_E_INVALID when the points are fewer than 4 or all coplanar (no
 * volume); SR_E_NOMEM. *out only on success. */
sr_status sr_convex_hull(const double *xyz, size_t n, sr_mesh *out, sr_err *err);

#endif
