/*
 * align_egi.c: candidate mirror-plane normals from the scan's normals alone
 * (align_internal.h).
 *
 * The extended Gaussian image (EGI, Horn 1984) of a surface is its area per normal
 * direction. Reflecting a part in a plane with unit normal m reflects its EGI by
 * n -> n - 2 (n.m) m, and a translation does not change it, so the normal of every
 * mirror or glide plane is a direction about which the EGI is reflection-symmetric -
 * whatever the plane's offset, and almost whatever the damage (a broken piece removes
 * a little area). That makes a cheap, offset-free first search over all directions:
 *  - the EGI is binned on a cube map (6 x 16 x 16 bins, about 5 deg each) and blurred
 *    with a 10 deg tent (scan noise tilts normals by a degree or two, and a candidate
 *    off by a few degrees must still score, smoothly);
 *  - each of 1000 normals of a Fibonacci hemisphere (about 4.5 deg apart) scores the
 *    overlap sum_b min(E(b), E(reflected b)) / sum_b E(b);
 *  - the best lattice directions at least 12 deg apart (twice as many as asked for)
 *    are each improved by a hill-climb in 2, 1 and 0.5 deg steps, and the best
 *    distinct results are returned.
 * The principal planes of the area covariance miss a mirror plane when damage tilts
 * them (a U clamp missing 8 % of its volume has its principal axes turned ~18 deg);
 * this search does not.
 */
#include "align/align_internal.h"

#include <stdlib.h>
#include <string.h>

#define NSIDE 24
#define NBIN (6 * NSIDE * NSIDE)
#define NDIR 1000
#define BLUR_DEG 10.0

static int bin_of(const double v[3])
{
    int ax = 0;
    if (fabs(v[1]) > fabs(v[ax]))
        ax = 1;
    if (fabs(v[2]) > fabs(v[ax]))
        ax = 2;
    double m = fabs(v[ax]);
    if (!(m > 0))
        return 0;
    int a = (ax + 1) % 3, b = (ax + 2) % 3;
    int face = 2 * ax + (v[ax] < 0);
    int i = (int)((v[a] / m + 1) * 0.5 * NSIDE), j = (int)((v[b] / m + 1) * 0.5 * NSIDE);
    i = i < 0 ? 0 : (i >= NSIDE ? NSIDE - 1 : i);
    j = j < 0 ? 0 : (j >= NSIDE ? NSIDE - 1 : j);
    return (face * NSIDE + i) * NSIDE + j;
}

static void bin_center(int bin, double v[3])
{
    int face = bin / (NSIDE * NSIDE), i = (bin / NSIDE) % NSIDE, j = bin % NSIDE;
    int ax = face / 2, a = (ax + 1) % 3, b = (ax + 2) % 3;
    v[ax] = face % 2 ? -1 : 1;
    v[a] = (i + 0.5) / NSIDE * 2 - 1;
    v[b] = (j + 0.5) / NSIDE * 2 - 1;
    v3_normalize(v);
}

/* sum_b min(E(b), E(reflection of b's centre in the plane with normal m)) */
static double reflect_overlap(const double *e, const double *cen, const double m[3])
{
    double sum = 0;
    for (int b = 0; b < NBIN; b++) {
        if (e[b] == 0)
            continue;
        const double *c = cen + 3 * b;
        double d = 2 * v3_dot(c, m);
        double rc[3] = {c[0] - d * m[0], c[1] - d * m[1], c[2] - d * m[2]};
        double o = e[bin_of(rc)];
        sum += o < e[b] ? o : e[b];
    }
    return sum;
}

int al_egi_mirror_normals(const al_surface *s, double (*out)[3], int max_out)
{
    double *h = calloc(NBIN, sizeof *h), *e = calloc(NBIN, sizeof *e);
    double *cen = malloc(NBIN * 3 * sizeof *cen);
    double *dir = malloc(NDIR * 3 * sizeof *dir), *score = malloc(NDIR * sizeof *score);
    int found = 0;
    if (!h || !e || !cen || !dir || !score)
        goto done;
    for (size_t i = 0; i < s->count; i++) {
        double n[3], area;
        al_surface_normal(s, i, n, &area);
        h[bin_of(n)] += area;
    }
    for (int b = 0; b < NBIN; b++)
        bin_center(b, cen + 3 * b);
    /* tent blur: weight 1 - angle / BLUR, so the score falls off smoothly with the
     * candidate's error even for the spiky EGI of a CAD mesh's flat faces */
    double cblur = cos(BLUR_DEG * M_PI / 180), total = 0;
    for (int b = 0; b < NBIN; b++) {
        if (h[b] == 0)
            continue;
        for (int c = 0; c < NBIN; c++) {
            double d = v3_dot(cen + 3 * b, cen + 3 * c);
            if (d >= cblur) /* angle ~ chord sqrt(2 (1 - d)) at these small angles */
                e[c] += h[b] * (1 - sqrt(2 * (1 - (d > 1 ? 1 : d))) / (BLUR_DEG * M_PI / 180));
        }
    }
    for (int b = 0; b < NBIN; b++)
        total += e[b];
    if (!(total > 0))
        goto done;
    double golden = M_PI * (3 - sqrt(5.0));
    for (int i = 0; i < NDIR; i++) {
        double z = 1 - (i + 0.5) / NDIR;
        double r = sqrt(1 - z * z), ph = golden * i;
        double *m = dir + 3 * i;
        m[0] = r * cos(ph);
        m[1] = r * sin(ph);
        m[2] = z;
        score[i] = reflect_overlap(e, cen, m) / total;
    }
    /* local maxima (antipodal directions are the same plane) */
    double cnear = cos(12 * M_PI / 180);
    enum { MAXC = 24 };
    double cm[MAXC][3], cs[MAXC];
    int nc = 0;
    while (nc < MAXC && nc < 2 * max_out) {
        int best = -1;
        for (int i = 0; i < NDIR; i++)
            if (score[i] >= 0 && (best < 0 || score[i] > score[best]))
                best = i;
        if (best < 0)
            break;
        /* hill-climb from the lattice point in steps of 2, 1, 0.5 deg: the binned score
         * is only a rough guide at the lattice point itself */
        double m[3], u[3], w[3], cur = score[best];
        memcpy(m, dir + 3 * best, sizeof m);
        for (double st = 2; st >= 0.5; st *= 0.5) {
            for (bool moved = true; moved;) {
                moved = false;
                al_perp_frame(m, u, w);
                for (int k = 0; k < 4; k++) {
                    double a = st * M_PI / 180 * (k < 2 ? 1 : -1);
                    const double *t = k % 2 ? w : u;
                    double c[3] = {m[0] + a * t[0], m[1] + a * t[1], m[2] + a * t[2]};
                    v3_normalize(c);
                    double sc = reflect_overlap(e, cen, c) / total;
                    if (sc > cur + 1e-12) {
                        cur = sc;
                        memcpy(m, c, sizeof m);
                        moved = true;
                    }
                }
            }
        }
        memcpy(cm[nc], m, sizeof m);
        cs[nc++] = cur;
        for (int i = 0; i < NDIR; i++)
            if (fabs(v3_dot(dir + 3 * i, dir + 3 * best)) >= cnear)
                score[i] = -1;
    }
    /* best climbed first, skipping climbs that ended on an earlier one */
    double csame = cos(5 * M_PI / 180);
    while (found < max_out) {
        int best = -1;
        for (int i = 0; i < nc; i++)
            if (cs[i] >= 0 && (best < 0 || cs[i] > cs[best]))
                best = i;
        if (best < 0)
            break;
        bool dup = false;
        for (int j = 0; j < found; j++)
            dup = dup || fabs(v3_dot(out[j], cm[best])) >= csame;
        if (!dup) {
            memcpy(out[found++], cm[best], sizeof cm[best]);
        }
        cs[best] = -1;
    }
done:
    free(h);
    free(e);
    free(cen);
    free(dir);
    free(score);
    return found;
}
