/*
 * symmetry_fit.c: proposing a scan's kind of symmetry (symmetry_fit.h).
 *
 * 1. Each kind is aligned by sr_align: the continuous axial axis, the mirror plane,
 *    the glide plane with its shift searched (a shift under 1.6 % of the bounding-box
 *    diagonal is a mirror, as sr_align counts it).
 * 2. One measure for every kind, the self-consistency: the same 3000 area-uniform
 *    samples p of the scan (with their normals) are mapped by each transform S of a
 *    candidate, and p matches when S(p) lies within tol of the scan's surface with the
 *    normal turned alike within 30 degrees. Continuous axial: turns by 0.1373, 0.2719,
 *    0.3819, 0.6181 and 0.8627 of a circle (no order up to 60 repeats them), a sample
 *    scoring 1 when most turns match it (a turn maps a sample onto a key, a bolt hole or
 *    the damage only now and then); n-fold: turns by k 360/n, k = 1, 2, n/2, n-1, the
 *    same way; mirror: the reflection; glide: the reflection with +shift and -shift,
 *    samples whose image leaves the part's ends not counted. tol = max(4 noise, 0.2 %
 *    of the diagonal), noise = the least residual of the fits / sqrt 2 (a matched image
 *    carries the noise twice): scan noise and facets both widen it.
 *    The consistency is the mean score leaving out the worst cells of a 4 x 4 x 4 grid
 *    over the part, up to a fifth of the samples: damage is local, and a kind that maps
 *    the damaged region onto itself (a mirror across a gouge) loses less to it than
 *    the right kind; trimmed, damage costs every kind alike, while a wrong symmetry
 *    misses everywhere.
 * 3. The order: on the continuous fit's axis, for n = 2..60, the share of every third
 *    sample matching when turned by 360/n; candidates are the n within 0.02 of the best
 *    whose turn by half the period, 180/n, matches clearly worse (by more than the
 *    paired noise 2 sqrt(discordant) / samples): any profile matches itself turned a
 *    little and a round part by any turn, while a real period's half puts a tooth onto
 *    a gap or a bolt hole onto the web. Of these the one matching best turned by
 *    k 360/n, k = 1, 2, n/2, n-1 (a neighbour of the order drifts off as k grows: 40
 *    for a 39-tooth gear), the largest within 0.01 (divisors match as well).
 *    With an order >= 3 the axis is refined by the n-fold fit.
 * 4. The proposal. A symmetry group that contains another fits at least as well: a
 *    round part matches every turn and has mirror planes through its axis, a gear has
 *    mirror planes through its teeth. So the highest kind that fits is taken:
 *     - axial (n-fold with the order found when >= 3, else continuous) when its
 *       consistency is at least AXIAL_KEEP of the planar one proposed (what does not
 *       turn with the part - a key - is a small share; on a mirror part most turned
 *       samples miss);
 *     - else the planar kinds: the glide (shift found) against the mirror; the higher
 *       consistency wins when they differ by more than the paired noise (at least 1 %),
 *       else "ambiguous" and the mirror (no shift) is proposed with the glide as the
 *       alternative. A mirror found across the glide's shift (its normal within 30
 *       degrees of the shift) is no evidence against the glide: a pattern repeated along
 *       a length has mirrors between its features, and damage in the middle of the
 *       length maps onto itself across one. Then the glide is weighed against the
 *       mirror in its own plane (no shift) and proposed when it beats that by the
 *       paired noise and keeps AXIAL_KEEP of the across mirror's consistency;
 *     - an order of 2 ranks below the planar kinds: parts with a 2-fold axis mostly
 *       also have a mirror or glide plane an engineer names (a bracket symmetric about
 *       two planes, a lever about its mid-plane, a rail whose glide composed with its
 *       ends' symmetry is a half turn); it is proposed only when it beats them by 0.1.
 *    Confidence: the margin of the proposal over the next candidate that does not
 *    contain it (the threshold it passed, for axial), saturating at 0.1, times the
 *    proposal's consistency; half its consistency when ambiguous.
 * Cost: three or four alignments (sr_align) and about 150k closest-point queries.
 */
#include "align/symmetry_fit.h"

#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FIT_SAMPLES 3000
#define COS_NORMAL 0.8660254037844386 /* 30 degrees */
#define AXIAL_KEEP 0.80
#define GLIDE_MIN_OF_DIAG 0.016

const char *sr_symfit_cand_name(sr_symfit_cand c)
{
    switch (c) {
    case SR_SYMFIT_ROUND: return "axial";
    case SR_SYMFIT_NFOLD: return "axial n-fold";
    case SR_SYMFIT_MIRROR: return "mirror";
    case SR_SYMFIT_GLIDE: return "glide";
    default: return "?";
    }
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A transform in the canonical frame of an alignment: rotation about z by `angle`
 * (axial) or reflection x -> -x with a shift along z (planar). */
typedef struct canon_op {
    int reflect;
    double angle;
    double shift;
} canon_op;

static void canon_apply(const canon_op *op, const double c[3], double out[3], int is_dir)
{
    if (op->reflect) {
        out[0] = -c[0];
        out[1] = c[1];
        out[2] = c[2] + (is_dir ? 0 : op->shift);
    } else {
        double cs = cos(op->angle), sn = sin(op->angle);
        out[0] = cs * c[0] - sn * c[1];
        out[1] = sn * c[0] + cs * c[1];
        out[2] = c[2];
    }
}

/* Scan-frame image of point p (is_dir 0) or direction (1) under op in the frame xf. */
static void image_of(const double xf[12], const canon_op *op, const double p[3], double out[3],
                     int is_dir)
{
    double c[3], d[3];
    for (int r = 0; r < 3; r++)
        c[r] = xf[4 * r] * p[0] + xf[4 * r + 1] * p[1] + xf[4 * r + 2] * p[2] +
               (is_dir ? 0 : xf[4 * r + 3]);
    canon_apply(op, c, d, is_dir);
    if (!is_dir)
        for (int r = 0; r < 3; r++)
            d[r] -= xf[4 * r + 3];
    for (int k = 0; k < 3; k++)
        out[k] = xf[k] * d[0] + xf[4 + k] * d[1] + xf[8 + k] * d[2];
}

/* Canonical z of point p in the frame xf. */
static double canon_z(const double xf[12], const double p[3])
{
    return xf[8] * p[0] + xf[9] * p[1] + xf[10] * p[2] + xf[11];
}

/* Marks in hit[] whether each sample's image under op lies on the surface with its
 * normal turned alike (1), not (0), or is not counted (2: a glide moves the part along
 * itself, so samples whose image leaves the part's extent along the shift, canonical z
 * outside [zlo, zhi], say nothing: the symmetry holds away from the ends). `stride`
 * takes every stride-th sample only (the others are marked 2). Returns the share of
 * the counted samples that match. */
static double classify(al_surface *s, const al_samples *smp, const double xf[12],
                       const canon_op *op, double tol, double zlo, double zhi, size_t stride,
                       unsigned char *hit)
{
    size_t on = 0, used = 0;
    for (size_t i = 0; i < smp->count; i++) {
        double q[3], nq[3], cp[3], cn[3], d;
        hit[i] = 2;
        if (i % stride)
            continue;
        if (op->reflect && op->shift != 0) {
            double z = canon_z(xf, smp->p + 3 * i) + op->shift;
            if (z < zlo || z > zhi)
                continue;
        }
        image_of(xf, op, smp->p + 3 * i, q, 0);
        image_of(xf, op, smp->n + 3 * i, nq, 1);
        int ok =
            al_surface_closest(s, q, tol, cp, cn, &d) && d <= tol && v3_dot(nq, cn) >= COS_NORMAL;
        hit[i] = (unsigned char)ok;
        on += (size_t)ok;
        used++;
    }
    return used ? (double)on / (double)used : 0;
}

/* Per-sample score of a candidate with several transforms: the share of its counted
 * transforms that match the sample (-1: none counted). majority != 0: 1 when more
 * than half match, else 0 (a turn of an axial part maps a sample onto a key, a bolt
 * hole or the damage only now and then; on a part that is not round most samples miss
 * at most turns). */
static void candidate_scores(al_surface *s, const al_samples *smp, const double xf[12],
                             const canon_op *ops, int count, double tol, double zlo, double zhi,
                             int majority, unsigned char *hit, float *score)
{
    size_t n = smp->count;
    unsigned char *votes = hit + n, *used = hit + 2 * n;
    memset(votes, 0, 2 * n);
    for (int k = 0; k < count; k++) {
        classify(s, smp, xf, ops + k, tol, zlo, zhi, 1, hit);
        for (size_t i = 0; i < n; i++)
            if (hit[i] != 2) {
                votes[i] = (unsigned char)(votes[i] + hit[i]);
                used[i]++;
            }
    }
    for (size_t i = 0; i < n; i++) {
        if (!used[i])
            score[i] = -1;
        else if (majority)
            score[i] = 2 * votes[i] > used[i] ? 1.0f : 0.0f;
        else
            score[i] = (float)votes[i] / (float)used[i];
    }
}

#define CELLS 4  /* per axis of the samples' bounding box */
#define TRIM 0.2 /* share of the samples the worst cells may take out */

/* The consistency of per-sample scores: their mean, leaving out the worst cells of a
 * CELLS^3 grid over the samples up to TRIM of the samples. Damage is local: it (and
 * where a symmetry maps it) takes out a few cells for every kind, whichever kind maps
 * it onto itself; a wrong symmetry misses everywhere. */
static double trimmed_mean(const float *score, const uint8_t *cell, size_t n)
{
    double sum[CELLS * CELLS * CELLS] = {0};
    size_t cnt[CELLS * CELLS * CELLS] = {0}, total = 0;
    for (size_t i = 0; i < n; i++)
        if (score[i] >= 0) {
            sum[cell[i]] += score[i];
            cnt[cell[i]]++;
            total++;
        }
    if (!total)
        return 0;
    int order[CELLS * CELLS * CELLS] = {0}, m = 0;
    for (int c = 0; c < CELLS * CELLS * CELLS; c++)
        if (cnt[c]) {
            /* insertion by mean, worst first */
            int j = m++;
            while (j > 0 &&
                   sum[order[j - 1]] / (double)cnt[order[j - 1]] > sum[c] / (double)cnt[c]) {
                order[j] = order[j - 1];
                j--;
            }
            order[j] = c;
        }
    size_t dropped = 0;
    int first = 0;
    while (first < m - 1 && (double)(dropped + cnt[order[first]]) <= TRIM * (double)total)
        dropped += cnt[order[first++]];
    double s = 0;
    size_t k = 0;
    for (int j = first; j < m; j++) {
        s += sum[order[j]];
        k += cnt[order[j]];
    }
    return k ? s / (double)k : 0;
}

/* The noise of the difference of two candidates' consistencies from the samples both
 * score (*used of them) on which they disagree: 2 sqrt(discordant) / used, at least
 * 1 %. */
static double scores_noise(const float *a, const float *b, size_t n, size_t *used)
{
    size_t disc = 0;
    *used = 0;
    for (size_t i = 0; i < n; i++)
        if (a[i] >= 0 && b[i] >= 0) {
            (*used)++;
            disc += fabsf(a[i] - b[i]) > 0.25f;
        }
    return fmax(0.01, 2.0 * sqrt((double)disc) / (double)(*used ? *used : 1));
}

/* Whether the mirror of frame xm lies across the glide of frame xg: its normal (the
 * canonical x of xm) within 30 degrees of the glide's shift direction (canonical z). */
static bool across_glide(const double xm[12], const double xg[12])
{
    return fabs(xm[0] * xg[8] + xm[1] * xg[9] + xm[2] * xg[10]) > COS_NORMAL;
}

static const double ROUND_TURNS[] = {0.1373, 0.2719, 0.3819, 0.6181, 0.8627};

/* Paired noise of two per-sample match sets: 2 sqrt(discordant) / counted, at least
 * 1 %. */
static double paired_noise(const unsigned char *a, const unsigned char *b, size_t n)
{
    size_t disc = 0, used = 0;
    for (size_t i = 0; i < n; i++)
        if (a[i] != 2 && b[i] != 2) {
            used++;
            disc += a[i] != b[i];
        }
    return fmax(0.01, 2.0 * sqrt((double)disc) / (double)(used ? used : 1));
}

/* The ops of an n-fold candidate: turns by k 360/n for k = 1, 2, n/2, n-1 (distinct);
 * returns how many. */
static int nfold_ops(int n, canon_op *ops)
{
    int ks[4] = {1, 2, n / 2, n - 1}, count = 0;
    for (int k = 0; k < 4; k++) {
        int dup = 0;
        for (int j = 0; j < k; j++)
            dup |= ks[j] == ks[k];
        if (!dup && ks[k] >= 1 && ks[k] < n)
            ops[count++] = (canon_op){0, 2 * M_PI * ks[k] / n, 0};
    }
    return count;
}

/* The order of the continuous fit's axis: for n = 2..60 the share of every third sample
 * that matches turned by 360/n. The orders within 0.02 of the best whose turn by half
 * the period, 180/n, matches clearly worse (any profile matches itself turned a little
 * and a round part by any turn; a real period's half puts a tooth onto a gap) are
 * candidates; of these the one whose turns by k 360/n (k = 1, 2, n/2, n-1) match most
 * samples (a neighbour of the order drifts off as k grows: 40 teeth for 39), the
 * largest within 0.01 of it (divisors of the order match as well). 0 when none. */
static int find_order(al_surface *s, const al_samples *smp, const double xf[12], double tol,
                      unsigned char *h1, unsigned char *h2)
{
    double c[61] = {0}, best = 0;
    for (int n = 2; n <= 60; n++) {
        canon_op op = {0, 2 * M_PI / n, 0};
        c[n] = classify(s, smp, xf, &op, tol, 0, 0, 3, h1);
        best = fmax(best, c[n]);
    }
    double full[61] = {0}, top = -1;
    for (int n = 60; n >= 2; n--) {
        full[n] = -1;
        canon_op op = {0, 2 * M_PI / n, 0}, half = {0, M_PI / n, 0};
        if (c[n] < best - 0.02)
            continue;
        classify(s, smp, xf, &op, tol, 0, 0, 3, h1);
        double ch = classify(s, smp, xf, &half, tol, 0, 0, 3, h2);
        if (c[n] - ch <= paired_noise(h1, h2, smp->count))
            continue;
        canon_op ops[4];
        int count = nfold_ops(n, ops);
        double sum = 0;
        for (int k = 0; k < count; k++)
            sum += classify(s, smp, xf, ops + k, tol, 0, 0, 3, h1);
        full[n] = sum / count;
        top = fmax(top, full[n]);
    }
    for (int n = 60; n >= 2 && top >= 0; n--)
        if (full[n] >= 0 && full[n] >= top - 0.01)
            return n;
    return 0;
}

sr_status sr_symmetry_propose(const sr_mesh *mesh, sr_symmetry_fit *out, sr_err *err)
{
    double t0 = now_s();
    sr_status st = sr_mesh_validate(mesh, "mesh", NULL, err);
    if (st != SR_OK)
        return st;
    sr_symmetry_fit r;
    memset(&r, 0, sizeof r);
    sr_alignment al[SR_SYMFIT_COUNT];
    memset(al, 0, sizeof al);
    const sr_symmetry kinds[3] = {
        {SR_SYM_AXIAL, 0, 0}, {SR_SYM_MIRROR, 0, 0}, {SR_SYM_GLIDE, 0, 0}};
    const int slot[3] = {SR_SYMFIT_ROUND, SR_SYMFIT_MIRROR, SR_SYMFIT_GLIDE};
    for (int k = 0; k < 3; k++) {
        st = sr_align(mesh, &kinds[k], NULL, &al[slot[k]], err);
        if (st != SR_OK)
            return st;
        r.fig[slot[k]].fitted = 1;
        r.fig[slot[k]].rms_mm = al[slot[k]].fit_rms_mm;
    }
    r.glide_shift_mm = al[SR_SYMFIT_GLIDE].glide_shift_mm;

    al_surface surf;
    st = al_surface_build(&surf, mesh, err);
    if (st != SR_OK)
        return st;
    al_samples smp = {0};
    const size_t N = FIT_SAMPLES;
    unsigned char *hit = malloc(4 * N);
    float *score = malloc((SR_SYMFIT_COUNT + 1) * N * sizeof *score);
    uint8_t *cell = malloc(N);
    if (!hit || !score || !cell || al_samples_make(&surf, N, 0x5eed0107u, &smp) != SR_OK) {
        st = sr_err_set(err, SR_E_NOMEM, "cannot fit the symmetry: out of memory");
        goto done;
    }
    r.samples = smp.count;
    if (r.glide_shift_mm < GLIDE_MIN_OF_DIAG * surf.diag)
        r.glide_shift_mm = 0; /* a mirror, as sr_align counts it */
    double rms_min = INFINITY;
    for (int c = 0; c < SR_SYMFIT_COUNT; c++)
        if (r.fig[c].fitted && r.fig[c].rms_mm < rms_min)
            rms_min = r.fig[c].rms_mm;
    r.noise_mm = rms_min / sqrt(2.0);
    r.tol_mm = fmax(4.0 * r.noise_mm, 0.002 * surf.diag);
    for (size_t i = 0; i < N; i++) {
        int idx = 0;
        for (int k = 0; k < 3; k++) {
            double ext = surf.bmax[k] - surf.bmin[k];
            int b = ext > 0 ? (int)((smp.p[3 * i + k] - surf.bmin[k]) / ext * CELLS) : 0;
            idx = idx * CELLS + (b < 0 ? 0 : (b >= CELLS ? CELLS - 1 : b));
        }
        cell[i] = (uint8_t)idx;
    }

    r.order = find_order(&surf, &smp, al[SR_SYMFIT_ROUND].xform, r.tol_mm, hit, hit + N);
    if (r.order == 2) {
        /* ranked below the planar kinds (see the top): scored on the continuous axis */
        al[SR_SYMFIT_NFOLD] = al[SR_SYMFIT_ROUND];
    } else if (r.order >= 3) {
        sr_symmetry nf = {SR_SYM_AXIAL, r.order, 0};
        st = sr_align(mesh, &nf, NULL, &al[SR_SYMFIT_NFOLD], err);
        if (st != SR_OK)
            goto done;
    }
    r.fig[SR_SYMFIT_NFOLD].fitted = r.order >= 2;
    r.fig[SR_SYMFIT_NFOLD].rms_mm = al[SR_SYMFIT_NFOLD].fit_rms_mm;

    canon_op ops[8];
    int n = 0;
    for (size_t k = 0; k < sizeof ROUND_TURNS / sizeof *ROUND_TURNS; k++)
        ops[n++] = (canon_op){0, 2 * M_PI * ROUND_TURNS[k], 0};
    candidate_scores(&surf, &smp, al[SR_SYMFIT_ROUND].xform, ops, n, r.tol_mm, 0, 0, 1, hit,
                     score + SR_SYMFIT_ROUND * N);
    if (r.order >= 2) {
        n = nfold_ops(r.order, ops);
        candidate_scores(&surf, &smp, al[SR_SYMFIT_NFOLD].xform, ops, n, r.tol_mm, 0, 0, 1, hit,
                         score + SR_SYMFIT_NFOLD * N);
    }
    ops[0] = (canon_op){1, 0, 0};
    candidate_scores(&surf, &smp, al[SR_SYMFIT_MIRROR].xform, ops, 1, r.tol_mm, 0, 0, 0, hit,
                     score + SR_SYMFIT_MIRROR * N);
    double zlo = INFINITY, zhi = -INFINITY;
    for (size_t i = 0; i < N; i++) {
        double z = canon_z(al[SR_SYMFIT_GLIDE].xform, smp.p + 3 * i);
        zlo = fmin(zlo, z);
        zhi = fmax(zhi, z);
    }
    ops[0] = (canon_op){1, 0, r.glide_shift_mm};
    ops[1] = (canon_op){1, 0, -r.glide_shift_mm};
    candidate_scores(&surf, &smp, al[SR_SYMFIT_GLIDE].xform, ops, r.glide_shift_mm > 0 ? 2 : 1,
                     r.tol_mm, zlo + r.tol_mm, zhi - r.tol_mm, 0, hit, score + SR_SYMFIT_GLIDE * N);
    /* a glide holds away from the part's ends: a sample within the shift of an end (an
     * end face maps into the part) says nothing about it, and the mirror it is weighed
     * against is scored on the same samples (a mirror across the middle of the length
     * maps one end face onto the other) */
    float *sm = score + SR_SYMFIT_COUNT * N, *sg = score + SR_SYMFIT_GLIDE * N;
    memcpy(sm, score + SR_SYMFIT_MIRROR * N, N * sizeof *sm);
    double margin = r.glide_shift_mm + r.tol_mm;
    for (size_t i = 0; i < N && r.glide_shift_mm > 0; i++) {
        double z = canon_z(al[SR_SYMFIT_GLIDE].xform, smp.p + 3 * i);
        if (z < zlo + margin || z > zhi - margin)
            sm[i] = sg[i] = -1;
    }
    for (int c = 0; c < SR_SYMFIT_COUNT; c++)
        if (r.fig[c].fitted)
            r.fig[c].consistency = trimmed_mean(score + (size_t)c * N, cell, N);
    double cm_glide = trimmed_mean(sm, cell, N);

    /* planar: glide against mirror; the noise of their difference from the samples on
     * which they disagree */
    size_t used = 0;
    double amb = scores_noise(sm, sg, N, &used);
    double cm = r.fig[SR_SYMFIT_MIRROR].consistency;
    double cg = r.fig[SR_SYMFIT_GLIDE].consistency;
    int has_glide = r.glide_shift_mm > 0 && used >= N / 2;
    int glide = has_glide && cg - cm_glide > amb;
    int planar_amb = has_glide && fabs(cg - cm_glide) <= amb;
    double c_inplane = 0;
    int across = has_glide && !glide;
    if (across)
        across = across_glide(al[SR_SYMFIT_MIRROR].xform, al[SR_SYMFIT_GLIDE].xform);
    if (across) {
        /* the mirror found lies across the glide's shift: a pattern repeated along a
         * length has such mirrors between its features (a rack's trapezoid teeth), and
         * damage in the middle of the length maps onto itself across one. It says
         * nothing against the glide; the mirror in the glide's own plane does. */
        float *si = score + SR_SYMFIT_COUNT * N;
        ops[0] = (canon_op){1, 0, 0};
        candidate_scores(&surf, &smp, al[SR_SYMFIT_GLIDE].xform, ops, 1, r.tol_mm, 0, 0, 0, hit,
                         si);
        for (size_t i = 0; i < N; i++)
            if (sg[i] < 0)
                si[i] = -1;
        c_inplane = trimmed_mean(si, cell, N);
        size_t u2 = 0;
        glide = cg - c_inplane > scores_noise(si, sg, N, &u2) && cg >= AXIAL_KEEP * cm;
        planar_amb = planar_amb && !glide;
    }
    sr_symfit_cand planar = glide ? SR_SYMFIT_GLIDE : SR_SYMFIT_MIRROR;
    double cp = glide ? cg : cm;
    sr_symfit_cand axial = r.order >= 3 ? SR_SYMFIT_NFOLD : SR_SYMFIT_ROUND;
    sr_symfit_cand pick = planar;
    double ca = r.fig[axial].consistency, other = 0;
    if (ca >= AXIAL_KEEP * cp) {
        pick = axial;
        other = AXIAL_KEEP * cp;
    } else if (r.order == 2 && r.fig[SR_SYMFIT_NFOLD].consistency > cp + 0.1) {
        pick = SR_SYMFIT_NFOLD;
        other = cp + 0.1;
    } else {
        other = ca / AXIAL_KEEP;
        if (planar_amb) {
            r.ambiguous = 1;
            r.alternative = (sr_symmetry){SR_SYM_GLIDE, 0, r.glide_shift_mm};
        } else if (has_glide) {
            /* an across mirror set aside: the glide's margin is over the mirror in its
             * own plane */
            other = fmax(other, !glide ? cg : across ? c_inplane : cm_glide);
        }
    }
    double cpick = r.fig[pick].consistency;
    r.confidence = r.ambiguous ? 0.5 * cpick : fmin(1.0, fmax(0.0, cpick - other) / 0.1) * cpick;
    switch (pick) {
    case SR_SYMFIT_ROUND: r.proposal = (sr_symmetry){SR_SYM_AXIAL, 0, 0}; break;
    case SR_SYMFIT_NFOLD: r.proposal = (sr_symmetry){SR_SYM_AXIAL, r.order, 0}; break;
    case SR_SYMFIT_MIRROR: r.proposal = (sr_symmetry){SR_SYM_MIRROR, 0, 0}; break;
    default: r.proposal = (sr_symmetry){SR_SYM_GLIDE, 0, r.glide_shift_mm}; break;
    }
    r.alignment = al[pick];
    r.seconds = now_s() - t0;
    *out = r;
    st = SR_OK;
done:
    free(hit);
    free(score);
    free(cell);
    al_samples_release(&smp);
    al_surface_release(&surf);
    return st;
}
