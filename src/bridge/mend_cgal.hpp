/*
 * mend_cgal.hpp: the private interface between the CGAL files that implement mend.h.
 * Not installed, not used outside src/bridge/.
 *
 *   mend_cgal.cpp         sr_mesh_mend_crossings: crossings found, cut out with rings of
 *                         neighbours and filled again, attempt by attempt; the
 *                         Surface_mesh built straight from the sr_mesh arrays (build)
 *   mend_fill_cgal.cpp    the regions cut out, and the fill of one from its own points
 *                         (CDT_2 across its mean normal)
 *   crossings_cgal.cpp    the crossing faces of a mesh, found on every core
 *   mend_unfold_cgal.cpp  sr_mesh_unfold and sr_mesh_collapse_short_edges; its rounds
 *                         on a Surface_mesh (unfold_rounds), which sliver_cgal.cpp's
 *                         sr_mesh_unfold_scan runs after cleaning the slivers
 *
 * CGAL_ALWAYS_ROUND_TO_NEAREST is defined here, before any CGAL header, for Valgrind as
 * in boolean_cgal.hpp (see its comment): every file above includes this header first.
 * These translation units are slow to compile: keep the includes to the CGAL headers
 * each needs. CGAL's PMP package is GPL-3.0-or-later.
 */
#ifndef SR_MEND_CGAL_HPP
#define SR_MEND_CGAL_HPP

#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* before any CGAL header; see boolean_cgal.hpp */

#include "bridge/box_ids_cgal.hpp" /* before CGAL makes a box; see there */

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

extern "C" {
#include "bridge/mend.h"
#include "mesh/mesh.h"
#include "mesh/tri_folds.h"
#include "base/status.h"
}

namespace sr_mend {

namespace PMP = CGAL::Polygon_mesh_processing;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef Mesh::Vertex_index Vertex_index;
typedef Mesh::Face_index Face_index;
typedef Mesh::Halfedge_index Halfedge_index;

/* ---- mend_cgal.cpp ---- */

bool build(const sr_mesh *m, Mesh &sm);

/* ---- mend_fill_cgal.cpp ---- */

/* One region of the faces to take out (connected across edges): its rim (the directed
 * edges of its faces that another face runs the other way), its inner vertices (every
 * face at them taken out) and the sum of its faces' area vectors. */
struct Region {
    std::vector<Face_index> faces;
    std::vector<std::pair<uint32_t, uint32_t>> rim;
    std::vector<std::pair<uint32_t, uint32_t>> edges; /* between two of its faces, once */
    std::vector<Vertex_index> inner;
    K::Vector_3 normal = K::Vector_3(0, 0, 0);
};

std::vector<Region> regions_of(const Mesh &sm, const std::vector<Face_index> &cut,
                               const std::vector<uint8_t> &mark);

/* What fill_from_points did: nothing fits (fill_none), the fill appended (fill_ok), or
 * a fill that crosses the faces around it, not appended (fill_crossing). */
enum Fill { fill_none, fill_ok, fill_crossing };
Fill fill_from_points(const Mesh &sm, const Region &reg, size_t id,
                      const std::vector<uint32_t> &region_of, bool in_space,
                      std::vector<uint32_t> &tris, std::vector<uint32_t> &grow_at);

/* ---- crossings_cgal.cpp ---- */

/* The pairs of faces of range that cross (as PMP::self_intersections finds them), on
 * `threads` threads (0: every core), each once with the lower face first, sorted: the
 * same for any number of threads. */
std::vector<std::pair<Face_index, Face_index>>
crossing_pairs(const Mesh &sm, const std::vector<Face_index> &range, int threads);

/* The same search, the faces of the pairs marked in mark (sm.num_faces() bytes, 1: in a
 * crossing pair) instead of the pairs kept; returns how many pairs crossing_pairs gives. */
size_t crossing_faces(const Mesh &sm, const std::vector<Face_index> &range, int threads,
                      std::vector<uint8_t> &mark);

/* ---- mend_unfold_cgal.cpp ---- */

/* The faces around seeds (removed vertices skipped) and rings - 1 rings more. */
std::vector<Face_index> faces_near(const Mesh &sm, std::vector<Vertex_index> seeds, int rings);

/* sr_mesh_unfold's rounds on sm (which may hold removed elements), looking for crossings
 * first among range only: rep gets what they did; sm's points move. */
void unfold_rounds(Mesh &sm, std::vector<Face_index> range, double max_move, sr_unfold_report *rep);

} // namespace sr_mend

#endif
