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
    double centre[3]; /* the centroid of its vertices, mm */
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
    size_t sealed_triangles; /* sr_scan_close_peeling: triangles taken out round the
                              * closing's defects and closed again (sr_scan_seal) */
    size_t uncurled_vertices; /* sr_scan_close_peeling: rim vertices merged where a rim
                               * twisted over itself in its plane (sr_scan_uncurl_rims) */
    sr_mesh fills;            /* sr_scan_close_peeling: the triangles its closing made (the fills of
                    * the openings, the triangles split on their rims), the mesh's frame,
                    * a mesh of their own; empty when nothing was closed */
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
 * max_span_mm2 (0: every one), turned against the rim so each boundary edge is then used
 * twice, once each way. Longest first, a loop whose rim lies in a plane (within 0.15 mm
 * rms, 0.5 mm at most: the face the part stood on, a hole in a flat face) is closed in
 * that plane together with every other such loop on it, by the constrained triangulation
 * of the region their rims wind around (bridge/planar_fill.h): the base with the rims of
 * the bores through it is one face with holes, a concave rim is filled inside only, rims
 * that cross in the plane are cut where they cross (the scan's triangle on a cut rim edge
 * is split there, in place, the rest appended); any other loop, or a plane one whose
 * triangulation does not fit its rims, by a fan from a new vertex at its centroid. Then a
 * vertex left pinched (two rims that touched) gets one copy per fan (mesh/mesh_pinch.h).
 * *closed (may be NULL) gets the loops closed. Triangle indices keep their components:
 * d's indices stay valid. SR_E_RANGE, SR_E_NOMEM: mesh unchanged (but for SR_E_NOMEM in
 * the pinch split, which leaves it closed with its pinches). */
sr_status sr_scan_close_openings(sr_mesh *mesh, sr_scan_desc *d, double max_span_mm2,
                                 size_t *closed, sr_err *err);

/* How an opening was closed (sr_scan_close_openings_how). */
typedef enum sr_scan_closing {
    SR_SCAN_LEFT_OPEN = 0, /* not closed: its walk did not close, or over max_span_mm2 */
    SR_SCAN_BY_FAN,        /* a fan from its centroid */
    SR_SCAN_IN_PLANE       /* triangulated in its rim's plane */
} sr_scan_closing;

/* sr_scan_close_openings, and how (may be NULL; d->loop_count entries) gets how each
 * loop of d was closed. */
sr_status sr_scan_close_openings_how(sr_mesh *mesh, sr_scan_desc *d, double max_span_mm2,
                                     size_t *closed, sr_scan_closing *how, sr_err *err);

/* Hangs back the walls the scan lost beside a plane opening (scan_curtain.c): every
 * eligible loop of d (sr_scan_describe of this mesh) that is not planar but lies for at
 * least a third of its vertices on the plane of a planar loop of d (within its
 * tolerances), leaving it to one side only, gets each excursion off the plane projected
 * onto it and a strip of triangles from the excursion down to its projection, so its
 * rim then lies in the plane (a bore's mouth in the face the part stood on, where a
 * scanner's hole in the bore's wall reached the face). *hung gets the loops so hung;
 * when it is not 0, d no longer describes mesh. On error the mesh is unchanged. */
sr_status sr_scan_hang_curtains(sr_mesh *mesh, const sr_scan_desc *d, size_t *hung, sr_err *err);

/* Peels off the planes of d's openings (sr_scan_describe of this mesh; the loops closed
 * in one plane as sr_scan_close_openings groups them; with how, from a closing of this
 * mesh, only the groups whose first loop it closed by a fan: whose fill did not fit)
 * the folds of the scan lying in them: a triangle on the rim of such a group whose
 * corners all lie within the rims' noise of its plane (3 x their rms distance, 0.15 to
 * 0.5 mm) and that faces into the part, against the way the plane's fill faces (a
 * sliver of the face the part stood on turned over by the noise),
 * then the next such triangle on the rim so grown. Triangles of d's strays are not
 * touched. The triangles peeled go with the vertices only they used; the rest keep
 * their order. *peeled (may be NULL) gets their count; when it is not 0, d no longer
 * describes mesh. SR_E_NOMEM: mesh unchanged. */
sr_status sr_scan_peel_folds(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                             size_t *peeled, sr_err *err);

/* sr_scan_peel_folds, peeling every triangle lying in such a plane from its rim that
 * faces within 80 degrees of either way across it (a wall's, sideways, stays): the
 * scraps of the face the part stood on that the scanner kept (tilted past the cut by the
 * noise, joined to the rim and to one another at vertices), which the plane's fill must
 * cover and cannot wind around. Grown from every such triangle with a corner on the
 * rim through the corners of those peeled, not only across the edges they leave on
 * the rim. A plane off which more would come than its openings span is left alone. */
sr_status sr_scan_peel_plane_rims(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                                  size_t *peeled, sr_err *err);

/* Undoes the twists of the rims of the planes whose fill did not fit (the groups, as
 * sr_scan_close_openings makes them, whose first loop how says was fanned, or with how
 * NULL every plane's group; d describes mesh): where two edges of one rim a few steps
 * apart (at most 6 vertices between them) cross in the plane, the rim having folded
 * back over itself, the vertices between them are merged into one at the crossing. The
 * triangles left degenerate go (with the vertices only they used). *merged
 * (may be NULL) gets the vertices merged away; when it is not 0, d no longer describes
 * mesh. SR_E_NOMEM: mesh may be changed. (scan_uncurl.c) */
sr_status sr_scan_uncurl_rims(sr_mesh *mesh, const sr_scan_desc *d, const sr_scan_closing *how,
                              size_t *merged, sr_err *err);

/* Seals a closed scan's last defects: every edge used other than once each way (where
 * rims the closing could not fill cleanly met) is cut out with the triangles round its
 * vertices, out to 0, 1, ... 4 rings until the opening so left closes (as
 * sr_scan_close_openings closes it, strays dropped) with every edge used once each
 * way. *cut (may be NULL) gets the triangles taken out: 0 when there was no defect or
 * no attempt sealed it (mesh then unchanged). SR_E_NOMEM. */
sr_status sr_scan_seal(sr_mesh *mesh, size_t *cut, sr_err *err);

/* A scan made ready for use: described (default options), every opening closed
 * (sr_scan_close_openings_how), strays dropped; when the result is not closed or a loop
 * lying in a plane was fanned (its plane's fill did not fit its rims: folds lying in
 * the plane), the scan as it came is peeled of those folds (sr_scan_peel_folds: first
 * the planes whose fill failed, then every plane) and closed again; a peeled closing is
 * kept when it leaves fewer edges used other than twice (once each way), or as few and
 * every plane filled. Last, when a plane's fill still failed, the scan as it came is
 * peeled of every scrap lying in those planes (sr_scan_peel_plane_rims), kept when then
 * every plane fills, no more edges are left bad and fewer rim edges are fanned. What
 * is kept, when edges are still left bad, is sealed (sr_scan_seal; out->sealed_triangles). *out
 * gets the description of the mesh kept (its strays dropped, its loops those closed),
 * *how its loops' closings (malloc'ed, out->loop_count entries), *peeled (may be NULL)
 * the triangles peeled off (0 when the first closing was kept). On error mesh may be
 * closed in part, nothing is written to out or how. */
sr_status sr_scan_close_peeling(sr_mesh *mesh, sr_scan_desc *out, sr_scan_closing **how,
                                size_t *peeled, sr_err *err);

#endif
