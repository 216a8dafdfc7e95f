/*
 * run.c: the plain-data side of the run record (run.h): the range checks of a parameter
 * set and the release of a run's heap fields. No I/O, no SQLite. The ranges of
 * sr_params_check are the same as the CHECK constraints of the parameter_sets table
 * (sql/001_init.sql), so a set that passes is never refused by the catalogue.
 */
#include "run/run.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LAYERS_MAX 100000
#define SECTORS_MAX 100000

/* True when a fixed field holds a NUL-terminated string of min..size-1 bytes. */
static bool field_ok(const char *field, size_t size, size_t min)
{
    const char *nul = memchr(field, '\0', size);
    return nul && (size_t)(nul - field) >= min;
}

static sr_status check_fraction(const char *field, double x, sr_err *err)
{
    if (!(x > 0 && x <= 1))  /* also refuses NaN */
        return sr_err_set(err, SR_E_RANGE, "bad %s %g: expected a value in (0, 1]", field, x);
    return SR_OK;
}

static sr_status check_minimum(const char *field, double x, sr_err *err)
{
    if (!(isfinite(x) && x >= 0))
        return sr_err_set(err, SR_E_RANGE, "bad %s %g: expected a finite value >= 0", field, x);
    return SR_OK;
}

sr_status sr_params_check(const sr_params *p, sr_err *err)
{
    if (!field_ok(p->name, sizeof p->name, 1))
        return sr_err_set(err, SR_E_RANGE, "bad name: expected 1..%zu bytes", sizeof p->name - 1);
    if (!field_ok(p->notes, sizeof p->notes, 0))
        return sr_err_set(err, SR_E_RANGE, "bad notes: expected at most %zu bytes",
                          sizeof p->notes - 1);
    if (p->layers < 1 || p->layers > LAYERS_MAX)
        return sr_err_set(err, SR_E_RANGE, "bad layers %d: expected 1..%d", p->layers, LAYERS_MAX);
    if (p->sectors < 3 || p->sectors > SECTORS_MAX)
        return sr_err_set(err, SR_E_RANGE, "bad sectors %d: expected 3..%d", p->sectors,
                          SECTORS_MAX);
    sr_status st;
    if ((st = check_fraction("gamma_axis", p->gamma_axis, err)) != SR_OK ||
        (st = check_fraction("gamma_plane", p->gamma_plane, err)) != SR_OK ||
        (st = check_fraction("delta_d", p->delta_d, err)) != SR_OK ||
        (st = check_minimum("min_depth_mm", p->min_depth_mm, err)) != SR_OK ||
        (st = check_minimum("min_volume_mm3", p->min_volume_mm3, err)) != SR_OK)
        return st;
    return SR_OK;
}

void sr_run_nominal_method_text(const sr_run_nominal *n, char *out, size_t size)
{
    if (strcmp(n->method, "cells") == 0 && n->exact_note[0])
        snprintf(out, size,
                 "by cells of %.3f mm (exact volume per cell); the exact difference refused "
                 "the scan: %s",
                 n->cell_mm, n->exact_note);
    else if (strcmp(n->method, "cells") == 0)
        snprintf(out, size, "by cells of %.3f mm (exact volume per cell)", n->cell_mm);
    else if (strcmp(n->method, "exact") == 0)
        snprintf(out, size, "by one exact difference (registered intact - scan)");
    else
        snprintf(out, size, "by a method not recorded (run from before schema version 10)");
}

void sr_run_nominal_free(sr_run_nominal *n)
{
    if (!n)
        return;
    free(n->sections);
    free(n->pieces);
    free(n);
}

void sr_run_scan_free(sr_run_scan *s)
{
    if (!s)
        return;
    free(s->gaps);
    free(s);
}

void sr_run_release(sr_run *run)
{
    if (!run)
        return;
    free(run->timings_json);
    free(run->symmetry_fit_json);
    free(run->layer_z);
    free(run->damaged_xy);
    free(run->restored_xy);
    for (size_t i = 0; run->sections && i < run->section_count; i++) {
        free(run->sections[i].features_json);
        sr_mesh_release(&run->sections[i].patch);
    }
    free(run->sections);
    for (size_t i = 0; run->advice && i < run->advice_count; i++)
        free(run->advice[i].details_json);
    free(run->advice);
    sr_mesh_release(&run->restored);
    sr_run_nominal_free(run->nominal);
    sr_run_scan_free(run->scan);
    memset(run, 0, sizeof *run);
}
