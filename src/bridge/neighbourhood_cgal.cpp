/*
 * neighbourhood_cgal.cpp: the part of the local union (union_local_cgal.cpp, where the
 * method is described) that works on a's arrays alone: the neighbourhood N of the
 * patch selected (triangles of a near b's box, grown over whole fans), directed-edge
 * keys, points mapped into the union's frame, and whether a point lies inside a by
 * rays.
 */
#include "bridge/boolean_cgal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

namespace sr_bool {

/* Key of the directed edge x -> y. */
uint64_t he_key(uint32_t x, uint32_t y)
{
    return static_cast<uint64_t>(x) << 32 | y;
}

/* Vertex v of m in the union's frame: mapped by xf (3x4), or as it is (xf NULL). */
void frame_point(const sr_mesh *m, size_t v, const double *xf, double out[3])
{
    const double *p = m->xyz + 3 * v;
    if (!xf) {
        out[0] = p[0];
        out[1] = p[1];
        out[2] = p[2];
        return;
    }
    sr_xform_apply(xf, p, out);
}

namespace {

bool tri_box_meets(const sr_mesh *m, size_t t, const double *xf, const double box[6])
{
    const uint32_t *f = m->tri + 3 * t;
    double q[3][3];
    for (int j = 0; j < 3; j++)
        frame_point(m, f[j], xf, q[j]);
    for (int k = 0; k < 3; k++) {
        double lo = q[0][k], hi = lo;
        for (int j = 1; j < 3; j++) {
            lo = q[j][k] < lo ? q[j][k] : lo;
            hi = q[j][k] > hi ? q[j][k] : hi;
        }
        if (hi < box[k] || lo > box[3 + k])
            return false;
    }
    return true;
}

/* The directed edges of the triangles flagged in `in`, sorted. */
std::vector<uint64_t> flagged_halfedges(const sr_mesh *m, const std::vector<uint8_t> &in)
{
    std::vector<uint64_t> he;
    for (size_t t = 0; t < m->tri_count; t++)
        if (in[t])
            for (int k = 0; k < 3; k++)
                he.push_back(he_key(m->tri[3 * t + k], m->tri[3 * t + (k + 1) % 3]));
    std::sort(he.begin(), he.end());
    return he;
}

bool has_key(const std::vector<uint64_t> &sorted, uint64_t key)
{
    return std::binary_search(sorted.begin(), sorted.end(), key);
}

} // namespace

/* Selects N (see above). False when the fans cannot be mended in a few rounds. */
bool select_neighbourhood(const sr_mesh *a, const double *xf, const double box[6],
                          std::vector<uint8_t> &in, size_t *count)
{
    in.assign(a->tri_count, 0);
    size_t n = 0;
    for (size_t t = 0; t < a->tri_count; t++)
        if (tri_box_meets(a, t, xf, box)) {
            in[t] = 1;
            n++;
        }
    /* Around a vertex v, the triangle after corner (v, x, y) holds the edge v -> y (a's
     * edges are manifold and oriented). So every run of N's triangles around v ends at
     * exactly one corner of N whose v -> y is in no triangle of N, and a vertex with two
     * such corners has N's triangles in several fans: take all of its triangles. */
    std::vector<uint32_t> bad;
    for (int round = 0; round < 8; round++) {
        std::vector<uint64_t> he = flagged_halfedges(a, in);
        std::vector<uint32_t> starts;
        for (size_t t = 0; t < a->tri_count; t++) {
            if (!in[t])
                continue;
            const uint32_t *f = a->tri + 3 * t;
            for (int k = 0; k < 3; k++) {
                uint32_t v = f[k], y = f[(k + 2) % 3];
                if (!has_key(he, he_key(v, y)))
                    starts.push_back(v);
            }
        }
        std::sort(starts.begin(), starts.end());
        bad.clear();
        for (size_t i = 0; i + 1 < starts.size(); i++)
            if (starts[i] == starts[i + 1] && (bad.empty() || bad.back() != starts[i]))
                bad.push_back(starts[i]);
        if (bad.empty()) {
            *count = n;
            return true;
        }
        for (size_t t = 0; t < a->tri_count; t++) {
            if (in[t])
                continue;
            const uint32_t *f = a->tri + 3 * t;
            for (int k = 0; k < 3; k++)
                if (std::binary_search(bad.begin(), bad.end(), f[k])) {
                    in[t] = 1;
                    n++;
                    break;
                }
        }
    }
    return false;
}

/* Whether p lies inside the closed mesh a (mapped by xf): parity of a's triangles
 * crossed by each of three rays in unrelated directions, the majority deciding; 1
 * inside, 0 outside, -1 when a ray runs through an edge or a vertex of a (parity
 * undefined) in two of them. Linear in a: for the few pieces of a patch that no
 * triangle of the neighbourhood cuts. */
int inside_by_rays(const sr_mesh *a, const double *xf, const Point &p)
{
    static const double dirs[3][3] = {{0.5773502691896258, 0.5773502691896258 + 1e-3,
                                       0.5773502691896258 - 2e-3},
                                      {-0.3120309, 0.8224617, -0.4755931},
                                      {0.7003127, -0.2101003, 0.6822417}};
    int in = 0, out = 0;
    for (int r = 0; r < 3; r++) {
        K::Ray_3 ray(p, K::Vector_3(dirs[r][0], dirs[r][1], dirs[r][2]));
        size_t hits = 0;
        bool clean = true;
        for (size_t t = 0; t < a->tri_count && clean; t++) {
            double q[3][3];
            for (int k = 0; k < 3; k++)
                frame_point(a, a->tri[3 * t + k], xf, q[k]);
            Triangle tri(Point(q[0][0], q[0][1], q[0][2]), Point(q[1][0], q[1][1], q[1][2]),
                         Point(q[2][0], q[2][1], q[2][2]));
            if (tri.is_degenerate() || !CGAL::do_intersect(ray, tri))
                continue;
            /* through an edge or a vertex: the ray meets the triangle's boundary */
            for (int k = 0; k < 3 && clean; k++) {
                K::Segment_3 e(tri.vertex(k), tri.vertex((k + 1) % 3));
                if (CGAL::do_intersect(ray, e))
                    clean = false;
            }
            hits++;
        }
        if (!clean)
            continue;
        if (hits & 1)
            in++;
        else
            out++;
    }
    if (in >= 2)
        return 1;
    if (out >= 2)
        return 0;
    return -1;
}

} // namespace sr_bool

using namespace sr_bool;

extern "C" {



} // extern "C"
