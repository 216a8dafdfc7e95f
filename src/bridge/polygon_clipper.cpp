/*
 * polygon_clipper.cpp: planar region booleans, offsets, point-in-region tests and open
 * line clipping behind the pure-C header polygon.h, on Clipper 6.4.2 (Angus Johnson;
 * Vatti's clipping algorithm, B. R. Vatti, "A generic solution to polygon clipping",
 * CACM 35(7), 1992; offsets after Chen & McMains, "Polygon offsetting by computing
 * winding numbers", ASME IDETC 2005).
 *
 * Every entry converts its inputs to Clipper's integer paths first (checking each
 * coordinate: finite, |v| <= SR_POLY2_MAX_MM, scaled by SR_POLY2_SCALE and rounded to
 * the nearest unit), runs Clipper, and converts the result back, reading closed results
 * from a PolyTree so that outer contours are written counter-clockwise and holes
 * clockwise whatever Clipper's own output order. The C arrays of the result are built
 * completely before the caller's struct is touched. Every extern "C" entry catches all
 * exceptions: std::bad_alloc -> SR_E_NOMEM, anything else (Clipper throws
 * clipperException for internal failures) -> SR_E_INTERNAL with what().
 */
#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <utility>
#include <vector>

extern "C" {
#include "bridge/polygon.h"
#include "base/status.h"
}

namespace {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;
using ClipperLib::PolyNode;
using ClipperLib::PolyTree;

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

/* One coordinate to grid units; SR_OK or the refusal naming the value. */
sr_status to_unit(double v, const char *what, size_t contour, size_t point, char axis,
                  cInt *out, sr_err *err)
{
    if (!std::isfinite(v))
        return sr_err_set(err, SR_E_INVALID, "'%s' contour %zu point %zu: %c is %g", what,
                          contour, point, axis, v);
    if (std::fabs(v) > SR_POLY2_MAX_MM)
        return sr_err_set(err, SR_E_RANGE,
                          "'%s' contour %zu point %zu: %c = %g mm is beyond the polygon "
                          "range of +-%g mm",
                          what, contour, point, axis, v, SR_POLY2_MAX_MM);
    *out = static_cast<cInt>(std::llround(v * SR_POLY2_SCALE));
    return SR_OK;
}

/* Checks the start array: start[0] = 0, non-decreasing. */
sr_status check_start(const size_t *start, size_t count, const char *what, sr_err *err)
{
    if (count == 0)
        return SR_OK;
    if (!start)
        return sr_err_set(err, SR_E_INVALID, "'%s' has %zu contours but no start array",
                          what, count);
    if (start[0] != 0)
        return sr_err_set(err, SR_E_INVALID, "'%s' start[0] is %zu, not 0", what, start[0]);
    for (size_t c = 0; c < count; c++)
        if (start[c + 1] < start[c])
            return sr_err_set(err, SR_E_INVALID,
                              "'%s' start[%zu] = %zu is less than start[%zu] = %zu", what,
                              c + 1, start[c + 1], c, start[c]);
    return SR_OK;
}

/* Arrays (xy, start, count) to Clipper paths. min_points: shorter paths are refused. */
sr_status arrays_to_paths(const double *xy, const size_t *start, size_t count,
                          const char *what, size_t min_points, Paths &out, sr_err *err)
{
    sr_status st = check_start(start, count, what, err);
    if (st != SR_OK)
        return st;
    out.clear();
    out.resize(count);
    for (size_t c = 0; c < count; c++) {
        size_t n = start[c + 1] - start[c];
        if (n < min_points)
            return sr_err_set(err, SR_E_INVALID,
                              "'%s' contour %zu has %zu points, needs at least %zu", what,
                              c, n, min_points);
        Path &path = out[c];
        path.resize(n);
        for (size_t i = 0; i < n; i++) {
            const double *p = xy + 2 * (start[c] + i);
            st = to_unit(p[0], what, c, i, 'x', &path[i].X, err);
            if (st == SR_OK)
                st = to_unit(p[1], what, c, i, 'y', &path[i].Y, err);
            if (st != SR_OK)
                return st;
        }
    }
    return SR_OK;
}

sr_status region_to_paths(const sr_poly2 *a, const char *what, Paths &out, sr_err *err)
{
    out.clear();
    if (!a || a->contour_count == 0)
        return SR_OK;
    return arrays_to_paths(a->xy, a->start, a->contour_count, what, 1, out, err);
}

/* Paths to a fresh sr_poly2 (arrays allocated with malloc). Empty paths are skipped. */
sr_status paths_to_region(const Paths &paths, sr_poly2 *res, sr_err *err, const char *doing)
{
    sr_poly2_init(res);
    size_t total = 0, count = 0;
    for (const Path &p : paths)
        if (!p.empty()) {
            total += p.size();
            count++;
        }
    if (count == 0)
        return SR_OK;
    double *xy = static_cast<double *>(std::malloc(total * 2 * sizeof(double)));
    size_t *start = static_cast<size_t *>(std::malloc((count + 1) * sizeof(size_t)));
    if (!xy || !start) {
        std::free(xy);
        std::free(start);
        return sr_err_set(err, SR_E_NOMEM, "%s: out of memory for %zu points", doing, total);
    }
    size_t k = 0, c = 0;
    start[0] = 0;
    for (const Path &p : paths) {
        if (p.empty())
            continue;
        for (const IntPoint &q : p) {
            xy[2 * k] = static_cast<double>(q.X) / SR_POLY2_SCALE;
            xy[2 * k + 1] = static_cast<double>(q.Y) / SR_POLY2_SCALE;
            k++;
        }
        start[++c] = k;
    }
    res->xy = xy;
    res->start = start;
    res->contour_count = count;
    return SR_OK;
}

/* Closed contours of a PolyTree, each oriented by its role: outer CCW, hole CW. */
void tree_to_paths(const PolyTree &tree, Paths &out)
{
    out.clear();
    for (const PolyNode *n = tree.GetFirst(); n; n = n->GetNext()) {
        if (n->IsOpen() || n->Contour.size() < 3)
            continue;
        Path p = n->Contour;
        bool ccw = ClipperLib::Orientation(p); /* true: positive area (CCW, y up) */
        if (ccw == n->IsHole())
            ClipperLib::ReversePath(p);
        out.push_back(std::move(p));
    }
}

/* Replaces *out by res (releasing out's old arrays). */
void replace(sr_poly2 *out, sr_poly2 *res)
{
    sr_poly2_release(out);
    *out = *res;
}

/* paths into *out (replace); *out untouched on failure. */
sr_status store(const Paths &paths, sr_poly2 *out, sr_err *err, const char *doing)
{
    sr_poly2 res;
    sr_status st = paths_to_region(paths, &res, err, doing);
    if (st == SR_OK)
        replace(out, &res);
    return st;
}

ClipperLib::ClipType clip_type(sr_poly_op op)
{
    switch (op) {
    case SR_POLY_UNION: return ClipperLib::ctUnion;
    case SR_POLY_INTERSECTION: return ClipperLib::ctIntersection;
    case SR_POLY_DIFFERENCE: return ClipperLib::ctDifference;
    case SR_POLY_XOR: return ClipperLib::ctXor;
    }
    return ClipperLib::ctUnion;
}

/* a op b on paths, clean and oriented, into out. */
void run_boolean(ClipperLib::ClipType ct, const Paths &a, const Paths &b, Paths &out)
{
    ClipperLib::Clipper c;
    out.clear();
    /* AddPaths returns false when no path has an area (none, or all collapsed); with
     * nothing added, Execute would report failure: the result is simply empty */
    bool any = c.AddPaths(a, ClipperLib::ptSubject, true);
    any = c.AddPaths(b, ClipperLib::ptClip, true) || any;
    if (!any)
        return;
    PolyTree tree;
    if (!c.Execute(ct, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero))
        throw std::runtime_error("clipper failed to execute");
    tree_to_paths(tree, out);
}

/* Squared distance from p to the segment a-b (doubles, mm). */
double seg_dist2(double px, double py, double ax, double ay, double bx, double by)
{
    double dx = bx - ax, dy = by - ay;
    double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    double qx = ax + t * dx - px, qy = ay + t * dy - py;
    return qx * qx + qy * qy;
}

/* Collects the outer nodes of a tree (each with its hole children) into regions. */
void collect_outers(const PolyNode *node, std::vector<const PolyNode *> &outers)
{
    for (const PolyNode *child : node->Childs) {
        if (!child->IsHole())
            outers.push_back(child);
        collect_outers(child, outers);
    }
}

} /* namespace */

extern "C" {

void sr_poly2_init(sr_poly2 *p)
{
    p->xy = nullptr;
    p->start = nullptr;
    p->contour_count = 0;
}

void sr_poly2_release(sr_poly2 *p)
{
    if (!p)
        return;
    std::free(p->xy);
    std::free(p->start);
    sr_poly2_init(p);
}

size_t sr_poly2_point_count(const sr_poly2 *p)
{
    return (p && p->contour_count && p->start) ? p->start[p->contour_count] : 0;
}

sr_status sr_poly2_add_contour(sr_poly2 *p, const double *xy, size_t n, sr_err *err)
{
    if (n < 3)
        return sr_err_set(err, SR_E_INVALID, "a contour needs at least 3 points, got %zu", n);
    for (size_t i = 0; i < n; i++) {
        cInt unused;
        sr_status st = to_unit(xy[2 * i], "region", p->contour_count, i, 'x', &unused, err);
        if (st == SR_OK)
            st = to_unit(xy[2 * i + 1], "region", p->contour_count, i, 'y', &unused, err);
        if (st != SR_OK)
            return st;
    }
    size_t have = sr_poly2_point_count(p);
    double *nxy = static_cast<double *>(std::realloc(p->xy, (have + n) * 2 * sizeof(double)));
    if (!nxy)
        return sr_err_set(err, SR_E_NOMEM, "out of memory adding a contour of %zu points", n);
    p->xy = nxy; /* larger block, same content: p stays valid if the next step fails */
    size_t *nstart = static_cast<size_t *>(
        std::realloc(p->start, (p->contour_count + 2) * sizeof(size_t)));
    if (!nstart)
        return sr_err_set(err, SR_E_NOMEM, "out of memory adding a contour of %zu points", n);
    p->start = nstart;
    std::memcpy(p->xy + 2 * have, xy, n * 2 * sizeof(double));
    p->start[0] = 0;
    p->start[p->contour_count + 1] = have + n;
    p->contour_count++;
    return SR_OK;
}

sr_status sr_poly2_from_contours(const double *xy, const size_t *start,
                                 size_t contour_count, sr_poly2 *out, sr_err *err)
{
    try {
        Paths check;
        sr_status st = arrays_to_paths(xy, start, contour_count, "contours", 3, check, err);
        if (st != SR_OK)
            return st;
        sr_poly2 res;
        sr_poly2_init(&res);
        for (size_t c = 0; c < contour_count; c++) {
            st = sr_poly2_add_contour(&res, xy + 2 * start[c], start[c + 1] - start[c], err);
            if (st != SR_OK) {
                sr_poly2_release(&res);
                return st;
            }
        }
        replace(out, &res);
        return SR_OK;
    } catch (...) {
        return status_from_exception(err, "building a region");
    }
}

sr_status sr_poly2_copy(const sr_poly2 *a, sr_poly2 *out, sr_err *err)
{
    if (a == out)
        return SR_OK;
    if (!a || a->contour_count == 0) {
        sr_poly2_release(out);
        return SR_OK;
    }
    sr_status st = check_start(a->start, a->contour_count, "region", err);
    if (st != SR_OK)
        return st;
    size_t n = a->start[a->contour_count];
    sr_poly2 res;
    res.xy = static_cast<double *>(std::malloc((n ? n : 1) * 2 * sizeof(double)));
    res.start = static_cast<size_t *>(std::malloc((a->contour_count + 1) * sizeof(size_t)));
    res.contour_count = a->contour_count;
    if (!res.xy || !res.start) {
        std::free(res.xy);
        std::free(res.start);
        return sr_err_set(err, SR_E_NOMEM, "out of memory copying %zu points", n);
    }
    std::memcpy(res.xy, a->xy, n * 2 * sizeof(double));
    std::memcpy(res.start, a->start, (a->contour_count + 1) * sizeof(size_t));
    replace(out, &res);
    return SR_OK;
}

sr_status sr_poly2_boolean(sr_poly_op op, const sr_poly2 *a, const sr_poly2 *b,
                           sr_poly2 *out, sr_err *err)
{
    if (op < SR_POLY_UNION || op > SR_POLY_XOR)
        return sr_err_set(err, SR_E_RANGE, "polygon operation %d is not one of union, "
                          "intersection, difference, xor", static_cast<int>(op));
    try {
        Paths pa, pb, res_paths;
        sr_status st = region_to_paths(a, "first region", pa, err);
        if (st == SR_OK)
            st = region_to_paths(b, "second region", pb, err);
        if (st != SR_OK)
            return st;
        run_boolean(clip_type(op), pa, pb, res_paths);
        return store(res_paths, out, err, "polygon boolean");
    } catch (...) {
        return status_from_exception(err, "polygon boolean");
    }
}

sr_status sr_poly2_offset(const sr_poly2 *a, double delta_mm, int round_joins,
                          sr_poly2 *out, sr_err *err)
{
    if (!std::isfinite(delta_mm) || std::fabs(delta_mm) > SR_POLY2_MAX_MM)
        return sr_err_set(err, SR_E_RANGE, "offset distance %g mm is not within +-%g mm",
                          delta_mm, SR_POLY2_MAX_MM);
    try {
        Paths pa, clean, res_paths;
        sr_status st = region_to_paths(a, "region", pa, err);
        if (st != SR_OK)
            return st;
        run_boolean(ClipperLib::ctUnion, pa, Paths(), clean);
        if (!clean.empty()) {
            ClipperLib::ClipperOffset co(2.0, SR_POLY2_ARC_TOL_MM * SR_POLY2_SCALE);
            co.AddPaths(clean, round_joins ? ClipperLib::jtRound : ClipperLib::jtMiter,
                        ClipperLib::etClosedPolygon);
            PolyTree tree;
            co.Execute(tree, delta_mm * SR_POLY2_SCALE);
            tree_to_paths(tree, res_paths);
        }
        return store(res_paths, out, err, "polygon offset");
    } catch (...) {
        return status_from_exception(err, "polygon offset");
    }
}

sr_status sr_poly2_clean(const sr_poly2 *a, double tol_mm, sr_poly2 *out, sr_err *err)
{
    if (!std::isfinite(tol_mm) || tol_mm < 0 || tol_mm > SR_POLY2_MAX_MM)
        return sr_err_set(err, SR_E_RANGE, "clean tolerance %g mm is not within [0, %g] mm", tol_mm,
                          SR_POLY2_MAX_MM);
    try {
        Paths pa, res_paths;
        sr_status st = region_to_paths(a, "region", pa, err);
        if (st != SR_OK)
            return st;
        ClipperLib::CleanPolygons(pa, tol_mm * SR_POLY2_SCALE);
        run_boolean(ClipperLib::ctUnion, pa, Paths(), res_paths);
        return store(res_paths, out, err, "polygon clean");
    } catch (...) {
        return status_from_exception(err, "polygon clean");
    }
}

double sr_poly2_area(const sr_poly2 *a)
{
    if (!a || a->contour_count == 0)
        return 0;
    double total = 0;
    for (size_t c = 0; c < a->contour_count; c++) {
        size_t s = a->start[c], e = a->start[c + 1];
        if (e - s < 3)
            continue;
        /* relative to the first point: less cancellation far from the origin */
        double x0 = a->xy[2 * s], y0 = a->xy[2 * s + 1], sum = 0;
        for (size_t i = s + 1; i + 1 < e; i++) {
            double x1 = a->xy[2 * i] - x0, y1 = a->xy[2 * i + 1] - y0;
            double x2 = a->xy[2 * i + 2] - x0, y2 = a->xy[2 * i + 3] - y0;
            sum += x1 * y2 - x2 * y1;
        }
        total += 0.5 * sum;
    }
    return total;
}

int sr_poly2_contains(const sr_poly2 *a, double x, double y)
{
    if (!a || a->contour_count == 0 || !std::isfinite(x) || !std::isfinite(y) ||
        std::fabs(x) > SR_POLY2_MAX_MM || std::fabs(y) > SR_POLY2_MAX_MM)
        return 0;
    try {
        IntPoint pt(static_cast<cInt>(std::llround(x * SR_POLY2_SCALE)),
                    static_cast<cInt>(std::llround(y * SR_POLY2_SCALE)));
        Paths pa;
        if (region_to_paths(a, "region", pa, nullptr) != SR_OK)
            return 0;
        int winding = 0;
        for (const Path &p : pa) {
            if (p.size() < 3)
                continue;
            int r = ClipperLib::PointInPolygon(pt, p);
            if (r < 0)
                return -1;
            if (r > 0)
                winding += ClipperLib::Orientation(p) ? 1 : -1;
        }
        return winding != 0 ? 1 : 0;
    } catch (...) {
        return 0;
    }
}

int sr_poly2_bounds(const sr_poly2 *a, double box[4])
{
    size_t n = sr_poly2_point_count(a);
    if (n == 0)
        return 0;
    double b[4] = {a->xy[0], a->xy[1], a->xy[0], a->xy[1]};
    for (size_t i = 1; i < n; i++) {
        b[0] = std::min(b[0], a->xy[2 * i]);
        b[1] = std::min(b[1], a->xy[2 * i + 1]);
        b[2] = std::max(b[2], a->xy[2 * i]);
        b[3] = std::max(b[3], a->xy[2 * i + 1]);
    }
    std::memcpy(box, b, sizeof b);
    return 1;
}

double sr_poly2_boundary_distance(const sr_poly2 *a, double x, double y)
{
    double best = INFINITY;
    if (!a)
        return best;
    for (size_t c = 0; c < a->contour_count; c++) {
        size_t s = a->start[c], e = a->start[c + 1];
        for (size_t i = s; i < e; i++) {
            size_t j = (i + 1 < e) ? i + 1 : s;
            best = std::min(best, seg_dist2(x, y, a->xy[2 * i], a->xy[2 * i + 1],
                                            a->xy[2 * j], a->xy[2 * j + 1]));
        }
    }
    return std::sqrt(best);
}

sr_status sr_poly2_clip_lines(const sr_poly2 *region, const double *xy,
                              const size_t *start, size_t path_count,
                              sr_poly2 *out_open, sr_err *err)
{
    try {
        Paths lines, pr, res_paths;
        sr_status st = arrays_to_paths(xy, start, path_count, "lines", 2, lines, err);
        if (st == SR_OK)
            st = region_to_paths(region, "region", pr, err);
        if (st != SR_OK)
            return st;
        ClipperLib::Clipper c;
        if (c.AddPaths(lines, ClipperLib::ptSubject, false) &&
            c.AddPaths(pr, ClipperLib::ptClip, true)) {
            PolyTree tree;
            if (!c.Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero,
                           ClipperLib::pftNonZero))
                throw std::runtime_error("clipper failed to execute");
            ClipperLib::OpenPathsFromPolyTree(tree, res_paths);
            res_paths.erase(std::remove_if(res_paths.begin(), res_paths.end(),
                                           [](const Path &p) { return p.size() < 2; }),
                            res_paths.end());
        }
        return store(res_paths, out_open, err, "line clipping");
    } catch (...) {
        return status_from_exception(err, "line clipping");
    }
}

sr_status sr_poly2_components(const sr_poly2 *a, sr_poly2 **out, size_t *out_count,
                              sr_err *err)
{
    std::vector<sr_poly2> parts;
    try {
        Paths pa;
        sr_status st = region_to_paths(a, "region", pa, err);
        if (st != SR_OK)
            return st;
        ClipperLib::Clipper c;
        PolyTree tree;
        if (c.AddPaths(pa, ClipperLib::ptSubject, true) &&
            !c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero,
                       ClipperLib::pftNonZero))
            throw std::runtime_error("clipper failed to execute");
        std::vector<const PolyNode *> outers;
        collect_outers(&tree, outers);
        std::vector<std::pair<double, size_t>> order;
        parts.reserve(outers.size());
        for (const PolyNode *o : outers) {
            Paths piece;
            Path p = o->Contour;
            if (!ClipperLib::Orientation(p))
                ClipperLib::ReversePath(p);
            double area = ClipperLib::Area(p);
            piece.push_back(std::move(p));
            for (const PolyNode *h : o->Childs) {
                Path q = h->Contour;
                if (ClipperLib::Orientation(q))
                    ClipperLib::ReversePath(q);
                area += ClipperLib::Area(q);
                piece.push_back(std::move(q));
            }
            sr_poly2 r;
            st = paths_to_region(piece, &r, err, "splitting a region");
            if (st != SR_OK)
                throw std::bad_alloc();
            order.emplace_back(-area, parts.size());
            parts.push_back(r);
        }
        std::stable_sort(order.begin(), order.end(),
                         [](const std::pair<double, size_t> &x,
                            const std::pair<double, size_t> &y) { return x.first < y.first; });
        sr_poly2 *arr = nullptr;
        if (!parts.empty()) {
            arr = static_cast<sr_poly2 *>(std::malloc(parts.size() * sizeof(sr_poly2)));
            if (!arr)
                throw std::bad_alloc();
            for (size_t i = 0; i < order.size(); i++)
                arr[i] = parts[order[i].second];
        }
        *out = arr;
        *out_count = parts.size();
        return SR_OK;
    } catch (...) {
        for (sr_poly2 &p : parts)
            sr_poly2_release(&p);
        return status_from_exception(err, "splitting a region");
    }
}

void sr_poly2_components_release(sr_poly2 *parts, size_t count)
{
    if (!parts)
        return;
    for (size_t i = 0; i < count; i++)
        sr_poly2_release(&parts[i]);
    std::free(parts);
}

} /* extern "C" */
