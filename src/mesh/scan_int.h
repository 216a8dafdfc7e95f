/*
 * scan_int.h: private to the scan files of src/mesh. scan_plane.c owns the planes of a
 * scan's openings: whether a loop's rim lies in a plane, and the group of loops closed
 * in one plane together (used by scan_close.c, which closes them, and by scan_peel.c,
 * which first peels the folds of the scan lying in them); scan_describe.c owns taking
 * triangles out of a scan. Pure C on plain arrays.
 */
#ifndef SR_SCAN_INT_H
#define SR_SCAN_INT_H

#include <stdbool.h>
#include <stddef.h>

#include "mesh/scan_describe.h"

/* A rim is planar when its vertices lie this close to the plane through its centroid
 * with its area normal: root mean square and largest distance, mm (the scan's noise,
 * sigma up to 0.1 mm, stays inside both). */
#define SR_SCAN_PLANE_RMS_MM 0.15
#define SR_SCAN_PLANE_MAX_MM 0.5

/* Whether loop l may be closed: its walk closed, at least 3 edges, a span of at most
 * max_span_mm2 (0: any). */
bool sr_scan_loop_eligible(const sr_scan_loop *l, double max_span_mm2);

/* Centroid c and unit area normal n (Newell's, as the rim walks) of loop l; false when
 * the loop has no area. */
bool sr_scan_loop_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                        double c[3], double n[3]);

/* Two unit vectors e1, e2 spanning the plane with unit normal n (e1 = a coordinate axis
 * not near n, crossed with n; e2 = n x e1): the plane's (u, v) frame. */
void sr_scan_plane_frame(const double n[3], double e1[3], double e2[3]);

/* Whether every vertex of loop l lies on the plane (c, n) within the tolerances above. */
bool sr_scan_loop_on_plane(const sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_loop *l,
                           const double c[3], const double n[3]);

/* The loops of d closed in one plane with loop i, into group (room for d->loop_count;
 * group[0] = i) and the plane into c, n (loop i's): every eligible loop after i still
 * open (done[j] SR_SCAN_LEFT_OPEN; done may be NULL) whose rim lies on that plane within
 * the tolerances and whose own plane is near parallel to it. Returns the count, 0 when
 * loop i is not eligible or not planar. */
size_t sr_scan_plane_group(const sr_mesh *mesh, const sr_scan_desc *d, size_t i,
                           const sr_scan_closing *done, double max_span_mm2, size_t *group,
                           double c[3], double n[3]);

/* How many times the edges of the closed loops in uv (loop c: points start[c] ..
 * start[c+1]-1, u and v interleaved, the closing edge implied) cross one another
 * properly in the plane, counted up to limit + 1 (then it stops); limit + 1 also when
 * there is no memory to count (rim_crossings.c). */
size_t sr_scan_rim_crossings(const double *uv, const size_t *start, size_t loop_count,
                             size_t limit);

/* Sorts n records of `size` bytes, each led by a uint64_t key lo << 32 | hi of two
 * vertex indices below nv, by key; records with equal keys keep their order. Linear in
 * n + nv (two counting passes, hi then lo), where a comparison sort of the five
 * million edges of a two-million-triangle scan took a second each time the scan was
 * described. SR_E_NOMEM: recs unchanged. (scan_describe.c) */
sr_status sr_scan_sort_edges(void *recs, size_t n, size_t size, size_t nv);

/* The triangles of `after` (a closing of `before`) that are not `before`'s: those whose
 * corners, in their order from any one of them, are no triangle's of before at exactly
 * the same positions (a turned or moved triangle counts as made). Into *fills (released
 * first; initialised by the caller) as a mesh of their own, vertices in the order first
 * used. SR_E_NOMEM: *fills unchanged. (scan_fills.c) */
sr_status sr_scan_fill_triangles(const sr_mesh *before, const sr_mesh *after, sr_mesh *fills,
                                 sr_err *err);

/* Removes the triangles gone[] (one flag per triangle) from mesh, and the vertices only
 * they used; the rest keep their order (scan_describe.c). SR_E_NOMEM: mesh unchanged. */
sr_status sr_scan_drop_triangles(sr_mesh *mesh, const bool *gone, sr_err *err);

/* What a closing of a scan left wrong: edges used other than twice, plane loops fanned
 * (their fill failed), and the spans fanned (all fans; plane fans). */
typedef struct sr_scan_closing_cost {
    size_t bad_edges, plane_fans;
    double fan_mm2, plane_fan_mm2;
} sr_scan_closing_cost;

/* Whether sr_scan_close_peeling keeps a pass's closing (`now`) over the one it has
 * (`was`); top_mm2: the span of the scan's largest opening. Passes 0 and 1 (folds
 * peeled): fewer edges left bad without fanning more than a speck (1 % of the largest
 * opening) beyond what was fanned, or as many with every plane then filled and the span
 * fanned falling by at least half the span the planes fanned. Pass 2 (scraps peeled off
 * failed planes) and later: every plane filled, no more edges bad, less fanned.
 * (scan_peel.c) */
bool sr_scan_peel_kept(int pass, const sr_scan_closing_cost *was, const sr_scan_closing_cost *now,
                       double top_mm2);

#endif
