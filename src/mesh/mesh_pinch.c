/*
 * mesh_pinch.c: sr_mesh_split_pinches (mesh_pinch.h). The corners of every vertex are
 * gathered (a count sort by vertex); around one vertex, two corners whose triangles share
 * an edge (the vertex and one other) are joined by union-find, and every fan but the one
 * holding the vertex's first corner is moved to a new vertex. The new vertices are
 * appended in the order their fans are met.
 */
#include "mesh/mesh_pinch.h"
#include "base/grow.h"
#include "mesh/pair_sort.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint32_t find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

sr_status sr_mesh_split_pinches(sr_mesh *mesh, size_t *added, sr_err *err)
{
    size_t nv = mesh->vertex_count, nt = mesh->tri_count;
    if (3 * nt >= UINT32_MAX)
        return sr_err_set(err, SR_E_RANGE, "too many triangles to split pinched vertices");
    uint32_t *start = calloc(nv + 2, sizeof *start);
    uint32_t *corner = malloc((3 * nt + 1) * sizeof *corner);
    sr_pair32 *nb = NULL;
    uint32_t *parent = NULL, *root_v = NULL;
    sr_pair32 *moved = NULL; /* (corner, its new vertex): the fans moved, applied at the end */
    size_t cap = 0, extra = 0, n_moved = 0, cap_moved = 0;
    sr_status st = SR_OK;
    if (!start || !corner) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory splitting pinched vertices");
        goto out;
    }
    for (size_t i = 0; i < 3 * nt; i++)
        start[mesh->tri[i] + 1]++;
    for (size_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    for (size_t i = 0; i < 3 * nt; i++)
        corner[start[mesh->tri[i]]++] = (uint32_t)i;
    for (size_t v = nv; v > 0; v--) /* the fill advanced each start by its count */
        start[v] = start[v - 1];
    start[0] = 0;
    for (size_t u = 0; u < nv; u++) {
        size_t c0 = start[u], deg = start[u + 1] - c0;
        if (deg < 2)
            continue;
        if (deg > cap) {
            cap = 2 * deg;
            sr_pair32 *n2 = realloc(nb, 2 * cap * sizeof *nb);
            if (n2)
                nb = n2;
            uint32_t *p2 = realloc(parent, cap * sizeof *parent);
            if (p2)
                parent = p2;
            uint32_t *r2 = realloc(root_v, cap * sizeof *root_v);
            if (r2)
                root_v = r2;
            if (!n2 || !p2 || !r2) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory splitting pinched vertices");
                goto out;
            }
        }
        size_t nn = 0;
        for (size_t j = 0; j < deg; j++) {
            uint32_t c = corner[c0 + j];
            size_t t = c / 3, k = c % 3;
            uint32_t a = mesh->tri[3 * t + (k + 1) % 3], b = mesh->tri[3 * t + (k + 2) % 3];
            parent[j] = (uint32_t)j;
            if (a != u)
                nb[nn++] = (sr_pair32){a, (uint32_t)j};
            if (b != u)
                nb[nn++] = (sr_pair32){b, (uint32_t)j};
        }
        sr_pair32_sort(nb, nn);
        for (size_t i = 1; i < nn; i++)
            if (nb[i].key == nb[i - 1].key) {
                uint32_t x = find(parent, nb[i].tag), y = find(parent, nb[i - 1].tag);
                if (x != y)
                    parent[x > y ? x : y] = x > y ? y : x; /* the smaller root stays */
            }
        for (size_t j = 0; j < deg; j++)
            root_v[j] = UINT32_MAX;
        root_v[find(parent, 0)] = (uint32_t)u; /* the first corner's fan keeps u */
        for (size_t j = 0; j < deg; j++) {
            uint32_t r = find(parent, (uint32_t)j);
            if (root_v[r] == UINT32_MAX) {
                if (nv + extra >= SR_MESH_MAX_COUNT) {
                    st = sr_err_set(err, SR_E_RANGE,
                                    "too many vertices to split the pinched vertices");
                    goto out;
                }
                root_v[r] = (uint32_t)(nv + extra++);
            }
            if (root_v[r] == u)
                continue;
            sr_pair32 *m2 = sr_grow(moved, n_moved, &cap_moved, sizeof *moved);
            if (!m2) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory splitting pinched vertices");
                goto out;
            }
            moved = m2;
            moved[n_moved++] = (sr_pair32){corner[c0 + j], root_v[r]};
        }
    }
    if (extra > 0) {
        double *xyz = realloc(mesh->xyz, 3 * (nv + extra) * sizeof *xyz);
        if (!xyz) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory splitting pinched vertices");
            goto out;
        }
        mesh->xyz = xyz;
        for (size_t i = 0; i < n_moved; i++) {
            uint32_t *v = &mesh->tri[moved[i].key];
            memcpy(xyz + 3 * (size_t)moved[i].tag, xyz + 3 * (size_t)*v, 3 * sizeof *xyz);
            *v = moved[i].tag;
        }
        mesh->vertex_count = nv + extra;
    }
    if (added)
        *added = extra;
out:
    free(start);
    free(corner);
    free(moved);
    free(nb);
    free(parent);
    free(root_v);
    return st;
}
