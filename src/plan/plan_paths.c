/*
 * plan_paths.c: the tool paths of one plan layer (plan.h, "Paths per layer"): contour
 * rings at the deposit region offset inwards, and zig-zag rasters clipped to it,
 * chained nearest end first, a join deposited only where it stays inside the region.
 * They are collected in a growable list of polylines (pathbuf, plan_int.h) that plan.c
 * moves into its layer. Offsets and clipping are Clipper's (bridge/polygon.h).
 */
#include "plan/plan_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_RINGS 10000

/* ---- growable list of polylines ---- */

void pathbuf_release(pathbuf *b)
{
    free(b->xy);
    free(b->start);
    free(b->kind);
    memset(b, 0, sizeof *b);
}

/* Appends n points (xy interleaved) as one polyline of `kind`; repeat_first appends
 * the first point again (closes a ring). */
static sr_status pathbuf_add(pathbuf *b, const double *xy, size_t n, int repeat_first,
                             unsigned char kind, sr_err *err)
{
    size_t need = b->n + n + (repeat_first ? 1 : 0);
    if (need > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        while (cap < need)
            cap *= 2;
        double *nxy = realloc(b->xy, cap * 2 * sizeof(double));
        if (!nxy)
            return sr_err_set(err, SR_E_NOMEM, "out of memory for tool paths");
        b->xy = nxy;
        b->cap = cap;
    }
    if (b->count + 2 > b->scap) {
        size_t cap = b->scap ? b->scap * 2 : 16;
        size_t *ns = realloc(b->start, cap * sizeof(size_t));
        if (!ns)
            return sr_err_set(err, SR_E_NOMEM, "out of memory for tool paths");
        b->start = ns;
        unsigned char *nk = realloc(b->kind, cap);
        if (!nk)
            return sr_err_set(err, SR_E_NOMEM, "out of memory for tool paths");
        b->kind = nk;
        b->scap = cap;
    }
    memcpy(b->xy + 2 * b->n, xy, n * 2 * sizeof(double));
    b->n += n;
    if (repeat_first) {
        b->xy[2 * b->n] = xy[0];
        b->xy[2 * b->n + 1] = xy[1];
        b->n++;
    }
    b->start[0] = 0;
    b->kind[b->count] = kind;
    b->start[++b->count] = b->n;
    return SR_OK;
}

/* Appends one point to the last polyline (there must be one). */
static sr_status pathbuf_extend(pathbuf *b, double x, double y, sr_err *err)
{
    if (b->n + 1 > b->cap) {
        size_t cap = b->cap * 2;
        double *nxy = realloc(b->xy, cap * 2 * sizeof(double));
        if (!nxy)
            return sr_err_set(err, SR_E_NOMEM, "out of memory for tool paths");
        b->xy = nxy;
        b->cap = cap;
    }
    b->xy[2 * b->n] = x;
    b->xy[2 * b->n + 1] = y;
    b->start[b->count] = ++b->n;
    return SR_OK;
}

/* Moves the polylines into an sr_poly2 and a kind array (b emptied). */
void pathbuf_take(pathbuf *b, sr_poly2 *paths, unsigned char **kind)
{
    sr_poly2_init(paths);
    *kind = NULL;
    if (b->count) {
        paths->xy = b->xy;
        paths->start = b->start;
        paths->contour_count = b->count;
        *kind = b->kind;
        memset(b, 0, sizeof *b);
    }
    pathbuf_release(b);
}

double pl_polyline_length(const double *xy, size_t n)
{
    double len = 0;
    for (size_t i = 1; i < n; i++)
        len += hypot(xy[2 * i] - xy[2 * i - 2], xy[2 * i + 1] - xy[2 * i - 1]);
    return len;
}

/* ---- paths ---- */

/* Rings: every contour of r, closed. */
static sr_status add_rings(pathbuf *b, const sr_poly2 *r, sr_err *err)
{
    for (size_t c = 0; c < r->contour_count; c++) {
        size_t s = r->start[c], n = r->start[c + 1] - s;
        if (n < 3)
            continue;
        sr_status st = pathbuf_add(b, r->xy + 2 * s, n, 1, SR_PLAN_PATH_RING, err);
        if (st != SR_OK)
            return st;
    }
    return SR_OK;
}

/* 1 when the segment (ax,ay)-(bx,by) lies inside region g (boundary included). */
static sr_status segment_inside(const sr_poly2 *g, double ax, double ay, double bx,
                                double by, int *inside, sr_err *err)
{
    double xy[4] = {ax, ay, bx, by};
    size_t start[2] = {0, 2};
    sr_poly2 out;
    sr_poly2_init(&out);
    sr_status st = sr_poly2_clip_lines(g, xy, start, 1, &out, err);
    if (st != SR_OK)
        return st;
    double len = hypot(bx - ax, by - ay), got = 0;
    for (size_t c = 0; c < out.contour_count; c++)
        got += pl_polyline_length(out.xy + 2 * out.start[c], out.start[c + 1] - out.start[c]);
    *inside = out.contour_count == 1 && fabs(got - len) <= 1e-4;
    sr_poly2_release(&out);
    return SR_OK;
}

typedef struct piece {
    double a[2], b[2];
    int used;
} piece;

/* A raster of lines `step` apart at `angle_deg` clipped to `fill`, chained nearest end
 * first; joins of at most 2 step that lie inside `g` are deposited, others break the
 * path. */
static sr_status add_raster(pathbuf *b, const sr_poly2 *fill, const sr_poly2 *g,
                            double step, double angle_deg, sr_err *err)
{
    size_t np = sr_poly2_point_count(fill);
    if (np == 0)
        return SR_OK;
    double t = angle_deg * PI / 180.0, ux = cos(t), uy = sin(t), vx = -uy, vy = ux;
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    for (size_t i = 0; i < np; i++) {
        double x = fill->xy[2 * i], y = fill->xy[2 * i + 1];
        double u = x * ux + y * uy, v = x * vx + y * vy;
        umin = fmin(umin, u);
        umax = fmax(umax, u);
        vmin = fmin(vmin, v);
        vmax = fmax(vmax, v);
    }
    size_t lines = (size_t)floor((vmax - vmin) / step) + 1;
    if (lines > 1000000)
        return sr_err_set(err, SR_E_RANGE,
                          "step_over_mm %g gives %zu raster lines in one layer", step, lines);
    double vmid = 0.5 * (vmin + vmax);
    double *xy = malloc(lines * 4 * sizeof(double));
    size_t *start = malloc((lines + 1) * sizeof(size_t));
    piece *pc = NULL;
    sr_poly2 clipped;
    sr_poly2_init(&clipped);
    sr_status st = SR_OK;
    if (!xy || !start) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu raster lines", lines);
        goto cleanup;
    }
    for (size_t j = 0; j < lines; j++) {
        double v = vmid + ((double)j - 0.5 * (double)(lines - 1)) * step;
        double u0 = umin - 1.0, u1 = umax + 1.0;
        xy[4 * j] = u0 * ux + v * vx;
        xy[4 * j + 1] = u0 * uy + v * vy;
        xy[4 * j + 2] = u1 * ux + v * vx;
        xy[4 * j + 3] = u1 * uy + v * vy;
        start[j] = 2 * j;
    }
    start[lines] = 2 * lines;
    st = sr_poly2_clip_lines(fill, xy, start, lines, &clipped, err);
    if (st != SR_OK || clipped.contour_count == 0)
        goto cleanup;
    size_t n = clipped.contour_count;
    pc = calloc(n, sizeof *pc);
    if (!pc) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu raster pieces", n);
        goto cleanup;
    }
    size_t first = 0;
    double best_key = INFINITY;
    for (size_t c = 0; c < n; c++) {
        const double *p = clipped.xy + 2 * clipped.start[c];
        size_t last = clipped.start[c + 1] - clipped.start[c] - 1;
        memcpy(pc[c].a, p, sizeof pc[c].a);
        memcpy(pc[c].b, p + 2 * last, sizeof pc[c].b);
        /* start at the lowest line, its low-u end */
        double va = pc[c].a[0] * vx + pc[c].a[1] * vy;
        double ua = pc[c].a[0] * ux + pc[c].a[1] * uy, ub = pc[c].b[0] * ux + pc[c].b[1] * uy;
        if (ub < ua) {
            double tmp[2];
            memcpy(tmp, pc[c].a, sizeof tmp);
            memcpy(pc[c].a, pc[c].b, sizeof tmp);
            memcpy(pc[c].b, tmp, sizeof tmp);
            ua = ub;
        }
        double key = va * 1e6 + ua;
        if (key < best_key) {
            best_key = key;
            first = c;
        }
    }
    size_t cur = first;
    pc[cur].used = 1;
    double seg[4] = {pc[cur].a[0], pc[cur].a[1], pc[cur].b[0], pc[cur].b[1]};
    st = pathbuf_add(b, seg, 2, 0, SR_PLAN_PATH_RASTER, err);
    double end[2] = {pc[cur].b[0], pc[cur].b[1]};
    for (size_t done = 1; st == SR_OK && done < n; done++) {
        size_t next = n;
        int flip = 0;
        double best = INFINITY;
        for (size_t c = 0; c < n; c++) {
            if (pc[c].used)
                continue;
            double da = hypot(pc[c].a[0] - end[0], pc[c].a[1] - end[1]);
            double db = hypot(pc[c].b[0] - end[0], pc[c].b[1] - end[1]);
            if (da < best) {
                best = da;
                next = c;
                flip = 0;
            }
            if (db < best) {
                best = db;
                next = c;
                flip = 1;
            }
        }
        pc[next].used = 1;
        const double *s0 = flip ? pc[next].b : pc[next].a;
        const double *s1 = flip ? pc[next].a : pc[next].b;
        int join = 0;
        if (best <= 2.0 * step + 1e-9)
            st = segment_inside(g, end[0], end[1], s0[0], s0[1], &join, err);
        if (st != SR_OK)
            break;
        if (join) {
            st = pathbuf_extend(b, s0[0], s0[1], err);
            if (st == SR_OK)
                st = pathbuf_extend(b, s1[0], s1[1], err);
        } else {
            double q[4] = {s0[0], s0[1], s1[0], s1[1]};
            st = pathbuf_add(b, q, 2, 0, SR_PLAN_PATH_RASTER, err);
        }
        end[0] = s1[0];
        end[1] = s1[1];
    }
cleanup:
    free(xy);
    free(start);
    free(pc);
    sr_poly2_release(&clipped);
    return st;
}

/* All paths of one layer's deposit region g. */
sr_status pl_layer_paths(const sr_plan_opts *o, const sr_poly2 *g, double angle_deg,
                         pathbuf *b, sr_err *err)
{
    if (g->contour_count == 0)
        return SR_OK;
    double s = o->step_over_mm;
    sr_poly2 ring, fill;
    sr_poly2_init(&ring);
    sr_poly2_init(&fill);
    sr_status st = SR_OK;
    if (o->pattern == SR_PLAN_CONTOUR || o->pattern == SR_PLAN_CONTOUR_RASTER) {
        size_t rings = o->pattern == SR_PLAN_CONTOUR ? MAX_RINGS : 1;
        for (size_t k = 0; st == SR_OK && k < rings; k++) {
            st = sr_poly2_offset(g, -((double)k + 0.5) * s, 1, &ring, err);
            if (st != SR_OK || ring.contour_count == 0)
                break;
            st = add_rings(b, &ring, err);
        }
    }
    if (st == SR_OK && o->pattern != SR_PLAN_CONTOUR) {
        double inset = o->pattern == SR_PLAN_RASTER ? 0.5 * s : s;
        st = sr_poly2_offset(g, -inset, 1, &fill, err);
        if (st == SR_OK)
            st = add_raster(b, &fill, g, s, angle_deg, err);
    }
    /* a region thinner than the step-over: centre lines over g itself */
    if (st == SR_OK && b->count == 0)
        st = add_raster(b, g, g, s, angle_deg, err);
    sr_poly2_release(&ring);
    sr_poly2_release(&fill);
    return st;
}
