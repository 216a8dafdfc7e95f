/*
 * nominal.c: the nominal model's second opinion on a reconstruction (see nominal.h):
 * registration of the intact mesh to the scan, the exact difference registered intact
 * − scan, its pieces sorted from the slivers, the pieces given to the symmetry
 * sections, the per-section figures and the check that the nominal fits the scan.
 * The registration's start is nominal_start.c's; the cell measure that stands in for
 * the difference on a scan crossing itself is nominal_cells.c's (nominal_int.h).
 *
 * Slivers: two surfaces that are the same design surface tessellated differently (a
 * cylinder's facets in the CAD export and in the scan), or a noisy scan over the
 * nominal, cross each other all over, and the difference keeps the thin lenses
 * between them. A lens is at most as thick as the gap between the surfaces, which is
 * what the registration measures as its RMS distance; a piece of real damage is as
 * thick as the damage is deep. So a piece whose mean thickness 2 V / A (a slab of
 * thickness t has V = A t / 2) is under three times the registration's RMS (and under
 * 0.05 % of the part's size, the scale of an exact copy's rounding) is a sliver.
 */
#include "nominal_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bridge/boolean.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sr_nominal_result_release(sr_nominal_result *r)
{
    if (!r)
        return;
    sr_mesh_release(&r->registered);
    sr_mesh_release(&r->missing);
    for (size_t i = 0; i < r->piece_count; i++)
        sr_mesh_release(&r->pieces[i].mesh);
    free(r->pieces);
    free(r->sections);
    memset(r, 0, sizeof *r);
}

typedef struct edge_key {
    uint32_t a, b; /* a < b */
    uint32_t tri;
} edge_key;

static int by_edge(const void *x, const void *y)
{
    const edge_key *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    return 0;
}

static uint32_t find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* The piece of every triangle: triangles joined through shared edges (not vertices:
 * the slivers between two crossing surfaces touch each other and the damage only at
 * points). shell_of[t] in 0..*count-1, numbered in the order of their first triangle. */
static sr_status edge_pieces(const sr_mesh *m, uint32_t *shell_of, size_t *count)
{
    size_t nt = m->tri_count, n = 0;
    edge_key *e = malloc(3 * nt * sizeof *e);
    uint32_t *parent = malloc(nt * sizeof *parent);
    if (!e || !parent) {
        free(e);
        free(parent);
        return SR_E_NOMEM;
    }
    for (size_t t = 0; t < nt; t++) {
        parent[t] = (uint32_t)t;
        for (int k = 0; k < 3; k++) {
            uint32_t u = m->tri[3 * t + k], v = m->tri[3 * t + (k + 1) % 3];
            e[3 * t + k] = (edge_key){u < v ? u : v, u < v ? v : u, (uint32_t)t};
        }
    }
    qsort(e, 3 * nt, sizeof *e, by_edge);
    for (size_t i = 1; i < 3 * nt; i++)
        if (e[i].a == e[i - 1].a && e[i].b == e[i - 1].b) {
            uint32_t x = find(parent, e[i].tri), y = find(parent, e[i - 1].tri);
            if (x != y)
                parent[x > y ? x : y] = x > y ? y : x;
        }
    for (size_t t = 0; t < nt; t++)
        shell_of[t] = UINT32_MAX;
    for (size_t t = 0; t < nt; t++) {
        uint32_t r = find(parent, (uint32_t)t);
        if (shell_of[r] == UINT32_MAX)
            shell_of[r] = (uint32_t)n++;
        shell_of[t] = shell_of[r];
    }
    free(e);
    free(parent);
    *count = n;
    return SR_OK;
}

/* *out = the triangles of `m` whose shell is `label` (vertices renumbered). */
static sr_status extract_shell(const sr_mesh *m, const uint32_t *shell_of, uint32_t label,
                               size_t tris, uint32_t *map, sr_mesh *out)
{
    size_t nv = 0;
    for (size_t v = 0; v < m->vertex_count; v++)
        map[v] = UINT32_MAX;
    for (size_t t = 0; t < m->tri_count; t++)
        if (shell_of[t] == label)
            for (int k = 0; k < 3; k++)
                if (map[m->tri[3 * t + k]] == UINT32_MAX)
                    map[m->tri[3 * t + k]] = (uint32_t)nv++;
    sr_mesh p;
    sr_mesh_init(&p);
    if (sr_mesh_alloc(&p, nv, tris) != SR_OK)
        return SR_E_NOMEM;
    for (size_t v = 0; v < m->vertex_count; v++)
        if (map[v] != UINT32_MAX)
            memcpy(p.xyz + 3 * (size_t)map[v], m->xyz + 3 * v, 3 * sizeof(double));
    size_t w = 0;
    for (size_t t = 0; t < m->tri_count; t++)
        if (shell_of[t] == label) {
            for (int k = 0; k < 3; k++)
                p.tri[3 * w + k] = map[m->tri[3 * t + k]];
            w++;
        }
    *out = p;
    return SR_OK;
}

#define DEV_TRIS 20000 /* the patch's triangles the deviation is measured at, at most */

/* *out = m without the vertices no triangle uses (a sample of its triangles when it
 * has more than DEV_TRIS). */
static sr_status compact(const sr_mesh *m, sr_mesh *out, sr_err *err)
{
    /* at most DEV_TRIS triangles, evenly strided: the deviation of a noisy scan's patch
     * (10^5 triangles) at all of them takes seconds, at the sample a tenth of that */
    size_t stride = (m->tri_count + DEV_TRIS - 1) / DEV_TRIS, kept = 0;
    uint32_t *zero = calloc(m->tri_count + 1, sizeof *zero);
    uint32_t *map = malloc((m->vertex_count + 1) * sizeof *map);
    for (size_t t = 0; zero && t < m->tri_count; t++) {
        zero[t] = stride > 1 && t % stride != 0;
        kept += zero[t] == 0;
    }
    sr_status st = zero && map ? extract_shell(m, zero, 0, kept, map, out) : SR_E_NOMEM;
    free(zero);
    free(map);
    return st == SR_OK ? st : sr_err_set(err, st, "out of memory comparing a patch");
}

static int by_volume_desc(const void *a, const void *b)
{
    double va = ((const sr_nominal_piece *)a)->volume_mm3;
    double vb = ((const sr_nominal_piece *)b)->volume_mm3;
    return va < vb ? 1 : va > vb ? -1 : 0;
}

/* The pieces of `raw` (the difference) thicker than r->sliver_mm and at least
 * min_vol, into r->pieces, largest first; the rest counted as slivers. */
static sr_status split_pieces(const sr_mesh *raw, double min_vol, sr_nominal_result *r, sr_err *err)
{
    size_t nt = raw->tri_count, n = 0;
    if (nt == 0)
        return SR_OK;
    uint32_t *shell_of = malloc(nt * sizeof *shell_of);
    uint32_t *map = malloc((raw->vertex_count + 1) * sizeof *map);
    size_t *tris = NULL;
    sr_status st = shell_of && map ? SR_OK : SR_E_NOMEM;
    if (st == SR_OK)
        st = edge_pieces(raw, shell_of, &n);
    if (st == SR_OK && n > 0) {
        tris = calloc(n, sizeof *tris);
        r->pieces = calloc(n, sizeof *r->pieces);
        if (!tris || !r->pieces)
            st = SR_E_NOMEM;
    }
    for (size_t t = 0; st == SR_OK && t < nt; t++)
        tris[shell_of[t]]++;
    for (uint32_t s = 0; st == SR_OK && s < n; s++) {
        sr_nominal_piece *p = &r->pieces[r->piece_count];
        st = extract_shell(raw, shell_of, s, tris[s], map, &p->mesh);
        if (st != SR_OK)
            break;
        p->volume_mm3 = sr_mesh_volume(&p->mesh);
        p->area_mm2 = sr_mesh_area(&p->mesh);
        p->thickness_mm = p->area_mm2 > 0 ? 2.0 * p->volume_mm3 / p->area_mm2 : 0;
        p->section = -1;
        if (p->thickness_mm < r->sliver_mm || p->volume_mm3 < min_vol) {
            r->slivers++;
            r->sliver_mm3 += fabs(p->volume_mm3);
            sr_mesh_release(&p->mesh);
            continue;
        }
        r->piece_count++;
    }
    free(shell_of);
    free(map);
    free(tris);
    if (st == SR_E_NOMEM)
        return sr_err_set(err, st, "out of memory splitting the nominal's missing material");
    if (st == SR_OK)
        qsort(r->pieces, r->piece_count, sizeof *r->pieces, by_volume_desc);
    return st;
}

/* Box of the vertices the triangles use (a boolean's result keeps unused ones). */
static void used_box(const sr_mesh *m, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < 3 * m->tri_count; i++)
        for (int k = 0; k < 3; k++) {
            double x = m->xyz[3 * (size_t)m->tri[i] + k];
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
}

/* Distance from p to the box [b[0..3), b[3..6)] (0 inside). */
static double box_distance(const double p[3], const double *b)
{
    double d = 0;
    for (int k = 0; k < 3; k++) {
        double e = fmax(fmax(b[k] - p[k], p[k] - b[3 + k]), 0);
        d += e * e;
    }
    return sqrt(d);
}

size_t nominal_nearest_section(const double p[3], const double *boxes, size_t count)
{
    size_t best = count;
    double bd = INFINITY;
    for (size_t s = 0; s < count; s++) {
        double d = box_distance(p, boxes + 7 * s);
        if (d <= boxes[7 * s + 6] && d < bd) {
            bd = d;
            best = s;
        }
    }
    return best;
}

/* p's section (the largest share; -1 = the share near no section, share[count]), that
 * share, and p's centroid: the no-section share's (acc: its volume-weighted sum of
 * points) when that is at least min_vol, else the piece's (all over vall), else o. */
static void settle_piece(sr_nominal_piece *p, const double *share, size_t count, double min_vol,
                         const double acc[3], const double all[3], double vall, const double o[3])
{
    p->outside_mm3 = share[count];
    p->section = -1;
    double most = share[count];
    for (size_t s = 0; s < count; s++)
        if (share[s] > most) {
            most = share[s];
            p->section = (long)s;
        }
    for (int k = 0; k < 3; k++)
        p->centroid[k] = p->outside_mm3 >= min_vol ? acc[k] / p->outside_mm3
                         : vall > 0                ? all[k] / vall
                                                   : o[k];
}

/* Splits piece p's volume among the sections (boxes: count x {lo, hi, reach}): each
 * triangle's tetrahedron to the piece's centre goes to the section whose patch box is
 * nearest its centroid, within the box's own diagonal, else to no section. By the
 * divergence theorem the shares add up to the piece's volume, and a share is the
 * volume of the piece's part near that section up to the thin skin where the parts
 * meet (a skin's two faces cancel). share: count + 1 (the last: no section). The
 * centroid is the no-section share's when that is at least min_vol, else the piece's. */
static void share_piece(sr_nominal_piece *p, const double *boxes, size_t count, double min_vol,
                        double *share)
{
    const sr_mesh *m = &p->mesh;
    double lo[3], hi[3], o[3], acc[3] = {0, 0, 0}, all[3] = {0, 0, 0}, vall = 0;
    sr_mesh_bbox(m, lo, hi);
    for (int k = 0; k < 3; k++)
        o[k] = 0.5 * (lo[k] + hi[k]);
    memset(share, 0, (count + 1) * sizeof *share);
    for (size_t t = 0; t < m->tri_count; t++) {
        const double *pa = m->xyz + 3 * (size_t)m->tri[3 * t],
                     *pb = m->xyz + 3 * (size_t)m->tri[3 * t + 1],
                     *pc = m->xyz + 3 * (size_t)m->tri[3 * t + 2];
        double a[3], b[3], c[3], cen[3];
        for (int k = 0; k < 3; k++) {
            a[k] = pa[k] - o[k];
            b[k] = pb[k] - o[k];
            c[k] = pc[k] - o[k];
            cen[k] = (pa[k] + pb[k] + pc[k]) / 3;
        }
        double v = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                    a[2] * (b[0] * c[1] - b[1] * c[0])) /
                   6.0;
        size_t best = nominal_nearest_section(cen, boxes, count);
        share[best] += v;
        for (int k = 0; k < 3; k++) { /* the tetrahedron's centroid, weighted */
            double g = o[k] + (a[k] + b[k] + c[k]) / 4;
            all[k] += v * g;
            if (best == count)
                acc[k] += v * g;
        }
        vall += v;
    }
    settle_piece(p, share, count, min_vol, acc, all, vall, o);
}

/* The sections' patch boxes: count x {lo[3], hi[3], reach (the diagonal)}; a section
 * without a patch gets an empty box that nothing is near. NULL when out of memory. */
static double *section_boxes(const sr_section *secs, size_t count)
{
    double *boxes = malloc((7 * count + 1) * sizeof *boxes);
    for (size_t s = 0; boxes && s < count; s++) {
        double *b = boxes + 7 * s;
        if (secs[s].patch.tri_count == 0) {
            b[0] = b[1] = b[2] = INFINITY; /* no patch: nothing is near it */
            b[3] = b[4] = b[5] = -INFINITY;
            b[6] = -1;
            continue;
        }
        used_box(&secs[s].patch, b, b + 3);
        b[6] = sqrt((b[3] - b[0]) * (b[3] - b[0]) + (b[4] - b[1]) * (b[4] - b[1]) +
                    (b[5] - b[2]) * (b[5] - b[2]));
    }
    return boxes;
}

/* Appends to *out the triangles of m whose box meets b grown by margin. */
static sr_status append_near(const sr_mesh *m, const double *b, double margin, sr_mesh *out)
{
    uint32_t *in = malloc((m->tri_count + 1) * sizeof *in);
    uint32_t *map = malloc((m->vertex_count + 1) * sizeof *map);
    size_t n = 0;
    for (size_t t = 0; in && t < m->tri_count; t++) {
        in[t] = 0;
        for (int k = 0; k < 3 && !in[t]; k++) {
            double lo = INFINITY, hi = -INFINITY;
            for (int v = 0; v < 3; v++) {
                double x = m->xyz[3 * (size_t)m->tri[3 * t + v] + k];
                lo = fmin(lo, x);
                hi = fmax(hi, x);
            }
            in[t] = hi < b[k] - margin || lo > b[3 + k] + margin;
        }
        in[t] = !in[t];
        n += in[t];
    }
    sr_mesh part;
    sr_mesh_init(&part);
    sr_status st = in && map ? SR_OK : SR_E_NOMEM;
    if (st == SR_OK && n > 0)
        st = extract_shell(m, in, 1, n, map, &part);
    if (st == SR_OK && n > 0)
        st = sr_mesh_append(out, &part);
    sr_mesh_release(&part);
    free(in);
    free(map);
    return st;
}

/* Fills the sections' figures from the pieces' shares: share (count + 1 per piece, in
 * r->pieces' order) when given (the cell measure), else each piece split by its
 * surface. The deviation of a section's patch is measured against the surface of its
 * pieces, or, with near (the cell measure: no piece meshes), against the registered
 * intact and the scan near the patch (a piece's surface is made of the two). */
static sr_status assign_sections(const sr_section *secs, size_t count, double min_vol,
                                 const double *boxes, const double *given, const sr_mesh *near,
                                 double margin, sr_nominal_result *r, sr_err *err)
{
    double *share = malloc((count + 1) * r->piece_count * sizeof *share + sizeof *share);
    if (!share)
        return sr_err_set(err, SR_E_NOMEM, "out of memory comparing with the nominal");
    for (size_t i = 0; i < r->piece_count; i++) {
        double *sh = share + (count + 1) * i;
        if (given)
            memcpy(sh, given + (count + 1) * i, (count + 1) * sizeof *sh);
        else
            share_piece(&r->pieces[i], boxes, count, min_vol, sh);
        if (r->pieces[i].outside_mm3 >= min_vol) {
            r->only_nominal++;
            r->only_nominal_mm3 += r->pieces[i].outside_mm3;
        }
    }
    for (size_t s = 0; s < count; s++) {
        sr_nominal_section *ns = &r->sections[s];
        ns->symmetry_mm3 = secs[s].volume_mm3;
        ns->dev_mean_mm = ns->dev_max_mm = -1;
        sr_mesh mine;
        sr_mesh_init(&mine);
        sr_status st = SR_OK;
        for (size_t i = 0; i < r->piece_count && st == SR_OK; i++) {
            double v = share[(count + 1) * i + s];
            ns->nominal_mm3 += v;
            if (v >= min_vol) {
                ns->pieces++;
                if (!near)
                    st = sr_mesh_append(&mine, &r->pieces[i].mesh);
            }
        }
        for (int k = 0; near && k < 2 && st == SR_OK && ns->pieces > 0; k++)
            st = append_near(&near[k], boxes + 7 * s, margin, &mine);
        ns->diff_mm3 = ns->nominal_mm3 - ns->symmetry_mm3;
        double base = ns->nominal_mm3 > 0 ? ns->nominal_mm3 : ns->symmetry_mm3;
        ns->diff_pct = base > 0 ? 100.0 * ns->diff_mm3 / base : 0;
        if (ns->pieces == 0)
            r->only_symmetry++;
        sr_mesh patch; /* without the vertices no triangle uses: they are no surface */
        sr_mesh_init(&patch);
        if (st == SR_OK && ns->pieces > 0 && secs[s].patch.tri_count > 0)
            st = compact(&secs[s].patch, &patch, err);
        if (st == SR_OK && patch.tri_count > 0 && mine.tri_count > 0) {
            sr_deviation ab;
            st = sr_mesh_deviation(&patch, &mine, &ab, err);
            if (st == SR_OK) {
                ns->dev_mean_mm = ab.mean_mm;
                ns->dev_max_mm = ab.max_mm;
            }
        }
        sr_mesh_release(&mine);
        sr_mesh_release(&patch);
        if (st != SR_OK) {
            free(share);
            return st == SR_E_NOMEM
                       ? sr_err_set(err, st, "out of memory comparing section %zu", s + 1)
                       : st;
        }
    }
    free(share);
    return SR_OK;
}

static int by_cell_volume_desc(const void *a, const void *b)
{
    double va = ((const nominal_cell_piece *)a)->volume_mm3;
    double vb = ((const nominal_cell_piece *)b)->volume_mm3;
    return va < vb ? 1 : va > vb ? -1 : 0;
}

/* r->pieces from the cell measure's pieces (no meshes), those under min_vol counted as
 * slivers; *shares: their shares, count + 1 each, in r->pieces' order. */
static sr_status cell_pieces(nominal_cell_pieces *cp, size_t count, double min_vol,
                             sr_nominal_result *r, double **shares, sr_err *err)
{
    if (cp->count) /* pieces is NULL without any */
        qsort(cp->pieces, cp->count, sizeof *cp->pieces, by_cell_volume_desc);
    r->pieces = calloc(cp->count + 1, sizeof *r->pieces);
    *shares = malloc((cp->count + 1) * (count + 1) * sizeof **shares);
    if (!r->pieces || !*shares)
        return sr_err_set(err, SR_E_NOMEM, "out of memory comparing with the nominal");
    for (size_t i = 0; i < cp->count; i++) {
        const nominal_cell_piece *c = &cp->pieces[i];
        if (c->volume_mm3 < min_vol) {
            r->slivers++;
            r->sliver_mm3 += fabs(c->volume_mm3);
            continue;
        }
        sr_nominal_piece *p = &r->pieces[r->piece_count];
        sr_mesh_init(&p->mesh);
        p->volume_mm3 = c->volume_mm3;
        memcpy(*shares + (count + 1) * r->piece_count, c->share, (count + 1) * sizeof **shares);
        settle_piece(p, c->share, count, min_vol, c->outside_centroid, c->centroid, c->volume_mm3,
                     c->centroid);
        r->piece_count++;
    }
    return SR_OK;
}

/* r->poor and r->note from the registration's coverage and the scan's extra material. */
static void judge(sr_nominal_result *r)
{
    if (r->reg.coverage < SR_NOMINAL_MIN_COVERAGE)
        snprintf(r->note, sizeof r->note,
                 "the nominal model does not fit this scan: only %.1f %% of it lies within "
                 "%.3f mm of the scan (a scan of its part covers at least %.0f %%)",
                 100.0 * r->reg.coverage, r->reg.tol_mm, 100.0 * SR_NOMINAL_MIN_COVERAGE);
    else if (r->extra_mm3 > r->extra_limit_mm3)
        snprintf(r->note, sizeof r->note,
                 "the nominal model does not fit this scan: the scan has %.1f mm³ of material "
                 "outside it (more than its surface x %.3f mm, %.1f mm³)",
                 r->extra_mm3, r->reg.tol_mm, r->extra_limit_mm3);
    r->poor = r->note[0] != 0;
}

sr_status sr_nominal_compare(const sr_mesh *scan, const sr_mesh *intact, const sr_section *secs,
                             size_t count, const sr_nominal_opts *opts, sr_nominal_result *out,
                             sr_err *err)
{
    double t0 = now_s();
    sr_nominal_opts o = {0};
    if (opts)
        o = *opts;
    double min_vol = o.min_volume_mm3 > 0 ? o.min_volume_mm3 : 1.0;
    sr_nominal_result r;
    memset(&r, 0, sizeof r);
    sr_mesh raw;
    sr_mesh_init(&raw);
    nominal_cell_pieces cp;
    memset(&cp, 0, sizeof cp);
    double *boxes = NULL, *shares = NULL;
    sr_err why;
    sr_err_clear(&why);
    sr_status st = nominal_register(scan, intact, &o, &r.reg, &r.full_search, err);
    if (st == SR_OK)
        st = sr_mesh_copy(&r.registered, intact);
    if (st == SR_OK)
        sr_mesh_transform(&r.registered, r.reg.mat);
    if (st == SR_OK && !o.exact_pieces) { /* the cells need closed surfaces */
        if (!sr_mesh_is_closed(scan))
            st = sr_err_set(err, SR_E_INVALID, "'the scan' is not closed");
        else if (!sr_mesh_is_closed(intact))
            st = sr_err_set(err, SR_E_INVALID, "'the nominal' is not closed");
        r.by_cells = 1;
    } else if (st == SR_OK) {
        st = sr_boolean_compute(SR_BOOLEAN_DIFFERENCE, &r.registered, "the registered nominal",
                                scan, "the scan", &raw, &why);
        /* a closed scan that crosses itself: measured by cells (nominal_cells.c) */
        if (st == SR_E_INVALID && sr_mesh_is_closed(scan) && sr_mesh_is_closed(&r.registered)) {
            r.by_cells = 1;
            snprintf(r.exact_note, sizeof r.exact_note, "%.199s", why.msg);
            st = SR_OK;
        } else if (st != SR_OK) {
            st = sr_err_set(err, st, "%s", why.msg);
        }
    }
    if (st == SR_OK && count > 0) {
        r.sections = calloc(count, sizeof *r.sections);
        if (!r.sections)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory comparing with the nominal");
        r.section_count = count;
    }
    if (st == SR_OK && !(boxes = section_boxes(secs, count)))
        st = sr_err_set(err, SR_E_NOMEM, "out of memory comparing with the nominal");
    if (st == SR_OK) {
        double lo[3], hi[3];
        sr_mesh_bbox(scan, lo, hi);
        double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        r.min_volume_mm3 = min_vol;
        r.sliver_mm = fmax(3.0 * r.reg.rms_mm, 5e-4 * diag);
        r.extra_limit_mm3 = sr_mesh_area(scan) * r.reg.tol_mm;
        if (r.by_cells) {
            st = nominal_cells(&r.registered, scan, boxes, count, r.sliver_mm, &cp, err);
            if (st == SR_OK)
                st = cell_pieces(&cp, count, min_vol, &r, &shares, err);
            r.extra_mm3 = cp.extra_mm3;
            r.cell_mm = cp.cell_mm;
        } else {
            r.extra_mm3 =
                fmax(0, sr_mesh_volume(scan) - sr_mesh_volume(intact) + sr_mesh_volume(&raw));
            st = split_pieces(&raw, min_vol, &r, err);
        }
    }
    for (size_t i = 0; st == SR_OK && i < r.piece_count; i++) {
        r.nominal_mm3 += r.pieces[i].volume_mm3;
        st = sr_mesh_append(&r.missing, &r.pieces[i].mesh);
    }
    const sr_mesh near[2] = {r.registered, *scan};
    if (st == SR_OK)
        st = assign_sections(secs, count, min_vol, boxes, shares, r.by_cells ? near : NULL,
                             2 * r.cell_mm, &r, err);
    sr_mesh_release(&raw);
    nominal_cell_pieces_release(&cp);
    free(boxes);
    free(shares);
    if (st != SR_OK) {
        sr_nominal_result_release(&r);
        return st;
    }
    for (size_t s = 0; s < count; s++)
        r.symmetry_mm3 += secs[s].volume_mm3;
    r.diff_mm3 = r.nominal_mm3 - r.symmetry_mm3;
    double base = r.nominal_mm3 > 0 ? r.nominal_mm3 : r.symmetry_mm3;
    r.diff_pct = base > 0 ? 100.0 * r.diff_mm3 / base : 0;
    judge(&r);
    r.seconds = now_s() - t0;
    *out = r;
    return SR_OK;
}
