/*
 * plan_export.c: the writers of a build plan: plan.json, one SVG drawing per layer and
 * plan.gcode (formats in plan_export.h). Each file is created in place (mode 0666 &
 * ~umask, like fopen) and removed when its write fails; the command line writes the
 * whole set into a staging folder and puts it in place at once (cli/outset.h), so
 * no reader sees half a file or half a set.
 * Coordinates are written with 5 decimals (the polygon grid is 1e-5 mm, so nothing is
 * lost); figures with 10 significant digits.
 */
#include "plan/plan_export.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/version.h"

void sr_plan_machine_init(sr_plan_machine *m)
{
    memset(m, 0, sizeof *m);
    m->feed_mm_min = 0;
    m->rapid_mm_min = 5000;
    m->travel_height_mm = 5;
    strcpy(m->on_code, "M3");
    strcpy(m->off_code, "M5");
}

static sr_status check_code(const char *code, size_t cap, const char *field, sr_err *err)
{
    size_t n = strnlen(code, cap);
    if (n == 0 || n == cap)
        return sr_err_set(err, SR_E_RANGE, "%s must be 1..%zu characters", field, cap - 1);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)code[i];
        if (c < 0x20 || c > 0x7e || c == ';' || c == '(' || c == ')')
            return sr_err_set(err, SR_E_RANGE,
                              "%s '%s' may hold only printable characters without ';', "
                              "'(' or ')'",
                              field, code);
    }
    return SR_OK;
}

sr_status sr_plan_machine_check(const sr_plan_machine *m, sr_err *err)
{
    if (!(m->feed_mm_min >= 0 && m->feed_mm_min <= 1e6))
        return sr_err_set(err, SR_E_RANGE,
                          "feed_mm_min must be > 0 (or 0 for the rate's) and <= 1e6, got %g",
                          m->feed_mm_min);
    if (!(m->rapid_mm_min > 0 && m->rapid_mm_min <= 1e6))
        return sr_err_set(err, SR_E_RANGE, "rapid_mm_min must be > 0 and <= 1e6, got %g",
                          m->rapid_mm_min);
    if (!(m->travel_height_mm >= 0 && m->travel_height_mm <= 1e4))
        return sr_err_set(err, SR_E_RANGE,
                          "travel_height_mm must be >= 0 and <= 10000, got %g",
                          m->travel_height_mm);
    sr_status st = check_code(m->on_code, sizeof m->on_code, "on_code", err);
    if (st == SR_OK)
        st = check_code(m->off_code, sizeof m->off_code, "off_code", err);
    return st;
}

/* ---- file writing ---- */

typedef struct outfile {
    FILE *f;
    const char *path;
} outfile;

/* Creates path like fopen (mode 0666 & ~umask, the rule for every output file). */
static sr_status outfile_open(outfile *o, const char *path, sr_err *err)
{
    o->path = path;
    o->f = fopen(path, "w");
    if (!o->f)
        return sr_err_set(err, SR_E_IO, "cannot write '%s': %s", path, strerror(errno));
    return SR_OK;
}

/* Closes the file, and removes it when anything failed (st or a write error). */
static sr_status outfile_close(outfile *o, sr_status st, sr_err *err)
{
    if (!o->f)
        return st;
    int bad = ferror(o->f);
    int e = bad ? EIO : 0;
    if (fclose(o->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    o->f = NULL;
    if (st != SR_OK || bad) {
        unlink(o->path);
        if (st == SR_OK)
            st = sr_err_set(err, SR_E_IO, "cannot write '%s': %s", o->path, strerror(e));
    }
    return st;
}

/* The machine settings to use (defaults for NULL), checked, and the file opened. */
static sr_status open_with_machine(const sr_plan_machine *machine, sr_plan_machine *m,
                                   outfile *o, const char *path, sr_err *err)
{
    if (machine)
        *m = *machine;
    else
        sr_plan_machine_init(m);
    sr_status st = sr_plan_machine_check(m, err);
    return st == SR_OK ? outfile_open(o, path, err) : st;
}

/* ---- JSON ---- */

static void jnum(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.10g", v);
    else
        fputs("null", f);
}

static void jcoord(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.5f", v == 0 ? 0.0 : v); /* no "-0.00000" */
    else
        fputs("null", f);
}

/* A region or path set as [[[x,y],...],...]. */
static void jcontours(FILE *f, const sr_poly2 *p)
{
    fputc('[', f);
    for (size_t c = 0; c < p->contour_count; c++) {
        fputs(c ? ",[" : "[", f);
        for (size_t i = p->start[c]; i < p->start[c + 1]; i++) {
            fputs(i > p->start[c] ? ",[" : "[", f);
            jcoord(f, p->xy[2 * i]);
            fputc(',', f);
            jcoord(f, p->xy[2 * i + 1]);
            fputc(']', f);
        }
        fputc(']', f);
    }
    fputc(']', f);
}

static void jkey_num(FILE *f, const char *key, double v, int comma)
{
    fprintf(f, "%s\"%s\":", comma ? "," : "", key);
    jnum(f, v);
}

static void jkey_str(FILE *f, const char *key, const char *s)
{
    /* only the plan's own fixed strings and validated G-codes reach here: no escaping
     * beyond quotes and backslashes is needed, and those are refused or absent */
    fprintf(f, ",\"%s\":\"%s\"", key, s);
}

static const char *build_direction(const sr_plan *p)
{
    return p->kind == SR_SYM_AXIAL
               ? "+z: along the symmetry axis, layers are slices across the axis"
               : "+z: along the symmetry plane's in-plane axis, layers are slices across it";
}

sr_status sr_plan_write_json(const sr_plan *p, const sr_plan_machine *machine,
                             const char *path, sr_err *err)
{
    sr_plan_machine m;
    outfile o;
    sr_status st = open_with_machine(machine, &m, &o, path, err);
    if (st != SR_OK)
        return st;
    FILE *f = o.f;
    fprintf(f, "{\"format\":\"symrec build plan\",\"software_version\":\"%s\"", SR_VERSION);
    fputs(",\"units\":{\"length\":\"mm\",\"area\":\"mm2\",\"volume\":\"mm3\",\"mass\":\"g\","
          "\"time\":\"min\",\"angle\":\"deg\",\"density\":\"g/cm3\",\"rate\":\"cm3/min\","
          "\"feed\":\"mm/min\"}",
          f);
    fprintf(f, ",\"run\":%lld,\"section\":%zu", (long long)p->run_id, p->section_index + 1);
    jkey_str(f, "symmetry", sr_sym_kind_name(p->kind));
    if (p->has_angles) {
        jkey_num(f, "angle_from_deg", p->angle_from_deg, 1);
        jkey_num(f, "angle_to_deg", p->angle_to_deg, 1);
    } else {
        fprintf(f, ",\"side\":%d", p->side);
    }
    jkey_num(f, "z_min_mm", p->z_min_mm, 1);
    jkey_num(f, "z_max_mm", p->z_max_mm, 1);
    jkey_str(f, "build_direction", build_direction(p));
    jkey_num(f, "layer_mm", p->opts.layer_mm, 1);
    fprintf(f, ",\"layer_count\":%zu", p->layer_count);
    jkey_num(f, "step_over_mm", p->opts.step_over_mm, 1);
    jkey_num(f, "allowance_mm", p->opts.allowance_mm, 1);
    jkey_str(f, "pattern", sr_plan_pattern_name(p->opts.pattern));
    jkey_num(f, "raster_angle_deg", p->opts.raster_angle_deg, 1);
    jkey_num(f, "density_g_cm3", p->opts.density_g_cm3, 1);
    jkey_num(f, "rate_cm3_min", p->opts.rate_cm3_min, 1);
    jkey_num(f, "missing_volume_mm3", p->missing_volume_mm3, 1);
    jkey_num(f, "deposit_volume_mm3", p->deposit_volume_mm3, 1);
    jkey_num(f, "deposit_mass_g", p->deposit_mass_g, 1);
    sr_plan timed = *p; /* the figures only; the arrays stay p's */
    sr_plan_time(&timed, &m, NULL);
    jkey_num(f, "build_time_min", timed.build_time_min, 1);
    jkey_num(f, "deposit_time_min", timed.deposit_time_min, 1);
    jkey_num(f, "travel_time_min", timed.travel_time_min, 1);
    jkey_num(f, "path_length_mm", p->path_length_mm, 1);
    jkey_num(f, "travel_length_mm", timed.travel_length_mm, 1);
    if (p->process[0]) {
        jkey_str(f, "process", p->process);
        jkey_str(f, "advised_by_rule", p->rule);
    }
    if (isfinite(p->preheat_c))
        jkey_num(f, "preheat_c", p->preheat_c, 1);
    fputs(",\"machine\":{", f);
    jkey_num(f, "feed_mm_min", timed.feed_mm_min, 0);
    jkey_num(f, "rapid_mm_min", m.rapid_mm_min, 1);
    jkey_num(f, "travel_height_mm", m.travel_height_mm, 1);
    jkey_str(f, "on_code", m.on_code);
    jkey_str(f, "off_code", m.off_code);
    fputs("},\"files\":{\"gcode\":\"plan.gcode\",\"svg\":\"layer_NNN.svg\"}", f);
    fputs(",\"layers\":[", f);
    for (size_t k = 0; k < p->layer_count; k++) {
        const sr_plan_layer *L = &p->layers[k];
        fprintf(f, "%s{\"layer\":%zu", k ? "," : "", k + 1);
        jkey_num(f, "z_bottom_mm", L->z_bottom_mm, 1);
        jkey_num(f, "z_top_mm", L->z_top_mm, 1);
        fprintf(f, ",\"run_layers\":[%zu,%zu]", L->run_layer_first, L->run_layer_last);
        jkey_num(f, "raster_angle_deg", L->raster_angle_deg, 1);
        jkey_num(f, "missing_area_mm2", L->missing_area_mm2, 1);
        jkey_num(f, "region_area_mm2", L->region_area_mm2, 1);
        jkey_num(f, "path_length_mm", L->path_length_mm, 1);
        fprintf(f, ",\"svg\":\"layer_%03zu.svg\"", k + 1);
        fputs(",\"missing\":", f);
        jcontours(f, &L->missing);
        fputs(",\"region\":", f);
        jcontours(f, &L->region);
        fputs(",\"paths\":[", f);
        for (size_t c = 0; c < L->paths.contour_count; c++) {
            sr_poly2 one = {L->paths.xy + 2 * L->paths.start[c],
                            (size_t[]){0, L->paths.start[c + 1] - L->paths.start[c]}, 1};
            fprintf(f, "%s{\"kind\":\"%s\",\"closed\":%s,\"points\":", c ? "," : "",
                    L->path_kind[c] == SR_PLAN_PATH_RING ? "ring" : "raster",
                    L->path_kind[c] == SR_PLAN_PATH_RING ? "true" : "false");
            /* one polyline: the points array without the outer contour brackets */
            fputc('[', f);
            for (size_t i = 0; i < one.start[1]; i++) {
                fputs(i ? ",[" : "[", f);
                jcoord(f, one.xy[2 * i]);
                fputc(',', f);
                jcoord(f, one.xy[2 * i + 1]);
                fputc(']', f);
            }
            fputs("]}", f);
        }
        fputs("]}", f);
    }
    fputs("]}\n", f);
    return outfile_close(&o, SR_OK, err);
}

/* ---- SVG ---- */

/* SVG path data of a region's contours (y is flipped by the enclosing group). */
static void svg_path_data(FILE *f, const sr_poly2 *p, int close)
{
    for (size_t c = 0; c < p->contour_count; c++) {
        for (size_t i = p->start[c]; i < p->start[c + 1]; i++)
            fprintf(f, "%s%.5f %.5f ", i == p->start[c] ? "M" : "L", p->xy[2 * i],
                    p->xy[2 * i + 1]);
        if (close)
            fputs("Z ", f);
    }
}

/* Largest 1, 2 or 5 x 10^k not above x. */
static double nice_length(double x)
{
    double e = pow(10.0, floor(log10(x)));
    double m = x / e;
    return (m >= 5 ? 5 : m >= 2 ? 2 : 1) * e;
}

sr_status sr_plan_write_svg(const sr_plan *p, size_t layer, const char *path, sr_err *err)
{
    if (layer >= p->layer_count)
        return sr_err_set(err, SR_E_RANGE, "layer %zu is not in the plan (%zu layers)",
                          layer + 1, p->layer_count);
    const sr_plan_layer *L = &p->layers[layer];
    double box[4] = {-1, -1, 1, 1}, b2[4];
    int have = sr_poly2_bounds(&L->region, box);
    if (sr_poly2_bounds(&L->missing, b2)) {
        if (!have)
            memcpy(box, b2, sizeof box);
        else {
            box[0] = fmin(box[0], b2[0]);
            box[1] = fmin(box[1], b2[1]);
            box[2] = fmax(box[2], b2[2]);
            box[3] = fmax(box[3], b2[3]);
        }
    }
    double w = box[2] - box[0], h = box[3] - box[1];
    double margin = 0.15 * fmax(w, h) + 2.0;
    double vx = box[0] - margin, vy = -(box[3] + margin);
    double vw = w + 2 * margin, vh = h + 2 * margin;
    if (vw < 1.2 * vh) { /* room for the caption: never narrower than 6:5 */
        vx -= 0.5 * (1.2 * vh - vw);
        vw = 1.2 * vh;
    }
    double band = 0.14 * fmax(vw, vh); /* caption and scale bar below the drawing */
    double font = 0.028 * vw;
    double px = 800.0 / fmax(vw, vh + band);
    outfile o;
    sr_status st = outfile_open(&o, path, err);
    if (st != SR_OK)
        return st;
    FILE *f = o.f;
    fprintf(f,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
            "viewBox=\"%.5f %.5f %.5f %.5f\">\n",
            vw * px, (vh + band) * px, vx, vy, vw, vh + band);
    fprintf(f,
            "<title>symrec build plan: run %lld section %zu, layer %zu of %zu, z %.3f..%.3f "
            "mm (units: mm)</title>\n",
            (long long)p->run_id, p->section_index + 1, layer + 1, p->layer_count,
            L->z_bottom_mm, L->z_top_mm);
    fprintf(f, "<rect x=\"%.5f\" y=\"%.5f\" width=\"%.5f\" height=\"%.5f\" fill=\"white\"/>\n",
            vx, vy, vw, vh + band);
    fputs("<g transform=\"scale(1,-1)\">\n", f);
    fputs("<path id=\"damaged\" fill=\"#d9d9d9\" stroke=\"#808080\" fill-rule=\"evenodd\" "
          "stroke-width=\"",
          f);
    fprintf(f, "%.5f\" d=\"", 0.003 * vw);
    svg_path_data(f, &L->damaged, 1);
    fputs("\"/>\n<path id=\"region\" fill=\"#f6c48f\" stroke=\"none\" "
          "fill-rule=\"evenodd\" d=\"",
          f);
    svg_path_data(f, &L->region, 1);
    fprintf(f, "\"/>\n<path id=\"missing\" fill=\"none\" stroke=\"#1f5fbf\" "
               "stroke-dasharray=\"%.5f %.5f\" stroke-width=\"%.5f\" d=\"",
            0.01 * vw, 0.006 * vw, 0.003 * vw);
    svg_path_data(f, &L->missing, 1);
    fprintf(f, "\"/>\n<path id=\"paths\" fill=\"none\" stroke=\"#c0181c\" "
               "stroke-linejoin=\"round\" stroke-width=\"%.5f\" d=\"",
            0.25 * p->opts.step_over_mm);
    svg_path_data(f, &L->paths, 0);
    fputs("\"/>\n</g>\n", f);
    fprintf(f, "<rect x=\"%.5f\" y=\"%.5f\" width=\"%.5f\" height=\"%.5f\" "
               "fill=\"white\"/>\n",
            vx, vy + vh, vw, band);
    /* scale bar and caption, in the band below the drawing */
    double bar = nice_length(0.3 * vw);
    double bx = vx + 0.05 * vw, by = vy + vh + 0.35 * band;
    fprintf(f,
            "<path id=\"scale\" stroke=\"black\" stroke-width=\"%.5f\" fill=\"none\" "
            "d=\"M%.5f %.5f l0 %.5f l%.5f 0 l0 %.5f\"/>\n",
            0.004 * vw, bx, by - 0.1 * band, 0.1 * band, bar, -0.1 * band);
    fprintf(f,
            "<text x=\"%.5f\" y=\"%.5f\" font-family=\"sans-serif\" font-size=\"%.5f\">%g "
            "mm</text>\n",
            bx + bar + 0.02 * vw, by, font, bar);
    fprintf(f,
            "<text x=\"%.5f\" y=\"%.5f\" font-family=\"sans-serif\" font-size=\"%.5f\">"
            "layer %zu/%zu  z %.3f..%.3f mm  deposit %.2f mm2  path %.1f mm</text>\n",
            bx, by + 0.45 * band, font, layer + 1, p->layer_count, L->z_bottom_mm,
            L->z_top_mm, L->region_area_mm2, L->path_length_mm);
    fputs("</svg>\n", f);
    return outfile_close(&o, SR_OK, err);
}

/* ---- G-code and its time ---- */

double sr_plan_feed(const sr_plan *p, const sr_plan_machine *m)
{
    if (m && m->feed_mm_min > 0)
        return m->feed_mm_min;
    double bead = p->opts.step_over_mm * p->opts.layer_mm; /* mm^2 */
    return bead > 0 ? p->opts.rate_cm3_min * 1000.0 / bead : 0;
}

/* What the moves add up to. */
typedef struct move_totals {
    double deposit_mm, travel_mm;
} move_totals;

/* Walks the moves of plan.gcode (plan_export.h) after its header, writing them to f
 * when f is not NULL, and sums the deposition and travel lengths: the G-code and the
 * build time come from this one walk. The first travel starts at the first path's
 * start, travel height up (where a set-up leaves the tool). */
static void walk_moves(const sr_plan *p, const sr_plan_machine *m, double feed, FILE *f,
                       move_totals *t)
{
    memset(t, 0, sizeof *t);
    double at[3] = {0, 0, 0};
    int placed = 0;
#define TRAVEL(x, y, z)                                                                            \
    do {                                                                                           \
        if (placed)                                                                                \
            t->travel_mm += sqrt(((x)-at[0]) * ((x)-at[0]) + ((y)-at[1]) * ((y)-at[1]) +           \
                                 ((z)-at[2]) * ((z)-at[2]));                                       \
        at[0] = (x), at[1] = (y), at[2] = (z);                                                     \
        placed = 1;                                                                                \
    } while (0)
    if (f)
        fprintf(f, "G21\nG90\n%s\n", m->off_code);
    double top = p->z_min_mm;
    for (size_t k = 0; k < p->layer_count; k++) {
        const sr_plan_layer *L = &p->layers[k];
        double z = L->z_top_mm;
        top = z;
        if (f)
            fprintf(f, "; layer %zu z=%.5f\n", k + 1, z);
        for (size_t c = 0; c < L->paths.contour_count; c++) {
            const double *q = L->paths.xy + 2 * L->paths.start[c];
            size_t n = L->paths.start[c + 1] - L->paths.start[c];
            double up = z + m->travel_height_mm;
            if (!placed)
                TRAVEL(q[0], q[1], up);
            TRAVEL(at[0], at[1], up);
            TRAVEL(q[0], q[1], up);
            TRAVEL(q[0], q[1], z);
            if (f)
                fprintf(f, "G0 Z%.5f\nG0 X%.5f Y%.5f\nG0 Z%.5f\n%s\n", up, q[0], q[1], z,
                        m->on_code);
            for (size_t i = 1; i < n; i++) {
                double dx = q[2 * i] - at[0], dy = q[2 * i + 1] - at[1];
                t->deposit_mm += sqrt(dx * dx + dy * dy);
                at[0] = q[2 * i], at[1] = q[2 * i + 1];
                if (f)
                    fprintf(f, "G1 X%.5f Y%.5f Z%.5f F%.1f\n", q[2 * i], q[2 * i + 1], z, feed);
            }
            if (f)
                fprintf(f, "%s\n", m->off_code);
        }
    }
    TRAVEL(at[0], at[1], top + m->travel_height_mm);
    if (f)
        fprintf(f, "%s\nG0 Z%.5f\nM2\n", m->off_code, top + m->travel_height_mm);
#undef TRAVEL
}

sr_status sr_plan_time(sr_plan *p, const sr_plan_machine *machine, sr_err *err)
{
    sr_plan_machine m;
    if (machine) {
        m = *machine;
        sr_status st = sr_plan_machine_check(&m, err);
        if (st != SR_OK)
            return st;
    } else {
        sr_plan_machine_init(&m);
    }
    move_totals t;
    double feed = sr_plan_feed(p, &m);
    walk_moves(p, &m, feed, NULL, &t);
    p->feed_mm_min = feed;
    p->deposit_time_min = feed > 0 ? t.deposit_mm / feed : 0;
    p->travel_length_mm = t.travel_mm;
    p->travel_time_min = t.travel_mm / m.rapid_mm_min;
    p->build_time_min = p->deposit_time_min + p->travel_time_min;
    return SR_OK;
}

sr_status sr_plan_write_gcode(const sr_plan *p, const sr_plan_machine *machine,
                              const char *path, sr_err *err)
{
    sr_plan_machine m;
    outfile o;
    sr_status st = open_with_machine(machine, &m, &o, path, err);
    if (st != SR_OK)
        return st;
    FILE *f = o.f;
    sr_plan timed = *p; /* the figures only; the arrays stay p's */
    sr_plan_time(&timed, &m, NULL);
    fprintf(f, "; symrec %s build plan: run %lld section %zu (%s)\n", SR_VERSION,
            (long long)p->run_id, p->section_index + 1, sr_sym_kind_name(p->kind));
    if (p->process[0])
        fprintf(f, "; process %s, as advised by rule %s\n", p->process,
                p->rule[0] ? p->rule : "(unknown)");
    if (isfinite(p->preheat_c))
        fprintf(f, "; preheat the part to %.0f C before depositing\n", p->preheat_c);
    fprintf(f, "; build direction %s\n", build_direction(p));
    fprintf(f, "; %zu layers of %.4f mm, step-over %.4f mm, allowance %.4f mm, pattern %s\n",
            p->layer_count, p->opts.layer_mm, p->opts.step_over_mm, p->opts.allowance_mm,
            sr_plan_pattern_name(p->opts.pattern));
    fprintf(f, "; deposit %.3f mm3 = %.3f g at %.3f g/cm3\n", p->deposit_volume_mm3,
            p->deposit_mass_g, p->opts.density_g_cm3);
    fprintf(f,
            "; build time %.2f min: deposition %.1f mm at F%.1f mm/min (%.2f min), travel "
            "%.1f mm at %.0f mm/min (%.2f min)\n",
            timed.build_time_min, timed.path_length_mm, timed.feed_mm_min, timed.deposit_time_min,
            timed.travel_length_mm, m.rapid_mm_min, timed.travel_time_min);
    fputs("; coordinates: the run's aligned frame, z along the symmetry axis\n", f);
    move_totals t;
    walk_moves(p, &m, timed.feed_mm_min, f, &t);
    return outfile_close(&o, SR_OK, err);
}

/* ---- all files ---- */

sr_status sr_plan_export(const sr_plan *p, const sr_plan_machine *machine, const char *dir,
                         sr_err *err)
{
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return sr_err_set(err, SR_E_IO, "cannot create '%s': %s", dir, strerror(errno));
    struct stat sb;
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        return sr_err_set(err, SR_E_IO, "cannot write into '%s': not a directory", dir);
    size_t len = strlen(dir) + 32;
    char *path = malloc(len);
    if (!path)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    snprintf(path, len, "%s/plan.json", dir);
    sr_status st = sr_plan_write_json(p, machine, path, err);
    for (size_t k = 0; st == SR_OK && k < p->layer_count; k++) {
        snprintf(path, len, "%s/layer_%03zu.svg", dir, k + 1);
        st = sr_plan_write_svg(p, k, path, err);
    }
    if (st == SR_OK) {
        snprintf(path, len, "%s/plan.gcode", dir);
        st = sr_plan_write_gcode(p, machine, path, err);
    }
    free(path);
    return st;
}
