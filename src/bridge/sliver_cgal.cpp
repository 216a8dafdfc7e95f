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
 */
#include "bridge/boolean_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <cmath>
#include <exception>
#include <iterator>
#include <set>
#include <utility>
#include <vector>

namespace {

using namespace sr_bool;

typedef Mesh::Face_index Face_index;

#define CAP_ANGLE_DEG 160.0 /* a cap: an angle over this */
#define NEEDLE_RATIO 4.0    /* a needle: longest edge over shortest above this */

/* The crossing faces of sm and their neighbours across an edge, each once. */
std::vector<Face_index> folded_faces(const Mesh &sm, size_t *pairs)
{
    std::vector<std::pair<Face_index, Face_index>> crossing;
    PMP::self_intersections(sm, std::back_inserter(crossing));
    *pairs = crossing.size();
    std::set<Face_index> faces;
    for (const auto &c : crossing)
        for (Face_index f : {c.first, c.second}) {
            faces.insert(f);
            for (auto h : CGAL::halfedges_around_face(sm.halfedge(f), sm)) {
                Face_index g = sm.face(sm.opposite(h));
                if (g != Mesh::null_face())
                    faces.insert(g);
            }
        }
    return std::vector<Face_index>(faces.begin(), faces.end());
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
