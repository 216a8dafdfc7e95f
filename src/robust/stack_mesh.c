/*
 * stack_mesh.c: closed mesh of a stack of extruded planar regions (stack_mesh.h): checks
 * the heights, gets the conforming triangle soup from the exact-arithmetic bridge
 * (bridge/stack_cgal.h), welds identical points and checks the result is closed; and
 * merges runs of identical layers before stacking (sr_stack_merge_identical).
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

/* *same = 1 when regions a and b are the same region (their exclusive-or is empty). */
static sr_status same_region(const sr_poly2 *a, const sr_poly2 *b, int *same, sr_err *err)
{
    if (a->contour_count == 0 || b->contour_count == 0) {
        *same = a->contour_count == 0 && b->contour_count == 0;
        return SR_OK;
    }
    sr_poly2 x = {0};
    sr_status st = sr_poly2_boolean(SR_POLY_XOR, a, b, &x, err);
    if (st == SR_OK)
        *same = x.contour_count == 0;
    sr_poly2_release(&x);
    return st;
}

sr_status sr_stack_merge_identical(sr_poly2 *regions, double *z, size_t *layers, sr_err *err)
{
    size_t n = *layers, runs = 0;
    if (n < 2)
        return SR_OK;
    uint8_t *same = calloc(n, 1); /* same[l]: layer l is layer l - 1's region */
    if (!same)
        return sr_err_set(err, SR_E_NOMEM, "out of memory merging layers");
    for (size_t l = 1; l < n; l++) {
        int s = 0;
        sr_status st = same_region(&regions[l - 1], &regions[l], &s, err);
        if (st != SR_OK) {
            free(same);
            return st;
        }
        same[l] = (uint8_t)s;
    }
    for (size_t l = 0; l < n; l++) {
        if (same[l]) {
            sr_poly2_release(&regions[l]);
        } else {
            if (runs != l) {
                regions[runs] = regions[l];
                sr_poly2_init(&regions[l]);
            }
            z[runs] = z[l];
            runs++;
        }
        z[runs] = z[l + 1];
    }
    free(same);
    *layers = runs;
    return SR_OK;
}
