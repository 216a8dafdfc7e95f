/*
 * plan.c: the build plan of one missing section (see plan.h for the construction):
 * per-layer missing regions from the run's polyline pairs, the deposit region with its
 * machining allowance, and the plan's figures. The contour rings and zig-zag rasters of
 * each layer are plan_paths.c's (plan_int.h). Polygon booleans, offsets and clipping
 * are Clipper's (bridge/polygon.h); this file only decides what to ask for and orders
 * the result.
 */
#include "plan/plan_export.h"
#include "plan/plan_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MIN_PIECE_AREA_MM2 1e-4 /* missing pieces smaller than this are rounding dust */

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
            st = pl_layer_paths(&o, &L->region, L->raster_angle_deg, &pb, err);
        if (st != SR_OK)
            break;
        pathbuf_take(&pb, &L->paths, &L->path_kind);
        L->missing_area_mm2 = sr_poly2_area(&L->missing);
        L->region_area_mm2 = sr_poly2_area(&L->region);
        for (size_t c = 0; c < L->paths.contour_count; c++)
            L->path_length_mm += pl_polyline_length(L->paths.xy + 2 * L->paths.start[c],
                                                    L->paths.start[c + 1] - L->paths.start[c]);
        p.missing_volume_mm3 += L->missing_area_mm2 * o.layer_mm;
        p.deposit_volume_mm3 += L->region_area_mm2 * o.layer_mm;
        p.path_length_mm += L->path_length_mm;
    }
    if (st == SR_OK) {
        p.deposit_mass_g = p.deposit_volume_mm3 / 1000.0 * o.density_g_cm3;
        p.preheat_c = NAN;
        st = sr_plan_time(&p, NULL, err);
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
