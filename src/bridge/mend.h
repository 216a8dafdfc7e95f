/*
 * mend.h: mends a surface where it crosses itself locally (the noise folds a scan gets at
 * sharp edges), the pure-C face of src/bridge/mend_cgal.cpp and the files mend_cgal.hpp
 * lists (CGAL 5.5 PMP self_intersections, CDT_2 and triangulate_hole, GPL-3.0-or-later
 * like boolean.h).
 *
 * A boolean needs operands free of crossings where the other operand cuts them; a noisy
 * scan folds over itself along the fracture's sharp edges, exactly where a patch
 * meets it. Mending removes the crossing triangles (with rings of neighbours if need be)
 * and fills each hole they leave again from the points it had (no new vertices): a
 * triangulation of its rim and inner vertices seen along its mean normal, so the
 * surface keeps the scanner's points and its sharp edges; where a hole cannot be seen
 * one to one that way, from its rim alone (the surface then moves by up to the hole's
 * size).
 */
#ifndef SR_MEND_H
#define SR_MEND_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

typedef struct sr_mend_report {
    size_t crossing_pairs; /* crossing triangle pairs found in the first round */
    size_t removed_tris;   /* triangles taken out (all rounds) */
    size_t filled_tris;    /* triangles put in by the fills */
    size_t rim_filled;     /* of removed_tris, those whose holes were filled from their
                            * rims alone */
    int rounds;            /* attempts made (0: nothing crossed) */
    int reached_border;    /* an attempt failed because the triangles taken out reach the
                            * border (a larger neighbourhood may succeed) */
    size_t folds_flipped;  /* edges between two filled triangles lying back to back,
                            * flipped (mesh/tri_folds.h) */
} sr_mend_report;

/* Mends the crossings among mesh's triangles whose bounding boxes meet box (min xyz,
 * max xyz; NULL: the whole mesh). Attempt r (r = 0..4, the smallest holes first) takes
 * out the crossing triangles and r rings of triangles around them (sharing a vertex),
 * fills the holes (from their points, else from their rims: see above) and looks again,
 * up to three times. Each r is tried twice (the later passes' fills checked against
 * the faces around them, then not); of those that leave no crossing, the one that
 * fills fewer triangles' holes from their rims alone wins, and no larger r is tried.
 * Two filled triangles left back to back across an edge (a fill across a sharp edge
 * that took the other diagonal: a fin of no volume) get that edge flipped
 * (mesh/tri_folds.h), kept when nothing near box crosses after. mesh must be an
 * oriented manifold (it may be open: a scan's neighbourhood); its border is never
 * touched. The vertex array is kept
 * as it is (indices stay valid; vertices of removed triangles may be left unused); the
 * triangle array is replaced, and only when something was mended. Errors, mesh then
 * unchanged: SR_E_INVALID when mesh is not an oriented manifold or no attempt works
 * (the crossings reach its border, a hole cannot be filled, crossings remain);
 * SR_E_NOMEM. report may be NULL. */
sr_status sr_mesh_mend_crossings(sr_mesh *mesh, const double *box, sr_mend_report *report,
                                 sr_err *err);

/* What sr_mesh_unfold did. */
typedef struct sr_unfold_report {
    size_t crossing_pairs;  /* crossing triangle pairs found first */
    size_t remaining_pairs; /* ... left where the last round looked (0: all unfolded) */
    size_t moved_vertices;  /* vertices moved */
    double max_move_mm;     /* the farthest any moved from where it was */
} sr_unfold_report;

/* Unfolds a noisy scan where it crosses itself: the vertices of the crossing triangles
 * (off the border) move halfway towards the centre of their ring of neighbours, never
 * more than max_move_mm from where they were, and the crossings are looked for again
 * around them, up to six rounds. A fold of noise on a sliver comes out this way with
 * the surface moved by about the noise, where cutting it out and filling the hole
 * (sr_mesh_mend_crossings) takes out material under a whole fan. Only vertex positions
 * change (indices, triangles and topology stay); what still crosses is left for the
 * mender. SR_E_INVALID when mesh is not an oriented manifold (mesh unchanged);
 * SR_E_NOMEM. report may be NULL. */
sr_status sr_mesh_unfold(sr_mesh *mesh, double max_move_mm, sr_unfold_report *report,
                         sr_err *err);

/* What sr_mesh_clean_folded_slivers did. */
typedef struct sr_sliver_report {
    size_t crossing_pairs;  /* crossing triangle pairs found (what is left is for
                             * sr_mesh_unfold, which looks for it again) */
    size_t faces_removed;   /* triangles gone with collapsed needles */
} sr_sliver_report;

/* Where the mesh crosses itself, its slivers folded over by noise are undone: a cap's
 * long edge flipped, a needle's short edge collapsed (CGAL's
 * remove_almost_degenerate_faces on the crossing triangles and their neighbours), the
 * surface moving by at most max_move_mm. The mesh is replaced (vertices renumbered)
 * when anything crossed. SR_E_INVALID when it is not an oriented manifold (mesh
 * unchanged); SR_E_RANGE for a bad bound; SR_E_NOMEM. report may be NULL. */
sr_status sr_mesh_clean_folded_slivers(sr_mesh *mesh, double max_move_mm,
                                       sr_sliver_report *report, sr_err *err);

/* A noisy scan's folds undone in one pass: sr_mesh_clean_folded_slivers, then
 * sr_mesh_unfold's rounds around what crossed, on one mesh built once and searched for
 * crossings once (the rest of the scan is left as it is, so it cannot cross anew).
 * When anything crossed, *out is the unfolded scan (vertices renumbered) and
 * slivers->crossing_pairs > 0; otherwise *out is empty and scan is the answer.
 * SR_E_INVALID when scan is not an oriented manifold; SR_E_RANGE for a bad bound;
 * SR_E_NOMEM. slivers and unfold may be NULL. */
sr_status sr_mesh_unfold_scan(const sr_mesh *scan, double max_move_mm, sr_mesh *out,
                              sr_sliver_report *slivers, sr_unfold_report *unfold, sr_err *err);

/* sr_mesh_unfold_scan on a scan handed over, held once: when anything crossed, the
 * scan's arrays are released as soon as its unfolded surface stands (before the
 * unfolded arrays are made) and *scan becomes the unfolded scan; otherwise *scan is
 * untouched. On failure *scan is untouched, or empty when the failure came after its
 * arrays went (out of memory making the unfolded ones). */
sr_status sr_mesh_unfold_scan_in_place(sr_mesh *scan, double max_move_mm, sr_sliver_report *slivers,
                                       sr_unfold_report *unfold, sr_err *err);

/* The pairs of triangles of mesh (an oriented manifold; it may be open) that cross,
 * as CGAL's self_intersections finds them, searched on `threads` threads (0: every
 * core): *pairs (malloc'ed, 2 * *count indices) each once, the lower triangle first,
 * sorted, the same for any number of threads (crossings_cgal.cpp). SR_E_INVALID when
 * mesh is not an oriented manifold; SR_E_NOMEM. */
sr_status sr_mesh_crossing_pairs(const sr_mesh *mesh, int threads, uint32_t **pairs, size_t *count,
                                 sr_err *err);

/* Collapses every edge shorter than min_edge_mm (off the border, where the link
 * condition allows) to its midpoint, in passes until none is left: the needles two
 * booleans leave where faces met to rounding (a fin of slivers standing inside the
 * solid, joined to the surface by edges a micrometre long) fold away, and the surface
 * moves by at most min_edge_mm / 2 (tried: onto the sharper end, which kept corners
 * in place but left zero-area triangles that refused the next union). A collapse can
 * fold a neighbour over: when a face around a moved vertex then crosses a face (any
 * whose box comes within min_edge_mm of its own; the rest of the mesh did not move and
 * is not searched), nothing is kept and *crossed = 1. The mesh is replaced (vertices
 * renumbered) only when edges were collapsed and kept; *collapsed says how many.
 * collapsed and crossed may be NULL. SR_E_INVALID when mesh is not an oriented
 * manifold (mesh unchanged); SR_E_NOMEM. */
sr_status sr_mesh_collapse_short_edges(sr_mesh *mesh, double min_edge_mm, size_t *collapsed,
                                       int *crossed, sr_err *err);

#endif
