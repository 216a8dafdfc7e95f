/*
 * sliver_cgal.cpp: sr_mesh_clean_folded_slivers (mend.h). A scanner's mesh of a part
 * with long straight edges holds slivers: caps (one angle near 180 degrees, a vertex
 * almost on the opposite edge) and needles (one edge far shorter than the others).
 * Noise of a few hundredths of a millimetre moves such a vertex across the edge it
 * nearly lies on, and the surface folds over there: the sliver and its neighbour lie on
 * top of each other, facing opposite ways. The fold is the sliver's shape, not a
 * crossing of two sheets of the part, so the cure is the sliver's own: a cap's long
 * edge is flipped (the arrowhead of a folded cap has one valid diagonal, from its
 * reflex vertex), a needle's short edge is collapsed. CGAL's
 * experimental::remove_almost_degenerate_faces (CGAL 5.5, repair_degeneracies.h) does
 * both, flipping only to the diagonal whose two triangles face the same way; it is run
 * on the crossing triangles and their neighbours only, with the collapse length and the
 * flipped triangles' height bounded by max_move_mm, so the surface moves by no more
 * than that and only where it folds.
 *
 * sr_mesh_unfold_scan does that and then sr_mesh_unfold's rounds (mend_unfold_cgal.cpp)
 * on the same Surface_mesh, the first round looking only around what crossed: nothing
 * else changed, so nothing else can cross. A million-triangle scan is built once and
 * searched for crossings once, not twice each.
 */
#include "bridge/boolean_cgal.hpp"
#include "bridge/mend_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iterator>
#include <utility>
#include <vector>

namespace {

using namespace sr_bool;

typedef Mesh::Face_index Face_index;

#define CAP_ANGLE_DEG 160.0 /* a cap: an angle over this */
#define NEEDLE_RATIO 4.0    /* a needle: longest edge over shortest above this */

/* The crossing faces of sm and their neighbours across an edge, each once, in index
 * order (marked, not kept in a tree nor as pairs: a noisy spline's scan crossed itself
 * 10.6 million times, a std::set of its faces took 2 of its 30 s and the pairs 170 MB). */
std::vector<Face_index> folded_faces(const Mesh &sm, size_t *pairs)
{
    std::vector<Face_index> all(sm.faces().begin(), sm.faces().end());
    std::vector<uint8_t> crossing;
    *pairs = sr_mend::crossing_faces(sm, all, 0, crossing);
    std::vector<Face_index>().swap(all);
    std::vector<uint8_t> mark(crossing);
    for (size_t i = 0; i < crossing.size(); i++) {
        if (!crossing[i])
            continue;
        Face_index f((uint32_t)i);
        for (auto h : CGAL::halfedges_around_face(sm.halfedge(f), sm)) {
            Face_index g = sm.face(sm.opposite(h));
            if (g != Mesh::null_face())
                mark[g.idx()] = 1;
        }
    }
    std::vector<Face_index> faces;
    for (size_t i = 0; i < mark.size(); i++)
        if (mark[i])
            faces.push_back(Face_index((uint32_t)i));
    return faces;
}

} // namespace

extern "C" sr_status sr_mesh_clean_folded_slivers(sr_mesh *mesh, double max_move_mm,
                                                  sr_sliver_report *report, sr_err *err)
{
    sr_sliver_report local = {0, 0};
    if (!report)
        report = &local;
    *report = local;
    if (!(max_move_mm > 0) || !std::isfinite(max_move_mm))
        return sr_err_set(err, SR_E_RANGE, "bad sliver move bound %g mm", max_move_mm);
    try {
        Mesh sm;
        size_t bad = 0;
        if (!build_surface_mesh(mesh, sm, &bad))
            return sr_err_set(err, SR_E_INVALID,
                              "mesh is not an oriented manifold at triangle %zu", bad);
        std::vector<Face_index> near = folded_faces(sm, &report->crossing_pairs);
        if (near.empty())
            return SR_OK;
        size_t faces_before = sm.number_of_faces();
        PMP::experimental::remove_almost_degenerate_faces(
            near, sm, std::cos(CAP_ANGLE_DEG * M_PI / 180.0), NEEDLE_RATIO, max_move_mm,
            CGAL::parameters::flip_triangle_height_threshold(max_move_mm));
        report->faces_removed = faces_before - sm.number_of_faces();
        sr_mesh out;
        sr_mesh_init(&out);
        sr_status st = mesh_to_arrays(sm, &out, err, "cleaning slivers");
        if (st != SR_OK)
            return st;
        sr_mesh_release(mesh);
        *mesh = out;
        return SR_OK;
    } catch (...) {
        return status_from_exception(err, "cleaning slivers");
    }
}

namespace
{

/* sr_mesh_unfold_scan; when `spent` is given (the scan itself), its arrays are released
 * once the unfolded surface stands in the Surface_mesh, before *out is made from it. */
sr_status unfold_scan(const sr_mesh *scan, sr_mesh *spent, double max_move_mm, sr_mesh *out,
                      sr_sliver_report *slivers, sr_unfold_report *unfold, sr_err *err)
{
    sr_sliver_report local_slivers = {0, 0};
    sr_unfold_report local_unfold = {0, 0, 0, 0};
    if (!slivers)
        slivers = &local_slivers;
    if (!unfold)
        unfold = &local_unfold;
    *slivers = local_slivers;
    *unfold = local_unfold;
    sr_mesh_init(out);
    if (!(max_move_mm > 0) || !std::isfinite(max_move_mm))
        return sr_err_set(err, SR_E_RANGE, "bad unfold move bound %g mm", max_move_mm);
    try {
        Mesh sm;
        size_t bad = 0;
        if (!build_surface_mesh(scan, sm, &bad))
            return sr_err_set(err, SR_E_INVALID, "mesh is not an oriented manifold at triangle %zu",
                              bad);
        std::vector<Face_index> near = folded_faces(sm, &slivers->crossing_pairs);
        if (near.empty())
            return SR_OK; /* nothing crosses: out stays empty */
        std::vector<Mesh::Vertex_index> seeds;
        for (Face_index f : near)
            for (Mesh::Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
                seeds.push_back(v);
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        size_t faces_before = sm.number_of_faces();
        PMP::experimental::remove_almost_degenerate_faces(
            near, sm, std::cos(CAP_ANGLE_DEG * M_PI / 180.0), NEEDLE_RATIO, max_move_mm,
            CGAL::parameters::flip_triangle_height_threshold(max_move_mm));
        slivers->faces_removed = faces_before - sm.number_of_faces();
        sr_mend::unfold_rounds(sm, sr_mend::faces_near(sm, seeds, 3), max_move_mm, unfold);
        if (spent)
            sr_mesh_release(spent);
        return mesh_to_arrays(sm, out, err, "unfolding a scan");
    } catch (...) {
        sr_mesh_release(out);
        return status_from_exception(err, "unfolding a scan");
    }
}

} // namespace

extern "C" sr_status sr_mesh_unfold_scan(const sr_mesh *scan, double max_move_mm, sr_mesh *out,
                                         sr_sliver_report *slivers, sr_unfold_report *unfold,
                                         sr_err *err)
{
    return unfold_scan(scan, nullptr, max_move_mm, out, slivers, unfold, err);
}

extern "C" sr_status sr_mesh_unfold_scan_in_place(sr_mesh *scan, double max_move_mm,
                                                  sr_sliver_report *slivers,
                                                  sr_unfold_report *unfold, sr_err *err)
{
    sr_mesh out;
    sr_mesh_init(&out);
    sr_status st = unfold_scan(scan, scan, max_move_mm, &out, slivers, unfold, err);
    if (st == SR_OK && out.tri_count > 0) {
        sr_mesh_release(scan); /* released already; the move below is all that is left */
        *scan = out;
    }
    return st;
}
