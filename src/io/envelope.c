/*
 * envelope.c: the physical envelope of an imported mesh (see envelope.h): every
 * coordinate finite and within +-1e6 mm, a bounding box at least 1e-3 mm across, and at
 * least one triangle with an area. The constants and the refusal messages live here and
 * nowhere else; the readers of src/bridge/ call these two functions.
 */
#include "io/envelope.h"

#include <math.h>
#include <stdio.h>

#include "io/check_int.h"

#include <stdlib.h>

/* The shortest %g form of v that reads back as v (1e+39, not 9.9999999999999994e+38). */
static const char *shortest(double v, char buf[32])
{
    for (int p = 6; p <= 17; p++) {
        snprintf(buf, 32, "%.*g", p, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return buf;
}

/* The refusal of point i's coordinate k, value v (named as in envelope.h). */
static sr_status outside(double v, size_t i, int k, int facet_corners, const char *name,
                         sr_err *err)
{
    char where[64], num[32];
    if (facet_corners == 3)
        snprintf(where, sizeof where, "facet %zu corner %zu", i / 3, i % 3);
    else
        snprintf(where, sizeof where, "vertex %zu", i);
    return fc_fail(err, SR_E_INVALID, name,
                   "%s coordinate %c = %s is outside the physical envelope "
                   "(|coordinate| <= 1e6 mm)",
                   where, "xyz"[k], shortest(v, num));
}

sr_status sr_envelope_check_points(const double *xyz, size_t count, int facet_corners,
                                   const char *name, sr_err *err)
{
    for (size_t i = 0; i < count; i++)
        for (int k = 0; k < 3; k++) {
            double v = xyz[3 * i + (size_t)k];
            if (!(fabs(v) <= SR_ENVELOPE_COORD_MAX)) /* written so that NaN fails too */
                return outside(v, i, k, facet_corners, name, err);
        }
    return SR_OK;
}

sr_status sr_envelope_check_corners(const float *corners, size_t facets, size_t first_facet,
                                    const char *name, sr_err *err)
{
    for (size_t i = 0; i < 3 * facets; i++)
        for (int k = 0; k < 3; k++) {
            double v = corners[3 * i + (size_t)k];
            if (!(fabs(v) <= SR_ENVELOPE_COORD_MAX))
                return outside(v, 3 * first_facet + i, k, 3, name, err);
        }
    return SR_OK;
}

sr_status sr_envelope_check_mesh(const double *xyz, size_t vertex_count, const uint32_t *tri,
                                 size_t tri_count, const char *name, sr_err *err)
{
    sr_status st = sr_envelope_check_points(xyz, vertex_count, 0, name, err);
    if (st != SR_OK)
        return st;
    if (tri_count == 0)
        return fc_fail(err, SR_E_INVALID, name, "contains no triangles");
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * tri_count; i++) {
        const double *p = xyz + 3 * (size_t)tri[i];
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    double extent = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    if (!(extent >= SR_ENVELOPE_EXTENT_MIN))
        return fc_fail(err, SR_E_INVALID, name,
                       "its largest extent, %.3g mm, is below the physical envelope "
                       "(bounding box >= 1e-3 mm)",
                       extent);
    for (size_t t = 0; t < tri_count; t++) {
        const double *a = xyz + 3 * (size_t)tri[3 * t], *b = xyz + 3 * (size_t)tri[3 * t + 1],
                     *c = xyz + 3 * (size_t)tri[3 * t + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        if (u[1] * v[2] - u[2] * v[1] != 0 || u[2] * v[0] - u[0] * v[2] != 0 ||
            u[0] * v[1] - u[1] * v[0] != 0)
            return SR_OK;
    }
    return fc_fail(err, SR_E_INVALID, name,
                   "none of its %zu triangles has an area (all degenerate: a flat or "
                   "collapsed mesh)",
                   tri_count);
}
