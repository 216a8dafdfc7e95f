/*
 * stack_mesh.c: closed mesh of a stack of extruded planar regions (stack_mesh.h): checks
 * the heights, gets the conforming triangle soup from the exact-arithmetic bridge
 * (bridge/stack_cgal.h), welds identical points and checks the result is closed.
 */
#include "stack_mesh.h"

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
    if (e.boundary_edges || e.nonmanifold_edges || e.misoriented_edges) {
        sr_mesh_release(&m);
        return sr_err_set(err, SR_E_INTERNAL,
                          "stacked patch is not closed (%zu open, %zu non-manifold, %zu "
                          "misoriented edges)",
                          e.boundary_edges, e.nonmanifold_edges, e.misoriented_edges);
    }
    *out = m;
    return SR_OK;
}
