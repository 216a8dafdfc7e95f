/*
 * mend_cgal.cpp: local mending of a surface that crosses itself (see mend.h), on a
 * CGAL Surface_mesh built straight from the sr_mesh arrays (vertex i is Vertex_index i;
 * no vertex is ever added, so indices map back one to one). Crossings are found by PMP
 * self_intersections on the triangles near the box and taken out (attempt r takes r
 * rings of neighbours with them: the smallest holes first). Each region taken out is
 * filled again from its own points: a constrained Delaunay triangulation (CGAL CDT_2)
 * of its rim and inner vertices seen along its mean normal, its rim and every edge of
 * it that crosses no other one there as constraints. The scan's points stay where the
 * scanner put them and the faces that did not fold come back as they were, so a fold
 * along a sharp edge keeps the edge. A region whose rim crosses itself seen that way
 * takes the faces around the crossing too; one that still cannot be seen one to one is
 * filled from its rim alone by PMP triangulate_hole (minimum-weight triangulation of
 * the rim's vertices, which cuts across a sharp edge: the keyed shaft's noisy scan lost
 * up to 2.9 mm of its dent's rim that way). Each ring count is tried twice: with the
 * later passes' fills checked against the faces around them (a fill that crosses them
 * takes them too, rather than the same crossing coming back pass after pass), and
 * without; the one with fewer holes filled from their rims wins. The mesh's own border
 * (a neighbourhood's rim) is recorded first and must stay as it is.
 *
 * Kept out of boolean_cgal.cpp: the hole-filling headers are heavy to compile, and the
 * two translation units build in parallel. CGAL_ALWAYS_ROUND_TO_NEAREST for Valgrind as
 * there (see its comment). Every extern "C" entry catches all exceptions.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* before any CGAL header; see boolean_cgal.hpp */

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iterator>
#include <new>
#include <unordered_map>
#include <utility>
#include <vector>

extern "C" {
#include "bridge/mend.h"
#include "mesh/mesh.h"
#include "base/status.h"
}

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex_index;
typedef Mesh::Face_index Face_index;
typedef Mesh::Halfedge_index Halfedge_index;

/* the re-triangulation of a hole in the plane across its mean normal */
typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> Cdt_vb;
typedef CGAL::Constrained_triangulation_face_base_2<K> Cdt_fb0;
typedef CGAL::Triangulation_face_base_with_info_2<int, K, Cdt_fb0> Cdt_fb;
typedef CGAL::Triangulation_data_structure_2<Cdt_vb, Cdt_fb> Cdt_tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Cdt_tds, CGAL::No_constraint_intersection_tag>
    Cdt;

const int max_rings = 4;  /* attempts take 0..max_rings rings around the crossings */
const int max_passes = 3; /* cut-and-fill passes per attempt */
const int max_grow = 8;   /* growth steps of a region whose rim crosses itself */
const int unfold_rounds = 6; /* relaxation rounds of sr_mesh_unfold */

bool build(const sr_mesh *m, Mesh &sm)
{
    sm.reserve(static_cast<Mesh::size_type>(m->vertex_count),
               static_cast<Mesh::size_type>(m->tri_count * 3 / 2 + 3),
               static_cast<Mesh::size_type>(m->tri_count));
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        sm.add_vertex(Point(p[0], p[1], p[2]));
    }
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
            sm.add_face(Vertex_index(f[0]), Vertex_index(f[1]), Vertex_index(f[2])) ==
                Mesh::null_face())
            return false;
    }
    return true;
}

std::vector<Face_index> near_faces(const Mesh &sm, const double *box)
{
    std::vector<Face_index> near;
    for (Face_index f : sm.faces()) {
        if (box) {
            CGAL::Bbox_3 b = PMP::face_bbox(f, sm);
            if (!(b.xmax() >= box[0] && b.xmin() <= box[3] && b.ymax() >= box[1] &&
                  b.ymin() <= box[4] && b.zmax() >= box[2] && b.zmin() <= box[5]))
                continue;
        }
        near.push_back(f);
    }
    return near;
}

/* One region of the faces to take out (connected across edges): its rim (the directed
 * edges of its faces that another face runs the other way), its inner vertices (every
 * face at them taken out) and the sum of its faces' area vectors. */
struct Region {
    std::vector<Face_index> faces;
    std::vector<std::pair<uint32_t, uint32_t>> rim;
    std::vector<std::pair<uint32_t, uint32_t>> edges; /* between two of its faces, once */
    std::vector<Vertex_index> inner;
    K::Vector_3 normal = K::Vector_3(0, 0, 0);
};

/* Splits the faces `cut` (mark: 1 for them) into regions. */
std::vector<Region> regions_of(const Mesh &sm, const std::vector<Face_index> &cut,
                               const std::vector<uint8_t> &mark)
{
    std::vector<Region> regions;
    std::vector<uint8_t> done(mark.size(), 0);
    std::vector<uint8_t> inner_seen(sm.num_vertices(), 0);
    for (Face_index f0 : cut) {
        if (done[f0.idx()])
            continue;
        Region reg;
        std::vector<Face_index> stack(1, f0);
        done[f0.idx()] = 1;
        while (!stack.empty()) {
            Face_index f = stack.back();
            stack.pop_back();
            reg.faces.push_back(f);
            Halfedge_index h0 = sm.halfedge(f);
            const Point &p = sm.point(sm.source(h0)), &q = sm.point(sm.target(h0)),
                        &r = sm.point(sm.target(sm.next(h0)));
            reg.normal = reg.normal + CGAL::cross_product(q - p, r - p);
            for (Halfedge_index h : sm.halfedges_around_face(h0)) {
                Face_index g = sm.face(sm.opposite(h));
                if (g != Mesh::null_face() && mark[g.idx()]) {
                    if (sm.source(h) < sm.target(h))
                        reg.edges.emplace_back(static_cast<uint32_t>(sm.source(h).idx()),
                                               static_cast<uint32_t>(sm.target(h).idx()));
                    if (!done[g.idx()]) {
                        done[g.idx()] = 1;
                        stack.push_back(g);
                    }
                } else {
                    reg.rim.emplace_back(static_cast<uint32_t>(sm.source(h).idx()),
                                         static_cast<uint32_t>(sm.target(h).idx()));
                }
                Vertex_index v = sm.target(h);
                if (inner_seen[v.idx()])
                    continue;
                bool inner = true;
                for (Face_index g2 : sm.faces_around_target(h))
                    if (g2 == Mesh::null_face() || !mark[g2.idx()])
                        inner = false;
                if (inner) {
                    inner_seen[v.idx()] = 1;
                    reg.inner.push_back(v);
                }
            }
        }
        regions.push_back(std::move(reg));
    }
    return regions;
}

/* Pairs of the segments `seg` that cross or overlap in the plane, handed to
 * found(i, j) (a sweep over their bounding boxes along x). Segments at a common end (ends[i]) meet
 * there: they count only when they overlap (collinear, going the same way from it). */
template <class Found>
void crossing_segments(const std::vector<K::Segment_2> &seg,
                       const std::vector<std::pair<uint32_t, uint32_t>> &ends, Found found)
{
    std::vector<size_t> order(seg.size());
    for (size_t i = 0; i < seg.size(); i++)
        order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t i, size_t j) {
        return seg[i].bbox().xmin() < seg[j].bbox().xmin();
    });
    for (size_t a1 = 0; a1 < order.size(); a1++) {
        size_t i = order[a1];
        CGAL::Bbox_2 b1 = seg[i].bbox();
        for (size_t a2 = a1 + 1; a2 < order.size(); a2++) {
            size_t j = order[a2];
            CGAL::Bbox_2 b2 = seg[j].bbox();
            if (b2.xmin() > b1.xmax())
                break;
            if (b2.ymin() > b1.ymax() || b2.ymax() < b1.ymin())
                continue;
            const auto &e1 = ends[i], &e2 = ends[j];
            bool crossing;
            if (e1.first == e2.first || e1.first == e2.second || e1.second == e2.first ||
                e1.second == e2.second) {
                bool at1 = e1.first == e2.first || e1.first == e2.second;
                uint32_t other2 = (e2.first == e1.first || e2.first == e1.second) ? 1 : 0;
                const K::Point_2 &c = at1 ? seg[i].source() : seg[i].target(),
                                 &p1 = at1 ? seg[i].target() : seg[i].source(),
                                 &p2 = other2 ? seg[j].target() : seg[j].source();
                crossing = CGAL::collinear(c, p1, p2) &&
                           !CGAL::collinear_are_ordered_along_line(p1, c, p2);
            } else {
                crossing = CGAL::do_intersect(seg[i], seg[j]);
            }
            if (crossing)
                found(i, j);
        }
    }
}

/* True when the triangles `out` (a region's fill) cross neither each other nor the
 * faces of sm that share a vertex with the region (outside it), checked by PMP
 * self_intersections on a small mesh of the two. False: the vertices of the crossing
 * faces are added to grow_at. */
bool fits_in_space(const Mesh &sm, const Region &reg, size_t id,
                   const std::vector<uint32_t> &region_of, const std::vector<uint32_t> &out,
                   std::vector<uint32_t> &grow_at)
{
    Mesh small;
    std::unordered_map<uint32_t, Vertex_index> local;
    std::vector<uint32_t> global;
    auto vertex = [&](uint32_t w) {
        auto it = local.find(w);
        if (it != local.end())
            return it->second;
        Vertex_index v = small.add_vertex(sm.point(Vertex_index(w)));
        local.emplace(w, v);
        global.push_back(w);
        return v;
    };
    std::vector<uint8_t> is_fill;
    auto face = [&](uint32_t x, uint32_t y, uint32_t z, bool fill) {
        Vertex_index a = vertex(x), b = vertex(y), c = vertex(z);
        Face_index f = small.add_face(a, b, c);
        if (f == Mesh::null_face())
            return false;
        if (is_fill.size() <= f.idx())
            is_fill.resize(f.idx() + 1, 0);
        is_fill[f.idx()] = fill;
        return true;
    };
    for (size_t t = 0; t < out.size(); t += 3)
        if (!face(out[t], out[t + 1], out[t + 2], true))
            return false;
    std::vector<uint8_t> seen(region_of.size(), 0);
    for (Face_index f : reg.faces)
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            for (Face_index g : sm.faces_around_target(sm.halfedge(v))) {
                if (g == Mesh::null_face() || region_of[g.idx()] == id || seen[g.idx()])
                    continue;
                seen[g.idx()] = 1;
                uint32_t w[3], k = 0;
                for (Vertex_index x : sm.vertices_around_face(sm.halfedge(g)))
                    w[k++] = static_cast<uint32_t>(x.idx());
                if (!face(w[0], w[1], w[2], false))
                    return false;
            }
    std::vector<std::pair<Face_index, Face_index>> pairs;
    PMP::self_intersections(small, std::back_inserter(pairs));
    bool crossing = false;
    for (const auto &p : pairs) {
        if (!is_fill[p.first.idx()] && !is_fill[p.second.idx()])
            continue; /* two faces around: not this fill's doing */
        crossing = true;
        for (Face_index f : {p.first, p.second})
            for (Vertex_index v : small.vertices_around_face(small.halfedge(f)))
                grow_at.push_back(global[v.idx()]);
    }
    return !crossing;
}

/* The triangles that fill `reg` again with the surface its own points sample: a
 * constrained Delaunay triangulation of its rim and inner vertices seen along its mean
 * normal, with the rim's edges and every edge of its own that crosses no other one
 * there as constraints (where the faces did not fold, they come back as they were),
 * the triangles inside the rim kept (no new vertex). The scan's points and edges stay
 * where they are, so a region across a sharp edge keeps the edge (a fill from the rim
 * alone cuts across it). False when the region is not seen one to one along its normal:
 * rim edges cross there, or the triangles would not fit the mesh (a rim edge not run
 * once the way the region's faces did, an edge the mesh has outside the region).
 * in_space: the triangles must not cross the faces around either (fits_in_space), else
 * fill_crossing (nothing appended). Where it fails, the vertices are added to grow_at
 * (the caller takes the faces there too, or fills the region from its rim). region_of:
 * the region number of each face (reg is number `id`). */
enum Fill { fill_none, fill_ok, fill_crossing };
Fill fill_from_points(const Mesh &sm, const Region &reg, size_t id,
                      const std::vector<uint32_t> &region_of, bool in_space,
                      std::vector<uint32_t> &tris, std::vector<uint32_t> &grow_at)
{
    double len = std::sqrt(reg.normal.squared_length());
    if (!(len > 0) || reg.rim.size() < 3)
        return fill_none;
    K::Vector_3 n = reg.normal / len;
    /* u, v, n right-handed: counter-clockwise in (u, v) is outward along n */
    K::Vector_3 a = std::fabs(n.x()) < 0.6 ? K::Vector_3(1, 0, 0) : K::Vector_3(0, 1, 0);
    K::Vector_3 u = CGAL::cross_product(a, n);
    u = u / std::sqrt(u.squared_length());
    K::Vector_3 v = CGAL::cross_product(n, u);
    auto flat = [&](uint32_t w) {
        K::Vector_3 p = sm.point(Vertex_index(w)) - CGAL::ORIGIN;
        return K::Point_2(p * u, p * v);
    };
    /* rim edges, then the region's own; rim edges crossing each other: grow there;
     * own edges crossing anything: not kept */
    std::vector<std::pair<uint32_t, uint32_t>> ends(reg.rim);
    ends.insert(ends.end(), reg.edges.begin(), reg.edges.end());
    std::vector<K::Segment_2> seg;
    seg.reserve(ends.size());
    for (const auto &e : ends)
        seg.emplace_back(flat(e.first), flat(e.second));
    const size_t nrim = reg.rim.size();
    std::vector<uint8_t> keep(ends.size(), 1);
    size_t grow_before = grow_at.size();
    crossing_segments(seg, ends, [&](size_t i, size_t j) {
        if (i < nrim && j < nrim) {
            grow_at.insert(grow_at.end(),
                           {ends[i].first, ends[i].second, ends[j].first, ends[j].second});
        } else {
            if (i >= nrim)
                keep[i] = 0;
            if (j >= nrim)
                keep[j] = 0;
        }
    });
    if (grow_at.size() > grow_before)
        return fill_none;

    Cdt cdt;
    std::unordered_map<uint32_t, Cdt::Vertex_handle> handle;
    for (const auto &e : reg.rim)
        for (uint32_t w : {e.first, e.second}) {
            if (handle.count(w))
                continue;
            size_t before = cdt.number_of_vertices();
            Cdt::Vertex_handle h = cdt.insert(flat(w));
            if (cdt.number_of_vertices() == before)
                return fill_none; /* two rim vertices at one point of the plane */
            h->info() = w;
            handle[w] = h;
        }
    for (Vertex_index w : reg.inner) {
        size_t before = cdt.number_of_vertices();
        Cdt::Vertex_handle h = cdt.insert(flat(static_cast<uint32_t>(w.idx())));
        if (cdt.number_of_vertices() == before)
            continue; /* at a point already there: left out (unused) */
        h->info() = static_cast<uint32_t>(w.idx());
        handle[static_cast<uint32_t>(w.idx())] = h;
    }
    try {
        for (size_t i = 0; i < ends.size(); i++) {
            if (!keep[i])
                continue;
            auto x = handle.find(ends[i].first), y = handle.find(ends[i].second);
            if (x == handle.end() || y == handle.end())
                continue; /* an end left out */
            cdt.insert_constraint(x->second, y->second);
        }
    } catch (const Cdt::Intersection_of_constraints_exception &) {
        return fill_none; /* cannot happen: crossing edges were left out */
    }
    /* inside the rim: odd nesting, level by level across the constraints from the
     * infinite face; the region's own edges (constraints too) do not count */
    std::unordered_map<uint64_t, uint8_t> is_rim;
    for (const auto &e : reg.rim) {
        is_rim[static_cast<uint64_t>(e.first) << 32 | e.second] = 1;
        is_rim[static_cast<uint64_t>(e.second) << 32 | e.first] = 1;
    }
    auto rim_edge = [&](Cdt::Face_handle f, int i) {
        if (!f->is_constrained(i))
            return false;
        Cdt::Vertex_handle vx = f->vertex(Cdt::cw(i)), vy = f->vertex(Cdt::ccw(i));
        if (cdt.is_infinite(vx) || cdt.is_infinite(vy))
            return false;
        return is_rim.count(static_cast<uint64_t>(vx->info()) << 32 | vy->info()) != 0;
    };
    for (Cdt::Face_handle f : cdt.all_face_handles())
        f->info() = -1;
    std::vector<Cdt::Face_handle> frontier(1, cdt.infinite_face());
    for (int level = 0; !frontier.empty(); level++) {
        std::vector<Cdt::Face_handle> stack = frontier, across;
        frontier.clear();
        while (!stack.empty()) {
            Cdt::Face_handle f = stack.back();
            stack.pop_back();
            if (f->info() != -1)
                continue;
            f->info() = level;
            for (int i = 0; i < 3; i++) {
                Cdt::Face_handle g = f->neighbor(i);
                if (g->info() == -1)
                    (rim_edge(f, i) ? across : stack).push_back(g);
            }
        }
        for (Cdt::Face_handle g : across)
            if (g->info() == -1)
                frontier.push_back(g);
    }
    /* the triangles, counter-clockwise in the plane; they must run each rim edge once
     * the way the region did and every other edge once each way, on no edge the mesh
     * has outside the region */
    std::vector<uint32_t> out;
    std::vector<uint64_t> he;
    for (Cdt::Face_handle f : cdt.finite_face_handles()) {
        if (f->info() % 2 != 1)
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t x = f->vertex(k)->info(), y = f->vertex((k + 1) % 3)->info();
            out.push_back(x);
            he.push_back(static_cast<uint64_t>(x) << 32 | y);
        }
    }
    std::sort(he.begin(), he.end());
    if (he.empty() || std::adjacent_find(he.begin(), he.end()) != he.end())
        return fill_none;
    std::vector<uint64_t> rim;
    for (const auto &e : reg.rim)
        rim.push_back(static_cast<uint64_t>(e.first) << 32 | e.second);
    std::sort(rim.begin(), rim.end());
    size_t on_rim = 0;
    for (uint64_t k : he) {
        uint32_t x = static_cast<uint32_t>(k >> 32), y = static_cast<uint32_t>(k);
        uint64_t back = static_cast<uint64_t>(y) << 32 | x;
        if (std::binary_search(rim.begin(), rim.end(), k)) {
            on_rim++;
            continue;
        }
        if (!std::binary_search(he.begin(), he.end(), back))
            return fill_none;
        Halfedge_index h = sm.halfedge(Vertex_index(x), Vertex_index(y));
        if (h != Mesh::null_halfedge()) {
            Face_index f1 = sm.face(h), f2 = sm.face(sm.opposite(h));
            bool ours = (f1 != Mesh::null_face() && region_of[f1.idx()] == id) ||
                        (f2 != Mesh::null_face() && region_of[f2.idx()] == id);
            if (!ours) {
                grow_at.insert(grow_at.end(), {x, y});
                return fill_none;
            }
        }
    }
    if (on_rim != rim.size())
        return fill_none;
    /* in space: the new triangles must not cross each other or the faces around */
    if (in_space && !fits_in_space(sm, reg, id, region_of, out, grow_at))
        return fill_crossing;
    tris.insert(tris.end(), out.begin(), out.end());
    return fill_ok;
}

/* Takes the faces `cut` out of sm and fills each hole they leave from its rim (CGAL
 * triangulate_hole). False (why set) when a hole stays open. */
bool cut_and_fill_from_rims(Mesh &sm, const std::vector<Face_index> &cut,
                            const std::vector<uint8_t> &own_border, sr_mend_report *rep,
                            const char **why)
{
    for (Face_index f : cut)
        CGAL::Euler::remove_face(sm.halfedge(f), sm);
    /* the holes: border halfedges that were not the mesh's own border (the cut never
     * reaches a vertex of it) */
    auto is_new_border = [&](Halfedge_index h) {
        return sm.is_border(h) && !own_border[sm.target(h).idx()];
    };
    std::vector<Halfedge_index> starts;
    std::vector<uint8_t> seen(sm.num_halfedges(), 0);
    for (Halfedge_index h : sm.halfedges()) {
        if (!is_new_border(h) || seen[h.idx()])
            continue;
        starts.push_back(h);
        Halfedge_index g = h;
        do {
            seen[g.idx()] = 1;
            g = sm.next(g);
        } while (g != h);
    }
    for (Halfedge_index h : starts) {
        std::vector<Face_index> added;
        PMP::triangulate_hole(sm, h, std::back_inserter(added));
        rep->filled_tris += added.size();
    }
    for (Halfedge_index h : sm.halfedges())
        if (is_new_border(h)) {
            *why = "a hole left by the crossing triangles could not be filled";
            return false;
        }
    return true;
}

/* One pass on sm (built from xyz): the faces of `pairs` and `rings` rings of faces
 * around them (sharing a vertex) out, each region of them filled again from its own
 * points (fill_from_points; in_space: checked against the faces around) or, where that
 * does not fit, from its rim. False (why set) when the faces taken out reach the
 * border or a hole stays open. */
bool cut_and_fill(Mesh &sm, const double *xyz, size_t nv,
                  const std::vector<std::pair<Face_index, Face_index>> &pairs, int rings,
                  bool in_space, const std::vector<uint8_t> &own_border,
                  sr_mend_report *rep, const char **why)
{
    std::vector<uint8_t> mark(sm.num_faces(), 0); /* num_*: capacity, removed included */
    std::vector<Face_index> cut;
    auto take = [&](Face_index f) {
        if (f == Mesh::null_face() || f.idx() >= mark.size() || mark[f.idx()])
            return;
        mark[f.idx()] = 1;
        cut.push_back(f);
    };
    for (const auto &p : pairs) {
        take(p.first);
        take(p.second);
    }
    size_t begin = 0;
    for (int k = 0; k < rings; k++) {
        size_t end = cut.size();
        for (size_t i = begin; i < end; i++)
            for (Vertex_index v : sm.vertices_around_face(sm.halfedge(cut[i])))
                if (!sm.is_border(v, false))
                    for (Face_index g : sm.faces_around_target(sm.halfedge(v)))
                        take(g);
        begin = end;
    }
    for (Face_index f : cut)
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            if (sm.is_border(v, false)) {
                *why = "the crossings reach the mesh's border";
                rep->reached_border = 1;
                return false;
            }

    /* regions filled from their points (their faces replaced in the arrays below),
     * the others from their rims on the halfedge mesh. A region whose rim crosses
     * itself seen along its normal, or (in_space) whose fill crosses the faces around
     * it, takes the faces at the crossing too, up to max_grow times or until they
     * would reach the border; then a fill that crosses only the faces around is kept
     * (the next pass sees to those crossings). */
    std::vector<Region> regions;
    std::vector<uint32_t> fills;
    std::vector<Face_index> from_rims;
    std::vector<uint8_t> by_points;
    bool last = false;
    std::vector<Face_index> prev_cut;
    std::vector<uint8_t> prev_mark;
    size_t prev_hard = SIZE_MAX;
    for (int grow = 0;; grow++) {
        last = last || grow == max_grow;
        regions = regions_of(sm, cut, mark);
        fills.clear();
        from_rims.clear();
        by_points.assign(mark.size(), 0);
        std::vector<uint32_t> grow_at;
        std::vector<uint32_t> region_of(mark.size(), UINT32_MAX);
        for (size_t i = 0; i < regions.size(); i++)
            for (Face_index f : regions[i].faces)
                region_of[f.idx()] = static_cast<uint32_t>(i);
        size_t hard = 0; /* faces of regions that cannot be filled from their points */
        for (size_t i = 0; i < regions.size(); i++) {
            const Region &reg = regions[i];
            Fill got = fill_from_points(sm, reg, i, region_of, in_space && !last, fills,
                                        grow_at);
            if (got == fill_ok) {
                for (Face_index f : reg.faces)
                    by_points[f.idx()] = 1;
            } else {
                from_rims.insert(from_rims.end(), reg.faces.begin(), reg.faces.end());
                if (got == fill_none)
                    hard += reg.faces.size();
            }
        }
        if (in_space && !last && hard > prev_hard) {
            /* the faces taken for fills crossing the faces around made regions
             * unfillable: back, and keep the fills that only cross the faces around */
            cut.swap(prev_cut);
            mark.swap(prev_mark);
            last = true;
            continue;
        }
        if (grow_at.empty() || last)
            break;
        prev_cut = cut;
        prev_mark = mark;
        prev_hard = hard;
        /* the faces at the crossing rim edges' ends, unless they reach the border */
        std::vector<Face_index> more;
        bool border = false;
        for (uint32_t w : grow_at)
            for (Face_index g : sm.faces_around_target(sm.halfedge(Vertex_index(w))))
                if (g != Mesh::null_face() && !mark[g.idx()]) {
                    more.push_back(g);
                    for (Vertex_index x : sm.vertices_around_face(sm.halfedge(g)))
                        border = border || sm.is_border(x, false);
                }
        if (border) {
            last = true; /* once more, fills crossing the faces around kept */
            continue;
        }
        for (Face_index g : more)
            take(g);
    }
    rep->removed_tris += cut.size();
    mark.swap(by_points); /* now: 1 = replaced by a point fill */
    rep->rim_filled += from_rims.size();
    if (!from_rims.empty() && !cut_and_fill_from_rims(sm, from_rims, own_border, rep, why))
        return false;
    if (fills.empty())
        return true;
    /* the point fills: sm again from its faces but the replaced ones, plus the fills
     * (the rim fills added faces only, in slots of faces they took out: the replaced
     * faces keep their indices) */
    std::vector<uint32_t> tri;
    tri.reserve(3 * sm.number_of_faces() + fills.size());
    for (Face_index f : sm.faces()) {
        if (f.idx() < mark.size() && mark[f.idx()])
            continue;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            tri.push_back(static_cast<uint32_t>(v.idx()));
    }
    tri.insert(tri.end(), fills.begin(), fills.end());
    rep->filled_tris += fills.size() / 3;
    sr_mesh arrays;
    arrays.xyz = const_cast<double *>(xyz);
    arrays.vertex_count = nv;
    arrays.tri = tri.data();
    arrays.tri_count = tri.size() / 3;
    sm = Mesh();
    if (!build(&arrays, sm)) {
        *why = "the triangles filling a hole do not fit the mesh";
        return false;
    }
    return true;
}

typedef std::vector<std::pair<Face_index, Face_index>> Pairs;

Pairs crossings_near(const Mesh &sm, const double *box)
{
    std::vector<Face_index> near = near_faces(sm, box);
    Pairs pairs;
    PMP::self_intersections(near, sm, std::back_inserter(pairs));
    return pairs;
}

/* One attempt with `rings` on sm (mesh as built, its crossings `pairs`): up to
 * max_passes of cut / fill / look again (checked: the fills of the passes after the
 * first must not cross the faces around them, see cut_and_fill). True with sm mended
 * when no crossing is left; false with why set. */
bool attempt(Mesh &sm, const sr_mesh *mesh, const double *box, int rings, bool checked,
             Pairs pairs, sr_mend_report *rep, const char **why)
{
    std::vector<uint8_t> own_border(sm.num_vertices(), 0);
    for (Vertex_index v : sm.vertices())
        if (sm.is_border(v, false))
            own_border[v.idx()] = 1;
    rep->removed_tris = rep->filled_tris = rep->rim_filled = 0;
    for (int pass = 0; !pairs.empty(); pass++) {
        if (pass == max_passes) {
            *why = "crossings are left after the holes were filled";
            return false;
        }
        bool in_space = checked && pass > 0;
        if (!cut_and_fill(sm, mesh->xyz, mesh->vertex_count, pairs, rings, in_space,
                          own_border, rep, why))
            return false;
        pairs = crossings_near(sm, box);
    }
    return true;
}

sr_status mend(sr_mesh *mesh, const double *box, sr_mend_report *rep, sr_err *err)
{
    sr_mesh_report vr;
    sr_status st = sr_mesh_validate(mesh, "mesh to mend", &vr, err);
    if (st != SR_OK)
        return st;
    Mesh sm;
    if (!build(mesh, sm))
        return sr_err_set(err, SR_E_INVALID,
                          "mesh to mend is not an oriented manifold (a triangle repeats an "
                          "edge or a vertex)");
    /* the mesh is rebuilt the same way for every attempt: same face indices, same pairs */
    const Pairs first = crossings_near(sm, box);
    rep->crossing_pairs = first.size();
    if (first.empty())
        return SR_OK;
    /* the smallest holes first: attempts with 0, 1, ... rings around the crossings,
     * each with the later passes' fills checked against the faces around them
     * (crossings a fill leaves are then taken with it instead of coming back pass after
     * pass) and without; of the two, the one that fills fewer holes from their rims */
    const char *why = "";
    Mesh best;
    sr_mend_report got = *rep;
    bool done = false;
    for (int rings = 0; rings <= max_rings && !done; rings++)
        for (int checked = 1; checked >= 0; checked--) {
            if (rep->rounds > 0) {
                sm = Mesh();
                build(mesh, sm);
            }
            rep->rounds++;
            if (!attempt(sm, mesh, box, rings, checked != 0, first, &got, &why)) {
                rep->reached_border |= got.reached_border;
                continue;
            }
            if (!done || got.rim_filled < rep->rim_filled) {
                rep->removed_tris = got.removed_tris;
                rep->filled_tris = got.filled_tris;
                rep->rim_filled = got.rim_filled;
                best = std::move(sm);
                done = true;
            }
        }
    if (!done)
        return sr_err_set(err, SR_E_INVALID, "cannot mend the crossings (%zu pairs): %s",
                          rep->crossing_pairs, why);
    sm = std::move(best);
    size_t nt = sm.number_of_faces();
    uint32_t *tri = static_cast<uint32_t *>(malloc((nt ? nt : 1) * 3 * sizeof(uint32_t)));
    if (!tri)
        return sr_err_set(err, SR_E_NOMEM, "out of memory mending a mesh");
    size_t w = 0;
    for (Face_index f : sm.faces())
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            tri[w++] = static_cast<uint32_t>(v.idx());
    free(mesh->tri);
    mesh->tri = tri;
    mesh->tri_count = nt;
    return SR_OK;
}

/* sr_mesh_unfold proper: see mend.h. */
sr_status unfold(sr_mesh *m, double max_move, sr_unfold_report *rep, sr_err *err)
{
    Mesh sm;
    if (!build(m, sm))
        return sr_err_set(err, SR_E_INVALID, "cannot unfold: not an oriented manifold");
    std::vector<Point> start(m->vertex_count);
    for (Vertex_index v : sm.vertices())
        start[v.idx()] = sm.point(v);
    std::vector<Face_index> range(sm.faces().begin(), sm.faces().end());
    std::vector<uint8_t> moved(m->vertex_count, 0);
    for (int round = 0; round < unfold_rounds; round++) {
        std::vector<std::pair<Face_index, Face_index>> pairs;
        PMP::self_intersections(range, sm, std::back_inserter(pairs));
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
            const Point &o = start[v.idx()];
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
            sm.point(verts[i]) = next[i];
            moved[verts[i].idx()] = 1;
        }
        /* the next round looks where this one moved: the triangles around the moved
         * vertices and two rings more */
        std::vector<uint8_t> take(sm.number_of_faces(), 0);
        std::vector<Vertex_index> ring(verts), more;
        for (int r = 0; r < 3; r++) {
            more.clear();
            for (Vertex_index v : ring)
                for (Face_index f : sm.faces_around_target(sm.halfedge(v))) {
                    if (f == Mesh::null_face() || take[f.idx()])
                        continue;
                    take[f.idx()] = 1;
                    for (Vertex_index w : sm.vertices_around_face(sm.halfedge(f)))
                        more.push_back(w);
                }
            ring.swap(more);
        }
        range.clear();
        for (Face_index f : sm.faces())
            if (take[f.idx()])
                range.push_back(f);
    }
    double worst = 0;
    for (Vertex_index v : sm.vertices()) {
        if (!moved[v.idx()])
            continue;
        rep->moved_vertices++;
        const Point &p = sm.point(v), &o = start[v.idx()];
        worst = std::max(worst, std::sqrt(CGAL::squared_distance(p, o)));
        double *x = m->xyz + 3 * v.idx();
        x[0] = p.x();
        x[1] = p.y();
        x[2] = p.z();
    }
    rep->max_move_mm = worst;
    return SR_OK;
}

/* sr_mesh_collapse_short_edges proper: see mend.h. */
sr_status collapse_short(sr_mesh *m, double min_edge, size_t *collapsed, sr_err *err)
{
    Mesh sm;
    if (!build(m, sm))
        return sr_err_set(err, SR_E_INVALID, "cannot collapse edges: not an oriented manifold");
    size_t n = 0;
    double min2 = min_edge * min_edge;
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
            n++;
        }
        if (n == before)
            break;
    }
    *collapsed = n;
    if (n == 0)
        return SR_OK;
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

extern "C" {

sr_status sr_mesh_mend_crossings(sr_mesh *mesh, const double *box, sr_mend_report *report,
                                 sr_err *err)
{
    sr_mend_report local;
    if (!report)
        report = &local;
    memset(report, 0, sizeof *report);
    try {
        return mend(mesh, box, report, err);
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory mending a mesh");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "mending a mesh: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "mending a mesh: unknown exception");
    }
}

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
                                       sr_err *err)
{
    size_t local = 0;
    if (!collapsed)
        collapsed = &local;
    *collapsed = 0;
    if (!(min_edge_mm > 0))
        return SR_OK;
    try {
        return collapse_short(mesh, min_edge_mm, collapsed, err);
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory collapsing edges");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "collapsing edges: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "collapsing edges: unknown exception");
    }
}

} // extern "C"
