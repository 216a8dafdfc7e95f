/*
 * operand_cgal.cpp: what every boolean of boolean.h does to its operands first (see
 * boolean_cgal.hpp). Each input is checked in the order a user can act on: validate
 * (empty, NaN, bad index), degenerate triangles, closed, manifold, consistently
 * oriented, not inside out, buildable as a halfedge mesh, not self-intersecting; every
 * refusal is SR_E_INVALID naming the input. The Surface_mesh<Epick::Point_3> is built
 * straight from the sr_mesh arrays (CGAL's file readers are several times slower) and
 * a result copied back to arrays. Also: the exception in flight as a status, and
 * sr_mesh_self_intersects.
 */
#include "bridge/boolean_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

namespace sr_bool {

const char *op_name(sr_boolean_op op)
{
    switch (op) {
    case SR_BOOLEAN_UNION: return "union";
    case SR_BOOLEAN_INTERSECTION: return "intersection";
    case SR_BOOLEAN_DIFFERENCE: return "difference";
    }
    return "boolean";
}

/* Converts the exception in flight into a status; call only inside a catch block. */
sr_status status_from_exception(sr_err *err, const char *doing)
{
    try {
        throw;
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "%s: out of memory", doing);
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "%s: %s", doing, e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "%s: unknown exception", doing);
    }
}

/* Copies the arrays into a Surface_mesh. False when Surface_mesh refuses a triangle
 * (a non-manifold vertex or edge, or a flipped neighbour); *bad_tri names it. */
bool build_surface_mesh(const sr_mesh *m, Mesh &sm, size_t *bad_tri)
{
    sm.clear();
    sm.reserve(static_cast<Mesh::size_type>(m->vertex_count),
               static_cast<Mesh::size_type>(m->tri_count * 3 / 2),
               static_cast<Mesh::size_type>(m->tri_count));
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        sm.add_vertex(Point(p[0], p[1], p[2]));
    }
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        if (sm.add_face(Vertex_index(f[0]), Vertex_index(f[1]), Vertex_index(f[2])) ==
            Mesh::null_face()) {
            *bad_tri = t;
            return false;
        }
    }
    return true;
}

/* Every check a boolean operand must pass; on success sm holds the mesh. */
/* True when some triangle of sm whose bounding box meets `box` (min xyz, max xyz)
 * crosses another: corefinement only needs the surface to be free of crossings where
 * the other operand can cut it, so a scan with a noise fold elsewhere still works. */
bool self_intersects_near(const Mesh &sm, const double box[6])
{
    std::vector<Mesh::Face_index> near;
    for (Mesh::Face_index f : sm.faces()) {
        CGAL::Bbox_3 b = PMP::face_bbox(f, sm);
        if (b.xmax() >= box[0] && b.xmin() <= box[3] && b.ymax() >= box[1] &&
            b.ymin() <= box[4] && b.zmax() >= box[2] && b.zmin() <= box[5])
            near.push_back(f);
    }
    return PMP::does_self_intersect(near, sm);
}

/* The checks of an operand on its arrays alone, in the order a user can act on:
 * validate, zero-area triangles, closed, manifold edges, oriented, not inside out.
 * *edges gets the edge statistics (with the vertex fans). */
sr_status check_arrays(const sr_mesh *m, const char *what, sr_mesh_edges *edges, sr_err *err)
{
    sr_mesh_report report;
    sr_status st = sr_mesh_validate(m, what, &report, err);
    if (st != SR_OK)
        return st;
    if (report.degenerate_tris) {
        /* confirmed by the exact predicate corefinement uses: a sliver whose cross
         * product only rounds to zero in doubles is fine */
        size_t degenerate = 0;
        for (size_t t = 0; t < m->tri_count; t++) {
            const uint32_t *f = m->tri + 3 * t;
            const double *p = m->xyz + 3 * f[0], *q = m->xyz + 3 * f[1],
                         *r = m->xyz + 3 * f[2];
            degenerate += CGAL::collinear(Point(p[0], p[1], p[2]), Point(q[0], q[1], q[2]),
                                          Point(r[0], r[1], r[2]))
                              ? 1
                              : 0;
        }
        if (degenerate)
            return sr_err_set(err, SR_E_INVALID,
                              "'%s' has %zu degenerate (zero-area) triangles", what,
                              degenerate);
    }
    st = sr_mesh_edge_stats(m, edges);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory counting the edges of '%s'", what);
    if (edges->boundary_edges)
        return sr_err_set(err, SR_E_INVALID, "'%s' is not closed (%zu boundary edges)",
                          what, edges->boundary_edges);
    if (edges->nonmanifold_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is not manifold (%zu edges shared by three or more "
                          "triangles)",
                          what, edges->nonmanifold_edges);
    if (edges->misoriented_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is not consistently oriented (%zu edges traversed the "
                          "same way by both triangles)",
                          what, edges->misoriented_edges);
    double volume = sr_mesh_volume(m);
    if (!(volume > 0))
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is inside out (enclosed volume %g mm^3)", what, volume);
    return SR_OK;
}

sr_status check_operand(const sr_mesh *m, const char *what, const double *other_box, Mesh &sm,
                        sr_err *err)
{
    sr_mesh_edges edges;
    sr_status st = check_arrays(m, what, &edges, err);
    if (st != SR_OK)
        return st;
    size_t bad_tri = 0;
    if (!build_surface_mesh(m, sm, &bad_tri))
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' has a non-manifold vertex (at triangle %zu)", what,
                          bad_tri);
    if (other_box ? self_intersects_near(sm, other_box) : PMP::does_self_intersect(sm))
        return sr_err_set(err, SR_E_INVALID, "'%s' intersects itself%s", what,
                          other_box ? " where the other mesh is" : "");
    return SR_OK;
}

/* Copies a triangulated Surface_mesh into *out: only vertices used by a face, numbered
 * compactly in index order; any face of more than three sides fanned into triangles.
 * No faces: *out is an empty mesh. */
/* The number of sides of face f, walking its halfedges at most `limit` steps; 0 when
 * the walk does not come back to where it started (a corefinement of a noisy rail's
 * scan left such a face, and Surface_mesh::degree looped on it for minutes). */
static size_t face_sides(const Mesh &sm, Mesh::Face_index f, size_t limit)
{
    Mesh::Halfedge_index h0 = sm.halfedge(f), h = h0;
    size_t n = 0;
    do {
        if (++n > limit || !sm.is_valid(h))
            return 0;
        h = sm.next(h);
    } while (h != h0);
    return n;
}

/* The order Surface_mesh::collect_garbage would leave n elements in (removed(i): the
 * element of index i is removed): each removed slot from the front takes the last
 * element kept. order[k] is the index now of the element it would put at k. */
template <class Removed>
static std::vector<uint32_t> order_after_collection(size_t n, Removed removed)
{
    std::vector<uint32_t> order(n);
    std::vector<char> gone(n);
    for (size_t i = 0; i < n; i++) {
        order[i] = (uint32_t)i;
        gone[i] = removed(i) ? 1 : 0;
    }
    if (n == 0)
        return order;
    size_t i0 = 0, i1 = n - 1;
    for (;;) {
        while (!gone[i0] && i0 < i1)
            ++i0;
        while (gone[i1] && i0 < i1)
            --i1;
        if (i0 >= i1)
            break;
        std::swap(order[i0], order[i1]);
        std::swap(gone[i0], gone[i1]);
    }
    order.resize(gone[i0] ? i0 : i0 + 1);
    return order;
}

/* The arrays in the order a collected mesh would give them, without collecting: a
 * collection copies every property array of the mesh (the unfolding of a scan of a
 * million triangles peaked 56 MB higher for it). */
sr_status mesh_to_arrays(Mesh &sm, sr_mesh *out, sr_err *err, const char *doing)
{
    std::vector<uint32_t> vorder = order_after_collection(
        sm.num_vertices(), [&](size_t i) { return sm.is_removed(Vertex_index((uint32_t)i)); });
    std::vector<uint32_t> forder = order_after_collection(
        sm.num_faces(), [&](size_t i) { return sm.is_removed(Mesh::Face_index((uint32_t)i)); });
    const uint32_t unused = UINT32_MAX;
    std::vector<uint32_t> index(sm.num_vertices(), unused);
    size_t nt = 0, limit = sm.num_halfedges();
    for (uint32_t fi : forder) {
        Mesh::Face_index f(fi);
        size_t sides = face_sides(sm, f, limit);
        if (sides < 3)
            return sr_err_set(err, SR_E_INTERNAL, "%s: the result has a broken face", doing);
        nt += sides - 2;
        Mesh::Halfedge_index h0 = sm.halfedge(f), h = h0;
        do {
            index[sm.target(h).idx()] = 0;
            h = sm.next(h);
        } while (h != h0);
    }
    size_t nv = 0;
    for (uint32_t v : vorder)
        if (index[v] != unused)
            index[v] = static_cast<uint32_t>(nv++);
    sr_mesh res;
    sr_mesh_init(&res);
    if (nt == 0) { /* e.g. the intersection of disjoint meshes */
        *out = res;
        return SR_OK;
    }
    if (nv > SR_MESH_MAX_COUNT || nt > SR_MESH_MAX_COUNT)
        return sr_err_set(err, SR_E_RANGE, "%s: result too large (%zu triangles)", doing,
                          nt);
    if (sr_mesh_alloc(&res, nv, nt) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "%s: out of memory for %zu triangles", doing,
                          nt);
    for (uint32_t vi : vorder) {
        uint32_t i = index[vi];
        if (i == unused)
            continue;
        const Point &p = sm.point(Vertex_index(vi));
        double *q = res.xyz + 3 * static_cast<size_t>(i);
        q[0] = p.x();
        q[1] = p.y();
        q[2] = p.z();
    }
    uint32_t *t = res.tri;
    for (uint32_t fi : forder) {
        Mesh::Face_index f(fi);
        /* a fan of sides - 2 triangles from the first vertex (the walk is bounded by
         * the count found above, whatever vertices the face repeats) */
        Mesh::Halfedge_index h0 = sm.halfedge(f);
        uint32_t first = index[sm.source(h0).idx()];
        Mesh::Halfedge_index h = sm.next(h0);
        for (size_t k = face_sides(sm, f, limit); k > 2; k--) {
            t[0] = first;
            t[1] = index[sm.source(h).idx()];
            t[2] = index[sm.target(h).idx()];
            t += 3;
            h = sm.next(h);
        }
    }
    *out = res;
    return SR_OK;
}

} // namespace sr_bool

using namespace sr_bool;

extern "C" {

sr_status sr_mesh_self_intersects(const sr_mesh *mesh, int *out, sr_err *err)
{
    try {
        sr_status st = sr_mesh_validate(mesh, "mesh", NULL, err);
        if (st != SR_OK)
            return st;
        Mesh sm;
        size_t bad_tri = 0;
        if (!build_surface_mesh(mesh, sm, &bad_tri))
            return sr_err_set(err, SR_E_INVALID,
                              "'mesh' is not an oriented manifold (triangle %zu shares an "
                              "edge or vertex it cannot)",
                              bad_tri);
        *out = PMP::does_self_intersect(sm) ? 1 : 0;
        return SR_OK;
    } catch (...) {
        return status_from_exception(err, "self-intersection test");
    }
}

} // extern "C"
