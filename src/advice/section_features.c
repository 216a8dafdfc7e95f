/*
 * section_features.c: the feature-level description of missing sections
 * (section_features.h): finds a
 * section's cells again on the run's layer grid, measures them (widths, coverage,
 * cross-section loss, local radius), reads the part's features off the restored
 * outline along z (shoulders, end faces; ear/arm/edge for planar parts), classifies
 * the damage with the thresholds of features.h and writes it all as JSON.
 */
#include "advice/section_features.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/jsonbuf.h"

#define PI 3.14159265358979323846

static void add_reason(sr_features *f, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static void add_reason(sr_features *f, const char *fmt, ...)
{
    if (f->reason_count >= SR_FEAT_MAX_REASONS)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(f->reasons[f->reason_count++], sizeof f->reasons[0], fmt, ap);
    va_end(ap);
}

static void add_location(sr_features *f, const char *name)
{
    if (f->location_count < SR_FEAT_MAX_LOCATIONS)
        snprintf(f->locations[f->location_count++], sizeof f->locations[0], "%s", name);
}

/* Whether the run carries its per-layer polyline pairs. */
static bool have_outlines(const sr_run *run)
{
    return run->damaged_xy && run->restored_xy && run->layer_count > 0;
}

/* Radius of grid point (layer l, sector j) of xy, NaN when there is no point. */
static double radius_at(const sr_run *run, const double *xy, size_t l, size_t j)
{
    const double *p = xy + 2 * (l * run->sectors + j);
    if (isnan(p[0]) || isnan(p[1]))
        return NAN;
    return hypot(p[0], p[1]);
}

/* Whether sector j belongs to the section's sectors (its range, and its side). */
static bool sector_in(const sr_run_section *s, size_t j, size_t sectors)
{
    double step = 360.0 / (double)sectors;
    double c = ((double)j + 0.5) * step;
    if (s->has_angles) {
        double from = fmod(s->angle_from_deg, 360.0);
        if (from < 0)
            from += 360.0;
        double arc = s->angle_to_deg - s->angle_from_deg;
        if (arc <= 0)
            arc += 360.0;
        double off = fmod(c - from + 720.0, 360.0);
        if (!(off < arc))
            return false;
    }
    if (s->side != 0 && cos(c * PI / 180.0) * (double)s->side <= 0)
        return false;
    return true;
}

/* Whether (l, j) is a cell of section s: in its layers and sectors, and restored
 * beyond the damaged outline. */
static bool is_cell(const sr_run *run, const sr_run_section *s, size_t l, size_t j)
{
    if (l < s->layer_first || l > s->layer_last || !sector_in(s, j, run->sectors))
        return false;
    double ro = radius_at(run, run->restored_xy, l, j);
    double ri = radius_at(run, run->damaged_xy, l, j);
    if (isnan(ri))
        ri = 0;
    return !isnan(ro) && ro - ri > 1e-9 * (1 + ro);
}

/* Beside the loss, in the given direction (dl, dj one of (-1,0), (1,0), (0,-1), (0,1)):
 * the mean over the section's boundary cells of the neighbour's restored radius over
 * the cell's (capped at 1; a neighbour outside the part counts 0). 1 when no cell has
 * a neighbour there that is not itself a cell (e.g. a band all round). */
static double wall_ratio(const sr_run *run, const sr_run_section *s, int dl, int dj)
{
    size_t N = run->sectors;
    double sum = 0;
    size_t count = 0;
    for (size_t l = s->layer_first; l <= s->layer_last; l++) {
        for (size_t j = 0; j < N; j++) {
            if (!is_cell(run, s, l, j))
                continue;
            long nl = (long)l + dl;
            size_t nj = (j + N + (size_t)(dj + 1) - 1) % N;
            if (nl >= 0 && (size_t)nl < run->layer_count && is_cell(run, s, (size_t)nl, nj))
                continue;
            double ro = radius_at(run, run->restored_xy, l, j);
            double rn = nl >= 0 && (size_t)nl < run->layer_count
                            ? radius_at(run, run->restored_xy, (size_t)nl, nj) : NAN;
            sum += isnan(rn) ? 0 : fmin(1.0, rn / ro);
            count++;
        }
    }
    return count ? sum / (double)count : 1.0;
}

/* Layer spacing of the run's grid. */
static double grid_dz(const sr_run *run, const sr_run_section *s)
{
    if (run->layer_z && run->layer_count >= 2)
        return (run->layer_z[run->layer_count - 1] - run->layer_z[0]) /
               (double)(run->layer_count - 1);
    size_t n = s->layer_last - s->layer_first + 1;
    return (s->z_max_mm - s->z_min_mm) / (double)n;
}

/* The cell figures from the outlines. */
static sr_status measure_cells(const sr_run *run, const sr_run_section *s, sr_features *f,
                               sr_err *err)
{
    size_t N = run->sectors;
    double step_rad = 2 * PI / (double)N;
    double wedge = 0.5 * sin(step_rad);
    double dz = grid_dz(run, s);
    size_t *per_sector = calloc(N, sizeof *per_sector);
    if (!per_sector)
        return sr_err_set(err, SR_E_NOMEM, "out of memory describing section %zu", f->section);
    double circ_sum = 0, loss_max = 0, x_min = INFINITY, x_max = 0, half_width = 0;
    size_t layers_with_cells = 0;
    f->local_radius_mm = 0;
    for (size_t l = s->layer_first; l <= s->layer_last; l++) {
        double lost = 0, total = 0, circ = 0;
        size_t cells = 0;
        for (size_t j = 0; j < N; j++) {
            double ro = radius_at(run, run->restored_xy, l, j);
            if (isnan(ro))
                continue;
            total += wedge * ro * ro;
            bool in = sector_in(s, j, N);
            if (in && s->side != 0)
                half_width = fmax(half_width, fabs(run->restored_xy[2 * (l * N + j)]));
            double ri = radius_at(run, run->damaged_xy, l, j);
            if (isnan(ri))
                ri = 0;
            if (!in || !(ro - ri > 1e-9 * (1 + ro)))
                continue;
            cells++;
            per_sector[j]++;
            lost += wedge * (ro * ro - ri * ri);
            circ += ro * step_rad;
            f->local_radius_mm = fmax(f->local_radius_mm, ro);
            double ax = fabs(run->restored_xy[2 * (l * N + j)]);
            x_min = fmin(x_min, ax);
            x_max = fmax(x_max, ax);
        }
        if (cells) {
            layers_with_cells++;
            circ_sum += circ;
            f->cell_count += cells;
            if (total > 0)
                loss_max = fmax(loss_max, lost / total);
        }
    }
    size_t touched = 0, axial_cells = 0;
    for (size_t j = 0; j < N; j++) {
        if (per_sector[j]) {
            touched++;
            axial_cells += per_sector[j];
        }
    }
    free(per_sector);
    if (f->cell_count == 0) {
        /* The outlines do not show this section (e.g. a hand-made record): measure as
         * if there were no outlines. */
        f->have_cells = false;
        f->local_radius_mm = NAN;
        return SR_OK;
    }
    f->circ_width_mm = circ_sum / (double)layers_with_cells;
    f->axial_width_mm = (double)axial_cells / (double)touched * dz;
    double around = s->side != 0 ? (double)N / 2 : (double)N;
    f->coverage = fmin(1.0, (double)touched / around);
    double span = (double)touched * step_rad * f->local_radius_mm;
    f->length_mm = fmax(span, f->height_mm);
    f->breadth_mm = fmin(span, f->height_mm);
    bool narrow_in_z = f->axial_width_mm < f->circ_width_mm;
    f->wall_a = wall_ratio(run, s, narrow_in_z ? -1 : 0, narrow_in_z ? 0 : -1);
    f->wall_b = wall_ratio(run, s, narrow_in_z ? 1 : 0, narrow_in_z ? 0 : 1);
    f->layer_loss_max = loss_max;
    if (s->side != 0) {
        f->extent_min_mm = x_min;
        f->extent_max_mm = x_max;
        f->position = half_width > 0 ? x_max / half_width : NAN;
    }
    return SR_OK;
}

/* Figures without outlines: the section's range at the part's radius. */
static void measure_without_cells(const sr_run_section *s, const sr_feature_part *part,
                                  sr_features *f)
{
    double r = part && part->radius_mm > 0 ? part->radius_mm : NAN;
    f->local_radius_mm = r;
    double arc = s->has_angles ? f->arc_deg : (s->side != 0 ? 180.0 : 360.0);
    f->circ_width_mm = arc * PI / 180.0 * r;
    f->axial_width_mm = f->height_mm;
    f->coverage = arc / (s->side != 0 ? 180.0 : 360.0);
    f->length_mm = fmax(f->circ_width_mm, f->height_mm);
    f->breadth_mm = fmin(f->circ_width_mm, f->height_mm);
    add_reason(f, "no per-layer outlines: widths from the section's range%s",
               isnan(r) ? " (part radius unknown)" : " at the part's radius");
}

/* Restored radius of layer l at the section's sectors (0 = none there). */
static double profile_at(const sr_run *run, const sr_run_section *s, size_t l)
{
    double r = 0;
    for (size_t j = 0; j < run->sectors; j++) {
        if (!sector_in(s, j, run->sectors))
            continue;
        double ro = radius_at(run, run->restored_xy, l, j);
        if (!isnan(ro))
            r = fmax(r, ro);
    }
    return r;
}

static void find_locations(const sr_run *run, const sr_run_section *s, sr_features *f)
{
    f->shoulder_z_mm = NAN;
    if (have_outlines(run)) {
        double dz = grid_dz(run, s);
        size_t w = 2;
        if (dz > 0 && isfinite(f->depth_max_mm) && f->depth_max_mm / dz > 2)
            w = (size_t)ceil(f->depth_max_mm / dz);
        size_t lo = s->layer_first > w ? s->layer_first - w : 0;
        size_t hi = s->layer_last + w < run->layer_count ? s->layer_last + w
                                                         : run->layer_count - 1;
        double best = 0, prev = profile_at(run, s, lo);
        for (size_t l = lo; l < hi; l++) {
            double next = profile_at(run, s, l + 1);
            double big = fmax(prev, next), step = fabs(next - prev);
            if (prev > 0 && next > 0 && step > SR_FEAT_STEP_FRACTION * big &&
                step > SR_FEAT_STEP_MIN_MM && step > best) {
                best = step;
                f->shoulder_z_mm = run->layer_z ? 0.5 * (run->layer_z[l] + run->layer_z[l + 1])
                                                : NAN;
            }
            prev = next;
        }
        if (best > 0) {
            add_location(f, "shoulder");
            add_reason(f, "shoulder: the restored radius steps by %.3g mm beside the loss",
                       best);
        }
        size_t first = SIZE_MAX, last = 0;
        for (size_t l = 0; l < run->layer_count; l++) {
            for (size_t j = 0; j < run->sectors; j++) {
                if (!isnan(radius_at(run, run->restored_xy, l, j))) {
                    if (first == SIZE_MAX)
                        first = l;
                    last = l;
                    break;
                }
            }
        }
        if (first != SIZE_MAX && (s->layer_first <= first || s->layer_last >= last))
            add_location(f, "end_face");
    } else if (s->layer_first == 0 ||
               (run->layer_count > 0 && s->layer_last + 1 >= run->layer_count)) {
        add_location(f, "end_face");
    }
    if (s->side != 0 && !isnan(f->position))
        add_location(f, f->position >= 2.0 / 3.0 ? "ear"
                        : f->position >= 1.0 / 3.0 ? "arm" : "edge");
    if (f->location_count == 0)
        add_location(f, "body");
}

static void classify(sr_features *f)
{
    double d = f->depth_max_mm, w = f->width_mm;
    double pct_r = 100 * f->depth_fraction;
    bool walled = f->wall_a >= SR_FEAT_WALL_RATIO && f->wall_b >= SR_FEAT_WALL_RATIO;
    bool through = f->wall_a < SR_FEAT_WALL_RATIO && f->wall_b < SR_FEAT_WALL_RATIO;
    if (w <= SR_FEAT_CRACK_WIDTH_RATIO * d && walled) {
        strcpy(f->damage_class, "crack");
        add_reason(f, "crack: %.3g mm wide, at most %.2g x its depth %.3g mm, with the part on "
                   "both sides (narrow loss)", w, SR_FEAT_CRACK_WIDTH_RATIO, d);
        return;
    }
    add_reason(f, "not a crack: width %.3g mm vs %.2g x depth %.3g mm, part beside it on %s",
               w, SR_FEAT_CRACK_WIDTH_RATIO, d, walled ? "both sides" : through ? "neither side"
                                                                          : "one side");
    if (f->depth_fraction >= SR_FEAT_BROKEN_DEPTH_FRACTION) {
        strcpy(f->damage_class, "broken_feature");
        add_reason(f, "broken feature: %.3g mm deep is %.0f %% of the local radius %.3g mm "
                   "(>= %.0f %%)", d, pct_r, f->local_radius_mm,
                   100 * SR_FEAT_BROKEN_DEPTH_FRACTION);
        return;
    }
    if (f->layer_loss_max >= SR_FEAT_BROKEN_LAYER_LOSS) {
        strcpy(f->damage_class, "broken_feature");
        add_reason(f, "broken feature: a layer loses %.0f %% of its cross-section (>= %.0f %%)",
                   100 * f->layer_loss_max, 100 * SR_FEAT_BROKEN_LAYER_LOSS);
        return;
    }
    if (through && d >= w) {
        strcpy(f->damage_class, "broken_feature");
        add_reason(f, "broken feature: the loss goes through the feature's whole %.3g mm "
                   "thickness (nothing of the part beside it) and is %.3g mm deep", w, d);
        return;
    }
    add_reason(f, "not broken: depth %.0f %% of the local radius (< %.0f %%), largest layer "
               "loss %.0f %% (< %.0f %%), not through a feature", pct_r,
               100 * SR_FEAT_BROKEN_DEPTH_FRACTION, 100 * f->layer_loss_max,
               100 * SR_FEAT_BROKEN_LAYER_LOSS);
    if (f->coverage >= SR_FEAT_WEAR_COVERAGE && f->depth_fraction <= SR_FEAT_WEAR_DEPTH_FRACTION) {
        strcpy(f->damage_class, "wear_band");
        add_reason(f, "wear band: covers %.0f %% of the way round (>= %.0f %%), %.0f %% of the "
                   "radius deep (<= %.0f %%)", 100 * f->coverage, 100 * SR_FEAT_WEAR_COVERAGE,
                   pct_r, 100 * SR_FEAT_WEAR_DEPTH_FRACTION);
        return;
    }
    add_reason(f, "not a wear band: covers %.0f %% of the way round, %.0f %% of the radius deep "
               "(needs >= %.0f %% and <= %.0f %%)", 100 * f->coverage, pct_r,
               100 * SR_FEAT_WEAR_COVERAGE, 100 * SR_FEAT_WEAR_DEPTH_FRACTION);
    if (f->aspect >= SR_FEAT_GOUGE_ASPECT) {
        strcpy(f->damage_class, "gouge");
        add_reason(f, "gouge: %.3g mm long, %.3g x its breadth %.3g mm (>= %.0f)", f->length_mm,
                   f->aspect, f->breadth_mm, SR_FEAT_GOUGE_ASPECT);
        return;
    }
    strcpy(f->damage_class, "chip");
    add_reason(f, "chip: local loss %.3g mm long by %.3g mm (length/breadth %.3g < %.0f), "
               "%.3g mm deep", f->length_mm, f->breadth_mm, f->aspect, SR_FEAT_GOUGE_ASPECT, d);
}

sr_status sr_features_compute(const sr_run *run, size_t index, const sr_feature_part *part,
                              sr_features *out, sr_err *err)
{
    if (index >= run->section_count)
        return sr_err_set(err, SR_E_RANGE, "no section %zu in the run (it has %zu)", index,
                          run->section_count);
    const sr_run_section *s = &run->sections[index];
    if (s->layer_last < s->layer_first)
        return sr_err_set(err, SR_E_RANGE, "section %zu: layer_last %zu < layer_first %zu",
                          index, s->layer_last, s->layer_first);
    if (!(s->z_max_mm >= s->z_min_mm))
        return sr_err_set(err, SR_E_RANGE, "section %zu: z_max_mm < z_min_mm", index);
    if (s->side != 0 && s->side != 1 && s->side != -1)
        return sr_err_set(err, SR_E_RANGE, "section %zu: side %d is not -1, 0 or +1", index,
                          s->side);
    bool outlines = have_outlines(run);
    if (outlines) {
        if (run->sectors < 3)
            return sr_err_set(err, SR_E_RANGE, "run has %zu sectors: expected >= 3",
                              run->sectors);
        if (s->layer_last >= run->layer_count)
            return sr_err_set(err, SR_E_RANGE, "section %zu: layer %zu beyond the run's %zu "
                              "layers", index, s->layer_last, run->layer_count);
    }

    sr_features f;
    memset(&f, 0, sizeof f);
    f.section = index;
    f.axial = s->has_angles && s->side == 0;
    f.layer_first = s->layer_first;
    f.layer_last = s->layer_last;
    f.layer_count = s->layer_last - s->layer_first + 1;
    f.z_min_mm = s->z_min_mm;
    f.z_max_mm = s->z_max_mm;
    f.height_mm = s->z_max_mm - s->z_min_mm;
    f.angle_min_deg = f.angle_max_deg = f.arc_deg = NAN;
    if (s->has_angles) {
        f.angle_min_deg = s->angle_from_deg;
        f.arc_deg = s->angle_to_deg - s->angle_from_deg;
        if (f.arc_deg <= 0)
            f.arc_deg += 360.0;
        f.angle_max_deg = f.angle_min_deg + f.arc_deg;
    }
    f.side = s->side;
    f.extent_min_mm = f.extent_max_mm = f.position = NAN;
    f.depth_max_mm = s->depth_max_mm;
    f.depth_mean_mm = s->depth_mean_mm;
    f.volume_mm3 = s->volume_mm3;
    f.area_mm2 = s->area_mm2;
    f.part_fraction = part && part->volume_mm3 > 0 ? s->volume_mm3 / part->volume_mm3 : NAN;
    f.layer_loss_max = NAN;
    f.wall_a = f.wall_b = NAN;
    f.have_cells = outlines;
    if (outlines) {
        sr_status st = measure_cells(run, s, &f, err);
        if (st != SR_OK)
            return st;
    }
    if (!f.have_cells)
        measure_without_cells(s, part, &f);
    f.width_mm = fmin(f.circ_width_mm, f.axial_width_mm);
    f.aspect = f.breadth_mm > 0 ? f.length_mm / f.breadth_mm : NAN;
    f.depth_fraction = f.local_radius_mm > 0 ? f.depth_max_mm / f.local_radius_mm : NAN;
    find_locations(run, s, &f);
    if (isnan(f.part_fraction))
        add_reason(&f, "part volume unknown: no fraction of the part");
    classify(&f);
    *out = f;
    return SR_OK;
}

/* ---- by name, for rules ---- */

typedef struct figure {
    const char *name;
    size_t offset;
    int only;           /* 0 any section, 1 axial only, -1 planar only */
} figure;

#define FIG(name, only) {#name, offsetof(sr_features, name), only}
static const figure figures[] = {
    FIG(z_min_mm, 0), FIG(z_max_mm, 0), FIG(height_mm, 0),
    {"angle_min_deg", offsetof(sr_features, angle_min_deg), 1},
    {"angle_max_deg", offsetof(sr_features, angle_max_deg), 1},
    FIG(arc_deg, 1),
    {"extent_from_plane_min_mm", offsetof(sr_features, extent_min_mm), -1},
    {"extent_from_plane_max_mm", offsetof(sr_features, extent_max_mm), -1},
    {"position_from_plane", offsetof(sr_features, position), -1},
    FIG(depth_max_mm, 0), FIG(depth_mean_mm, 0), FIG(volume_mm3, 0), FIG(area_mm2, 0),
    FIG(part_fraction, 0), FIG(local_radius_mm, 0), FIG(depth_fraction, 0),
    FIG(circ_width_mm, 0), FIG(axial_width_mm, 0), FIG(width_mm, 0), FIG(length_mm, 0),
    FIG(breadth_mm, 0), FIG(wall_a, 0), FIG(wall_b, 0),
    FIG(aspect, 0), FIG(coverage, 0), FIG(layer_loss_max, 0), FIG(shoulder_z_mm, 0),
};
#undef FIG
static const size_t figure_count = sizeof figures / sizeof figures[0];

static double figure_value(const sr_features *f, const figure *fig)
{
    return *(const double *)((const char *)f + fig->offset);
}

bool sr_features_is_figure(const char *name)
{
    for (size_t i = 0; i < figure_count; i++)
        if (strcmp(figures[i].name, name) == 0)
            return true;
    return name && (strcmp(name, "layer_count") == 0 || strcmp(name, "cells") == 0 ||
                    strcmp(name, "side") == 0);
}

bool sr_features_value(const sr_features *f, const char *name, double *out)
{
    double v = NAN;
    if (strcmp(name, "layer_count") == 0) {
        v = (double)f->layer_count;
    } else if (strcmp(name, "cells") == 0) {
        v = f->have_cells ? (double)f->cell_count : NAN;
    } else if (strcmp(name, "side") == 0) {
        v = f->side != 0 ? (double)f->side : NAN;
    } else {
        for (size_t i = 0; i < figure_count; i++) {
            if (strcmp(figures[i].name, name) != 0)
                continue;
            bool planar = f->side != 0;
            if ((figures[i].only == 1 && (planar || !isfinite(f->arc_deg))) ||
                (figures[i].only == -1 && !planar))
                return false;
            v = figure_value(f, &figures[i]);
            break;
        }
    }
    if (isnan(v))
        return false;
    *out = v;
    return true;
}

bool sr_features_at(const sr_features *f, const char *location)
{
    for (size_t i = 0; i < f->location_count; i++)
        if (strcmp(f->locations[i], location) == 0)
            return true;
    return false;
}

sr_status sr_features_to_json(const sr_features *f, char **out, sr_err *err)
{
    sr_jsonbuf jb;
    sr_jsonbuf_init(&jb);
    sr_jsonbuf_object_begin(&jb);
    sr_jsonbuf_key(&jb, "class");
    sr_jsonbuf_string(&jb, f->damage_class);
    sr_jsonbuf_key(&jb, "layers");
    sr_jsonbuf_object_begin(&jb);
    sr_jsonbuf_key(&jb, "first");
    sr_jsonbuf_int(&jb, (int64_t)f->layer_first);
    sr_jsonbuf_key(&jb, "last");
    sr_jsonbuf_int(&jb, (int64_t)f->layer_last);
    sr_jsonbuf_key(&jb, "count");
    sr_jsonbuf_int(&jb, (int64_t)f->layer_count);
    sr_jsonbuf_object_end(&jb);
    if (f->side != 0) {
        sr_jsonbuf_key(&jb, "side");
        sr_jsonbuf_int(&jb, f->side);
    }
    for (size_t i = 0; i < figure_count; i++) {
        const figure *fig = &figures[i];
        if ((fig->only == 1 && f->side != 0) || (fig->only == 1 && !isfinite(f->arc_deg)) ||
            (fig->only == -1 && f->side == 0))
            continue;
        if (strcmp(fig->name, "shoulder_z_mm") == 0 && isnan(f->shoulder_z_mm))
            continue;
        sr_jsonbuf_key(&jb, fig->name);
        sr_jsonbuf_number(&jb, figure_value(f, fig));
    }
    sr_jsonbuf_key(&jb, "cells");
    if (f->have_cells)
        sr_jsonbuf_int(&jb, (int64_t)f->cell_count);
    else
        sr_jsonbuf_null(&jb);
    sr_jsonbuf_key(&jb, "location");
    sr_jsonbuf_string(&jb, f->location_count ? f->locations[0] : NULL);
    sr_jsonbuf_key(&jb, "locations");
    sr_jsonbuf_array_begin(&jb);
    for (size_t i = 0; i < f->location_count; i++)
        sr_jsonbuf_string(&jb, f->locations[i]);
    sr_jsonbuf_array_end(&jb);
    sr_jsonbuf_key(&jb, "surface");
    sr_jsonbuf_string(&jb, "outer");
    sr_jsonbuf_key(&jb, "reasons");
    sr_jsonbuf_array_begin(&jb);
    for (size_t i = 0; i < f->reason_count; i++)
        sr_jsonbuf_string(&jb, f->reasons[i]);
    sr_jsonbuf_array_end(&jb);
    sr_jsonbuf_object_end(&jb);
    return sr_jsonbuf_take(&jb, out, err);
}

sr_status sr_features_describe(sr_run *run, const sr_feature_part *part, sr_err *err)
{
    size_t n = run->section_count;
    if (n == 0)
        return SR_OK;
    char **json = calloc(n, sizeof *json);
    sr_features *fs = calloc(n, sizeof *fs);
    sr_status st = SR_OK;
    if (!json || !fs)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory describing %zu sections", n);
    for (size_t i = 0; st == SR_OK && i < n; i++) {
        st = sr_features_compute(run, i, part, &fs[i], err);
        if (st == SR_OK)
            st = sr_features_to_json(&fs[i], &json[i], err);
    }
    if (st == SR_OK) {
        for (size_t i = 0; i < n; i++) {
            sr_run_section *s = &run->sections[i];
            free(s->features_json);
            s->features_json = json[i];
            snprintf(s->damage_class, sizeof s->damage_class, "%s", fs[i].damage_class);
        }
    } else if (json) {
        for (size_t i = 0; i < n; i++)
            free(json[i]);
    }
    free(json);
    free(fs);
    return st;
}
