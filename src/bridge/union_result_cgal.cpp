/*
 * union_result_cgal.cpp: the part of the local union (union_local_cgal.cpp, where the
 * method is described) that makes its result from CGAL's classification of the
 * corefined patches: N and b united as arrays (Local_result: a's vertex numbers kept,
 * new points after them), the patches with no intersection edge placed by a point of
 * them; the check that the result closes up with the untouched rest of a; the splice
 * into a's arrays; and b \ a, for the _split form, as a compact mesh.
 */
#include "bridge/boolean_cgal.hpp"
#include "bridge/classify_cgal.hpp"

#include <CGAL/Side_of_triangle_mesh.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

namespace sr_bool {

namespace {

/* Appends a new point to the local result, mapped back to a's frame (back NULL: as it
 * is). */
void push_point(Local_result &res, const Point &p, const double *back)
{
    double q[3] = {p.x(), p.y(), p.z()};
    if (back)
        sr_xform_apply(back, q, q);
    res.fresh.push_back(q[0]);
    res.fresh.push_back(q[1]);
    res.fresh.push_back(q[2]);
}

} // namespace

/* Writes the local result into *dst, which holds a's arrays (its own copy, or a's very
 * arrays when the union is in place) with room for the growth: N's triangles out, the
 * local result in, vertices no triangle uses any more dropped. Cannot fail. */
void splice_local(sr_mesh *dst, const std::vector<uint8_t> &in, const Local_result &res)
{
    size_t nv = dst->vertex_count, w = 0;
    for (size_t t = 0; t < dst->tri_count; t++)
        if (in[t]) {
            continue;
        } else {
            if (w != t)
                memmove(dst->tri + 3 * w, dst->tri + 3 * t, 3 * sizeof(uint32_t));
            w++;
        }
    if (!res.fresh.empty())
        memcpy(dst->xyz + 3 * nv, res.fresh.data(), res.fresh.size() * sizeof(double));
    size_t next = nv + res.fresh.size() / 3;
    memcpy(dst->tri + 3 * w, res.tri.data(), res.tri.size() * sizeof(uint32_t));
    w += res.tri.size() / 3;
    std::vector<uint32_t> remap(next, no_vertex);
    for (size_t i = 0; i < 3 * w; i++)
        remap[dst->tri[i]] = 0;
    size_t kept = 0;
    for (size_t v = 0; v < next; v++)
        if (remap[v] != no_vertex) {
            if (kept != v)
                memmove(dst->xyz + 3 * kept, dst->xyz + 3 * v, 3 * sizeof(double));
            remap[v] = static_cast<uint32_t>(kept++);
        }
    for (size_t i = 0; i < 3 * w; i++)
        dst->tri[i] = remap[dst->tri[i]];
    dst->vertex_count = kept;
    dst->tri_count = w;
}

/* Unites the corefined N (sm) and b (mb) from the patch flags: N's patches outside b
 * (and its coplanar patches a union keeps), b's patches outside a, joined at the
 * intersection nodes. Patches with no intersection edge are placed by a point of them:
 * b's against the whole of a (inside_by_rays: N alone cannot tell), N's against b.
 * False (why set) when that cannot be told (a ray through an edge of a; a patch of N
 * on b's surface). */
bool assemble_local(const sr_mesh *a, const char *a_what, const char *b_what,
                    const double *xf, const double *back, Mesh &sm,
                    Mesh::Property_map<Vertex_index, uint32_t> orig, Mesh &mb,
                    Patch_flags flags[2], const std::vector<uint32_t> node_vertex[2],
                    Local_result &res, std::vector<uint32_t> *diff, char *why,
                    size_t why_size)
{
    Patch_flags &f1 = flags[0], &f2 = flags[1];
    if (f2.not_set.any() &&
        !classify_free_patches(mb, f2, [&](std::size_t pid, const Point &p) {
            int side = inside_by_rays(a, xf, p);
            if (side < 0) {
                snprintf(why, why_size, "a part of '%s' meets no triangle of '%s'", b_what,
                         a_what);
                return false;
            }
            if (side == 1)
                f2.inside.set(pid);
            return true;
        }))
        return false;
    if (f1.not_set.any()) {
        CGAL::Side_of_triangle_mesh<Mesh, K> side(mb);
        if (!classify_free_patches(sm, f1, [&](std::size_t pid, const Point &p) {
                if (f1.coplanar.test(pid)) {
                    f1.coplanar_union.set(pid);
                    return true;
                }
                CGAL::Bounded_side bs = side(p);
                if (bs == CGAL::ON_BOUNDARY) {
                    snprintf(why, why_size,
                             "a part of '%s' touches '%s' away from the intersection", a_what,
                             b_what);
                    return false;
                }
                if (bs == CGAL::ON_BOUNDED_SIDE)
                    f1.inside.set(pid);
                return true;
            }))
            return false;
    }
    boost::dynamic_bitset<> use1 = ~f1.inside - f1.coplanar;
    if (f1.coplanar.any())
        use1 |= f1.coplanar_union;
    boost::dynamic_bitset<> use2 = ~f2.inside - f2.coplanar;

    const uint32_t base = static_cast<uint32_t>(a->vertex_count);
    std::vector<uint32_t> id1(sm.num_vertices(), no_vertex), id2(mb.num_vertices(), no_vertex);
    auto id_of_n = [&](Vertex_index v) {
        uint32_t &id = id1[v.idx()];
        if (id == no_vertex) {
            if (orig[v] != no_vertex) {
                id = orig[v];
            } else {
                id = base + static_cast<uint32_t>(res.fresh.size() / 3);
                push_point(res, sm.point(v), back);
            }
        }
        return id;
    };
    /* b's vertices at intersection nodes are N's vertices at the same nodes (by node,
     * not by position: distinct nodes may round to the same point) */
    for (std::size_t node = 0; node < node_vertex[1].size(); node++) {
        uint32_t vb = node_vertex[1][node];
        if (vb != no_vertex && node < node_vertex[0].size() && node_vertex[0][node] != no_vertex)
            id2[vb] = id_of_n(Vertex_index(node_vertex[0][node]));
    }
    for (Mesh::Face_index fd : sm.faces()) {
        if (!use1.test(f1.patch[fd.idx()]))
            continue;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(fd)))
            res.tri.push_back(id_of_n(v));
    }
    for (Mesh::Face_index fd : mb.faces()) {
        if (!use2.test(f2.patch[fd.idx()]))
            continue;
        for (Vertex_index v : mb.vertices_around_face(mb.halfedge(fd))) {
            uint32_t &id = id2[v.idx()];
            if (id == no_vertex) {
                id = base + static_cast<uint32_t>(res.fresh.size() / 3);
                push_point(res, mb.point(v), back);
            }
            res.tri.push_back(id);
            if (diff)
                diff->push_back(id);
        }
    }
    if (!diff)
        return true;
    /* b \ a: b's patches outside a (above) and, turned over, N's patches inside b and
     * those on b's surface facing it (coplanar, not kept by the union: the two touch
     * there from opposite sides, so b's face bounds the difference) */
    boost::dynamic_bitset<> turn = f1.inside - f1.coplanar;
    if (f1.coplanar.any())
        turn |= f1.coplanar - f1.coplanar_union;
    for (Mesh::Face_index fd : sm.faces()) {
        if (!turn.test(f1.patch[fd.idx()]))
            continue;
        uint32_t ids[3];
        int k = 0;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(fd)))
            if (k < 3)
                ids[k++] = id_of_n(v);
        diff->push_back(ids[0]);
        diff->push_back(ids[2]);
        diff->push_back(ids[1]);
    }
    return true;
}

/* The difference's triangles (ids as in Local_result) as a compact mesh in a's frame. */
sr_status diff_to_mesh(const sr_mesh *a, const Local_result &res,
                       const std::vector<uint32_t> &diff, sr_mesh *out)
{
    const uint32_t base = static_cast<uint32_t>(a->vertex_count);
    std::vector<uint32_t> remap;
    std::vector<uint32_t> ids = diff;
    std::vector<std::pair<uint32_t, uint32_t>> order;
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    sr_mesh m;
    sr_mesh_init(&m);
    if (sr_mesh_alloc(&m, ids.size() ? ids.size() : 1, diff.size() / 3 ? diff.size() / 3 : 1) != SR_OK)
        return SR_E_NOMEM;
    m.vertex_count = ids.size();
    m.tri_count = diff.size() / 3;
    for (size_t i = 0; i < ids.size(); i++) {
        const double *p = ids[i] < base ? a->xyz + 3 * static_cast<size_t>(ids[i])
                                        : res.fresh.data() + 3 * static_cast<size_t>(ids[i] - base);
        memcpy(m.xyz + 3 * i, p, 3 * sizeof(double));
    }
    for (size_t t = 0; t < diff.size(); t++)
        m.tri[t] = static_cast<uint32_t>(std::lower_bound(ids.begin(), ids.end(), diff[t]) -
                                         ids.begin());
    *out = m;
    return SR_OK;
}

/* True when the local result closes up with the rest of a: its open edges are exactly
 * N's border (border_before: a's directed edges of N with no N triangle across), and
 * elsewhere every edge has two triangles running it both ways and every vertex one
 * fan. */
bool local_result_fits(const Local_result &res, const std::vector<uint64_t> &border_before,
                       size_t base)
{
    size_t nt = res.tri.size() / 3;
    if (nt == 0)
        return false;
    std::vector<uint64_t> he;
    he.reserve(3 * nt);
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            he.push_back(he_key(res.tri[3 * t + k], res.tri[3 * t + (k + 1) % 3]));
    std::sort(he.begin(), he.end());
    if (std::adjacent_find(he.begin(), he.end()) != he.end())
        return false; /* an edge run twice the same way: not oriented or not manifold */ /* an edge run twice the same way: not oriented or not manifold */
    std::vector<uint64_t> open;
    for (uint64_t k : he) {
        uint32_t x = static_cast<uint32_t>(k >> 32), y = static_cast<uint32_t>(k);
        if (!std::binary_search(he.begin(), he.end(), he_key(y, x))) {
            if (x >= base || y >= base)
                return false;
            open.push_back(k);
        }
    }
    if (open != border_before) /* both sorted */
        return false;
    /* fans: the local result's own check (edges are fine by now) */
    sr_mesh m;
    m.tri = const_cast<uint32_t *>(res.tri.data());
    m.tri_count = nt;
    m.xyz = nullptr;
    m.vertex_count = 0;
    sr_mesh_edges e;
    if (sr_mesh_edge_stats(&m, &e) != SR_OK)
        return false;
    return e.nonmanifold_edges == 0 && e.misoriented_edges == 0 && e.nonmanifold_vertices == 0;
}

} // namespace sr_bool
