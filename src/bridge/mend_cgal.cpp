/*
 * mend_cgal.cpp: local mending of a surface that crosses itself (see mend.h), on a
 * CGAL Surface_mesh built straight from the sr_mesh arrays (vertex i is Vertex_index i;
 * no vertex is ever added, so indices map back one to one). Crossings are found by PMP
 * self_intersections on the triangles near the box and taken out (attempt r takes r
 * rings of neighbours with them: the smallest holes first). Each region taken out is
 * filled again from its own points: a constrained Delaunay triangulation (CGAL CDT_2)
 * of its rim and inner vertices seen along its mean normal, its rim and every edge of
 * it that crosses no other one there as constraints. The scan's points stay where the
 * scanner put them and the faces that did not fold come back as they were, so a fold
 * along a sharp edge keeps the edge. A region whose rim crosses itself seen that way
 * takes the faces around the crossing too; one that still cannot be seen one to one is
 * filled from its rim alone by PMP triangulate_hole (minimum-weight triangulation of
 * the rim's vertices, which cuts across a sharp edge: the keyed shaft's noisy scan lost
 * up to 2.9 mm of its dent's rim that way). Each ring count is tried twice: with the
 * later passes' fills checked against the faces around them (a fill that crosses them
 * takes them too, rather than the same crossing coming back pass after pass), and
 * without; the one with fewer holes filled from their rims wins. The mesh's own border
 * (a neighbourhood's rim) is recorded first and must stay as it is. Last, two filled
 * triangles lying back to back (a fill across a bore's wall and a base took the other
 * diagonal of the quad that had their sharp edge: a fin 1.4 mm high on a plate) have
 * their edge flipped back (mesh/tri_folds.h), kept when nothing crosses after.
 *
 * The fill from a region's own points (CDT_2) is in mend_fill_cgal.cpp, mend.h's other
 * two repairs (sr_mesh_unfold, sr_mesh_collapse_short_edges) in mend_unfold_cgal.cpp;
 * mend_cgal.hpp is what the three share. Kept out of boolean_cgal.cpp: the hole-filling
 * headers are heavy to compile, and the translation units build in parallel.
 * CGAL_ALWAYS_ROUND_TO_NEAREST for Valgrind as there (see its comment; mend_cgal.hpp
 * defines it). Every extern "C" entry catches all exceptions.
 */
#include "bridge/mend_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <cstring>
#include <exception>
#include <iterator>
#include <new>
#include <utility>
#include <vector>

namespace sr_mend {

/* sm from m's arrays: vertex i is Vertex_index i, triangle t face t. False when a
 * triangle repeats a vertex or does not fit (m is not an oriented manifold). */
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

namespace {

const int max_rings = 4;  /* attempts take 0..max_rings rings around the crossings */
const int max_passes = 3; /* cut-and-fill passes per attempt */
const int max_grow = 8;   /* growth steps of a region whose rim crosses itself */

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

/* Takes the faces `cut` out of sm and fills each hole they leave from its rim (CGAL
 * triangulate_hole). False (why set) when a hole stays open. */
bool cut_and_fill_from_rims(Mesh &sm, const std::vector<Face_index> &cut,
                            const std::vector<uint8_t> &own_border, sr_mend_report *rep,
                            const char **why)
{
    for (Face_index f : cut)
        CGAL::Euler::remove_face(sm.halfedge(f), sm);
    /* the holes: border halfedges that were not the mesh's own border (the cut never
     * reaches a vertex of it) */
    auto is_new_border = [&](Halfedge_index h) {
        return sm.is_border(h) && !own_border[sm.target(h).idx()];
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

/* One pass on sm (built from xyz): the faces of `pairs` and `rings` rings of faces
 * around them (sharing a vertex) out, each region of them filled again from its own
 * points (fill_from_points; in_space: checked against the faces around) or, where that
 * does not fit, from its rim. False (why set) when the faces taken out reach the
 * border or a hole stays open. */
bool cut_and_fill(Mesh &sm, const double *xyz, size_t nv,
                  const std::vector<std::pair<Face_index, Face_index>> &pairs, int rings,
                  bool in_space, const std::vector<uint8_t> &own_border,
                  sr_mend_report *rep, const char **why)
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

    /* regions filled from their points (their faces replaced in the arrays below),
     * the others from their rims on the halfedge mesh. A region whose rim crosses
     * itself seen along its normal, or (in_space) whose fill crosses the faces around
     * it, takes the faces at the crossing too, up to max_grow times or until they
     * would reach the border; then a fill that crosses only the faces around is kept
     * (the next pass sees to those crossings). */
    std::vector<Region> regions;
    std::vector<uint32_t> fills;
    std::vector<Face_index> from_rims;
    std::vector<uint8_t> by_points;
    bool last = false;
    std::vector<Face_index> prev_cut;
    std::vector<uint8_t> prev_mark;
    size_t prev_hard = SIZE_MAX;
    for (int grow = 0;; grow++) {
        last = last || grow == max_grow;
        regions = regions_of(sm, cut, mark);
        fills.clear();
        from_rims.clear();
        by_points.assign(mark.size(), 0);
        std::vector<uint32_t> grow_at;
        std::vector<uint32_t> region_of(mark.size(), UINT32_MAX);
        for (size_t i = 0; i < regions.size(); i++)
            for (Face_index f : regions[i].faces)
                region_of[f.idx()] = static_cast<uint32_t>(i);
        size_t hard = 0; /* faces of regions that cannot be filled from their points */
        for (size_t i = 0; i < regions.size(); i++) {
            const Region &reg = regions[i];
            Fill got = fill_from_points(sm, reg, i, region_of, in_space && !last, fills,
                                        grow_at);
            if (got == fill_ok) {
                for (Face_index f : reg.faces)
                    by_points[f.idx()] = 1;
            } else {
                from_rims.insert(from_rims.end(), reg.faces.begin(), reg.faces.end());
                if (got == fill_none)
                    hard += reg.faces.size();
            }
        }
        if (in_space && !last && hard > prev_hard) {
            /* the faces taken for fills crossing the faces around made regions
             * unfillable: back, and keep the fills that only cross the faces around */
            cut.swap(prev_cut);
            mark.swap(prev_mark);
            last = true;
            continue;
        }
        if (grow_at.empty() || last)
            break;
        prev_cut = cut;
        prev_mark = mark;
        prev_hard = hard;
        /* the faces at the crossing rim edges' ends, unless they reach the border */
        std::vector<Face_index> more;
        bool border = false;
        for (uint32_t w : grow_at)
            for (Face_index g : sm.faces_around_target(sm.halfedge(Vertex_index(w))))
                if (g != Mesh::null_face() && !mark[g.idx()]) {
                    more.push_back(g);
                    for (Vertex_index x : sm.vertices_around_face(sm.halfedge(g)))
                        border = border || sm.is_border(x, false);
                }
        if (border) {
            last = true; /* once more, fills crossing the faces around kept */
            continue;
        }
        for (Face_index g : more)
            take(g);
    }
    rep->removed_tris += cut.size();
    mark.swap(by_points); /* now: 1 = replaced by a point fill */
    rep->rim_filled += from_rims.size();
    if (!from_rims.empty() && !cut_and_fill_from_rims(sm, from_rims, own_border, rep, why))
        return false;
    if (fills.empty())
        return true;
    /* the point fills: sm again from its faces but the replaced ones, plus the fills
     * (the rim fills added faces only, in slots of faces they took out: the replaced
     * faces keep their indices) */
    std::vector<uint32_t> tri;
    tri.reserve(3 * sm.number_of_faces() + fills.size());
    for (Face_index f : sm.faces()) {
        if (f.idx() < mark.size() && mark[f.idx()])
            continue;
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            tri.push_back(static_cast<uint32_t>(v.idx()));
    }
    tri.insert(tri.end(), fills.begin(), fills.end());
    rep->filled_tris += fills.size() / 3;
    sr_mesh arrays;
    arrays.xyz = const_cast<double *>(xyz);
    arrays.vertex_count = nv;
    arrays.tri = tri.data();
    arrays.tri_count = tri.size() / 3;
    sm = Mesh();
    if (!build(&arrays, sm)) {
        *why = "the triangles filling a hole do not fit the mesh";
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

/* The fills' folds (tri_folds.h) in tri (nt triangles on mesh's vertices, the mended
 * mesh), flipped flat where that leaves nothing crossing near box: the triangles of tri
 * that are no triangle of mesh (the fills) may flip. Returns how many were flipped. */
size_t flip_fill_folds(const sr_mesh *mesh, uint32_t *tri, size_t nt, const double *box)
{
    typedef std::array<uint32_t, 3> Tri;
    auto sorted = [](const uint32_t *v) {
        Tri t = {v[0], v[1], v[2]};
        std::sort(t.begin(), t.end());
        return t;
    };
    std::vector<Tri> old(mesh->tri_count);
    for (size_t t = 0; t < mesh->tri_count; t++)
        old[t] = sorted(mesh->tri + 3 * t);
    std::sort(old.begin(), old.end());
    std::unique_ptr<bool[]> pick(new bool[nt + 1]);
    for (size_t t = 0; t < nt; t++)
        pick[t] = !std::binary_search(old.begin(), old.end(), sorted(tri + 3 * t));
    std::vector<uint32_t> before(tri, tri + 3 * nt);
    sr_mesh m = *mesh;
    m.tri = tri;
    m.tri_count = nt;
    size_t flipped = sr_tri_folds_flip(&m, pick.get());
    if (flipped == 0 || flipped == SIZE_MAX)
        return 0;
    Mesh sm;
    if (build(&m, sm) && crossings_near(sm, box).empty())
        return flipped;
    std::copy(before.begin(), before.end(), tri); /* a flip crossed something: undone */
    return 0;
}

/* One attempt with `rings` on sm (mesh as built, its crossings `pairs`): up to
 * max_passes of cut / fill / look again (checked: the fills of the passes after the
 * first must not cross the faces around them, see cut_and_fill). True with sm mended
 * when no crossing is left; false with why set. */
bool attempt(Mesh &sm, const sr_mesh *mesh, const double *box, int rings, bool checked,
             Pairs pairs, sr_mend_report *rep, const char **why)
{
    std::vector<uint8_t> own_border(sm.num_vertices(), 0);
    for (Vertex_index v : sm.vertices())
        if (sm.is_border(v, false))
            own_border[v.idx()] = 1;
    rep->removed_tris = rep->filled_tris = rep->rim_filled = 0;
    for (int pass = 0; !pairs.empty(); pass++) {
        if (pass == max_passes) {
            *why = "crossings are left after the holes were filled";
            return false;
        }
        bool in_space = checked && pass > 0;
        if (!cut_and_fill(sm, mesh->xyz, mesh->vertex_count, pairs, rings, in_space,
                          own_border, rep, why))
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
    /* the smallest holes first: attempts with 0, 1, ... rings around the crossings,
     * each with the later passes' fills checked against the faces around them
     * (crossings a fill leaves are then taken with it instead of coming back pass after
     * pass) and without; of the two, the one that fills fewer holes from their rims */
    const char *why = "";
    Mesh best;
    sr_mend_report got = *rep;
    bool done = false;
    for (int rings = 0; rings <= max_rings && !done; rings++)
        for (int checked = 1; checked >= 0; checked--) {
            if (rep->rounds > 0) {
                sm = Mesh();
                build(mesh, sm);
            }
            rep->rounds++;
            if (!attempt(sm, mesh, box, rings, checked != 0, first, &got, &why)) {
                rep->reached_border |= got.reached_border;
                continue;
            }
            if (!done || got.rim_filled < rep->rim_filled) {
                rep->removed_tris = got.removed_tris;
                rep->filled_tris = got.filled_tris;
                rep->rim_filled = got.rim_filled;
                best = std::move(sm);
                done = true;
            }
        }
    if (!done)
        return sr_err_set(err, SR_E_INVALID, "cannot mend the crossings (%zu pairs): %s",
                          rep->crossing_pairs, why);
    sm = std::move(best);
    size_t nt = sm.number_of_faces();
    uint32_t *tri = static_cast<uint32_t *>(malloc((nt ? nt : 1) * 3 * sizeof(uint32_t)));
    if (!tri)
        return sr_err_set(err, SR_E_NOMEM, "out of memory mending a mesh");
    size_t w = 0;
    for (Face_index f : sm.faces())
        for (Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
            tri[w++] = static_cast<uint32_t>(v.idx());
    rep->folds_flipped = flip_fill_folds(mesh, tri, nt, box);
    free(mesh->tri);
    mesh->tri = tri;
    mesh->tri_count = nt;
    return SR_OK;
}

} // namespace

} // namespace sr_mend

using namespace sr_mend;

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
