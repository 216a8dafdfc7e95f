/*
 * clip_local.h: the intersection of a large closed mesh with a small one computed near
 * the small one only (a scan's symmetry image clipped to a section's hull), the pure-C
 * face of src/bridge/clip_local_cgal.cpp (CGAL 5.5 PMP corefinement, GPL-3.0-or-later
 * like boolean.h).
 */
#ifndef SR_CLIP_LOCAL_H
#define SR_CLIP_LOCAL_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

/* What sr_boolean_intersection_local did. */
typedef struct sr_local_clip_info {
    int local;                 /* 1: clipped locally; 0: the whole-mesh intersection ran */
    size_t neighbourhood_tris; /* a's triangles in the neighbourhood */
    char fallback[160];        /* why the whole-mesh intersection ran ("" when it did not) */
} sr_local_clip_info;

/* out = a ∩ b as sr_boolean_compute(SR_BOOLEAN_INTERSECTION, a, a_what, b, b_what, ...)
 * gives it (same refusals, same surface up to the order of vertices and triangles and
 * to how a flat polygon cut by the other mesh is split into triangles), for a large a
 * and a small b. Only a's triangles near b (their bounding boxes meet b's grown by
 * margin_mm; 0 = 1 % of b's bounding-box diagonal) go through CGAL: every triangle of a
 * that lies inside b or that b cuts is among them, so the result is made of theirs and
 * b's alone. a is checked on its arrays (closed, manifold, oriented, not inside out, no
 * zero-area triangle), for crossings only near b. The parts of b no triangle of a cuts
 * are placed by rays against the whole of a.
 *
 * When the local intersection cannot be trusted (a or b refused, b meets no triangle
 * of a, a ray runs through an edge of a, a part of a touches b away from the
 * intersection, the result is not a closed manifold) the whole-mesh intersection runs
 * instead (its refusal is this one's) and info->fallback says why. out may not be a or
 * b. info may be NULL. margin_mm negative or not finite: SR_E_RANGE. */
sr_status sr_boolean_intersection_local(const sr_mesh *a, const char *a_what, const sr_mesh *b,
                                        const char *b_what, double margin_mm, sr_mesh *out,
                                        sr_local_clip_info *info, sr_err *err);

/* The same of a mapped by a_xf (3x4, any non-singular affine map; a reflection's image
 * has its faces turned as sr_mesh_flip turns them) with b, without a mapped copy of a:
 * only the neighbourhood's vertices are mapped (sr_xform_apply, as sr_mesh_transform
 * maps them, so the result is the one the mapped copy gives), and a copy is made only
 * when the whole-mesh intersection runs. A singular a_xf: SR_E_RANGE. */
sr_status sr_boolean_intersection_local_mapped(const sr_mesh *a, const char *a_what,
                                               const double *a_xf, const sr_mesh *b,
                                               const char *b_what, double margin_mm, sr_mesh *out,
                                               sr_local_clip_info *info, sr_err *err);

#endif
