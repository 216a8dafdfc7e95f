/*
 * order_detect.c: cyclic order of an axial part from its sector grid (order_detect.h):
 * the trimmed mismatch of each full layer with itself turned, its median over layers,
 * against the mismatch at turns no order repeats.
 */
#include "align/order_detect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of v[0..n) (n >= 1); v is reordered. */
static double median(double *v, size_t n)
{
    qsort(v, n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Mean of the smallest seven eighths of |r(k) - r(k + turn)| over the S sectors of
 * one layer (r: S radii); d: S scratch doubles. */
static double layer_mismatch(const double *r, size_t S, double turn, double *d)
{
    for (size_t k = 0; k < S; k++) {
        double p = fmod((double)k + turn, (double)S);
        if (p < 0)
            p += (double)S;
        size_t i = (size_t)p % S, j = (i + 1) % S;
        double f = p - floor(p), rt = (1 - f) * r[i] + f * r[j];
        d[k] = fabs(r[k] - rt);
    }
    qsort(d, S, sizeof *d, cmp_double);
    size_t keep = S - S / 8;
    double sum = 0;
    for (size_t k = 0; k < keep; k++)
        sum += d[k];
    return sum / (double)keep;
}

/* The part's mismatch at a turn of `turn` sectors: the median over the full layers. */
static double part_mismatch(const sr_layer_grid *g, const size_t *full, size_t nfull,
                            double turn, double *d, double *per_layer)
{
    for (size_t i = 0; i < nfull; i++)
        per_layer[i] = layer_mismatch(g->r + full[i] * g->sectors, g->sectors, turn, d);
    return median(per_layer, nfull);
}

sr_status sr_order_detect(const sr_layer_grid *grid, double tolerance_mm,
                          sr_order_detection *out, sr_err *err)
{
    if (!(tolerance_mm > 0) || !isfinite(tolerance_mm))
        return sr_err_set(err, SR_E_RANGE, "bad order tolerance %g mm: expected > 0",
                          tolerance_mm);
    size_t S = grid->sectors, L = grid->layers;
    if (S < 4)
        return sr_err_set(err, SR_E_RANGE,
                          "cannot find an order on %zu sectors: expected at least 4", S);
    size_t *full = malloc((L ? L : 1) * sizeof *full);
    double *d = malloc(S * sizeof *d), *per_layer = malloc((L ? L : 1) * sizeof *per_layer);
    if (!full || !d || !per_layer) {
        free(full);
        free(d);
        free(per_layer);
        return sr_err_set(err, SR_E_NOMEM, "out of memory finding the order");
    }
    size_t nfull = 0;
    for (size_t l = 0; l < L; l++) {
        size_t k = 0;
        while (k < S && grid->r[l * S + k] > 0)
            k++;
        if (k == S)
            full[nfull++] = l;
    }
    sr_status st = SR_OK;
    if (nfull == 0) {
        st = sr_err_set(err, SR_E_INVALID,
                        "cannot find an order: no layer has a surface point in every sector");
        goto done;
    }
    sr_order_detection o;
    memset(&o, 0, sizeof o);
    o.layers_used = nfull;
    static const double odd_turns[3] = {0.1373, 0.2719, 0.3819};
    for (int i = 0; i < 3; i++)
        o.base_mm += part_mismatch(grid, full, nfull, odd_turns[i] * (double)S, d, per_layer) / 3;
    if (o.base_mm <= tolerance_mm) {
        o.round = 1;
    } else {
        /* every n's mismatch first: the best is the order or a divisor of it (or a
         * multiple's near miss); the largest n within twice the best (and the noise's
         * share of the tolerance) is the order. A neighbour of the order turns the part
         * by 360/n(n+1) degrees too far, which its flanks show (a 20-tooth gear: 0.30
         * mm at 21 teeth against 3e-5 mm at 20, posed). A turn by half the period must
         * mismatch clearly: any smooth profile matches itself turned by a sector or two */
        int nmax = (int)(S / 2 < 360 ? S / 2 : 360);
        double *m = malloc((size_t)(nmax + 1) * sizeof *m), best = INFINITY;
        if (!m) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory finding the order");
            goto done;
        }
        for (int n = 2; n <= nmax; n++) {
            m[n] = part_mismatch(grid, full, nfull, (double)S / n, d, per_layer);
            best = fmin(best, m[n]);
        }
        double accept = fmax(2 * best, tolerance_mm / 4);
        for (int n = nmax; n >= 2 && best <= tolerance_mm; n--)
            if (m[n] <= accept &&
                part_mismatch(grid, full, nfull, (double)S / (2 * n), d, per_layer) >
                    fmax(4 * accept, tolerance_mm)) {
                o.order = n;
                o.mismatch_mm = m[n];
                break;
            }
        free(m);
    }
    *out = o;
done:
    free(full);
    free(d);
    free(per_layer);
    return st;
}
