/*
 * identify.c: the scan's preparation and its fit to candidate parts (identify.h), on
 * the registration pipeline of register.c (al_register_fit) with a lighter effort.
 */
#include "align/identify.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "align/align_internal.h"

/* Samples: of the scan (the registration's three stages) and of each part (lacking). */
#define SCAN_COARSE 128
#define SCAN_MEDIUM 600
#define SCAN_FINE 1000
#define PART_SAMPLES 1000

/* Less than sr_register: 45 degree start turns (the coarse ICP pulls in about 20
 * degrees either way; 90 degree turns missed a square nut's pose by a quarter turn
 * mod its symmetry), a coarse cut-off of 5 % of the size, fewer samples and steps;
 * a candidate with under 40 % of the scan within 4 tol after the coarse stage is no
 * match (a match needs 80 % within tol), so it is not refined. Coverage at 0.5 % of
 * the size needs no more. */
static const al_register_effort EFFORT = {8, 0.05, 3, 2, 10, 15, 0.4, 30};

struct sr_identify_scan {
    al_surface surf;
    al_samples coarse, medium, fine;
    sr_shape_descriptor desc;
    double tol;
};

void sr_identify_scan_free(sr_identify_scan *s)
{
    if (!s)
        return;
    al_surface_release(&s->surf);
    al_samples_release(&s->coarse);
    al_samples_release(&s->medium);
    al_samples_release(&s->fine);
    free(s);
}

sr_status sr_identify_scan_make(const sr_mesh *scan, double tol_mm, sr_identify_scan **out,
                                sr_err *err)
{
    sr_status st = sr_mesh_validate(scan, "scan", NULL, err);
    if (st != SR_OK)
        return st;
    sr_identify_scan *s = calloc(1, sizeof *s);
    if (!s)
        return sr_err_set(err, SR_E_NOMEM, "out of memory preparing the scan");
    st = al_surface_build(&s->surf, scan, NULL);
    if (st != SR_OK) {
        free(s);
        if (st == SR_E_INVALID)
            return sr_err_set(err, st, "scan has no triangle with an area");
        return sr_err_set(err, st, "out of memory preparing the scan");
    }
    if (al_samples_make(&s->surf, SCAN_COARSE, 21, &s->coarse) != SR_OK ||
        al_samples_make(&s->surf, SCAN_MEDIUM, 22, &s->medium) != SR_OK ||
        al_samples_make(&s->surf, SCAN_FINE, 23, &s->fine) != SR_OK) {
        sr_identify_scan_free(s);
        return sr_err_set(err, SR_E_NOMEM, "out of memory preparing the scan");
    }
    if (al_shape_describe(&s->surf, &s->desc) != SR_OK) {
        sr_identify_scan_free(s);
        return sr_err_set(err, SR_E_NOMEM, "out of memory preparing the scan");
    }
    s->tol = tol_mm > 0 ? tol_mm : 0.005 * s->surf.diag;
    *out = s;
    return SR_OK;
}

const sr_shape_descriptor *sr_identify_scan_descriptor(const sr_identify_scan *s)
{
    return &s->desc;
}

double sr_identify_scan_tol(const sr_identify_scan *s)
{
    return s->tol;
}

static void apply(const double m[12], const double p[3], double q[3])
{
    for (int i = 0; i < 3; i++)
        q[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3];
}

/* The inverse of a rigid 3 x 4 transform. */
static void invert(const double m[12], double inv[12])
{
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            inv[4 * i + j] = m[4 * j + i];
        inv[4 * i + 3] = -(m[i] * m[3] + m[4 + i] * m[7] + m[8 + i] * m[11]);
    }
}

/* Coverage, RMS and the share inside of the scan's fine samples on part surface `fix`
 * under fit->mat. Inside: the closest point's face looks away from the sample (a
 * fracture face lies well inside the solid, away from its edges), searched within a
 * quarter of the part's size. */
static void measure_on_part(al_surface *fix, const al_samples *smp, double tol,
                            sr_identify_fit *fit)
{
    size_t in = 0, inside = 0;
    double sum2 = 0;
    for (size_t i = 0; i < smp->count; i++) {
        double x[3], q[3], n[3], d;
        apply(fit->mat, smp->p + 3 * i, x);
        if (al_surface_closest(fix, x, tol, q, n, &d) && d <= tol) {
            in++;
            sum2 += d * d;
        } else if (al_surface_closest(fix, x, 0.25 * fix->diag, q, n, &d) &&
                   n[0] * (x[0] - q[0]) + n[1] * (x[1] - q[1]) + n[2] * (x[2] - q[2]) < 0) {
            inside++;
        }
    }
    fit->coverage = smp->count ? (double)in / (double)smp->count : 0;
    fit->inside = smp->count ? (double)inside / (double)smp->count : 0;
    fit->rms_mm = in ? sqrt(sum2 / (double)in) : 0;
}

/* Share of the part's samples farther than tol from the scan under fit->mat. */
static double lacking_of(al_surface *scan, const al_samples *part, double tol, const double m[12])
{
    double inv[12];
    invert(m, inv);
    size_t far = 0;
    for (size_t i = 0; i < part->count; i++) {
        double x[3], q[3], n[3], d;
        apply(inv, part->p + 3 * i, x);
        if (!al_surface_closest(scan, x, tol, q, n, &d) || d > tol)
            far++;
    }
    return part->count ? (double)far / (double)part->count : 1;
}

/* One candidate: its surface, the registration, coverage and its samples for lacking.
 * Returns SR_E_INVALID or SR_E_NOMEM; on success *smp holds the part's samples. */
static sr_status fit_one(sr_identify_scan *s, const sr_mesh *part, sr_identify_fit *fit,
                         al_samples *smp)
{
    al_surface fix;
    sr_status st = al_surface_build(&fix, part, NULL);
    if (st != SR_OK)
        return st;
    double *scratch = malloc(SCAN_FINE * sizeof *scratch);
    if (!scratch || al_samples_make(&fix, PART_SAMPLES, 31, smp) != SR_OK) {
        free(scratch);
        al_surface_release(&fix);
        return SR_E_NOMEM;
    }
    memset(fit, 0, sizeof *fit);
    al_register_fit(&fix, &s->surf, &s->coarse, &s->medium, &s->fine, s->tol, &EFFORT, fit->mat,
                    scratch);
    measure_on_part(&fix, &s->fine, s->tol, fit);
    free(scratch);
    al_surface_release(&fix);
    return SR_OK;
}

sr_status sr_identify_fit_parts(sr_identify_scan *s, const sr_mesh *const *parts, size_t count,
                                sr_identify_fit *out, sr_err *err)
{
    al_samples *smp = calloc(count ? count : 1, sizeof *smp);
    sr_status *sts = calloc(count ? count : 1, sizeof *sts);
    if (!smp || !sts) {
        free(smp);
        free(sts);
        return sr_err_set(err, SR_E_NOMEM, "out of memory fitting %zu parts", count);
    }
    for (size_t i = 0; i < count; i++)
        sts[i] = sr_mesh_validate(parts[i], "part", NULL, NULL);
        /* each candidate owns its surface, so they run side by side; the scan's surface is
     * only read here (its query stamps are written below, in one thread) */
#pragma omp parallel for schedule(dynamic, 1)
    for (long i = 0; i < (long)count; i++)
        if (sts[i] == SR_OK)
            sts[i] = fit_one(s, parts[i], &out[i], &smp[i]);
    sr_status st = SR_OK;
    for (size_t i = 0; i < count; i++) {
        if (sts[i] != SR_OK && st == SR_OK)
            st = sr_err_set(err, sts[i] == SR_E_NOMEM ? SR_E_NOMEM : SR_E_INVALID,
                            sts[i] == SR_E_NOMEM ? "out of memory fitting candidate %zu"
                                                 : "candidate %zu has no usable surface",
                            i);
        if (sts[i] == SR_OK) {
            out[i].lacking = lacking_of(&s->surf, &smp[i], s->tol, out[i].mat);
            out[i].tol_mm = s->tol;
            double r = s->tol > 0 ? out[i].rms_mm / s->tol : 0;
            out[i].score = out[i].coverage * (1 - out[i].lacking) * (1 - 0.5 * r * r);
        }
        al_samples_release(&smp[i]);
    }
    free(smp);
    free(sts);
    return st;
}

int sr_identify_fit_matches(const sr_identify_fit *fit)
{
    return fit->coverage + fit->inside >= SR_IDENTIFY_MIN_COVERAGE &&
           fit->coverage >= SR_IDENTIFY_MIN_ON && fit->lacking <= SR_IDENTIFY_MAX_LACKING &&
           fit->rms_mm <= SR_IDENTIFY_MAX_RMS_TOL * fit->tol_mm;
}
