/*
 * image_restore.c: the image method's driver (see image_restore.h): voxel grid and
 * vote, then per section the hull, the choice of image, the exact patch and its
 * figures.
 */
#include "images/image_restore.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bridge/boolean.h"
#include "bridge/hull.h"
#include "bridge/mend.h"
#include "images/axis_seam.h"
#include "images/image_vote.h"
#include "images/voxels.h"
#include "mesh/mesh_shells.h"

#define GRID_VOXELS 8.0e6       /* the automatic pitch aims at this many voxels */
#define PITCH_MIN 0.15
#define PITCH_MAX 1.5
#define HULL_GROW 4.5           /* hull corners: voxel half-size + four voxels, in pitches */
#define BAND 2                  /* voxels around a section where images are compared */
#define MAX_IMAGES 4            /* images united for one section, at most */
#define FURTHER_SHARE 0.005     /* a further image only for this share of the section (tried
                                 * 0.02: a gouge beside two chips kept 1.4 % of itself, a
                                 * fracture face standing 2.9 mm inside the part) */
#define AXIS_RING 0.25          /* the ring about the axis tested for a seam, in pitches */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The grid over the aligned scan: symmetric about x = 0 (and y = 0 for an axis) so a
 * mirror maps voxel centres onto voxel centres, two voxels of air all round. */
static sr_status grid_make(const sr_mesh *m, const sr_image_opts *o, sr_voxels *g,
                           sr_err *err)
{
    double lo[3], hi[3];
    sr_mesh_bbox(m, lo, hi);
    double ext[3] = {2.0 * fmax(fabs(lo[0]), fabs(hi[0])), hi[1] - lo[1], hi[2] - lo[2]};
    int axial = o->symmetry.kind == SR_SYM_AXIAL;
    if (axial) {
        double r = fmax(ext[0] / 2, fmax(fabs(lo[1]), fabs(hi[1])));
        ext[0] = ext[1] = 2.0 * r;
    }
    double h = o->pitch_mm;
    if (!(h > 0)) {
        h = cbrt(fmax(ext[0] * ext[1] * ext[2], 1e-9) / GRID_VOXELS);
        h = fmin(PITCH_MAX, fmax(PITCH_MIN, h));
    }
    size_t n[3];
    double origin[3];
    for (int a = 0; a < 3; a++) {
        n[a] = (size_t)ceil(ext[a] / h) + 5;
        if (a == 0 || (a == 1 && axial)) {
            n[a] += n[a] % 2 ? 0 : 1; /* odd: a centre on the plane */
            origin[a] = -0.5 * (double)(n[a] - 1) * h;
        } else {
            origin[a] = lo[a] - 2.0 * h;
        }
    }
    double total = (double)n[0] * (double)n[1] * (double)n[2];
    if (total > 2.0e8)
        return sr_err_set(err, SR_E_RANGE,
                          "voxel pitch %.3g mm gives %.3g voxels over the part: too fine", h,
                          total);
    sr_status st = sr_voxels_alloc(g, n, h, origin);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory for %.0f voxels", total);
    return SR_OK;
}

static void voxel_centre(const sr_voxels *g, size_t v, double c[3])
{
    size_t i = v % g->nx, j = (v / g->nx) % g->ny, k = v / (g->nx * g->ny);
    c[0] = g->origin[0] + (double)i * g->h;
    c[1] = g->origin[1] + (double)j * g->h;
    c[2] = g->origin[2] + (double)k * g->h;
}

/* Sections whose grown boxes meet (their hulls would overlap, and the union of one's
 * image would cut the other's) become one: two chips side by side are one repair. */
static void merge_near_sections(const sr_voxels *g, sr_vote_result *vr)
{
    size_t n = vr->sections;
    if (n < 2)
        return;
    long *box = malloc(n * 6 * sizeof *box);
    size_t *parent = malloc((n + 1) * sizeof *parent);
    if (!box || !parent) {
        free(box);
        free(parent);
        return;
    }
    for (size_t s = 0; s < n; s++) {
        box[6 * s] = box[6 * s + 1] = box[6 * s + 2] = LONG_MAX;
        box[6 * s + 3] = box[6 * s + 4] = box[6 * s + 5] = LONG_MIN;
    }
    size_t total = g->nx * g->ny * g->nz;
    for (size_t v = 0; v < total; v++) {
        int l = vr->label[v];
        if (l <= 0)
            continue;
        long ijk[3] = {(long)(v % g->nx), (long)((v / g->nx) % g->ny), (long)(v / (g->nx * g->ny))};
        long *b = box + 6 * (size_t)(l - 1);
        for (int a = 0; a < 3; a++) {
            if (ijk[a] < b[a]) b[a] = ijk[a];
            if (ijk[a] > b[3 + a]) b[3 + a] = ijk[a];
        }
    }
    long grow = (long)ceil(HULL_GROW) + 1;
    for (size_t s = 0; s <= n; s++)
        parent[s] = s;
    int merged = 0;
    for (size_t a = 0; a < n; a++)
        for (size_t b = a + 1; b < n; b++) {
            int meet = 1;
            for (int k = 0; k < 3 && meet; k++)
                meet = box[6 * a + k] - grow <= box[6 * b + 3 + k] + grow &&
                       box[6 * b + k] - grow <= box[6 * a + 3 + k] + grow;
            if (!meet)
                continue;
            size_t ra = a + 1, rb = b + 1;
            while (parent[ra] != ra) ra = parent[ra];
            while (parent[rb] != rb) rb = parent[rb];
            if (ra != rb) {
                parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
                merged = 1;
            }
        }
    if (merged) {
        /* labels to their roots, renumbered 1..k in order (largest first stays first) */
        size_t *num = calloc(n + 1, sizeof *num), k = 0;
        if (num) {
            for (size_t s = 1; s <= n; s++) {
                size_t r = s;
                while (parent[r] != r) r = parent[r];
                if (!num[r])
                    num[r] = ++k;
                num[s] = num[r];
            }
            memset(vr->voxels, 0, n * sizeof *vr->voxels);
            for (size_t v = 0; v < total; v++)
                if (vr->label[v] > 0) {
                    vr->label[v] = (int)num[vr->label[v]];
                    vr->voxels[vr->label[v] - 1]++;
                }
            vr->sections = k;
            free(num);
        }
    }
    free(box);
    free(parent);
}

/* One section's voxels in a local box: sec (1 = in the section), the box's origin in
 * grid indices and its size. */
typedef struct local_box {
    size_t i0, j0, k0, nx, ny, nz;
    uint8_t *sec;      /* 1 section, 2 band (within BAND voxels, not in the section) */
} local_box;

static size_t lidx(const local_box *b, size_t i, size_t j, size_t k)
{
    return (k * b->ny + j) * b->nx + i;
}

/* out[i] = 1 where in has a 1 within BAND steps of i along a line of len voxels,
 * stride apart (a running count over the window). */
static void dilate_line(const uint8_t *in, uint8_t *out, size_t len, size_t stride)
{
    long n = (long)len, ones = 0;
    for (long i = 0; i < BAND && i < n; i++)
        ones += in[(size_t)i * stride];
    for (long i = 0; i < n; i++) {
        if (i + BAND < n)
            ones += in[(size_t)(i + BAND) * stride];
        if (i - BAND - 1 >= 0)
            ones -= in[(size_t)(i - BAND - 1) * stride];
        out[(size_t)i * stride] = ones > 0;
    }
}

static sr_status box_make(const sr_voxels *g, const int *label, int s, local_box *b)
{
    size_t lo[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX}, hi[3] = {0, 0, 0};
    size_t total = g->nx * g->ny * g->nz;
    for (size_t v = 0; v < total; v++) {
        if (label[v] != s)
            continue;
        size_t ijk[3] = {v % g->nx, (v / g->nx) % g->ny, v / (g->nx * g->ny)};
        for (int a = 0; a < 3; a++) {
            if (ijk[a] < lo[a]) lo[a] = ijk[a];
            if (ijk[a] > hi[a]) hi[a] = ijk[a];
        }
    }
    if (lo[0] == SIZE_MAX)
        return SR_E_RANGE; /* no voxel left (a design recess taken out) */
    size_t n[3] = {g->nx, g->ny, g->nz};
    for (int a = 0; a < 3; a++) {
        lo[a] = lo[a] >= BAND ? lo[a] - BAND : 0;
        hi[a] = hi[a] + BAND < n[a] ? hi[a] + BAND : n[a] - 1;
    }
    b->i0 = lo[0];
    b->j0 = lo[1];
    b->k0 = lo[2];
    b->nx = hi[0] - lo[0] + 1;
    b->ny = hi[1] - lo[1] + 1;
    b->nz = hi[2] - lo[2] + 1;
    b->sec = calloc(b->nx * b->ny * b->nz, 1);
    if (!b->sec)
        return SR_E_NOMEM;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++)
                if (label[sr_voxel_index(g, b->i0 + i, b->j0 + j, b->k0 + k)] == s)
                    b->sec[lidx(b, i, j, k)] = 1;
    /* the band: within BAND voxels (a cube) of the section, a dilation axis by axis */
    size_t nb = b->nx * b->ny * b->nz;
    uint8_t *m = malloc(nb), *t = malloc(nb);
    if (!m || !t) {
        free(m);
        free(t);
        free(b->sec);
        b->sec = NULL;
        return SR_E_NOMEM;
    }
    for (size_t v = 0; v < nb; v++)
        m[v] = b->sec[v] == 1;
    size_t sx = 1, sy = b->nx, sz = b->nx * b->ny;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            dilate_line(m + k * sz + j * sy, t + k * sz + j * sy, b->nx, sx);
    for (size_t k = 0; k < b->nz; k++)
        for (size_t i = 0; i < b->nx; i++)
            dilate_line(t + k * sz + i, m + k * sz + i, b->ny, sy);
    for (size_t j = 0; j < b->ny; j++)
        for (size_t i = 0; i < b->nx; i++)
            dilate_line(m + j * sy + i, t + j * sy + i, b->nz, sz);
    for (size_t v = 0; v < nb; v++)
        if (b->sec[v] == 0 && t[v])
            b->sec[v] = 2;
    free(m);
    free(t);
    return SR_OK;
}

/* The section's hull: corners of its column-extreme voxels grown by HULL_GROW. */
static sr_status hull_make(const sr_voxels *g, const local_box *b, double z_min, double z_max,
                           sr_mesh *out, sr_err *err)
{
    size_t cap = 2 * b->nx * b->ny + 8, n = 0;
    double *pts = malloc(cap * 3 * sizeof *pts);
    if (!pts)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a section's hull");
    double r = HULL_GROW * g->h;
    for (size_t j = 0; j < b->ny; j++)
        for (size_t i = 0; i < b->nx; i++) {
            long kmin = -1, kmax = -1;
            for (size_t k = 0; k < b->nz; k++)
                if (b->sec[lidx(b, i, j, k)] == 1) {
                    if (kmin < 0)
                        kmin = (long)k;
                    kmax = (long)k;
                }
            if (kmin < 0)
                continue;
            long ks[2] = {kmin, kmax};
            for (int e = 0; e < (kmin == kmax ? 1 : 2) && n < cap; e++, n++) {
                pts[3 * n] = g->origin[0] + (double)(b->i0 + i) * g->h;
                pts[3 * n + 1] = g->origin[1] + (double)(b->j0 + j) * g->h;
                pts[3 * n + 2] = g->origin[2] + (double)(b->k0 + (size_t)ks[e]) * g->h;
            }
        }
    /* the hull of the centres first, then its corners grown: the hull of a set grown
     * by a cube is the hull of its hull's vertices grown by it (8 times fewer points
     * for the large hull) */
    sr_mesh centres = {0};
    sr_status st = sr_convex_hull(pts, n, &centres, err);
    if (st != SR_OK) { /* flat (one layer, one row): every centre grown */
        centres.xyz = pts;
        centres.vertex_count = n;
        pts = NULL;
    }
    size_t m = centres.vertex_count;
    double *grown = malloc((8 * m + 1) * 3 * sizeof *grown);
    if (!grown) {
        free(pts);
        if (st == SR_OK)
            sr_mesh_release(&centres);
        else
            free(centres.xyz);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a section's hull");
    }
    for (size_t v = 0; v < m; v++)
        for (int q = 0; q < 8; q++) {
            const double *c = centres.xyz + 3 * v;
            double *o = grown + 3 * (8 * v + (size_t)q);
            o[0] = c[0] + (q & 1 ? r : -r);
            o[1] = c[1] + (q & 2 ? r : -r);
            o[2] = fmin(fmax(c[2] + (q & 4 ? r : -r), z_min), z_max);
        }
    if (st == SR_OK)
        sr_mesh_release(&centres);
    else
        free(centres.xyz);
    free(pts);
    st = sr_convex_hull(grown, 8 * m, out, err);
    free(grown);
    return st;
}

/* Over the section's voxels not covered yet: cover[m] += those whose preimage under
 * im[m] (m < n) is material; mark: they are marked covered too (give one image). */
static void cover_pass(const sr_voxels *g, const local_box *b, uint8_t *covered,
                       const sr_image *im, size_t n, double z_lo, double z_hi, int glide,
                       long *cover, int mark)
{
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++) {
                size_t q = lidx(b, i, j, k);
                if (b->sec[q] != 1 || covered[q])
                    continue;
                double c[3];
                voxel_centre(g, sr_voxel_index(g, b->i0 + i, b->j0 + j, b->k0 + k), c);
                for (size_t m = 0; m < n; m++)
                    if (sr_image_material(g, &im[m], c, z_lo, z_hi, glide) == 1) {
                        cover[m]++;
                        if (mark)
                            covered[q] = 1;
                    }
            }
}

/* The images whose material covers the section, best first (greedy cover): each
 * scored by the section voxels it newly covers less the band voxels where it
 * disagrees with the scan. Writes up to MAX_IMAGES indices; returns how many. */
static size_t choose_images(const sr_voxels *g, const local_box *b, const sr_image *im,
                            size_t n_im, const sr_symmetry *sym, double z_lo, double z_hi,
                            size_t pick[MAX_IMAGES])
{
    size_t cells = b->nx * b->ny * b->nz;
    uint8_t *covered = calloc(cells, 1);
    long *cover = calloc(n_im, sizeof *cover), *mismatch = calloc(n_im, sizeof *mismatch);
    size_t chosen = 0;
    if (!covered || !cover || !mismatch)
        goto done;
    int glide = sym->kind == SR_SYM_GLIDE;
    size_t section_voxels = 0;
    for (size_t q = 0; q < cells; q++)
        section_voxels += b->sec[q] == 1;
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++) {
                uint8_t s = b->sec[lidx(b, i, j, k)];
                if (s != 2)
                    continue;
                size_t v = sr_voxel_index(g, b->i0 + i, b->j0 + j, b->k0 + k);
                double c[3];
                voxel_centre(g, v, c);
                int here = g->v[v] & 1;
                for (size_t m = 0; m < n_im; m++) {
                    int mat = sr_image_material(g, &im[m], c, z_lo, z_hi, glide);
                    if (mat >= 0 && mat != here)
                        mismatch[m]++;
                }
            }
    size_t done_voxels = 0;
    while (chosen < MAX_IMAGES && done_voxels < section_voxels) {
        memset(cover, 0, n_im * sizeof *cover);
        cover_pass(g, b, covered, im, n_im, z_lo, z_hi, glide, cover, 0);
        long best_score = 0;
        size_t best = n_im;
        for (size_t m = 0; m < n_im; m++) {
            int used = 0;
            for (size_t u = 0; u < chosen; u++)
                used |= pick[u] == m;
            /* covering the section first; the band's disagreement (noise, a key the
             * image carries) decides between images that cover alike */
            long score = 4 * cover[m] - mismatch[m];
            if (!used && cover[m] > 0 && (best == n_im || score > best_score)) {
                best = m;
                best_score = score;
            }
        }
        /* a further image only for a real share of the section */
        if (best == n_im || (chosen > 0 && (double)cover[best] < FURTHER_SHARE * (double)section_voxels))
            break;
        pick[chosen++] = best;
        long newly = 0;
        cover_pass(g, b, covered, &im[best], 1, z_lo, z_hi, glide, &newly, 1);
        done_voxels += (size_t)newly;
        if ((double)done_voxels >= (1 - FURTHER_SHARE) * (double)section_voxels)
            break;
    }
done:
    free(covered);
    free(cover);
    free(mismatch);
    return chosen;
}

/* A boolean where either operand may cross itself near the other (a noisy scan and its
 * images fold over at a fracture's sharp edges): refused, the crossing operand is
 * mended near the other's box and the boolean tried again. */
static void grown_box(const sr_mesh *m, double grow, double box[6])
{
    double lo[3], hi[3];
    sr_mesh_bbox(m, lo, hi);
    for (int k = 0; k < 3; k++) {
        box[k] = lo[k] - grow;
        box[3 + k] = hi[k] + grow;
    }
}

static sr_status boolean_mending(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                                 const sr_mesh *b, const char *b_what, sr_mesh *out,
                                 size_t *mended, sr_err *err)
{
    sr_err e1 = {{0}}, local = {{0}};
    if (!err)
        err = &local;
    sr_status st = sr_boolean_compute(op, a, a_what, b, b_what, out, &e1);
    if (st != SR_E_INVALID) {
        if (st != SR_OK)
            *err = e1;
        return st;
    }
    sr_mesh ma = {0}, mb = {0};
    double box_a[6], box_b[6];
    grown_box(a, 1.0, box_a);
    grown_box(b, 1.0, box_b);
    sr_mend_report ra = {0}, rb = {0};
    st = sr_mesh_copy(&ma, a);
    if (st == SR_OK)
        st = sr_mesh_copy(&mb, b);
    if (st == SR_OK) {
        if (sr_mesh_mend_crossings(&ma, box_b, &ra, NULL) != SR_OK)
            ra.removed_tris = 0;
        if (sr_mesh_mend_crossings(&mb, box_a, &rb, NULL) != SR_OK)
            rb.removed_tris = 0;
        if (ra.removed_tris + rb.removed_tris == 0) {
            *err = e1;
            st = SR_E_INVALID;
        } else {
            st = sr_boolean_compute(op, &ma, a_what, &mb, b_what, out, err);
            if (st == SR_OK)
                *mended += ra.removed_tris + rb.removed_tris;
        }
    }
    sr_mesh_release(&ma);
    sr_mesh_release(&mb);
    return st;
}

/* True when the scan's surface around section s (its triangles whose outside, a voxel
 * along the normal, lies in the section) is a recess of the design rather than a
 * fracture: nearly all of its area (DESIGN_SHARE) faces along the frame of the axis,
 * within DESIGN_DEG (walls parallel to the axis, floors across it: an axial hole, a
 * keyway; walls round a radial direction: a radial hole), and faces more than one way
 * (a single plane facing so is a chip that happens to lie so). Of the walls along the
 * axis, only those facing the recess's own frame (radial or tangential at its centre,
 * within DESIGN_WALL_DEG) are design, unless they face every way round (a hole). A
 * cutter's bite out of the part has fracture faces at its own angles. */
#define DESIGN_DEG 3.0
#define DESIGN_SHARE 0.85
#define DESIGN_WALL_DEG 12.0    /* a wall along the axis facing farther than this off the
                                 * recess's frame is fracture (a noisy scan's facets of a
                                 * keyway's walls scatter by several degrees) */
#define DESIGN_BINS 12          /* a hole's walls face (nearly) every 30 degrees round */
#define DESIGN_BIN_SHARE 0.01
static int design_recess(const sr_mesh *m, const sr_voxels *g, const int *label, int s)
{
    /* the radial direction at the section's centre (a radial hole's axis) */
    double cen[2] = {0, 0};
    size_t total_v = g->nx * g->ny * g->nz;
    for (size_t v = 0; v < total_v; v++)
        if (label[v] == s) {
            double c[3];
            voxel_centre(g, v, c);
            cen[0] += c[0];
            cen[1] += c[1];
        }
    double rc = hypot(cen[0], cen[1]);
    double rdir[2] = {rc > 0 ? cen[0] / rc : 1, rc > 0 ? cen[1] / rc : 0};
    double sn = sin(DESIGN_DEG * M_PI / 180), cs = cos(DESIGN_DEG * M_PI / 180);
    double total = 0, design = 0, mean[3] = {0, 0, 0};
    /* the walls along the axis: their area, the share facing the section's own frame
     * (radial or tangential at its centre), and the bins of azimuth they face */
    double walls = 0, walls_framed = 0, wall_bin[DESIGN_BINS] = {0};
    double wall_cs = cos(DESIGN_WALL_DEG * M_PI / 180);
    for (size_t t = 0; t < m->tri_count; t++) {
        const double *a = m->xyz + 3 * m->tri[3 * t], *b = m->xyz + 3 * m->tri[3 * t + 1],
                     *c = m->xyz + 3 * m->tri[3 * t + 2];
        double n[3];
        sr_mesh_tri_normal(m, t, n);
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0))
            continue;
        double area = 0.5 * len;
        for (int k = 0; k < 3; k++)
            n[k] /= len;
        double p[3];
        for (int k = 0; k < 3; k++)
            p[k] = (a[k] + b[k] + c[k]) / 3 + n[k] * g->h;
        long vi = sr_voxels_locate(g, p);
        if (vi < 0 || label[vi] != s)
            continue;
        total += area;
        double rad = fabs(n[0] * rdir[0] + n[1] * rdir[1]);
        if (fabs(n[2]) < sn || fabs(n[2]) > cs || rad < sn) {
            design += area;
            for (int k = 0; k < 3; k++)
                mean[k] += area * n[k];
        }
        if (fabs(n[2]) < sn) {
            double tan_ = fabs(-n[0] * rdir[1] + n[1] * rdir[0]), h = hypot(n[0], n[1]);
            walls += area;
            if (rad >= wall_cs * h || tan_ >= wall_cs * h)
                walls_framed += area;
            double az = atan2(n[1], n[0]) + M_PI;
            int bin = (int)(az / (2 * M_PI) * DESIGN_BINS);
            wall_bin[bin < 0 ? 0 : bin >= DESIGN_BINS ? DESIGN_BINS - 1 : bin] += area;
        }
    }
    /* walls along the axis are a keyway's or a slot's (facing the frame at the recess:
     * its sides tangential, its floor radial), or a hole's (facing every way round);
     * a box's faces cut to a wedge of the part face neither, and count as fracture (a
     * chip inside a sleeve's bore, a pulley's rim broken off: both kept as a design
     * pocket, -26 % and -100 %) */
    int bins = 0;
    for (int k = 0; k < DESIGN_BINS; k++)
        bins += wall_bin[k] > DESIGN_BIN_SHARE * walls;
    double spread = design > 0
                        ? sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]) / design
                        : 1.0;
    if (bins < DESIGN_BINS - 2)
        design -= walls - walls_framed;
    return total > 0 && design >= DESIGN_SHARE * total && spread < 0.8;
}

/* Glide, a section of weak evidence alone (image_vote.h): an end of the pattern where
 * the other side's pattern runs on (a phantom tooth: not to be built), or a feature of
 * the ends broken off (a first tooth). The scan's surface facing the section (its
 * triangles whose outside, a voxel along the normal, lies in it) tells them apart: the
 * design's faces there either lie along the frame (the plain core's face: within
 * FRAME_DEG of x, y or z) or have an image on the scan's surface (the next tooth's
 * flank); a fracture's do neither. True when FRACTURE_SHARE of that area is fracture.
 * (Tried first on voxels alone: the core's face at a sawtooth rack's end has no image
 * on the surface, so phantoms were built at both ends.) */
#define FRAME_DEG 3.0
#define FRACTURE_SHARE 0.5
static int surface_at(const sr_voxels *g, const double p[3], const double n[3])
{
    double in[3], out[3];
    for (int k = 0; k < 3; k++) {
        in[k] = p[k] - 0.75 * g->h * n[k];
        out[k] = p[k] + 1.25 * g->h * n[k];
    }
    long vi = sr_voxels_locate(g, in), vo = sr_voxels_locate(g, out);
    return vi >= 0 && vo >= 0 && (g->v[vi] & 1) && !(g->v[vo] & 1);
}

static int fracture_bounded(const sr_mesh *m, const sr_voxels *g, const int *label, int s,
                            const sr_symmetry *sym)
{
    sr_image *im = NULL;
    size_t n_im = 0;
    if (sr_images_of(sym, &im, &n_im, NULL) != SR_OK)
        return 1;
    double cs = cos(FRAME_DEG * M_PI / 180);
    double total = 0, fracture = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const double *a = m->xyz + 3 * m->tri[3 * t], *b = m->xyz + 3 * m->tri[3 * t + 1],
                     *c = m->xyz + 3 * m->tri[3 * t + 2];
        double nv[3];
        sr_mesh_tri_normal(m, t, nv);
        double len = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
        if (!(len > 0))
            continue;
        double p[3];
        for (int k = 0; k < 3; k++) {
            nv[k] /= len;
            p[k] = (a[k] + b[k] + c[k]) / 3;
        }
        double q[3] = {p[0] + nv[0] * g->h, p[1] + nv[1] * g->h, p[2] + nv[2] * g->h};
        long vi = sr_voxels_locate(g, q);
        if (vi < 0 || label[vi] != s)
            continue;
        double area = 0.5 * len;
        total += area;
        if (fabs(nv[0]) > cs || fabs(nv[1]) > cs || fabs(nv[2]) > cs)
            continue; /* along the frame: the design's */
        int twin = 0;
        for (size_t k = 0; k < n_im && !twin; k++) {
            const double *x = im[k].xf;
            double pp[3], nn[3];
            for (int r = 0; r < 3; r++) {
                pp[r] = x[4 * r] * p[0] + x[4 * r + 1] * p[1] + x[4 * r + 2] * p[2] + x[4 * r + 3];
                nn[r] = x[4 * r] * nv[0] + x[4 * r + 1] * nv[1] + x[4 * r + 2] * nv[2];
            }
            twin = surface_at(g, pp, nn);
        }
        if (!twin)
            fracture += area;
    }
    free(im);
    return total > 0 && fracture >= FRACTURE_SHARE * total;
}

sr_status sr_image_patch_alone(const sr_mesh *q, const sr_mesh *aligned, sr_mesh *out,
                               size_t *mended, sr_err *err)
{
    size_t m = 0;
    sr_status st = boolean_mending(SR_BOOLEAN_DIFFERENCE, q, "section's image", aligned,
                                   "scan", out, mended ? mended : &m, err);
    if (st == SR_OK)
        sr_mesh_drop_small_shells(out, 0, NULL, NULL);
    return st;
}

/* Depth of build-up and lost surface area from the section's voxels: the chamfer
 * distance from the fracture (section voxels next to the scan), its largest value and
 * its mean over the restored surface (section voxels next to air). */
static void voxel_figures(const sr_voxels *g, const local_box *b, sr_section *s)
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
                size_t q = lidx(b, i, j, k);
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
                                b->sec[lidx(b, (size_t)li, (size_t)lj, (size_t)lk)] == 1;
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
                        size_t w = lidx(b, (size_t)ii, (size_t)jj, (size_t)kk);
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
                size_t q = lidx(b, i, j, k);
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
                                b->sec[lidx(b, (size_t)li, (size_t)lj, (size_t)lk)] == 1;
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

static double det3(const double m[12])
{
    return m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
           m[2] * (m[4] * m[9] - m[5] * m[8]);
}

static int cmp_section(const void *pa, const void *pb)
{
    const sr_section *a = pa, *b = pb;
    return a->volume_mm3 < b->volume_mm3 ? 1 : a->volume_mm3 > b->volume_mm3 ? -1 : 0;
}

/* The crossings of united image pieces are intersection points of near-coincident
 * faces rounded across each other, a micrometre deep (measured: the fill of a hole 60
 * triangles wide on a generated gear's root chorded a flank and filled 3 % of a broken
 * tooth outside the part; the unfold alone uncrosses it). */
#define UNCROSS_MOVE_MM 0.002
#define UNCROSS_VOLUME 0.002
int sr_image_uncross(sr_mesh *q, double max_volume_share)
{
    double before = sr_mesh_volume(q);
    int crosses = 0;
    sr_mesh u = {0};
    if (sr_mesh_copy(&u, q) != SR_OK)
        return 0;
    sr_unfold_report ur = {0};
    if (sr_mesh_unfold(&u, UNCROSS_MOVE_MM, &ur, NULL) == SR_OK &&
        sr_mesh_self_intersects(&u, &crosses, NULL) == SR_OK && !crosses) {
        sr_mesh_release(q);
        *q = u;
        return 1;
    }
    sr_mesh_release(&u);
    sr_mend_report mr = {0};
    return sr_mesh_mend_crossings(q, NULL, &mr, NULL) == SR_OK && sr_mesh_is_closed(q) &&
           sr_mesh_self_intersects(q, &crosses, NULL) == SR_OK && !crosses &&
           fabs(sr_mesh_volume(q) - before) <= max_volume_share * fabs(before);
}

/* Q of a section: the chosen images of the scan (the first np of pick) clipped to the
 * section's hull and united, checked closed and free of crossings; empty when that
 * cannot be had. */
static sr_status clip_images(const sr_mesh *aligned, const sr_image *im, const size_t *pick,
                             size_t np, const sr_mesh *hull, sr_mesh *out, sr_image_info *info,
                             sr_err *err)
{
    sr_mesh q = {0};
    for (size_t u = 0; u < np; u++) {
        sr_mesh img = {0}, piece = {0};
        sr_status st = sr_mesh_copy(&img, aligned);
        if (st != SR_OK) {
            sr_mesh_release(&q);
            return sr_err_set(err, st, "out of memory copying the scan");
        }
        sr_mesh_transform(&img, im[pick[u]].xf);
        if (det3(im[pick[u]].xf) < 0)
            sr_mesh_flip(&img); /* a reflection turns the faces inside out */
        sr_err berr = {{0}};
        sr_status bs = boolean_mending(SR_BOOLEAN_INTERSECTION, &img, "scan image", hull,
                                       "section hull", &piece, &info->mended_tris, &berr);
        sr_mesh_release(&img);
        if (bs != SR_OK || piece.tri_count == 0) {
            sr_mesh_release(&piece);
            continue;
        }
        if (q.tri_count == 0) {
            q = piece;
        } else {
            sr_mesh both = {0};
            if (sr_boolean_compute(SR_BOOLEAN_UNION, &q, "image piece", &piece, "image piece",
                                   &both, &berr) == SR_OK) {
                sr_mesh_release(&q);
                q = both;
            }
            sr_mesh_release(&piece);
        }
    }
    if (q.tri_count > 0) {
        /* the booleans' slivers rounded to zero area: no later boolean takes them */
        sr_repair_report rep = {0};
        int crosses = 0;
        int ok = sr_mesh_repair(&q, &rep, NULL) == SR_OK && sr_mesh_is_closed(&q) &&
                 sr_mesh_self_intersects(&q, &crosses, NULL) == SR_OK;
        if (ok && crosses) /* near-coincident intersection points rounded across */
            ok = sr_image_uncross(&q, UNCROSS_VOLUME);
        if (!ok)
            sr_mesh_release(&q);
    }
    *out = q;
    return SR_OK;
}

sr_status sr_image_reconstruct(const sr_mesh *aligned, const sr_layer_grid *grid,
                               const sr_image_opts *opts, sr_section **sections,
                               size_t *count, sr_image_info *info, sr_err *err)
{
    sr_image_info local = {0};
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    double t0 = now_s();
    double min_vol = opts->min_volume_mm3 > 0 ? opts->min_volume_mm3 : 1.0;
    sr_voxels g = {0};
    sr_status st = grid_make(aligned, opts, &g, err);
    if (st != SR_OK)
        return st;
    st = sr_voxels_fill(&g, aligned, err);
    if (st != SR_OK) {
        sr_voxels_release(&g);
        return st;
    }
    info->pitch_mm = g.h;
    info->voxels = g.nx * g.ny * g.nz;
    double lo[3], hi[3];
    sr_mesh_bbox(aligned, lo, hi);
    double z_lo = lo[2] + 0.5 * g.h, z_hi = hi[2] - 0.5 * g.h;
    size_t min_voxels = (size_t)ceil(0.5 * min_vol / (g.h * g.h * g.h));
    sr_vote_result vr = {0};
    st = sr_vote_missing(&g, &opts->symmetry, z_lo, z_hi, min_voxels, opts->threads, &vr,
                         err);
    if (st != SR_OK) {
        sr_voxels_release(&g);
        return st;
    }
    /* holes, slots and keyways of the design out first (merged with a chip beside
     * them they would no longer read as such) */
    if (opts->symmetry.kind == SR_SYM_AXIAL && opts->symmetry.order < 2)
        for (size_t s = 1; s <= vr.sections; s++)
            if (design_recess(aligned, &g, vr.label, (int)s)) {
                info->features_kept++;
                size_t total = g.nx * g.ny * g.nz;
                for (size_t v = 0; v < total; v++)
                    if (vr.label[v] == (int)s)
                        vr.label[v] = -1; /* not missing; -1 so no label reuses it */
            }
    /* glide: a core of weak evidence alone is built only where a fracture bounds it */
    for (size_t s = 1; vr.weak_only && s <= vr.sections; s++)
        if (vr.weak_only[s - 1] && !fracture_bounded(aligned, &g, vr.label, (int)s,
                                                     &opts->symmetry)) {
            size_t total = g.nx * g.ny * g.nz;
            for (size_t v = 0; v < total; v++)
                if (vr.label[v] == (int)s)
                    vr.label[v] = -1;
        }
    info->misfit = vr.misfit;
    info->misfit_located = vr.misfit_located;
    memcpy(info->misfit_where, vr.misfit_where, sizeof info->misfit_where);
    merge_near_sections(&g, &vr);
    info->vote_s = now_s() - t0;
    double t1 = now_s();
    sr_image *im = NULL;
    size_t n_im = 0;
    size_t ns = 0;
    sr_section *sec = calloc(vr.sections ? vr.sections : 1, sizeof *sec);
    if (!sec) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu sections", vr.sections);
        goto done;
    }
    st = sr_images_of(&opts->symmetry, &im, &n_im, err);
    for (size_t s = 1; st == SR_OK && s <= vr.sections; s++) {
        local_box b = {0};
        sr_mesh hull = {0}, q = {0};
        sr_status box_st = box_make(&g, vr.label, (int)s, &b);
        if (box_st == SR_E_RANGE)
            continue;
        if (box_st != SR_OK) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory for a section's voxels");
            break;
        }
        size_t pick[MAX_IMAGES];
        size_t np = choose_images(&g, &b, im, n_im, &opts->symmetry, z_lo, z_hi, pick);
        sr_err herr = {{0}};
        int glide = opts->symmetry.kind == SR_SYM_GLIDE; /* its hull ends with the part */
        if (np == 0 || hull_make(&g, &b, glide ? lo[2] : -HUGE_VAL, glide ? hi[2] : HUGE_VAL,
                                 &hull, &herr) != SR_OK) {
            free(b.sec);
            continue; /* no image carries it, or too thin for a hull: not restorable */
        }
        st = clip_images(aligned, im, pick, np, &hull, &q, info, err);
        if (st == SR_OK && q.tri_count == 0 && np > 1) /* two images that do not unite clean */
            st = clip_images(aligned, im, pick, 1, &hull, &q, info, err);
        sr_mesh_release(&hull);
        if (st == SR_OK && q.tri_count > 0 && opts->symmetry.kind == SR_SYM_AXIAL) {
            size_t pins = 0;
            st = sr_axis_seam_close(&q, aligned, AXIS_RING * g.h, &pins, err);
            info->axis_pins += pins;
        }
        if (st != SR_OK || q.tri_count == 0) {
            sr_mesh_release(&q);
            free(b.sec);
            continue;
        }
        double vol = sr_mesh_volume(&q);
        if (vol < min_vol) {
            sr_mesh_release(&q);
            free(b.sec);
            continue;
        }
        sr_section *sc = &sec[ns];
        memset(sc, 0, sizeof *sc);
        sc->patch = q; /* the clipped image: the union makes it the patch */
        sc->volume_mm3 = vol;
        sr_image_section_figures(grid, sc);
        voxel_figures(&g, &b, sc);
        free(b.sec);
        if (sc->depth_max_mm < opts->min_depth_mm) {
            sr_mesh_release(&sc->patch);
            continue;
        }
        ns++;
    }
done:
    free(im);
    sr_vote_result_release(&vr);
    sr_voxels_release(&g);
    if (st != SR_OK) {
        sr_sections_release(sec, ns);
        return st;
    }
    qsort(sec, ns, sizeof *sec, cmp_section);
    info->patch_s = now_s() - t1;
    *sections = sec;
    *count = ns;
    return SR_OK;
}
