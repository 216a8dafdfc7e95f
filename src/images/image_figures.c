/*
 * image_figures.c: a section's figures in the image method (image_restore.h step 5):
 * from its voxels, the depth of build-up from the fracture and the lost surface area
 * (sr_img_voxel_figures, images_int.h); from its patch, its z, layer and angular range
 * and cell count (sr_image_section_figures).
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "images/images_int.h"

/* Depth of build-up and lost surface area from the section's voxels: the chamfer
 * distance from the fracture (section voxels next to the scan), its largest value and
 * its mean over the restored surface (section voxels next to air). */
void sr_img_voxel_figures(const sr_voxels *g, const local_box *b, sr_section *s)
{
    size_t cells = b->nx * b->ny * b->nz;
    float *d = malloc(cells * sizeof *d);
    if (!d)
        return;
    float inf = FLT_MAX;
    float h = (float)g->h;
    size_t faces_air = 0;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++) {
                size_t q = sr_img_lidx(b, i, j, k);
                d[q] = inf;
                if (b->sec[q] != 1)
                    continue;
                size_t gi = b->i0 + i, gj = b->j0 + j, gk = b->k0 + k;
                long nb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
                for (int e = 0; e < 6; e++) {
                    long ii = (long)gi + nb[e][0], jj = (long)gj + nb[e][1], kk = (long)gk + nb[e][2];
                    if (ii < 0 || jj < 0 || kk < 0 || ii >= (long)g->nx || jj >= (long)g->ny ||
                        kk >= (long)g->nz)
                        continue;
                    int solid = g->v[sr_voxel_index(g, (size_t)ii, (size_t)jj, (size_t)kk)] & 1;
                    long li = (long)i + nb[e][0], lj = (long)j + nb[e][1], lk = (long)k + nb[e][2];
                    int insec = li >= 0 && lj >= 0 && lk >= 0 && li < (long)b->nx &&
                                lj < (long)b->ny && lk < (long)b->nz &&
                                b->sec[sr_img_lidx(b, (size_t)li, (size_t)lj, (size_t)lk)] == 1;
                    if (solid)
                        d[q] = 0.5f * h;
                    else if (!insec)
                        faces_air++;
                }
            }
    /* two chamfer passes (weights 1, sqrt 2, sqrt 3 pitches) inside the section */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t n = 0; n < cells; n++) {
            size_t q = pass == 0 ? n : cells - 1 - n;
            if (b->sec[q] != 1)
                continue;
            size_t i = q % b->nx, j = (q / b->nx) % b->ny, k = q / (b->nx * b->ny);
            for (int dk = -1; dk <= 1; dk++)
                for (int dj = -1; dj <= 1; dj++)
                    for (int di = -1; di <= 1; di++) {
                        long ii = (long)i + di, jj = (long)j + dj, kk = (long)k + dk;
                        if (ii < 0 || jj < 0 || kk < 0 || ii >= (long)b->nx ||
                            jj >= (long)b->ny || kk >= (long)b->nz)
                            continue;
                        size_t w = sr_img_lidx(b, (size_t)ii, (size_t)jj, (size_t)kk);
                        if (b->sec[w] != 1 || d[w] == inf)
                            continue;
                        int steps = abs(di) + abs(dj) + abs(dk);
                        float c = d[w] + h * (steps == 1 ? 1.0f : steps == 2 ? 1.41421356f : 1.7320508f);
                        if (c < d[q])
                            d[q] = c;
                    }
        }
    }
    double dmax = 0, dsum = 0;
    size_t dn = 0;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++) {
                size_t q = sr_img_lidx(b, i, j, k);
                if (b->sec[q] != 1 || d[q] == inf)
                    continue;
                if (d[q] > dmax)
                    dmax = d[q];
                /* on the restored surface: a neighbour that is air */
                int air = 0;
                long nb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
                for (int e = 0; e < 6 && !air; e++) {
                    long li = (long)i + nb[e][0], lj = (long)j + nb[e][1], lk = (long)k + nb[e][2];
                    size_t gi = b->i0 + i + (size_t)nb[e][0], gj = b->j0 + j + (size_t)nb[e][1],
                           gk = b->k0 + k + (size_t)nb[e][2];
                    if (gi >= g->nx || gj >= g->ny || gk >= g->nz)
                        continue;
                    int insec = li >= 0 && lj >= 0 && lk >= 0 && li < (long)b->nx &&
                                lj < (long)b->ny && lk < (long)b->nz &&
                                b->sec[sr_img_lidx(b, (size_t)li, (size_t)lj, (size_t)lk)] == 1;
                    air = !insec && !(g->v[sr_voxel_index(g, gi, gj, gk)] & 1);
                }
                if (air) {
                    dsum += d[q];
                    dn++;
                }
            }
    free(d);
    s->depth_max_mm = dmax + 0.5 * g->h;
    s->depth_mean_mm = dn ? dsum / (double)dn + 0.5 * g->h : s->depth_max_mm;
    /* a voxel surface is on average 1.5 times the area of the surface it steps along */
    s->area_mm2 = (double)faces_air * g->h * g->h / 1.5;
}

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* z, layer and angular range of a section from its patch (aligned frame). */
void sr_image_section_figures(const sr_layer_grid *grid, sr_section *s)
{
    const sr_mesh *p = &s->patch;
    double lo[3], hi[3];
    sr_mesh_bbox(p, lo, hi);
    s->z_min = lo[2];
    s->z_max = hi[2];
    double fl = floor((lo[2] - grid->z_init) / grid->dz), fh = floor((hi[2] - grid->z_init) / grid->dz);
    double top = (double)grid->layers - 1;
    s->layer_first = (size_t)fmin(top, fmax(0, fl));
    s->layer_last = (size_t)fmin(top, fmax(0, fh));
    /* the smallest arc holding every vertex's azimuth: the complement of the widest gap */
    size_t n = p->vertex_count;
    double *a = malloc((n ? n : 1) * sizeof *a);
    s->angle_min_deg = 0;
    s->angle_max_deg = 360;
    if (a && n) {
        for (size_t v = 0; v < n; v++) {
            double t = atan2(p->xyz[3 * v + 1], p->xyz[3 * v]);
            a[v] = t < 0 ? t + 2 * M_PI : t;
        }
        qsort(a, n, sizeof *a, cmp_double);
        double gap = a[0] + 2 * M_PI - a[n - 1];
        size_t at = 0; /* the arc starts at a[at] */
        for (size_t i = 1; i < n; i++)
            if (a[i] - a[i - 1] > gap) {
                gap = a[i] - a[i - 1];
                at = i;
            }
        double start = a[at], span = 2 * M_PI - gap;
        /* as the other methods: max wrapped into [0, 360), the whole circle 0..360 */
        s->angle_min_deg = start * 180 / M_PI;
        s->angle_max_deg = fmod((start + span) * 180 / M_PI, 360.0);
        if (span >= 2 * M_PI * (1 - 1e-9)) {
            s->angle_min_deg = 0;
            s->angle_max_deg = 360;
        }
    }
    free(a);
    size_t N = grid->sectors;
    double step = 2 * M_PI / (double)N;
    s->sector_first = (size_t)floor(s->angle_min_deg * M_PI / 180 / step) % N;
    double arc = s->angle_max_deg - s->angle_min_deg;
    if (arc < 0)
        arc += 360;
    size_t sc = (size_t)ceil(arc * M_PI / 180 / step) + 1;
    s->sector_count = sc > N ? N : sc;
    s->cell_count = (s->layer_last - s->layer_first + 1) * s->sector_count;
}
