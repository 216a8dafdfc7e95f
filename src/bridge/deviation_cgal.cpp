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

        double max2 = 0, sum = 0, sum2 = 0;
        auto sample = [&](const Point &p) {
            double d2 = tree.squared_distance(p);
            if (d2 > max2)
                max2 = d2;
            sum += std::sqrt(d2);
            sum2 += d2;
        };
        for (size_t v = 0; v < a->vertex_count; v++) {
            const double *p = a->xyz + 3 * v;
            sample(Point(p[0], p[1], p[2]));
        }
        for (size_t t = 0; t < a->tri_count; t++) {
            const uint32_t *f = a->tri + 3 * t;
            const double *p = a->xyz + 3 * f[0], *q = a->xyz + 3 * f[1],
                         *r = a->xyz + 3 * f[2];
            sample(Point((p[0] + q[0] + r[0]) / 3, (p[1] + q[1] + r[1]) / 3,
                         (p[2] + q[2] + r[2]) / 3));
        }
        size_t n = a->vertex_count + a->tri_count;
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
