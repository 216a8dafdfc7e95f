/*
 * region_sections.c: cross-section reconstruction core (region_sections.h): contour
 * layers, symmetry vote, grouping of missing pieces into sections across layers,
 * section figures and patches, restored outline on the sector grid.
 */
#include "robust/region_sections.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/polygon.h"
#include "slice/contour_slice.h"
#include "robust/layer_flats.h"
#include "robust/restore_continuity.h"
#include "robust/restore_vote.h"
#include "robust/stack_mesh.h"

/* ---- pieces and their grouping ---- */

typedef struct piece {
    size_t layer;
    sr_poly2 region;
    double box[4];
    size_t parent;          /* union-find */
} piece;

static size_t find(piece *p, size_t i)
{
    while (p[i].parent != i) {
        p[i].parent = p[p[i].parent].parent;
        i = p[i].parent;
    }
    return i;
}

/* How far a section's patch reaches past its missing regions into the damaged part,
 * mm (so no fracture surface is left exposed between layer planes). */
static double patch_grow_mm(const sr_layer_grid *grid)
{
    return 3.0 * grid->dz + 0.1;
}

static int boxes_overlap(const double a[4], const double b[4])
{
    return a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3];
}

/* The smallest arc (degrees) holding every angle of the points: start in [0, 360). */
static void angular_range(const double *ang, size_t n, double *from, double *span)
{
    if (n == 0) {
        *from = 0;
        *span = 0;
        return;
    }
    double best_gap = -1, best_end = 0;
    for (size_t i = 0; i < n; i++) {
        double next = i + 1 < n ? ang[i + 1] : ang[0] + 360.0;
        if (next - ang[i] > best_gap) {
            best_gap = next - ang[i];
            best_end = next;
        }
    }
    *from = fmod(best_end, 360.0);
    *span = 360.0 - best_gap;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int cmp_section_volume(const void *a, const void *b)
{
    double x = ((const sr_section *)a)->volume_mm3, y = ((const sr_section *)b)->volume_mm3;
    return (x < y) - (x > y);
}

/* Builds one section from its pieces (indices idx[0..n), sorted by layer). */
/* What the patch fills in layer l: the missing region grown by `grow` mm and clipped to
 * the restored section, so it overlaps the damaged part. Between layer planes a
 * fracture that is not vertical leaves a wedge of its surface outside the layer's
 * missing region; growing the region into the damaged part covers it (for fractures
 * steeper than about atan(dz / 2 / grow)), and the union removes the overlap. */
typedef struct layer_data {
    const sr_poly2 *d, *r;      /* per layer: damaged and restored sections */
    const double *flat;         /* per layer: flat-face area at its planes, mm^2
                                 * (layer_flats.h) */
} layer_data;

/* The finest detail a patch's layer outline keeps, mm: the closing below fills slits
 * narrower than twice this, so the outline is only defined to it. */
#define OUTLINE_MM 0.005

static sr_status grown(const sr_poly2 *missing, const sr_poly2 *restored, double grow,
                       sr_poly2 *out, sr_err *err)
{
    sr_poly2 g = {0};
    sr_status st = sr_poly2_offset(missing, grow, 0, &g, err);
    if (st == SR_OK)
        st = sr_poly2_boolean(SR_POLY_INTERSECTION, &g, restored, &g, err);
    /* vertices that move the outline less than OUTLINE_MM go: runs of collinear points
     * and notches of the sector vote that each layer's walls and caps were cut at (the
     * lever's continuation patch 106 k -> 74 k triangles, its union 2.9 -> 1.3 s) */
    if (st == SR_OK && g.contour_count > 0)
        st = sr_poly2_clean(&g, OUTLINE_MM, &g, err);
    /* close by OUTLINE_MM, then pull in by 1e-4 mm more: slits and holes narrower than
     * 10 µm (where grown pieces meet edge to edge) are filled rather than opened into
     * 0.2 µm-thin voids inside the patch, and pieces touching at a single point (which
     * the 2D booleans may output) come apart, so no wall edge is shared by four faces */
    if (st == SR_OK && g.contour_count > 0)
        st = sr_poly2_offset(&g, OUTLINE_MM, 0, &g, err);
    if (st == SR_OK && g.contour_count > 0)
        st = sr_poly2_offset(&g, -OUTLINE_MM - 1e-4, 0, &g, err);
    if (st != SR_OK) {
        sr_poly2_release(&g);
        return st;
    }
    sr_poly2_release(out);
    *out = g;
    return SR_OK;
}

static sr_status build_section(piece *pc, const size_t *idx, size_t n, const layer_data *sd,
                               const sr_layer_grid *grid, sr_section *out, sr_err *err)
{
    const sr_poly2 *damaged = sd->d;
    size_t first = pc[idx[0]].layer, last = pc[idx[n - 1]].layer, L = last - first + 1;
    sr_poly2 *regions = calloc(L, sizeof *regions);
    double *z = malloc((L + 1) * sizeof *z);
    double *ang = NULL;
    size_t nang = 0;
    sr_status st = SR_OK;
    memset(out, 0, sizeof *out);
    if (!regions || !z) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory building a section");
        goto done;
    }
    for (size_t i = 0; i < n && st == SR_OK; i++) {
        const sr_poly2 *r = &pc[idx[i]].region;
        sr_poly2 *dst = &regions[pc[idx[i]].layer - first];
        for (size_t c = 0; c < r->contour_count && st == SR_OK; c++)
            st = sr_poly2_add_contour(dst, r->xy + 2 * r->start[c],
                                      r->start[c + 1] - r->start[c], err);
    }
    for (size_t l = 0; l <= L; l++)
        z[l] = grid->z_init + (double)(first + l) * grid->dz;
    size_t points = 0;
    for (size_t l = 0; l < L; l++)
        points += sr_poly2_point_count(&regions[l]);
    ang = malloc((points ? points : 1) * sizeof *ang);
    if (st == SR_OK && !ang)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory building a section");
    double depth_sum = 0;
    size_t depth_n = 0;
    for (size_t l = 0; l < L && st == SR_OK; l++) {
        const sr_poly2 *r = &regions[l];
        out->volume_mm3 += sr_poly2_area(r) * grid->dz;
        size_t np = sr_poly2_point_count(r);
        for (size_t i = 0; i < np; i++) {
            double x = r->xy[2 * i], y = r->xy[2 * i + 1];
            double d = sr_poly2_boundary_distance(&damaged[first + l], x, y);
            if (!isfinite(d))
                d = 0;
            if (d > out->depth_max_mm)
                out->depth_max_mm = d;
            if (d > 1e-3) {
                depth_sum += d;
                depth_n++;
            }
            double a = atan2(y, x) * 180.0 / M_PI;
            ang[nang++] = a < 0 ? a + 360.0 : (a >= 360.0 ? 0 : a);
        }
    }
    /* the patch: grown regions, one extra layer below and above where the grid goes on
     * (a fracture ending inside a layer's slab is covered too) */
    if (st == SR_OK) {
        size_t lo = first > 0 ? first - 1 : first;
        size_t hi = last + 1 < grid->layers ? last + 1 : last;
        size_t GL = hi - lo + 1;
        double grow = patch_grow_mm(grid);
        sr_poly2 *g = calloc(GL, sizeof *g);
        double *gz = malloc((GL + 1) * sizeof *gz);
        if (!g || !gz)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory building a section");
        for (size_t l = lo; l <= hi && st == SR_OK; l++) {
            size_t src = l < first ? first : (l > last ? last : l);
            st = grown(&regions[src - first], &sd->r[l], grow, &g[l - lo], err);
        }
        for (size_t l = 0; l <= GL && gz; l++)
            gz[l] = grid->z_init + (double)(lo + l) * grid->dz;
        /* outlines of neighbouring layers touching within a grid unit are pulled
         * apart (stack_mesh.h) */
        if (st == SR_OK)
            st = sr_stack_mesh_pulled_in(g, gz, GL, &out->patch, err);
        if (g)
            for (size_t l = 0; l < GL; l++)
                sr_poly2_release(&g[l]);
        free(g);
        free(gz);
    }
    if (st != SR_OK)
        goto done;
    out->layer_first = first;
    out->layer_last = last;
    out->z_min = z[0];
    out->z_max = z[L];
    out->cell_count = n;
    out->depth_mean_mm = depth_n ? depth_sum / (double)depth_n : 0;
    out->area_mm2 = 0;              /* the lost surface: the restored outline's length */
    for (size_t l = 0; l < L; l++) {
        const sr_poly2 *r = &regions[l];
        for (size_t c = 0; c < r->contour_count; c++)
            for (size_t i = r->start[c]; i < r->start[c + 1]; i++) {
                size_t j = i + 1 < r->start[c + 1] ? i + 1 : r->start[c];
                double mx = 0.5 * (r->xy[2 * i] + r->xy[2 * j]);
                double my = 0.5 * (r->xy[2 * i + 1] + r->xy[2 * j + 1]);
                if (sr_poly2_boundary_distance(&damaged[first + l], mx, my) > 1e-3)
                    out->area_mm2 += hypot(r->xy[2 * j] - r->xy[2 * i],
                                           r->xy[2 * j + 1] - r->xy[2 * i + 1]) * grid->dz;
            }
    }
    qsort(ang, nang, sizeof *ang, cmp_double);
    double from, span;
    angular_range(ang, nang, &from, &span);
    out->angle_min_deg = from;
    out->angle_max_deg = fmod(from + span, 360.0);
    double step = 360.0 / (double)grid->sectors;
    out->sector_first = (size_t)floor(from / step) % grid->sectors;
    out->sector_count = (size_t)ceil((from + span) / step) - (size_t)floor(from / step);
    if (out->sector_count == 0)
        out->sector_count = 1;
    if (out->sector_count > grid->sectors)
        out->sector_count = grid->sectors;
done:
    if (regions)
        for (size_t l = 0; l < L; l++)
            sr_poly2_release(&regions[l]);
    free(regions);
    free(z);
    free(ang);
    if (st != SR_OK)
        sr_mesh_release(&out->patch);
    return st;
}

static sr_status group_sections(sr_poly2 *missing, const layer_data *sd,
                                const sr_layer_grid *grid, const sr_region_opts *o,
                                sr_section **out, size_t *count, sr_err *err)
{
    size_t layers = grid->layers, np = 0, cap = 0;
    piece *pc = NULL;
    size_t *layer_start = calloc(layers + 1, sizeof *layer_start);
    sr_status st = layer_start ? SR_OK : SR_E_NOMEM;
    for (size_t l = 0; l < layers && st == SR_OK; l++) {
        layer_start[l] = np;
        sr_poly2 *parts = NULL;
        size_t n = 0;
        st = sr_poly2_components(&missing[l], &parts, &n, err);
        if (st != SR_OK)
            break;
        if (np + n > cap) {
            size_t nc = cap ? 2 * cap : 64;
            while (nc < np + n)
                nc *= 2;
            piece *g = realloc(pc, nc * sizeof *g);
            if (!g) {
                sr_poly2_components_release(parts, n);
                st = SR_E_NOMEM;
                break;
            }
            pc = g;
            cap = nc;
        }
        for (size_t i = 0; i < n; i++) {
            pc[np].layer = l;
            pc[np].region = parts[i];
            sr_poly2_bounds(&parts[i], pc[np].box);
            pc[np].parent = np;
            np++;
        }
        free(parts);            /* the regions moved into the pieces */
    }
    if (layer_start)
        layer_start[layers] = np;
    /* join overlapping pieces of consecutive layers */
    for (size_t l = 0; l + 1 < layers && st == SR_OK; l++) {
        for (size_t i = layer_start[l]; i < layer_start[l + 1] && st == SR_OK; i++) {
            for (size_t j = layer_start[l + 1]; j < layer_start[l + 2]; j++) {
                if (!boxes_overlap(pc[i].box, pc[j].box) || find(pc, i) == find(pc, j))
                    continue;
                sr_poly2 both = {0};
                st = sr_poly2_boolean(SR_POLY_INTERSECTION, &pc[i].region, &pc[j].region,
                                      &both, err);
                if (st != SR_OK)
                    break;
                if (sr_poly2_area(&both) > 1e-9)
                    pc[find(pc, i)].parent = find(pc, j);
                sr_poly2_release(&both);
            }
        }
    }
    /* gather pieces by root (pieces are in layer order, so each group is sorted) */
    size_t *order = NULL, *gstart = NULL, groups = 0;
    sr_section *sec = NULL;
    size_t ns = 0;
    if (st == SR_OK) {
        order = malloc((np ? np : 1) * sizeof *order);
        gstart = malloc((np + 1) * sizeof *gstart);
        sec = calloc(np ? np : 1, sizeof *sec);
        if (!order || !gstart || !sec)
            st = SR_E_NOMEM;
    }
    if (st == SR_OK) {
        size_t *root_group = malloc((np ? np : 1) * sizeof *root_group);
        size_t *fill = calloc(np + 1, sizeof *fill);
        if (!root_group || !fill) {
            st = SR_E_NOMEM;
        } else {
            for (size_t i = 0; i < np; i++)
                root_group[i] = SIZE_MAX;
            for (size_t i = 0; i < np; i++) {
                size_t r = find(pc, i);
                if (root_group[r] == SIZE_MAX)
                    root_group[r] = groups++;
                fill[root_group[r] + 1]++;
            }
            for (size_t g = 0; g < groups; g++)
                fill[g + 1] += fill[g];
            memcpy(gstart, fill, (groups + 1) * sizeof *gstart);
            for (size_t i = 0; i < np; i++)
                order[fill[root_group[find(pc, i)]]++] = i;
        }
        free(root_group);
        free(fill);
    }
    for (size_t g = 0; g < groups && st == SR_OK; g++) {
        const size_t *idx = order + gstart[g];
        size_t n = gstart[g + 1] - gstart[g];
        double vol = 0, depth = 0;
        for (size_t i = 0; i < n; i++)
            vol += sr_poly2_area(&pc[idx[i]].region) * grid->dz;
        if (vol < o->min_volume_mm3 || vol <= 0)
            continue;
        /* one layer, no larger than the flat faces its planes cut: a noisy face's ragged
         * cut, not a loss (layer_flats.h) */
        size_t l0 = pc[idx[0]].layer;
        if (pc[idx[n - 1]].layer == l0 && vol <= sd->flat[l0] * grid->dz)
            continue;
        if (o->want) {
            /* the pieces' boxes and layers, grown by what the patch grows (and its
             * extra layer below and above) */
            double grow = patch_grow_mm(grid) + grid->dz, box[6];
            box[0] = box[1] = HUGE_VAL;
            box[3] = box[4] = -HUGE_VAL;
            for (size_t i = 0; i < n; i++) {
                const double *b = pc[idx[i]].box;
                box[0] = fmin(box[0], b[0]), box[1] = fmin(box[1], b[1]);
                box[3] = fmax(box[3], b[2]), box[4] = fmax(box[4], b[3]);
            }
            box[2] = sr_layer_z(grid, l0);
            box[5] = sr_layer_z(grid, pc[idx[n - 1]].layer);
            for (int a = 0; a < 3; a++)
                box[a] -= grow, box[3 + a] += grow;
            if (!o->want(box, vol, o->want_ctx))
                continue;
        }
        st = build_section(pc, idx, n, sd, grid, &sec[ns], err);
        if (st != SR_OK)
            break;
        depth = sec[ns].depth_max_mm;
        if (depth < o->min_depth_mm) {
            sr_mesh_release(&sec[ns].patch);
            continue;
        }
        ns++;
    }
    for (size_t i = 0; i < np; i++)
        sr_poly2_release(&pc[i].region);
    free(pc);
    free(layer_start);
    free(order);
    free(gstart);
    if (st != SR_OK) {
        sr_sections_release(sec, ns);
        if (st == SR_E_NOMEM)
            sr_err_set(err, st, "out of memory grouping missing sections");
        return st;
    }
    qsort(sec, ns, sizeof *sec, cmp_section_volume);
    *out = sec;
    *count = ns;
    return SR_OK;
}

/* ---- restored outline on the sector grid ---- */

static sr_status outline_analysis(const sr_layer_grid *grid, const sr_poly2 *restored,
                                  const sr_region_opts *o, sr_analysis *out, sr_err *err)
{
    sr_layer_grid rg;
    sr_status st = sr_layer_grid_alloc(&rg, grid->layers, grid->sectors, grid->z_init, grid->dz);
    if (st != SR_OK)
        return sr_err_set(err, st, "out of memory for the restored outline");
    for (size_t l = 0; l < grid->layers; l++) {
        const sr_poly2 *r = &restored[l];
        for (size_t c = 0; c < r->contour_count; c++) {
            size_t a = r->start[c], b = r->start[c + 1];
            for (size_t i = a; i < b; i++)
                sr_layer_grid_add_segment(&rg, l, r->xy + 2 * i,
                                          r->xy + 2 * (i + 1 < b ? i + 1 : a));
        }
    }
    size_t cells = grid->layers * grid->sectors;
    sr_analysis an = {0};
    an.layers = grid->layers;
    an.sectors = grid->sectors;
    an.restored_r = malloc(cells * sizeof *an.restored_r);
    an.damaged = calloc(cells, 1);
    if (!an.restored_r || !an.damaged) {
        sr_layer_grid_release(&rg);
        sr_analysis_release(&an);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for the restored outline");
    }
    for (size_t c = 0; c < cells; c++) {
        an.restored_r[c] = fmax(rg.r[c], grid->r[c]);
        if (an.restored_r[c] > grid->r[c] + fmax(o->open_mm, 1e-6)) {
            an.damaged[c] = 1;
            an.damaged_cells++;
        }
    }
    an.plane_angle = M_PI / 2;
    an.shift_mm = o->symmetry.kind == SR_SYM_GLIDE ? o->symmetry.shift_mm : 0;
    sr_layer_grid_release(&rg);
    *out = an;
    return SR_OK;
}

/* ---- the whole core ---- */

static sr_status cut_regions(const sr_mesh *m, const double *z, size_t n, sr_poly2 *out,
                             size_t *open_chains, sr_err *err)
{
    sr_contour_stack s;
    sr_status st = sr_contour_slice(m, z, n, &s, err);
    if (st != SR_OK)
        return st;
    *open_chains += s.open_chains;
    for (size_t l = 0; l < n && st == SR_OK; l++)
        st = sr_poly2_boolean(SR_POLY_UNION, &s.raw[l], NULL, &out[l], err);
    sr_contour_stack_release(&s);
    return st;
}

/* Each layer's cross-section cut to the box's xy rectangle, layers outside its z
 * range emptied (sr_region_opts.roi). */
static sr_status crop_layers(sr_poly2 *d, const double *z, size_t n, const double roi[6],
                             sr_err *err)
{
    double rect[8] = {roi[0], roi[1], roi[3], roi[1], roi[3], roi[4], roi[0], roi[4]};
    sr_poly2 box = {0};
    sr_status st = sr_poly2_add_contour(&box, rect, 4, err);
    for (size_t l = 0; l < n && st == SR_OK; l++) {
        if (z[l] < roi[2] || z[l] > roi[5]) {
            sr_poly2_release(&d[l]);
            continue;
        }
        sr_poly2 cut = {0};
        st = sr_poly2_boolean(SR_POLY_INTERSECTION, &d[l], &box, &cut, err);
        sr_poly2_release(&d[l]);
        d[l] = cut;
    }
    sr_poly2_release(&box);
    return st;
}

/* Sections that reach a face of the region of interest where that face cuts the part
 * (inside the part's own box by more than tol) are dropped: cut by the crop, their
 * size is not known. */
static void drop_cropped(sr_section *sec, size_t *count, const double roi[6],
                         const double part_lo[3], const double part_hi[3], double tol)
{
    size_t kept = 0;
    for (size_t i = 0; i < *count; i++) {
        double lo[3], hi[3];
        sr_mesh_bbox(&sec[i].patch, lo, hi);
        int cut = 0;
        for (int a = 0; a < 3 && !cut; a++)
            cut = (roi[a] > part_lo[a] + tol && lo[a] < roi[a] + tol) ||
                  (roi[3 + a] < part_hi[a] - tol && hi[a] > roi[3 + a] - tol);
        if (cut) {
            sr_mesh_release(&sec[i].patch);
            continue;
        }
        sec[kept++] = sec[i];
    }
    *count = kept;
}

sr_status sr_region_reconstruct(const sr_mesh *aligned, const sr_layer_grid *grid,
                                const sr_region_opts *opts, sr_analysis *analysis,
                                sr_section **sections, size_t *count, sr_err *err)
{
    size_t L = grid->layers;
    int glide = opts->symmetry.kind == SR_SYM_GLIDE;
    if (glide && !(opts->symmetry.shift_mm > 0))
        return sr_err_set(err, SR_E_RANGE, "glide reconstruction needs a shift > 0 mm");
    double *z = malloc(3 * L * sizeof *z);
    sr_poly2 *d = calloc(L, sizeof *d), *up = glide ? calloc(L, sizeof *up) : NULL,
             *down = glide ? calloc(L, sizeof *down) : NULL, *res = calloc(L, sizeof *res),
             *mis = calloc(L, sizeof *mis);
    double *flat = NULL;        /* per layer: flat-face area at its planes */
    size_t open_chains = 0;
    sr_status st = SR_OK;
    if (!z || !d || !res || !mis || (glide && (!up || !down))) {
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu contour layers", L);
        goto done;
    }
    for (size_t l = 0; l < L; l++) {
        z[l] = sr_layer_z(grid, l);
        z[L + l] = z[l] + opts->symmetry.shift_mm;
        z[2 * L + l] = z[l] - opts->symmetry.shift_mm;
    }
    st = cut_regions(aligned, z, L, d, &open_chains, err);
    if (st == SR_OK && opts->have_roi)
        st = crop_layers(d, z, L, opts->roi, err);
    if (st == SR_OK && glide)
        st = cut_regions(aligned, z + L, L, up, &open_chains, err);
    if (st == SR_OK && glide)
        st = cut_regions(aligned, z + 2 * L, L, down, &open_chains, err);
    if (st != SR_OK)
        goto done;
    sr_vote_opts vo = {
        .symmetry = opts->symmetry, .coverage = opts->coverage, .open_mm = opts->open_mm};
    st = sr_vote_restore(d, up, down, L, &vo, res, mis, err);
    /* a plane within 2 x open_mm of the model's end faces cuts them where scan noise
     * lifts them, leaving a ragged partial section: no damage is read there */
    double z_end = grid->z_init + (double)L * grid->dz, margin = 2.0 * opts->open_mm;
    for (size_t l = 0; st == SR_OK && l < L; l++)
        if (z[l] - grid->z_init < margin || z_end - z[l] < margin)
            sr_poly2_release(&mis[l]);
    /* a break through both sides of a mirror (glide) plane: continuity along z.
     * Candidates lie within 0.6 mm + 3 layers of the damage: over the 0.5 mm step a
     * fracture steeper than about 40 degrees uncovers a band narrower than that */
    if (st == SR_OK && opts->symmetry.kind != SR_SYM_AXIAL) {
        sr_continuity_opts co = {
            .symmetry = opts->symmetry, .open_mm = opts->open_mm, .near_mm = 3.0 * grid->dz + 0.6};
        st = sr_continuity_extend(aligned, z, L, res, mis, &co, NULL, err);
    }
    if (st == SR_OK)
        flat = malloc(L * sizeof *flat);
    if (st == SR_OK && !flat)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu contour layers", L);
    if (st == SR_OK) {
        double shifts[2] = {opts->symmetry.shift_mm, -opts->symmetry.shift_mm};
        sr_layer_flats_opts fo = {.z_init = grid->z_init,
                                  .dz = grid->dz,
                                  .layers = L,
                                  .margin_mm = fmax(2.0 * opts->open_mm, SR_LAYER_FLATS_MARGIN_MM),
                                  .shifts = glide ? shifts : NULL,
                                  .shift_count = glide ? 2 : 0};
        st = sr_layer_flats_area(aligned, &fo, flat, err);
    }
    if (st == SR_OK) {
        layer_data sd = {d, res, flat};
        st = group_sections(mis, &sd, grid, opts, sections, count, err);
    }
    if (st == SR_OK && opts->have_roi) {
        double lo[3], hi[3];
        sr_mesh_bbox(aligned, lo, hi);
        drop_cropped(*sections, count, opts->roi, lo, hi, 2.0 * grid->dz + opts->open_mm);
        memset(analysis, 0, sizeof *analysis);
    } else if (st == SR_OK) {
        st = outline_analysis(grid, res, opts, analysis, err);
        if (st != SR_OK) {
            sr_sections_release(*sections, *count);
            *sections = NULL;
            *count = 0;
        }
    }
done:
    for (size_t l = 0; l < L; l++) {
        if (d)
            sr_poly2_release(&d[l]);
        if (up)
            sr_poly2_release(&up[l]);
        if (down)
            sr_poly2_release(&down[l]);
        if (res)
            sr_poly2_release(&res[l]);
        if (mis)
            sr_poly2_release(&mis[l]);
    }
    free(flat);
    free(z);
    free(d);
    free(up);
    free(down);
    free(res);
    free(mis);
    return st;
}
