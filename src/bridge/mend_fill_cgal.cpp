/*
 * mend_fill_cgal.cpp: the part of the mending (mend_cgal.cpp, where the method is
 * described) that fills a hole again from its own points. The faces cut out split into
 * regions (regions_of: each with its rim, its own inner edges and vertices, and its
 * mean normal); a region is filled by a constrained Delaunay triangulation (CGAL CDT_2)
 * of its rim and inner vertices seen along its mean normal, its rim and every edge of it
 * that crosses no other one there as constraints (fill_from_points), so the scan's
 * points stay where the scanner put them and a fold along a sharp edge keeps the edge.
 * Where a region's rim crosses itself seen that way, or (checked) its fill crosses the
 * faces around it, the vertices there are handed back for the region to grow.
 */
#include "bridge/mend_cgal.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <unordered_map>
#include <utility>
#include <vector>

namespace sr_mend {

/* the re-triangulation of a hole in the plane across its mean normal */
typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> Cdt_vb;
typedef CGAL::Constrained_triangulation_face_base_2<K> Cdt_fb0;
typedef CGAL::Triangulation_face_base_with_info_2<int, K, Cdt_fb0> Cdt_fb;
typedef CGAL::Triangulation_data_structure_2<Cdt_vb, Cdt_fb> Cdt_tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Cdt_tds, CGAL::No_constraint_intersection_tag>
    Cdt;

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

namespace {

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

} // namespace

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

} // namespace sr_mend
