/*
 * image_restore.c: the image method's driver (see image_restore.h): voxel grid and
 * vote, then per section its box and hull (section_box.c), the choice of image, the
 * exact patch, and its figures (image_figures.c); candidates that are recesses of the
 * design or phantom ends of a glide are taken out first (section_kind.c). The folder's
 * private interface is images_int.h.
 */
#include "images/image_restore.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bridge/boolean.h"
#include "bridge/clip_local.h"
#include "bridge/mend.h"
#include "images/axis_seam.h"
#include "images/image_vote.h"
#include "images/images_int.h"
#include "images/voxels.h"
#include "mesh/mesh_shells.h"

#define GRID_VOXELS 8.0e6       /* the automatic pitch aims at this many voxels */
#define PITCH_MIN 0.15
#define PITCH_MAX 1.5
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
    for (size_t q = 0; q < vr->at_count; q++) {
        size_t v = vr->at[q];
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
            for (size_t q = 0; q < vr->at_count; q++)
                if (vr->label[vr->at[q]] > 0) {
                    size_t v = vr->at[q];
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

/* Over the section's voxels not covered yet: cover[m] += those whose preimage under
 * im[m] (m < n) is material; mark: they are marked covered too (give one image). */
static void cover_pass(const sr_voxels *g, const local_box *b, uint8_t *covered,
                       const sr_image *im, size_t n, double z_lo, double z_hi, int glide,
                       long *cover, int mark)
{
    for (size_t k = 0; k < b->nz; k++)
        for (size_t j = 0; j < b->ny; j++)
            for (size_t i = 0; i < b->nx; i++) {
                size_t q = sr_img_lidx(b, i, j, k);
                if (b->sec[q] != 1 || covered[q])
                    continue;
                double c[3];
                sr_img_voxel_centre(g, sr_voxel_index(g, b->i0 + i, b->j0 + j, b->k0 + k), c);
                for (size_t m = 0; m < n; m++)
                    if (sr_image_material(g, &im[m], c, z_lo, z_hi, glide) == 1) {
                        cover[m]++;
                        if (mark)
                            covered[q] = 1;
                    }
            }
}

/* Marks in `covered` (as 2) the section voxels still uncovered that the air reaches
 * through uncovered section voxels (air: neither the scan's material nor the section,
 * or beyond the box); the others stay 0. Returns 1 when some uncovered voxel is sealed
 * (not reached); clears the marks before returning. */
static int sealed_pocket(const sr_voxels *g, const local_box *b, uint8_t *covered)
{
    size_t nx = b->nx, ny = b->ny, nz = b->nz, cells = nx * ny * nz;
    size_t *queue = malloc(cells * sizeof *queue);
    if (!queue)
        return 0;
    size_t head = 0, tail = 0, open = 0;
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                size_t q = sr_img_lidx(b, i, j, k);
                if (b->sec[q] != 1 || covered[q])
                    continue;
                open++;
                int air = i == 0 || j == 0 || k == 0 || i + 1 == nx || j + 1 == ny || k + 1 == nz;
                const long d[6][3] = {{-1, 0, 0}, {1, 0, 0},  {0, -1, 0},
                                      {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};
                for (int e = 0; !air && e < 6; e++) {
                    size_t ii = (size_t)((long)i + d[e][0]), jj = (size_t)((long)j + d[e][1]),
                           kk = (size_t)((long)k + d[e][2]);
                    size_t w = sr_voxel_index(g, b->i0 + ii, b->j0 + jj, b->k0 + kk);
                    air = b->sec[sr_img_lidx(b, ii, jj, kk)] != 1 && !(g->v[w] & 1);
                }
                if (air) {
                    covered[q] = 2;
                    queue[tail++] = q;
                }
            }
    while (head < tail) {
        size_t q = queue[head++];
        size_t i = q % nx, j = (q / nx) % ny, k = q / (nx * ny);
        size_t nb[6];
        int m = 0;
        if (i > 0)
            nb[m++] = q - 1;
        if (i + 1 < nx)
            nb[m++] = q + 1;
        if (j > 0)
            nb[m++] = q - nx;
        if (j + 1 < ny)
            nb[m++] = q + nx;
        if (k > 0)
            nb[m++] = q - nx * ny;
        if (k + 1 < nz)
            nb[m++] = q + nx * ny;
        for (int e = 0; e < m; e++)
            if (b->sec[nb[e]] == 1 && !covered[nb[e]]) {
                covered[nb[e]] = 2;
                queue[tail++] = nb[e];
            }
    }
    for (size_t q = 0; q < tail; q++)
        covered[queue[q]] = 0;
    free(queue);
    return tail < open;
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
                uint8_t s = b->sec[sr_img_lidx(b, i, j, k)];
                if (s != 2)
                    continue;
                size_t v = sr_voxel_index(g, b->i0 + i, b->j0 + j, b->k0 + k);
                double c[3];
                sr_img_voxel_centre(g, v, c);
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
    /* a pocket the chosen images leave empty inside the section, away from the air (an
     * image carried a hole of the design into it): it would be a void inside the
     * restored part, whatever its share; the image that fills most of it is added */
    while (chosen < MAX_IMAGES && sealed_pocket(g, b, covered)) {
        memset(cover, 0, n_im * sizeof *cover);
        cover_pass(g, b, covered, im, n_im, z_lo, z_hi, glide, cover, 0);
        size_t best = n_im;
        for (size_t m = 0; m < n_im; m++) {
            int used = 0;
            for (size_t u = 0; u < chosen; u++)
                used |= pick[u] == m;
            if (!used && cover[m] > 0 && (best == n_im || cover[m] > cover[best]))
                best = m;
        }
        if (best == n_im)
            break;
        pick[chosen++] = best;
        long newly = 0;
        cover_pass(g, b, covered, &im[best], 1, z_lo, z_hi, glide, &newly, 1);
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

/* The boolean again with either operand mended near the other, after it was refused
 * (e1: the refusal, which stays the answer when nothing is mended). */
static sr_status mend_and_retry(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                                const sr_mesh *b, const char *b_what, sr_mesh *out, size_t *mended,
                                const sr_err *e1, sr_err *err)
{
    sr_mesh ma = {0}, mb = {0};
    double box_a[6], box_b[6];
    grown_box(a, 1.0, box_a);
    grown_box(b, 1.0, box_b);
    sr_mend_report ra = {0}, rb = {0};
    sr_status st = sr_mesh_copy(&ma, a);
    if (st == SR_OK)
        st = sr_mesh_copy(&mb, b);
    if (st == SR_OK) {
        if (sr_mesh_mend_crossings(&ma, box_b, &ra, NULL) != SR_OK)
            ra.removed_tris = 0;
        if (sr_mesh_mend_crossings(&mb, box_a, &rb, NULL) != SR_OK)
            rb.removed_tris = 0;
        if (ra.removed_tris + rb.removed_tris == 0) {
            *err = *e1;
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

static sr_status boolean_mending(sr_boolean_op op, const sr_mesh *a, const char *a_what,
                                 const sr_mesh *b, const char *b_what, sr_mesh *out, size_t *mended,
                                 sr_err *err)
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
    return mend_and_retry(op, a, a_what, b, b_what, out, mended, &e1, err);
}

/* The image of the scan under xf clipped to a section's hull: near the hull only
 * (clip_local.h: the same surface as the whole-mesh intersection, without a
 * million-triangle scan going through CGAL for each image, nor copied and mapped for
 * it), mended and tried again as boolean_mending does when refused. */
static sr_status clip_mending(const sr_mesh *aligned, const double xf[12], const sr_mesh *hull,
                              sr_mesh *out, size_t *mended, sr_err *err)
{
    sr_err e1 = {{0}};
    sr_status st = sr_boolean_intersection_local_mapped(aligned, "scan image", xf, hull,
                                                        "section hull", 0, out, NULL, &e1);
    if (st != SR_E_INVALID) {
        if (st != SR_OK)
            *err = e1;
        return st;
    }
    sr_mesh img = {0};
    st = sr_mesh_copy(&img, aligned);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory copying the scan");
    sr_mesh_map(&img, xf); /* a reflection's faces turned back out */
    st = mend_and_retry(SR_BOOLEAN_INTERSECTION, &img, "scan image", hull, "section hull", out,
                        mended, &e1, err);
    sr_mesh_release(&img);
    return st;
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
        sr_mesh piece = {0};
        sr_err berr = {{0}};
        sr_status bs =
            clip_mending(aligned, im[pick[u]].xf, hull, &piece, &info->mended_tris, &berr);
        if (bs == SR_E_NOMEM) {
            sr_mesh_release(&q);
            *err = berr;
            return bs;
        }
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

/* The places the vote judged the design's round a section (box b: label -1, a recess
 * of the design, a phantom end of a glide's pattern in front of a face of the design),
 * cut out of the section's clipped images q. The section's hull is convex and reaches
 * HULL_GROW pitches past its voxels, and there an image carries the feature the vote
 * left out: a rack's phantom tooth beside a chip at its end stood 1 mm high on a noisy
 * scan (+6 % of the loss), a ratchet's 2.6 mm. Marked in mark (the grid's size, zero
 * on entry and on return); q is left as it is when the cut fails. */
static sr_status cut_design_out(const sr_voxels *g, const sr_vote_result *vr, const local_box *b,
                                uint8_t *mark, sr_mesh *q, sr_image_info *info, sr_err *err)
{
    size_t reach = (size_t)ceil(HULL_GROW) + 1, n[3] = {g->nx, g->ny, g->nz};
    size_t lo[3] = {b->i0, b->j0, b->k0}, len[3] = {b->nx, b->ny, b->nz}, box[6];
    for (int a = 0; a < 3; a++) {
        box[a] = lo[a] >= reach ? lo[a] - reach : 0;
        box[3 + a] = lo[a] + len[a] - 1 + reach < n[a] ? lo[a] + len[a] - 1 + reach : n[a] - 1;
    }
    size_t count = 0;
    for (size_t k = box[2]; k <= box[5]; k++)
        for (size_t j = box[1]; j <= box[4]; j++)
            for (size_t i = box[0]; i <= box[3]; i++) {
                size_t v = sr_voxel_index(g, i, j, k);
                if (vr->label[v] == -1) {
                    mark[v] = 1;
                    count++;
                }
            }
    if (count == 0)
        return SR_OK;
    /* and one voxel round them where the scan and the sections are not: a sloping face
     * of the image leaves a sliver in the cubes beyond the marked voxels' whose centres
     * lie outside it (a ratchet's phantom tooth, cut at the voxels, kept a wedge of its
     * ramp 2.6 mm high and a tenth thick) */
    for (size_t k = box[2]; k <= box[5]; k++)
        for (size_t j = box[1]; j <= box[4]; j++)
            for (size_t i = box[0]; i <= box[3]; i++) {
                size_t v = sr_voxel_index(g, i, j, k);
                if (mark[v] || (g->v[v] & 1) || vr->label[v] > 0)
                    continue;
                size_t nb[26], nn = sr_voxel_neighbours26(g, v, nb);
                for (size_t e = 0; e < nn; e++)
                    if (mark[nb[e]] == 1) {
                        mark[v] = 2;
                        break;
                    }
            }
    sr_mesh design = {0}, cut = {0};
    sr_err e = {{0}};
    sr_status st = sr_img_marked_mesh(g, mark, 3, box, &design, &e);
    if (st == SR_OK && design.tri_count > 0 &&
        boolean_mending(SR_BOOLEAN_DIFFERENCE, q, "section's image", &design, "design's voxels",
                        &cut, &info->mended_tris, &e) == SR_OK &&
        cut.tri_count > 0) {
        sr_mesh_release(q);
        *q = cut;
    } else {
        sr_mesh_release(&cut);
    }
    sr_mesh_release(&design);
    for (size_t k = box[2]; k <= box[5]; k++)
        for (size_t j = box[1]; j <= box[4]; j++)
            memset(mark + sr_voxel_index(g, box[0], j, k), 0, box[3] - box[0] + 1);
    return st == SR_E_NOMEM ? sr_err_set(err, st, "out of memory for the design's voxels") : SR_OK;
}

/* A section of the vote (box b, voxels of side h) that gave no patch counted in info,
 * when by its voxels it is at least min_vol: the user is told that damage was found
 * there and not restored, not shown a part with nothing to repair. */
static void unbuilt(const local_box *b, double h, double min_vol, sr_image_info *info)
{
    size_t n = 0, cells = b->nx * b->ny * b->nz;
    for (size_t i = 0; i < cells; i++)
        n += b->sec[i] == 1;
    double vol = (double)n * h * h * h;
    if (vol < min_vol)
        return;
    info->unbuilt++;
    info->unbuilt_mm3 += vol;
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
            if (sr_img_design_recess(aligned, &g, &vr, (int)s)) {
                info->features_kept++;
                for (size_t q = 0; q < vr.at_count; q++)
                    if (vr.label[vr.at[q]] == (int)s)
                        vr.label[vr.at[q]] = -1; /* not missing; -1 so no label reuses it */
            }
    /* glide: a core of weak evidence alone is built only where a fracture bounds it */
    size_t phantoms = 0;
    for (size_t s = 1; vr.weak_only && s <= vr.sections; s++)
        if (vr.weak_only[s - 1] && !sr_img_fracture_bounded(aligned, &g, vr.label, (int)s,
                                                            &opts->symmetry, opts->noise_mm)) {
            phantoms++;
            for (size_t q = 0; q < vr.at_count; q++)
                if (vr.label[vr.at[q]] == (int)s)
                    vr.label[vr.at[q]] = -1;
        }
    /* and where such a phantom end showed the pattern stops short of an end (on an
     * intact end, the image from the middle's side carried a feature past it), the
     * weak evidence inside sections with strong evidence is judged too: without that
     * sign a break flush with a face of the frame reads as the design (a rail's end
     * chip: -3.9 %, 4.4 mm) */
    if (phantoms > 0)
        sr_img_drop_phantom_ends(aligned, &g, &vr, min_voxels, &opts->symmetry, opts->noise_mm);
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
    sr_mesh *fill = calloc(vr.sections ? vr.sections : 1, sizeof *fill);
    if (!sec || !fill) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu sections", vr.sections);
        goto done;
    }
    /* a mirror's loss that took both sides: no image carries it */
    st = sr_img_both_sides_lost(aligned, &g, &vr, min_voxels, &opts->symmetry, opts->noise_mm, fill,
                                &info->both_sides, err);
    if (st == SR_OK)
        st = sr_images_of(&opts->symmetry, &im, &n_im, err);
    /* scratch for the design's voxels round each section (cut_design_out) */
    uint8_t *mark = st == SR_OK ? calloc(g.nx * g.ny * g.nz, 1) : NULL;
    if (st == SR_OK && !mark)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu voxels", g.nx * g.ny * g.nz);
    for (size_t s = 1; st == SR_OK && s <= vr.sections; s++) {
        local_box b = {0};
        sr_mesh hull = {0}, q = {0};
        sr_status box_st = sr_img_box_make(&g, &vr, (int)s, &b);
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
        if (np == 0 || sr_img_hull_make(&g, &b, glide ? lo[2] : -HUGE_VAL,
                                        glide ? hi[2] : HUGE_VAL, &hull, &herr) != SR_OK) {
            unbuilt(&b, g.h, min_vol, info);
            free(b.sec);
            continue; /* no image carries it, or too thin for a hull: not restorable */
        }
        st = clip_images(aligned, im, pick, np, &hull, &q, info, err);
        if (st == SR_OK && q.tri_count == 0 && np > 1) /* two images that do not unite clean */
            st = clip_images(aligned, im, pick, 1, &hull, &q, info, err);
        sr_mesh_release(&hull);
        if (st == SR_OK && q.tri_count > 0)
            st = cut_design_out(&g, &vr, &b, mark, &q, info, err);
        if (st == SR_OK && q.tri_count > 0 && opts->symmetry.kind == SR_SYM_AXIAL) {
            size_t pins = 0;
            st = sr_axis_seam_close(&q, aligned, AXIS_RING * g.h, &pins, err);
            info->axis_pins += pins;
        }
        if (st == SR_OK && q.tri_count > 0 && fill[s - 1].tri_count > 0) {
            sr_mesh u = {0};
            sr_err ferr = {{0}};
            if (boolean_mending(SR_BOOLEAN_UNION, &q, "section's image", &fill[s - 1],
                                "loss on both sides", &u, &info->mended_tris, &ferr) == SR_OK &&
                u.tri_count > 0) {
                sr_mesh_release(&q);
                q = u;
            } else {
                sr_mesh_release(&u);
            }
        }
        if (st != SR_OK || q.tri_count == 0) {
            if (st == SR_OK)
                unbuilt(&b, g.h, min_vol, info);
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
        sr_img_voxel_figures(&g, &b, sc);
        free(b.sec);
        if (sc->depth_max_mm < opts->min_depth_mm) {
            sr_mesh_release(&sc->patch);
            continue;
        }
        ns++;
    }
    free(mark);
done:
    for (size_t s = 0; fill && s < vr.sections; s++)
        sr_mesh_release(&fill[s]);
    free(fill);
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
