/*
 * hull_cgal.cpp: convex hulls of point sets (see hull.h) by CGAL's convex_hull_3 into a
 * Surface_mesh over exact predicates, copied out as indexed triangles.
 */
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <exception>
#include <new>
#include <vector>

extern "C" {
#include "bridge/hull.h"
}

namespace {
typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;

sr_status hull(const double *xyz, size_t n, sr_mesh *out, sr_err *err)
{
    if (n < 4)
        return sr_err_set(err, SR_E_INVALID, "convex hull of %zu points has no volume", n);
    std::vector<Point> pts;
    pts.reserve(n);
    for (size_t i = 0; i < n; i++)
        pts.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    Mesh sm;
    CGAL::convex_hull_3(pts.begin(), pts.end(), sm);
    if (sm.number_of_faces() < 4)
        return sr_err_set(err, SR_E_INVALID, "convex hull of %zu points has no volume", n);
    std::vector<uint32_t> index(sm.number_of_vertices());
    sr_mesh res;
    sr_mesh_init(&res);
    if (sr_mesh_alloc(&res, sm.number_of_vertices(), sm.number_of_faces()) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a convex hull");
    size_t v = 0;
    for (Mesh::Vertex_index vi : sm.vertices()) {
        const Point &p = sm.point(vi);
        res.xyz[3 * v] = p.x();
        res.xyz[3 * v + 1] = p.y();
        res.xyz[3 * v + 2] = p.z();
        index[vi.idx()] = static_cast<uint32_t>(v++);
    }
    size_t t = 0;
    for (Mesh::Face_index f : sm.faces()) {
        int k = 0;
        for (Mesh::Vertex_index vi : sm.vertices_around_face(sm.halfedge(f)))
            if (k < 3)
                res.tri[3 * t + k++] = index[vi.idx()];
        t++;
    }
    *out = res;
    return SR_OK;
}
} // namespace

extern "C" sr_status sr_convex_hull(const double *xyz, size_t n, sr_mesh *out, sr_err *err)
{
    try {
        return hull(xyz, n, out, err);
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "convex hull: out of memory");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "convex hull: %s", e.what());
    }
}
