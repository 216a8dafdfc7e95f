/*
 * deviation_cgal.cpp: surface deviation (sr_mesh_deviation, boolean.h). It samples every
 * vertex and every triangle centroid of a, and asks an AABB tree over b's triangles for
 * the squared distance to the nearest point (CGAL builds a KD-tree of b's reference
 * points on the first query to start each search close). The tree holds b as a
 * triangle soup rather than a face graph, so b may be open, non-manifold or
 * inconsistently oriented (a raw scan); zero-area triangles of b are left out (they
 * hold no point that their neighbours' edges do not).
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

using namespace sr_bool;

extern "C" {

sr_status sr_mesh_deviation(const sr_mesh *a, const sr_mesh *b, sr_deviation *out,
                            sr_err *err)
{
    try {
        sr_status st = sr_mesh_validate(a, "sampled mesh", NULL, err);
        if (st != SR_OK)
            return st;
        st = sr_mesh_validate(b, "reference mesh", NULL, err);
        if (st != SR_OK)
            return st;

        std::vector<Triangle> tris;
        tris.reserve(b->tri_count);
        for (size_t t = 0; t < b->tri_count; t++) {
            const uint32_t *f = b->tri + 3 * t;
            const double *p = b->xyz + 3 * f[0], *q = b->xyz + 3 * f[1],
                         *r = b->xyz + 3 * f[2];
            Triangle tri(Point(p[0], p[1], p[2]), Point(q[0], q[1], q[2]),
                         Point(r[0], r[1], r[2]));
            if (!tri.is_degenerate())
                tris.push_back(tri);
        }
        if (tris.empty())
            return sr_err_set(err, SR_E_INVALID,
                              "'reference mesh' has no triangle of non-zero area");
        Aabb_tree tree(tris.begin(), tris.end());
        tree.build();
        tree.accelerate_distance_queries();

        /* The samples (a's vertices, then its centroids) in fixed blocks, spread over
         * the threads; a block's partial figures are combined in block order, so the
         * result does not depend on the thread count. Inside a block each query starts
         * from the previous sample's nearest point (neighbouring samples have nearby
         * nearest points), which prunes the tree walk far sooner than a cold query. */
        const size_t n = a->vertex_count + a->tri_count;
        const size_t block = 4096;
        const size_t blocks = (n + block - 1) / block;
        std::vector<double> bmax2(blocks, 0.0), bsum(blocks, 0.0), bsum2(blocks, 0.0);
        auto at = [&](size_t i) {
            if (i < a->vertex_count) {
                const double *p = a->xyz + 3 * i;
                return Point(p[0], p[1], p[2]);
            }
            const uint32_t *f = a->tri + 3 * (i - a->vertex_count);
            const double *p = a->xyz + 3 * f[0], *q = a->xyz + 3 * f[1], *r = a->xyz + 3 * f[2];
            return Point((p[0] + q[0] + r[0]) / 3, (p[1] + q[1] + r[1]) / 3,
                         (p[2] + q[2] + r[2]) / 3);
        };
#pragma omp parallel for schedule(dynamic, 1)
        for (size_t bi = 0; bi < blocks; bi++) {
            size_t end = std::min(n, (bi + 1) * block);
            double m2 = 0, s = 0, s2 = 0;
            Point hint = tree.closest_point(at(bi * block));
            for (size_t i = bi * block; i < end; i++) {
                Point p = at(i);
                hint = tree.closest_point(p, hint);
                double d2 = CGAL::to_double(CGAL::squared_distance(p, hint));
                if (d2 > m2)
                    m2 = d2;
                s += std::sqrt(d2);
                s2 += d2;
            }
            bmax2[bi] = m2;
            bsum[bi] = s;
            bsum2[bi] = s2;
        }
        double max2 = 0, sum = 0, sum2 = 0;
        for (size_t bi = 0; bi < blocks; bi++) {
            max2 = std::max(max2, bmax2[bi]);
            sum += bsum[bi];
            sum2 += bsum2[bi];
        }
        sr_deviation d;
        d.max_mm = std::sqrt(max2);
        d.mean_mm = sum / static_cast<double>(n);
        d.rms_mm = std::sqrt(sum2 / static_cast<double>(n));
        d.samples = n;
        *out = d;
        return SR_OK;
    } catch (...) {
        return status_from_exception(err, "surface deviation");
    }
}

} // extern "C"
