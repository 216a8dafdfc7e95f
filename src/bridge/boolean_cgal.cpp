/*
 * boolean_cgal.cpp: robust 3D booleans (union, intersection, difference), the
 * self-intersection test and surface deviation, behind the pure-C header boolean.h.
 *
 * Booleans use CGAL 5.5 Polygon Mesh Processing corefinement
 * (corefine_and_compute_union / _intersection / _difference) on a
 * Surface_mesh<Epick::Point_3>: exact predicates, intersection points constructed
 * exactly and rounded to double once. The Surface_mesh is built straight from the
 * sr_mesh arrays (CGAL's file readers are several times slower). Each input is checked
 * first, in the order a user can act on: validate (empty, NaN, bad index), degenerate
 * triangles, closed, manifold, consistently oriented, not inside out, buildable as a
 * halfedge mesh, not self-intersecting; every refusal is SR_E_INVALID naming the input.
 * The result is checked after (CGAL::is_closed, then sr_mesh_is_closed on the arrays).
 *
 * Deviation samples every vertex and every triangle centroid of a, and asks an AABB
 * tree over b's triangles for the squared distance to the nearest point (CGAL builds a
 * KD-tree of b's reference points on the first query to start each search close). The
 * tree holds b as a triangle soup rather than a face graph, so b may be open,
 * non-manifold or inconsistently oriented (a raw scan); zero-area triangles of b are
 * left out (they hold no point that their neighbours' edges do not).
 *
 * CGAL_ALWAYS_ROUND_TO_NEAREST: CGAL's interval filters normally switch the FPU to
 * round-upward; Valgrind ignores rounding-mode changes, so under Valgrind the filtered
 * predicates lie and corefinement writes out of bounds (seen: invalid writes, a failed
 * union). With this macro the intervals are widened by nextafter in round-to-nearest
 * instead: correct everywhere, 5-20 % slower (measured on the
 * shaft union and on 1M-triangle meshes).
 *
 * This translation unit is slow to compile (about 40 s, 1.7 GB at -O2): keep the
 * includes to the CGAL headers below. CGAL's PMP package is GPL-3.0-or-later.
 * Every extern "C" entry catches all exceptions: std::bad_alloc -> SR_E_NOMEM,
 * anything else -> SR_E_INTERNAL with what() in the message.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* before any CGAL header; see above */

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

extern "C" {
#include "bridge/boolean.h"
#include "mesh.h"
#include "status.h"
}

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef K::Triangle_3 Triangle;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex_index;

typedef std::vector<Triangle>::const_iterator Triangle_iterator;
typedef CGAL::AABB_triangle_primitive<K, Triangle_iterator> Primitive;
typedef CGAL::AABB_traits<K, Primitive> Aabb_traits;
typedef CGAL::AABB_tree<Aabb_traits> Aabb_tree;

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

sr_status check_operand(const sr_mesh *m, const char *what, const double *other_box, Mesh &sm,
                        sr_err *err)
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
    sr_mesh_edges edges;
    st = sr_mesh_edge_stats(m, &edges);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory counting the edges of '%s'", what);
    if (edges.boundary_edges)
        return sr_err_set(err, SR_E_INVALID, "'%s' is not closed (%zu boundary edges)",
                          what, edges.boundary_edges);
    if (edges.nonmanifold_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is not manifold (%zu edges shared by three or more "
                          "triangles)",
                          what, edges.nonmanifold_edges);
    if (edges.misoriented_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is not consistently oriented (%zu edges traversed the "
                          "same way by both triangles)",
                          what, edges.misoriented_edges);
    double volume = sr_mesh_volume(m);
    if (!(volume > 0))
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is inside out (enclosed volume %g mm^3)", what, volume);
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
sr_status mesh_to_arrays(Mesh &sm, sr_mesh *out, sr_err *err, const char *doing)
{
    if (sm.has_garbage())
        sm.collect_garbage();
    const uint32_t unused = UINT32_MAX;
    std::vector<uint32_t> index(sm.number_of_vertices(), unused);
    size_t nt = 0;
    for (Mesh::Face_index f : sm.faces()) {
        nt += sm.degree(f) - 2;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            index[v.idx()] = 0;
    }
    size_t nv = 0;
    for (uint32_t &i : index)
        if (i != unused)
            i = static_cast<uint32_t>(nv++);
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
    for (Vertex_index v : sm.vertices()) {
        uint32_t i = index[v.idx()];
        if (i == unused)
            continue;
        const Point &p = sm.point(v);
        double *q = res.xyz + 3 * static_cast<size_t>(i);
        q[0] = p.x();
        q[1] = p.y();
        q[2] = p.z();
    }
    uint32_t *t = res.tri;
    for (Mesh::Face_index f : sm.faces()) {
        Mesh::Halfedge_index h0 = sm.halfedge(f);
        uint32_t first = index[sm.source(h0).idx()];
        Mesh::Halfedge_index h = sm.next(h0);
        while (sm.target(h) != sm.source(h0)) {
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

sr_status boolean_compute(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                          const sr_mesh *b, const char *b_what, sr_mesh *out,
                          sr_err *err)
{
    const char *name = op_name(op);
    if (op != SR_BOOLEAN_UNION && op != SR_BOOLEAN_INTERSECTION &&
        op != SR_BOOLEAN_DIFFERENCE)
        return sr_err_set(err, SR_E_RANGE, "unknown boolean operation %d",
                          static_cast<int>(op));
    if (!a_what)
        a_what = "first mesh";
    if (!b_what)
        b_what = "second mesh";

    Mesh ma, mb;
    double box_a[6], box_b[6];
    sr_mesh_bbox(a, box_a, box_a + 3);
    sr_mesh_bbox(b, box_b, box_b + 3);
    sr_status st = check_operand(a, a_what, box_b, ma, err);
    if (st != SR_OK)
        return st;
    st = check_operand(b, b_what, box_a, mb, err);
    if (st != SR_OK)
        return st;

    /* The result goes into ma in place (both inputs are corefined anyway). */
    bool ok = false;
    switch (op) {
    case SR_BOOLEAN_UNION: ok = PMP::corefine_and_compute_union(ma, mb, ma); break;
    case SR_BOOLEAN_INTERSECTION:
        ok = PMP::corefine_and_compute_intersection(ma, mb, ma);
        break;
    case SR_BOOLEAN_DIFFERENCE: ok = PMP::corefine_and_compute_difference(ma, mb, ma); break;
    }
    if (!ok)
        return sr_err_set(err, SR_E_INVALID,
                          "cannot compute the %s of '%s' and '%s': the result would not "
                          "be a manifold surface (the meshes touch along an edge or at a "
                          "point)",
                          name, a_what, b_what);
    if (!CGAL::is_closed(ma))
        return sr_err_set(err, SR_E_INTERNAL,
                          "the %s of '%s' and '%s' is not closed", name, a_what, b_what);

    char doing[160];
    snprintf(doing, sizeof doing, "%s of '%s' and '%s'", name, a_what, b_what);
    sr_mesh res;
    st = mesh_to_arrays(ma, &res, err, doing);
    if (st != SR_OK)
        return st;
    if (res.tri_count && !sr_mesh_is_closed(&res)) {
        sr_mesh_release(&res);
        return sr_err_set(err, SR_E_INTERNAL, "the %s is not closed once converted",
                          doing);
    }
    if (out == a || out == b)
        sr_mesh_release(out);
    *out = res;
    return SR_OK;
}

sr_status boolean_entry(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                        const sr_mesh *b, const char *b_what, sr_mesh *out, sr_err *err)
{
    try {
        return boolean_compute(op, a, a_what, b, b_what, out, err);
    } catch (...) {
        return status_from_exception(err, op_name(op));
    }
}

sr_status repair(sr_mesh *m, int fix_crossings, sr_repair_report *rep, sr_err *err)
{
    *rep = sr_repair_report();
    sr_status st = sr_mesh_validate(m, "mesh to repair", nullptr, err);
    if (st != SR_OK)
        return st;
    Mesh sm;
    size_t bad_tri = 0;
    if (!build_surface_mesh(m, sm, &bad_tri))
        return sr_err_set(err, SR_E_INVALID,
                          "cannot repair: non-manifold vertex or edge at triangle %zu", bad_tri);
    size_t before = sm.number_of_faces();
    bool degenerate = false;
    for (Mesh::Face_index f : sm.faces())
        if (PMP::is_degenerate_triangle_face(f, sm)) {
            degenerate = true;
            break;
        }
    if (degenerate) {
        PMP::remove_degenerate_faces(sm);
        sm.collect_garbage();
        rep->degenerate_removed = before > sm.number_of_faces() ? before - sm.number_of_faces() : 0;
        rep->changed = 1;
    }
    (void)fix_crossings;
    if (!rep->changed)
        return SR_OK;
    sr_mesh res;
    st = mesh_to_arrays(sm, &res, err, "repair");
    if (st != SR_OK)
        return st;
    sr_mesh_release(m);
    *m = res;
    return SR_OK;
}

} // namespace

extern "C" {

sr_status sr_mesh_repair(sr_mesh *mesh, int fix_crossings, sr_repair_report *report,
                         sr_err *err)
{
    sr_repair_report local;
    try {
        return repair(mesh, fix_crossings, report ? report : &local, err);
    } catch (...) {
        return status_from_exception(err, "repair");
    }


}

sr_status sr_boolean_compute(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                             const sr_mesh *b, const char *b_what, sr_mesh *out,
                             sr_err *err)
{
    return boolean_entry(op, a, a_what, b, b_what, out, err);
}

sr_status sr_boolean_union(const sr_mesh *a, const sr_mesh *b, sr_mesh *out, sr_err *err)
{
    return boolean_entry(SR_BOOLEAN_UNION, a, NULL, b, NULL, out, err);
}

sr_status sr_boolean_intersection(const sr_mesh *a, const sr_mesh *b, sr_mesh *out,
                                  sr_err *err)
{
    return boolean_entry(SR_BOOLEAN_INTERSECTION, a, NULL, b, NULL, out, err);
}

sr_status sr_boolean_difference(const sr_mesh *a, const sr_mesh *b, sr_mesh *out,
                                sr_err *err)
{
    return boolean_entry(SR_BOOLEAN_DIFFERENCE, a, NULL, b, NULL, out, err);
}

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

sr_status sr_mesh_deviation(const sr_mesh *a, const sr_mesh *b, sr_deviation *out,
                            sr_err *err)
{
    try {
        sr_status st = sr_mesh_validate(a, "sampled mesh", NULL, err);
        if (st != SR_OK)
            return st;
        st = sr_mesh_validate(b, "reference mesh", NULL, err);
        if (st != SR_OK)
            return st;

        std::vector<Triangle> tris;
        tris.reserve(b->tri_count);
        for (size_t t = 0; t < b->tri_count; t++) {
            const uint32_t *f = b->tri + 3 * t;
            const double *p = b->xyz + 3 * f[0], *q = b->xyz + 3 * f[1],
                         *r = b->xyz + 3 * f[2];
            Triangle tri(Point(p[0], p[1], p[2]), Point(q[0], q[1], q[2]),
                         Point(r[0], r[1], r[2]));
            if (!tri.is_degenerate())
                tris.push_back(tri);
        }
        if (tris.empty())
            return sr_err_set(err, SR_E_INVALID,
                              "'reference mesh' has no triangle of non-zero area");
        Aabb_tree tree(tris.begin(), tris.end());
        tree.build();
        tree.accelerate_distance_queries();

        double max2 = 0, sum = 0, sum2 = 0;
        auto sample = [&](const Point &p) {
            double d2 = tree.squared_distance(p);
            if (d2 > max2)
                max2 = d2;
            sum += std::sqrt(d2);
            sum2 += d2;
        };
        for (size_t v = 0; v < a->vertex_count; v++) {
            const double *p = a->xyz + 3 * v;
            sample(Point(p[0], p[1], p[2]));
        }
        for (size_t t = 0; t < a->tri_count; t++) {
            const uint32_t *f = a->tri + 3 * t;
            const double *p = a->xyz + 3 * f[0], *q = a->xyz + 3 * f[1],
                         *r = a->xyz + 3 * f[2];
            sample(Point((p[0] + q[0] + r[0]) / 3, (p[1] + q[1] + r[1]) / 3,
                         (p[2] + q[2] + r[2]) / 3));
        }
        size_t n = a->vertex_count + a->tri_count;
        sr_deviation d;
        d.max_mm = std::sqrt(max2);
        d.mean_mm = sum / static_cast<double>(n);
        d.rms_mm = std::sqrt(sum2 / static_cast<double>(n));
        d.samples = n;
        *out = d;
        return SR_OK;
    } catch (...) {
        return status_from_exception(err, "surface deviation");
    }
}

} // extern "C"
