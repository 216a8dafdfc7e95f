/*
 * mend_cgal.cpp: local mending of a surface that crosses itself (see mend.h), on a
 * CGAL Surface_mesh built straight from the sr_mesh arrays (vertex i is Vertex_index i;
 * no vertex is ever added, so indices map back one to one). Crossings are found by PMP
 * self_intersections on the triangles near the box, taken out by Euler::remove_face
 * (attempt r takes r rings of neighbours with them: the smallest holes first), and
 * every hole that leaves is filled by PMP triangulate_hole
 * (minimum-weight triangulation of the rim's vertices). The mesh's own border (a
 * neighbourhood's rim) is recorded first and must stay as it is.
 *
 * Kept out of boolean_cgal.cpp: the hole-filling headers are heavy to compile, and the
 * two translation units build in parallel. CGAL_ALWAYS_ROUND_TO_NEAREST for Valgrind as
 * there (see its comment). Every extern "C" entry catches all exceptions.
 */
#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* before any CGAL header; see boolean_cgal.cpp */

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iterator>
#include <new>
#include <utility>
#include <vector>

extern "C" {
#include "bridge/mend.h"
#include "mesh.h"
#include "status.h"
}

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex_index;
typedef Mesh::Face_index Face_index;
typedef Mesh::Halfedge_index Halfedge_index;

const int max_rings = 4;  /* attempts take 0..max_rings rings around the crossings */
const int max_passes = 3; /* cut-and-fill passes per attempt */

bool build(const sr_mesh *m, Mesh &sm)
{
    sm.reserve(static_cast<Mesh::size_type>(m->vertex_count),
               static_cast<Mesh::size_type>(m->tri_count * 3 / 2 + 3),
               static_cast<Mesh::size_type>(m->tri_count));
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        sm.add_vertex(Point(p[0], p[1], p[2]));
    }
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *f = m->tri + 3 * t;
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
            sm.add_face(Vertex_index(f[0]), Vertex_index(f[1]), Vertex_index(f[2])) ==
                Mesh::null_face())
            return false;
    }
    return true;
}

std::vector<Face_index> near_faces(const Mesh &sm, const double *box)
{
    std::vector<Face_index> near;
    for (Face_index f : sm.faces()) {
        if (box) {
            CGAL::Bbox_3 b = PMP::face_bbox(f, sm);
            if (!(b.xmax() >= box[0] && b.xmin() <= box[3] && b.ymax() >= box[1] &&
                  b.ymin() <= box[4] && b.zmax() >= box[2] && b.zmin() <= box[5]))
                continue;
        }
        near.push_back(f);
    }
    return near;
}

/* One pass: the faces of `pairs` and `rings` rings of faces around them (sharing a
 * vertex) out, holes filled. False (why set) when the faces taken out reach the border
 * or a hole stays open. */
bool cut_and_fill(Mesh &sm, const std::vector<std::pair<Face_index, Face_index>> &pairs,
                  int rings, const std::vector<uint8_t> &was_border, sr_mend_report *rep,
                  const char **why)
{
    std::vector<uint8_t> mark(sm.num_faces(), 0); /* num_*: capacity, removed included */
    std::vector<Face_index> cut;
    auto take = [&](Face_index f) {
        if (f == Mesh::null_face() || f.idx() >= mark.size() || mark[f.idx()])
            return;
        mark[f.idx()] = 1;
        cut.push_back(f);
    };
    for (const auto &p : pairs) {
        take(p.first);
        take(p.second);
    }
    size_t begin = 0;
    for (int k = 0; k < rings; k++) {
        size_t end = cut.size();
        for (size_t i = begin; i < end; i++)
            for (Vertex_index v : sm.vertices_around_face(sm.halfedge(cut[i])))
                if (!sm.is_border(v, false))
                    for (Face_index g : sm.faces_around_target(sm.halfedge(v)))
                        take(g);
        begin = end;
    }
    for (Face_index f : cut)
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            if (sm.is_border(v, false)) {
                *why = "the crossings reach the mesh's border";
                rep->reached_border = 1;
                return false;
            }
    for (Face_index f : cut)
        CGAL::Euler::remove_face(sm.halfedge(f), sm);
    rep->removed_tris += cut.size();

    /* the holes: border halfedges that were not the mesh's own border */
    auto is_new_border = [&](Halfedge_index h) {
        return sm.is_border(h) && !(h.idx() < was_border.size() && was_border[h.idx()]);
    };
    std::vector<Halfedge_index> starts;
    std::vector<uint8_t> seen(sm.num_halfedges(), 0);
    for (Halfedge_index h : sm.halfedges()) {
        if (!is_new_border(h) || seen[h.idx()])
            continue;
        starts.push_back(h);
        Halfedge_index g = h;
        do {
            seen[g.idx()] = 1;
            g = sm.next(g);
        } while (g != h);
    }
    for (Halfedge_index h : starts) {
        std::vector<Face_index> added;
        PMP::triangulate_hole(sm, h, std::back_inserter(added));
        rep->filled_tris += added.size();
    }
    for (Halfedge_index h : sm.halfedges())
        if (is_new_border(h)) {
            *why = "a hole left by the crossing triangles could not be filled";
            return false;
        }
    return true;
}

typedef std::vector<std::pair<Face_index, Face_index>> Pairs;

Pairs crossings_near(const Mesh &sm, const double *box)
{
    std::vector<Face_index> near = near_faces(sm, box);
    Pairs pairs;
    PMP::self_intersections(near, sm, std::back_inserter(pairs));
    return pairs;
}

/* One attempt with `rings` on sm (mesh as built, its crossings `pairs`): up to
 * max_passes of cut / fill / look again. True with sm mended when no crossing is left;
 * false with why set. */
bool attempt(Mesh &sm, const double *box, int rings, Pairs pairs, sr_mend_report *rep,
             const char **why)
{
    std::vector<uint8_t> was_border(sm.num_halfedges(), 0);
    for (Halfedge_index h : sm.halfedges())
        if (sm.is_border(h))
            was_border[h.idx()] = 1;
    rep->removed_tris = rep->filled_tris = 0;
    for (int pass = 0; !pairs.empty(); pass++) {
        if (pass == max_passes) {
            *why = "crossings are left after the holes were filled";
            return false;
        }
        if (!cut_and_fill(sm, pairs, rings, was_border, rep, why))
            return false;
        pairs = crossings_near(sm, box);
    }
    return true;
}

sr_status mend(sr_mesh *mesh, const double *box, sr_mend_report *rep, sr_err *err)
{
    sr_mesh_report vr;
    sr_status st = sr_mesh_validate(mesh, "mesh to mend", &vr, err);
    if (st != SR_OK)
        return st;
    Mesh sm;
    if (!build(mesh, sm))
        return sr_err_set(err, SR_E_INVALID,
                          "mesh to mend is not an oriented manifold (a triangle repeats an "
                          "edge or a vertex)");
    /* the mesh is rebuilt the same way for every attempt: same face indices, same pairs */
    const Pairs first = crossings_near(sm, box);
    rep->crossing_pairs = first.size();
    if (first.empty())
        return SR_OK;
    /* the smallest holes first: attempts with 0, 1, ... rings around the crossings */
    const char *why = "";
    bool done = false;
    for (int rings = 0; rings <= max_rings && !done; rings++) {
        rep->rounds = rings + 1;
        if (rings > 0) {
            sm = Mesh();
            build(mesh, sm);
        }
        done = attempt(sm, box, rings, first, rep, &why);
    }
    if (!done)
        return sr_err_set(err, SR_E_INVALID, "cannot mend the crossings (%zu pairs): %s",
                          rep->crossing_pairs, why);
    size_t nt = sm.number_of_faces();
    uint32_t *tri = static_cast<uint32_t *>(malloc((nt ? nt : 1) * 3 * sizeof(uint32_t)));
    if (!tri)
        return sr_err_set(err, SR_E_NOMEM, "out of memory mending a mesh");
    size_t w = 0;
    for (Face_index f : sm.faces())
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            tri[w++] = static_cast<uint32_t>(v.idx());
    free(mesh->tri);
    mesh->tri = tri;
    mesh->tri_count = nt;
    return SR_OK;
}

} // namespace

extern "C" {

sr_status sr_mesh_mend_crossings(sr_mesh *mesh, const double *box, sr_mend_report *report,
                                 sr_err *err)
{
    sr_mend_report local;
    if (!report)
        report = &local;
    memset(report, 0, sizeof *report);
    try {
        return mend(mesh, box, report, err);
    } catch (const std::bad_alloc &) {
        return sr_err_set(err, SR_E_NOMEM, "out of memory mending a mesh");
    } catch (const std::exception &e) {
        return sr_err_set(err, SR_E_INTERNAL, "mending a mesh: %s", e.what());
    } catch (...) {
        return sr_err_set(err, SR_E_INTERNAL, "mending a mesh: unknown exception");
    }
}

} // extern "C"
