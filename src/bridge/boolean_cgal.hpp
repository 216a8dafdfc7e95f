/*
 * boolean_cgal.hpp: the private interface between the CGAL files that implement
 * boolean.h. Not installed, not used outside src/bridge/.
 *
 *   operand_cgal.cpp        an operand's checks, Surface_mesh to and from sr_mesh arrays,
 *                           exceptions as statuses, sr_mesh_self_intersects
 *   boolean_cgal.cpp        the whole-mesh booleans (union, intersection, difference)
 *   neighbourhood_cgal.cpp  the local union's neighbourhood N of a patch, point in mesh
 *   union_local_cgal.cpp    the local union proper (sr_boolean_union_local*)
 *   union_result_cgal.cpp   the local union's result: united from the patch flags,
 *                           checked to close up with the rest of the scan, spliced in
 *   repair_cgal.cpp         sr_mesh_repair
 *   deviation_cgal.cpp      sr_mesh_deviation
 *
 * CGAL_ALWAYS_ROUND_TO_NEAREST: CGAL's interval filters normally switch the FPU to
 * round-upward; Valgrind ignores rounding-mode changes, so under Valgrind the filtered
 * predicates lie and corefinement writes out of bounds (seen: invalid writes, a failed
 * union). With this macro the intervals are widened by nextafter in round-to-nearest
 * instead: correct everywhere, 5-20 % slower (measured on the
 * shaft union and on 1M-triangle meshes). It is defined here, before any CGAL header:
 * every file above includes this header first.
 *
 * These translation units are slow to compile: keep the includes to the CGAL headers
 * each needs. CGAL's PMP package is GPL-3.0-or-later.
 */
#ifndef SR_BOOLEAN_CGAL_HPP
#define SR_BOOLEAN_CGAL_HPP

#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* before any CGAL header; see above */

#include "bridge/box_ids_cgal.hpp" /* before CGAL makes a box; see there */

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <boost/dynamic_bitset.hpp>

#include <cstdint>
#include <vector>

extern "C" {
#include "bridge/boolean.h"
#include "bridge/mend.h"
#include "mesh/mesh.h"
#include "base/status.h"
}

namespace sr_bool {

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

const uint32_t no_vertex = UINT32_MAX;

/* ---- operand_cgal.cpp ---- */

bool build_surface_mesh(const sr_mesh *m, Mesh &sm, size_t *bad_tri);
sr_status check_arrays(const sr_mesh *m, const char *what, sr_mesh_edges *edges, sr_err *err);
sr_status check_operand(const sr_mesh *m, const char *what, const double *other_box, Mesh &sm,
                        sr_err *err);
sr_status mesh_to_arrays(Mesh &sm, sr_mesh *out, sr_err *err, const char *doing);
const char *op_name(sr_boolean_op op);
bool self_intersects_near(const Mesh &sm, const double box[6]);
sr_status status_from_exception(sr_err *err, const char *doing);

/* ---- boolean_cgal.cpp ---- */

sr_status boolean_entry(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                        const sr_mesh *b, const char *b_what, sr_mesh *out, sr_err *err);

/* ---- neighbourhood_cgal.cpp ---- */

void frame_point(const sr_mesh *m, size_t v, const double *xf, double out[3]);
uint64_t he_key(uint32_t x, uint32_t y);
int inside_by_rays(const sr_mesh *a, const double *xf, const Point &p);
bool select_neighbourhood(const sr_mesh *a, const double *xf, const double box[6],
                          std::vector<uint8_t> &in, size_t *count);

/* ---- union_result_cgal.cpp ---- */

/* Patch flags of one corefined operand, as CGAL's output builder works them out. */
struct Patch_flags {
    std::vector<std::size_t> patch;          /* per face index: its patch */
    boost::dynamic_bitset<> inside;          /* patch inside the other operand */
    boost::dynamic_bitset<> coplanar;        /* patch on the other operand's surface */
    boost::dynamic_bitset<> coplanar_union;  /* ... kept once by a union */
    boost::dynamic_bitset<> not_set;         /* patch with no intersection edge */
    bool have = false;
};

/* The local result as arrays: vertex ids below base are a's vertices, the others index
 * `fresh` (new points) as id - base. */
struct Local_result {
    std::vector<uint32_t> tri;
    std::vector<double> fresh;
};

void splice_local(sr_mesh *dst, const std::vector<uint8_t> &in, const Local_result &res);
bool assemble_local(const sr_mesh *a, const char *a_what, const char *b_what,
                    const double *xf, const double *back, Mesh &sm,
                    Mesh::Property_map<Vertex_index, uint32_t> orig, Mesh &mb,
                    Patch_flags flags[2], const std::vector<uint32_t> node_vertex[2],
                    Local_result &res, std::vector<uint32_t> *diff, char *why,
                    size_t why_size);
sr_status diff_to_mesh(const sr_mesh *a, const Local_result &res,
                       const std::vector<uint32_t> &diff, sr_mesh *out);
bool local_result_fits(const Local_result &res, const std::vector<uint64_t> &border_before,
                       size_t base);

} // namespace sr_bool

#endif
