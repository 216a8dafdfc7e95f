/*
 * clip_local_cgal.cpp: the local intersection (sr_boolean_intersection_local,
 * clip_local.h): a ∩ b for a large closed a (a scan's image) and a small closed b (a
 * section's hull) from a's neighbourhood N of b alone. Every triangle of a inside b or
 * cut by b is in N (N holds all that meet b's grown box), so a ∩ b is N's patches inside
 * b (and those on b's surface facing the same way) with b's patches inside a: unlike the
 * local union nothing is spliced back into a. The patches come from CGAL's own
 * classification (classify_cgal.hpp's visitor); b's patches no triangle of N cuts are
 * placed by rays against the whole of a, N's by CGAL's point-in-volume against b.
 * Whenever that cannot be trusted the whole-mesh intersection (boolean_cgal.cpp) runs.
 * a may come mapped (a symmetry image of the scan): only N's vertices are mapped, and a
 * mapped copy of a is made only for the whole-mesh fallback.
 */
#include "bridge/boolean_cgal.hpp"
#include "bridge/classify_cgal.hpp"

#include <CGAL/Side_of_triangle_mesh.h>

extern "C" {
#include "bridge/clip_local.h"
}

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

namespace sr_bool
{

namespace
{

/* The corefined N (sm) and b (mb) joined into the intersection as a compact mesh: the
 * faces of the patches use1 (of N) and use2 (of b); b's vertices at intersection nodes
 * are N's at the same nodes (by node, not by position). */
sr_status join_patches(const Mesh &sm, const Mesh &mb, const Patch_flags flags[2],
                       const boost::dynamic_bitset<> &use1, const boost::dynamic_bitset<> &use2,
                       const std::vector<uint32_t> node_vertex[2], sr_mesh *out)
{
    std::vector<uint32_t> id1(sm.num_vertices(), no_vertex), id2(mb.num_vertices(), no_vertex);
    std::vector<double> xyz;
    std::vector<uint32_t> tri;
    auto take = [&](uint32_t &id, const Point &p) {
        if (id == no_vertex) {
            id = static_cast<uint32_t>(xyz.size() / 3);
            xyz.push_back(p.x());
            xyz.push_back(p.y());
            xyz.push_back(p.z());
        }
        return id;
    };
    for (std::size_t node = 0; node < node_vertex[1].size(); node++) {
        uint32_t vb = node_vertex[1][node];
        if (vb != no_vertex && node < node_vertex[0].size() && node_vertex[0][node] != no_vertex) {
            Vertex_index vn(node_vertex[0][node]);
            id2[vb] = take(id1[vn.idx()], sm.point(vn));
        }
    }
    for (Mesh::Face_index fd : sm.faces())
        if (use1.test(flags[0].patch[fd.idx()]))
            for (Vertex_index v : sm.vertices_around_face(sm.halfedge(fd)))
                tri.push_back(take(id1[v.idx()], sm.point(v)));
    for (Mesh::Face_index fd : mb.faces())
        if (use2.test(flags[1].patch[fd.idx()]))
            for (Vertex_index v : mb.vertices_around_face(mb.halfedge(fd)))
                tri.push_back(take(id2[v.idx()], mb.point(v)));
    sr_mesh m;
    sr_mesh_init(&m);
    size_t nv = xyz.size() / 3, nt = tri.size() / 3;
    if (sr_mesh_alloc(&m, nv ? nv : 1, nt ? nt : 1) != SR_OK)
        return SR_E_NOMEM;
    if (nv)
        memcpy(m.xyz, xyz.data(), xyz.size() * sizeof(double));
    if (nt)
        memcpy(m.tri, tri.data(), tri.size() * sizeof(uint32_t));
    m.vertex_count = nv;
    m.tri_count = nt;
    *out = m;
    return SR_OK;
}

/* The bounding box of a's vertices mapped by xf (NULL: as they are), as sr_mesh_bbox
 * gives it of the mapped copy. */
void mapped_bbox(const sr_mesh *a, const double *xf, double box[6])
{
    for (int k = 0; k < 6; k++)
        box[k] = 0;
    for (size_t v = 0; v < a->vertex_count; v++) {
        double p[3];
        frame_point(a, v, xf, p);
        for (int k = 0; k < 3; k++) {
            if (v == 0 || p[k] < box[k])
                box[k] = p[k];
            if (v == 0 || p[k] > box[3 + k])
                box[3 + k] = p[k];
        }
    }
}

/* The local intersection proper. SR_OK with *done = false when a condition for it fails
 * (why in `why`): the caller runs the whole-mesh intersection. */
sr_status clip_local(const sr_mesh *a, const char *a_what, const double *xf, const sr_mesh *b,
                     const char *b_what, double margin, sr_mesh *out, bool *done, char *why,
                     size_t why_size, size_t *n_tris, sr_err *err)
{
    *done = false;
    sr_mesh_edges edges;
    sr_status st = check_arrays(a, a_what, &edges, err);
    if (st != SR_OK)
        return st; /* as the whole-mesh check of a refuses it */
    if (edges.nonmanifold_vertices) {
        snprintf(why, why_size, "'%s' has a non-manifold vertex", a_what);
        return SR_OK;
    }
    double box_a[6], box_b[6];
    mapped_bbox(a, xf, box_a);
    sr_mesh_bbox(b, box_b, box_b + 3);
    Mesh mb;
    sr_err berr = {{0}};
    if (check_operand(b, b_what, box_a, mb, &berr) != SR_OK) {
        snprintf(why, why_size, "'%s' was refused", b_what);
        return SR_OK;
    }
    double box[6];
    grown_box(box_b, margin, box);
    std::vector<uint8_t> in;
    size_t n = 0;
    if (!select_neighbourhood(a, xf, box, in, &n)) {
        snprintf(why, why_size, "the neighbourhood's fans could not be mended");
        return SR_OK;
    }
    *n_tris = n;
    std::vector<double> loc_xyz;
    std::vector<uint32_t> loc_tri, loc_orig;
    neighbourhood_arrays(a, xf, in, n, loc_xyz, loc_tri, loc_orig, xf && sr_xform_det(xf) < 0);
    sr_mesh loc = {loc_xyz.data(), loc_tri.data(), loc_orig.size(), n};
    Mesh sm;
    if (!build_neighbourhood(loc, loc_orig, sm)) {
        snprintf(why, why_size, "the neighbourhood is not a halfedge mesh");
        return SR_OK;
    }
    /* N holds every triangle of a that meets b's box: the whole-mesh check's answer */
    if (self_intersects_near(sm, box_b))
        return sr_err_set(err, SR_E_INVALID, "'%s' intersects itself where the other mesh is",
                          a_what);

    Patch_flags flags[2];
    std::vector<uint32_t> node_vertex[2];
    Classify_visitor vis;
    vis.flags = flags;
    vis.first = &sm;
    vis.node_vertex = node_vertex;
    const std::array<boost::optional<Mesh *>, 4> no_output = {
        {boost::none, boost::none, boost::none, boost::none}};
    PMP::corefine_and_compute_boolean_operations(sm, mb, no_output, CGAL::parameters::visitor(vis));
    if (!flags[0].have || !flags[1].have) {
        snprintf(why, why_size, "'%s' meets no triangle of '%s'", b_what, a_what);
        return SR_OK;
    }
    Patch_flags &f1 = flags[0], &f2 = flags[1];
    if (f2.not_set.any() && !classify_free_patches(mb, f2, [&](std::size_t pid, const Point &p) {
            int side = inside_by_rays(a, xf, p);
            if (side < 0) {
                snprintf(why, why_size, "a part of '%s' meets no triangle of '%s'", b_what, a_what);
                return false;
            }
            if (side == 1)
                f2.inside.set(pid);
            return true;
        }))
        return SR_OK;
    if (f1.not_set.any()) {
        CGAL::Side_of_triangle_mesh<Mesh, K> side(mb);
        if (!classify_free_patches(sm, f1, [&](std::size_t pid, const Point &p) {
                CGAL::Bounded_side bs = side(p);
                if (f1.coplanar.test(pid) || bs == CGAL::ON_BOUNDARY) {
                    snprintf(why, why_size,
                             "a part of '%s' touches '%s' away from the intersection", a_what,
                             b_what);
                    return false;
                }
                if (bs == CGAL::ON_BOUNDED_SIDE)
                    f1.inside.set(pid);
                return true;
            }))
            return SR_OK;
    }
    /* N inside b, and N on b's surface facing as b does (kept once, from N); b inside a */
    boost::dynamic_bitset<> use1 = f1.inside - f1.coplanar;
    if (f1.coplanar.any())
        use1 |= f1.coplanar & f1.coplanar_union;
    boost::dynamic_bitset<> use2 = f2.inside - f2.coplanar;
    sr_mesh res;
    if (join_patches(sm, mb, flags, use1, use2, node_vertex, &res) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "intersection of '%s' and '%s': out of memory", a_what,
                          b_what);
    sr_mesh_edges e;
    if (res.tri_count == 0 || sr_mesh_edge_stats(&res, &e) != SR_OK || e.boundary_edges ||
        e.nonmanifold_edges || e.misoriented_edges || e.nonmanifold_vertices) {
        sr_mesh_release(&res);
        snprintf(why, why_size, "the clipped neighbourhood is not a closed manifold");
        return SR_OK;
    }
    *out = res;
    *done = true;
    return SR_OK;
}

} // namespace

} // namespace sr_bool

using namespace sr_bool;

/* The local intersection of a mapped by xf (NULL: as it is) with b, or the whole-mesh
 * one of the mapped copy when the local one cannot be trusted. */
static sr_status intersection_local(const sr_mesh *a, const char *a_what, const double *xf,
                                    const sr_mesh *b, const char *b_what, double margin_mm,
                                    sr_mesh *out, sr_local_clip_info *info, sr_err *err)
{
    sr_local_clip_info local_info;
    if (!info)
        info = &local_info;
    memset(info, 0, sizeof *info);
    if (!a_what)
        a_what = "first mesh";
    if (!b_what)
        b_what = "second mesh";
    if (!(margin_mm >= 0) || !std::isfinite(margin_mm))
        return sr_err_set(err, SR_E_RANGE, "bad clip margin %g mm: expected 0 or more", margin_mm);
    try {
        bool done = false;
        size_t n = 0;
        sr_status st = clip_local(a, a_what, xf, b, b_what, margin_mm, out, &done, info->fallback,
                                  sizeof info->fallback, &n, err);
        info->neighbourhood_tris = n;
        if (st != SR_OK || done) {
            info->local = done ? 1 : 0;
            return st;
        }
    } catch (...) {
        snprintf(info->fallback, sizeof info->fallback,
                 "the intersection of the neighbourhood failed");
    }
    if (!xf)
        return boolean_entry(SR_BOOLEAN_INTERSECTION, a, a_what, b, b_what, out, err);
    sr_mesh img;
    sr_mesh_init(&img);
    if (sr_mesh_copy(&img, a) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory mapping '%s'", a_what);
    sr_mesh_map(&img, xf);
    sr_status st = boolean_entry(SR_BOOLEAN_INTERSECTION, &img, a_what, b, b_what, out, err);
    sr_mesh_release(&img);
    return st;
}

extern "C" sr_status sr_boolean_intersection_local(const sr_mesh *a, const char *a_what,
                                                   const sr_mesh *b, const char *b_what,
                                                   double margin_mm, sr_mesh *out,
                                                   sr_local_clip_info *info, sr_err *err)
{
    return intersection_local(a, a_what, nullptr, b, b_what, margin_mm, out, info, err);
}

extern "C" sr_status sr_boolean_intersection_local_mapped(const sr_mesh *a, const char *a_what,
                                                          const double *a_xf, const sr_mesh *b,
                                                          const char *b_what, double margin_mm,
                                                          sr_mesh *out, sr_local_clip_info *info,
                                                          sr_err *err)
{
    if (!a_xf || sr_xform_det(a_xf) == 0 || !std::isfinite(sr_xform_det(a_xf)))
        return sr_err_set(err, SR_E_RANGE, "the map of '%s' is singular",
                          a_what ? a_what : "first mesh");
    return intersection_local(a, a_what, a_xf, b, b_what, margin_mm, out, info, err);
}
