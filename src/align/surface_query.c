/*
 * surface_query.c: surface_query.h on align_surface.c's al_surface (the closest-point
 * grid and the area-uniform sampler), so callers outside src/align need not see
 * align_internal.h.
 */
#include "align/surface_query.h"

#include <math.h>
#include <stdlib.h>

#include "align/align_internal.h"

struct sr_surface_query {
    al_surface surf;
};

sr_status sr_surface_query_build(const sr_mesh *mesh, sr_surface_query **out, sr_err *err)
{
    sr_surface_query *s = calloc(1, sizeof *s);
    if (!s)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    sr_status st = al_surface_build(&s->surf, mesh, err);
    if (st != SR_OK) {
        free(s);
        return st;
    }
    *out = s;
    return SR_OK;
}

void sr_surface_query_free(sr_surface_query *s)
{
    if (!s)
        return;
    al_surface_release(&s->surf);
    free(s);
}

bool sr_surface_query_closest(sr_surface_query *s, const double p[3], double max_dist, double q[3],
                              double *dist, double *signed_dist)
{
    double qq[3], n[3], d;
    if (!isfinite(max_dist))
        max_dist = 1e300;
    if (!al_surface_closest(&s->surf, p, max_dist, qq, n, &d))
        return false;
    if (q) {
        q[0] = qq[0];
        q[1] = qq[1];
        q[2] = qq[2];
    }
    if (dist)
        *dist = d;
    if (signed_dist) {
        double dot = (p[0] - qq[0]) * n[0] + (p[1] - qq[1]) * n[1] + (p[2] - qq[2]) * n[2];
        *signed_dist = dot < 0 ? -d : d;
    }
    return true;
}

double sr_surface_query_area(const sr_surface_query *s)
{
    return s->surf.total_area;
}

sr_status sr_surface_query_samples(const sr_surface_query *s, size_t count, uint64_t seed,
                                   double *xyz)
{
    if (count == 0)
        return SR_OK;
    al_samples smp = {0};
    sr_status st = al_samples_make(&s->surf, count, seed, &smp);
    if (st != SR_OK)
        return st;
    for (size_t i = 0; i < 3 * count; i++)
        xyz[i] = smp.p[i];
    al_samples_release(&smp);
    return SR_OK;
}
