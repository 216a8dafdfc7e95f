/*
 * layer_flats.c: flat-face area at each layer's planes (layer_flats.h): one histogram
 * of flat-triangle area over z (each triangle counted in every bin within margin of
 * its z-extent), read once per plane.
 */
#include "robust/layer_flats.h"

#include <math.h>
#include <stdlib.h>

#define MAX_BINS ((size_t)1 << 22)

typedef struct flat_histogram {
    double lo, w;           /* bin i covers [lo + i w, lo + (i + 1) w) */
    size_t bins;
    double *area;           /* area of the flat triangles within margin of bin i */
} flat_histogram;

static double area_at(const flat_histogram *h, double z)
{
    double f = floor((z - h->lo) / h->w);
    if (!(f >= 0) || f >= (double)h->bins)
        return 0;
    return h->area[(size_t)f];
}

static sr_status build_histogram(const sr_mesh *m, double margin, flat_histogram *h,
                                 sr_err *err)
{
    double bmin[3], bmax[3];
    sr_mesh_bbox(m, bmin, bmax);
    h->w = margin / 4;
    h->lo = bmin[2] - 2 * margin;
    double span = bmax[2] - bmin[2] + 4 * margin;
    if (span / h->w > (double)(MAX_BINS - 2))
        h->w = span / (double)(MAX_BINS - 2);
    h->bins = (size_t)ceil(span / h->w) + 2;
    h->area = calloc(h->bins + 1, sizeof *h->area);
    if (!h->area)
        return sr_err_set(err, SR_E_NOMEM, "out of memory measuring flat faces");
    /* a difference array: +area at the first bin within margin of the triangle, -area
     * after the last */
    for (size_t t = 0; t < m->tri_count; t++) {
        const double *a = m->xyz + 3 * m->tri[3 * t], *b = m->xyz + 3 * m->tri[3 * t + 1],
                     *c = m->xyz + 3 * m->tri[3 * t + 2];
        double n[3];
        sr_mesh_tri_normal(m, t, n);
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0) || fabs(n[2]) < SR_LAYER_FLATS_NZ * len)
            continue;
        double zlo = fmin(a[2], fmin(b[2], c[2])) - margin;
        double zhi = fmax(a[2], fmax(b[2], c[2])) + margin;
        size_t i0 = (size_t)floor((zlo - h->lo) / h->w);
        size_t i1 = (size_t)floor((zhi - h->lo) / h->w);
        if (i1 >= h->bins)
            i1 = h->bins - 1;
        h->area[i0] += 0.5 * len;
        h->area[i1 + 1] -= 0.5 * len;
    }
    double run = 0;
    for (size_t i = 0; i < h->bins; i++) {
        run += h->area[i];
        h->area[i] = run > 0 ? run : 0; /* rounding of the running sum */
    }
    return SR_OK;
}

sr_status sr_layer_flats_area(const sr_mesh *mesh, const sr_layer_flats_opts *o,
                              double *area_out, sr_err *err)
{
    if (o->layers == 0 || !(o->dz > 0) || !isfinite(o->dz) || !(o->margin_mm >= 0) ||
        !isfinite(o->margin_mm) || !isfinite(o->z_init))
        return sr_err_set(err, SR_E_RANGE,
                          "bad layer flats: %zu layers, dz %g mm, margin %g mm (expected "
                          "layers >= 1, dz > 0, margin > 0 or 0 for the default)",
                          o->layers, o->dz, o->margin_mm);
    double margin = o->margin_mm > 0 ? o->margin_mm : SR_LAYER_FLATS_MARGIN_MM;
    flat_histogram h = {0};
    sr_status st = build_histogram(mesh, margin, &h, err);
    if (st != SR_OK)
        return st;
    for (size_t l = 0; l < o->layers; l++) {
        double z = o->z_init + ((double)l + 0.5) * o->dz, a = area_at(&h, z);
        for (size_t s = 0; s < o->shift_count; s++)
            a += area_at(&h, z + o->shifts[s]);
        area_out[l] = a;
    }
    free(h.area);
    return SR_OK;
}
