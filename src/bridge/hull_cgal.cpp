/*
 * hull_cgal.cpp: convex hulls of point sets (see hull.h) by CGAL's convex_hull_3 into a
 * Surface_mesh over exact predicates, copied out as indexed triangles in a canonical
 * form that depends on the hull alone: convex_hull_3 orders its faces, and splits a
 * facet of coplanar points, by the addresses of its own cells (which follow the heap's
 * history: one more thread in an earlier step gave a section another hull mesh, and
 * the patch 16 other triangles). Each planar facet is fanned from its least vertex, the
 * vertices are sorted by their coordinates and the triangles by their indices.
 */
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <exception>
#include <new>
#include <numeric>
#include <vector>

extern "C" {
#include "bridge/hull.h"
}

namespace {
typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Halfedge_index Halfedge;
typedef std::array<uint32_t, 3> Tri;

/* The root of face f in the union-find parent. */
uint32_t root(std::vector<uint32_t> &parent, uint32_t f)
{
    while (parent[f] != f)
        f = parent[f] = parent[parent[f]];
    return f;
}

/* Faces joined into their planar facets: parent[f]'s root is the same for the faces of
 * one facet (an edge between two faces whose four corners are coplanar, exactly). */
std::vector<uint32_t> facets(const Mesh &sm)
{
    std::vector<uint32_t> parent(sm.number_of_faces());
    std::iota(parent.begin(), parent.end(), 0u);
    for (Mesh::Edge_index e : sm.edges()) {
        Halfedge h = sm.halfedge(e), o = sm.opposite(h);
        const Point &p = sm.point(sm.source(h)), &q = sm.point(sm.target(h));
        const Point &r = sm.point(sm.target(sm.next(h))), &s = sm.point(sm.target(sm.next(o)));
        if (CGAL::coplanar(p, q, r, s)) {
            uint32_t a = root(parent, (uint32_t)sm.face(h).idx());
            uint32_t b = root(parent, (uint32_t)sm.face(o).idx());
            parent[std::max(a, b)] = std::min(a, b);
        }
    }
    return parent;
}

/* The hull's triangles, each facet fanned from its least vertex (in rank, the vertices'
 * coordinate order) round its boundary; a facet whose fan would hold a triangle of
 * three collinear points keeps the hull's own triangles. */
std::vector<Tri> fanned(const Mesh &sm, const std::vector<uint32_t> &rank)
{
    std::vector<uint32_t> parent = facets(sm);
    std::vector<std::vector<Halfedge>> rim(sm.number_of_faces());
    for (Mesh::Halfedge_index h : sm.halfedges()) {
        if (sm.is_border(h))
            continue;
        uint32_t f = root(parent, (uint32_t)sm.face(h).idx());
        if (sm.is_border(sm.opposite(h)) ||
            root(parent, (uint32_t)sm.face(sm.opposite(h)).idx()) != f)
            rim[f].push_back(h);
    }
    std::vector<Tri> out;
    std::vector<uint32_t> next(sm.number_of_vertices()), loop;
    for (Mesh::Face_index fi : sm.faces()) {
        uint32_t f = (uint32_t)fi.idx();
        if (root(parent, f) != f)
            continue;
        /* the rim as one loop from its least vertex */
        uint32_t start = (uint32_t)sm.source(rim[f][0]).idx();
        for (Halfedge h : rim[f]) {
            uint32_t s = (uint32_t)sm.source(h).idx();
            next[s] = (uint32_t)sm.target(h).idx();
            if (rank[s] < rank[start])
                start = s;
        }
        loop.clear();
        uint32_t v = start;
        do {
            loop.push_back(v);
            v = next[v];
        } while (v != start && loop.size() <= rim[f].size());
        bool fan = loop.size() == rim[f].size();
        for (size_t k = 1; fan && k + 1 < loop.size(); k++)
            fan = !CGAL::collinear(sm.point(Mesh::Vertex_index(loop[0])),
                                   sm.point(Mesh::Vertex_index(loop[k])),
                                   sm.point(Mesh::Vertex_index(loop[k + 1])));
        if (fan) {
            for (size_t k = 1; k + 1 < loop.size(); k++)
                out.push_back({loop[0], loop[k], loop[k + 1]});
            continue;
        }
        for (Mesh::Face_index g : sm.faces())
            if (root(parent, (uint32_t)g.idx()) == f) {
                Tri t;
                int k = 0;
                for (Mesh::Vertex_index vi : sm.vertices_around_face(sm.halfedge(g)))
                    if (k < 3)
                        t[k++] = (uint32_t)vi.idx();
                out.push_back(t);
            }
    }
    return out;
}

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
    sm.collect_garbage(); /* indices 0 .. count - 1 */
    /* the vertices in coordinate order: rank[v] is v's place in it */
    size_t nv = sm.number_of_vertices();
    std::vector<uint32_t> order(nv), rank(nv);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return sm.point(Mesh::Vertex_index(a)) < sm.point(Mesh::Vertex_index(b));
    });
    for (size_t k = 0; k < nv; k++)
        rank[order[k]] = static_cast<uint32_t>(k);
    std::vector<Tri> tris = fanned(sm, rank);
    for (Tri &t : tris) {
        for (uint32_t &v : t)
            v = rank[v];
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    }
    std::sort(tris.begin(), tris.end());
    sr_mesh res;
    sr_mesh_init(&res);
    if (sr_mesh_alloc(&res, nv, tris.size()) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a convex hull");
    for (size_t k = 0; k < nv; k++) {
        const Point &p = sm.point(Mesh::Vertex_index(order[k]));
        res.xyz[3 * k] = p.x();
        res.xyz[3 * k + 1] = p.y();
        res.xyz[3 * k + 2] = p.z();
    }
    for (size_t t = 0; t < tris.size(); t++)
        for (int k = 0; k < 3; k++)
            res.tri[3 * t + k] = tris[t][k];
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
