/*
 * envelope.h: the physical envelope every imported mesh must lie in, in one place.
 *
 * symrec restores mechanical parts measured in millimetres. A coordinate beyond a
 * kilometre, or a whole part smaller than a micrometre, is not a part but a damaged or
 * hostile file, and the stages after import (alignment, comparison through CGAL's exact
 * arithmetic, booleans, export to float32 formats) are only sound inside a bounded
 * range: coordinates near 1e155 overflowed the alignment's squared distances (SIGSEGV),
 * near 5e304 CGAL's GMP conversion (SIGFPE), and values beyond float range could be
 * stored but not written back to STL/GLB. So every reader (STL ascii and binary, OBJ,
 * PLY ascii and binary float/double, OFF, glTF, GLB; sr_mesh_read, sr_mesh_read_memory
 * and sr_scene_read, after glTF node transforms) checks its result here:
 *
 *   |coordinate| <= SR_ENVELOPE_COORD_MAX (1e6 mm) on every axis, finite: which also makes
 *       every coordinate representable in float32, so any mesh read can be written to
 *       any format (STL, glTF and GLB store float32);
 *   the bounding box of the triangles' vertices has a largest extent of at least
 *       SR_ENVELOPE_EXTENT_MIN (1e-3 mm);
 *   at least one triangle has a non-zero area.
 *
 * Degenerate triangles, one rule for every format: a triangle that repeats a vertex
 * index (or, in STL, a corner) is dropped by every reader (it has no third edge and no
 * format's writer can store it); a triangle of three distinct vertices on one line is
 * kept, because in a closed mesh it fills a T-junction and dropping it would open the
 * mesh; a mesh none of whose triangles has an area (all collinear, or a glTF node scaled
 * to 0) is refused, as is a mesh of only repeated-vertex triangles.
 *
 * A refusal is one line naming the file and what is outside, e.g.
 *   cannot read 'x.ply': vertex 17 coordinate z = 5.1e+304 is outside the physical
 *   envelope (|coordinate| <= 1e6 mm)
 * with status SR_E_INVALID. Pure C on plain arrays; nothing is allocated.
 */
#ifndef SR_ENVELOPE_H
#define SR_ENVELOPE_H

#include <stddef.h>
#include <stdint.h>

#include "base/status.h"

/* Largest |coordinate| accepted, mm (a kilometre: far beyond any part's fixture). */
#define SR_ENVELOPE_COORD_MAX 1e6
/* Smallest largest bounding-box extent accepted, mm (a micrometre). */
#define SR_ENVELOPE_EXTENT_MIN 1e-3

/* Every coordinate of xyz (count by 3) is finite and within +-SR_ENVELOPE_COORD_MAX.
 * facet_corners 0 names a failing point "vertex I"; 3 names it "facet I/3 corner I%3"
 * (STL, whose points are each facet's three corners). SR_OK, or SR_E_INVALID with err
 * set to "cannot read 'name': vertex I coordinate x = V is outside the physical
 * envelope (|coordinate| <= 1e6 mm)". */
sr_status sr_envelope_check_points(const double *xyz, size_t count, int facet_corners,
                                   const char *name, sr_err *err);

/* The same for an STL's facets as stored: corners facets by 9 floats, the file's facets
 * first_facet on, a failing point named "facet I corner K" (I counted in the file). */
sr_status sr_envelope_check_corners(const float *corners, size_t facets, size_t first_facet,
                                    const char *name, sr_err *err);

/* A whole mesh read from a file: xyz vertex_count by 3, tri tri_count by 3 (indices
 * below vertex_count, the caller guarantees it). Checks every vertex as
 * sr_envelope_check_points does, then that some triangle has a non-zero area and that
 * the bounding box of the vertices the triangles use has a largest extent of at least
 * SR_ENVELOPE_EXTENT_MIN. SR_OK or SR_E_INVALID with err set. */
sr_status sr_envelope_check_mesh(const double *xyz, size_t vertex_count, const uint32_t *tri,
                                 size_t tri_count, const char *name, sr_err *err);

#endif
