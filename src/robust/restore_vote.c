/*
 * restore_vote.c: restored and missing regions per layer by the symmetry's vote
 * (restore_vote.h): mirror/glide/rotation images united with Clipper, the continuous
 * axial coverage profile from exact circle-edge crossings, and the opening filter.
 */
#include "robust/restore_vote.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define CIRCLE_SEGMENTS 720

/* ---- images ---- */

/* out = p mirrored x -> -x, contours reversed so the orientation is kept. */
static sr_status mirrored(const sr_poly2 *p, sr_poly2 *out, sr_err *err)
{
    sr_poly2 m = {0};
    size_t n = sr_poly2_point_count(p);
    double *xy = malloc((n ? n : 1) * 2 * sizeof *xy);
    if (!xy)
        return sr_err_set(err, SR_E_NOMEM, "out of memory mirroring a layer");
    sr_status st = SR_OK;
    for (size_t c = 0; st == SR_OK && c < p->contour_count; c++) {
        size_t a = p->start[c], b = p->start[c + 1], k = 0;
        for (size_t i = b; i-- > a;) {
            xy[2 * k] = -p->xy[2 * i];
            xy[2 * k + 1] = p->xy[2 * i + 1];
            k++;
        }
        st = sr_poly2_add_contour(&m, xy, k, err);
    }
    free(xy);
    if (st != SR_OK) {
        sr_poly2_release(&m);
        return st;
    }
    *out = m;
    return SR_OK;
}

/* Appends p rotated by angle (radians) to *acc as raw contours. */
static sr_status append_rotated(const sr_poly2 *p, double angle, sr_poly2 *acc, sr_err *err)
{
    double c = cos(angle), s = sin(angle);
    size_t n = sr_poly2_point_count(p);
    double *xy = malloc((n ? n : 1) * 2 * sizeof *xy);
    if (!xy)
        return sr_err_set(err, SR_E_NOMEM, "out of memory rotating a layer");
    sr_status st = SR_OK;
    for (size_t k = 0; st == SR_OK && k < p->contour_count; k++) {
        size_t a = p->start[k], b = p->start[k + 1];
        for (size_t i = a; i < b; i++) {
            double x = p->xy[2 * i], y = p->xy[2 * i + 1];
            xy[2 * (i - a)] = c * x - s * y;
            xy[2 * (i - a) + 1] = s * x + c * y;
        }
        st = sr_poly2_add_contour(acc, xy, b - a, err);
    }
    free(xy);
    return st;
}

/* ---- continuous axial: coverage of circles ---- */

typedef struct crossing {
    double angle;
    int enter;              /* 1: moving counter-clockwise along the circle enters */
} crossing;

static int cmp_crossing(const void *a, const void *b)
{
    double x = ((const crossing *)a)->angle, y = ((const crossing *)b)->angle;
    return (x > y) - (x < y);
}

static sr_status coverage_profile(const sr_poly2 *d, double dr, size_t K, double *cov);

double sr_vote_circle_coverage(const sr_poly2 *region, double r)
{
    double cov = 0;
    /* one radius: the profile with dr = 2r has exactly the circle r as its sample 0 */
    if (!(r > 0) || coverage_profile(region, 2 * r, 1, &cov) != SR_OK)
        return -1;
    return cov;
}

static sr_status add_circle(sr_poly2 *p, double r, int cw, sr_err *err)
{
    double xy[2 * CIRCLE_SEGMENTS];
    for (int i = 0; i < CIRCLE_SEGMENTS; i++) {
        double a = 2 * M_PI * (cw ? CIRCLE_SEGMENTS - i : i) / CIRCLE_SEGMENTS;
        xy[2 * i] = r * cos(a);
        xy[2 * i + 1] = r * sin(a);
    }
    return sr_poly2_add_contour(p, xy, CIRCLE_SEGMENTS, err);
}

/* Non-zero winding number test of (x, y) against the region's contours. */
static int inside(const sr_poly2 *d, double x, double y)
{
    int w = 0;
    for (size_t c = 0; c < d->contour_count; c++) {
        size_t a = d->start[c], b = d->start[c + 1];
        for (size_t i = a; i < b; i++) {
            const double *P = d->xy + 2 * i, *Q = d->xy + 2 * (i + 1 < b ? i + 1 : a);
            double side = (Q[0] - P[0]) * (y - P[1]) - (x - P[0]) * (Q[1] - P[1]);
            if (P[1] <= y) {
                if (Q[1] > y && side > 0)
                    w++;
            } else if (Q[1] <= y && side < 0) {
                w--;
            }
        }
    }
    return w != 0;
}

/* Distance from the origin to segment p-q. */
static double seg_min_radius(const double *P, const double *Q)
{
    double dx = Q[0] - P[0], dy = Q[1] - P[1], len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? -(P[0] * dx + P[1] * dy) / len2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return hypot(P[0] + t * dx, P[1] + t * dy);
}

/* The coverage of the circles of radius (k + 1/2) dr, k = 0..K-1, in one pass over the
 * edges: each edge adds its crossings only to the radii its distance range spans. */
static sr_status coverage_profile(const sr_poly2 *d, double dr, size_t K, double *cov)
{
    size_t *count = calloc(K + 1, sizeof *count);
    crossing *all = NULL;
    if (!count)
        return SR_E_NOMEM;
    for (int pass = 0; pass < 2; pass++) {
        for (size_t c = 0; c < d->contour_count; c++) {
            size_t a = d->start[c], b = d->start[c + 1];
            for (size_t i = a; i < b; i++) {
                const double *P = d->xy + 2 * i, *Q = d->xy + 2 * (i + 1 < b ? i + 1 : a);
                double rlo = seg_min_radius(P, Q), rhi = fmax(hypot(P[0], P[1]), hypot(Q[0], Q[1]));
                long k0 = (long)ceil(rlo / dr - 0.5), k1 = (long)floor(rhi / dr - 0.5);
                if (k0 < 0)
                    k0 = 0;
                if (k1 >= (long)K)
                    k1 = (long)K - 1;
                double dx = Q[0] - P[0], dy = Q[1] - P[1];
                double A = dx * dx + dy * dy, B = P[0] * dx + P[1] * dy;
                for (long k = k0; k <= k1 && A > 0; k++) {
                    double r = (k + 0.5) * dr;
                    double C = P[0] * P[0] + P[1] * P[1] - r * r, disc = B * B - A * C;
                    if (disc <= 0)
                        continue;
                    double sq = sqrt(disc), ts[2] = {(-B - sq) / A, (-B + sq) / A};
                    for (int m = 0; m < 2; m++) {
                        if (ts[m] < 0 || ts[m] >= 1)
                            continue;
                        if (pass == 0) {
                            count[k + 1]++;
                            continue;
                        }
                        double x = P[0] + ts[m] * dx, y = P[1] + ts[m] * dy;
                        /* entering when the circle's ccw tangent (-y, x) points to the
                         * left of the edge (material lies left of an oriented contour) */
                        all[count[k]++] = (crossing){atan2(y, x), dx * x + dy * y > 0};
                    }
                }
            }
        }
        if (pass == 0) {
            for (size_t k = 0; k < K; k++)
                count[k + 1] += count[k];
            all = malloc((count[K] + 1) * sizeof *all);
            if (!all) {
                free(count);
                return SR_E_NOMEM;
            }
        } else {
            for (size_t k = K; k > 0; k--)
                count[k] = count[k - 1];
            count[0] = 0;
        }
    }
    for (size_t k = 0; k < K; k++) {
        crossing *v = all + count[k];
        size_t n = count[k + 1] - count[k];
        double r = (k + 0.5) * dr;
        if (n == 0) {
            /* no crossing: the whole circle is in or out; the same as the circle
             * before when that one had no crossing either (a contour fitting entirely
             * between two circles, dr apart, is ignored) */
            if (k > 0 && count[k] == count[k - 1])
                cov[k] = cov[k - 1];
            else
                cov[k] = inside(d, r, 0) ? 1.0 : 0.0;
            continue;
        }
        qsort(v, n, sizeof *v, cmp_crossing);
        double inside = 0;
        for (size_t i = 0; i < n; i++)
            if (v[i].enter)
                inside += (i + 1 < n ? v[i + 1].angle : v[0].angle + 2 * M_PI) - v[i].angle;
        cov[k] = inside / (2 * M_PI);
    }
    free(all);
    free(count);
    return SR_OK;
}

/* The annuli where coverage >= opts->coverage, minus the outer contours of d. */
static sr_status coverage_fill(const sr_poly2 *d, const sr_vote_opts *o, sr_poly2 *out,
                               sr_err *err)
{
    double rmax = 0;
    size_t n = sr_poly2_point_count(d);
    for (size_t i = 0; i < n; i++)
        rmax = fmax(rmax, hypot(d->xy[2 * i], d->xy[2 * i + 1]));
    double dr = o->radial_step_mm > 0 ? o->radial_step_mm : 0.01;
    double need = o->coverage > 0 ? o->coverage : 0.5;
    size_t K = (size_t)ceil(rmax / dr);
    sr_poly2 rings = {0}, outer = {0};
    double *cov = malloc((K + 1) * sizeof *cov);
    if (!cov || coverage_profile(d, dr, K, cov) != SR_OK) {
        free(cov);
        return sr_err_set(err, SR_E_NOMEM, "out of memory measuring coverage");
    }
    sr_status st = SR_OK;
    size_t run_start = SIZE_MAX;
    for (size_t k = 0; k <= K && st == SR_OK; k++) {
        int filled = k < K && cov[k] >= need;
        if (filled && run_start == SIZE_MAX)
            run_start = k;
        if (!filled && run_start != SIZE_MAX) {
            st = add_circle(&rings, k * dr, 0, err);
            if (st == SR_OK && run_start > 0)
                st = add_circle(&rings, run_start * dr, 1, err);
            run_start = SIZE_MAX;
        }
    }
    free(cov);
    for (size_t c = 0; st == SR_OK && c < d->contour_count; c++) {
        size_t a = d->start[c], b = d->start[c + 1];
        sr_poly2 one = {0};
        st = sr_poly2_add_contour(&one, d->xy + 2 * a, b - a, err);
        if (st == SR_OK && sr_poly2_area(&one) > 0)
            st = sr_poly2_add_contour(&outer, d->xy + 2 * a, b - a, err);
        sr_poly2_release(&one);
    }
    /* rings minus outer contours; on a noisy scan every dip of the surface below the
     * ring's radius would be a sliver (thousands per layer, and slow to build), so the
     * outer contours are grown by open_mm first and what is left grown back by as much
     * (within the rings): dips shallower than open_mm vanish, real losses keep their
     * shape (less a little at their corners: -1.6 % on the flange's broken rim). Only
     * for a noisy scan, when open_mm is above its 0.05 mm floor (reconstruct.c) */
    double grow = o->open_mm > 0.05 + 1e-9 ? o->open_mm : 0;
    if (st == SR_OK && grow > 0)
        st = sr_poly2_offset(&outer, grow, 0, &outer, err);
    if (st == SR_OK)
        st = sr_poly2_boolean(SR_POLY_DIFFERENCE, &rings, &outer, out, err);
    if (st == SR_OK && grow > 0 && out->contour_count > 0) {
        st = sr_poly2_offset(out, grow, 0, out, err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_INTERSECTION, out, &rings, out, err);
    }
    sr_poly2_release(&rings);
    sr_poly2_release(&outer);
    return st;
}

/* ---- per layer ---- */

static sr_status restore_layer(const sr_poly2 *d, const sr_poly2 *up, const sr_poly2 *down,
                               const sr_vote_opts *o, sr_poly2 *restored, sr_err *err)
{
    sr_poly2 acc = {0}, img = {0};
    sr_status st = sr_poly2_copy(d, &acc, err);
    switch (o->symmetry.kind) {
    case SR_SYM_MIRROR:
        if (st == SR_OK)
            st = mirrored(d, &img, err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_UNION, &acc, &img, &acc, err);
        break;
    case SR_SYM_GLIDE:
        for (int k = 0; k < 2 && st == SR_OK; k++) {
            const sr_poly2 *s = k ? down : up;
            if (!s || s->contour_count == 0)
                continue;
            sr_poly2_release(&img);
            st = mirrored(s, &img, err);
            if (st == SR_OK)
                st = sr_poly2_boolean(SR_POLY_UNION, &acc, &img, &acc, err);
        }
        break;
    case SR_SYM_AXIAL:
        if (o->symmetry.order >= 2) {
            /* the images one and two steps round each way: a broken tooth is restored
             * from its neighbours even when one of them is broken too; more copies
             * only cost time (damage only removes material) */
            int n = o->symmetry.order;
            for (int k = 1; k < n && st == SR_OK; k++)
                if (n <= 5 || k <= 2 || k >= n - 2)
                    st = append_rotated(d, 2 * M_PI * k / n, &acc, err);
            if (st == SR_OK)
                st = sr_poly2_boolean(SR_POLY_UNION, &acc, NULL, &acc, err);
        } else {
            if (st == SR_OK)
                st = coverage_fill(d, o, &img, err);
            if (st == SR_OK)
                st = sr_poly2_boolean(SR_POLY_UNION, &acc, &img, &acc, err);
        }
        break;
    default:
        st = sr_err_set(err, SR_E_RANGE, "bad symmetry: expected axial, mirror or glide");
    }
    sr_poly2_release(&img);
    if (st != SR_OK) {
        sr_poly2_release(&acc);
        return st;
    }
    sr_poly2_release(restored);
    *restored = acc;
    return SR_OK;
}

sr_status sr_vote_restore(const sr_poly2 *damaged, const sr_poly2 *shifted_up,
                          const sr_poly2 *shifted_down, size_t layers,
                          const sr_vote_opts *opts, sr_poly2 *restored, sr_poly2 *missing,
                          sr_err *err)
{
    if (!(opts->open_mm >= 0) || !isfinite(opts->open_mm))
        return sr_err_set(err, SR_E_RANGE, "bad open_mm %g: expected >= 0", opts->open_mm);
    if (!(opts->coverage >= 0 && opts->coverage <= 1))
        return sr_err_set(err, SR_E_RANGE, "bad coverage %g: expected 0..1", opts->coverage);
    if (opts->symmetry.kind == SR_SYM_GLIDE && (!shifted_up || !shifted_down))
        return sr_err_set(err, SR_E_RANGE, "glide vote needs the layers one shift away");
    for (size_t l = 0; l < layers; l++) {
        sr_status st = restore_layer(&damaged[l], shifted_up ? &shifted_up[l] : NULL,
                                     shifted_down ? &shifted_down[l] : NULL, opts,
                                     &restored[l], err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_DIFFERENCE, &restored[l], &damaged[l], &missing[l],
                                  err);
        /* the opening is mitred: round joins put an arc of 1 um chords at every corner
         * of a noisy layer's slivers, which everything after it then carries (a noisy
         * plate's continuation 2.7 -> 1.9 s, its restored part the same) */
        if (st == SR_OK && opts->open_mm > 0 && missing[l].contour_count > 0) {
            st = sr_poly2_offset(&missing[l], -opts->open_mm, 0, &missing[l], err);
            if (st == SR_OK && missing[l].contour_count > 0)
                st = sr_poly2_offset(&missing[l], opts->open_mm, 0, &missing[l], err);
            /* growing back may cross into the damaged part at concave corners */
            if (st == SR_OK && missing[l].contour_count > 0)
                st = sr_poly2_boolean(SR_POLY_INTERSECTION, &missing[l], &restored[l],
                                      &missing[l], err);
            if (st == SR_OK && missing[l].contour_count > 0)
                st = sr_poly2_boolean(SR_POLY_DIFFERENCE, &missing[l], &damaged[l],
                                      &missing[l], err);
        }
        if (st != SR_OK)
            return st;
    }
    return SR_OK;
}
