/*
 * surface_query.h: closest points and signed distances on a triangle surface, and
 * area-uniform sample points of it, for code outside src/align that measures one
 * surface against another point by point (the inspection of a repaired part,
 * inspect/inspect.h). A thin public face of the uniform grid of align_surface.c
 * (align_internal.h's al_surface), which the registration and the symmetry fit use.
 */
#ifndef SR_SURFACE_QUERY_H
#define SR_SURFACE_QUERY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base/status.h"
#include "mesh/mesh.h"

typedef struct sr_surface_query sr_surface_query;

/* Builds the query structure of `mesh` (validated: sr_mesh_validate). It keeps
 * pointers into mesh, so mesh must outlive the query, unchanged. SR_E_INVALID when
 * no triangle has an area, SR_E_NOMEM. *out only on success. */
sr_status sr_surface_query_build(const sr_mesh *mesh, sr_surface_query **out, sr_err *err);

/* Frees; accepts NULL. */
void sr_surface_query_free(sr_surface_query *s);

/* The closest point q of the surface to p among points within max_dist (INFINITY =
 * any); false when there is none. *dist = |p - q|, *signed_dist the same with the sign
 * of (p - q) . n, n the unit outward normal of the triangle q lies on (positive
 * outside an outward-oriented closed surface, exact away from its edges and for
 * convex and concave edges alike). Any of q, signed_dist may be NULL. Not for
 * concurrent use of one query (it keeps a visit stamp). */
bool sr_surface_query_closest(sr_surface_query *s, const double p[3], double max_dist, double q[3],
                              double *dist, double *signed_dist);

/* Total area of the surface, mm^2. */
double sr_surface_query_area(const sr_surface_query *s);

/* count area-uniform points of the surface into xyz (count by 3, caller's), stratified
 * and deterministic for a given seed. count 0 writes nothing. SR_E_NOMEM. */
sr_status sr_surface_query_samples(const sr_surface_query *s, size_t count, uint64_t seed,
                                   double *xyz);

#endif
