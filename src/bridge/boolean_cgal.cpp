/*
 * boolean_cgal.cpp: robust 3D booleans (union, intersection, difference) of whole
 * meshes, behind the pure-C header boolean.h (the private interface of the files that
 * implement it: boolean_cgal.hpp).
 *
 * Booleans use CGAL 5.5 Polygon Mesh Processing corefinement
 * (corefine_and_compute_union / _intersection / _difference) on a
 * Surface_mesh<Epick::Point_3>: exact predicates, intersection points constructed
 * exactly and rounded to double once. Each operand is checked first (operand_cgal.cpp).
 * The result is checked after (CGAL::is_closed, then sr_mesh_is_closed on the arrays).
 *
 * Every extern "C" entry catches all exceptions: std::bad_alloc -> SR_E_NOMEM,
 * anything else -> SR_E_INTERNAL with what() in the message.
 */
#include "bridge/boolean_cgal.hpp"

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

namespace {

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

} // namespace

sr_status boolean_entry(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                        const sr_mesh *b, const char *b_what, sr_mesh *out, sr_err *err)
{
    try {
        return boolean_compute(op, a, a_what, b, b_what, out, err);
    } catch (...) {
        return status_from_exception(err, op_name(op));
    }
}

} // namespace sr_bool

using namespace sr_bool;

extern "C" {

sr_status sr_boolean_compute(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                             const sr_mesh *b, const char *b_what, sr_mesh *out,
                             sr_err *err)
{
    return boolean_entry(op, a, a_what, b, b_what, out, err);
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

} // extern "C"
