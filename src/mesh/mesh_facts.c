/*
 * mesh_facts.c: the facts `symrec check` prints about a mesh (mesh_facts.h): counts,
 * box, volume and area, edge use and orientation, degenerate and duplicate triangles
 * (sorted vertex triples), connected pieces (union-find over the triangles' vertices),
 * and the unit the size suggests.
 */
#include "mesh/mesh_facts.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *sr_unit_guess(double largest_extent)
{
    if (!(largest_extent > 0))
        return "mm";
    if (largest_extent < 1)
        return "m";
    if (largest_extent < 5)
        return "in";
    if (largest_extent <= 3000)
        return "mm";
    return "um";
}

static uint32_t find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static int cmp_triple(const void *a, const void *b)
{
    const uint32_t *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

sr_status sr_mesh_facts_get(const sr_mesh *m, sr_mesh_facts *out, sr_err *err)
{
    sr_mesh_facts f;
    memset(&f, 0, sizeof f);
    f.vertices = m->vertex_count;
    f.triangles = m->tri_count;
    sr_mesh_bbox(m, f.bbox_min, f.bbox_max);
    for (int k = 0; k < 3; k++)
        f.largest_extent = fmax(f.largest_extent, f.bbox_max[k] - f.bbox_min[k]);
    f.volume = sr_mesh_volume(m);
    f.area = sr_mesh_area(m);
    if (sr_mesh_edge_stats(m, &f.edges) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory checking the mesh");
    f.closed = m->tri_count > 0 && f.edges.boundary_edges == 0 && f.edges.nonmanifold_edges == 0;
    f.oriented = f.closed && f.edges.misoriented_edges == 0;
    f.outward = f.oriented && f.volume > 0;
    f.likely_unit = sr_unit_guess(f.largest_extent);

    uint32_t *triples = malloc((m->tri_count ? m->tri_count : 1) * 3 * sizeof *triples);
    uint32_t *parent = malloc((m->vertex_count ? m->vertex_count : 1) * sizeof *parent);
    size_t *size = calloc(m->vertex_count ? m->vertex_count : 1, sizeof *size);
    if (!triples || !parent || !size) {
        free(triples);
        free(parent);
        free(size);
        return sr_err_set(err, SR_E_NOMEM, "out of memory checking the mesh");
    }
    for (size_t v = 0; v < m->vertex_count; v++)
        parent[v] = (uint32_t)v;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *tri = m->tri + 3 * t;
        double n[3];
        sr_mesh_tri_normal(m, t, n);
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
            !(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 0))
            f.degenerate_triangles++;
        uint32_t s[3] = {tri[0], tri[1], tri[2]};
        for (int i = 0; i < 2; i++) /* sort the three */
            for (int j = 0; j < 2 - i; j++)
                if (s[j] > s[j + 1]) {
                    uint32_t x = s[j];
                    s[j] = s[j + 1];
                    s[j + 1] = x;
                }
        memcpy(triples + 3 * t, s, sizeof s);
        uint32_t a = find(parent, tri[0]);
        for (int k = 1; k < 3; k++) {
            uint32_t b = find(parent, tri[k]);
            if (a != b)
                parent[b] = a;
        }
    }
    qsort(triples, m->tri_count, 3 * sizeof *triples, cmp_triple);
    for (size_t t = 1; t < m->tri_count; t++)
        if (cmp_triple(triples + 3 * (t - 1), triples + 3 * t) == 0)
            f.duplicate_triangles++;
    for (size_t t = 0; t < m->tri_count; t++)
        size[find(parent, m->tri[3 * t])]++;
    for (size_t v = 0; v < m->vertex_count; v++)
        if (size[v] > 0) {
            f.components++;
            if (size[v] > f.largest_component)
                f.largest_component = size[v];
        }
    free(triples);
    free(parent);
    free(size);
    *out = f;
    return SR_OK;
}
