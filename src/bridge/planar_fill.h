/*
 * planar_fill.h: the region bounded by a set of oriented planar closed loops,
 * triangulated (the pure-C face of src/bridge/planar_fill_cgal.cpp, CGAL 5.5
 * Constrained_triangulation_plus_2 over a constrained Delaunay triangulation). Used to
 * close the face a scanned part stood on from its rims (mesh/scan_describe.h): an outer
 * rim with the rims of bores through it is one region with holes, a concave rim is
 * filled inside only, and rims whose projections cross (a noisy rim folding over itself,
 * two rims touching) are cut where they cross and filled by their winding number.
 */
#ifndef SR_PLANAR_FILL_H
#define SR_PLANAR_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "base/status.h"

/* The triangulation of sr_planar_fill, malloc'ed (sr_planar_fill_free). Point indices:
 * below n (the input's point count) an input point (a point repeated takes the first
 * index); n + k the point CGAL made where two loop edges cross, at extra_uv[2k], [2k+1].
 * Each input edge q -> q' (q' the next point of q's loop) runs through the points
 * split[split_first[q] .. split_first[q + 1]) in order from q to q' (none when nothing
 * lies on it; split_first has n + 1 entries). */
typedef struct sr_planar_fill_out {
    uint32_t *tri; /* tri_count triangles, 3 indices each */
    size_t tri_count;
    double *extra_uv; /* extra_count points, u and v interleaved */
    size_t extra_count;
    size_t *split_first;
    uint32_t *split;
} sr_planar_fill_out;

/* Triangulates the region the loop_count closed loops wind around (loop c holds the
 * points start[c] .. start[c+1]-1 of uv, u and v interleaved, start[0] = 0, the closing
 * edge implied): every face of the constrained triangulation of the loop edges whose
 * winding number w (the loops' turns around it) is not 0, turned clockwise in (u, v)
 * where w > 0 and counter-clockwise where w < 0, so each loop edge q -> q' is walked
 * q' -> q by the fill (through its split points) when no face winds twice. *out is
 * written on SR_OK. SR_E_INVALID for a non-finite point, SR_E_RANGE when the indices do
 * not fit 32 bits, SR_E_NOMEM, SR_E_INTERNAL (named) when CGAL throws. */
sr_status sr_planar_fill(const double *uv, const size_t *start, size_t loop_count,
                         sr_planar_fill_out *out, sr_err *err);

/* Frees out's arrays and zeroes it; out may be NULL. */
void sr_planar_fill_free(sr_planar_fill_out *out);

#endif
