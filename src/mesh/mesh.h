/*
 * mesh.h: the indexed triangle mesh every part of symrec works on, and the plain
 * geometry on it: validation, bounding box, enclosed volume, surface area, closedness,
 * rigid transforms. Pure C on plain arrays: no I/O, no SQLite, no C++.
 *
 * Layout (libigl style shapes):
 *   xyz  vertex_count by 3 doubles, millimetres
 *   tri  tri_count by 3 uint32 vertex indices, counter-clockwise seen from outside
 * A mesh owns both arrays; sr_mesh_release frees them and accepts a zeroed mesh.
 */
#ifndef SR_MESH_H
#define SR_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base/status.h"

typedef struct sr_mesh {
    double *xyz;          /* vertex_count by 3 */
    uint32_t *tri;        /* tri_count by 3 */
    size_t vertex_count;
    size_t tri_count;
} sr_mesh;

/* Largest vertex or triangle count symrec accepts (indices are uint32). */
#define SR_MESH_MAX_COUNT ((size_t)UINT32_MAX)

/* Zeroes *mesh (an empty mesh). */
void sr_mesh_init(sr_mesh *mesh);

/* Frees the arrays and zeroes *mesh. mesh may be NULL. */
void sr_mesh_release(sr_mesh *mesh);

/* Allocates uninitialised arrays for vertex_count vertices and tri_count triangles
 * into *out (which must be released/empty). SR_E_NOMEM if they do not fit. */
sr_status sr_mesh_alloc(sr_mesh *out, size_t vertex_count, size_t tri_count);

/* Deep copy of src into *dst (dst is overwritten, not released). */
sr_status sr_mesh_copy(sr_mesh *dst, const sr_mesh *src);

/* Appends src's vertices and triangles to *dst (indices shifted). */
sr_status sr_mesh_append(sr_mesh *dst, const sr_mesh *src);

/* The triangles t of m with keep[t] != 0, in order, as a mesh of their own into *out
 * (overwritten, not released), its vertices in the order the triangles first use them;
 * orig (may be NULL; room for m->vertex_count) gets each of out's vertices' index in m.
 * SR_E_NOMEM. */
sr_status sr_mesh_subset(const sr_mesh *m, const uint8_t *keep, sr_mesh *out, uint32_t *orig);

/* What validation found. Counts, not verdicts: the caller decides. */
typedef struct sr_mesh_report {
    size_t nonfinite_vertices;  /* vertices with a NaN or Inf coordinate */
    size_t bad_indices;         /* triangles with an index >= vertex_count */
    size_t degenerate_tris;     /* triangles with a repeated index or zero area */
} sr_mesh_report;

/* Checks a mesh before use. Fills *report (may be NULL). Returns SR_E_INVALID with a
 * message naming `what` (e.g. the file name) when the mesh is empty, has a NaN/Inf
 * coordinate or an out-of-range index; degenerate triangles are only counted. */
sr_status sr_mesh_validate(const sr_mesh *mesh, const char *what, sr_mesh_report *report,
                           sr_err *err);

/* Triangle t's normal (b - a) x (c - a): counter-clockwise outward, its length twice
 * the triangle's area (zero for a degenerate triangle). */
void sr_mesh_tri_normal(const sr_mesh *mesh, size_t t, double n[3]);

/* Axis-aligned bounding box. For an empty mesh min = max = 0. */
void sr_mesh_bbox(const sr_mesh *mesh, double min[3], double max[3]);

/* Enclosed (signed) volume by the divergence theorem, mm^3: sum det(a,b,c)/6 over
 * triangles. Positive for a closed outward-oriented mesh. Coordinates are taken
 * relative to the bbox centre for accuracy. */
double sr_mesh_volume(const sr_mesh *mesh);

/* The enclosed volume of a closed outward mesh on each side of the plane x = x0, mm^3:
 * *below where x < x0, *above where x > x0 (their sum is sr_mesh_volume). Each
 * triangle's part on a side counted by the divergence theorem from a point of the
 * plane, where the cut face adds nothing: no boolean, exact to rounding. */
void sr_mesh_volume_across_x(const sr_mesh *mesh, double x0, double *below, double *above);

/* Total triangle area, mm^2. */
double sr_mesh_area(const sr_mesh *mesh);

/* Edge topology summary (undirected edges keyed by their two vertex indices). */
typedef struct sr_mesh_edges {
    size_t edge_count;          /* distinct undirected edges */
    size_t boundary_edges;      /* edges used by exactly one triangle */
    size_t nonmanifold_edges;   /* edges used by three or more triangles */
    size_t misoriented_edges;   /* two-triangle edges traversed the same way by both */
    size_t nonmanifold_vertices;/* vertices whose triangles form more than one fan
                                 * (triangles joined across the edges they share at
                                 * the vertex): two cones touching at their tips */
} sr_mesh_edges;

/* Counts edges by use, and vertices by fan. A mesh is closed when boundary and
 * non-manifold edges are 0, and consistently oriented when misoriented_edges is 0 too;
 * it is a manifold surface when nonmanifold_vertices is 0 as well. */
sr_status sr_mesh_edge_stats(const sr_mesh *mesh, sr_mesh_edges *out);

/* True when every edge is shared by exactly two triangles, traversed in opposite
 * directions (closed and consistently oriented). */
bool sr_mesh_is_closed(const sr_mesh *mesh);

/* Welds vertices with bitwise-equal coordinates (after mapping -0 to 0) and drops
 * triangles that become degenerate (repeated index). Keeps first-seen vertex order. */
sr_status sr_mesh_weld_exact(sr_mesh *mesh);

/* Rigid (or any affine) transform. m is 3 by 4, row-major: p' = M[:, :3] p + M[:, 3]. */
void sr_mesh_transform(sr_mesh *mesh, const double m[12]);

/* Reverses the orientation of every triangle (swaps two indices). */
void sr_mesh_flip(sr_mesh *mesh);

/* sr_mesh_transform, then sr_mesh_flip when m reflects (sr_xform_det < 0), so that a
 * closed mesh's image still faces out. */
void sr_mesh_map(sr_mesh *mesh, const double m[12]);

/* Affine transform helpers on the same 3x4 row-major layout. */

/* The determinant of m's linear part (negative: m reflects; 0: singular). */
double sr_xform_det(const double m[12]);
void sr_xform_identity(double m[12]);
/* out = a * b (apply b first, then a). out may alias a or b. */
void sr_xform_mul(double out[12], const double a[12], const double b[12]);
/* Inverse of a rigid transform (rotation part orthonormal). */
void sr_xform_rigid_inverse(double out[12], const double m[12]);
void sr_xform_apply(const double m[12], const double p[3], double out[3]);

/* q: the closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
 * Detection 5.1.5); a degenerate triangle gives a point on it too. */
void sr_tri_closest_point(const double p[3], const double a[3], const double b[3],
                          const double c[3], double q[3]);

#endif
