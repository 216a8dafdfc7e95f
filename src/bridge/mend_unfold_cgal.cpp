/*
 * mend_unfold_cgal.cpp: mend.h's two repairs that move vertices instead of cutting
 * faces out (mend_cgal.cpp does that), on the same Surface_mesh built from the arrays
 * (build, mend_cgal.hpp). sr_mesh_unfold relaxes the crossing triangles' vertices
 * towards the centres of their rings, never farther than max_move_mm, looking again
 * around what it moved, round after round; sr_mesh_collapse_short_edges collapses the
 * short edges where CGAL's Euler link condition allows, in passes, and keeps the result
 * (vertices renumbered) only when the faces it moved cross no face near them. Every
 * extern "C" entry catches all exceptions.
 */
#include "bridge/mend_cgal.hpp"

#include <CGAL/Bbox_3.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <iterator>
#include <new>
#include <utility>
#include <vector>

namespace sr_mend {

namespace {

const int unfold_rounds_max = 6; /* relaxation rounds of sr_mesh_unfold */

} // namespace

/* The faces around the seed vertices (removed ones skipped) and rings - 1 rings more,
 * each once, in index order. */
std::vector<Face_index> faces_near(const Mesh &sm, std::vector<Vertex_index> seeds, int rings)
{
    std::vector<uint8_t> take(sm.num_faces(), 0);
    std::vector<Vertex_index> more;
    for (int r = 0; r < rings; r++) {
        more.clear();
        for (Vertex_index v : seeds) {
            if (sm.is_removed(v) || sm.halfedge(v) == Mesh::null_halfedge())
                continue;
            for (Face_index f : sm.faces_around_target(sm.halfedge(v))) {
                if (f == Mesh::null_face() || take[f.idx()])
                    continue;
                take[f.idx()] = 1;
                for (Vertex_index w : sm.vertices_around_face(sm.halfedge(f)))
                    more.push_back(w);
            }
        }
        seeds.swap(more);
    }
    std::vector<Face_index> range;
    for (Face_index f : sm.faces())
        if (take[f.idx()])
            range.push_back(f);
    return range;
}

/* The rounds of sr_mesh_unfold (see mend.h) on sm, looking first among range. */
void unfold_rounds(Mesh &sm, std::vector<Face_index> range, double max_move, sr_unfold_report *rep)
{
    /* where each moved vertex started: slot[v] indexes start, kept for the moved ones
     * only (4 bytes a vertex, not a copy of every point) */
    const uint32_t unmoved = UINT32_MAX;
    std::vector<uint32_t> slot(sm.num_vertices(), unmoved);
    std::vector<Point> start;
    for (int round = 0; round < unfold_rounds_max; round++) {
        std::vector<std::pair<Face_index, Face_index>> pairs = crossing_pairs(sm, range, 0);
        if (round == 0)
            rep->crossing_pairs = pairs.size();
        rep->remaining_pairs = pairs.size();
        if (pairs.empty())
            break;
        /* the crossing triangles' vertices off the border, each to halfway towards
         * the centre of its ring (Jacobi: all from the old positions) */
        std::vector<Vertex_index> verts;
        for (const auto &pr : pairs)
            for (Face_index f : {pr.first, pr.second})
                for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
                    verts.push_back(v);
        std::sort(verts.begin(), verts.end());
        verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
        std::vector<Point> next;
        next.reserve(verts.size());
        for (Vertex_index v : verts) {
            const Point &p = sm.point(v);
            if (sm.is_border(v)) {
                next.push_back(p);
                continue;
            }
            double c[3] = {0, 0, 0};
            int n = 0;
            for (Vertex_index w : sm.vertices_around_target(sm.halfedge(v))) {
                const Point &q = sm.point(w);
                c[0] += q.x();
                c[1] += q.y();
                c[2] += q.z();
                n++;
            }
            double t[3] = {0.5 * (p.x() + c[0] / n), 0.5 * (p.y() + c[1] / n),
                           0.5 * (p.z() + c[2] / n)};
            /* never farther than max_move from where the scan put it */
            const Point &o = slot[v.idx()] == unmoved ? p : start[slot[v.idx()]];
            double d[3] = {t[0] - o.x(), t[1] - o.y(), t[2] - o.z()};
            double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (len > max_move) {
                double k = max_move / len;
                t[0] = o.x() + k * d[0];
                t[1] = o.y() + k * d[1];
                t[2] = o.z() + k * d[2];
            }
            next.push_back(Point(t[0], t[1], t[2]));
        }
        for (size_t i = 0; i < verts.size(); i++) {
            uint32_t &k = slot[verts[i].idx()];
            if (k == unmoved) {
                k = (uint32_t)start.size();
                start.push_back(sm.point(verts[i]));
            }
            sm.point(verts[i]) = next[i];
        }
        /* the next round looks where this one moved: the triangles around the moved
         * vertices and two rings more */
        range = faces_near(sm, verts, 3);
    }
    double worst = 0;
    for (Vertex_index v : sm.vertices()) {
        if (slot[v.idx()] == unmoved)
            continue;
        rep->moved_vertices++;
        worst =
            std::max(worst, std::sqrt(CGAL::squared_distance(sm.point(v), start[slot[v.idx()]])));
    }
    rep->max_move_mm = worst;
}

namespace
{

/* sr_mesh_unfold proper: see mend.h. */
sr_status unfold(sr_mesh *m, double max_move, sr_unfold_report *rep, sr_err *err)
{
    Mesh sm;
    if (!build(m, sm))
        return sr_err_set(err, SR_E_INVALID, "cannot unfold: not an oriented manifold");
    unfold_rounds(sm, std::vector<Face_index>(sm.faces().begin(), sm.faces().end()), max_move, rep);
    if (rep->moved_vertices == 0)
        return SR_OK;
    for (Vertex_index v : sm.vertices()) {
        const Point &p = sm.point(v);
        double *x = m->xyz + 3 * v.idx();
        x[0] = p.x();
        x[1] = p.y();
        x[2] = p.z();
    }
    return SR_OK;
}

/* Whether a face around the vertices `moved` crosses a face (their own or any other
 * whose box comes within `grow` of theirs): the faces near them found by CGAL's box
 * intersection, then CGAL's self-intersection test on those faces only. A fold a
 * collapse makes is local; the rest of the mesh, which did not move, is not searched. */
bool crosses_near(const Mesh &sm, const std::vector<Vertex_index> &moved, double grow)
{
    typedef CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t> Box;
    std::vector<Face_index> around = faces_near(sm, moved, 1);
    if (around.empty())
        return false;
    std::vector<Box> near_boxes, all_boxes;
    near_boxes.reserve(around.size());
    all_boxes.reserve(sm.number_of_faces());
    for (Face_index f : sm.faces()) {
        CGAL::Bbox_3 b;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            b += sm.point(v).bbox();
        all_boxes.emplace_back(b, f.idx());
    }
    for (Face_index f : around) {
        CGAL::Bbox_3 b;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            b += sm.point(v).bbox();
        b.dilate(1);
        CGAL::Bbox_3 g(b.xmin() - grow, b.ymin() - grow, b.zmin() - grow, b.xmax() + grow,
                       b.ymax() + grow, b.zmax() + grow);
        near_boxes.emplace_back(g, f.idx());
    }
    std::vector<uint8_t> take(sm.num_faces(), 0);
    for (Face_index f : around)
        take[f.idx()] = 1;
    CGAL::box_intersection_d(near_boxes.begin(), near_boxes.end(), all_boxes.begin(),
                             all_boxes.end(),
                             [&take](const Box &, const Box &b) { take[b.info()] = 1; });
    std::vector<Face_index> range;
    for (Face_index f : sm.faces())
        if (take[f.idx()])
            range.push_back(f);
    return PMP::does_self_intersect(range, sm);
}

/* sr_mesh_collapse_short_edges proper: see mend.h. */
sr_status collapse_short(sr_mesh *m, double min_edge, size_t *collapsed, int *crossed, sr_err *err)
{
    Mesh sm;
    if (!build(m, sm))
        return sr_err_set(err, SR_E_INVALID, "cannot collapse edges: not an oriented manifold");
    size_t n = 0;
    double min2 = min_edge * min_edge;
    std::vector<Vertex_index> moved;
    for (int pass = 0; pass < 8; pass++) {
        size_t before = n;
        std::vector<Mesh::Edge_index> short_edges;
        for (Mesh::Edge_index e : sm.edges()) {
            Halfedge_index h = sm.halfedge(e);
            if (CGAL::squared_distance(sm.point(sm.source(h)), sm.point(sm.target(h))) < min2)
                short_edges.push_back(e);
        }
        for (Mesh::Edge_index e : short_edges) {
            if (sm.is_removed(e))
                continue;
            Halfedge_index h = sm.halfedge(e);
            Point a = sm.point(sm.source(h)), b = sm.point(sm.target(h));
            if (!(CGAL::squared_distance(a, b) < min2) || sm.is_border(e) ||
                !CGAL::Euler::does_satisfy_link_condition(e, sm))
                continue;
            Vertex_index v = CGAL::Euler::collapse_edge(e, sm);
            sm.point(v) = CGAL::midpoint(a, b);
            moved.push_back(v);
            n++;
        }
        if (n == before)
            break;
    }
    if (n == 0)
        return SR_OK;
    if (crosses_near(sm, moved, min_edge)) {
        *crossed = 1; /* a neighbour folded over: the mesh is left as it was */
        return SR_OK;
    }
    *collapsed = n;
    sm.collect_garbage();
    sr_mesh out;
    sr_mesh_init(&out);
    if (sr_mesh_alloc(&out, sm.number_of_vertices(), sm.number_of_faces()) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory collapsing edges");
    for (Vertex_index v : sm.vertices()) {
        const Point &p = sm.point(v);
        out.xyz[3 * v.idx()] = p.x();
        out.xyz[3 * v.idx() + 1] = p.y();
        out.xyz[3 * v.idx() + 2] = p.z();
    }
    size_t t = 0;
    for (Face_index f : sm.faces()) {
        int k = 0;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            out.tri[3 * t + k++] = static_cast<uint32_t>(v.idx());
        t++;
    }
    sr_mesh_release(m);
    *m = out;
    return SR_OK;
}

} // namespace

} // namespace sr_mend

using namespace sr_mend;

extern "C" {

sr_status sr_mesh_unfold(sr_mesh *mesh, double max_move_mm, sr_unfold_report *report,
                         sr_err *err)
{
    sr_unfold_report local;
    if (!report)
        report = &local;
    memset(report, 0, sizeof *report);
    try {
        return unfold(mesh, max_move_mm, report, err);
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory unfolding a mesh");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "unfolding a mesh: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "unfolding a mesh: unknown exception");
    }
}

sr_status sr_mesh_collapse_short_edges(sr_mesh *mesh, double min_edge_mm, size_t *collapsed,
                                       int *crossed, sr_err *err)
{
    size_t local = 0;
    int local_crossed = 0;
    if (!collapsed)
        collapsed = &local;
    if (!crossed)
        crossed = &local_crossed;
    *collapsed = 0;
    *crossed = 0;
    if (!(min_edge_mm > 0))
        return SR_OK;
    try {
        return collapse_short(mesh, min_edge_mm, collapsed, crossed, err);
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory collapsing edges");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "collapsing edges: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "collapsing edges: unknown exception");
    }
}

} // extern "C"
