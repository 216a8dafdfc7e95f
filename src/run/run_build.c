/*
 * run_build.c: an sr_run record from an sr_recon_result (see run_build.h): copies of
 * the figures, the layer polylines laid out as the catalogue stores them, copies of
 * the meshes, the timings as one JSON object.
 */
#include "run/run_build.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/version.h"

#define TWO_PI 6.28318530717958647692

void sr_run_utc_time(double offset_s, char out[32])
{
    time_t t = time(NULL) + (time_t)floor(offset_s + 0.5);
    struct tm tm;
    if (!gmtime_r(&t, &tm) || strftime(out, 32, "%Y-%m-%dT%H:%M:%SZ", &tm) == 0)
        snprintf(out, 32, "1970-01-01T00:00:00Z");
}

static sr_status fill_layers(const sr_recon_result *res, sr_run *run, sr_err *err)
{
    const sr_layer_grid *g = &res->grid;
    const sr_analysis *a = &res->analysis;
    size_t L = g->layers, n = g->sectors;
    if (L == 0)
        return SR_OK;
    if (a->layers != L || a->sectors != n || !a->restored_r || !a->damaged || !g->r || !g->pt)
        return sr_err_set(err, SR_E_RANGE,
                          "bad result: grid %zu x %zu and analysis %zu x %zu disagree", L, n,
                          a->layers, a->sectors);
    run->layer_z = malloc(L * sizeof *run->layer_z);
    run->damaged_xy = malloc(L * n * 2 * sizeof(double));
    run->restored_xy = malloc(L * n * 2 * sizeof(double));
    if (!run->layer_z || !run->damaged_xy || !run->restored_xy)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu layers of %zu sectors", L, n);
    run->layer_count = L;
    run->sectors = n;
    for (size_t l = 0; l < L; l++) {
        run->layer_z[l] = sr_layer_z(g, l);
        for (size_t k = 0; k < n; k++) {
            size_t c = l * n + k;
            double *d = run->damaged_xy + 2 * c, *r = run->restored_xy + 2 * c;
            if (g->r[c] > 0) {
                d[0] = g->pt[3 * c];
                d[1] = g->pt[3 * c + 1];
            } else {
                d[0] = d[1] = NAN;
            }
            if (a->damaged[c]) {
                double th = sr_sector_angle(k, n), rr = a->restored_r[c];
                r[0] = rr * cos(th);
                r[1] = rr * sin(th);
            } else {
                r[0] = d[0];
                r[1] = d[1];
            }
        }
    }
    return SR_OK;
}

static sr_status fill_sections(const sr_recon_result *res, sr_sym_kind kind, sr_run *run,
                               sr_err *err)
{
    size_t count = res->section_count;
    if (count == 0)
        return SR_OK;
    run->sections = calloc(count, sizeof *run->sections);
    if (!run->sections)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu sections", count);
    run->section_count = count;
    size_t n = res->grid.sectors ? res->grid.sectors : 1;
    double step = 360.0 / (double)n;
    for (size_t i = 0; i < count; i++) {
        const sr_section *s = &res->sections[i];
        sr_run_section *o = &run->sections[i];
        o->index = i;
        o->layer_first = s->layer_first;
        o->layer_last = s->layer_last;
        o->z_min_mm = s->z_min;
        o->z_max_mm = s->z_max;
        if (kind == SR_SYM_AXIAL) {
            o->has_angles = 1;
            if (s->sector_count >= n) {
                o->angle_from_deg = 0;
                o->angle_to_deg = 360;
            } else {
                /* the section's own arc (the paper method's is whole sectors; the
                 * robust method's is the exact arc of its outline) */
                o->angle_from_deg = s->angle_min_deg;
                o->angle_to_deg = s->angle_max_deg >= s->angle_min_deg
                                      ? s->angle_max_deg
                                      : s->angle_max_deg + 360.0;
                (void)step;
            }
        } else {
            /* The plane's trace is at plane_angle; its normal at plane_angle - 90 deg
             * (canonical +x when the trace is the y axis). */
            double mid = ((double)s->sector_first + 0.5 * (double)s->sector_count) *
                         (TWO_PI / (double)n);
            double phi = res->analysis.plane_angle;
            o->side = sin(phi - mid) >= 0 ? 1 : -1;
        }
        o->volume_mm3 = s->volume_mm3;
        o->area_mm2 = s->area_mm2;
        o->depth_max_mm = s->depth_max_mm;
        o->depth_mean_mm = s->depth_mean_mm;
        snprintf(o->damage_class, sizeof o->damage_class, "unclassified");
        sr_status st = sr_mesh_copy(&o->patch, &s->patch);
        if (st != SR_OK)
            return sr_err_set(err, st, "out of memory copying the patch of section %zu", i);
    }
    return SR_OK;
}

static sr_status fill_timings(const sr_recon_timings *t, sr_run *run, sr_err *err)
{
    const char *names[SR_RECON_PHASES];
    double v[SR_RECON_PHASES];
    size_t n = sr_recon_timings_list(t, names, v);
    char buf[512];
    size_t len = 0;
    buf[len++] = '{';
    for (size_t i = 0; i < n; i++) {
        double x = v[i];
        int w = snprintf(buf + len, sizeof buf - len, "%s\"%s\":%.6g", i ? "," : "", names[i], x);
        if (w < 0 || (size_t)w >= sizeof buf - len)
            return sr_err_set(err, SR_E_INTERNAL, "timings do not fit");
        len += (size_t)w;
    }
    if (len + 2 > sizeof buf)
        return sr_err_set(err, SR_E_INTERNAL, "timings do not fit");
    buf[len++] = '}';
    buf[len] = '\0';
    run->timings_json = malloc(len + 1);
    if (!run->timings_json)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for the timings");
    memcpy(run->timings_json, buf, len + 1);
    return SR_OK;
}

sr_status sr_run_from_result(const sr_recon_result *result, int64_t instance_id,
                             const sr_symmetry *sym, const sr_params *params,
                             const char *method, sr_run *out, sr_err *err)
{
    if (!method || strlen(method) < 1 || strlen(method) >= sizeof out->method)
        return sr_err_set(err, SR_E_RANGE, "bad method '%s': expected 1..%zu bytes",
                          method ? method : "", sizeof out->method - 1);
    sr_run run;
    memset(&run, 0, sizeof run);
    run.instance_id = instance_id;
    run.symmetry = *sym;
    if (sym->kind == SR_SYM_AXIAL)
        run.symmetry.order = result->order; /* the order found, for --order auto */
    if (sym->kind == SR_SYM_GLIDE && result->analysis.shift_mm > 0)
        run.symmetry.shift_mm = result->analysis.shift_mm;
    run.params = *params;
    run.params.layers = (int)result->grid.layers;
    run.params.sectors = (int)result->grid.sectors;
    snprintf(run.method, sizeof run.method, "%s", method);
    run.has_alignment = 1;
    memcpy(run.alignment, result->alignment.xform, sizeof run.alignment);
    double q = result->alignment.fit_score;
    run.fit_quality = isnan(q) ? -1 : q < 0 ? 0 : q > 1 ? 1 : q;
    run.ok = 1;
    if (result->method == SR_METHOD_IMAGE) {
        run.unbuilt_sections = result->image.unbuilt;
        run.unbuilt_mm3 = result->image.unbuilt_mm3;
    }
    snprintf(run.software_version, sizeof run.software_version, "%s", SR_VERSION);
    sr_run_utc_time(0, run.finished_at);
    sr_run_utc_time(-result->timings.total_s, run.started_at);

    sr_status st = fill_timings(&result->timings, &run, err);
    if (st == SR_OK)
        st = fill_layers(result, &run, err);
    if (st == SR_OK)
        st = fill_sections(result, sym->kind, &run, err);
    if (st == SR_OK && result->restored.tri_count > 0) {
        st = sr_mesh_copy(&run.restored, &result->restored);
        if (st != SR_OK)
            sr_err_set(err, st, "out of memory copying the restored mesh");
    }
    if (st != SR_OK) {
        sr_run_release(&run);
        return st;
    }
    *out = run;
    return SR_OK;
}
