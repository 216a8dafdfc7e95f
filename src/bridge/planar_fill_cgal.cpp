/*
 * planar_fill_cgal.cpp: sr_planar_fill (planar_fill.h) on CGAL 5.5: every loop edge a
 * constraint of one Constrained_Delaunay_triangulation_2 over Epick with exact
 * predicates (crossing constraints are cut at a constructed point), the faces marked by
 * their nesting depth from the infinite face (CGAL's polygon example), the odd ones kept.
 * GPL-3.0-or-later like the rest of CGAL's packages used here. Every extern "C" entry
 * catches all exceptions.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* Valgrind-safe interval filters, see boolean_cgal.hpp */

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
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
    int depth = -1;
};
const uint32_t NO_INDEX = UINT32_MAX; /* a point CGAL made where two loops cross */
typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> Vb;
typedef CGAL::Triangulation_face_base_with_info_2<FaceInfo, K> Fbb;
typedef CGAL::Constrained_triangulation_face_base_2<K, Fbb> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag> CDT;

/* Gives depth to every face reachable from start without crossing a constraint; the
 * constrained edges met go to border. */
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

sr_status run(const double *uv, const size_t *start, size_t loop_count, std::vector<uint32_t> &tri,
              std::vector<double> &extra, sr_err *err)
{
    size_t n = start[loop_count];
    for (size_t i = 0; i < 2 * n; i++)
        if (!std::isfinite(uv[i]))
            return sr_err_set(err, SR_E_INVALID, "a loop point is not finite");
    CDT cdt;
    std::vector<CDT::Vertex_handle> vh(n);
    for (size_t i = 0; i < n; i++)
        vh[i] = cdt.insert(Point(uv[2 * i], uv[2 * i + 1]));
    for (size_t c = 0; c < loop_count; c++)
        for (size_t i = start[c]; i < start[c + 1]; i++) {
            size_t j = i + 1 < start[c + 1] ? i + 1 : start[c];
            if (vh[i] != vh[j])
                cdt.insert_constraint(vh[i], vh[j]);
        }
    /* info (vertex handles outlive the insertions): the first input index of each point (a repeated point keeps the first) */
    for (CDT::Vertex_handle v : cdt.finite_vertex_handles())
        v->info() = NO_INDEX;
    for (size_t i = 0; i < n; i++)
        if (vh[i]->info() == NO_INDEX)
            vh[i]->info() = (uint32_t)i;
    for (CDT::Face_handle h : cdt.all_face_handles())
        h->info().depth = -1;
    std::deque<CDT::Edge> border;
    mark(cdt, cdt.infinite_face(), 0, border);
    while (!border.empty()) {
        CDT::Edge e = border.front();
        border.pop_front();
        CDT::Face_handle nb = e.first->neighbor(e.second);
        if (nb->info().depth == -1)
            mark(cdt, nb, e.first->info().depth + 1, border);
    }
    for (CDT::Vertex_handle v : cdt.finite_vertex_handles())
        if (v->info() == NO_INDEX) {
            if (n + extra.size() / 2 >= NO_INDEX)
                return sr_err_set(err, SR_E_RANGE, "too many points to fill a planar opening");
            v->info() = (uint32_t)(n + extra.size() / 2);
            extra.push_back(v->point().x());
            extra.push_back(v->point().y());
        }
    for (CDT::Face_handle h : cdt.finite_face_handles()) {
        if (h->info().depth % 2 != 1)
            continue;
        for (int k = 0; k < 3; k++)
            tri.push_back(h->vertex(k)->info());
    }
    return SR_OK;
}

} // namespace

extern "C" sr_status sr_planar_fill(const double *uv, const size_t *start, size_t loop_count,
                                    uint32_t **tri, size_t *tri_count, double **extra_uv,
                                    size_t *extra_count, sr_err *err)
{
    try {
        std::vector<uint32_t> t;
        std::vector<double> x;
        sr_status st = run(uv, start, loop_count, t, x, err);
        if (st != SR_OK)
            return st;
        uint32_t *tp = (uint32_t *)malloc((t.size() + 1) * sizeof *tp);
        double *xp = (double *)malloc((x.size() + 1) * sizeof *xp);
        if (!tp || !xp) {
            free(tp);
            free(xp);
            return sr_err_set(err, SR_E_NOMEM, "out of memory filling a planar opening");
        }
        std::copy(t.begin(), t.end(), tp);
        std::copy(x.begin(), x.end(), xp);
        *tri = tp;
        *tri_count = t.size() / 3;
        *extra_uv = xp;
        *extra_count = x.size() / 2;
        return SR_OK;
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory filling a planar opening");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "cannot fill a planar opening: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "cannot fill a planar opening: unknown exception");
    }
}
