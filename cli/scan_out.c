/*
 * scan_out.c: what the CLI says about an input mesh read as a scan (mesh/scan_describe.h),
 * the same for `check` and `reconstruct`: its openings (boundary loops, longest first),
 * its components, the share of the surface that is open, and the strays (small pieces
 * off the part's surface) dropped before use. As text lines on stdout (check's block,
 * reconstruct's summary) and as a JSON object; and the run record's scan gaps (the
 * openings closed before the reconstruction, kept apart from the sections) as `run
 * show` prints them, in text and JSON.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "json_out.h"
#include "mesh/scan_describe.h"
#include "run/run_scan.h"

/* Loops and components listed by name before "... and N more". */
#define SHOWN 5

/* One line: "open scan: 3 boundary loops (...), open 7.1 % of the surface". */
static void loops_line(const sr_scan_desc *d, char *buf, size_t size)
{
    int n = snprintf(buf, size, "%zu boundary loop%s, %zu edges", d->loop_count,
                     d->loop_count == 1 ? "" : "s", d->boundary_edges);
    for (size_t i = 0; i < d->loop_count && i < SHOWN && n > 0 && (size_t)n < size; i++)
        n += snprintf(buf + n, size - (size_t)n, "%s%zu edges %.1f mm", i ? "; " : " (",
                      d->loops[i].edges, d->loops[i].length_mm);
    if (d->loop_count > SHOWN && n > 0 && (size_t)n < size)
        n += snprintf(buf + n, size - (size_t)n, "; %zu more", d->loop_count - SHOWN);
    if (d->loop_count && n > 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, ")");
}

static void components_line(const sr_scan_desc *d, char *buf, size_t size)
{
    int n = snprintf(buf, size, "%zu component%s", d->component_count,
                     d->component_count == 1 ? "" : "s");
    for (size_t i = 0; i < d->component_count && i < SHOWN && n > 0 && (size_t)n < size; i++)
        n += snprintf(buf + n, size - (size_t)n, "%s%zu triangles %.4g mm²%s", i ? "; " : " (",
                      d->components[i].triangles, d->components[i].area_mm2,
                      d->components[i].stray ? " stray" : "");
    if (d->component_count > SHOWN && n > 0 && (size_t)n < size)
        n += snprintf(buf + n, size - (size_t)n, "; %zu more", d->component_count - SHOWN);
    if (d->component_count && n > 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, ")");
}

bool cli_scan_is_plain(const sr_scan_desc *d)
{
    return !d->open && d->component_count <= 1 && d->nonmanifold_edges == 0;
}

void cli_scan_print(const sr_scan_desc *d)
{
    char buf[1024];
    printf("  scan                %s\n", d->open ? "open: read as a scan" : "closed");
    loops_line(d, buf, sizeof buf);
    printf("  openings            %s\n", buf);
    printf("  open share          %.2f %% (%.4g mm² of openings)\n", 100.0 * d->open_share,
           d->open_area_mm2);
    components_line(d, buf, sizeof buf);
    printf("  components          %s\n", buf);
    printf("  strays              %zu (%zu triangles, %.4g mm²): small and off the surface\n",
           d->strays, d->stray_triangles, d->stray_area_mm2);
}

/* Counts of rec's gaps closed in their plane and by fans. */
static void closing_counts(const sr_run_scan *rec, size_t *plane, size_t *fan)
{
    *plane = *fan = 0;
    for (size_t i = 0; rec && i < rec->gap_count; i++) {
        if (strcmp(rec->gaps[i].closed_by, "plane") == 0)
            (*plane)++;
        else if (strcmp(rec->gaps[i].closed_by, "fan") == 0)
            (*fan)++;
    }
}

void cli_scan_summary(const sr_scan_desc *d, const sr_run_scan *rec)
{
    if (cli_scan_is_plain(d))
        return;
    char loops[1024], comps[1024];
    loops_line(d, loops, sizeof loops);
    components_line(d, comps, sizeof comps);
    printf("  scan:       %s: %s, open %.2f %% of the surface\n",
           d->open ? "open, read as a scan" : "closed, in several pieces", loops,
           100.0 * d->open_share);
    printf("              %s\n", comps);
    size_t plane, fan;
    closing_counts(rec, &plane, &fan);
    if (plane + fan)
        printf("              scan gaps closed, not damage: %zu in their plane, %zu by fans "
               "from their centroids\n",
               plane, fan);
    if (d->strays)
        printf("              dropped %zu stray%s (%zu triangles, %.4g mm²: small pieces off the "
               "part's surface)\n",
               d->strays, d->strays == 1 ? "" : "s", d->stray_triangles, d->stray_area_mm2);
    if (d->sealed_triangles)
        printf("              sealed: %zu triangles cut out where the closing left edges used "
               "other than twice, and closed again\n",
               d->sealed_triangles);
    if (d->uncurled_vertices)
        printf("              untwisted: %zu rim vertices merged where a rim folded over itself "
               "in its plane\n",
               d->uncurled_vertices);
    if (rec && rec->sags)
        printf("              restored behind gap fills, not damage: %zu sag%s, %.4g mm³ (the "
               "fill lay under the surface the scanner did not see)\n",
               rec->sags, rec->sags == 1 ? "" : "s", rec->sag_mm3);
}

void cli_run_scan_print(const sr_run_scan *s)
{
    if (!s)
        return;
    size_t plane, fan;
    closing_counts(s, &plane, &fan);
    printf("  scan gaps:   %zu (%.4g mm², %.2f %% of the surface; closed: %zu in their plane, "
           "%zu by fans; not damage)\n",
           s->gap_count, s->open_area_mm2, 100.0 * s->open_share, plane, fan);
    for (size_t i = 0; i < s->gap_count && i < SHOWN; i++) {
        const sr_run_scan_gap *g = &s->gaps[i];
        printf("               %zu edges, %.1f mm rim, %.4g mm² at (%.2f, %.2f, %.2f): %s\n",
               g->edges, g->length_mm, g->area_mm2, g->centre[0], g->centre[1], g->centre[2],
               g->closed_by);
    }
    if (s->gap_count > SHOWN)
        printf("               and %zu more\n", s->gap_count - SHOWN);
    if (s->strays)
        printf("  strays:      %zu dropped (%zu triangles, %.4g mm²)\n", s->strays,
               s->stray_triangles, s->stray_area_mm2);
    if (s->sealed_triangles)
        printf("  sealed:      %zu triangles cut out round the closing's defects and closed "
               "again\n",
               s->sealed_triangles);
    if (s->uncurled_vertices)
        printf("  untwisted:   %zu rim vertices merged where a rim folded over itself in its "
               "plane\n",
               s->uncurled_vertices);
    if (s->sags)
        printf("  gap sags:    %zu restored behind gap fills (%.4g mm³; not sections)\n", s->sags,
               s->sag_mm3);
}

void json_run_scan(json_out *j, const sr_run_scan *s)
{
    if (!s) {
        json_null(j);
        return;
    }
    json_object_begin(j);
    json_key(j, "triangles");
    json_int(j, (int64_t)s->triangles);
    json_key(j, "boundary_edges");
    json_int(j, (int64_t)s->boundary_edges);
    json_key(j, "open_area_mm2");
    json_number(j, s->open_area_mm2);
    json_key(j, "open_share");
    json_number(j, s->open_share);
    json_key(j, "components");
    json_int(j, (int64_t)s->components);
    json_key(j, "strays");
    json_int(j, (int64_t)s->strays);
    json_key(j, "stray_triangles");
    json_int(j, (int64_t)s->stray_triangles);
    json_key(j, "stray_area_mm2");
    json_number(j, s->stray_area_mm2);
    json_key(j, "sealed_triangles"); /* cut out round the closing's defects, closed again */
    json_int(j, (int64_t)s->sealed_triangles);
    json_key(j, "uncurled_vertices"); /* merged where a rim twisted in its plane */
    json_int(j, (int64_t)s->uncurled_vertices);
    json_key(j, "sags"); /* lenses restored behind gap fills: not sections */
    json_int(j, (int64_t)s->sags);
    json_key(j, "sag_mm3");
    json_number(j, s->sag_mm3);
    json_key(j, "gaps");
    json_array_begin(j);
    for (size_t i = 0; i < s->gap_count; i++) {
        const sr_run_scan_gap *g = &s->gaps[i];
        json_object_begin(j);
        json_key(j, "edges");
        json_int(j, (int64_t)g->edges);
        json_key(j, "length_mm");
        json_number(j, g->length_mm);
        json_key(j, "area_mm2");
        json_number(j, g->area_mm2);
        json_key(j, "centre");
        json_array_begin(j);
        for (int k = 0; k < 3; k++)
            json_number(j, g->centre[k]);
        json_array_end(j);
        json_key(j, "closed_by");
        json_string(j, g->closed_by);
        json_object_end(j);
    }
    json_array_end(j);
    json_object_end(j);
}

void json_scan(json_out *j, const sr_scan_desc *d)
{
    json_object_begin(j);
    json_key(j, "open");
    json_bool(j, d->open);
    json_key(j, "boundary_edges");
    json_int(j, (int64_t)d->boundary_edges);
    json_key(j, "nonmanifold_edges");
    json_int(j, (int64_t)d->nonmanifold_edges);
    json_key(j, "open_share");
    json_number(j, d->open_share);
    json_key(j, "open_area_mm2");
    json_number(j, d->open_area_mm2);
    json_key(j, "loops"); /* longest first */
    json_array_begin(j);
    for (size_t i = 0; i < d->loop_count; i++) {
        json_object_begin(j);
        json_key(j, "edges");
        json_int(j, (int64_t)d->loops[i].edges);
        json_key(j, "length_mm");
        json_number(j, d->loops[i].length_mm);
        json_key(j, "span_mm2");
        json_number(j, d->loops[i].span_mm);
        json_key(j, "closed");
        json_bool(j, d->loops[i].closed);
        json_object_end(j);
    }
    json_array_end(j);
    json_key(j, "components"); /* most triangles first */
    json_array_begin(j);
    for (size_t i = 0; i < d->component_count; i++) {
        json_object_begin(j);
        json_key(j, "triangles");
        json_int(j, (int64_t)d->components[i].triangles);
        json_key(j, "area_mm2");
        json_number(j, d->components[i].area_mm2);
        json_key(j, "distance_mm"); /* to the largest's surface; null: not measured */
        if (d->components[i].distance_mm < 0)
            json_null(j);
        else
            json_number(j, d->components[i].distance_mm);
        json_key(j, "stray");
        json_bool(j, d->components[i].stray);
        json_object_end(j);
    }
    json_array_end(j);
    json_key(j, "strays");
    json_object_begin(j);
    json_key(j, "count");
    json_int(j, (int64_t)d->strays);
    json_key(j, "triangles");
    json_int(j, (int64_t)d->stray_triangles);
    json_key(j, "area_mm2");
    json_number(j, d->stray_area_mm2);
    json_object_end(j);
    json_object_end(j);
}

sr_status cli_scan_input(sr_mesh *scan, sr_scan_desc *out, sr_run_scan **rec, sr_err *err)
{
    sr_scan_desc d;
    sr_scan_closing *how = NULL;
    sr_status st = sr_scan_close_peeling(scan, &d, &how, NULL, err);
    if (st != SR_OK)
        return st;
    sr_run_scan *r = NULL;
    st = sr_run_scan_from_desc(&d, how, &r, err);
    free(how);
    if (st != SR_OK) {
        sr_scan_desc_release(&d);
        return st;
    }
    *out = d;
    *rec = r;
    return SR_OK;
}
