/*
 * scan_describe.h: a mesh as a scanner delivers it, described before use: its boundary
 * loops (the openings: the face the part stood on, occlusion holes), its connected
 * components, the share of the surface that is open, and its strays (small pieces off
 * the part's surface: fixture, dust, turntable), which sr_scan_drop_strays removes. A
 * closed part has no loop and one component; the description says so in the same terms.
 * Pure C on plain arrays: no I/O.
 */
#ifndef SR_SCAN_DESCRIBE_H
#define SR_SCAN_DESCRIBE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base/status.h"
#include "mesh/mesh.h"

/* One boundary loop: a chain of edges used by one triangle each, walked head to tail.
 * A loop that cannot be closed (a misoriented rim, a vertex two openings touch at) ends
 * where the walk stops: `closed` is then false. */
typedef struct sr_scan_loop {
    size_t edges;
    double length_mm;
    double span_mm; /* area of the opening it bounds, mm^2: a fan from the loop's centroid */
    bool closed;
    size_t first; /* its vertices: loop_verts[first .. first + edges), in walk order */
} sr_scan_loop;

/* One connected component (triangles joined through shared vertices). */
typedef struct sr_scan_component {
    size_t triangles;
    double area_mm2;
    double distance_mm; /* from its nearest vertex to the largest component's surface;
                         * 0 for the largest itself; computed for small ones only
                         * (-1 when not computed) */
    bool stray;         /* far smaller than the largest and off its surface */
} sr_scan_component;

/* Options; all zero gives the defaults. */
typedef struct sr_scan_opts {
    double small_fraction; /* a component is small when its area is at most this share of
                            * the largest's (the one of most triangles); 0: 0.01 */
    double off_surface_mm; /* a small component is off the surface when every one of its
                            * vertices is farther than this from the largest component's
                            * triangles; 0: 0.5 mm */
} sr_scan_opts;

typedef struct sr_scan_desc {
    size_t triangles;
    size_t boundary_edges;    /* edges used by one triangle (strays excluded, as below) */
    size_t nonmanifold_edges; /* edges used by three or more */
    sr_scan_loop *loops;      /* loop_count, longest first; the strays' own not counted */
    uint32_t *loop_verts;     /* boundary_edges: each loop's vertices (sr_scan_loop.first) */
    size_t loop_count;
    sr_scan_component *components; /* component_count, most triangles first */
    size_t component_count;
    uint32_t *tri_component; /* triangles: each triangle's index into components */
    double area_mm2;         /* the surface, strays included */
    double open_area_mm2;    /* sum of the loops' span_mm */
    double open_share;       /* open_area / (area of the kept surface + open_area) */
    size_t strays;           /* components flagged stray */
    size_t stray_triangles;
    double stray_area_mm2;
    bool open; /* any boundary edge */
} sr_scan_desc;

/* Describes mesh (validated: indices in range). *out is written on success only and owns
 * its arrays (sr_scan_desc_release). opts may be NULL. A negative or non-finite option:
 * SR_E_RANGE. SR_E_NOMEM. */
sr_status sr_scan_describe(const sr_mesh *mesh, const sr_scan_opts *opts, sr_scan_desc *out,
                           sr_err *err);

/* Frees the description's arrays and zeroes it; d may be NULL. */
void sr_scan_desc_release(sr_scan_desc *d);

/* Removes from mesh the triangles of every component d (sr_scan_describe of this mesh)
 * flags as stray, and the vertices only they used; the rest keeps its order. Triangles
 * appended after the description (sr_scan_close_openings) are kept. Nothing flagged: mesh
 * unchanged. SR_E_NOMEM, mesh unchanged on error. */
sr_status sr_scan_drop_strays(sr_mesh *mesh, const sr_scan_desc *d, sr_err *err);

/* Closes every closed loop of d (sr_scan_describe of this mesh) whose span is at most
 * max_span_mm2 (0: every one) with a fan of triangles from a new vertex at the loop's
 * centroid, turned against the rim so each boundary edge is then used twice, once each
 * way. For a plane loop the fan lies in its plane: the winding number of the closed
 * surface is that of the part, whatever the loop's shape (a concave rim's fan folds over
 * itself and cancels; a bore's rim inside the base is turned the other way and cancels
 * its share of the base's fan). *closed (may be NULL) gets the loops closed. Appends
 * vertices and triangles only: d's indices stay valid. SR_E_NOMEM, mesh unchanged. */
sr_status sr_scan_close_openings(sr_mesh *mesh, const sr_scan_desc *d, double max_span_mm2,
                                 size_t *closed, sr_err *err);

#endif
