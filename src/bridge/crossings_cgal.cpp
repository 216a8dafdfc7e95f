/*
 * crossings_cgal.cpp: where a mesh crosses itself, found on every core
 * (sr_mend::crossing_pairs, and sr_mesh_crossing_pairs of mend.h for C). CGAL's
 * self_intersections runs on one thread; on a scan of two million triangles it was
 * the largest part of the unfolding (4.4 of 8.4 s). The faces are split into slabs
 * along x, at quantiles of their centres, at least as many as threads and none much
 * over slab_faces (CGAL holds a call's candidate pairs all at once); a face goes to
 * every slab its box overlaps, and the threads take the slabs in turn. Two faces that cross share a point, which lies in some slab,
 * and both overlap it: every pair is found, those across a cut twice. The pairs come
 * back each once, the lower face first, sorted: the same for any number of threads.
 */
#include "bridge/mend_cgal.hpp"

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iterator>
#include <limits>
#include <new>
#include <thread>

namespace sr_mend
{

namespace
{

/* Below this many faces one thread does it: the split costs more than it saves. */
const size_t parallel_min_faces = 20000;
const unsigned threads_max = 8;
/* At most about this many faces a slab: CGAL keeps every pair of overlapping boxes of a
 * call before it tests them (8 pairs a face on a scan: 70 MB for a million faces in
 * two calls, 8 MB in slabs of this size). */
const size_t slab_faces = 65536;

unsigned threads_for(int threads)
{
    unsigned n = threads > 0 ? (unsigned)threads : std::thread::hardware_concurrency();
    return std::max(1u, std::min(n, threads_max));
}

} // namespace

std::vector<std::pair<Face_index, Face_index>>
crossing_pairs(const Mesh &sm, const std::vector<Face_index> &range, int threads)
{
    std::vector<std::pair<Face_index, Face_index>> out;
    size_t n = range.size();
    unsigned nt = n < parallel_min_faces ? 1u : threads_for(threads);
    size_t slabs = std::max<size_t>(nt, (n + slab_faces - 1) / slab_faces);
    if (slabs <= 1) {
        PMP::self_intersections(range, sm, std::back_inserter(out));
    } else {
        auto extent = [&](Face_index f, double &a, double &b) {
            a = std::numeric_limits<double>::infinity();
            b = -a;
            for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f))) {
                double x = sm.point(v).x();
                a = std::min(a, x);
                b = std::max(b, x);
            }
        };
        std::vector<double> mid(n);
        for (size_t i = 0; i < n; i++) {
            double a, b;
            extent(range[i], a, b);
            mid[i] = 0.5 * (a + b);
        }
        std::vector<double> cut(slabs + 1);
        cut[0] = -std::numeric_limits<double>::infinity();
        cut[slabs] = std::numeric_limits<double>::infinity();
        for (size_t s = 1; s < slabs; s++) {
            std::vector<double>::iterator q = mid.begin() + (std::ptrdiff_t)(n * s / slabs);
            std::nth_element(mid.begin(), q, mid.end());
            cut[s] = *q;
        }
        std::vector<double>().swap(mid);
        /* each face in the slabs its box overlaps, from the first (a binary search) */
        std::vector<std::vector<Face_index>> part(slabs);
        for (size_t i = 0; i < n; i++) {
            double a, b;
            extent(range[i], a, b);
            size_t s = (size_t)(std::lower_bound(cut.begin(), cut.end(), a) - cut.begin()) - 1;
            for (; s < slabs && b >= cut[s]; s++) /* cut[s] < a <= cut[s + 1] first */
                part[s].push_back(range[i]);
        }
        /* thread k takes slabs k, k + nt, ...: each slab's pairs apart, merged below */
        std::vector<std::vector<std::pair<Face_index, Face_index>>> found(slabs);
        std::vector<std::exception_ptr> failed(nt);
        auto work = [&](unsigned k) {
            try {
                for (size_t s = k; s < slabs; s += nt) {
                    PMP::self_intersections(part[s], sm, std::back_inserter(found[s]));
                    std::vector<Face_index>().swap(part[s]);
                }
            } catch (...) {
                failed[k] = std::current_exception();
            }
        };
        if (nt == 1) {
            work(0);
        } else {
            std::vector<std::thread> pool;
            for (unsigned k = 0; k < nt; k++)
                pool.emplace_back(work, k);
            for (std::thread &t : pool)
                t.join();
        }
        for (unsigned k = 0; k < nt; k++)
            if (failed[k])
                std::rethrow_exception(failed[k]);
        size_t total = 0;
        for (const auto &f : found)
            total += f.size();
        out.reserve(total);
        for (const auto &f : found)
            out.insert(out.end(), f.begin(), f.end());
    }
    for (auto &p : out)
        if (p.second < p.first)
            std::swap(p.first, p.second);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

} // namespace sr_mend

extern "C" sr_status sr_mesh_crossing_pairs(const sr_mesh *mesh, int threads, uint32_t **pairs,
                                            size_t *count, sr_err *err)
{
    *pairs = NULL;
    *count = 0;
    try {
        sr_mend::Mesh sm;
        if (!sr_mend::build(mesh, sm))
            return sr_err_set(err, SR_E_INVALID, "mesh is not an oriented manifold");
        std::vector<sr_mend::Face_index> all(sm.faces().begin(), sm.faces().end());
        auto found = sr_mend::crossing_pairs(sm, all, threads);
        uint32_t *p = (uint32_t *)malloc((2 * found.size() + 1) * sizeof *p);
        if (!p)
            return sr_err_set(err, SR_E_NOMEM, "out of memory finding crossings");
        for (size_t i = 0; i < found.size(); i++) {
            p[2 * i] = (uint32_t)found[i].first.idx();
            p[2 * i + 1] = (uint32_t)found[i].second.idx();
        }
        *pairs = p;
        *count = found.size();
        return SR_OK;
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory finding crossings");
    } catch (...) {
        return sr_err_set(err, SR_E_INVALID, "finding crossings failed");
    }
}
