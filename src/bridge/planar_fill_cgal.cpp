/*
 * planar_fill_cgal.cpp: sr_planar_fill (planar_fill.h) on CGAL 5.5: every loop edge a
 * constraint of one Constrained_triangulation_plus_2 over a constrained Delaunay
 * triangulation on Epick with exact predicates (crossing constraints are cut at a
 * constructed point; the constraint hierarchy says which points each input edge runs
 * through). The faces are grouped into regions joined across unconstrained edges; each
 * region takes the winding number of the input loops around one of its faces, and the
 * faces of a non-zero one are kept, turned against the loops. GPL-3.0-or-later like the
 * rest of CGAL's packages used here. Every extern "C" entry catches all exceptions.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* Valgrind-safe interval filters, see boolean_cgal.hpp */

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <exception>
#include <new>
#include <vector>

extern "C" {
#include "bridge/planar_fill.h"
#include "base/status.h"
}

namespace
{

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_2 Point;

struct FaceInfo {
    long region = -1;
};
const uint32_t NO_INDEX = UINT32_MAX; /* a point CGAL made where two loops cross */
typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> Vb;
typedef CGAL::Triangulation_face_base_with_info_2<FaceInfo, K> Fbb;
typedef CGAL::Constrained_triangulation_face_base_2<K, Fbb> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag> CDT;
typedef CGAL::Constrained_triangulation_plus_2<CDT> CDTP;

/* Gives region id to every face reachable from start without crossing a constraint. */
void mark(CDTP &cdt, CDTP::Face_handle start, long id)
{
    std::deque<CDTP::Face_handle> queue;
    queue.push_back(start);
    start->info().region = id;
    while (!queue.empty()) {
        CDTP::Face_handle f = queue.front();
        queue.pop_front();
        for (int i = 0; i < 3; i++) {
            CDTP::Face_handle n = f->neighbor(i);
            if (n->info().region == -1 && !cdt.is_constrained(CDTP::Edge(f, i))) {
                n->info().region = id;
                queue.push_back(n);
            }
        }
    }
}

/* The winding number of the loops around (x, y) (Sunday's crossing rule). */
long winding(const double *uv, const size_t *start, size_t loop_count, double x, double y)
{
    long w = 0;
    for (size_t c = 0; c < loop_count; c++)
        for (size_t i = start[c]; i < start[c + 1]; i++) {
            size_t j = i + 1 < start[c + 1] ? i + 1 : start[c];
            double ax = uv[2 * i], ay = uv[2 * i + 1], bx = uv[2 * j], by = uv[2 * j + 1];
            double left = (bx - ax) * (y - ay) - (x - ax) * (by - ay);
            if (ay <= y) {
                if (by > y && left > 0)
                    w++;
            } else if (by <= y && left < 0) {
                w--;
            }
        }
    return w;
}

struct Result {
    std::vector<uint32_t> tri, split;
    std::vector<double> extra;
    std::vector<size_t> split_first;
};

sr_status run(const double *uv, const size_t *start, size_t loop_count, Result &r, sr_err *err)
{
    size_t n = start[loop_count];
    for (size_t i = 0; i < 2 * n; i++)
        if (!std::isfinite(uv[i]))
            return sr_err_set(err, SR_E_INVALID, "a loop point is not finite");
    if (n >= NO_INDEX / 2)
        return sr_err_set(err, SR_E_RANGE, "too many points to fill a planar opening");
    CDTP cdt;
    std::vector<CDTP::Vertex_handle> vh(n);
    for (size_t i = 0; i < n; i++)
        vh[i] = cdt.insert(Point(uv[2 * i], uv[2 * i + 1]));
    std::vector<CDTP::Constraint_id> cid(n);
    std::vector<bool> has(n, false);
    for (size_t c = 0; c < loop_count; c++)
        for (size_t i = start[c]; i < start[c + 1]; i++) {
            size_t j = i + 1 < start[c + 1] ? i + 1 : start[c];
            if (vh[i] != vh[j]) {
                cid[i] = cdt.insert_constraint(vh[i], vh[j]);
                has[i] = true;
            }
        }
    /* info (vertex handles outlive the insertions): the first input index of each point
     * (a repeated point keeps the first), then the constructed ones */
    for (CDTP::Vertex_handle v : cdt.finite_vertex_handles())
        v->info() = NO_INDEX;
    for (size_t i = 0; i < n; i++)
        if (vh[i]->info() == NO_INDEX)
            vh[i]->info() = (uint32_t)i;
    for (CDTP::Vertex_handle v : cdt.finite_vertex_handles())
        if (v->info() == NO_INDEX) {
            if (n + r.extra.size() / 2 >= NO_INDEX)
                return sr_err_set(err, SR_E_RANGE, "too many points to fill a planar opening");
            v->info() = (uint32_t)(n + r.extra.size() / 2);
            r.extra.push_back(v->point().x());
            r.extra.push_back(v->point().y());
        }
    /* the points each input edge runs through, from its first point to its second */
    r.split_first.assign(n + 1, 0);
    for (size_t i = 0; i < n; i++) {
        r.split_first[i] = r.split.size();
        if (!has[i])
            continue;
        std::vector<uint32_t> chain;
        for (auto it = cdt.vertices_in_constraint_begin(cid[i]);
             it != cdt.vertices_in_constraint_end(cid[i]); ++it)
            chain.push_back((*it)->info());
        if (chain.size() < 2)
            continue;
        if (chain.front() != vh[i]->info())
            std::reverse(chain.begin(), chain.end());
        r.split.insert(r.split.end(), chain.begin() + 1, chain.end() - 1);
    }
    r.split_first[n] = r.split.size();
    /* regions, and their winding numbers from their largest face */
    for (CDTP::Face_handle h : cdt.all_face_handles())
        h->info().region = -1;
    long regions = 0;
    for (CDTP::Face_handle h : cdt.all_face_handles())
        if (h->info().region == -1)
            mark(cdt, h, regions++);
    std::vector<double> best((size_t)regions, -1.0);
    std::vector<long> wind((size_t)regions, 0);
    for (CDTP::Face_handle h : cdt.finite_face_handles()) {
        const Point &a = h->vertex(0)->point(), &b = h->vertex(1)->point(),
                    &c = h->vertex(2)->point();
        double area =
            std::fabs((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
        size_t g = (size_t)h->info().region;
        if (area > best[g]) {
            best[g] = area;
            wind[g] = winding(uv, start, loop_count, (a.x() + b.x() + c.x()) / 3,
                              (a.y() + b.y() + c.y()) / 3);
        }
    }
    for (CDTP::Face_handle h : cdt.finite_face_handles()) {
        long w = wind[(size_t)h->info().region];
        if (w == 0)
            continue;
        uint32_t t[3] = {h->vertex(0)->info(), h->vertex(1)->info(), h->vertex(2)->info()};
        if (w > 0) /* CGAL's faces are counter-clockwise: against a counter-clockwise loop */
            std::swap(t[1], t[2]);
        r.tri.insert(r.tri.end(), t, t + 3);
    }
    return SR_OK;
}

template <typename T> T *copy_out(const std::vector<T> &v)
{
    T *p = (T *)malloc((v.size() + 1) * sizeof(T));
    if (p)
        std::copy(v.begin(), v.end(), p);
    return p;
}

} // namespace

extern "C" void sr_planar_fill_free(sr_planar_fill_out *out)
{
    if (!out)
        return;
    free(out->tri);
    free(out->extra_uv);
    free(out->split_first);
    free(out->split);
    *out = sr_planar_fill_out();
}

extern "C" sr_status sr_planar_fill(const double *uv, const size_t *start, size_t loop_count,
                                    sr_planar_fill_out *out, sr_err *err)
{
    try {
        Result r;
        sr_status st = run(uv, start, loop_count, r, err);
        if (st != SR_OK)
            return st;
        sr_planar_fill_out o = sr_planar_fill_out();
        o.tri = copy_out(r.tri);
        o.extra_uv = copy_out(r.extra);
        o.split_first = copy_out(r.split_first);
        o.split = copy_out(r.split);
        o.tri_count = r.tri.size() / 3;
        o.extra_count = r.extra.size() / 2;
        if (!o.tri || !o.extra_uv || !o.split_first || !o.split) {
            sr_planar_fill_free(&o);
            return sr_err_set(err, SR_E_NOMEM, "out of memory filling a planar opening");
        }
        *out = o;
        return SR_OK;
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory filling a planar opening");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "cannot fill a planar opening: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "cannot fill a planar opening: unknown exception");
    }
}
