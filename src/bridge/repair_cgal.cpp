/*
 * repair_cgal.cpp: sr_mesh_repair (boolean.h): degenerate faces removed by CGAL's
 * Polygon Mesh Processing on a Surface_mesh built from the arrays, the result copied
 * back.
 */
#include "bridge/boolean_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>

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

namespace {

sr_status repair(sr_mesh *m, sr_repair_report *rep, sr_err *err)
{
    *rep = sr_repair_report();
    sr_status st = sr_mesh_validate(m, "mesh to repair", nullptr, err);
    if (st != SR_OK)
        return st;
    /* the common case first, on the arrays: no triangle of zero area (the same exact
     * test as below), so no halfedge mesh to build (a second on a two-million-triangle
     * restored part, which had none) */
    bool any = false;
    for (size_t t = 0; t < m->tri_count && !any; t++) {
        const uint32_t *c = m->tri + 3 * t;
        const double *a = m->xyz + 3 * (size_t)c[0], *b = m->xyz + 3 * (size_t)c[1],
                     *d = m->xyz + 3 * (size_t)c[2];
        any = c[0] == c[1] || c[1] == c[2] || c[0] == c[2] ||
              CGAL::collinear(Point(a[0], a[1], a[2]), Point(b[0], b[1], b[2]),
                              Point(d[0], d[1], d[2]));
    }
    if (!any)
        return SR_OK;
    Mesh sm;
    size_t bad_tri = 0;
    if (!build_surface_mesh(m, sm, &bad_tri))
        return sr_err_set(err, SR_E_INVALID,
                          "cannot repair: non-manifold vertex or edge at triangle %zu", bad_tri);
    auto degenerate_faces = [&sm]() {
        size_t n = 0;
        for (Mesh::Face_index f : sm.faces())
            n += PMP::is_degenerate_triangle_face(f, sm) ? 1 : 0;
        return n;
    };
    size_t before = degenerate_faces();
    if (before) {
        /* CGAL collapses or flips edges: the face count need not drop, so what is
         * reported is the zero-area triangles gone */
        PMP::remove_degenerate_faces(sm);
        sm.collect_garbage();
        size_t after = degenerate_faces();
        rep->degenerate_removed = before > after ? before - after : 0;
        rep->changed = 1;
    }
    if (!rep->changed)
        return SR_OK;
    sr_mesh res;
    st = mesh_to_arrays(sm, &res, err, "repair");
    if (st != SR_OK)
        return st;
    sr_mesh_release(m);
    *m = res;
    return SR_OK;
}

} // namespace

} // namespace sr_bool

using namespace sr_bool;

extern "C" {

sr_status sr_mesh_repair(sr_mesh *mesh, sr_repair_report *report, sr_err *err)
{
    sr_repair_report local;
    try {
        return repair(mesh, report ? report : &local, err);
    } catch (...) {
        return status_from_exception(err, "repair");
    }
}

} // extern "C"
