/*
 * crossings_cgal.cpp: where a mesh crosses itself, found on every core
 * (sr_mend::crossing_pairs, and sr_mesh_crossing_pairs of mend.h for C). CGAL's
 * self_intersections runs on one thread; on a scan of two million triangles it was
 * the largest part of the unfolding (4.4 of 8.4 s). The faces are split into slabs
 * along x, at quantiles of their centres, at least as many as threads and none much
 * over slab_faces (CGAL holds a call's candidate pairs all at once); a face goes to
 * every slab its box overlaps, and the threads take the slabs in turn. Two faces that cross share a point, which lies in some slab,
 * and both overlap it: every pair is found, those across a cut more than once, and kept
 * only by the first slab both faces overlap, as it is found (no slab's finds are held
 * for a merge: a noisy spline crossed itself 10.6 million times). The pairs come back
 * each once, the lower face first, sorted: the same for any number of threads; or only
 * the faces that cross are marked (crossing_faces).
 */
#include "bridge/mend_cgal.hpp"

#include <algorithm>
#include <boost/iterator/function_output_iterator.hpp>
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

namespace
{

/* Runs PMP::self_intersections over range in slabs on threads and hands each crossing
 * pair once to sink(thread, pair): the slab that owns a pair is the first both its faces
 * overlap (the lowest of the slabs it is found in), so no pair is kept twice and no
 * slab's finds are held beyond their call. *used: the threads used (sink's first
 * argument is below it). */
template <class Sink>
void each_crossing(const Mesh &sm, const std::vector<Face_index> &range, int threads,
                   unsigned *used, Sink sink)
{
    size_t n = range.size();
    unsigned nt = n < parallel_min_faces ? 1u : threads_for(threads);
    size_t slabs = std::max<size_t>(nt, (n + slab_faces - 1) / slab_faces);
    *used = nt;
    if (slabs <= 1) {
        auto out = boost::make_function_output_iterator(
            [&](const std::pair<Face_index, Face_index> &p) { sink(0u, p); });
        PMP::self_intersections(range, sm, out);
        return;
    }
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
    std::vector<uint32_t> first(sm.num_faces(), 0);
    for (size_t i = 0; i < n; i++) {
        double a, b;
        extent(range[i], a, b);
        size_t s = (size_t)(std::lower_bound(cut.begin(), cut.end(), a) - cut.begin()) - 1;
        first[range[i].idx()] = (uint32_t)s;
        for (; s < slabs && b >= cut[s]; s++) /* cut[s] < a <= cut[s + 1] first */
            part[s].push_back(range[i]);
    }
    /* thread k takes slabs k, k + nt, ... */
    std::vector<std::exception_ptr> failed(nt);
    auto work = [&](unsigned k) {
        try {
            for (size_t s = k; s < slabs; s += nt) {
                auto out = boost::make_function_output_iterator(
                    [&](const std::pair<Face_index, Face_index> &p) {
                        if (std::max(first[p.first.idx()], first[p.second.idx()]) == s)
                            sink(k, p);
                    });
                PMP::self_intersections(part[s], sm, out);
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
}

} // namespace

std::vector<std::pair<Face_index, Face_index>>
crossing_pairs(const Mesh &sm, const std::vector<Face_index> &range, int threads)
{
    std::vector<std::vector<std::pair<Face_index, Face_index>>> found(threads_max);
    unsigned nt = 1;
    each_crossing(
        sm, range, threads, &nt, [&](unsigned k, const std::pair<Face_index, Face_index> &p) {
            found[k].push_back(p.second < p.first ? std::make_pair(p.second, p.first) : p);
        });
    std::vector<std::pair<Face_index, Face_index>> out = std::move(found[0]);
    for (unsigned k = 1; k < nt; k++) {
        out.insert(out.end(), found[k].begin(), found[k].end());
        std::vector<std::pair<Face_index, Face_index>>().swap(found[k]);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

size_t crossing_faces(const Mesh &sm, const std::vector<Face_index> &range, int threads,
                      std::vector<uint8_t> &mark)
{
    std::vector<std::vector<uint8_t>> marks(threads_max); /* each thread its own */
    std::vector<size_t> count(threads_max, 0);
    unsigned nt = 1;
    each_crossing(sm, range, threads, &nt,
                  [&](unsigned k, const std::pair<Face_index, Face_index> &p) {
                      if (marks[k].empty())
                          marks[k].assign(sm.num_faces(), 0);
                      marks[k][p.first.idx()] = 1;
                      marks[k][p.second.idx()] = 1;
                      count[k]++;
                  });
    mark.assign(sm.num_faces(), 0);
    size_t pairs = 0;
    for (unsigned k = 0; k < nt; k++) {
        for (size_t i = 0; i < marks[k].size(); i++)
            mark[i] |= marks[k][i];
        pairs += count[k];
    }
    return pairs;
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
