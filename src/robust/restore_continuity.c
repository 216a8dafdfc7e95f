/*
 * restore_continuity.c: carrying restored material from layer to layer where a break
 * hit both sides of the symmetry plane (restore_continuity.h): an xy bin index of the
 * scan's non-vertical triangles answers "which surface does a vertical segment through
 * this point meet first, and how steep is it"; Clipper does the region work.
 */
#include "robust/restore_continuity.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SAMPLES_PER_PIECE 400
#define END_VETO 4
#define WINDOW_MM 5.0 /* candidates are looked for this far beyond the damage */

/* ---- the vertical-segment query ---- */

typedef struct tri_index {
    const sr_mesh *m;
    double x0, y0, cell;    /* bin grid origin and cell size, mm */
    size_t nx, ny;
    size_t *first;          /* nx * ny + 1: CSR offsets into ids */
    uint32_t *ids;          /* triangle ids per bin */
    float *nz;              /* per triangle: z of the unit normal (0 = vertical, skipped) */
} tri_index;

static void tri_index_release(tri_index *t)
{
    free(t->first);
    free(t->ids);
    free(t->nz);
    memset(t, 0, sizeof *t);
}

static void tri_bbox(const sr_mesh *m, size_t i, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int v = 0; v < 3; v++) {
        const double *p = m->xyz + 3 * m->tri[3 * i + v];
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
}

static sr_status tri_index_build(const sr_mesh *m, tri_index *t, sr_err *err)
{
    memset(t, 0, sizeof *t);
    t->m = m;
    t->nz = malloc((m->tri_count ? m->tri_count : 1) * sizeof *t->nz);
    if (!t->nz)
        return sr_err_set(err, SR_E_NOMEM, "out of memory indexing the scan's triangles");
    double lo[3], hi[3];
    sr_mesh_bbox(m, lo, hi);
    size_t kept = 0;
    for (size_t i = 0; i < m->tri_count; i++) {
        const uint32_t *f = m->tri + 3 * i;
        const double *a = m->xyz + 3 * f[0], *b = m->xyz + 3 * f[1], *c = m->xyz + 3 * f[2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double nz = len > 0 ? n[2] / len : 0;
        t->nz[i] = fabs(nz) < 1e-3 ? 0.0f : (float)nz;
        kept += t->nz[i] != 0.0f;
    }
    double w = fmax(hi[0] - lo[0], 1e-6), h = fmax(hi[1] - lo[1], 1e-6);
    size_t side = (size_t)fmin(512.0, fmax(1.0, sqrt((double)kept) / 2));
    t->cell = fmax(w, h) / (double)side;
    t->x0 = lo[0];
    t->y0 = lo[1];
    t->nx = (size_t)(w / t->cell) + 1;
    t->ny = (size_t)(h / t->cell) + 1;
    t->first = calloc(t->nx * t->ny + 1, sizeof *t->first);
    if (!t->first) {
        tri_index_release(t);
        return sr_err_set(err, SR_E_NOMEM, "out of memory indexing the scan's triangles");
    }
    /* two passes: count per bin, then fill */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i = 0; i < m->tri_count; i++) {
            if (t->nz[i] == 0.0f)
                continue;
            double blo[3], bhi[3];
            tri_bbox(m, i, blo, bhi);
            size_t i0 = (size_t)((blo[0] - t->x0) / t->cell), i1 = (size_t)((bhi[0] - t->x0) / t->cell);
            size_t j0 = (size_t)((blo[1] - t->y0) / t->cell), j1 = (size_t)((bhi[1] - t->y0) / t->cell);
            if (i1 >= t->nx)
                i1 = t->nx - 1;
            if (j1 >= t->ny)
                j1 = t->ny - 1;
            for (size_t j = j0; j <= j1; j++)
                for (size_t k = i0; k <= i1; k++) {
                    size_t b = j * t->nx + k;
                    if (pass == 0)
                        t->first[b + 1]++;
                    else
                        t->ids[t->first[b]++] = (uint32_t)i;
                }
        }
        if (pass == 0) {
            for (size_t b = 0; b < t->nx * t->ny; b++)
                t->first[b + 1] += t->first[b];
            t->ids = malloc((t->first[t->nx * t->ny] ? t->first[t->nx * t->ny] : 1) *
                            sizeof *t->ids);
            if (!t->ids) {
                tri_index_release(t);
                return sr_err_set(err, SR_E_NOMEM,
                                  "out of memory indexing the scan's triangles");
            }
        }
    }
    /* the fill pass advanced first[b] to the end of bin b: shift back */
    for (size_t b = t->nx * t->ny; b > 0; b--)
        t->first[b] = t->first[b - 1];
    t->first[0] = 0;
    return SR_OK;
}

/* The first surface a vertical segment at (x, y) from z0 towards z1 meets strictly
 * after z0 and up to z1: returns 1 and its normal's z in *nz, or 0 if none. */
static int first_crossing(const tri_index *t, double x, double y, double z0, double z1,
                          double *nz, double *dist_out)
{
    if (x < t->x0 || y < t->y0)
        return 0;
    size_t i = (size_t)((x - t->x0) / t->cell), j = (size_t)((y - t->y0) / t->cell);
    if (i >= t->nx || j >= t->ny)
        return 0;
    size_t b = j * t->nx + i;
    double zlo = fmin(z0, z1), zhi = fmax(z0, z1), best = INFINITY;
    int found = 0;
    for (size_t k = t->first[b]; k < t->first[b + 1]; k++) {
        uint32_t id = t->ids[k];
        const uint32_t *f = t->m->tri + 3 * (size_t)id;
        const double *a = t->m->xyz + 3 * f[0], *p = t->m->xyz + 3 * f[1],
                     *q = t->m->xyz + 3 * f[2];
        if (fmax(a[2], fmax(p[2], q[2])) < zlo || fmin(a[2], fmin(p[2], q[2])) > zhi)
            continue;
        /* barycentric coordinates of (x, y) in the triangle's projection */
        double d = (p[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (p[1] - a[1]);
        if (d == 0)
            continue;
        double s = ((x - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (y - a[1])) / d;
        double r = ((p[0] - a[0]) * (y - a[1]) - (x - a[0]) * (p[1] - a[1])) / d;
        if (s < 0 || r < 0 || s + r > 1)
            continue;
        double zc = a[2] + s * (p[2] - a[2]) + r * (q[2] - a[2]);
        if (!(zc > zlo && zc < zhi) && !(zc == z1))
            continue;
        double dist = fabs(zc - z0);
        if (dist < best) {
            best = dist;
            *nz = t->nz[id];
            *dist_out = dist;
            found = 1;
        }
    }
    return found;
}

/* ---- scanlines ---- */

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The sorted x where row y crosses the region's boundary (clean region: inside between
 * crossings 2k and 2k + 1). *xs grows as needed; returns the count or -1 on no memory. */
static long row_crossings(const sr_poly2 *r, double y, double **xs, size_t *cap)
{
    size_t n = 0;
    for (size_t c = 0; c < r->contour_count; c++)
        for (size_t i = r->start[c]; i < r->start[c + 1]; i++) {
            size_t j = i + 1 < r->start[c + 1] ? i + 1 : r->start[c];
            double ay = r->xy[2 * i + 1], by = r->xy[2 * j + 1];
            if ((ay <= y) == (by <= y))
                continue;
            if (n == *cap) {
                size_t nc = *cap ? 2 * *cap : 64;
                double *g = realloc(*xs, nc * sizeof *g);
                if (!g)
                    return -1;
                *xs = g;
                *cap = nc;
            }
            double ax = r->xy[2 * i], bx = r->xy[2 * j];
            (*xs)[n++] = ax + (y - ay) / (by - ay) * (bx - ax);
        }
    qsort(*xs, n, sizeof **xs, cmp_dbl);
    return (long)n;
}

/* Inside test along a row walked left to right: *k is the caller's cursor. */
static int row_inside(const double *xs, long n, long *k, double x)
{
    while (*k < n && xs[*k] <= x)
        (*k)++;
    return (*k & 1) != 0;
}

/* ---- per layer ---- */

/* What the surface between z0 and z1 says about carrying the point (x, y), from the
 * first surface each image's vertical segment meets:
 *  - END: an image leaves material through a flat face (the feature ends here);
 *  - BROKEN: the point itself leaves material through an oblique face at a height
 *    where no other image leaves it alike (within sym_mm): a fracture. A surface the
 *    images meet alike is the part's own (a hole across the plane, a chamfer on both
 *    sides): damage does not come in mirrored pairs at one height;
 *  - SURFACE: some image meets a surface, but not so (e.g. only the mirror image
 *    leaves material, through the part's own surface, where the point itself is
 *    broken away: the point's fate is not known here);
 *  - NOTHING: no image meets a surface (the point lies in a break carried before). */
enum { SAY_NOTHING = 0, SAY_END, SAY_BROKEN, SAY_SURFACE };

static int judge_point(const tri_index *t, const sr_continuity_opts *o, double flat_cos,
                       double sym_mm, double x, double y, double z0, double z1)
{
    double img[3][3] = {{x, y, 0}, {-x, y, 0}, {-x, y, 0}};
    int n = 2;
    if (o->symmetry.kind == SR_SYM_GLIDE) {
        img[1][2] = o->symmetry.shift_mm;
        img[2][2] = -o->symmetry.shift_mm;
        n = 3;
    }
    double h[3], nz[3];
    int found[3], any = 0;
    for (int k = 0; k < n; k++) {
        found[k] = first_crossing(t, img[k][0], img[k][1], z0 + img[k][2], z1 + img[k][2],
                                  &nz[k], &h[k]);
        any |= found[k];
        if (found[k] && fabs(nz[k]) >= flat_cos && nz[k] * (z1 - z0) > 0)
            return SAY_END;
    }
    if (!any)
        return SAY_NOTHING;
    if (!found[0] || nz[0] * (z1 - z0) <= 0)
        return SAY_SURFACE; /* the point itself meets nothing, or enters material */
    for (int j = 1; j < n; j++)
        if (found[j] && (nz[j] > 0) == (nz[0] > 0) && fabs(h[j] - h[0]) <= sym_mm)
            return SAY_SURFACE;
    /* a break takes everything beyond it; material further on along the line (the
     * other side of a hole, an undercut) makes the face the part's own */
    double dir = z1 > z0 ? 1.0 : -1.0, nz_far, h_far;
    if (first_crossing(t, x, y, z0 + dir * (h[0] + 0.5 * sym_mm), z0 + dir * 1e9, &nz_far, &h_far) &&
        nz_far * dir < 0)
        return SAY_SURFACE;
    return SAY_BROKEN;
}

/* Whether any contour of r has its box within `near` of box b. */
static int near_box(const sr_poly2 *r, const double b[4], double near)
{
    for (size_t c = 0; c < r->contour_count; c++) {
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t i = r->start[c]; i < r->start[c + 1]; i++)
            for (int k = 0; k < 2; k++) {
                lo[k] = fmin(lo[k], r->xy[2 * i + k]);
                hi[k] = fmax(hi[k], r->xy[2 * i + k]);
            }
        if (lo[0] <= b[2] + near && b[0] <= hi[0] + near && lo[1] <= b[3] + near &&
            b[1] <= hi[1] + near)
            return 1;
    }
    return 0;
}

/* The verdict on one candidate piece: the surface between the planes is judged on a
 * grid of samples inside it (step `step`, made coarser to stay under
 * MAX_SAMPLES_PER_PIECE, finer until some sample falls inside a thin piece). Votes for:
 * BROKEN samples, and NOTHING samples lying in the reference layer's missing region on
 * a chain (this layer shows damage of its own next to the piece); against: END
 * samples. Carried when there are votes for and at least END_VETO times as many as
 * against. Deciding per piece keeps the carried outline an exact copy of the
 * reference layer's, so consecutive layers share their edges instead of nearly
 * touching. Returns 1 to carry, 0 not, -1 on no memory. */
static int judge_piece(const tri_index *t, const sr_continuity_opts *o, double flat_cos,
                       double step, const sr_poly2 *piece, const sr_poly2 *missing_prev,
                       int chain, double z0, double z1)
{
    double box[4];
    if (!sr_poly2_bounds(piece, box))
        return 0;
    double h = step;
    while (((box[2] - box[0]) / h + 1) * ((box[3] - box[1]) / h + 1) > MAX_SAMPLES_PER_PIECE)
        h *= 1.5;
    double *xs = NULL;
    size_t cap = 0;
    size_t inside = 0, broken = 0, chained = 0, ends = 0;
    int verdict = 0;
    for (int refine = 0; refine < 4 && inside == 0; refine++, h /= 3) {
        size_t ni = (size_t)((box[2] - box[0]) / h) + 1, nj = (size_t)((box[3] - box[1]) / h) + 1;
        for (size_t j = 0; j < nj; j++) {
            double y = box[1] + ((double)j + 0.5) * (box[3] - box[1]) / (double)nj;
            long n = row_crossings(piece, y, &xs, &cap), k = 0;
            if (n < 0) {
                free(xs);
                return -1;
            }
            for (size_t i = 0; i < ni; i++) {
                double x = box[0] + ((double)i + 0.5) * (box[2] - box[0]) / (double)ni;
                if (!row_inside(xs, n, &k, x))
                    continue;
                inside++;
                int say = judge_point(t, o, flat_cos, fmax(o->open_mm, 0.01), x, y, z0, z1);
                if (say == SAY_END)
                    ends++;
                else if (say == SAY_BROKEN)
                    broken++;
                else if (say == SAY_NOTHING && chain && sr_poly2_contains(missing_prev, x, y) != 0)
                    chained++;
            }
        }
    }
    free(xs);
    verdict = broken + chained > 0 && broken + chained >= END_VETO * ends;
    return verdict;
}

/* Carries into layer l (plane z1) what layer prev (plane z0) holds; *did = 1 when
 * something was carried. */
static sr_status carry(const tri_index *t, const sr_continuity_opts *o, double flat_cos,
                       double step, sr_poly2 *restored_l, sr_poly2 *missing_l,
                       const sr_poly2 *restored_prev, const sr_poly2 *missing_prev, double z0,
                       double z1, int *did, sr_err *err)
{
    *did = 0;
    if (missing_l->contour_count == 0 && missing_prev->contour_count == 0)
        return SR_OK;
    sr_poly2 near = {0}, cand = {0}, acc = {0};
    sr_poly2 *parts = NULL;
    size_t n_parts = 0;
    /* the candidate: what the reference layer holds that this layer lacks, in pieces
     * that reach within near_mm of either layer's damage (whole pieces: a shallow
     * fracture moves further than near_mm along the plane from one step to the next) */
    sr_status st = sr_poly2_boolean(SR_POLY_UNION, missing_l, missing_prev, &near, err);
    if (st == SR_OK)
        st = sr_poly2_offset(&near, o->near_mm, 0, &near, err);
    /* looked for within WINDOW_MM of that (the whole layer's difference costs seconds
     * on a noisy scan, in slivers far from any damage) */
    double nb[4];
    int have_near = st == SR_OK && sr_poly2_bounds(&near, nb);
    if (have_near) {
        double w[8] = {nb[0] - WINDOW_MM, nb[1] - WINDOW_MM, nb[2] + WINDOW_MM,
                       nb[1] - WINDOW_MM, nb[2] + WINDOW_MM, nb[3] + WINDOW_MM,
                       nb[0] - WINDOW_MM, nb[3] + WINDOW_MM};
        sr_poly2 win = {0};
        st = sr_poly2_add_contour(&win, w, 4, err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_INTERSECTION, restored_prev, &win, &cand, err);
        sr_poly2_release(&win);
    }
    if (st == SR_OK && cand.contour_count)
        st = sr_poly2_boolean(SR_POLY_DIFFERENCE, &cand, restored_l, &cand, err);
    /* slivers thinner than 2 x open_mm go, but what is kept keeps its exact outline
     * (the opened candidate grown by half the opening again, clipped to the raw one):
     * an opened outline rounds the candidate's convex corners, and what the rounding
     * leaves out becomes a pinhole in this layer that every later layer would copy.
     * The shrink is mitred: round joins put an arc of 1 um chords at every concave
     * vertex of a noisy candidate, and growing that back took a noisy plate's
     * continuation 2.2 of its 4.7 s (mitred: 0.16 s, the same restored part) */
    if (st == SR_OK && cand.contour_count && o->open_mm > 0) {
        sr_poly2 op = {0};
        st = sr_poly2_offset(&cand, -o->open_mm, 0, &op, err);
        if (st == SR_OK && op.contour_count)
            st = sr_poly2_offset(&op, 1.5 * o->open_mm, 0, &op, err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_INTERSECTION, &cand, &op, &cand, err);
        sr_poly2_release(&op);
    }
    if (st == SR_OK && cand.contour_count)
        st = sr_poly2_components(&cand, &parts, &n_parts, err);
    for (size_t i = 0; i < n_parts && st == SR_OK && have_near; i++) {
        double box[4];
        sr_poly2_bounds(&parts[i], box);
        if (box[0] > nb[2] || nb[0] > box[2] || box[1] > nb[3] || nb[1] > box[3])
            continue;
        sr_poly2 both = {0};
        st = sr_poly2_boolean(SR_POLY_INTERSECTION, &parts[i], &near, &both, err);
        int touches = both.contour_count > 0;
        sr_poly2_release(&both);
        if (st != SR_OK || !touches)
            continue;
        int chain = near_box(missing_l, box, o->near_mm);
        int v = judge_piece(t, o, flat_cos, step, &parts[i], missing_prev, chain, z0, z1);
        if (v < 0)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory carrying a layer");
        else if (v > 0)
            for (size_t c = 0; c < parts[i].contour_count && st == SR_OK; c++)
                st = sr_poly2_add_contour(&acc, parts[i].xy + 2 * parts[i].start[c],
                                          parts[i].start[c + 1] - parts[i].start[c], err);
    }
    if (st == SR_OK && acc.contour_count) {
        st = sr_poly2_boolean(SR_POLY_UNION, restored_l, &acc, restored_l, err);
        if (st == SR_OK)
            st = sr_poly2_boolean(SR_POLY_UNION, missing_l, &acc, missing_l, err);
        *did = st == SR_OK;
    }
    sr_poly2_components_release(parts, n_parts);
    sr_poly2_release(&near);
    sr_poly2_release(&cand);
    sr_poly2_release(&acc);
    return st;
}

sr_status sr_continuity_extend(const sr_mesh *aligned, const double *z, size_t layers,
                               sr_poly2 *restored, sr_poly2 *missing,
                               const sr_continuity_opts *opts, size_t *carried, sr_err *err)
{
    const sr_continuity_opts *o = opts;
    if (o->symmetry.kind != SR_SYM_MIRROR && o->symmetry.kind != SR_SYM_GLIDE)
        return sr_err_set(err, SR_E_RANGE, "continuity along z needs a mirror or glide");
    if (o->symmetry.kind == SR_SYM_GLIDE && !(o->symmetry.shift_mm > 0))
        return sr_err_set(err, SR_E_RANGE, "continuity along z: glide shift must be > 0 mm");
    if (!(o->open_mm >= 0) || !(o->near_mm >= 0) || !(o->flat_deg >= 0 && o->flat_deg < 90) ||
        !(o->sample_mm >= 0) || !isfinite(o->near_mm) || !isfinite(o->sample_mm))
        return sr_err_set(err, SR_E_RANGE,
                          "continuity along z: bad option (open %g, near %g, flat %g deg, "
                          "sample %g mm)",
                          o->open_mm, o->near_mm, o->flat_deg, o->sample_mm);
    sr_continuity_opts resolved = *opts;
    if (resolved.near_mm == 0)
        resolved.near_mm =
            3.0 * (layers >= 2 ? (z[layers - 1] - z[0]) / (double)(layers - 1) : 0) + 0.6;
    o = &resolved;
    double flat_cos = cos((o->flat_deg > 0 ? o->flat_deg : 20.0) * M_PI / 180.0);
    double step = o->sample_mm > 0 ? o->sample_mm : 0.2;
    size_t n_carried = 0;
    int any = 0;
    for (size_t l = 0; l < layers && !any; l++)
        any = missing[l].contour_count > 0;
    if (any && layers >= 2) {
        tri_index t;
        sr_status st = tri_index_build(aligned, &t, err);
        if (st != SR_OK)
            return st;
        char *hit = calloc(layers, 1);
        if (!hit) {
            tri_index_release(&t);
            return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu layers", layers);
        }
        /* the reference layer lies `stride` layers away, at least step_z_mm: a fracture
         * moves its edge by only a fraction of dz per layer, a sliver the opening
         * would drop */
        double dz = (z[layers - 1] - z[0]) / (double)(layers - 1);
        size_t stride = dz > 0 ? (size_t)ceil(fmax(o->step_z_mm > 0 ? o->step_z_mm : 0.5, dz) / dz - 1e-9) : 1;
        if (stride < 1)
            stride = 1;
        for (int down = 0; down < 2 && st == SR_OK; down++)
            for (size_t k = stride; k < layers && st == SR_OK; k++) {
                size_t l = down ? layers - 1 - k : k, prev = down ? l + stride : l - stride;
                int did = 0;
                st = carry(&t, o, flat_cos, step, &restored[l], &missing[l], &restored[prev],
                           &missing[prev], z[prev], z[l], &did, err);
                hit[l] |= (char)did;
            }
        for (size_t l = 0; l < layers; l++)
            n_carried += hit[l] != 0;
        free(hit);
        tri_index_release(&t);
        if (st != SR_OK)
            return st;
    }
    if (carried)
        *carried = n_carried;
    return SR_OK;
}
