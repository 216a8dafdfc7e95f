/*
 * both_sides_lost.c: under a mirror, the loss that took a place and its mirror image
 * both (images_int.h, sr_img_both_sides_lost). No image of the scan carries it: a chip
 * on each side, at mirror places that overlap, leaves the overlap missing from the
 * scan and from its image alike, and the patches built from the image stop short of
 * it, leaving a notch or slab between the two fractures (a generated clamp's two plane
 * chips: a slab across an arm, 2.9 mm from the intact surface).
 *
 * Such a place is found by what stands round it along an axis of the grid: on one
 * side the image's material where the scan lost it (a section's voxel), on the other
 * the scan's material whose own image is a section's voxel (a fracture's other face),
 * both on the same side of the plane, through voxels neither the scan nor its image
 * holds. The line's two ends are then the two chips' fracture faces, one of them
 * carried over by the image. A single loss never has such a line: a hole or a slot
 * lost on one side runs from the image of its wall to the scan's wall on the other
 * side of the plane, or to a wall whose image is intact. Each 26-connected region of
 * such voxels is built when the scan's faces facing it and its mirror are mostly
 * fracture (section_kind.c, faces of the frame that go on away from the losses being
 * the design's): a stack of its voxel layers, grown by two voxels into the material
 * round it so the union with the patch and the scan leaves no seam. (A thin wedge open
 * to a face of the part, whose lines along the axes leave through that face, is not
 * found: a generated bracket's two box chips leave one 1.2 mm deep under its base.)
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "images/images_int.h"

enum { CANDIDATE = 1, SEEN = 2, GROWN = 4, FRESH = 8, NEXT = 16 };

#define GROW_VOXELS 2 /* the region's mesh reaches this deep into the material round it */

#define NEAR_MM 1.0 /* the sections and the mirror images come this near, or none is looked for */

static inline size_t mirror_of(const sr_voxels *g, size_t v)
{
    size_t i = v % g->nx;
    return v - i + (g->nx - 1 - i);
}

static inline bool solid(const sr_voxels *g, size_t v)
{
    return g->v[v] & 1;
}

/* neither the scan nor its image holds v */
static inline bool neither(const sr_voxels *g, size_t v)
{
    return !solid(g, v) && !solid(g, mirror_of(g, v));
}

/* 1: the image's material in a section; 2: the scan's material whose image is in a
 * section; 0 otherwise */
static inline int end_kind(const sr_voxels *g, const int *label, size_t v)
{
    if (!solid(g, v))
        return label[v] > 0 ? 1 : 0;
    return label[mirror_of(g, v)] > 0 ? 2 : 0;
}

/* v's face neighbours inside the grid into out; returns how many */
static size_t neighbours6(const sr_voxels *g, size_t v, size_t out[6])
{
    size_t ijk[3] = {v % g->nx, (v / g->nx) % g->ny, v / (g->nx * g->ny)};
    size_t n3[3] = {g->nx, g->ny, g->nz}, stride[3] = {1, g->nx, g->nx * g->ny}, n = 0;
    for (int a = 0; a < 3; a++) {
        if (ijk[a] > 0)
            out[n++] = v - stride[a];
        if (ijk[a] + 1 < n3[a])
            out[n++] = v + stride[a];
    }
    return n;
}

/* The grid's lines looked along: its axes. (Its diagonals too were tried: a clamp's
 * fractures, concave, let diagonal lines leave the part and come back, and the region
 * took in air beside the arm, 10 mm out.) */
static const int LINE_DIR[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

static inline bool in_box(const long p[3], const size_t box[6])
{
    for (int a = 0; a < 3; a++)
        if (p[a] < (long)box[a] || p[a] > (long)box[3 + a])
            return false;
    return true;
}

/* Marks CANDIDATE the runs of voxels along direction d (the lines through box[]: lo in
 * 0..2, hi in 3..5, inclusive) that neither holds, ended inside the box by one voxel
 * of each end kind, all on one side of the plane. */
static void mark_runs(const sr_voxels *g, const int *label, const int d[3], const size_t box[6],
                      uint8_t *mark)
{
    long centre = (long)(g->nx - 1) / 2;
    long step = d[0] + d[1] * (long)g->nx + d[2] * (long)(g->nx * g->ny);
    for (size_t k = box[2]; k <= box[5]; k++)
        for (size_t j = box[1]; j <= box[4]; j++)
            for (size_t i = box[0]; i <= box[3]; i++) {
                long p[3] = {(long)i - d[0], (long)j - d[1], (long)k - d[2]};
                if (in_box(p, box))
                    continue; /* not the first voxel of its line */
                if (d[0] == 0 && (long)i == centre)
                    continue; /* a line in the plane */
                long q[3] = {(long)i, (long)j, (long)k};
                size_t v = sr_voxel_index(g, i, j, k);
                /* the line's voxels in turn; prev_kind, prev_i: the last voxel held by
                 * either, its end kind and x index; len voxels held by neither since */
                long prev_i = -1;
                size_t first = 0, len = 0;
                int prev_kind = 0;
                while (in_box(q, box)) {
                    if (neither(g, v)) {
                        if (len++ == 0)
                            first = v;
                    } else {
                        int kind = end_kind(g, label, v);
                        if (len > 0 && prev_i >= 0 && prev_kind && kind && prev_kind != kind &&
                            (prev_i - centre) * (q[0] - centre) > 0)
                            for (size_t u = 0, w = first; u < len; u++, w += (size_t)step)
                                mark[w] |= CANDIDATE;
                        prev_kind = kind;
                        prev_i = q[0];
                        len = 0;
                    }
                    for (int a = 0; a < 3; a++)
                        q[a] += d[a];
                    v += (size_t)step;
                }
            }
}

static void box_add(size_t box[6], size_t v, const sr_voxels *g)
{
    size_t ijk[3] = {v % g->nx, (v / g->nx) % g->ny, v / (g->nx * g->ny)};
    for (int a = 0; a < 3; a++) {
        if (ijk[a] < box[a])
            box[a] = ijk[a];
        if (ijk[a] > box[3 + a])
            box[3 + a] = ijk[a];
    }
}

/* The region (region[0..n)): built when its faces are mostly fracture; its section
 * (the label most of its image's ends carry) and mesh into *sec and *out. */
static sr_status build_region(const sr_mesh *m, const sr_voxels *g, sr_vote_result *vr,
                              uint8_t *mark, const size_t *region, size_t n, const sr_symmetry *sym,
                              double noise_mm, int *sec, sr_mesh *out, sr_err *err)
{
    *sec = 0;
    int probe = (int)vr->sections + 1;
    size_t vbox[6] = {SIZE_MAX, SIZE_MAX, SIZE_MAX, 0, 0, 0};
    for (size_t r = 0; r < n; r++) {
        vr->label[region[r]] = probe;
        vr->label[mirror_of(g, region[r])] = probe;
        box_add(vbox, region[r], g);
        box_add(vbox, mirror_of(g, region[r]), g);
    }
    double share =
        sr_img_fracture_share(m, g, vr->label, probe, sym, noise_mm, true, true, n ? vbox : NULL);
    for (size_t r = 0; r < n; r++) {
        vr->label[region[r]] = 0;
        vr->label[mirror_of(g, region[r])] = 0;
    }
    if (!(share >= 0.5))
        return SR_OK;
    /* its section: the most common label among the image's material round it */
    size_t *votes = calloc(vr->sections + 1, sizeof *votes);
    if (!votes)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    size_t box[6] = {SIZE_MAX, SIZE_MAX, SIZE_MAX, 0, 0, 0};
    for (size_t r = 0; r < n; r++) {
        size_t v = region[r];
        mark[v] |= GROWN | FRESH;
        box_add(box, v, g);
        size_t nb[6], nn = neighbours6(g, v, nb);
        for (size_t q = 0; q < nn; q++)
            if (!solid(g, nb[q]) && vr->label[nb[q]] > 0 &&
                (size_t)vr->label[nb[q]] <= vr->sections)
                votes[vr->label[nb[q]]]++;
    }
    /* grown into the material round it (scan or image), GROW_VOXELS deep: its faces
     * then stand clear of the scan's noisy fracture, and the union leaves no seam and
     * traps no voids (grown one voxel deep, a noisy clamp's union trapped 186 voids
     * between the fracture and the steps, and took 10 times as long) */
    for (int pass = 0; pass < GROW_VOXELS; pass++) {
        size_t pbox[6];
        memcpy(pbox, box, sizeof pbox);
        for (size_t k = pbox[2]; k <= pbox[5]; k++)
            for (size_t j = pbox[1]; j <= pbox[4]; j++)
                for (size_t i = pbox[0]; i <= pbox[3]; i++) {
                    size_t v = sr_voxel_index(g, i, j, k);
                    if (!(mark[v] & FRESH))
                        continue;
                    size_t nb[6], nn = neighbours6(g, v, nb);
                    for (size_t q = 0; q < nn; q++)
                        if (!(mark[nb[q]] & GROWN) && !neither(g, nb[q])) {
                            mark[nb[q]] |= GROWN | NEXT;
                            box_add(box, nb[q], g);
                        }
                }
        for (size_t k = box[2]; k <= box[5]; k++)
            for (size_t j = box[1]; j <= box[4]; j++)
                for (size_t i = box[0]; i <= box[3]; i++) {
                    uint8_t *mv = &mark[sr_voxel_index(g, i, j, k)];
                    *mv = (uint8_t)((*mv & ~(FRESH | NEXT)) | (*mv & NEXT ? FRESH : 0));
                }
    }
    for (size_t s = 1; s <= vr->sections; s++)
        if (votes[s] > votes[*sec])
            *sec = (int)s;
    free(votes);
    sr_status st = SR_OK;
    if (*sec > 0)
        st = sr_img_marked_mesh(g, mark, GROWN, box, out, err);
    for (size_t k = box[2]; k <= box[5]; k++)
        for (size_t j = box[1]; j <= box[4]; j++)
            for (size_t i = box[0]; i <= box[3]; i++)
                mark[sr_voxel_index(g, i, j, k)] &= (uint8_t) ~(GROWN | FRESH | NEXT);
    if (st != SR_OK)
        *sec = 0;
    return st;
}

sr_status sr_img_both_sides_lost(const sr_mesh *m, const sr_voxels *g, sr_vote_result *vr,
                                 size_t min_voxels, const sr_symmetry *sym, double noise_mm,
                                 sr_mesh *fill, size_t *regions, sr_err *err)
{
    *regions = 0;
    if (sym->kind != SR_SYM_MIRROR || vr->sections == 0)
        return SR_OK;
    /* the lines through the box of the sections and their mirror images (a run's two
     * ends: a section's voxel, and the scan's voxel at a section's mirror image), only
     * where these come near each other (one side's loss across from the other's) */
    size_t box[6] = {SIZE_MAX, SIZE_MAX, SIZE_MAX, 0, 0, 0};
    for (size_t q = 0; q < vr->at_count; q++)
        if (vr->label[vr->at[q]] > 0)
            box_add(box, vr->at[q], g);
    if (box[0] == SIZE_MAX)
        return SR_OK;
    size_t mlo = g->nx - 1 - box[3], mhi = g->nx - 1 - box[0];
    size_t near = (size_t)ceil(NEAR_MM / g->h);
    if (mlo > box[3] + near || box[0] > mhi + near)
        return SR_OK;
    box[0] = box[0] < mlo ? box[0] : mlo;
    box[3] = box[3] > mhi ? box[3] : mhi;
    size_t total = g->nx * g->ny * g->nz;
    uint8_t *mark = calloc(total, 1);
    if (!mark)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu voxels", total);
    for (int d = 0; d < 3; d++)
        mark_runs(g, vr->label, LINE_DIR[d], box, mark);
    size_t cand = 0;
    for (size_t v = 0; v < total; v++)
        cand += mark[v] & CANDIDATE;
    size_t *region = malloc((cand + 1) * sizeof *region);
    size_t *stack = malloc((cand + 1) * sizeof *stack);
    sr_status st = region && stack ? SR_OK : sr_err_set(err, SR_E_NOMEM, "out of memory");
    for (size_t k = box[2]; st == SR_OK && cand && k <= box[5]; k++)
        for (size_t j = box[1]; st == SR_OK && j <= box[4]; j++)
            for (size_t i = box[0]; st == SR_OK && i <= box[3]; i++) {
                size_t v0 = sr_voxel_index(g, i, j, k);
                if ((mark[v0] & (CANDIDATE | SEEN)) != CANDIDATE)
                    continue;
                /* its 26-connected region (each voxel stacked once: cand is room) */
                size_t n = 0, top = 0;
                mark[v0] |= SEEN;
                stack[top++] = v0;
                while (top) {
                    size_t v = stack[--top];
                    region[n++] = v;
                    size_t nb[26], nn = sr_voxel_neighbours26(g, v, nb);
                    for (size_t q = 0; q < nn; q++)
                        if ((mark[nb[q]] & (CANDIDATE | SEEN)) == CANDIDATE) {
                            mark[nb[q]] |= SEEN;
                            stack[top++] = nb[q];
                        }
                }
                if (n < min_voxels)
                    continue;
                int sec = 0;
                sr_mesh piece = {0};
                st = build_region(m, g, vr, mark, region, n, sym, noise_mm, &sec, &piece, err);
                if (st != SR_OK || sec == 0) {
                    sr_mesh_release(&piece);
                    st = SR_OK; /* a region that does not stack is left as the images
                                 * leave it */
                    continue;
                }
                sr_mesh *f = &fill[sec - 1];
                if (f->tri_count == 0) {
                    sr_mesh_release(f);
                    *f = piece;
                } else {
                    st = sr_mesh_append(f, &piece);
                    sr_mesh_release(&piece);
                    if (st != SR_OK)
                        st = sr_err_set(err, st, "out of memory");
                }
                (*regions)++;
            }
    free(region);
    free(stack);
    free(mark);
    return st;
}
