/*
 * boolean_cgal.cpp: robust 3D booleans (union, intersection, difference), the
 * self-intersection test and surface deviation, behind the pure-C header boolean.h.
 *
 * Booleans use CGAL 5.5 Polygon Mesh Processing corefinement
 * (corefine_and_compute_union / _intersection / _difference) on a
 * Surface_mesh<Epick::Point_3>: exact predicates, intersection points constructed
 * exactly and rounded to double once. The Surface_mesh is built straight from the
 * sr_mesh arrays (CGAL's file readers are several times slower). Each input is checked
 * first, in the order a user can act on: validate (empty, NaN, bad index), degenerate
 * triangles, closed, manifold, consistently oriented, not inside out, buildable as a
 * halfedge mesh, not self-intersecting; every refusal is SR_E_INVALID naming the input.
 * The result is checked after (CGAL::is_closed, then sr_mesh_is_closed on the arrays).
 *
 * The local union (sr_boolean_union_local, see the comment above union_local) runs the
 * same corefinement on a scan's neighbourhood of a patch only, takes CGAL's own
 * classification of the corefined patches (its output builder's "classify patches"
 * mode, through a visitor), assembles the union of the neighbourhood from it and
 * splices it into the untouched rest of the scan; it falls back to the whole-mesh union
 * whenever the result would not close up.
 *
 * Deviation samples every vertex and every triangle centroid of a, and asks an AABB
 * tree over b's triangles for the squared distance to the nearest point (CGAL builds a
 * KD-tree of b's reference points on the first query to start each search close). The
 * tree holds b as a triangle soup rather than a face graph, so b may be open,
 * non-manifold or inconsistently oriented (a raw scan); zero-area triangles of b are
 * left out (they hold no point that their neighbours' edges do not).
 *
 * CGAL_ALWAYS_ROUND_TO_NEAREST: CGAL's interval filters normally switch the FPU to
 * round-upward; Valgrind ignores rounding-mode changes, so under Valgrind the filtered
 * predicates lie and corefinement writes out of bounds (seen: invalid writes, a failed
 * union). With this macro the intervals are widened by nextafter in round-to-nearest
 * instead: correct everywhere, 5-20 % slower (measured on the
 * shaft union and on 1M-triangle meshes).
 *
 * This translation unit is slow to compile (about 40 s, 1.7 GB at -O2): keep the
 * includes to the CGAL headers below. CGAL's PMP package is GPL-3.0-or-later.
 * Every extern "C" entry catches all exceptions: std::bad_alloc -> SR_E_NOMEM,
 * anything else -> SR_E_INTERNAL with what() in the message.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* before any CGAL header; see above */

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

extern "C" {
#include "bridge/boolean.h"
#include "bridge/mend.h"
#include "mesh/mesh.h"
#include "base/status.h"
}

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef K::Triangle_3 Triangle;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex_index;

typedef std::vector<Triangle>::const_iterator Triangle_iterator;
typedef CGAL::AABB_triangle_primitive<K, Triangle_iterator> Primitive;
typedef CGAL::AABB_traits<K, Primitive> Aabb_traits;
typedef CGAL::AABB_tree<Aabb_traits> Aabb_tree;

const char *op_name(sr_boolean_op op)
{
    switch (op) {
    case SR_BOOLEAN_UNION: return "union";
    case SR_BOOLEAN_INTERSECTION: return "intersection";
    case SR_BOOLEAN_DIFFERENCE: return "difference";
    }
    return "boolean";
}

/* Converts the exception in flight into a status; call only inside a catch block. */
sr_status status_from_exception(sr_err *err, const char *doing)
{
    try {
        throw;
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "%s: out of memory", doing);
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "%s: %s", doing, e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "%s: unknown exception", doing);
    }
}

/* Copies the arrays into a Surface_mesh. False when Surface_mesh refuses a triangle
 * (a non-manifold vertex or edge, or a flipped neighbour); *bad_tri names it. */
bool build_surface_mesh(const sr_mesh *m, Mesh &sm, size_t *bad_tri)
{
    sm.clear();
    sm.reserve(static_cast<Mesh::size_type>(m->vertex_count),
               static_cast<Mesh::size_type>(m->tri_count * 3 / 2),
               static_cast<Mesh::size_type>(m->tri_count));
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        sm.add_vertex(Point(p[0], p[1], p[2]));
    }
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        if (sm.add_face(Vertex_index(f[0]), Vertex_index(f[1]), Vertex_index(f[2])) ==
            Mesh::null_face()) {
            *bad_tri = t;
            return false;
        }
    }
    return true;
}

/* Every check a boolean operand must pass; on success sm holds the mesh. */
/* True when some triangle of sm whose bounding box meets `box` (min xyz, max xyz)
 * crosses another: corefinement only needs the surface to be free of crossings where
 * the other operand can cut it, so a scan with a noise fold elsewhere still works. */
bool self_intersects_near(const Mesh &sm, const double box[6])
{
    std::vector<Mesh::Face_index> near;
    for (Mesh::Face_index f : sm.faces()) {
        CGAL::Bbox_3 b = PMP::face_bbox(f, sm);
        if (b.xmax() >= box[0] && b.xmin() <= box[3] && b.ymax() >= box[1] &&
            b.ymin() <= box[4] && b.zmax() >= box[2] && b.zmin() <= box[5])
            near.push_back(f);
    }
    return PMP::does_self_intersect(near, sm);
}

/* The checks of an operand on its arrays alone, in the order a user can act on:
 * validate, zero-area triangles, closed, manifold edges, oriented, not inside out.
 * *edges gets the edge statistics (with the vertex fans). */
sr_status check_arrays(const sr_mesh *m, const char *what, sr_mesh_edges *edges, sr_err *err)
{
    sr_mesh_report report;
    sr_status st = sr_mesh_validate(m, what, &report, err);
    if (st != SR_OK)
        return st;
    if (report.degenerate_tris) {
        /* confirmed by the exact predicate corefinement uses: a sliver whose cross
         * product only rounds to zero in doubles is fine */
        size_t degenerate = 0;
        for (size_t t = 0; t < m->tri_count; t++) {
            const uint32_t *f = m->tri + 3 * t;
            const double *p = m->xyz + 3 * f[0], *q = m->xyz + 3 * f[1],
                         *r = m->xyz + 3 * f[2];
            degenerate += CGAL::collinear(Point(p[0], p[1], p[2]), Point(q[0], q[1], q[2]),
                                          Point(r[0], r[1], r[2]))
                              ? 1
                              : 0;
        }
        if (degenerate)
            return sr_err_set(err, SR_E_INVALID,
                              "'%s' has %zu degenerate (zero-area) triangles", what,
                              degenerate);
    }
    st = sr_mesh_edge_stats(m, edges);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory counting the edges of '%s'", what);
    if (edges->boundary_edges)
        return sr_err_set(err, SR_E_INVALID, "'%s' is not closed (%zu boundary edges)",
                          what, edges->boundary_edges);
    if (edges->nonmanifold_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is not manifold (%zu edges shared by three or more "
                          "triangles)",
                          what, edges->nonmanifold_edges);
    if (edges->misoriented_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is not consistently oriented (%zu edges traversed the "
                          "same way by both triangles)",
                          what, edges->misoriented_edges);
    double volume = sr_mesh_volume(m);
    if (!(volume > 0))
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' is inside out (enclosed volume %g mm^3)", what, volume);
    return SR_OK;
}

sr_status check_operand(const sr_mesh *m, const char *what, const double *other_box, Mesh &sm,
                        sr_err *err)
{
    sr_mesh_edges edges;
    sr_status st = check_arrays(m, what, &edges, err);
    if (st != SR_OK)
        return st;
    size_t bad_tri = 0;
    if (!build_surface_mesh(m, sm, &bad_tri))
        return sr_err_set(err, SR_E_INVALID,
                          "'%s' has a non-manifold vertex (at triangle %zu)", what,
                          bad_tri);
    if (other_box ? self_intersects_near(sm, other_box) : PMP::does_self_intersect(sm))
        return sr_err_set(err, SR_E_INVALID, "'%s' intersects itself%s", what,
                          other_box ? " where the other mesh is" : "");
    return SR_OK;
}

/* Copies a triangulated Surface_mesh into *out: only vertices used by a face, numbered
 * compactly in index order; any face of more than three sides fanned into triangles.
 * No faces: *out is an empty mesh. */
sr_status mesh_to_arrays(Mesh &sm, sr_mesh *out, sr_err *err, const char *doing)
{
    if (sm.has_garbage())
        sm.collect_garbage();
    const uint32_t unused = UINT32_MAX;
    std::vector<uint32_t> index(sm.number_of_vertices(), unused);
    size_t nt = 0;
    for (Mesh::Face_index f : sm.faces()) {
        nt += sm.degree(f) - 2;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            index[v.idx()] = 0;
    }
    size_t nv = 0;
    for (uint32_t &i : index)
        if (i != unused)
            i = static_cast<uint32_t>(nv++);
    sr_mesh res;
    sr_mesh_init(&res);
    if (nt == 0) { /* e.g. the intersection of disjoint meshes */
        *out = res;
        return SR_OK;
    }
    if (nv > SR_MESH_MAX_COUNT || nt > SR_MESH_MAX_COUNT)
        return sr_err_set(err, SR_E_RANGE, "%s: result too large (%zu triangles)", doing,
                          nt);
    if (sr_mesh_alloc(&res, nv, nt) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "%s: out of memory for %zu triangles", doing,
                          nt);
    for (Vertex_index v : sm.vertices()) {
        uint32_t i = index[v.idx()];
        if (i == unused)
            continue;
        const Point &p = sm.point(v);
        double *q = res.xyz + 3 * static_cast<size_t>(i);
        q[0] = p.x();
        q[1] = p.y();
        q[2] = p.z();
    }
    uint32_t *t = res.tri;
    for (Mesh::Face_index f : sm.faces()) {
        Mesh::Halfedge_index h0 = sm.halfedge(f);
        uint32_t first = index[sm.source(h0).idx()];
        Mesh::Halfedge_index h = sm.next(h0);
        while (sm.target(h) != sm.source(h0)) {
            t[0] = first;
            t[1] = index[sm.source(h).idx()];
            t[2] = index[sm.target(h).idx()];
            t += 3;
            h = sm.next(h);
        }
    }
    *out = res;
    return SR_OK;
}

sr_status boolean_compute(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                          const sr_mesh *b, const char *b_what, sr_mesh *out,
                          sr_err *err)
{
    const char *name = op_name(op);
    if (op != SR_BOOLEAN_UNION && op != SR_BOOLEAN_INTERSECTION &&
        op != SR_BOOLEAN_DIFFERENCE)
        return sr_err_set(err, SR_E_RANGE, "unknown boolean operation %d",
                          static_cast<int>(op));
    if (!a_what)
        a_what = "first mesh";
    if (!b_what)
        b_what = "second mesh";

    Mesh ma, mb;
    double box_a[6], box_b[6];
    sr_mesh_bbox(a, box_a, box_a + 3);
    sr_mesh_bbox(b, box_b, box_b + 3);
    sr_status st = check_operand(a, a_what, box_b, ma, err);
    if (st != SR_OK)
        return st;
    st = check_operand(b, b_what, box_a, mb, err);
    if (st != SR_OK)
        return st;

    /* The result goes into ma in place (both inputs are corefined anyway). */
    bool ok = false;
    switch (op) {
    case SR_BOOLEAN_UNION: ok = PMP::corefine_and_compute_union(ma, mb, ma); break;
    case SR_BOOLEAN_INTERSECTION:
        ok = PMP::corefine_and_compute_intersection(ma, mb, ma);
        break;
    case SR_BOOLEAN_DIFFERENCE: ok = PMP::corefine_and_compute_difference(ma, mb, ma); break;
    }
    if (!ok)
        return sr_err_set(err, SR_E_INVALID,
                          "cannot compute the %s of '%s' and '%s': the result would not "
                          "be a manifold surface (the meshes touch along an edge or at a "
                          "point)",
                          name, a_what, b_what);
    if (!CGAL::is_closed(ma))
        return sr_err_set(err, SR_E_INTERNAL,
                          "the %s of '%s' and '%s' is not closed", name, a_what, b_what);

    char doing[160];
    snprintf(doing, sizeof doing, "%s of '%s' and '%s'", name, a_what, b_what);
    sr_mesh res;
    st = mesh_to_arrays(ma, &res, err, doing);
    if (st != SR_OK)
        return st;
    if (res.tri_count && !sr_mesh_is_closed(&res)) {
        sr_mesh_release(&res);
        return sr_err_set(err, SR_E_INTERNAL, "the %s is not closed once converted",
                          doing);
    }
    if (out == a || out == b)
        sr_mesh_release(out);
    *out = res;
    return SR_OK;
}

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

const uint32_t no_vertex = UINT32_MAX;

/* Key of the directed edge x -> y. */
uint64_t he_key(uint32_t x, uint32_t y)
{
    return static_cast<uint64_t>(x) << 32 | y;
}

/* Vertex v of m in the union's frame: mapped by xf (3x4), or as it is (xf NULL). */
void frame_point(const sr_mesh *m, size_t v, const double *xf, double out[3])
{
    const double *p = m->xyz + 3 * v;
    if (!xf) {
        out[0] = p[0];
        out[1] = p[1];
        out[2] = p[2];
        return;
    }
    sr_xform_apply(xf, p, out);
}

bool tri_box_meets(const sr_mesh *m, size_t t, const double *xf, const double box[6])
{
    const uint32_t *f = m->tri + 3 * t;
    double q[3][3];
    for (int j = 0; j < 3; j++)
        frame_point(m, f[j], xf, q[j]);
    for (int k = 0; k < 3; k++) {
        double lo = q[0][k], hi = lo;
        for (int j = 1; j < 3; j++) {
            lo = q[j][k] < lo ? q[j][k] : lo;
            hi = q[j][k] > hi ? q[j][k] : hi;
        }
        if (hi < box[k] || lo > box[3 + k])
            return false;
    }
    return true;
}

/* The directed edges of the triangles flagged in `in`, sorted. */
std::vector<uint64_t> flagged_halfedges(const sr_mesh *m, const std::vector<uint8_t> &in)
{
    std::vector<uint64_t> he;
    for (size_t t = 0; t < m->tri_count; t++)
        if (in[t])
            for (int k = 0; k < 3; k++)
                he.push_back(he_key(m->tri[3 * t + k], m->tri[3 * t + (k + 1) % 3]));
    std::sort(he.begin(), he.end());
    return he;
}

bool has_key(const std::vector<uint64_t> &sorted, uint64_t key)
{
    return std::binary_search(sorted.begin(), sorted.end(), key);
}

/* Selects N (see above). False when the fans cannot be mended in a few rounds. */
bool select_neighbourhood(const sr_mesh *a, const double *xf, const double box[6],
                          std::vector<uint8_t> &in, size_t *count)
{
    in.assign(a->tri_count, 0);
    size_t n = 0;
    for (size_t t = 0; t < a->tri_count; t++)
        if (tri_box_meets(a, t, xf, box)) {
            in[t] = 1;
            n++;
        }
    /* Around a vertex v, the triangle after corner (v, x, y) holds the edge v -> y (a's
     * edges are manifold and oriented). So every run of N's triangles around v ends at
     * exactly one corner of N whose v -> y is in no triangle of N, and a vertex with two
     * such corners has N's triangles in several fans: take all of its triangles. */
    std::vector<uint32_t> bad;
    for (int round = 0; round < 8; round++) {
        std::vector<uint64_t> he = flagged_halfedges(a, in);
        std::vector<uint32_t> starts;
        for (size_t t = 0; t < a->tri_count; t++) {
            if (!in[t])
                continue;
            const uint32_t *f = a->tri + 3 * t;
            for (int k = 0; k < 3; k++) {
                uint32_t v = f[k], y = f[(k + 2) % 3];
                if (!has_key(he, he_key(v, y)))
                    starts.push_back(v);
            }
        }
        std::sort(starts.begin(), starts.end());
        bad.clear();
        for (size_t i = 0; i + 1 < starts.size(); i++)
            if (starts[i] == starts[i + 1] && (bad.empty() || bad.back() != starts[i]))
                bad.push_back(starts[i]);
        if (bad.empty()) {
            *count = n;
            return true;
        }
        for (size_t t = 0; t < a->tri_count; t++) {
            if (in[t])
                continue;
            const uint32_t *f = a->tri + 3 * t;
            for (int k = 0; k < 3; k++)
                if (std::binary_search(bad.begin(), bad.end(), f[k])) {
                    in[t] = 1;
                    n++;
                    break;
                }
        }
    }
    return false;
}

/* Whether p lies inside the closed mesh a (mapped by xf): parity of a's triangles
 * crossed by each of three rays in unrelated directions, the majority deciding; 1
 * inside, 0 outside, -1 when a ray runs through an edge or a vertex of a (parity
 * undefined) in two of them. Linear in a: for the few pieces of a patch that no
 * triangle of the neighbourhood cuts. */
int inside_by_rays(const sr_mesh *a, const double *xf, const Point &p)
{
    static const double dirs[3][3] = {{0.5773502691896258, 0.5773502691896258 + 1e-3,
                                       0.5773502691896258 - 2e-3},
                                      {-0.3120309, 0.8224617, -0.4755931},
                                      {0.7003127, -0.2101003, 0.6822417}};
    int in = 0, out = 0;
    for (int r = 0; r < 3; r++) {
        K::Ray_3 ray(p, K::Vector_3(dirs[r][0], dirs[r][1], dirs[r][2]));
        size_t hits = 0;
        bool clean = true;
        for (size_t t = 0; t < a->tri_count && clean; t++) {
            double q[3][3];
            for (int k = 0; k < 3; k++)
                frame_point(a, a->tri[3 * t + k], xf, q[k]);
            Triangle tri(Point(q[0][0], q[0][1], q[0][2]), Point(q[1][0], q[1][1], q[1][2]),
                         Point(q[2][0], q[2][1], q[2][2]));
            if (tri.is_degenerate() || !CGAL::do_intersect(ray, tri))
                continue;
            /* through an edge or a vertex: the ray meets the triangle's boundary */
            for (int k = 0; k < 3 && clean; k++) {
                K::Segment_3 e(tri.vertex(k), tri.vertex((k + 1) % 3));
                if (CGAL::do_intersect(ray, e))
                    clean = false;
            }
            hits++;
        }
        if (!clean)
            continue;
        if (hits & 1)
            in++;
        else
            out++;
    }
    if (in >= 2)
        return 1;
    if (out >= 2)
        return 0;
    return -1;
}

/* Patch flags of one corefined operand, as CGAL's output builder works them out. */
struct Patch_flags {
    std::vector<std::size_t> patch;          /* per face index: its patch */
    boost::dynamic_bitset<> inside;          /* patch inside the other operand */
    boost::dynamic_bitset<> coplanar;        /* patch on the other operand's surface */
    boost::dynamic_bitset<> coplanar_union;  /* ... kept once by a union */
    boost::dynamic_bitset<> not_set;         /* patch with no intersection edge */
    bool have = false;
};

/* A corefinement visitor that asks CGAL's output builder for its classification of the
 * patches (the parts of each surface between intersection edges) instead of a boolean's
 * output: the builder does this when no output is requested and the visitor declares
 * Has_extra_functions (CGAL 5.5, Face_graph_output_builder.h). It is the builder's own
 * exact, orientation-around-the-edge classification, also valid where an operand is
 * open (its boolean output path is not: CGAL 5.5's consistency check for open operands
 * rejects every patch it finds inside). */
struct Classify_visitor : public PMP::Corefinement::Default_visitor<Mesh> {
    typedef int Has_extra_functions;
    Patch_flags *flags; /* [0] first operand, [1] second */
    const Mesh *first;
    std::vector<uint32_t> *node_vertex; /* [0], [1]: per intersection node, the
                                         * operand's vertex at it (no_vertex if none) */

    void record(std::size_t node, Vertex_index v, const Mesh &tm)
    {
        std::vector<uint32_t> &m = node_vertex[&tm == first ? 0 : 1];
        if (m.size() <= node)
            m.resize(node + 1, no_vertex);
        m[node] = static_cast<uint32_t>(v.idx());
    }

    /* a vertex made for a node (an edge or a face of this operand was cut there) */
    void new_vertex_added(std::size_t node, Vertex_index v, const Mesh &tm)
    {
        record(node, v, tm);
    }

    /* an operand's own vertex at a node: an end of the cutting edge h1, or the vertex
     * of the other operand the edge passes through */
    void intersection_point_detected(std::size_t node, int sdim, Mesh::Halfedge_index h1,
                                     Mesh::Halfedge_index h2, const Mesh &tm1,
                                     const Mesh &tm2, bool is_target_coplanar,
                                     bool is_source_coplanar)
    {
        if (is_target_coplanar)
            record(node, tm1.target(h1), tm1);
        if (is_source_coplanar)
            record(node, tm1.source(h1), tm1);
        if (sdim == PMP::Corefinement::ON_VERTEX)
            record(node, tm2.target(h2), tm2);
    }

    template <class Fim>
    void export_flags(Fim fim, const std::vector<std::size_t> &ids,
                      const boost::dynamic_bitset<> &inside,
                      const boost::dynamic_bitset<> &coplanar,
                      const boost::dynamic_bitset<> &coplanar_union,
                      const boost::dynamic_bitset<> &not_set, Mesh &tm)
    {
        Patch_flags &f = flags[&tm == first ? 0 : 1];
        f.patch.assign(tm.num_faces(), 0);
        for (Mesh::Face_index fd : tm.faces())
            f.patch[fd.idx()] = ids[get(fim, fd)];
        f.inside = inside;
        f.coplanar = coplanar;
        f.coplanar_union = coplanar_union;
        f.not_set = not_set;
        f.have = true;
    }

    template <class H>
    void register_halfedge_pair(H, H, bool, bool, bool, bool, bool = false, bool = false,
                                bool = false, bool = false)
    {
    }
};

/* The local result as arrays: vertex ids below base are a's vertices, the others index
 * `fresh` (new points) as id - base. */
struct Local_result {
    std::vector<uint32_t> tri;
    std::vector<double> fresh;
};

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

/* Hands each patch of tm with no intersection edge (f.not_set), once, to decide(pid,
 * point) with a point of it (its first face's centroid); decide marks the patch and
 * returns false to give up, which this returns. */
template <class Decide>
bool classify_free_patches(const Mesh &tm, const Patch_flags &f, Decide decide)
{
    boost::dynamic_bitset<> done(f.not_set.size());
    for (Mesh::Face_index fd : tm.faces()) {
        std::size_t pid = f.patch[fd.idx()];
        if (!f.not_set.test(pid) || done.test(pid))
            continue;
        done.set(pid);
        Mesh::Halfedge_index h = tm.halfedge(fd);
        if (!decide(pid, CGAL::centroid(tm.point(tm.source(h)), tm.point(tm.target(h)),
                                        tm.point(tm.target(tm.next(h))))))
            return false;
    }
    return true;
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

/* The neighbourhood as a halfedge mesh with property "v:orig" (a's vertex number), from
 * its arrays: only vertices some triangle uses. False when a triangle is refused. */
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
    double diag = std::sqrt((box_b[3] - box_b[0]) * (box_b[3] - box_b[0]) +
                            (box_b[4] - box_b[1]) * (box_b[4] - box_b[1]) +
                            (box_b[5] - box_b[2]) * (box_b[5] - box_b[2]));
    double grow = margin > 0 ? margin : 0.01 * diag;
    *grow_used = grow;
    double box[6];
    for (int k = 0; k < 3; k++) {
        box[k] = box_b[k] - grow;
        box[3 + k] = box_b[3 + k] + grow;
    }
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
    {
        std::vector<uint32_t> local(a->vertex_count, no_vertex);
        loc_tri.reserve(3 * n);
        for (size_t t = 0; t < a->tri_count; t++)
            if (in[t])
                for (int k = 0; k < 3; k++) {
                    uint32_t v = a->tri[3 * t + k];
                    if (local[v] == no_vertex) {
                        double p[3];
                        frame_point(a, v, xf, p);
                        local[v] = static_cast<uint32_t>(loc_orig.size());
                        loc_orig.push_back(v);
                        loc_xyz.insert(loc_xyz.end(), p, p + 3);
                    }
                    loc_tri.push_back(local[v]);
                }
    }
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
#ifdef __GLIBC__
    /* what the checks and the neighbourhood used (the edge statistics' lists alone are
     * 14 MB for a million triangles) goes back to the system first: glibc keeps freed
     * blocks of that size in its heap, and the result would come on top of them */
    malloc_trim(0);
#endif
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

sr_status boolean_entry(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                        const sr_mesh *b, const char *b_what, sr_mesh *out, sr_err *err)
{
    try {
        return boolean_compute(op, a, a_what, b, b_what, out, err);
    } catch (...) {
        return status_from_exception(err, op_name(op));
    }
}

sr_status repair(sr_mesh *m, sr_repair_report *rep, sr_err *err)
{
    *rep = sr_repair_report();
    sr_status st = sr_mesh_validate(m, "mesh to repair", nullptr, err);
    if (st != SR_OK)
        return st;
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

sr_status sr_boolean_compute(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                             const sr_mesh *b, const char *b_what, sr_mesh *out,
                             sr_err *err)
{
    return boolean_entry(op, a, a_what, b, b_what, out, err);
}

} // extern "C"

namespace {

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

sr_status sr_boolean_union(const sr_mesh *a, const sr_mesh *b, sr_mesh *out, sr_err *err)
{
    return boolean_entry(SR_BOOLEAN_UNION, a, NULL, b, NULL, out, err);
}

sr_status sr_boolean_intersection(const sr_mesh *a, const sr_mesh *b, sr_mesh *out,
                                  sr_err *err)
{
    return boolean_entry(SR_BOOLEAN_INTERSECTION, a, NULL, b, NULL, out, err);
}

sr_status sr_boolean_difference(const sr_mesh *a, const sr_mesh *b, sr_mesh *out,
                                sr_err *err)
{
    return boolean_entry(SR_BOOLEAN_DIFFERENCE, a, NULL, b, NULL, out, err);
}

sr_status sr_mesh_self_intersects(const sr_mesh *mesh, int *out, sr_err *err)
{
    try {
        sr_status st = sr_mesh_validate(mesh, "mesh", NULL, err);
        if (st != SR_OK)
            return st;
        Mesh sm;
        size_t bad_tri = 0;
        if (!build_surface_mesh(mesh, sm, &bad_tri))
            return sr_err_set(err, SR_E_INVALID,
                              "'mesh' is not an oriented manifold (triangle %zu shares an "
                              "edge or vertex it cannot)",
                              bad_tri);
        *out = PMP::does_self_intersect(sm) ? 1 : 0;
        return SR_OK;
    } catch (...) {
        return status_from_exception(err, "self-intersection test");
    }
}

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
