/*
 * align_surface.c: the scan as a surface for the alignment (align_internal.h).
 *
 * Owns three things, all linear in the triangle count:
 *  - per-triangle unit normals (rounded to float, 12 bytes a triangle: only for skipping
 *    far triangles; al_surface_normal recomputes the exact normal and area from the
 *    vertices, bit for bit what the build computed), the area centroid and the exact
 *    area-weighted second moments of the surface (a triangle's integral of x x^T is
 *    A/12 (a a^T + b b^T + c c^T + 9 m m^T), m its centroid), whose eigenvectors are
 *    the principal directions used as alignment candidates;
 *  - area-uniform sample points (stratified over the cumulative area, jittered with a
 *    fixed-seed splitmix64, so runs are reproducible);
 *  - a uniform grid of triangles answering "closest surface point to p". A triangle
 *    goes into every cell it meets (separating-axis test), so long slivers of CAD
 *    meshes do not flood the grid. Cells are kept by bricks of 4 x 4 x 4
 *    and only the bricks the triangles reach hold cell offsets: a surface fills few of
 *    a grid's cells, and a dense offset array for a million-triangle scan took 34 MB.
 *    Queries visit cubic shells of cells around p and stop once the best distance
 *    found is below the shell's inner distance (or past max_dist). A per-triangle stamp
 *    (one array for each thread that queries: al_surface_threads) skips triangles
 *    already tested through another cell. A chessboard distance
 *    transform of the occupied bricks (two raster passes over the 26-neighbourhood,
 *    exact for that metric) lets a query far from the surface skip its empty shells,
 *    or give up at once when even the nearest occupied brick is beyond max_dist; a cell
 *    whose box is farther than the best triangle so far, and a triangle whose plane is,
 *    are skipped. The cell size is 1.5 x the mean triangle size, but at least 1/250 of
 *    the bounding-box diagonal (on a million-triangle scan finer cells make wide
 *    queries walk too many of them) and such that the grid has at most about 16M cells.
 */
#include "align/align_internal.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CELLS 16000000.0
#define CELLS_PER_DIAG 250.0

static const double *vtx(const al_surface *s, size_t i, int k)
{
    return s->mesh->xyz + 3 * (size_t)s->mesh->tri[3 * al_tri_of(s, i) + k];
}

void al_surface_release(al_surface *s)
{
    if (!s)
        return;
    free(s->tri);
    free(s->nrm);
    free(s->brick_slot);
    free(s->cell_start);
    free(s->cell_items);
    for (int t = 0; t < AL_THREADS_MAX; t++)
        free(s->stamp[t]);
    free(s->brick_rings);
    memset(s, 0, sizeof *s);
}

/* Unit normal and area of triangle t of m (NaN-free only when the area is > 0). */
static double tri_normal(const sr_mesh *m, size_t t, double n[3])
{
    const uint32_t *f = m->tri + 3 * t;
    const double *pa = m->xyz + 3 * (size_t)f[0], *pb = m->xyz + 3 * (size_t)f[1],
                 *pc = m->xyz + 3 * (size_t)f[2];
    double u[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    double w[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
    v3_cross(u, w, n);
    return 0.5 * v3_normalize(n);
}

void al_surface_normal(const al_surface *s, size_t i, double n[3], double *area)
{
    double a = tri_normal(s->mesh, al_tri_of(s, i), n);
    if (area)
        *area = a;
}

/* Index of cell (x, y, z) in cell_start, or SIZE_MAX when its brick holds nothing. */
static size_t cell_index(const al_surface *s, int x, int y, int z)
{
    size_t b = (size_t)(x >> 2) +
               (size_t)s->bdim[0] * ((size_t)(y >> 2) + (size_t)s->bdim[1] * (size_t)(z >> 2));
    uint32_t slot = s->brick_slot[b];
    if (slot == UINT32_MAX)
        return SIZE_MAX;
    return (size_t)slot * 64 + (size_t)((x & 3) + 4 * ((y & 3) + 4 * (z & 3)));
}

static void cell_of(const al_surface *s, const double p[3], int idx[3])
{
    for (int k = 0; k < 3; k++) {
        double f = (p[k] - s->origin[k]) / s->cell;
        int i = f <= 0 ? 0 : (f >= s->dim[k] - 1 ? s->dim[k] - 1 : (int)f);
        idx[k] = i;
    }
}

/* The separating axes of a triangle against axis-aligned cells (Akenine-Moeller): its
 * plane and the 9 cross products of its edges with the box axes (the box axes
 * themselves are the bounding-box range). Per axis the triangle's extent [lo, hi]
 * along it and the factor giving the cell's half extent along it. */
typedef struct tri_axes {
    double n[3], d;        /* plane: n . x = d */
    double ax[9][3], lo[9], hi[9], r[9];
} tri_axes;

static void tri_axes_make(const al_surface *s, size_t i, tri_axes *t, bool edges)
{
    const double *v[3] = {vtx(s, i, 0), vtx(s, i, 1), vtx(s, i, 2)};
    al_surface_normal(s, i, t->n, NULL);
    t->d = v3_dot(t->n, v[0]);
    for (int e = 0; edges && e < 3; e++) {
        const double *a = v[e], *b = v[(e + 1) % 3];
        double f[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        for (int k = 0; k < 3; k++) {
            double *ax = t->ax[3 * e + k]; /* e_k x f */
            ax[k] = 0;
            ax[(k + 1) % 3] = -f[(k + 2) % 3];
            ax[(k + 2) % 3] = f[(k + 1) % 3];
            double p0 = v3_dot(ax, v[0]), p1 = v3_dot(ax, v[1]), p2 = v3_dot(ax, v[2]);
            t->lo[3 * e + k] = fmin(p0, fmin(p1, p2));
            t->hi[3 * e + k] = fmax(p0, fmax(p1, p2));
            t->r[3 * e + k] = fabs(ax[0]) + fabs(ax[1]) + fabs(ax[2]);
        }
    }
}

/* Does the triangle meet the cell (ix, iy, iz)? The cell is grown by a hair and every
 * comparison given a margin of 1e-9 of its magnitudes, so rounding never drops a cell
 * the triangle touches (an extra cell costs only time). A triangle is filed only where
 * it is: a CAD end cap's long fan triangles, tilted, used to be filed in every cell
 * their plane cut within their box (5.7 cells a triangle on a million-triangle scan,
 * 23 MB of lists; now 2.6). */
static bool plane_meets_cell(const al_surface *s, const tri_axes *t, int ix, int iy, int iz)
{
    double h = s->cell, half = 0.5 * h * (1 + 1e-9) + 1e-12;
    double c[3] = {s->origin[0] + (ix + 0.5) * h, s->origin[1] + (iy + 0.5) * h,
                   s->origin[2] + (iz + 0.5) * h};
    double pc = v3_dot(t->n, c), reach = half * (fabs(t->n[0]) + fabs(t->n[1]) + fabs(t->n[2]));
    return fabs(pc - t->d) <= reach + 1e-9 * (fabs(pc) + fabs(t->d) + reach);
}

static bool tri_meets_cell(const al_surface *s, const tri_axes *t, int ix, int iy, int iz)
{
    if (!plane_meets_cell(s, t, ix, iy, iz))
        return false;
    double h = s->cell, half = 0.5 * h * (1 + 1e-9) + 1e-12;
    double c[3] = {s->origin[0] + (ix + 0.5) * h, s->origin[1] + (iy + 0.5) * h,
                   s->origin[2] + (iz + 0.5) * h};
    double pc;
    for (int a = 0; a < 9; a++) {
        pc = v3_dot(t->ax[a], c);
        double r = half * t->r[a];
        double slack = 1e-9 * (fabs(t->lo[a]) + fabs(t->hi[a]) + fabs(pc) + r);
        if (t->lo[a] - pc > r + slack || t->hi[a] - pc < -r - slack)
            return false;
    }
    return true;
}

/* The range of cells triangle i's bounding box spans. */
static void tri_cells(const al_surface *s, size_t i, int a[3], int b[3])
{
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = hi[k] = vtx(s, i, 0)[k];
        for (int j = 1; j < 3; j++) {
            double x = vtx(s, i, j)[k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    }
    cell_of(s, lo, a);
    cell_of(s, hi, b);
}

/* Visits the cells triangle i is filed in: pass 0 counts, pass 1 fills each cell
 * downwards from cursor[cell] (its end). */
static void file_cell(al_surface *s, size_t i, int pass, uint32_t *cursor, int x, int y,
                      int z)
{
    size_t cidx = cell_index(s, x, y, z);
    if (pass == 0)
        s->cell_start[cidx + 1]++;
    else
        s->cell_items[--cursor[cidx]] = (uint32_t)i;
}

static void file_triangle(al_surface *s, size_t i, int pass, uint32_t *cursor)
{
    int a[3], b[3];
    tri_cells(s, i, a, b);
    int spread = (b[0] > a[0]) + (b[1] > a[1]) + (b[2] > a[2]);
    if (spread < 2) { /* a row of cells at most: all of them */
        for (int z = a[2]; z <= b[2]; z++)
            for (int y = a[1]; y <= b[1]; y++)
                for (int x = a[0]; x <= b[0]; x++)
                    file_cell(s, i, pass, cursor, x, y, z);
        return;
    }
    tri_axes t;
    bool small = (b[0] - a[0] + 1) * (b[1] - a[1] + 1) * (b[2] - a[2] + 1) <= 8;
    tri_axes_make(s, i, &t, !small);
    if (small) {
        /* a small triangle over a cell corner: its plane's cells (the edge axes would
         * drop one in a few, not worth their cost on a million triangles) */
        for (int z = a[2]; z <= b[2]; z++)
            for (int y = a[1]; y <= b[1]; y++)
                for (int x = a[0]; x <= b[0]; x++)
                    if (plane_meets_cell(s, &t, x, y, z))
                        file_cell(s, i, pass, cursor, x, y, z);
        return;
    }
    /* walk the box's columns along the normal's dominant axis m; in each, only the
     * cells near the plane (its crossing of the column +- one cell) can pass the test */
    int m = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(t.n[k]) > fabs(t.n[m]))
            m = k;
    int u = (m + 1) % 3, v = (m + 2) % 3;
    double h = s->cell;
    for (int cu = a[u]; cu <= b[u]; cu++)
        for (int cv = a[v]; cv <= b[v]; cv++) {
            double xu = s->origin[u] + (cu + 0.5) * h, xv = s->origin[v] + (cv + 0.5) * h;
            double xm = (t.d - t.n[u] * xu - t.n[v] * xv) / t.n[m];
            double reach = 0.5 * h * (fabs(t.n[0]) + fabs(t.n[1]) + fabs(t.n[2])) /
                           fabs(t.n[m]);
            double f0 = (xm - reach - s->origin[m]) / h - 1.5,
                   f1 = (xm + reach - s->origin[m]) / h + 0.5;
            int lo = f0 <= a[m] ? a[m] : (f0 >= b[m] ? b[m] : (int)f0);
            int hi = f1 >= b[m] ? b[m] : (f1 <= a[m] ? a[m] : (int)f1 + 1);
            for (int cm = lo; cm <= hi; cm++) {
                int c[3];
                c[m] = cm;
                c[u] = cu;
                c[v] = cv;
                if (tri_meets_cell(s, &t, c[0], c[1], c[2]))
                    file_cell(s, i, pass, cursor, c[0], c[1], c[2]);
            }
        }
}

/* Chessboard distance from every brick to the nearest brick holding a triangle,
 * saturated at 255: a forward and a backward raster pass, each taking the minimum over
 * the 13 already visited neighbours + 1 (exact for the 26-neighbourhood metric). */
static void distance_transform(al_surface *s)
{
    int nx = s->bdim[0], ny = s->bdim[1], nz = s->bdim[2];
    uint8_t *d = s->brick_rings;
    for (size_t c = 0; c < (size_t)nx * ny * nz; c++)
        d[c] = s->brick_slot[c] != UINT32_MAX ? 0 : 255;
    for (int pass = 0; pass < 2; pass++) {
        int dir = pass == 0 ? 1 : -1;
        for (int zi = 0; zi < nz; zi++) {
            int z = pass == 0 ? zi : nz - 1 - zi;
            for (int yi = 0; yi < ny; yi++) {
                int y = pass == 0 ? yi : ny - 1 - yi;
                for (int xi = 0; xi < nx; xi++) {
                    int x = pass == 0 ? xi : nx - 1 - xi;
                    size_t c = (size_t)x + (size_t)nx * ((size_t)y + (size_t)ny * z);
                    int best = d[c];
                    if (best == 0)
                        continue;
                    /* the 13 neighbours before (x, y, z) in this pass's raster order */
                    for (int dz = -1; dz <= 0; dz++)
                        for (int dy = -1; dy <= 1; dy++)
                            for (int dx = -1; dx <= 1; dx++) {
                                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0)))
                                    continue;
                                int X = x + dir * dx, Y = y + dir * dy, Z = z + dir * dz;
                                if (X < 0 || Y < 0 || Z < 0 || X >= nx || Y >= ny || Z >= nz)
                                    continue;
                                size_t cn = (size_t)X + (size_t)nx * ((size_t)Y + (size_t)ny * Z);
                                int v = d[cn] + 1;
                                best = v < best ? v : best;
                            }
                    d[c] = (uint8_t)(best > 255 ? 255 : best);
                }
            }
        }
    }
}

sr_status al_surface_build(al_surface *s, const sr_mesh *mesh, sr_err *err)
{
    memset(s, 0, sizeof *s);
    s->mesh = mesh;
    size_t nt = mesh->tri_count;
    s->tri = malloc((nt ? nt : 1) * sizeof *s->tri);
    s->nrm = malloc((nt ? nt : 1) * 3 * sizeof *s->nrm);
    if (!s->tri || !s->nrm) {
        al_surface_release(s);
        return sr_err_set(err, SR_E_NOMEM, "cannot align: out of memory for %zu triangles", nt);
    }
    sr_mesh_bbox(mesh, s->bmin, s->bmax);
    double ref[3]; /* moments are taken about the bbox centre for accuracy */
    for (int k = 0; k < 3; k++)
        ref[k] = 0.5 * (s->bmin[k] + s->bmax[k]);
    double m1[3] = {0, 0, 0}, m2[9] = {0};
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *f = mesh->tri + 3 * t;
        const double *pa = mesh->xyz + 3 * (size_t)f[0], *pb = mesh->xyz + 3 * (size_t)f[1],
                     *pc = mesh->xyz + 3 * (size_t)f[2];
        double n[3];
        double A = tri_normal(mesh, t, n);
        if (!(A > 0))
            continue;
        size_t i = s->count++;
        s->tri[i] = (uint32_t)t;
        for (int k = 0; k < 3; k++)
            s->nrm[3 * i + k] = (float)n[k];
        s->total_area += A;
        double a[3], b[3], c[3], m[3];
        for (int k = 0; k < 3; k++) {
            a[k] = pa[k] - ref[k];
            b[k] = pb[k] - ref[k];
            c[k] = pc[k] - ref[k];
            m[k] = (a[k] + b[k] + c[k]) / 3;
            m1[k] += A * m[k];
        }
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++)
                m2[3 * r + q] +=
                    A / 12 * (a[r] * a[q] + b[r] * b[q] + c[r] * c[q] + 9 * m[r] * m[q]);
    }
    if (s->count == nt) { /* no zero-area triangle: the index list is the identity */
        free(s->tri);
        s->tri = NULL;
    }
    if (s->count == 0 || !(s->total_area > 0)) {
        al_surface_release(s);
        return sr_err_set(err, SR_E_INVALID, "cannot align: the mesh has no triangle with an area");
    }
    for (int k = 0; k < 3; k++)
        m1[k] /= s->total_area;
    for (int r = 0; r < 3; r++)
        for (int q = 0; q < 3; q++)
            s->cov[3 * r + q] = m2[3 * r + q] / s->total_area - m1[r] * m1[q];
    for (int k = 0; k < 3; k++)
        s->centroid[k] = m1[k] + ref[k];
    double ext[3];
    for (int k = 0; k < 3; k++)
        ext[k] = s->bmax[k] - s->bmin[k];
    s->diag = v3_norm(ext);

    /* grid */
    double h = 1.5 * sqrt(s->total_area / (double)s->count);
    if (h < s->diag / CELLS_PER_DIAG)
        h = s->diag / CELLS_PER_DIAG;
    double vol = (ext[0] + h) * (ext[1] + h) * (ext[2] + h);
    double hmin = cbrt(vol / MAX_CELLS);
    if (h < hmin)
        h = hmin;
    if (!(h > 0))
        h = 1;
    s->cell = h;
    size_t nbrick = 1;
    for (int k = 0; k < 3; k++) {
        s->origin[k] = s->bmin[k];
        s->dim[k] = (int)(ext[k] / h) + 1;
        s->bdim[k] = (s->dim[k] + 3) / 4;
        nbrick *= (size_t)s->bdim[k];
    }
    /* bricks the triangles' boxes reach get slots (a few more than needed: harmless) */
    s->brick_slot = malloc(nbrick * sizeof *s->brick_slot);
    s->brick_rings = malloc(nbrick);
    s->stamp[0] = calloc(s->count, sizeof *s->stamp[0]);
    s->threads = 1;
    if (!s->brick_slot || !s->brick_rings || !s->stamp[0]) {
        al_surface_release(s);
        return sr_err_set(err, SR_E_NOMEM, "cannot align: out of memory for the search grid");
    }
    memset(s->brick_slot, 0xff, nbrick * sizeof *s->brick_slot);
    for (size_t i = 0; i < s->count; i++) {
        int a[3], b[3];
        tri_cells(s, i, a, b);
        for (int z = a[2] >> 2; z <= b[2] >> 2; z++)
            for (int y = a[1] >> 2; y <= b[1] >> 2; y++)
                for (int x = a[0] >> 2; x <= b[0] >> 2; x++)
                    s->brick_slot[(size_t)x + (size_t)s->bdim[0] *
                                                  ((size_t)y + (size_t)s->bdim[1] * z)] = 0;
    }
    size_t slots = 0;
    for (size_t bi = 0; bi < nbrick; bi++)
        if (s->brick_slot[bi] != UINT32_MAX)
            s->brick_slot[bi] = (uint32_t)slots++;
    size_t ncell = slots * 64;
    s->cell_start = calloc(ncell + 1, sizeof *s->cell_start);
    if (!s->cell_start) {
        al_surface_release(s);
        return sr_err_set(err, SR_E_NOMEM, "cannot align: out of memory for the search grid");
    }
    for (size_t i = 0; i < s->count; i++)
        file_triangle(s, i, 0, NULL);
    uint64_t total = 0;
    for (size_t c = 0; c < ncell; c++) {
        total += s->cell_start[c + 1];
        if (total > UINT32_MAX) {
            al_surface_release(s);
            return sr_err_set(err, SR_E_NOMEM, "cannot align: search grid too large");
        }
        s->cell_start[c + 1] = (uint32_t)total;
    }
    s->cell_items = malloc((total ? total : 1) * sizeof *s->cell_items);
    if (!s->cell_items) {
        al_surface_release(s);
        return sr_err_set(err, SR_E_NOMEM, "cannot align: out of memory for the search grid");
    }
    /* fill each cell from its end, triangles in descending order so each cell lists them
     * ascending; cell_start[c + 1] (c's end) then holds c's start: shift it into place
     * (no second offset array) */
    for (size_t i = s->count; i-- > 0;)
        file_triangle(s, i, 1, s->cell_start + 1);
    memmove(s->cell_start, s->cell_start + 1, ncell * sizeof *s->cell_start);
    s->cell_start[ncell] = (uint32_t)total;
    distance_transform(s);
    return SR_OK;
}

/* The distance along axis a from v to the cells of index i on that axis (0 inside). */
static inline double axis_gap(const al_surface *s, int a, int i, double v)
{
    double lo = s->origin[a] + i * s->cell, hi = lo + s->cell;
    return v < lo ? lo - v : (v > hi ? v - hi : 0);
}

static void scan_cell(const al_surface *s, uint32_t *stamp, uint32_t id, int x, int y, int z,
                      const double p[3], double *best2, size_t *best)
{
    size_t cidx = cell_index(s, x, y, z);
    if (cidx == SIZE_MAX || s->cell_start[cidx + 1] == s->cell_start[cidx])
        return;
    /* the cell's box is already farther than the best triangle: nothing to gain */
    int idx[3] = {x, y, z};
    double box2 = 0;
    for (int k = 0; k < 3; k++) {
        double lo = s->origin[k] + idx[k] * s->cell, hi = lo + s->cell;
        double e = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0);
        box2 += e * e;
    }
    if (box2 >= *best2)
        return;
    for (uint32_t j = s->cell_start[cidx]; j < s->cell_start[cidx + 1]; j++) {
        uint32_t i = s->cell_items[j];
        if (stamp[i] == id)
            continue;
        stamp[i] = id;
        /* the distance to the triangle's plane bounds the distance to the triangle; the
         * float normal is off by < 1.1e-7 of |p - a|: take that off the bound, so no
         * triangle the exact normal would keep is skipped */
        const double *a = vtx(s, i, 0);
        const float *n = s->nrm + 3 * (size_t)i;
        double d0 = p[0] - a[0], d1 = p[1] - a[1], d2a = p[2] - a[2];
        double hp = fabs(n[0] * d0 + n[1] * d1 + n[2] * d2a) -
                    2e-7 * (fabs(d0) + fabs(d1) + fabs(d2a));
        if (hp > 0 && hp * hp >= *best2)
            continue;
        double q[3];
        sr_tri_closest_point(p, vtx(s, i, 0), vtx(s, i, 1), vtx(s, i, 2), q);
        double d2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                    (q[2] - p[2]) * (q[2] - p[2]);
        if (d2 < *best2) {
            *best2 = d2;
            *best = i;
        }
    }
}

sr_status al_surface_threads(al_surface *s, int threads)
{
    int n = threads > 0 ? threads : omp_get_max_threads();
    n = n < 1 ? 1 : (n > AL_THREADS_MAX ? AL_THREADS_MAX : n);
    for (int t = 1; t < n; t++)
        if (!s->stamp[t]) {
            s->stamp[t] = calloc(s->count ? s->count : 1, sizeof *s->stamp[t]);
            if (!s->stamp[t])
                return SR_E_NOMEM;
            s->stamp_id[t] = 0;
        }
    s->threads = n;
    return SR_OK;
}

bool al_surface_closest(al_surface *s, const double p[3], double max_dist, double q[3],
                        double n[3], double *dist)
{
    /* this thread's stamps (a surface serving one thread may be another's: identify.c
     * fits each candidate's own surface in a thread of its loop) */
    int t = s->threads > 1 ? omp_get_thread_num() : 0;
    uint32_t *stamp = s->stamp[t];
    if (++s->stamp_id[t] == 0) { /* wrapped: reset the stamps */
        memset(stamp, 0, s->count * sizeof *stamp);
        s->stamp_id[t] = 1;
    }
    uint32_t id = s->stamp_id[t];
    /* distance from p to the grid box: nothing is closer */
    double out2 = 0;
    for (int k = 0; k < 3; k++) {
        double lo = s->origin[k], hi = s->origin[k] + s->dim[k] * s->cell;
        double e = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0);
        out2 += e * e;
    }
    if (out2 > max_dist * max_dist)
        return false;
    int c0[3];
    cell_of(s, p, c0);
    /* p clamped into the grid box: distances to cells are bounded from there */
    double pc[3];
    for (int k = 0; k < 3; k++) {
        double lo = s->origin[k], hi = s->origin[k] + s->dim[k] * s->cell;
        pc[k] = p[k] < lo ? lo : (p[k] > hi ? hi : p[k]);
    }
    double best2 = max_dist * max_dist;
    size_t best = SIZE_MAX;
    int kmax = s->dim[0] + s->dim[1] + s->dim[2];
    /* shells closer than the nearest occupied cell are empty: skip them, or give up
     * when that cell is out of reach: it is >= (k0 - 1) cells from pc, and for p
     * outside the grid box |p - x|^2 >= |pc - x|^2 + |p - pc|^2 for any x in the box */
    /* the nearest brick holding anything is D bricks away: the nearest cell is at least
     * 4 (D - 1) + 1 cells away */
    size_t b0 = (size_t)(c0[0] >> 2) +
                (size_t)s->bdim[0] * ((size_t)(c0[1] >> 2) + (size_t)s->bdim[1] * (size_t)(c0[2] >> 2));
    int D = s->brick_rings[b0];
    int k0 = D == 0 ? 0 : 4 * (D - 1) + 1;
    double gap = (k0 - 1) * s->cell; /* 255 means "at least 255": still a bound */
    if (k0 >= 2 && out2 + gap * gap > max_dist * max_dist)
        return false;
    for (int k = k0; k <= kmax; k++) {
        int zlo = c0[2] - k, zhi = c0[2] + k;
        for (int z = zlo < 0 ? 0 : zlo; z <= zhi && z < s->dim[2]; z++) {
            /* a slab of cells, then a row, farther than the best triangle holds nothing
             * scan_cell would look at (its box test is the sum of these terms) */
            double ez = axis_gap(s, 2, z, p[2]);
            if (ez * ez >= best2)
                continue;
            int ylo = c0[1] - k, yhi = c0[1] + k;
            bool zface = (z == zlo || z == zhi);
            for (int y = ylo < 0 ? 0 : ylo; y <= yhi && y < s->dim[1]; y++) {
                double ey = axis_gap(s, 1, y, p[1]);
                if (ez * ez + ey * ey >= best2)
                    continue;
                bool face = zface || y == ylo || y == yhi;
                if (face) {
                    int xlo = c0[0] - k, xhi = c0[0] + k;
                    for (int x = xlo < 0 ? 0 : xlo; x <= xhi && x < s->dim[0]; x++)
                        scan_cell(s, stamp, id, x, y, z, p, &best2, &best);
                } else {
                    int x = c0[0] - k;
                    if (x >= 0)
                        scan_cell(s, stamp, id, x, y, z, p, &best2, &best);
                    x = c0[0] + k;
                    if (k > 0 && x < s->dim[0])
                        scan_cell(s, stamp, id, x, y, z, p, &best2, &best);
                }
            }
        }
        /* every cell not yet visited lies outside the block of (2k+1)^3 cells around
         * c0: bound the distance from p to it by pc's distance to the block's faces
         * (faces on the grid boundary have nothing beyond them) */
        double reach = INFINITY;
        for (int a = 0; a < 3; a++) {
            if (c0[a] - k > 0) {
                double e = pc[a] - (s->origin[a] + (c0[a] - k) * s->cell);
                reach = e < reach ? e : reach;
            }
            if (c0[a] + k < s->dim[a] - 1) {
                double e = s->origin[a] + (c0[a] + k + 1) * s->cell - pc[a];
                reach = e < reach ? e : reach;
            }
        }
        if (best != SIZE_MAX && best2 <= reach * reach)
            break;
        if (reach >= max_dist || reach == INFINITY)
            break;
    }
    if (best == SIZE_MAX)
        return false;
    sr_tri_closest_point(p, vtx(s, best, 0), vtx(s, best, 1), vtx(s, best, 2), q);
    al_surface_normal(s, best, n, NULL);
    *dist = sqrt(best2);
    return true;
}

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double uniform01(uint64_t *state)
{
    return (double)(splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

void al_samples_release(al_samples *smp)
{
    if (!smp)
        return;
    free(smp->p);
    free(smp->n);
    memset(smp, 0, sizeof *smp);
}

sr_status al_samples_make(const al_surface *s, size_t count, uint64_t seed, al_samples *out)
{
    al_samples r = {0};
    r.p = malloc((count ? count : 1) * 3 * sizeof *r.p);
    r.n = malloc((count ? count : 1) * 3 * sizeof *r.n);
    if (!r.p || !r.n) {
        free(r.p);
        free(r.n);
        return SR_E_NOMEM;
    }
    r.count = count;
    uint64_t st = seed;
    double step = s->total_area / (double)count, acc = 0;
    size_t i = 0;
    double n[3], area;
    al_surface_normal(s, 0, n, &area);
    for (size_t j = 0; j < count; j++) {
        double u = (j + uniform01(&st)) * step;
        while (i + 1 < s->count && acc + area < u) {
            acc += area;
            i++;
            al_surface_normal(s, i, n, &area);
        }
        double r1 = sqrt(uniform01(&st)), r2 = uniform01(&st);
        double wa = 1 - r1, wb = r1 * (1 - r2), wc = r1 * r2;
        const double *a = vtx(s, i, 0), *b = vtx(s, i, 1), *c = vtx(s, i, 2);
        for (int k = 0; k < 3; k++) {
            r.p[3 * j + k] = wa * a[k] + wb * b[k] + wc * c[k];
            r.n[3 * j + k] = n[k];
        }
    }
    *out = r;
    return SR_OK;
}
