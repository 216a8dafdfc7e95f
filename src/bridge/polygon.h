/*
 * polygon.h: planar regions and their booleans, offsets, point tests and line
 * clipping, the pure-C face of src/bridge/polygon_clipper.cpp (Clipper 6.4.2 by Angus
 * Johnson, Debian libpolyclipping-dev, Boost licence). Used for per-layer cross-sections:
 * the missing region of a layer (restored minus damaged), machining allowances, and
 * contour-parallel or raster tool paths (plan.c).
 *
 * A region (sr_poly2) is a set of closed contours in millimetres. Contour c holds the
 * points start[c] .. start[c+1]-1 of xy (x, y interleaved); start has contour_count + 1
 * entries and start[0] = 0; the closing edge from the last point back to the first is
 * implied (the first point is not repeated). Inputs are read with the NON-ZERO fill
 * rule, so any orientation of a single contour is accepted; every region this module
 * returns is clean (no self-intersections, no overlapping contours) and oriented the
 * mathematical way: outer contours counter-clockwise (positive area), holes clockwise.
 * The same struct carries open polylines (sr_poly2_clip_lines output), then without the
 * implied closing edge.
 *
 * Fixed point: Clipper works on 64-bit integers. Coordinates are scaled by
 * SR_POLY2_SCALE = 1e5 units per mm (one unit = 1e-5 mm = 10 nm) and rounded, so every
 * result is exact to 5e-6 mm; |x|, |y| must be at most SR_POLY2_MAX_MM = 1e9 mm, which
 * keeps every scaled value (also after an offset of the same size) exactly
 * representable in a double (2^53 units ~ 9e10 mm) and far inside Clipper's hiRange
 * (~4.6e13 mm). Larger or non-finite coordinates are refused with SR_E_RANGE /
 * SR_E_INVALID naming the value. Round joins are approximated by chords within
 * SR_POLY2_ARC_TOL_MM of the true arc.
 *
 * Ownership: an sr_poly2 owns its two arrays. Start from sr_poly2_init (or a zeroed
 * struct: the empty region), free with sr_poly2_release. Functions writing a region
 * through `out` release its old arrays and replace them only on SR_OK (out may be an
 * input); on failure *out is untouched. Every entry catches all exceptions:
 * std::bad_alloc -> SR_E_NOMEM, anything else -> SR_E_INTERNAL.
 */
#ifndef SR_POLYGON_H
#define SR_POLYGON_H

#include <stddef.h>

#include "base/status.h"

#define SR_POLY2_SCALE 1e5        /* Clipper integer units per mm */
#define SR_POLY2_MAX_MM 1e9       /* largest |coordinate| accepted, mm */
#define SR_POLY2_ARC_TOL_MM 1e-3  /* chord error of round joins, mm */

/* A region (or a set of open polylines). contour_count = 0 is empty; then start and xy
 * may be NULL. xy holds start[contour_count] points (2 doubles each). */
typedef struct sr_poly2 {
    double *xy;
    size_t *start;
    size_t contour_count;
} sr_poly2;

/* Sets *p to the empty region (no allocation). */
void sr_poly2_init(sr_poly2 *p);

/* Frees p's arrays and makes it empty; p may be NULL. */
void sr_poly2_release(sr_poly2 *p);

/* Number of points over all contours (0 for an empty region). */
size_t sr_poly2_point_count(const sr_poly2 *p);

/* Appends one contour of n points (xy: n x (x, y), mm) to p. n >= 3 (a closed contour
 * needs an area); every coordinate finite and within SR_POLY2_MAX_MM. On failure p is
 * unchanged. Errors: SR_E_INVALID (n < 3, NaN/Inf), SR_E_RANGE (too large),
 * SR_E_NOMEM. */
sr_status sr_poly2_add_contour(sr_poly2 *p, const double *xy, size_t n, sr_err *err);

/* Builds a region from contour_count contours given as in sr_poly2 (start has
 * contour_count + 1 entries, start[0] = 0, non-decreasing). Contours of fewer than 3
 * points are refused (SR_E_INVALID naming the contour). *out is released and replaced
 * on success. */
sr_status sr_poly2_from_contours(const double *xy, const size_t *start,
                                 size_t contour_count, sr_poly2 *out, sr_err *err);

/* Copies a into *out (out released and replaced on success). */
sr_status sr_poly2_copy(const sr_poly2 *a, sr_poly2 *out, sr_err *err);

typedef enum sr_poly_op {
    SR_POLY_UNION = 0,
    SR_POLY_INTERSECTION,
    SR_POLY_DIFFERENCE, /* a minus b */
    SR_POLY_XOR,
} sr_poly_op;

/* out = a op b, inputs read with the non-zero rule, output clean and oriented (outer
 * CCW, holes CW). b may be NULL: the empty region (so SR_POLY_UNION with b = NULL
 * cleans a: overlaps merged, self-intersections resolved, orientation fixed). Empty
 * inputs are fine (the result may be empty). Contours that collapse after rounding to
 * the grid are dropped. Errors: SR_E_RANGE (op out of range, coordinate too large),
 * SR_E_INVALID (NaN, a malformed start array), SR_E_NOMEM, SR_E_INTERNAL. */
sr_status sr_poly2_boolean(sr_poly_op op, const sr_poly2 *a, const sr_poly2 *b,
                           sr_poly2 *out, sr_err *err);

/* out = a grown by delta_mm (delta < 0 shrinks; a region shrunk away is empty). a is
 * cleaned first (non-zero rule). round_joins != 0: convex corners become arcs (area of
 * a square of side s grown by d: (s + 2d)^2 - (4 - pi) d^2); 0: mitred corners (miter
 * limit 2, i.e. corners sharper than 60 degrees are squared off). delta must be finite
 * and within SR_POLY2_MAX_MM (SR_E_RANGE). */
sr_status sr_poly2_offset(const sr_poly2 *a, double delta_mm, int round_joins,
                          sr_poly2 *out, sr_err *err);

/* out = a with the vertices that move it less than tol_mm taken out (Clipper's
 * CleanPolygons: a vertex within tol_mm of the line through its neighbours, or of a
 * neighbour, goes, and its neighbours are then looked at again), then cleaned as
 * sr_poly2_boolean's union cleans (non-zero rule, oriented, self-intersections
 * resolved). Every vertex kept is one of a's; each one dropped lay within tol_mm of
 * the outline as it was when it went, so a long gentle curve may move by a few times
 * tol_mm. tol_mm finite and in [0, SR_POLY2_MAX_MM] (SR_E_RANGE). */
sr_status sr_poly2_clean(const sr_poly2 *a, double tol_mm, sr_poly2 *out, sr_err *err);

/* Signed area, mm^2: the sum of the contours' shoelace areas (CCW positive), so holes
 * of an oriented region subtract. 0 for an empty region. */
double sr_poly2_area(const sr_poly2 *a);

/* Where (x, y) lies with respect to the region, by the non-zero winding of its
 * contours evaluated on the integer grid: 1 inside, 0 outside, -1 on a boundary
 * (within one grid unit, 1e-5 mm). A non-finite or out-of-range point is outside (0). */
int sr_poly2_contains(const sr_poly2 *a, double x, double y);

/* Bounding box of all points: box = {xmin, ymin, xmax, ymax}. Returns 0 (box untouched)
 * for an empty region, else 1. */
int sr_poly2_bounds(const sr_poly2 *a, double box[4]);

/* Distance in mm from (x, y) to the nearest point of a's boundary (any contour,
 * closing edges included); INFINITY for an empty region. */
double sr_poly2_boundary_distance(const sr_poly2 *a, double x, double y);

/* Clips path_count open polylines (path p = points start[p] .. start[p+1]-1 of xy,
 * each of at least 2 points) to the region: the parts inside (boundary included) as
 * open polylines in *out_open (no implied closing edge). Clipper may reverse the
 * direction of a piece; pieces come in no particular order. Errors as
 * sr_poly2_boolean, naming 'lines' or 'region'. */
sr_status sr_poly2_clip_lines(const sr_poly2 *region, const double *xy,
                              const size_t *start, size_t path_count,
                              sr_poly2 *out_open, sr_err *err);

/* Splits a region into its connected pieces: one sr_poly2 per outer contour, holding
 * that outer contour (CCW, first) followed by its holes (CW). An island inside a hole
 * is a piece of its own. Pieces are ordered by decreasing area. *out (a malloc'd array
 * of *out_count regions; NULL when 0) is written only on success; free it with
 * sr_poly2_components_release. */
sr_status sr_poly2_components(const sr_poly2 *a, sr_poly2 **out, size_t *out_count,
                              sr_err *err);

/* Releases every region of an array from sr_poly2_components, then the array. */
void sr_poly2_components_release(sr_poly2 *parts, size_t count);

#endif
