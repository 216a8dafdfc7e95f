/*
 * boolean.h: robust 3D booleans and surface distances, the pure-C face of
 * the CGAL files of src/bridge/ that boolean_cgal.hpp lists (CGAL 5.5 Polygon Mesh
 * Processing: corefinement, AABB trees). CGAL's PMP package is GPL-3.0-or-later, so a symrec binary linking it is
 * distributed under the GPL (see README).
 *
 * Inputs must be closed, consistently oriented and free of self-intersections where the
 * other input can cut them (triangles whose bounding box meets the other mesh's: a scan
 * with a noise fold far from a patch can still be united with it); that is checked
 * first and refused with SR_E_INVALID naming the input (`what`).
 */
#ifndef SR_BOOLEAN_H
#define SR_BOOLEAN_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

/* out = a ∪ b (closed, oriented, no internal faces). On failure *out is untouched.
 * On success *out is overwritten, not released (as sr_mesh_copy); out may be a or b,
 * whose old arrays are then released. The result may be empty (no triangles, e.g. the
 * intersection of disjoint meshes). Faces shared exactly by a and b (a patch sitting
 * on a fracture surface) are handled: they vanish from a union. SR_E_INVALID too when
 * the result would not be manifold (a and b touch only along an edge or at a point).
 * In messages the inputs are called 'first mesh' and 'second mesh'. */
sr_status sr_boolean_union(const sr_mesh *a, const sr_mesh *b, sr_mesh *out, sr_err *err);

/* out = a ∪ b as sr_boolean_compute(SR_BOOLEAN_UNION, a, a_what, b, b_what, ...) gives
 * it (same refusals, same surface up to the order of vertices and triangles and to
 * how a flat polygon cut by the other mesh is split into triangles), for a large a and
 * a small b: a scan and a patch. Only a's triangles near b (their bounding boxes meet
 * b's grown by margin_mm; 0 = 1 % of b's bounding-box diagonal) go through CGAL; the
 * rest of a is copied as it is, so a million-triangle scan is united in a fraction of a
 * second and CGAL's structures stay small. a is still checked whole (closed, manifold
 * edges and vertices, oriented, not inside out, no zero-area triangle) but for
 * crossings only near b (after b's own checks, unlike sr_boolean_compute).
 *
 * a_to_b (3x4 rigid, may be NULL = the same frame): b is given in another frame than a;
 * the union is computed on a mapped by a_to_b (the neighbourhood's vertices only) and
 * the result is in a's frame: a's vertices keep their coordinates bit for bit, the new
 * ones are mapped back by the inverse. (A patch built in an aligned frame stays exactly
 * as built; mapping it into the scan's frame could round touching faces into
 * crossing ones.)
 *
 * When the local union cannot be trusted (b meets no triangle of a, or a component of
 * it does not, so it lies wholly inside or outside a; the united neighbourhood does not
 * close up with the rest; CGAL failed on the neighbourhood) the whole-mesh union runs
 * instead and info->fallback says why. out may be a (a's arrays are then grown and
 * reused, no second copy of a) or b. info may be NULL. margin_mm negative or not
 * finite: SR_E_RANGE. */
typedef struct sr_local_union_info {
    int local;                  /* 1: united locally; 0: the whole-mesh union ran */
    size_t neighbourhood_tris;  /* a's triangles in the neighbourhood */
    size_t mended_tris;         /* _mending: a's triangles replaced where it crossed itself */
    char fallback[160];         /* why the whole-mesh union ran ("" when it did not) */
} sr_local_union_info;
sr_status sr_boolean_union_local(const sr_mesh *a, const char *a_what, const double *a_to_b,
                                 const sr_mesh *b, const char *b_what, double margin_mm,
                                 sr_mesh *out, sr_local_union_info *info, sr_err *err);

/* As sr_boolean_union_local, but where a crosses itself near b (a noisy scan folded
 * over along the sharp edges of a fracture, where the patch meets it) a's neighbourhood
 * is mended first (mend.h: the crossing triangles and their one-vertex ring replaced by
 * a fill of the hole they leave, no new vertices) instead of the union being refused;
 * info->mended_tris counts the triangles taken out. The restored surface then differs
 * from a there by at most the size of those triangles. Refused (SR_E_INVALID, naming a)
 * when the crossings cannot be mended (they reach the neighbourhood's rim, a hole
 * cannot be filled). The whole-mesh fallback does not mend. */
sr_status sr_boolean_union_local_mending(const sr_mesh *a, const char *a_what,
                                         const double *a_to_b, const sr_mesh *b,
                                         const char *b_what, double margin_mm, sr_mesh *out,
                                         sr_local_union_info *info, sr_err *err);

/* As sr_boolean_union_local_mending, and *b_minus_a = b \ a (in a's frame) from the
 * same corefinement: the part of b that a lacks, bounded by b's surface outside a and
 * by a's (mended) surface inside b, turned over. So out = a ∪ b_minus_a with no
 * overlap and with the very triangles of out (a patch that is exactly what a scan
 * lacks). The whole-mesh fallback computes both with whole-mesh booleans. *b_minus_a
 * only on success, and may be empty. */
sr_status sr_boolean_union_local_split(const sr_mesh *a, const char *a_what,
                                       const double *a_to_b, const sr_mesh *b,
                                       const char *b_what, double margin_mm, sr_mesh *out,
                                       sr_mesh *b_minus_a, sr_local_union_info *info,
                                       sr_err *err);

/* out = a ∩ b and out = a \ b, same contract. */
sr_status sr_boolean_intersection(const sr_mesh *a, const sr_mesh *b, sr_mesh *out,
                                  sr_err *err);
sr_status sr_boolean_difference(const sr_mesh *a, const sr_mesh *b, sr_mesh *out,
                                sr_err *err);

/* The three operations behind one entry, with the inputs named in messages:
 *   'patch' is not closed (12 boundary edges)
 * a_what / b_what may be NULL ('first mesh' / 'second mesh'). op out of range:
 * SR_E_RANGE. Same contract as sr_boolean_union. */
typedef enum sr_boolean_op {
    SR_BOOLEAN_UNION = 0,
    SR_BOOLEAN_INTERSECTION,
    SR_BOOLEAN_DIFFERENCE,
} sr_boolean_op;
sr_status sr_boolean_compute(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                             const sr_mesh *b, const char *b_what, sr_mesh *out,
                             sr_err *err);

/* *out = 1 when the mesh has self-intersecting triangles (CGAL's test: triangles that
 * meet other than along their shared edges or vertices; a zero-area triangle counts),
 * else 0. The mesh need not be closed but must form an oriented manifold (every edge
 * in at most two triangles, traversed in opposite directions), else SR_E_INVALID. */
sr_status sr_mesh_self_intersects(const sr_mesh *mesh, int *out, sr_err *err);

/* Makes a closed mesh fit for a boolean: removes zero-area triangles (CGAL PMP
 * remove_degenerate_faces). Crossing triangles are not re-meshed (CGAL's experimental
 * remover took minutes on scans and its header alone tripled the bridge's build
 * time). *mesh is replaced only when something changed. A mesh with no zero-area
 * triangle (the same exact test, on the arrays) is left alone at once, SR_OK, and not
 * checked further; one with any: SR_E_INVALID when it is not an oriented manifold. */
typedef struct sr_repair_report {
    int changed;
    size_t degenerate_removed;
} sr_repair_report;
sr_status sr_mesh_repair(sr_mesh *mesh, sr_repair_report *report, sr_err *err);

/* Surface deviation of a from b: for sample points on a (every vertex plus the
 * centroid of every triangle), the unsigned distance to the nearest point of b's
 * surface. max, mean and RMS in mm, and the number of samples (vertex_count +
 * tri_count of a). b may be open or non-manifold (a scan); its zero-area triangles
 * are ignored. SR_E_INVALID when either mesh fails sr_mesh_validate, or b has no
 * triangle of non-zero area. Cost: O((n_a + n_b) log n_b); 1M triangles in seconds. */
typedef struct sr_deviation {
    double max_mm, mean_mm, rms_mm;
    size_t samples;
} sr_deviation;
sr_status sr_mesh_deviation(const sr_mesh *a, const sr_mesh *b, sr_deviation *out,
                            sr_err *err);

#endif
