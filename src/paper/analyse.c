/*
 * analyse.c: paper Algorithm 4 (axial) and Algorithm 5 (mirror, glide) on a layer grid
 * (see analyse.h for the readings of the paper's pseudo-code).
 */
#include "paper/analyse.h"
#include "run/params_default.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.28318530717958647692

void sr_analysis_release(sr_analysis *a)
{
    if (!a)
        return;
    free(a->restored_r);
    free(a->damaged);
    memset(a, 0, sizeof *a);
}

static void axial(const sr_layer_grid *g, double gamma, sr_analysis *a)
{
    size_t n = g->sectors;
    for (size_t l = 0; l < g->layers; l++) {
        const double *D = g->r + l * n;
        double dmax = 0;
        for (size_t j = 0; j < n; j++)
            dmax = fmax(dmax, D[j]);
        for (size_t j = 0; j < n; j++)
            a->restored_r[l * n + j] = D[j] < gamma * dmax ? dmax : D[j];
    }
}

/* Mirror partner of sector j for a plane whose trace is at angle index `twice_phi`
 * measured in half sectors: angle theta -> 2 phi - theta. Centre (j + 1/2) D maps to
 * (twice_phi - j - 1/2) D, i.e. sector twice_phi - j - 1 (mod n). */
static size_t mirror_of(size_t j, long twice_phi, size_t n)
{
    long k = (twice_phi - (long)j - 1) % (long)n;
    return (size_t)(k < 0 ? k + (long)n : k);
}

static double plane_diff(const sr_layer_grid *g, long twice_phi)
{
    size_t n = g->sectors;
    double sum = 0;
    size_t count = 0;
    for (size_t l = 0; l < g->layers; l++) {
        const double *D = g->r + l * n;
        for (size_t j = 0; j < n; j++) {
            size_t k = mirror_of(j, twice_phi, n);
            double hi = fmax(D[j], D[k]);
            if (hi > 0) {
                sum += fabs(D[j] - D[k]) / hi;
                count++;
            }
        }
    }
    return count ? sum / (double)count : INFINITY;
}

static void planar(const sr_layer_grid *g, const sr_analyse_opts *o, sr_analysis *a)
{
    size_t n = g->sectors;
    /* the aligned plane is x = 0: its trace is at phi = pi/2, i.e. n/2 half sectors */
    long base = (long)(n / 2);
    long best = base;
    double diff_min = INFINITY;
    if (!o->fixed_plane) {
        long span = (long)(n / 36) + 1; /* +-10 deg around the aligned plane */
        for (long t = base - span; t <= base + span; t++) {
            double d = plane_diff(g, t);
            if (d < diff_min) {
                diff_min = d;
                best = t;
            }
        }
    } else {
        diff_min = plane_diff(g, base);
    }
    a->plane_angle = (double)best * (TWO_PI / (double)n) / 2.0;
    a->fit_diff = diff_min;
    double gamma = o->gamma_plane;
    long shift = 0;
    if (o->symmetry.kind == SR_SYM_GLIDE)
        shift = lround(o->symmetry.shift_mm / g->dz);
    a->shift_mm = (double)shift * g->dz;
    for (size_t l = 0; l < g->layers; l++) {
        const double *D = g->r + l * n;
        for (size_t j = 0; j < n; j++) {
            size_t k = mirror_of(j, best, n);
            double own = D[j], partner = 0;
            if (shift == 0) {
                partner = D[k];
            } else {
                long lm = (long)l - shift, lp = (long)l + shift;
                if (lm >= 0)
                    partner = fmax(partner, g->r[(size_t)lm * n + k]);
                if (lp < (long)g->layers)
                    partner = fmax(partner, g->r[(size_t)lp * n + k]);
            }
            double hi = fmax(own, partner), lo = fmin(own, partner);
            double restored = own;
            if (hi > 0 && lo / hi < gamma && partner > own)
                restored = partner;
            a->restored_r[l * n + j] = restored;
        }
    }
}

sr_status sr_analyse(const sr_layer_grid *grid, const sr_analyse_opts *opts,
                     sr_analysis *out, sr_err *err)
{
    sr_analyse_opts o = *opts;
    sr_params d;
    sr_params_default(&d);
    if (o.gamma_axis == 0)
        o.gamma_axis = d.gamma_axis;
    if (o.gamma_plane == 0)
        o.gamma_plane = d.gamma_plane;
    if (!(o.gamma_axis > 0 && o.gamma_axis <= 1))
        return sr_err_set(err, SR_E_RANGE, "bad gamma_axis %g: expected 0 < gamma <= 1",
                          o.gamma_axis);
    if (!(o.gamma_plane > 0 && o.gamma_plane <= 1))
        return sr_err_set(err, SR_E_RANGE, "bad gamma_plane %g: expected 0 < gamma <= 1",
                          o.gamma_plane);
    if (!(o.min_depth_mm >= 0) || !isfinite(o.min_depth_mm))
        return sr_err_set(err, SR_E_RANGE, "bad min_depth %g mm: expected >= 0",
                          o.min_depth_mm);
    sr_status st = sr_symmetry_check(&o.symmetry, err);
    if (st != SR_OK)
        return st;
    size_t cells = grid->layers * grid->sectors;
    sr_analysis a = {grid->layers, grid->sectors, NULL, NULL, 0, 0, 0, 0};
    a.restored_r = calloc(cells, sizeof *a.restored_r);
    a.damaged = calloc(cells, 1);
    if (!a.restored_r || !a.damaged) {
        sr_analysis_release(&a);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu cells", cells);
    }
    if (o.symmetry.kind == SR_SYM_AXIAL)
        axial(grid, o.gamma_axis, &a);
    else
        planar(grid, &o, &a);
    for (size_t c = 0; c < cells; c++) {
        if (a.restored_r[c] - grid->r[c] > o.min_depth_mm) {
            a.damaged[c] = 1;
            a.damaged_cells++;
        } else {
            a.restored_r[c] = grid->r[c];
        }
    }
    *out = a;
    return SR_OK;
}
