/*
 * union_local_cgal.cpp: the local union (sr_boolean_union_local and its _mending and
 * _split forms, boolean.h) runs the whole-mesh union's corefinement on a scan's
 * neighbourhood of a patch only (neighbourhood_cgal.cpp selects it), takes CGAL's own
 * classification of the corefined patches (its output builder's "classify patches"
 * mode, through a visitor), assembles the union of the neighbourhood from it and
 * splices it into the untouched rest of the scan (union_result_cgal.cpp does both); it
 * falls back to the whole-mesh union (boolean_cgal.cpp) whenever the result would not
 * close up.
 */
#include "bridge/boolean_cgal.hpp"
#include "bridge/classify_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/corefinement.h>

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

/* declared in classify_cgal.hpp */
void neighbourhood_arrays(const sr_mesh *a, const double *xf, const std::vector<uint8_t> &in,
                          size_t n, std::vector<double> &xyz, std::vector<uint32_t> &tri,
                          std::vector<uint32_t> &orig, bool turned)
{
    static const int in_order[3] = {0, 1, 2}, turned_order[3] = {0, 2, 1};
    const int *corner = turned ? turned_order : in_order;
    std::vector<uint32_t> local(a->vertex_count, no_vertex);
    tri.reserve(3 * n);
    for (size_t t = 0; t < a->tri_count; t++)
        if (in[t])
            for (int k = 0; k < 3; k++) {
                uint32_t v = a->tri[3 * t + corner[k]];
                if (local[v] == no_vertex) {
                    double p[3];
                    frame_point(a, v, xf, p);
                    local[v] = static_cast<uint32_t>(orig.size());
                    orig.push_back(v);
                    xyz.insert(xyz.end(), p, p + 3);
                }
                tri.push_back(local[v]);
            }
}

/* declared in classify_cgal.hpp */
bool build_neighbourhood(const sr_mesh &loc, const std::vector<uint32_t> &loc_orig, Mesh &sm)
{
    auto orig = sm.add_property_map<Vertex_index, uint32_t>("v:orig", no_vertex).first;
    std::vector<uint32_t> id(loc.vertex_count, no_vertex);
    for (size_t i = 0; i < 3 * loc.tri_count; i++) {
        uint32_t v = loc.tri[i];
        if (id[v] == no_vertex) {
            const double *p = loc.xyz + 3 * v;
            Vertex_index lv = sm.add_vertex(Point(p[0], p[1], p[2]));
            orig[lv] = loc_orig[v];
            id[v] = static_cast<uint32_t>(lv.idx());
        }
    }
    for (size_t t = 0; t < loc.tri_count; t++) {
        const uint32_t *f = loc.tri + 3 * t;
        if (sm.add_face(Vertex_index(id[f[0]]), Vertex_index(id[f[1]]),
                        Vertex_index(id[f[2]])) == Mesh::null_face())
            return false;
    }
    return true;
}

namespace
{

/* ---- the local union ----------------------------------------------------------------
 * a ∪ b for a large closed a (a scan) and a small closed b (a patch): only a's
 * neighbourhood of b goes through CGAL. N = a's triangles whose bounding box meets b's
 * box grown by the margin, plus, at a vertex where N's triangles would form more than one
 * fan, every triangle of that vertex (a halfedge mesh cannot hold such a vertex). Every
 * triangle of a that b can cut is in N, so no intersection lies on N's border.
 * corefine_and_compute_union runs on N (open) and b in place: CGAL's output builder
 * classifies the patches of an open operand by the orientation around the intersection
 * edges exactly as for a closed one, and the intersection-free patches of N against b
 * (closed) by a point-in-volume test; only b's intersection-free components would be
 * misjudged (kept as outside), so each component of b must meet N's surface. After it,
 * N's border (directed edges, in a's vertex numbers) must be what it was: then the
 * untouched triangles of a and the new N close up into one surface. Whenever a condition
 * fails the whole-mesh union runs instead (info->fallback says why). */

/* The local union proper. SR_OK with *done = false when a condition for it fails
 * (why in `why`): the caller runs the whole-mesh union. */
sr_status union_local(const sr_mesh *a, const char *a_what, const double *xf,
                      const sr_mesh *b, const char *b_what, double margin, bool mend,
                      sr_mesh *out, sr_mesh *b_minus_a, bool *done, char *why,
                      size_t why_size, size_t *n_tris, size_t *mended_tris,
                      double *grow_used, bool *mend_rim, sr_err *err)
{
    *done = false;
    /* a: every check of check_operand that needs no halfedge mesh, on all of a */
    sr_mesh_edges edges;
    sr_status st = check_arrays(a, a_what, &edges, err);
    if (st != SR_OK)
        return st;
    if (edges.nonmanifold_vertices)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' has a non-manifold vertex (%zu vertices whose triangles "
                          "form more than one fan)",
                          a_what, edges.nonmanifold_vertices);
    /* b: all of check_operand (it is small) */
    double box_a[6], box_b[6];
    for (size_t v = 0; v < a->vertex_count; v++) {
        double q[3];
        frame_point(a, v, xf, q);
        for (int k = 0; k < 3; k++) {
            box_a[k] = v == 0 || q[k] < box_a[k] ? q[k] : box_a[k];
            box_a[3 + k] = v == 0 || q[k] > box_a[3 + k] ? q[k] : box_a[3 + k];
        }
    }
    sr_mesh_bbox(b, box_b, box_b + 3);
    Mesh mb;
    st = check_operand(b, b_what, box_a, mb, err);
    if (st != SR_OK)
        return st;

    /* N and its halfedge mesh; orig = a's vertex number, no_vertex for new ones */
    double box[6];
    *grow_used = grown_box(box_b, margin, box);
    std::vector<uint8_t> in;
    size_t n = 0;
    if (!select_neighbourhood(a, xf, box, in, &n)) {
        snprintf(why, why_size, "the neighbourhood's fans could not be mended");
        return SR_OK;
    }
    *n_tris = n;
    /* N as arrays in b's frame (loc_orig: a's vertex number of each), then as a
     * halfedge mesh */
    sr_mesh loc = {nullptr, nullptr, 0, 0};
    std::vector<double> loc_xyz;
    std::vector<uint32_t> loc_tri, loc_orig;
    neighbourhood_arrays(a, xf, in, n, loc_xyz, loc_tri, loc_orig);
    loc.xyz = loc_xyz.data();
    loc.vertex_count = loc_orig.size();
    loc.tri = loc_tri.data();
    loc.tri_count = n;
    Mesh sm;
    if (!build_neighbourhood(loc, loc_orig, sm)) {
        snprintf(why, why_size, "the neighbourhood is not a halfedge mesh");
        return SR_OK;
    }
    if (self_intersects_near(sm, box_b)) {
        if (!mend)
            return sr_err_set(err, SR_E_INVALID,
                              "'%s' intersects itself where the other mesh is", a_what);
        /* mend N on a malloc'd copy of its triangles (the mender frees and replaces
         * the array it is given) */
        sr_mend_report mr;
        sr_err merr = {{0}};
        loc.tri = static_cast<uint32_t *>(malloc(loc_tri.size() * sizeof(uint32_t)));
        if (!loc.tri)
            return sr_err_set(err, SR_E_NOMEM, "union of '%s' and '%s': out of memory",
                              a_what, b_what);
        memcpy(loc.tri, loc_tri.data(), loc_tri.size() * sizeof(uint32_t));
        sr_status ms = sr_mesh_mend_crossings(&loc, box_b, &mr, &merr);
        std::vector<uint32_t> mended;
        if (ms == SR_OK)
            mended.assign(loc.tri, loc.tri + 3 * loc.tri_count);
        free(loc.tri);
        if (ms == SR_E_NOMEM)
            return sr_err_set(err, ms, "union of '%s' and '%s': out of memory", a_what,
                              b_what);
        if (ms != SR_OK) {
            *mend_rim = mr.reached_border != 0;
            return sr_err_set(err, SR_E_INVALID,
                              "'%s' intersects itself where the other mesh is, and %s",
                              a_what, merr.msg);
        }
        loc_tri.swap(mended);
        loc.tri = loc_tri.data();
        *mended_tris = mr.removed_tris;
        sm = Mesh();
        if (!build_neighbourhood(loc, loc_orig, sm)) {
            snprintf(why, why_size, "the mended neighbourhood is not a halfedge mesh");
            return SR_OK;
        }
    }
    Mesh::Property_map<Vertex_index, uint32_t> orig =
        sm.property_map<Vertex_index, uint32_t>("v:orig").first;
    /* N's border before: a's directed edges of N with no N triangle across */
    std::vector<uint64_t> border_before;
    for (Mesh::Halfedge_index h : sm.halfedges())
        if (sm.is_border(h)) {
            Mesh::Halfedge_index o = sm.opposite(h);
            border_before.push_back(he_key(orig[sm.source(o)], orig[sm.target(o)]));
        }
    std::sort(border_before.begin(), border_before.end());

    Patch_flags flags[2];
    std::vector<uint32_t> node_vertex[2];
    Classify_visitor vis;
    vis.flags = flags;
    vis.first = &sm;
    vis.node_vertex = node_vertex;
    const std::array<boost::optional<Mesh *>, 4> no_output = {{boost::none, boost::none,
                                                               boost::none, boost::none}};
    PMP::corefine_and_compute_boolean_operations(sm, mb, no_output,
                                                 CGAL::parameters::visitor(vis));
    if (!flags[0].have || !flags[1].have) { /* no intersection at all */
        snprintf(why, why_size, "'%s' meets no triangle of '%s'", b_what, a_what);
        return SR_OK;
    }
    Local_result res;
    double back[12];
    if (xf)
        sr_xform_rigid_inverse(back, xf);
    std::vector<uint32_t> diff;
    if (!assemble_local(a, a_what, b_what, xf, xf ? back : nullptr, sm, orig, mb, flags,
                        node_vertex, res, b_minus_a ? &diff : nullptr, why, why_size))
        return SR_OK;
    if (!local_result_fits(res, border_before, a->vertex_count)) {
        snprintf(why, why_size, "the united neighbourhood does not close up with the rest");
        return SR_OK;
    }
    size_t nt = a->tri_count - n + res.tri.size() / 3, nv = a->vertex_count + res.fresh.size() / 3;
    if (nt > SR_MESH_MAX_COUNT || nv > SR_MESH_MAX_COUNT)
        return sr_err_set(err, SR_E_RANGE, "union of '%s' and '%s': result too large "
                          "(%zu triangles)", a_what, b_what, nt);
    size_t tri_room = nt > a->tri_count ? nt : a->tri_count;

    /* the arrays: a's own (in place) or a copy, with room to grow; nothing of *out is
     * changed before every allocation has succeeded */
    sr_mesh dst;
    if (out == a) {
        double *xyz = static_cast<double *>(realloc(out->xyz, nv * 3 * sizeof(double)));
        if (!xyz)
            return sr_err_set(err, SR_E_NOMEM, "union of '%s' and '%s': out of memory",
                              a_what, b_what);
        out->xyz = xyz;
        uint32_t *tri = static_cast<uint32_t *>(realloc(out->tri, tri_room * 3 * sizeof(uint32_t)));
        if (!tri)
            return sr_err_set(err, SR_E_NOMEM, "union of '%s' and '%s': out of memory",
                              a_what, b_what);
        out->tri = tri;
        dst = *out;
    } else {
        if (sr_mesh_alloc(&dst, nv, tri_room) != SR_OK)
            return sr_err_set(err, SR_E_NOMEM, "union of '%s' and '%s': out of memory",
                              a_what, b_what);
        memcpy(dst.xyz, a->xyz, a->vertex_count * 3 * sizeof(double));
        memcpy(dst.tri, a->tri, a->tri_count * 3 * sizeof(uint32_t));
        dst.vertex_count = a->vertex_count;
        dst.tri_count = a->tri_count;
    }
    sr_mesh dm;
    sr_mesh_init(&dm);
    if (b_minus_a && diff_to_mesh(a, res, diff, &dm) != SR_OK) {
        if (out != a)
            sr_mesh_release(&dst);
        return sr_err_set(err, SR_E_NOMEM, "union of '%s' and '%s': out of memory", a_what,
                          b_what);
    }
    splice_local(&dst, in, res);
    if (out == b)
        sr_mesh_release(out);
    *out = dst;
    if (b_minus_a)
        *b_minus_a = dm;
    *done = true;
    return SR_OK;
}

sr_status union_local_entry(const sr_mesh *a, const char *a_what, const double *a_to_b,
                            const sr_mesh *b, const char *b_what, double margin_mm, bool mend,
                            sr_mesh *out, sr_mesh *b_minus_a, sr_local_union_info *info,
                            sr_err *err)
{
    sr_local_union_info local_info;
    if (!info)
        info = &local_info;
    memset(info, 0, sizeof *info);
    if (!a_what)
        a_what = "first mesh";
    if (!b_what)
        b_what = "second mesh";
    if (!(margin_mm >= 0) || !std::isfinite(margin_mm))
        return sr_err_set(err, SR_E_RANGE, "bad union margin %g mm: expected 0 or more",
                          margin_mm);
    try {
        bool done = false;
        size_t n = 0;
        size_t mended = 0;
        double grow = 0;
        bool rim = false;
        sr_status st = union_local(a, a_what, a_to_b, b, b_what, margin_mm, mend, out,
                                   b_minus_a, &done, info->fallback, sizeof info->fallback, &n, &mended, &grow,
                                   &rim, err);
        /* crossings reaching the neighbourhood's rim (a fold along an edge that runs out
         * of it, long triangles): a wider neighbourhood (x4), then all of a */
        for (int wider = 0; wider < 2 && st == SR_E_INVALID && rim; wider++) {
            rim = false;
            st = union_local(a, a_what, a_to_b, b, b_what, wider == 0 ? 4.0 * grow : 1e30,
                             mend, out, b_minus_a, &done, info->fallback, sizeof info->fallback, &n,
                             &mended, &grow, &rim, err);
        }
        info->neighbourhood_tris = n;
        info->mended_tris = mended;
        if (st != SR_OK || done) {
            info->local = done ? 1 : 0;
            return st;
        }
    } catch (...) {
        /* CGAL threw on the neighbourhood: the whole-mesh union decides */
        snprintf(info->fallback, sizeof info->fallback,
                 "the union of the neighbourhood failed");
    }
    /* the whole-mesh union (in b's frame, the result brought back to a's); a refusal
     * says why the local one was not used */
    sr_mesh moved, res, dif;
    sr_mesh_init(&dif);
    sr_status st;
    if (sr_mesh_copy(&moved, a) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "union of '%s' and '%s': out of memory", a_what,
                          b_what);
    if (a_to_b)
        sr_mesh_transform(&moved, a_to_b);
    st = boolean_entry(SR_BOOLEAN_UNION, &moved, a_what, b, b_what, &res, err);
    if (st == SR_OK && b_minus_a) {
        st = boolean_entry(SR_BOOLEAN_DIFFERENCE, b, b_what, &moved, a_what, &dif, err);
        if (st != SR_OK)
            sr_mesh_release(&res);
    }
    sr_mesh_release(&moved);
    if (st != SR_OK && st != SR_E_NOMEM && err && info->fallback[0]) {
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err->msg);
        sr_err_set(err, st, "%s (the whole-mesh union ran: %s)", msg, info->fallback);
    }
    if (st != SR_OK)
        return st;
    if (a_to_b) {
        double back[12];
        sr_xform_rigid_inverse(back, a_to_b);
        sr_mesh_transform(&res, back);
        sr_mesh_transform(&dif, back);
    }
    if (out == a || out == b)
        sr_mesh_release(out);
    *out = res;
    if (b_minus_a)
        *b_minus_a = dif;
    return SR_OK;
}

} // namespace

} // namespace sr_bool

using namespace sr_bool;

extern "C" {

sr_status sr_boolean_union_local(const sr_mesh *a, const char *a_what, const double *a_to_b,
                                 const sr_mesh *b, const char *b_what, double margin_mm,
                                 sr_mesh *out, sr_local_union_info *info, sr_err *err)
{
    return union_local_entry(a, a_what, a_to_b, b, b_what, margin_mm, false, out, nullptr,
                             info, err);
}

sr_status sr_boolean_union_local_mending(const sr_mesh *a, const char *a_what,
                                         const double *a_to_b, const sr_mesh *b,
                                         const char *b_what, double margin_mm, sr_mesh *out,
                                         sr_local_union_info *info, sr_err *err)
{
    return union_local_entry(a, a_what, a_to_b, b, b_what, margin_mm, true, out, nullptr,
                             info, err);
}

sr_status sr_boolean_union_local_split(const sr_mesh *a, const char *a_what,
                                       const double *a_to_b, const sr_mesh *b,
                                       const char *b_what, double margin_mm, sr_mesh *out,
                                       sr_mesh *b_minus_a, sr_local_union_info *info,
                                       sr_err *err)
{
    return union_local_entry(a, a_what, a_to_b, b, b_what, margin_mm, true, out, b_minus_a,
                             info, err);
}

} // extern "C"
