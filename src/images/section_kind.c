/*
 * section_kind.c: what a candidate section of the image method is, from the scan's
 * surface facing it (images_int.h): a recess of the design on an axis (a hole, a slot,
 * a keyway: kept, not filled; sr_img_design_recess), and, under a glide, whether a
 * core of weak evidence is bounded by a fracture (a feature broken off: built) or by
 * the design (a phantom end of the pattern: not built; sr_img_fracture_bounded), also
 * for such a region inside a section with strong evidence (sr_img_drop_phantom_ends).
 */
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "images/image_vote.h"
#include "images/images_int.h"

/* True when the scan's surface around section s (its triangles whose outside, a voxel
 * along the normal, lies in the section) is a recess of the design rather than a
 * fracture: nearly all of its area (DESIGN_SHARE) faces along the frame of the axis,
 * within DESIGN_DEG (walls parallel to the axis, floors across it: an axial hole, a
 * keyway; walls round a radial direction: a radial hole), and faces more than one way
 * (a single plane facing so is a chip that happens to lie so). Of the walls along the
 * axis, only those facing the recess's own frame (radial or tangential at its centre,
 * within DESIGN_WALL_DEG) are design, unless they face every way round (a hole), and
 * such a recess must run along the axis as keyways and slots do (DESIGN_MIN_LENGTH). A
 * cutter's bite out of the part has fracture faces at its own angles. */
#define DESIGN_DEG 3.0
#define DESIGN_SHARE 0.85
#define DESIGN_WALL_DEG 12.0    /* a wall along the axis facing farther than this off the
                                 * recess's frame is fracture (a noisy scan's facets of a
                                 * keyway's walls scatter by several degrees) */
#define DESIGN_BINS 12          /* a hole's walls face (nearly) every 30 degrees round */
#define DESIGN_MIN_LENGTH                                                                          \
    0.8 /* a keyway or slot runs along the axis: at least this
                                 * long along it for its width across (a radial hole's
                                 * are equal); a box chip clipped to a wedge of a pulley's
                                 * rim faced the frame as a keyway's walls do, 5.7 mm long
                                 * for 11 wide, and was kept (s2207p00: -35 %) */
#define DESIGN_BIN_SHARE 0.01
int sr_img_design_recess(const sr_mesh *m, const sr_voxels *g, const sr_vote_result *vr, int s)
{
    const int *label = vr->label;
    /* the radial direction at the section's centre (a radial hole's axis) */
    double cen[2] = {0, 0};
    for (size_t q = 0; q < vr->at_count; q++)
        if (label[vr->at[q]] == s) {
            size_t v = vr->at[q];
            double c[3];
            sr_img_voxel_centre(g, v, c);
            cen[0] += c[0];
            cen[1] += c[1];
        }
    double rc = hypot(cen[0], cen[1]);
    double rdir[2] = {rc > 0 ? cen[0] / rc : 1, rc > 0 ? cen[1] / rc : 0};
    /* its length along the axis and its width across, round its centre */
    double zlo = INFINITY, zhi = -INFINITY, tlo = INFINITY, thi = -INFINITY;
    for (size_t q = 0; q < vr->at_count; q++)
        if (label[vr->at[q]] == s) {
            double c[3];
            sr_img_voxel_centre(g, vr->at[q], c);
            double t = -c[0] * rdir[1] + c[1] * rdir[0];
            zlo = fmin(zlo, c[2]), zhi = fmax(zhi, c[2]);
            tlo = fmin(tlo, t), thi = fmax(thi, t);
        }
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
    if (bins < DESIGN_BINS - 2) {
        design -= walls - walls_framed;
        if (zhi - zlo + g->h < DESIGN_MIN_LENGTH * (thi - tlo + g->h))
            return 0; /* wider than long: not a keyway's or a slot's */
    }
    return total > 0 && design >= DESIGN_SHARE * total && spread < 0.8;
}

/* Glide, a section of weak evidence alone (image_vote.h): an end of the pattern where
 * the other side's pattern runs on (a phantom tooth: not to be built), or a feature of
 * the ends broken off (a first tooth). The scan's surface facing the section (its
 * triangles whose outside, a voxel along the normal, lies in it) tells them apart: the
 * design's faces there either lie along the frame (the plain core's face: within
 * FRAME_DEG of x, y or z, and within what the scan's noise tilts that facet by) or have
 * an image on the scan's surface (the next tooth's flank); a fracture's do neither.
 * True when FRACTURE_SHARE of that area is fracture. The tilt: noise of sigma moving a
 * vertex off the plane turns the normal by sigma over that vertex's height in the
 * triangle, so by sigma sqrt(sum 1 / h_i^2) over all three; three times that is
 * allowed, up to FRAME_MAX_DEG (a generated rack's noisy scan, sigma 0.02 mm on facets
 * of 1.5 mm: the core's end face tilted past 3 degrees read as fracture, and a phantom
 * tooth of 196 mm^3 was built beyond the end). A facet is judged by the mean normal of
 * the facets facing the section within SMOOTH_PITCHES voxels of it (area-weighted), its
 * allowance shrunk by the square root of their count: noise scatters small facets' normals
 * both ways round the face's, and a scan's facets of half a millimetre were each allowed
 * 20 degrees, so a ratchet's tooth broken off along a fracture 17 degrees off the core's
 * face read as design and was not built (s2207p11, noisy: 163 mm^3 missed).
 * (Tried first on voxels alone: the core's face at a sawtooth rack's end has no image
 * on the surface, so phantoms were built at both ends.) */
#define FRAME_DEG 3.0
#define FRAME_MAX_DEG 30.0
#define FRACTURE_SHARE 0.5
#define SMOOTH_PITCHES 8.0
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

/* A facet facing the section: its centroid, unit normal, area and noise allowance
 * (1 / h^2 summed over its three heights). */
typedef struct facet {
    double p[3], n[3], area, inv_h2;
    size_t outside; /* the voxel one pitch along its normal */
    bool fracture;  /* judged fracture (else design) */
    int frame_key;  /* design as a face of the frame: 2 * axis + (normal < 0); else -1 */
} facet;

static int facet_x_cmp(const void *a, const void *b)
{
    double x = ((const facet *)a)->p[0], y = ((const facet *)b)->p[0];
    return (x > y) - (x < y);
}

/* The facets facing section s (their outside voxel, one pitch along the normal, in it),
 * each judged design or fracture as said above, into *out (malloc'ed, *count of them);
 * false when out of memory or the images cannot be had. */
/* A plane of the frame the scan's surface lies in away from a region: axis (0..2) and
 * sign of its normal, its offset along the axis, the area lying in it. */
typedef struct frame_face {
    int key; /* 2 * axis + (normal < 0) */
    double at, area;
} frame_face;

static int frame_face_cmp(const void *a, const void *b)
{
    const frame_face *x = a, *y = b;
    if (x->key != y->key)
        return x->key - y->key;
    return (x->at > y->at) - (x->at < y->at);
}

/* The area of the scan's facets facing away from every loss (their outside voxel in no
 * section) that lie, within tol, in the plane of the frame of key and offset at. */
static double continued_area(const frame_face *ff, size_t n, int key, double at, double tol)
{
    size_t lo = 0, hi = n;
    while (lo < hi) { /* the first entry at or past (key, at - tol) */
        size_t mid = lo + (hi - lo) / 2;
        if (ff[mid].key < key || (ff[mid].key == key && ff[mid].at < at - tol))
            lo = mid + 1;
        else
            hi = mid;
    }
    double area = 0;
    for (size_t i = lo; i < n && ff[i].key == key && ff[i].at <= at + tol; i++)
        area += ff[i].area;
    return area;
}

/* The points one facet of triangle a, b, c stands for: its centroid (parts 1), or with
 * parts k > 1 the centroids of the k * k triangles of its barycentric grid, numbered
 * 0 .. k * k - 1. */
static void part_centroid(const double *a, const double *b, const double *c, size_t k, size_t idx,
                          double p[3])
{
    if (k == 1) {
        for (int d = 0; d < 3; d++)
            p[d] = (a[d] + b[d] + c[d]) / 3;
        return;
    }
    /* row i holds 2 (k - i) - 1 triangles: k - i pointing up, k - i - 1 down */
    size_t i = 0;
    while (idx >= 2 * (k - i) - 1) {
        idx -= 2 * (k - i) - 1;
        i++;
    }
    double u, w; /* barycentric weights of b and c at the small triangle's centroid */
    if (idx < k - i) {
        size_t j = idx;
        u = ((double)i + 1.0 / 3) / (double)k;
        w = ((double)j + 1.0 / 3) / (double)k;
    } else {
        size_t j = idx - (k - i);
        u = ((double)i + 2.0 / 3) / (double)k;
        w = ((double)j + 2.0 / 3) / (double)k;
    }
    for (int d = 0; d < 3; d++)
        p[d] = a[d] + u * (b[d] - a[d]) + w * (c[d] - a[d]);
}

#define DENSE_MAX_PARTS 64 /* a triangle looked at in at most 64 x 64 parts */

/* Whether triangle (a, b, c) lies within reach of the voxels whose indices lie in vbox
 * (NULL: the whole grid): a part's centroid p is in the triangle's box, the point
 * looked at is p + n h, and the voxel nearest it is within half a pitch: so no part of
 * a triangle whose box is more than 1.5 pitches from vbox's centres (2 taken) faces
 * one of them. */
static bool near_box(const sr_voxels *g, const size_t *vbox, const double *a, const double *b,
                     const double *c)
{
    if (!vbox)
        return true;
    for (int d = 0; d < 3; d++) {
        double lo = g->origin[d] + (double)vbox[d] * g->h - 2.0 * g->h,
               hi = g->origin[d] + (double)vbox[3 + d] * g->h + 2.0 * g->h;
        if (fmax(a[d], fmax(b[d], c[d])) < lo || fmin(a[d], fmin(b[d], c[d])) > hi)
            return false;
    }
    return true;
}

static bool judge_facets(const sr_mesh *m, const sr_voxels *g, const int *label, int s,
                         const sr_symmetry *sym, double noise_mm, bool continued, bool dense,
                         const size_t *vbox, facet **out, size_t *count)
{
    sr_image *im = NULL;
    size_t n_im = 0;
    if (sr_images_of(sym, &im, &n_im, NULL) != SR_OK)
        return false;
    size_t cap = m->tri_count + 1;
    facet *f = malloc(cap * sizeof *f);
    frame_face *ff = continued ? malloc((m->tri_count + 1) * sizeof *ff) : NULL;
    if (!f || (continued && !ff)) {
        free(im);
        free(f);
        free(ff);
        return false;
    }
    size_t nf = 0, nff = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const double *a = m->xyz + 3 * m->tri[3 * t], *b = m->xyz + 3 * m->tri[3 * t + 1],
                     *c = m->xyz + 3 * m->tri[3 * t + 2];
        double nv[3];
        sr_mesh_tri_normal(m, t, nv);
        double len = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
        if (!(len > 0))
            continue;
        double un[3] = {nv[0] / len, nv[1] / len, nv[2] / len}, cen[3];
        part_centroid(a, b, c, 1, 0, cen);
        double q[3] = {cen[0] + un[0] * g->h, cen[1] + un[1] * g->h, cen[2] + un[2] * g->h};
        long vi = sr_voxels_locate(g, q);
        if (vi < 0 || label[vi] != s) {
            bool away = vi < 0 || label[vi] <= 0; /* facing no loss at all */
            for (int ax = 0; continued && away && ax < 3; ax++)
                if (fabs(un[ax]) > cos(FRAME_DEG * M_PI / 180.0))
                    ff[nff++] = (frame_face){2 * ax + (un[ax] < 0), cen[ax], 0.5 * len};
            if (!dense || !near_box(g, vbox, a, b, c))
                continue;
        }
        /* dense: a triangle longer than a pitch is looked at in parts, each facing its
         * own voxel (a coarse mesh's plane chip is a few triangles, whose centroids
         * face no thin region beside them) */
        double e_max = 0;
        const double *v[3] = {a, b, c};
        double inv_h2 = 0;
        for (int i = 0; i < 3; i++) {
            const double *p = v[(i + 1) % 3], *o = v[(i + 2) % 3];
            double e2 = (p[0] - o[0]) * (p[0] - o[0]) + (p[1] - o[1]) * (p[1] - o[1]) +
                        (p[2] - o[2]) * (p[2] - o[2]);
            e_max = fmax(e_max, sqrt(e2));
            inv_h2 += e2 / (len * len); /* height h_i = len / |opposite edge| */
        }
        size_t k = 1;
        if (dense && e_max > g->h)
            k = (size_t)fmin(DENSE_MAX_PARTS, ceil(e_max / g->h));
        for (size_t part = 0; part < k * k; part++) {
            double p[3];
            part_centroid(a, b, c, k, part, p);
            if (k > 1 || dense) {
                double qq[3] = {p[0] + un[0] * g->h, p[1] + un[1] * g->h, p[2] + un[2] * g->h};
                vi = sr_voxels_locate(g, qq);
                if (vi < 0 || label[vi] != s)
                    continue;
            }
            if (nf + 1 >= cap) {
                facet *f2 = realloc(f, 2 * cap * sizeof *f2);
                if (!f2) {
                    free(im);
                    free(f);
                    free(ff);
                    return false;
                }
                f = f2;
                cap *= 2;
            }
            facet *x = &f[nf++];
            memcpy(x->n, un, sizeof un);
            memcpy(x->p, p, sizeof x->p);
            x->outside = (size_t)vi;
            x->area = 0.5 * len / (double)(k * k);
            x->inv_h2 = inv_h2 * (double)(k * k);
        }
    }
    qsort(f, nf, sizeof *f, facet_x_cmp);
    if (continued)
        qsort(ff, nff, sizeof *ff, frame_face_cmp);
    double r = SMOOTH_PITCHES * g->h, sigma = noise_mm > 0 ? noise_mm : 0;
    double tol = fmax(0.5 * g->h, 3.0 * sigma), least = 4.0 * g->h * g->h;
    for (size_t i = 0, lo = 0; i < nf; i++) {
        facet *x = &f[i];
        while (f[lo].p[0] < x->p[0] - r)
            lo++;
        double nv[3] = {0, 0, 0};
        size_t count_near = 0;
        for (size_t j = lo; j < nf && f[j].p[0] <= x->p[0] + r; j++) {
            double d[3] = {f[j].p[0] - x->p[0], f[j].p[1] - x->p[1], f[j].p[2] - x->p[2]};
            if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > r * r)
                continue;
            for (int k = 0; k < 3; k++)
                nv[k] += f[j].area * f[j].n[k];
            count_near++;
        }
        double len = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
        for (int k = 0; k < 3; k++)
            nv[k] = len > 0 ? nv[k] / len : x->n[k];
        double deg = FRAME_DEG + 3.0 * sigma *
                                     sqrt(x->inv_h2 / (double)(count_near ? count_near : 1)) *
                                     180.0 / M_PI;
        double cs = cos(fmin(deg, FRAME_MAX_DEG) * M_PI / 180.0);
        x->fracture = false;
        x->frame_key = -1;
        int along = -1;
        for (int a = 0; a < 3; a++)
            along = fabs(nv[a]) > cs ? a : along;
        if (along >= 0 && (!continued || continued_area(ff, nff, 2 * along + (nv[along] < 0),
                                                        x->p[along], tol) >= least)) {
            /* a plane to part the region by only when it lies along the frame itself,
             * not within the noise's allowance (a noisy end chip's tilted facets cut
             * its own voxels off: -3.3 %) */
            if (fabs(nv[along]) > cos(FRAME_DEG * M_PI / 180.0))
                x->frame_key = 2 * along + (nv[along] < 0);
            continue;
        } /* along the frame (and, if asked, a face of the part going on away
                       * from the region): the design's */
        int twin = 0;
        for (size_t k = 0; k < n_im && !twin; k++) {
            const double *xf = im[k].xf;
            double pp[3], nn[3];
            for (int q = 0; q < 3; q++) {
                pp[q] = xf[4 * q] * x->p[0] + xf[4 * q + 1] * x->p[1] + xf[4 * q + 2] * x->p[2] +
                        xf[4 * q + 3];
                nn[q] = xf[4 * q] * nv[0] + xf[4 * q + 1] * nv[1] + xf[4 * q + 2] * nv[2];
            }
            twin = surface_at(g, pp, nn);
        }
        x->fracture = !twin;
    }
    free(im);
    free(ff);
    *out = f;
    *count = nf;
    return true;
}

double sr_img_fracture_share(const sr_mesh *m, const sr_voxels *g, const int *label, int s,
                             const sr_symmetry *sym, double noise_mm, bool continued, bool dense,
                             const size_t *vbox)
{
    facet *f = NULL;
    size_t nf = 0;
    if (!judge_facets(m, g, label, s, sym, noise_mm, continued, dense, vbox, &f, &nf))
        return -1;
    double total = 0, fracture = 0;
    for (size_t i = 0; i < nf; i++) {
        total += f[i].area;
        fracture += f[i].fracture ? f[i].area : 0;
    }
    free(f);
    return total > 0 ? fracture / total : 0;
}

int sr_img_fracture_bounded(const sr_mesh *m, const sr_voxels *g, const int *label, int s,
                            const sr_symmetry *sym, double noise_mm)
{
    double share = sr_img_fracture_share(m, g, label, s, sym, noise_mm, false, false, NULL);
    return share < 0 /* built: a loss left out is the worse mistake */ || share >= FRACTURE_SHARE;
}

/* A glide's pattern ends on each side at its own place: at an end, the image from the
 * middle's side carries the other side's first tooth onto a stretch where this side has
 * none. When a chip there took the plain end's material, that phantom tooth joins the
 * chip's strong core and was built with it (a double-sided rack's end chip restored
 * with a tooth more: +36 % of the loss; a ratchet's: +28 %). Such a region of weak
 * evidence also holds the chip's own material near the end (where the image from
 * beyond falls past the end): judged whole, the chip was missed (-17 %). So its voxels
 * are parted (claim): those standing in front of a face of the frame that faces them
 * and goes on as a face of the part away from the loss (the intact face a phantom tooth
 * would stand on) go with the design; the rest stay. Those only nearer to these than
 * to a fracture facing the region count towards the design's share (the region is
 * parted only when enough goes), but stay: behind every face of the design they are
 * the chip's own material by a corner or along a face of the frame (dropped, a
 * generated rack's end chip lost the corner of its core, 1.2 mm, and another 1.7 mm of
 * its depth, which the section's hull took back only where it reached). A face of the
 * frame that does not go on (a cut along an axis, a test's box chip) is a fracture
 * here. (Tried: the nearest facet alone left a third of the phantom built; faces of the
 * frame counted as design whether or not they went on dropped a rack's chip cut along
 * the frame.) */
#define WEAK_REGION INT_MIN /* a weak voxel of the section looked at, not yet grouped */

/* The voxels labelled probe (n of them, region[]) that go with the design: those
 * standing in front of a face of the frame that faces them and goes on as a face of
 * the part away from every loss (past its plane, half a pitch or more, along its
 * outward normal), then those nearer (in 26-connected steps through the region) to
 * them or to such a face than to a fracture facing the region (fracture first at equal
 * steps; a voxel neither reaches stays). Relabelled probe + 1 (in front of a face) or
 * probe + 3 (nearer to one), the others probe + 2 or left; returns how many went with
 * the design, or SIZE_MAX when out of memory. queue has room for n. */
static size_t claim(const sr_mesh *m, const sr_voxels *g, int *label, int probe,
                    const size_t *region, size_t n, size_t *queue, const sr_symmetry *sym,
                    double noise_mm)
{
    facet *f = NULL;
    size_t nf = 0;
    if (!judge_facets(m, g, label, probe, sym, noise_mm, true, false, NULL, &f, &nf))
        return SIZE_MAX;
    size_t head = 0, tail = 0, design = 0;
    /* the fracture's seeds first: the voxels its facets face */
    for (size_t i = 0; i < nf; i++)
        if (f[i].fracture && label[f[i].outside] == probe) {
            label[f[i].outside] = probe + 2;
            queue[tail++] = f[i].outside;
        }
    for (size_t r = 0; r < n; r++) {
        if (label[region[r]] != probe)
            continue;
        double c[3];
        sr_img_voxel_centre(g, region[r], c);
        for (size_t i = 0; i < nf; i++) {
            int key = f[i].frame_key;
            if (key < 0)
                continue;
            int axis = key / 2;
            double out = (key & 1 ? -1.0 : 1.0) * (c[axis] - f[i].p[axis]);
            if (out >= 0.5 * g->h || f[i].outside == region[r]) {
                label[region[r]] = probe + 1;
                queue[tail++] = region[r];
                break;
            }
        }
    }
    free(f);
    while (head < tail) {
        size_t v = queue[head++];
        int kind = label[v];
        design += kind == probe + 1 || kind == probe + 3;
        size_t nb[26], nn = sr_voxel_neighbours26(g, v, nb);
        for (size_t q = 0; q < nn; q++)
            if (label[nb[q]] == probe) {
                label[nb[q]] = kind == probe + 2 ? kind : probe + 3;
                queue[tail++] = nb[q];
            }
    }
    return design;
}

size_t sr_img_drop_phantom_ends(const sr_mesh *m, const sr_voxels *g, sr_vote_result *vr,
                                size_t min_voxels, const sr_symmetry *sym, double noise_mm)
{
    if (!vr->weak || vr->sections == 0 || vr->sections >= (size_t)INT_MAX - 4)
        return 0;
    size_t *stack = malloc((vr->at_count + 1) * sizeof *stack);
    size_t *region = malloc((vr->at_count + 1) * sizeof *region);
    if (!stack || !region) {
        free(stack);
        free(region);
        return 0;
    }
    size_t dropped = 0;
    int probe = (int)vr->sections + 1; /* labels no section has: probe .. probe + 3 */
    for (size_t s = 1; s <= vr->sections; s++) {
        if (vr->weak_only && vr->weak_only[s - 1])
            continue; /* a core of weak evidence alone: judged whole (image_restore.c) */
        for (size_t q = 0; q < vr->at_count; q++)
            if (vr->weak[q] && vr->label[vr->at[q]] == (int)s)
                vr->label[vr->at[q]] = WEAK_REGION;
        for (size_t q0 = 0; q0 < vr->at_count; q0++) {
            if (vr->label[vr->at[q0]] != WEAK_REGION)
                continue;
            size_t top = 0, n = 0;
            stack[top++] = vr->at[q0];
            vr->label[vr->at[q0]] = probe;
            while (top) {
                size_t v = stack[--top];
                region[n++] = v;
                size_t nb[26], nn = sr_voxel_neighbours26(g, v, nb);
                for (size_t q = 0; q < nn; q++)
                    if (vr->label[nb[q]] == WEAK_REGION) {
                        vr->label[nb[q]] = probe;
                        stack[top++] = nb[q];
                    }
            }
            size_t design = n < min_voxels ? 0
                                           : claim(m, g, vr->label, probe, region, n, stack, sym,
                                                   noise_mm);
            bool drop = design != SIZE_MAX && design >= min_voxels;
            for (size_t r = 0; r < n; r++) {
                bool gone = drop && vr->label[region[r]] == probe + 1;
                vr->label[region[r]] = gone ? -1 : (int)s;
                vr->voxels[s - 1] -= gone;
            }
            dropped += drop;
        }
    }
    free(stack);
    free(region);
    return dropped;
}
