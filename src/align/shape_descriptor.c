/*
 * shape_descriptor.c: the pose-invariant part descriptor of shape_descriptor.h (area,
 * principal spreads, log2 D2 shape distribution) and its stored form. Samples come
 * from the alignment's surface machinery (align_surface.c), which draws them by area
 * in triangle order with a fixed seed, so the same mesh in any pose gives the same
 * samples moved with it. (The stored form is the catalogue's: catalog_identify.c.)
 */
#include "align/shape_descriptor.h"

#include <math.h>
#include <string.h>

#include "align/align_internal.h"

/* Samples for the D2 histogram: all their pairs (about 290,000) are measured. */
#define D2_SAMPLES 768
#define D2_SEED 0x5d2u

sr_status sr_shape_descriptor_compute(const sr_mesh *mesh, const char *what,
                                      sr_shape_descriptor *out, sr_err *err)
{
    al_surface s;
    sr_status st = al_surface_build(&s, mesh, NULL);
    if (st == SR_E_INVALID)
        return sr_err_set(err, st, "%s has no triangle with an area", what);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory describing %s", what);
    st = al_shape_describe(&s, out);
    al_surface_release(&s);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory describing %s", what);
    return SR_OK;
}

sr_status al_shape_describe(const al_surface *s, sr_shape_descriptor *out)
{
    al_samples smp;
    if (al_samples_make(s, D2_SAMPLES, D2_SEED, &smp) != SR_OK)
        return SR_E_NOMEM;
    sr_shape_descriptor d;
    memset(&d, 0, sizeof d);
    d.area_mm2 = s->total_area;
    double e[9], w[3];
    al_eig_sym(3, s->cov, w, e);
    /* al_eig_sym: ascending */
    for (int k = 0; k < 3; k++)
        d.spread_mm[k] = sqrt(fmax(0.0, w[2 - k]));
    double count = 0;
    for (size_t i = 0; i < smp.count; i++)
        for (size_t j = i + 1; j < smp.count; j++) {
            const double *a = smp.p + 3 * i, *b = smp.p + 3 * j;
            double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
            double r2 = dx * dx + dy * dy + dz * dz;
            /* log2 of the distance, in bins, from the histogram's first edge */
            double x = (0.5 * log2(r2 + 1e-300) - SR_SHAPE_D2_LOG2_MIN) * SR_SHAPE_D2_PER_OCTAVE;
            int bin = x < 0 ? 0 : x >= SR_SHAPE_D2_BINS ? SR_SHAPE_D2_BINS - 1 : (int)x;
            d.d2[bin] += 1;
            count += 1;
        }
    for (int k = 0; k < SR_SHAPE_D2_BINS && count > 0; k++)
        d.d2[k] /= count;
    al_samples_release(&smp);
    *out = d;
    return SR_OK;
}

double sr_shape_descriptor_distance(const sr_shape_descriptor *a, const sr_shape_descriptor *b)
{
    /* earth mover's distance on the log2 axis: the area between the two CDFs */
    double ca = 0, cb = 0, emd = 0;
    for (int k = 0; k < SR_SHAPE_D2_BINS; k++) {
        ca += a->d2[k];
        cb += b->d2[k];
        emd += fabs(ca - cb);
    }
    emd /= SR_SHAPE_D2_PER_OCTAVE;
    double spread = 0;
    for (int k = 0; k < 3; k++) {
        /* a flat part's smallest spread may be near 0: a floor of 1 % of the largest */
        double floor = 0.01 * fmax(a->spread_mm[0], b->spread_mm[0]) + 1e-9;
        spread += fabs(log2((a->spread_mm[k] + floor) / (b->spread_mm[k] + floor)));
    }
    return 0.5 * (emd + spread / 3);
}
