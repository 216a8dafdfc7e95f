/*
 * image_vote.c: the symmetry's vote on the scan's voxels, the opening and the grouping
 * into sections (see image_vote.h).
 */
#include "images/image_vote.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "images/image_lookup.h"

#define AXIAL_TURNS 24          /* continuous axial: turns by 15 degrees */
#define AXIAL_SHARE 0.6         /* ... of which this share must carry material */
#define CYCLIC_SLACK 1000       /* n-fold: one image in this many may disagree (tried
                                 * 10: a 15-tooth star read with order 14 filled the
                                 * narrow roots of its 15 gaps) */
#define WEAK_FIT_FLOOR 0.05     /* n-fold: the misfit no damage explains (reconstruct.c's
                                 * POOR_FIT_FLOOR) below which weak evidence is taken */
#define GROW_BACK 4             /* steps the opened cores grow back into the missing set */

static void rot_z(double xf[12], double a)
{
    double c = cos(a), s = sin(a);
    double m[12] = {c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0};
    memcpy(xf, m, sizeof m);
}

sr_status sr_images_of(const sr_symmetry *sym, sr_image **out, size_t *count, sr_err *err)
{
    size_t n = 0;
    sr_image *im = NULL;
    if (sym->kind == SR_SYM_MIRROR) {
        n = 1;
        im = calloc(n, sizeof *im);
        if (im) {
            double m[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
            memcpy(im[0].xf, m, sizeof m);
            memcpy(im[0].inv, m, sizeof m);
            im[0].form = SR_IMAGE_REFLECT_X;
        }
    } else if (sym->kind == SR_SYM_GLIDE) {
        if (!(sym->shift_mm > 0) || !isfinite(sym->shift_mm))
            return sr_err_set(err, SR_E_RANGE, "glide images need a shift > 0 mm");
        n = 2;
        im = calloc(n, sizeof *im);
        for (size_t k = 0; im && k < 2; k++) {
            double s = k == 0 ? sym->shift_mm : -sym->shift_mm;
            double m[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, s};
            double v[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -s};
            memcpy(im[k].xf, m, sizeof m);
            memcpy(im[k].inv, v, sizeof v);
            im[k].form = SR_IMAGE_REFLECT_X;
        }
    } else if (sym->kind == SR_SYM_AXIAL) {
        size_t turns = sym->order >= 2 ? (size_t)sym->order : AXIAL_TURNS;
        n = turns - 1;
        im = calloc(n, sizeof *im);
        for (size_t k = 1; im && k < turns; k++) {
            double a = 2.0 * M_PI * (double)k / (double)turns;
            rot_z(im[k - 1].xf, a);
            rot_z(im[k - 1].inv, -a);
            im[k - 1].form = SR_IMAGE_TURN_Z;
        }
    } else {
        return sr_err_set(err, SR_E_RANGE, "no symmetry to restore by");
    }
    if (!im)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for the symmetry's images");
    *out = im;
    *count = n;
    return SR_OK;
}

int sr_image_material(const sr_voxels *scan, const sr_image *im, const double c[3],
                      double z_lo, double z_hi, int glide)
{
    double p[3];
    const double *m = im->inv;
    if (im->form == SR_IMAGE_REFLECT_X) { /* the rows' zero and unit terms, left out */
        p[0] = -c[0];
        p[1] = c[1];
        p[2] = c[2] + m[11];
    } else if (im->form == SR_IMAGE_TURN_Z) {
        p[0] = m[0] * c[0] + m[1] * c[1];
        p[1] = m[4] * c[0] + m[5] * c[1];
        p[2] = c[2];
    } else {
        p[0] = m[0] * c[0] + m[1] * c[1] + m[2] * c[2] + m[3];
        p[1] = m[4] * c[0] + m[5] * c[1] + m[6] * c[2] + m[7];
        p[2] = m[8] * c[0] + m[9] * c[1] + m[10] * c[2] + m[11];
    }
    if (glide && (p[2] < z_lo || p[2] > z_hi))
        return -1;
    long v = sr_voxels_locate(scan, p);
    return v >= 0 ? (scan->v[v] & 1) : 0;
}

/* sr_image_material of image q at voxel (i, j, k), centre c: by the lookup when the
 * vote has one. */
static inline int material_at(const sr_voxels *scan, const sr_image *im, const sr_image_lookup *lut,
                              size_t q, size_t i, size_t j, size_t k, const double c[3],
                              double z_lo, double z_hi, int glide)
{
    return lut ? sr_image_lookup_material(lut, scan, q, i, j, k)
               : sr_image_material(scan, &im[q], c, z_lo, z_hi, glide);
}

/* The vote at one voxel the scan lacks: 2 when the images say material (strong), 1
 * for a glide voxel that one image says material and the other does not confirm, or
 * an n-fold one that a majority of the turns but not all say material (weak), 0
 * otherwise. */
static int vote(const sr_voxels *scan, const sr_image *im, const sr_image_lookup *lut, size_t n,
                const sr_symmetry *sym, size_t i, size_t j, size_t k, const double c[3],
                double z_lo, double z_hi)
{
    if (sym->kind == SR_SYM_MIRROR)
        return material_at(scan, im, lut, 0, i, j, k, c, z_lo, z_hi, 0) == 1 ? 2 : 0;
    if (sym->kind == SR_SYM_GLIDE) {
        /* both images, inside the part's length, are strong evidence. Within a
         * feature of the ends a rail's or rack's pattern ends on one side first, so
         * the image from beyond (the end's side) may say air or fall beyond the
         * ends: the image from the middle's side alone is weak evidence, taken only
         * where it continues a strong core (see sr_vote_missing). Tried: one image
         * alone (filled the patterns' ends on every rail and rack of a generated
         * set), the majority over the whole orbit (filled the plain ends beyond a
         * rack's teeth), both images only (missed every chip within a feature of
         * the ends), either image as weak evidence (filled a design notch at the
         * end beside a chip), weak only beyond the ends (missed a broken first
         * tooth). */
        if (c[2] < z_lo || c[2] > z_hi)
            return 0; /* beyond the ends the images say nothing */
        int a = material_at(scan, im, lut, 0, i, j, k, c, z_lo, z_hi, 1);
        int b = material_at(scan, im, lut, 1, i, j, k, c, z_lo, z_hi, 1);
        int inward = 2.0 * c[2] < z_lo + z_hi ? b : a; /* the image from the middle's side */
        return a == 1 && b == 1 ? 2 : inward == 1 ? 1 : 0;
    }
    size_t allowed = sym->order >= 2 ? n / CYCLIC_SLACK
                                     : (size_t)floor((1.0 - AXIAL_SHARE) * (double)n);
    /* n-fold: all turns but one in CYCLIC_SLACK are strong evidence; a majority of
     * them weak, taken only where it continues a strong core (sr_vote_missing): where
     * two damages lie a turn apart, each lacks the other's turn (a castellated nut's
     * chip beside a broken merlon stood 1.7 mm deep, the images voting 2 of 3) */
    size_t weak_fails = sym->order >= 2 ? (n - 1) / 2 : allowed;
    size_t fails = 0;
    for (size_t q = 0; q < n; q++)
        if (material_at(scan, im, lut, q, i, j, k, c, z_lo, z_hi, 0) != 1 && ++fails > weak_fails)
            return 0;
    return fails <= allowed ? 2 : 1;
}

void sr_vote_result_release(sr_vote_result *r)
{
    if (!r)
        return;
    free(r->label);
    free(r->voxels);
    free(r->weak_only);
    free(r->weak);
    free(r->at);
    memset(r, 0, sizeof *r);
}

typedef struct comp {
    size_t label, count;
} comp;

static int cmp_comp(const void *a, const void *b)
{
    const comp *x = a, *y = b;
    return x->count < y->count ? 1 : x->count > y->count ? -1 : (x->label > y->label) - (x->label < y->label);
}

static int cmp_dbl(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* Where the scan's voxels that image g lacks lie (out->misfit_where): the central 80 %
 * of their distance from the axis (axial) or the plane (planar), and of their z. */
static void misfit_where(const sr_voxels *scan, const sr_image *im, const sr_image_lookup *lut,
                         size_t g, const sr_symmetry *sym, double z_lo, double z_hi,
                         sr_vote_result *out)
{
    size_t nx = scan->nx, ny = scan->ny, total = nx * ny * scan->nz, cap = 4096, n = 0;
    double *d = malloc(cap * sizeof *d), *z = malloc(cap * sizeof *z);
    if (!d || !z) {
        free(d);
        free(z);
        return;
    }
    int axial = sym->kind == SR_SYM_AXIAL;
    for (size_t v = 0; v < total; v += 7) {
        if (!(scan->v[v] & 1))
            continue;
        size_t i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
        double c[3] = {scan->origin[0] + (double)i * scan->h, scan->origin[1] + (double)j * scan->h,
                       scan->origin[2] + (double)k * scan->h};
        if (material_at(scan, im, lut, g, i, j, k, c, z_lo, z_hi, sym->kind == SR_SYM_GLIDE) != 0)
            continue;
        if (n == cap) {
            double *d2 = realloc(d, 2 * cap * sizeof *d), *z2 = d2 ? realloc(z, 2 * cap * sizeof *z) : NULL;
            if (d2)
                d = d2;
            if (!z2)
                break;
            z = z2;
            cap *= 2;
        }
        d[n] = axial ? hypot(c[0], c[1]) : fabs(c[0]);
        z[n] = c[2];
        n++;
    }
    if (n >= 10) {
        qsort(d, n, sizeof *d, cmp_dbl);
        qsort(z, n, sizeof *z, cmp_dbl);
        out->misfit_where[0] = d[n / 10];
        out->misfit_where[1] = d[n - 1 - n / 10];
        out->misfit_where[2] = z[n / 10];
        out->misfit_where[3] = z[n - 1 - n / 10];
        out->misfit_located = 1;
    }
    free(d);
    free(z);
}

/* Axial: which rings about the axis hold material, per layer: ring[k nb + b] = 1 when
 * an occupied voxel of layer k has its centre at b <= r / h < b + 1. A turn keeps a
 * voxel centre's radius r and its layer, and lands in the voxel nearest to it, whose
 * centre is within h / sqrt 2 of it: so every turn of a voxel whose rings b - 1 .. b + 1
 * are empty finds air, and its vote is 0 without asking them (the same votes, most of
 * the grid's air skipped). NULL when out of memory (then every voxel is voted). */
static uint8_t *axial_rings(const sr_voxels *scan, size_t *nb)
{
    size_t nx = scan->nx, ny = scan->ny, nz = scan->nz;
    double rmax = 0;
    for (int c = 0; c < 4; c++) {
        double x = scan->origin[0] + (c & 1 ? (double)(nx - 1) * scan->h : 0);
        double y = scan->origin[1] + (c & 2 ? (double)(ny - 1) * scan->h : 0);
        rmax = fmax(rmax, hypot(x, y));
    }
    double inv_h = 1.0 / scan->h; /* as the vote's ring test computes it */
    *nb = (size_t)(rmax * inv_h) + 3;
    uint8_t *ring = calloc(nz * *nb, 1);
    if (!ring)
        return NULL;
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++)
                if (scan->v[sr_voxel_index(scan, i, j, k)] & 1) {
                    double x = scan->origin[0] + (double)i * scan->h;
                    double y = scan->origin[1] + (double)j * scan->h;
                    ring[k * *nb + (size_t)(sqrt(x * x + y * y) * inv_h)] = 1;
                }
    return ring;
}

/* 1 when rings b - 1 .. b + 1 of layer k (b = floor(rh), rh = radius / pitch) hold no
 * material */
static int ring_empty(const uint8_t *ring, size_t nb, size_t k, double rh)
{
    size_t b = (size_t)rh;
    const uint8_t *row = ring + k * nb;
    for (size_t q = b ? b - 1 : 0; q <= b + 1; q++)
        if (q < nb && row[q])
            return 0;
    return 1;
}

/* The indices of the voxels m marks (m != 0), ascending, into *out (malloc'd). */
static sr_status missing_list(const uint8_t *m, size_t total, size_t **out, size_t *count)
{
    size_t n = 0;
    for (size_t v = 0; v < total; v++)
        n += m[v] != 0;
    size_t *at = malloc((n ? n : 1) * sizeof *at);
    if (!at)
        return SR_E_NOMEM;
    n = 0;
    for (size_t v = 0; v < total; v++)
        if (m[v])
            at[n++] = v;
    *out = at;
    *count = n;
    return SR_OK;
}

/* The erosion, in place: a missing voxel whose six neighbours are all missing (bit 1: of
 * the strong and weak voxels together, bits 0 and 2; bit 3: of the strong alone, bit 0).
 * It reads bits 0 and 2 and writes bits 1 and 3, so the order of the voxels does not
 * matter. Voxels on the grid's border keep no core. */
static void erode(const sr_voxels *g, uint8_t *m, const size_t *at, size_t at_n)
{
    size_t nx = g->nx, ny = g->ny, nz = g->nz, sx = 1, sy = nx, sz = nx * ny;
    for (size_t q = 0; q < at_n; q++) {
        size_t v = at[q], i = v % nx, j = (v / nx) % ny, k = v / sz;
        if (i < 1 || j < 1 || k < 1 || i + 1 >= nx || j + 1 >= ny || k + 1 >= nz)
            continue;
        uint8_t all = m[v] & m[v - sx] & m[v + sx] & m[v - sy] & m[v + sy] & m[v - sz] & m[v + sz];
        uint8_t any = (m[v] & 5) && (m[v - sx] & 5) && (m[v + sx] & 5) && (m[v - sy] & 5) &&
                      (m[v + sy] & 5) && (m[v - sz] & 5) && (m[v + sz] & 5);
        m[v] |= (uint8_t)((any ? 2 : 0) | (all & 1 ? 8 : 0));
    }
}

/* The label of the first labelled voxel among v's 26 neighbours (0: none). */
static int labelled_neighbour(const sr_voxels *g, const int *label, size_t v)
{
    size_t nx = g->nx, ny = g->ny, nz = g->nz;
    long i = (long)(v % nx), j = (long)((v / nx) % ny), k = (long)(v / (nx * ny));
    for (long dk = -1; dk <= 1; dk++)
        for (long dj = -1; dj <= 1; dj++)
            for (long di = -1; di <= 1; di++) {
                long ii = i + di, jj = j + dj, kk = k + dk;
                if (ii < 0 || jj < 0 || kk < 0 || ii >= (long)nx || jj >= (long)ny ||
                    kk >= (long)nz)
                    continue;
                int w = label[sr_voxel_index(g, (size_t)ii, (size_t)jj, (size_t)kk)];
                if (w > 0)
                    return w;
            }
    return 0;
}

/* The eroded cores (bit 1), 26-connected, numbered 1.. in the order of their first
 * voxel; *ncomp of them. */
static sr_status group_cores(const sr_voxels *g, const uint8_t *m, const size_t *at, size_t at_n,
                             int *label, size_t *ncomp, sr_err *err)
{
    size_t cap = 1024, nc = 0;
    size_t *stack = malloc(cap * sizeof *stack);
    if (!stack)
        return sr_err_set(err, SR_E_NOMEM, "out of memory grouping missing voxels");
    for (size_t q = 0; q < at_n; q++) {
        size_t v0 = at[q];
        if (!(m[v0] & 2) || label[v0])
            continue;
        nc++;
        size_t top = 0;
        stack[top++] = v0;
        label[v0] = (int)nc;
        while (top) {
            size_t v = stack[--top];
            size_t nb[26], nn = sr_voxel_neighbours26(g, v, nb);
            for (size_t e = 0; e < nn; e++) {
                size_t w = nb[e];
                if (!(m[w] & 2) || label[w])
                    continue;
                label[w] = (int)nc;
                size_t *grown = sr_grow(stack, top, &cap, sizeof *stack);
                if (!grown) {
                    free(stack);
                    return sr_err_set(err, SR_E_NOMEM, "out of memory grouping missing voxels");
                }
                stack = grown;
                stack[top++] = w;
            }
        }
    }
    free(stack);
    *ncomp = nc;
    return SR_OK;
}

/* The cores grown back inside the missing set (bits 0 and 2), GROW_BACK steps,
 * 26-connected: one undoes the erosion, the rest take back the thin edges of a chip the
 * erosion cut off. Each step reads the labels before it and sets its own after. */
static sr_status grow_back(const sr_voxels *g, const uint8_t *m, const size_t *at, size_t at_n,
                           int *label, int nt)
{
    int *grow = malloc((at_n ? at_n : 1) * sizeof *grow);
    if (!grow)
        return SR_E_NOMEM;
    for (int step = 0; step < GROW_BACK; step++) {
#pragma omp parallel for num_threads(nt) schedule(static)
        for (size_t q = 0; q < at_n; q++) {
            size_t v = at[q];
            grow[q] = (m[v] & 5) && !label[v] ? labelled_neighbour(g, label, v) : 0;
        }
        for (size_t q = 0; q < at_n; q++)
            if (grow[q])
                label[at[q]] = grow[q];
    }
    free(grow);
    return SR_OK;
}

/* The sections with at least min_voxels voxels, renumbered 1.. largest first, into
 * out (voxels, sections, weak_only from strong[core]: 1 when the core has a strong
 * voxel, NULL but on a glide); the others' labels to 0, and *at_n cut to the labelled
 * voxels. */
static sr_status keep_large(size_t *at, size_t *at_n, int *label, size_t ncomp, size_t min_voxels,
                            const uint8_t *strong, sr_vote_result *out, sr_err *err)
{
    comp *cs = calloc(ncomp + 1, sizeof *cs);
    int *remap = calloc(ncomp + 1, sizeof *remap);
    if (!cs || !remap) {
        free(cs);
        free(remap);
        return sr_err_set(err, SR_E_NOMEM, "out of memory grouping missing voxels");
    }
    for (size_t c = 0; c <= ncomp; c++)
        cs[c].label = c;
    for (size_t q = 0; q < *at_n; q++)
        if (label[at[q]] > 0)
            cs[label[at[q]]].count++;
    qsort(cs + 1, ncomp, sizeof *cs, cmp_comp);
    size_t kept = 0;
    for (size_t c = 1; c <= ncomp; c++)
        if (cs[c].count >= min_voxels && cs[c].count > 0)
            remap[cs[c].label] = (int)++kept;
    size_t *counts = calloc(kept ? kept : 1, sizeof *counts);
    uint8_t *weak_only = calloc(kept ? kept : 1, 1);
    if (!counts || !weak_only) {
        free(counts);
        free(weak_only);
        free(cs);
        free(remap);
        return sr_err_set(err, SR_E_NOMEM, "out of memory grouping missing voxels");
    }
    for (size_t c = 1; strong && c <= ncomp; c++)
        if (remap[c] > 0)
            weak_only[remap[c] - 1] = !strong[c];
    size_t n = 0;
    for (size_t q = 0; q < *at_n; q++) {
        size_t v = at[q];
        if (label[v] > 0)
            label[v] = remap[label[v]];
        if (label[v] > 0) {
            counts[label[v] - 1]++;
            at[n++] = v;
        }
    }
    *at_n = n;
    free(cs);
    free(remap);
    out->sections = kept;
    out->voxels = counts;
    out->weak_only = weak_only;
    return SR_OK;
}

sr_status sr_vote_missing(const sr_voxels *scan, const sr_symmetry *sym, double z_lo, double z_hi,
                          size_t min_voxels, int threads, sr_vote_result *out, sr_err *err)
{
    sr_image *im = NULL;
    size_t n = 0;
    memset(out, 0, sizeof *out);
    sr_status st = sr_images_of(sym, &im, &n, err);
    if (st != SR_OK)
        return st;
    size_t nx = scan->nx, ny = scan->ny, nz = scan->nz, total = nx * ny * nz;
    uint8_t *m = calloc(total, 1);      /* bit 0 missing, bit 1 eroded core */
    int *label = calloc(total, sizeof *label);
    if (!m || !label) {
        free(im);
        free(m);
        free(label);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu voxels", total);
    }
    size_t nb = 0;
    uint8_t *ring = sym->kind == SR_SYM_AXIAL ? axial_rings(scan, &nb) : NULL;
    /* each voxel's vote reads the scan alone and writes its own byte: layers spread
     * over the threads give the same votes for any number of them */
    int nt = threads > 0 ? threads : omp_get_max_threads();
    double inv_h = 1.0 / scan->h;
    sr_image_lookup *lut = sr_image_lookup_make(scan, im, n, z_lo, z_hi, sym->kind == SR_SYM_GLIDE,
                                                SR_IMAGE_LOOKUP_BUDGET);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 4)
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                size_t v = sr_voxel_index(scan, i, j, k);
                if (scan->v[v] & 1)
                    continue;
                double c[3] = {scan->origin[0] + (double)i * scan->h,
                               scan->origin[1] + (double)j * scan->h,
                               scan->origin[2] + (double)k * scan->h};
                if (ring && ring_empty(ring, nb, k, sqrt(c[0] * c[0] + c[1] * c[1]) * inv_h))
                    continue; /* every turn lands in the same empty ring: air */
                int e = vote(scan, im, lut, n, sym, i, j, k, c, z_lo, z_hi);
                m[v] = e == 2 ? 1 : e == 1 ? 4 : 0;
            }
    free(ring);
    /* how well the scan fits the symmetry: per image, the share of the scan's voxels
     * whose preimage is empty (where it is valid); the median over the images */
    size_t *miss = calloc(n, sizeof *miss), *seen = calloc(n, sizeof *seen);
    double *share = malloc(n * sizeof *share);
    int ok = miss && seen && share;
    if (ok) {
        /* counted per thread and summed: integers, so the same for any number */
#pragma omp parallel num_threads(nt)
        {
            size_t *my = calloc(2 * n, sizeof *my);
            if (!my) {
#pragma omp atomic write
                ok = 0;
            }
#pragma omp for schedule(static)
            for (size_t v = 0; v < total; v += 7) { /* a sample is plenty */
                if (!my || !(scan->v[v] & 1))
                    continue;
                size_t i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
                double c[3] = {scan->origin[0] + (double)i * scan->h,
                               scan->origin[1] + (double)j * scan->h,
                               scan->origin[2] + (double)k * scan->h};
                for (size_t q = 0; q < n; q++) {
                    int mat = material_at(scan, im, lut, q, i, j, k, c, z_lo, z_hi,
                                          sym->kind == SR_SYM_GLIDE);
                    if (mat < 0)
                        continue;
                    my[q]++;
                    my[n + q] += mat == 0;
                }
            }
#pragma omp critical
            for (size_t q = 0; my && q < n; q++) {
                seen[q] += my[q];
                miss[q] += my[n + q];
            }
            free(my);
        }
    }
    if (ok) {
        for (size_t q = 0; q < n; q++)
            share[q] = seen[q] ? (double)miss[q] / (double)seen[q] : 1.0;
        size_t *rank = malloc(n * sizeof *rank);
        if (rank) {
            for (size_t q = 0; q < n; q++)
                rank[q] = q;
            for (size_t a = 1; a < n; a++) /* n is small */
                for (size_t b = a; b > 0 && share[rank[b - 1]] > share[rank[b]]; b--) {
                    size_t t = rank[b];
                    rank[b] = rank[b - 1];
                    rank[b - 1] = t;
                }
            out->misfit = share[rank[n / 2]];
            misfit_where(scan, im, lut, rank[n / 2], sym, z_lo, z_hi, out);
            free(rank);
        }
    }
    free(miss);
    free(seen);
    free(share);
    /* the later steps touch the voxels the vote marked, and only them */
    size_t *at = NULL, at_n = 0;
    if (missing_list(m, total, &at, &at_n) != SR_OK) {
        free(im);
        free(m);
        free(label);
        sr_image_lookup_free(lut);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for the missing voxels");
    }
    free(im);
    sr_image_lookup_free(lut);
    /* n-fold: the majority's weak evidence only where the turns fit the scan (its
     * misfit explained by what the strong vote finds missing, as reconstruct.c's
     * poor-fit test reads it): a wrong order's turns agree by majority across the
     * roots of every gap (a 15-tooth star read with order 14: 11 sections, 1.4 cm3) */
    if (sym->kind == SR_SYM_AXIAL && sym->order >= 2) {
        size_t strong_n = 0, scan_n = 0;
        for (size_t q = 0; q < at_n; q++)
            strong_n += m[at[q]] == 1;
        for (size_t v = 0; v < total; v++)
            scan_n += scan->v[v] & 1;
        double explained = scan_n ? 2.0 * (double)strong_n / (double)scan_n : 0;
        if (!(out->misfit <= WEAK_FIT_FLOOR + explained))
            for (size_t q = 0; q < at_n; q++)
                if (m[at[q]] == 4)
                    m[at[q]] = 0;
    }
    erode(scan, m, at, at_n);
    size_t ncomp = 0;
    st = group_cores(scan, m, at, at_n, label, &ncomp, err);
    /* a core with no strong voxel is only an end of a pattern (dropped), or, on a glide,
     * a feature of the ends broken off: kept as a section said to be weak only, for
     * the caller to tell by the scan's surface round it (section_kind.c) */
    uint8_t *strong = st == SR_OK ? calloc(ncomp + 1, 1) : NULL;
    if (st == SR_OK && !strong)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory grouping missing voxels");
    if (st == SR_OK) {
        for (size_t q = 0; q < at_n; q++)
            if (label[at[q]] > 0 && (m[at[q]] & 8))
                strong[label[at[q]]] = 1;
        if (sym->kind != SR_SYM_GLIDE)
            for (size_t q = 0; q < at_n; q++)
                if (label[at[q]] > 0 && !strong[label[at[q]]])
                    label[at[q]] = 0;
        if (grow_back(scan, m, at, at_n, label, nt) != SR_OK)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu voxels", at_n);
    }
    if (st == SR_OK)
        st = keep_large(at, &at_n, label, ncomp, min_voxels,
                        sym->kind == SR_SYM_GLIDE ? strong : NULL, out, err);
    free(strong);
    if (st == SR_OK && sym->kind == SR_SYM_GLIDE) {
        out->weak = malloc((at_n ? at_n : 1) * sizeof *out->weak);
        if (!out->weak)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory grouping missing voxels");
        for (size_t q = 0; out->weak && q < at_n; q++)
            out->weak[q] = (m[at[q]] & 5) == 4;
    }
    free(m);
    if (st != SR_OK) {
        free(out->weak); /* what keep_large or the weak flags wrote */
        free(out->voxels);
        free(out->weak_only);
        out->weak = NULL;
        out->voxels = NULL;
        out->weak_only = NULL;
        free(at);
        free(label);
        return st;
    }
    out->label = label;
    out->at = at;
    out->at_count = at_n;
    return SR_OK;
}
