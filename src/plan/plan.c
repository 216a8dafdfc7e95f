/*
 * plan.c: the build plan of one missing section (see plan.h for the construction):
 * per-layer missing regions from the run's polyline pairs, the deposit region with its
 * machining allowance, contour rings and zig-zag rasters, and the plan's figures.
 * Polygon booleans, offsets and clipping are Clipper's (bridge/polygon.h); this file
 * only decides what to ask for and orders the result.
 */
#include "plan/plan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define MIN_PIECE_AREA_MM2 1e-4 /* missing pieces smaller than this are rounding dust */
#define MAX_RINGS 10000

const char *sr_plan_pattern_name(sr_plan_pattern pattern)
{
    switch (pattern) {
    case SR_PLAN_CONTOUR_RASTER: return "contour+raster";
    case SR_PLAN_CONTOUR: return "contour";
    case SR_PLAN_RASTER: return "raster";
    }
    return "unknown";
}

sr_status sr_plan_pattern_parse(const char *text, const char *field, sr_plan_pattern *out,
                                sr_err *err)
{
    static const sr_plan_pattern all[] = {SR_PLAN_CONTOUR_RASTER, SR_PLAN_CONTOUR,
                                          SR_PLAN_RASTER};
    for (size_t i = 0; text && i < sizeof all / sizeof all[0]; i++)
        if (strcmp(text, sr_plan_pattern_name(all[i])) == 0) {
            *out = all[i];
            return SR_OK;
        }
    return sr_err_set(err, SR_E_RANGE,
                      "%s '%s' is not one of contour+raster, contour, raster", field,
                      text ? text : "");
}

/* The defaults of plan.h: what sr_plan_opts_init gives and what a 0 stands for
 * (layer_mm 0 stays: the run's spacing, filled in by sr_plan_build). */
static const sr_plan_opts plan_defaults = {
    .step_over_mm = 1.0,
    .allowance_mm = 0.5,
    .layer_mm = 0,
    .density_g_cm3 = 7.85,
    .rate_cm3_min = 1.0,
    .raster_angle_deg = 0,
    .pattern = SR_PLAN_CONTOUR_RASTER,
};

void sr_plan_opts_init(sr_plan_opts *opts)
{
    *opts = plan_defaults;
}

/* o with each 0 that stands for a default replaced by it (allowance 0 is none). */
static sr_plan_opts with_defaults(sr_plan_opts o)
{
    if (o.step_over_mm == 0)
        o.step_over_mm = plan_defaults.step_over_mm;
    if (o.density_g_cm3 == 0)
        o.density_g_cm3 = plan_defaults.density_g_cm3;
    if (o.rate_cm3_min == 0)
        o.rate_cm3_min = plan_defaults.rate_cm3_min;
    return o;
}

sr_status sr_plan_opts_check(const sr_plan_opts *o, sr_err *err)
{
    if (!(o->step_over_mm >= 0) || !isfinite(o->step_over_mm) || o->step_over_mm > 1e4)
        return sr_err_set(err, SR_E_RANGE,
                          "step_over_mm must be > 0 (or 0 for 1 mm) and <= 10000, got %g",
                          o->step_over_mm);
    if (!(o->allowance_mm >= 0) || !isfinite(o->allowance_mm) || o->allowance_mm > 1e4)
        return sr_err_set(err, SR_E_RANGE, "allowance_mm must be >= 0 and <= 10000, got %g",
                          o->allowance_mm);
    if (!(o->layer_mm >= 0) || !isfinite(o->layer_mm))
        return sr_err_set(err, SR_E_RANGE,
                          "layer_mm must be > 0 (or 0 for the run's spacing), got %g",
                          o->layer_mm);
    if (!(o->density_g_cm3 >= 0) || !isfinite(o->density_g_cm3))
        return sr_err_set(err, SR_E_RANGE, "density_g_cm3 must be > 0 (or 0 for 7.85), got %g",
                          o->density_g_cm3);
    if (!(o->rate_cm3_min >= 0) || !isfinite(o->rate_cm3_min))
        return sr_err_set(err, SR_E_RANGE, "rate_cm3_min must be > 0 (or 0 for 1), got %g",
                          o->rate_cm3_min);
    if (!isfinite(o->raster_angle_deg))
        return sr_err_set(err, SR_E_RANGE, "raster_angle_deg must be finite, got %g",
                          o->raster_angle_deg);
    if (o->pattern != SR_PLAN_CONTOUR_RASTER && o->pattern != SR_PLAN_CONTOUR &&
        o->pattern != SR_PLAN_RASTER)
        return sr_err_set(err, SR_E_RANGE, "pattern %d is not a plan pattern",
                          (int)o->pattern);
    return SR_OK;
}

/* ---- growable list of polylines ---- */

typedef struct pathbuf {
    double *xy;
    size_t n, cap;            /* points */
    size_t *start;            /* count + 1 entries once anything is added */
    unsigned char *kind;
    size_t count, scap;       /* polylines */
} pathbuf;

static void pathbuf_release(pathbuf *b)
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
static void pathbuf_take(pathbuf *b, sr_poly2 *paths, unsigned char **kind)
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

static double polyline_length(const double *xy, size_t n)
{
    double len = 0;
    for (size_t i = 1; i < n; i++)
        len += hypot(xy[2 * i] - xy[2 * i - 2], xy[2 * i + 1] - xy[2 * i - 1]);
    return len;
}

/* ---- regions ---- */

/* The outline of run layer l (damaged or restored) as a clean region; the points of
 * sectors without one are left out. Fewer than 3 points: empty. */
static sr_status outline_region(const sr_run *run, const double *grid, size_t l,
                                sr_poly2 *out, sr_err *err)
{
    size_t n = run->sectors;
    const double *row = grid + 2 * l * n;
    double *xy = malloc(n * 2 * sizeof(double));
    if (!xy)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for layer %zu's outline", l);
    size_t k = 0;
    for (size_t j = 0; j < n; j++)
        if (isfinite(row[2 * j]) && isfinite(row[2 * j + 1])) {
            xy[2 * k] = row[2 * j];
            xy[2 * k + 1] = row[2 * j + 1];
            k++;
        }
    sr_status st = SR_OK;
    sr_poly2 raw;
    sr_poly2_init(&raw);
    if (k >= 3)
        st = sr_poly2_add_contour(&raw, xy, k, err);
    free(xy);
    if (st == SR_OK)
        st = sr_poly2_boolean(SR_POLY_UNION, &raw, NULL, out, err);
    sr_poly2_release(&raw);
    return st;
}

/* Drops pieces of less than MIN_PIECE_AREA_MM2 from r (in place). */
static sr_status drop_specks(sr_poly2 *r, sr_err *err)
{
    sr_poly2 *parts = NULL, keep;
    size_t count = 0;
    sr_poly2_init(&keep);
    sr_status st = sr_poly2_components(r, &parts, &count, err);
    for (size_t i = 0; st == SR_OK && i < count; i++)
        if (sr_poly2_area(&parts[i]) >= MIN_PIECE_AREA_MM2)
            st = sr_poly2_boolean(SR_POLY_UNION, &keep, &parts[i], &keep, err);
    sr_poly2_components_release(parts, count);
    if (st == SR_OK) {
        sr_poly2_release(r);
        *r = keep;
    } else {
        sr_poly2_release(&keep);
    }
    return st;
}

/* The section's wedge (axial) or half-plane (planar) as a region reaching beyond
 * radius `reach`; *none = 1 when the section is not restricted (a full ring). */
static sr_status section_window(const sr_plan *p, double half_sector_deg, double reach,
                                sr_poly2 *out, int *none, sr_err *err)
{
    *none = 0;
    if (p->has_angles) {
        double from = p->angle_from_deg - half_sector_deg;
        double to = p->angle_to_deg + half_sector_deg;
        if (to - from >= 360.0) {
            *none = 1;
            return SR_OK;
        }
        size_t steps = (size_t)ceil((to - from) / 5.0) + 1; /* chords of at most 5 deg */
        double *xy = malloc((steps + 2) * 2 * sizeof(double));
        if (!xy)
            return sr_err_set(err, SR_E_NOMEM, "out of memory for the section's wedge");
        xy[0] = xy[1] = 0;
        /* the chord of a 5 degree step sits within reach * (1 - cos 2.5 deg): reach
         * is chosen so that this stays beyond every outline point */
        for (size_t i = 0; i <= steps; i++) {
            double a = (from + (to - from) * (double)i / (double)steps) * PI / 180.0;
            xy[2 * (i + 1)] = reach * cos(a);
            xy[2 * (i + 1) + 1] = reach * sin(a);
        }
        sr_poly2 w;
        sr_poly2_init(&w);
        sr_status st = sr_poly2_add_contour(&w, xy, steps + 2, err);
        free(xy);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_UNION, &w, NULL, out, err);
        sr_poly2_release(&w);
        return st;
    }
    if (p->side == 0) {
        *none = 1;
        return SR_OK;
    }
    double x0 = p->side > 0 ? 0 : -reach, x1 = p->side > 0 ? reach : 0;
    double box[8] = {x0, -reach, x1, -reach, x1, reach, x0, reach};
    sr_poly2 w;
    sr_poly2_init(&w);
    sr_status st = sr_poly2_add_contour(&w, box, 4, err);
    if (st == SR_OK)
        st = sr_poly2_boolean(SR_POLY_UNION, &w, NULL, out, err);
    sr_poly2_release(&w);
    return st;
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
        got += polyline_length(out.xy + 2 * out.start[c], out.start[c + 1] - out.start[c]);
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
static sr_status layer_paths(const sr_plan_opts *o, const sr_poly2 *g, double angle_deg,
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

/* ---- the plan ---- */

static void layer_release(sr_plan_layer *l)
{
    sr_poly2_release(&l->damaged);
    sr_poly2_release(&l->missing);
    sr_poly2_release(&l->region);
    sr_poly2_release(&l->paths);
    free(l->path_kind);
    l->path_kind = NULL;
}

void sr_plan_release(sr_plan *plan)
{
    if (!plan)
        return;
    for (size_t i = 0; plan->layers && i < plan->layer_count; i++)
        layer_release(&plan->layers[i]);
    free(plan->layers);
    memset(plan, 0, sizeof *plan);
}

/* Checks the run's layer arrays against the section. */
static sr_status check_run_layers(const sr_run *run, const sr_run_section *sec, sr_err *err)
{
    if (run->layer_count == 0 || !run->layer_z || !run->damaged_xy || !run->restored_xy)
        return sr_err_set(err, SR_E_INVALID, "run %lld has no layer polylines",
                          (long long)run->id);
    if (run->sectors < 3)
        return sr_err_set(err, SR_E_INVALID, "run %lld has %zu sectors, needs at least 3",
                          (long long)run->id, run->sectors);
    if (sec->layer_first > sec->layer_last || sec->layer_last >= run->layer_count)
        return sr_err_set(err, SR_E_INVALID,
                          "section %zu of run %lld covers layers %zu..%zu but the run has "
                          "%zu layers",
                          sec->index + 1, (long long)run->id, sec->layer_first,
                          sec->layer_last, run->layer_count);
    if (!(sec->z_max_mm > sec->z_min_mm) || !isfinite(sec->z_min_mm) ||
        !isfinite(sec->z_max_mm))
        return sr_err_set(err, SR_E_INVALID, "section %zu of run %lld has z range %g..%g mm",
                          sec->index + 1, (long long)run->id, sec->z_min_mm, sec->z_max_mm);
    for (size_t l = 0; l < run->layer_count; l++)
        if (!isfinite(run->layer_z[l]) || (l > 0 && !(run->layer_z[l] > run->layer_z[l - 1])))
            return sr_err_set(err, SR_E_INVALID,
                              "run %lld layer %zu height %g is not above the layer below",
                              (long long)run->id, l, run->layer_z[l]);
    return SR_OK;
}

/* Largest distance from the z axis of any outline point of the section's layers. */
static double outline_reach(const sr_run *run, const sr_run_section *sec)
{
    double r = 0;
    const double *grids[2] = {run->damaged_xy, run->restored_xy};
    for (int g = 0; g < 2; g++)
        for (size_t l = sec->layer_first; l <= sec->layer_last; l++)
            for (size_t j = 0; j < run->sectors; j++) {
                const double *p = grids[g] + 2 * (l * run->sectors + j);
                if (isfinite(p[0]) && isfinite(p[1]))
                    r = fmax(r, hypot(p[0], p[1]));
            }
    return r;
}

sr_status sr_plan_build(const sr_run *run, size_t section_index, const sr_plan_opts *opts,
                        sr_plan *out, sr_err *err)
{
    sr_plan_opts o = plan_defaults;
    if (opts)
        o = *opts;
    sr_status st = sr_plan_opts_check(&o, err);
    if (st != SR_OK)
        return st;
    o = with_defaults(o);
    const sr_run_section *sec = NULL;
    for (size_t i = 0; i < run->section_count; i++)
        if (run->sections[i].index == section_index)
            sec = &run->sections[i];
    if (!sec)
        return sr_err_set(err, SR_E_NOTFOUND, "run %lld has no section %zu",
                          (long long)run->id, section_index + 1);
    if (run->symmetry.kind == SR_SYM_NONE)
        return sr_err_set(err, SR_E_RANGE, "run %lld has no symmetry kind",
                          (long long)run->id);
    st = check_run_layers(run, sec, err);
    if (st != SR_OK)
        return st;

    size_t run_layers = sec->layer_last - sec->layer_first + 1;
    double dz = run->layer_count >= 2
                    ? (run->layer_z[run->layer_count - 1] - run->layer_z[0]) /
                          (double)(run->layer_count - 1)
                    : (sec->z_max_mm - sec->z_min_mm) / (double)run_layers;
    if (o.layer_mm == 0)
        o.layer_mm = dz;
    double height = sec->z_max_mm - sec->z_min_mm;
    double nl = ceil(height / o.layer_mm - 1e-9);
    if (nl < 1)
        nl = 1;
    if (nl > SR_PLAN_MAX_LAYERS)
        return sr_err_set(err, SR_E_RANGE,
                          "layer_mm %g gives %.0f layers over %g mm (at most %d)", o.layer_mm,
                          nl, height, SR_PLAN_MAX_LAYERS);

    sr_plan p;
    memset(&p, 0, sizeof p);
    p.run_id = run->id;
    p.section_index = sec->index;
    p.kind = run->symmetry.kind;
    p.has_angles = sec->has_angles;
    p.angle_from_deg = sec->angle_from_deg;
    p.angle_to_deg = sec->angle_to_deg;
    p.side = sec->side;
    p.z_min_mm = sec->z_min_mm;
    p.z_max_mm = sec->z_max_mm;
    p.opts = o;
    p.layer_count = (size_t)nl;

    sr_poly2 *miss = calloc(run_layers, sizeof *miss);   /* per run layer: M */
    sr_poly2 *dam = calloc(run_layers, sizeof *dam);     /* per run layer: damaged */
    sr_poly2 window, restored, grown;
    sr_poly2_init(&window);
    sr_poly2_init(&restored);
    sr_poly2_init(&grown);
    int unrestricted = 0;
    pathbuf pb;
    memset(&pb, 0, sizeof pb);
    p.layers = calloc(p.layer_count, sizeof *p.layers);
    if (!miss || !dam || !p.layers) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu plan layers", p.layer_count);
        goto cleanup;
    }
    double reach = 2.0 * outline_reach(run, sec) + 10.0;
    st = section_window(&p, 180.0 / (double)run->sectors, reach, &window, &unrestricted, err);

    /* M for every run layer of the section */
    for (size_t i = 0; st == SR_OK && i < run_layers; i++) {
        size_t l = sec->layer_first + i;
        st = outline_region(run, run->restored_xy, l, &restored, err);
        if (st == SR_OK)
            st = outline_region(run, run->damaged_xy, l, &dam[i], err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_DIFFERENCE, &restored, &dam[i], &miss[i], err);
        if (st == SR_OK && !unrestricted)
            st = sr_poly2_boolean(SR_POLY_INTERSECTION, &miss[i], &window, &miss[i], err);
        if (st == SR_OK)
            st = drop_specks(&miss[i], err);
    }

    /* plan layers: union of the overlapping run layers, grown, paths */
    for (size_t k = 0; st == SR_OK && k < p.layer_count; k++) {
        sr_plan_layer *L = &p.layers[k];
        L->z_bottom_mm = p.z_min_mm + (double)k * o.layer_mm;
        L->z_top_mm = L->z_bottom_mm + o.layer_mm;
        L->raster_angle_deg = fmod(o.raster_angle_deg + (k % 2 ? 90.0 : 0.0), 360.0);
        sr_poly2 damaged_union;
        sr_poly2_init(&damaged_union);
        int found = 0;
        for (size_t i = 0; st == SR_OK && i < run_layers; i++) {
            double zl = run->layer_z[sec->layer_first + i];
            double lo = fmax(zl - 0.5 * dz, L->z_bottom_mm), hi = fmin(zl + 0.5 * dz, L->z_top_mm);
            if (hi - lo <= 1e-6)
                continue;
            if (!found) {
                L->run_layer_first = sec->layer_first + i;
                st = sr_poly2_copy(&dam[i], &L->damaged, err);
            }
            found = 1;
            L->run_layer_last = sec->layer_first + i;
            if (st == SR_OK)
                st = sr_poly2_boolean(SR_POLY_UNION, &L->missing, &miss[i], &L->missing, err);
            if (st == SR_OK)
                st = sr_poly2_boolean(SR_POLY_UNION, &damaged_union, &dam[i], &damaged_union,
                                      err);
        }
        if (st == SR_OK && !found) { /* a plan layer above the run's layers: the top one */
            L->run_layer_first = L->run_layer_last = sec->layer_last;
            st = sr_poly2_copy(&miss[run_layers - 1], &L->missing, err);
            if (st == SR_OK)
                st = sr_poly2_copy(&dam[run_layers - 1], &L->damaged, err);
            if (st == SR_OK)
                st = sr_poly2_copy(&dam[run_layers - 1], &damaged_union, err);
        }
        if (st == SR_OK)
            st = sr_poly2_offset(&L->missing, o.allowance_mm, 1, &grown, err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_DIFFERENCE, &grown, &damaged_union, &L->region, err);
        sr_poly2_release(&damaged_union);
        if (st == SR_OK)
            st = layer_paths(&o, &L->region, L->raster_angle_deg, &pb, err);
        if (st != SR_OK)
            break;
        pathbuf_take(&pb, &L->paths, &L->path_kind);
        L->missing_area_mm2 = sr_poly2_area(&L->missing);
        L->region_area_mm2 = sr_poly2_area(&L->region);
        for (size_t c = 0; c < L->paths.contour_count; c++)
            L->path_length_mm += polyline_length(L->paths.xy + 2 * L->paths.start[c],
                                                 L->paths.start[c + 1] - L->paths.start[c]);
        p.missing_volume_mm3 += L->missing_area_mm2 * o.layer_mm;
        p.deposit_volume_mm3 += L->region_area_mm2 * o.layer_mm;
        p.path_length_mm += L->path_length_mm;
    }
    if (st == SR_OK) {
        p.deposit_mass_g = p.deposit_volume_mm3 / 1000.0 * o.density_g_cm3;
        p.build_time_min = p.deposit_volume_mm3 / 1000.0 / o.rate_cm3_min;
    }

cleanup:
    for (size_t i = 0; i < run_layers; i++) {
        if (miss)
            sr_poly2_release(&miss[i]);
        if (dam)
            sr_poly2_release(&dam[i]);
    }
    free(miss);
    free(dam);
    sr_poly2_release(&window);
    sr_poly2_release(&restored);
    sr_poly2_release(&grown);
    pathbuf_release(&pb);
    if (st != SR_OK) {
        sr_plan_release(&p);
        return st;
    }
    *out = p;
    return SR_OK;
}
