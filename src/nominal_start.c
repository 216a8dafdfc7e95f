/*
 * nominal_start.c: the nominal's registration started from the symmetry alignment
 * (nominal_int.h). The reconstruction has already found the scan's symmetry element
 * and the transform A_s to its canonical frame (align.h); the part's intact mesh has
 * the same element, so sr_align with the same symmetry gives A_i, and the intact mesh
 * lies on the scan near A_s^-1 F A_i for some F that the canonical conventions leave
 * free: the signs of the canonical axes (the conventions sign them along the input's
 * own axes, which a posed scan turns), for an axial part the turn about the axis (only
 * within one period for an n-fold part: the other periods are the same pose), and a
 * shift by the damage (the canonical origins sit at the lowest point and the middle of
 * the extent, which a broken end moves). F's translation puts the intact's canonical
 * box centre on the scan's, on the axis or plane; the registration's ICP takes up the
 * rest. Those few starts replace sr_register's search of 160 turns of the principal
 * frames with a wide first cut-off, which is most of the nominal's time on a noisy
 * scan.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "align/align.h"
#include "nominal_int.h"

/* c = a b for 3 x 4 rigid transforms (b first). */
static void compose(const double a[12], const double b[12], double c[12])
{
    double m[12];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 4; j++)
            m[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j];
        m[4 * i + 3] += a[4 * i + 3];
    }
    memcpy(c, m, sizeof m);
}

/* inv = m^-1 for a rigid 3 x 4 transform. */
static void invert(const double m[12], double inv[12])
{
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            inv[4 * i + j] = m[4 * j + i];
        inv[4 * i + 3] = -(m[i] * m[3] + m[4 + i] * m[7] + m[8 + i] * m[11]);
    }
}

/* Centre of the box of m's vertices under the transform x. */
static void box_centre(const sr_mesh *m, const double x[12], double c[3])
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        for (int i = 0; i < 3; i++) {
            double q = x[4 * i] * p[0] + x[4 * i + 1] * p[1] + x[4 * i + 2] * p[2] + x[4 * i + 3];
            lo[i] = fmin(lo[i], q);
            hi[i] = fmax(hi[i], q);
        }
    }
    for (int i = 0; i < 3; i++)
        c[i] = 0.5 * (lo[i] + hi[i]);
}

#define MAX_TURNS 36

/* The starts (count x 12, intact -> scan) from the two alignments; returns the count. */
static size_t symmetry_starts(const sr_mesh *scan, const sr_mesh *intact, const double as[12],
                              const double ai[12], int axial, int order, double *out)
{
    double cs[3], ci[3], back[12];
    box_centre(scan, as, cs);
    box_centre(intact, ai, ci);
    invert(as, back);
    /* the proper sign matrices: identity, then turns by 180 degrees about z, x, y */
    static const double sign[4][3] = {{1, 1, 1}, {-1, -1, 1}, {1, -1, -1}, {-1, 1, -1}};
    /* axial: flips of the axis (x) times turns about it within one period */
    int turns = 1, flips = 4;
    double period = 2 * M_PI;
    if (axial) {
        flips = 2;
        period = order >= 2 ? 2 * M_PI / order : 2 * M_PI;
        turns = (int)ceil(period / (10 * M_PI / 180));
        turns = turns < 6 ? 6 : turns > MAX_TURNS ? MAX_TURNS : turns;
    }
    size_t n = 0;
    for (int f = 0; f < flips; f++)
        for (int t = 0; t < turns; t++) {
            double a = period * t / turns, ca = cos(a), sa = sin(a);
            const double *s = sign[axial && f ? 2 : f];
            /* F = Rz(a) diag(s), then its translation: F ci onto cs (on the axis or
             * the plane) */
            double fm[12] = {ca * s[0], -sa * s[1], 0, 0, sa * s[0], ca * s[1],
                             0,         0,          0, 0, s[2],      0};
            double fc[3];
            for (int i = 0; i < 3; i++)
                fc[i] = fm[4 * i] * ci[0] + fm[4 * i + 1] * ci[1] + fm[4 * i + 2] * ci[2];
            for (int i = 0; i < 3; i++)
                fm[4 * i + 3] = cs[i] - fc[i];
            if (axial)
                fm[3] = fm[7] = 0; /* both on the axis */
            else
                fm[3] = 0; /* both on the plane */
            double m[12];
            compose(fm, ai, m);
            compose(back, m, out + 12 * n);
            n++;
        }
    return n;
}

sr_status nominal_register(const sr_mesh *scan, const sr_mesh *intact, const sr_nominal_opts *o,
                           sr_register_result *out, int *full, sr_err *err)
{
    sr_register_opts ro = {o->tol_mm, o->samples};
    sr_register_result quick;
    memset(&quick, 0, sizeof quick);
    *full = 0;
    if (o->alignment) {
        const sr_alignment *as = o->alignment;
        int axial =
            as->plane_normal[0] == 0 && as->plane_normal[1] == 0 && as->plane_normal[2] == 0;
        sr_symmetry sym = {axial ? SR_SYM_AXIAL : SR_SYM_MIRROR, axial ? o->order : 0, 0};
        if (!axial && as->glide_shift_mm > 0) {
            sym.kind = SR_SYM_GLIDE;
            sym.shift_mm = as->glide_shift_mm;
        }
        sr_alignment ai;
        double *starts = malloc(2 * MAX_TURNS * 12 * sizeof *starts);
        sr_status st = starts ? sr_align(intact, &sym, NULL, &ai, err)
                              : sr_err_set(err, SR_E_NOMEM, "out of memory registering");
        if (st == SR_OK) {
            size_t n = symmetry_starts(scan, intact, as->xform, ai.xform, axial, sym.order, starts);
            st = sr_register_from(intact, scan, starts, n, &ro, &quick, err);
        }
        free(starts);
        if (st != SR_OK)
            return st;
        if (quick.coverage >= SR_NOMINAL_MIN_COVERAGE) {
            *out = quick;
            return SR_OK;
        }
    }
    *full = 1;
    sr_register_result r;
    sr_status st = sr_register(intact, scan, &ro, &r, err);
    if (st == SR_OK)
        *out = o->alignment && quick.coverage > r.coverage ? quick : r;
    return st;
}
