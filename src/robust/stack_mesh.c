/*
 * stack_mesh.c: closed mesh of a stack of extruded planar regions (stack_mesh.h): checks
 * the heights, gets the conforming triangle soup from the exact-arithmetic bridge
 * (bridge/stack_cgal.h), welds identical points and checks the result is closed.
 */
#include "robust/stack_mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "bridge/stack_cgal.h"

sr_status sr_stack_mesh(const sr_poly2 *regions, const double *z, size_t layers, sr_mesh *out,
                        sr_err *err)
{
    for (size_t i = 0; i < layers; i++)
        if (!(z[i + 1] > z[i]) || !isfinite(z[i]) || !isfinite(z[i + 1]))
            return sr_err_set(err, SR_E_RANGE,
                              "bad layer heights: z[%zu] = %g is not above z[%zu] = %g", i + 1,
                              z[i + 1], i, z[i]);
    sr_mesh m = {0};
    sr_status st = sr_stack_soup(regions, z, layers, &m.xyz, &m.vertex_count, &m.tri,
                                 &m.tri_count, err);
    if (st != SR_OK)
        return st;
    if (m.tri_count == 0) {
        sr_mesh_release(&m);
        *out = m;
        return SR_OK;
    }
    sr_mesh_edges e;
    st = sr_mesh_weld_exact(&m);
    if (st == SR_OK)
        st = sr_mesh_edge_stats(&m, &e);
    if (st != SR_OK) {
        sr_mesh_release(&m);
        return sr_err_set(err, st, "cannot build a patch: out of memory");
    }
    if (e.boundary_edges || e.nonmanifold_edges || e.misoriented_edges ||
        e.nonmanifold_vertices) {
        sr_mesh_release(&m);
        return sr_err_set(err, SR_E_INTERNAL,
                          "stacked patch is not a closed manifold (%zu open, %zu non-manifold, "
                          "%zu misoriented edges, %zu non-manifold vertices)",
                          e.boundary_edges, e.nonmanifold_edges, e.misoriented_edges,
                          e.nonmanifold_vertices);
    }
    *out = m;
    return SR_OK;
}

sr_status sr_stack_mesh_pulled_in(sr_poly2 *regions, const double *z, size_t layers,
                                  sr_mesh *out, sr_err *err)
{
    sr_status st = sr_stack_mesh(regions, z, layers, out, err);
    for (int retry = 1; retry <= 2 && st == SR_E_INTERNAL; retry++) {
        st = SR_OK;
        for (size_t l = 0; l < layers && st == SR_OK; l++)
            if (regions[l].contour_count > 0)
                st = sr_poly2_offset(&regions[l], -3e-4, 0, &regions[l], err);
        if (st == SR_OK)
            st = sr_stack_mesh(regions, z, layers, out, err);
    }
    return st;
}
