/*
 * stack_cgal.cpp: sr_stack_soup (stack_cgal.h) on CGAL 5.5: Arrangement_2 of segments
 * with consolidated curve data over Epeck per interface, face classification by a walk
 * from the unbounded face, caps by Constrained_Delaunay_triangulation_2 of each cap
 * face's boundary with the nesting-depth marking of CGAL's polygon example, walls cut at
 * the arrangement vertices. GPL-3.0-or-later like the rest of CGAL's packages used here.
 * Every extern "C" entry catches all exceptions.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* Valgrind-safe interval filters, see boolean_cgal.hpp */

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <exception>
#include <map>
#include <new>
#include <unordered_map>
#include <vector>

extern "C" {
#include "bridge/stack_cgal.h"
#include "base/status.h"
}

namespace {

typedef CGAL::Exact_predicates_exact_constructions_kernel K;
typedef K::Point_2 Point;
typedef CGAL::Arr_segment_traits_2<K> Seg_traits;
typedef CGAL::Arr_consolidated_curve_data_traits_2<Seg_traits, long> Traits;
typedef Traits::Curve_2 Curve;
typedef CGAL::Arrangement_2<Traits> Arr;

struct FaceInfo {
    int depth = -1;
};
typedef CGAL::Triangulation_vertex_base_2<K> Vb;
typedef CGAL::Triangulation_face_base_with_info_2<FaceInfo, K> Fbb;
typedef CGAL::Constrained_triangulation_face_base_2<K, Fbb> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_tag>
    CDT;

struct Soup {
    std::vector<double> xyz;
    std::vector<uint32_t> tri;
    uint32_t vertex(const Point &p, double z)
    {
        xyz.push_back(nearest(p.x()));
        xyz.push_back(nearest(p.y()));
        xyz.push_back(z);
        return (uint32_t)(xyz.size() / 3 - 1);
    }
    /* A coordinate as a double: its interval's when that is a single double (an input
     * point's: exactly its value), else converted from the exact value as before. The
     * same for the same exact point either way (identical points weld); converting
     * every corner's exact value took a third of a mirror's plane continuation. */
    static double nearest(const K::FT &c)
    {
        const auto &iv = c.approx();
        if (iv.inf() == iv.sup())
            return iv.inf();
        return CGAL::to_double(c.exact());
    }
    void triangle(uint32_t a, uint32_t b, uint32_t c)
    {
        tri.push_back(a);
        tri.push_back(b);
        tri.push_back(c);
    }
};

/* Point index i of region r as an exact point. */
Point point_of(const sr_poly2 &r, size_t i)
{
    return Point(r.xy[2 * i], r.xy[2 * i + 1]);
}

size_t next_of(const sr_poly2 &r, size_t i)
{
    /* the contour holding point i */
    size_t c = std::upper_bound(r.start, r.start + r.contour_count + 1, i) - r.start - 1;
    return i + 1 < r.start[c + 1] ? i + 1 : r.start[c];
}

/* Curve data: 2 * edge for an edge of the layer below, 2 * edge + 1 for the layer above
 * (edge = the index of its first point in the region). */
void add_edges(const sr_poly2 *r, int side, std::vector<Curve> &curves)
{
    if (!r)
        return;
    size_t n = r->contour_count ? r->start[r->contour_count] : 0;
    for (size_t i = 0; i < n; i++) {
        Point p = point_of(*r, i), q = point_of(*r, next_of(*r, i));
        if (p == q)
            continue;
        curves.push_back(Curve(Seg_traits::Curve_2(p, q), (long)(2 * i + side)));
    }
}

void mark(CDT &cdt, CDT::Face_handle start, int depth, std::deque<CDT::Edge> &border)
{
    if (start->info().depth != -1)
        return;
    std::deque<CDT::Face_handle> queue;
    queue.push_back(start);
    start->info().depth = depth;
    while (!queue.empty()) {
        CDT::Face_handle f = queue.front();
        queue.pop_front();
        for (int i = 0; i < 3; i++) {
            CDT::Edge e(f, i);
            CDT::Face_handle n = f->neighbor(i);
            if (n->info().depth == -1) {
                if (cdt.is_constrained(e)) {
                    border.push_back(e);
                } else {
                    n->info().depth = depth;
                    queue.push_back(n);
                }
            }
        }
    }
}

/* Triangulates one arrangement face (outer boundary and holes) at height z. */
void cap_face(Arr::Face_const_handle f, double z, bool up, Soup &soup)
{
    CDT cdt;
    auto add_ccb = [&](Arr::Ccb_halfedge_const_circulator c) {
        Arr::Ccb_halfedge_const_circulator e = c;
        do {
            const Point &a = e->source()->point(), &b = e->target()->point();
            if (a != b)
                cdt.insert_constraint(a, b);
        } while (++e != c);
    };
    for (auto c = f->outer_ccbs_begin(); c != f->outer_ccbs_end(); ++c)
        add_ccb(*c);
    for (auto c = f->inner_ccbs_begin(); c != f->inner_ccbs_end(); ++c)
        add_ccb(*c);
    for (CDT::Face_handle h : cdt.all_face_handles())
        h->info().depth = -1;
    std::deque<CDT::Edge> border;
    mark(cdt, cdt.infinite_face(), 0, border);
    while (!border.empty()) {
        CDT::Edge e = border.front();
        border.pop_front();
        CDT::Face_handle n = e.first->neighbor(e.second);
        if (n->info().depth == -1)
            mark(cdt, n, e.first->info().depth + 1, border);
    }
    for (CDT::Face_handle h : cdt.finite_face_handles()) {
        if (h->info().depth % 2 != 1)
            continue;
        uint32_t a = soup.vertex(h->vertex(0)->point(), z),
                 b = soup.vertex(h->vertex(1)->point(), z),
                 c = soup.vertex(h->vertex(2)->point(), z);
        if (up)
            soup.triangle(a, b, c);
        else
            soup.triangle(a, c, b);
    }
}

typedef std::unordered_map<long, std::vector<Point>> OnEdge;

/* One interface: caps into soup; for every input edge id, the arrangement vertices on it. */
void interface(const sr_poly2 *below, const sr_poly2 *above, double z, Soup &soup, OnEdge &on)
{
    std::vector<Curve> curves;
    add_edges(below, 0, curves);
    add_edges(above, 1, curves);
    if (curves.empty())
        return;
    Arr arr;
    CGAL::insert(arr, curves.begin(), curves.end());
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e)
        for (auto d = e->curve().data().begin(); d != e->curve().data().end(); ++d) {
            std::vector<Point> &v = on[*d];
            v.push_back(e->source()->point());
            v.push_back(e->target()->point());
        }
    /* walk the faces: crossing an edge toggles membership of each side it came from */
    std::map<Arr::Face_const_handle, int> state;   /* bit 0: in below, bit 1: in above */
    std::deque<Arr::Face_const_handle> queue;
    Arr::Face_const_handle unb = arr.unbounded_face();
    state[unb] = 0;
    queue.push_back(unb);
    while (!queue.empty()) {
        Arr::Face_const_handle f = queue.front();
        queue.pop_front();
        int s = state[f];
        auto visit = [&](Arr::Ccb_halfedge_const_circulator c) {
            Arr::Ccb_halfedge_const_circulator e = c;
            do {
                Arr::Face_const_handle g = e->twin()->face();
                if (state.find(g) == state.end()) {
                    int t = s;
                    for (auto d = e->curve().data().begin(); d != e->curve().data().end(); ++d)
                        t ^= (*d & 1) ? 2 : 1;
                    state[g] = t;
                    queue.push_back(g);
                }
            } while (++e != c);
        };
        for (auto c = f->outer_ccbs_begin(); c != f->outer_ccbs_end(); ++c)
            visit(*c);
        for (auto c = f->inner_ccbs_begin(); c != f->inner_ccbs_end(); ++c)
            visit(*c);
    }
    /* capped in the arrangement's order of faces: the map's order is the faces'
     * addresses, which follow the heap's history (the soup's numbering, then the
     * patch, changed with the thread count of an earlier step) */
    const Arr &faces = arr;
    for (Arr::Face_const_iterator f = faces.faces_begin(); f != faces.faces_end(); ++f) {
        auto fs = state.find(Arr::Face_const_handle(f));
        if (fs != state.end() && fs->second == 1)
            cap_face(fs->first, z, true, soup);
        else if (fs != state.end() && fs->second == 2)
            cap_face(fs->first, z, false, soup);
    }
}

/* The points on edge p->q (from the interface), sorted from p to q, unique, ends excluded. */
std::vector<Point> chain(const Point &p, const Point &q, std::vector<Point> *pts)
{
    std::vector<Point> out;
    if (!pts)
        return out;
    for (const Point &x : *pts)
        if (x != p && x != q)
            out.push_back(x);
    std::sort(out.begin(), out.end(), [&](const Point &a, const Point &b) {
        return CGAL::compare_distance_to_point(p, a, b) == CGAL::SMALLER;
    });
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

/* The wall under edge p->q between z0 and z1, zipped by distance from p. */
void wall(const Point &p, const Point &q, const std::vector<Point> &bot,
          const std::vector<Point> &top, double z0, double z1, Soup &soup)
{
    std::vector<Point> B, T;
    B.push_back(p);
    B.insert(B.end(), bot.begin(), bot.end());
    B.push_back(q);
    T.push_back(p);
    T.insert(T.end(), top.begin(), top.end());
    T.push_back(q);
    std::vector<uint32_t> bi, ti;
    for (const Point &x : B)
        bi.push_back(soup.vertex(x, z0));
    for (const Point &x : T)
        ti.push_back(soup.vertex(x, z1));
    size_t i = 0, j = 0;
    while (i + 1 < B.size() || j + 1 < T.size()) {
        bool bottom;
        if (i + 1 >= B.size())
            bottom = false;
        else if (j + 1 >= T.size())
            bottom = true;
        else
            bottom = CGAL::compare_distance_to_point(p, B[i + 1], T[j + 1]) != CGAL::LARGER;
        if (bottom) {
            soup.triangle(bi[i], bi[i + 1], ti[j]);
            i++;
        } else {
            soup.triangle(bi[i], ti[j + 1], ti[j]);
            j++;
        }
    }
}

sr_status run(const sr_poly2 *regions, const double *z, size_t layers, Soup &soup)
{
    std::vector<OnEdge> on(layers + 1);
    for (size_t k = 0; k <= layers; k++) {
        const sr_poly2 *below = k > 0 ? &regions[k - 1] : nullptr;
        const sr_poly2 *above = k < layers ? &regions[k] : nullptr;
        interface(below, above, z[k], soup, on[k]);
    }
    for (size_t l = 0; l < layers; l++) {
        const sr_poly2 &r = regions[l];
        size_t n = r.contour_count ? r.start[r.contour_count] : 0;
        for (size_t i = 0; i < n; i++) {
            Point p = point_of(r, i), q = point_of(r, next_of(r, i));
            if (p == q)
                continue;
            auto b = on[l].find((long)(2 * i + 1)), t = on[l + 1].find((long)(2 * i));
            std::vector<Point> bot = chain(p, q, b == on[l].end() ? nullptr : &b->second);
            std::vector<Point> top = chain(p, q, t == on[l + 1].end() ? nullptr : &t->second);
            wall(p, q, bot, top, z[l], z[l + 1], soup);
        }
    }
    return SR_OK;
}

} // namespace

extern "C" sr_status sr_stack_soup(const sr_poly2 *regions, const double *z, size_t layers,
                                   double **xyz, size_t *vertex_count, uint32_t **tri,
                                   size_t *tri_count, sr_err *err)
{
    try {
        Soup soup;
        sr_status st = run(regions, z, layers, soup);
        if (st != SR_OK)
            return st;
        if (soup.xyz.size() / 3 > UINT32_MAX)
            return sr_err_set(err, SR_E_RANGE, "patch too large: %zu vertices",
                              soup.xyz.size() / 3);
        double *v = (double *)malloc((soup.xyz.size() + 1) * sizeof *v);
        uint32_t *t = (uint32_t *)malloc((soup.tri.size() + 1) * sizeof *t);
        if (!v || !t) {
            free(v);
            free(t);
            return sr_err_set(err, SR_E_NOMEM, "out of memory for a patch");
        }
        std::copy(soup.xyz.begin(), soup.xyz.end(), v);
        std::copy(soup.tri.begin(), soup.tri.end(), t);
        *xyz = v;
        *vertex_count = soup.xyz.size() / 3;
        *tri = t;
        *tri_count = soup.tri.size() / 3;
        return SR_OK;
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory building a patch");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "cannot build a patch: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "cannot build a patch: unknown exception");
    }
}
