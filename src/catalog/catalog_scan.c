/*
 * catalog_scan.c: a run's input read as a scan in the catalogue (tables run_scan and
 * run_scan_gaps of sql/011_scan_gaps.sql, sealed_triangles of sql/012_scan_sealed.sql, uncurled_vertices of sql/014_scan_uncurled.sql, sags and sag_mm3 of
 * sql/015_gap_sags.sql; the record is run.h's sr_run_scan): the
 * openings closed before the reconstruction, kept apart from the sections. Written
 * inside sr_catalog_run_add's transaction (catalog_runs.c), read by sr_catalog_run_get
 * (catalog_run_read.c). The centre blob as the nominal's centroids: little-endian
 * doubles (sr_cat_put_f64).
 */
#include "catalog/catalog_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sr_status sr_cat_scan_insert(sr_catalog *cat, const sr_run_scan *s, int64_t run_id, sr_err *err)
{
    if (!s)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "INSERT INTO run_scan (run_id, triangles, boundary_edges, gaps, open_area_mm2,"
        " open_share, components, strays, stray_triangles, stray_area_mm2, sealed_triangles,"
        " uncurled_vertices, sags, sag_mm3)"
        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    sqlite3_bind_int64(stmt, 2, (sqlite3_int64)s->triangles);
    sqlite3_bind_int64(stmt, 3, (sqlite3_int64)s->boundary_edges);
    sqlite3_bind_int64(stmt, 4, (sqlite3_int64)s->gap_count);
    sqlite3_bind_double(stmt, 5, s->open_area_mm2);
    sqlite3_bind_double(stmt, 6, s->open_share);
    sqlite3_bind_int64(stmt, 7, (sqlite3_int64)s->components);
    sqlite3_bind_int64(stmt, 8, (sqlite3_int64)s->strays);
    sqlite3_bind_int64(stmt, 9, (sqlite3_int64)s->stray_triangles);
    sqlite3_bind_double(stmt, 10, s->stray_area_mm2);
    sqlite3_bind_int64(stmt, 11, (sqlite3_int64)s->sealed_triangles);
    sqlite3_bind_int64(stmt, 12, (sqlite3_int64)s->uncurled_vertices);
    sqlite3_bind_int64(stmt, 13, (sqlite3_int64)s->sags);
    sqlite3_bind_double(stmt, 14, s->sag_mm3);
    st = sr_cat_exec(cat, stmt, err, "record a run's scan");
    for (size_t i = 0; st == SR_OK && i < s->gap_count; i++) {
        const sr_run_scan_gap *g = &s->gaps[i];
        st = sr_cat_prepare(cat,
                            "INSERT INTO run_scan_gaps (run_id, gap_index, edges, length_mm,"
                            " area_mm2, centre, closed_by) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
                            &stmt, err);
        if (st != SR_OK)
            break;
        unsigned char c[24];
        for (int k = 0; k < 3; k++)
            sr_cat_put_f64(c + 8 * k, g->centre[k]);
        sqlite3_bind_int64(stmt, 1, run_id);
        sqlite3_bind_int64(stmt, 2, (sqlite3_int64)i);
        sqlite3_bind_int64(stmt, 3, (sqlite3_int64)g->edges);
        sqlite3_bind_double(stmt, 4, g->length_mm);
        sqlite3_bind_double(stmt, 5, g->area_mm2);
        sqlite3_bind_blob(stmt, 6, c, sizeof c, SQLITE_TRANSIENT);
        sqlite3_bind_text(stmt, 7, g->closed_by, -1, SQLITE_STATIC);
        st = sr_cat_exec(cat, stmt, err, "record a run's scan gaps");
    }
    return st;
}

/* Reads run_id's gaps into s. */
static sr_status read_gaps(sr_catalog *cat, int64_t run_id, sr_run_scan *s, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT edges, length_mm, area_mm2, centre, closed_by"
                                  " FROM run_scan_gaps WHERE run_id = ?1 ORDER BY gap_index",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    size_t cap = 0, count = 0;
    sr_run_scan_gap *arr = NULL;
    bool row = true;
    while (st == SR_OK &&
           (st = sr_cat_step(cat, stmt, &row, err, "read a run's scan gaps")) == SR_OK && row) {
        if (count == cap) {
            size_t nc = cap ? 2 * cap : 8;
            sr_run_scan_gap *g = realloc(arr, nc * sizeof *g);
            if (!g) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory reading a run's scan gaps");
                break;
            }
            arr = g;
            cap = nc;
        }
        sr_run_scan_gap *g = arr + count++;
        g->edges = (size_t)sqlite3_column_int64(stmt, 0);
        g->length_mm = sqlite3_column_double(stmt, 1);
        g->area_mm2 = sqlite3_column_double(stmt, 2);
        const unsigned char *c = sqlite3_column_blob(stmt, 3);
        for (int k = 0; k < 3; k++)
            g->centre[k] =
                c && sqlite3_column_bytes(stmt, 3) == 24 ? sr_cat_get_f64(c + 8 * k) : NAN;
        sr_cat_column_text(stmt, 4, g->closed_by, sizeof g->closed_by);
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        free(arr);
        return st;
    }
    s->gaps = arr;
    s->gap_count = count;
    return sr_cat_finish(cat, stmt, err, "read a run's scan gaps");
}

sr_status sr_cat_scan_read(sr_catalog *cat, sr_run *r, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT triangles, boundary_edges, open_area_mm2, open_share,"
                                  " components, strays, stray_triangles, stray_area_mm2,"
                                  " sealed_triangles, uncurled_vertices, sags, sag_mm3"
                                  " FROM run_scan WHERE run_id = ?1",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, r->id);
    bool row = false;
    st = sr_cat_step(cat, stmt, &row, err, "read a run's scan");
    if (st != SR_OK || !row) {
        if (st != SR_OK)
            sqlite3_finalize(stmt);
        return st != SR_OK ? st : sr_cat_finish(cat, stmt, err, "read a run's scan");
    }
    sr_run_scan *s = calloc(1, sizeof *s);
    if (!s) {
        sqlite3_finalize(stmt);
        return sr_err_set(err, SR_E_NOMEM, "out of memory reading a run's scan");
    }
    s->triangles = (size_t)sqlite3_column_int64(stmt, 0);
    s->boundary_edges = (size_t)sqlite3_column_int64(stmt, 1);
    s->open_area_mm2 = sqlite3_column_double(stmt, 2);
    s->open_share = sqlite3_column_double(stmt, 3);
    s->components = (size_t)sqlite3_column_int64(stmt, 4);
    s->strays = (size_t)sqlite3_column_int64(stmt, 5);
    s->stray_triangles = (size_t)sqlite3_column_int64(stmt, 6);
    s->stray_area_mm2 = sqlite3_column_double(stmt, 7);
    s->sealed_triangles = (size_t)sqlite3_column_int64(stmt, 8);
    s->uncurled_vertices = (size_t)sqlite3_column_int64(stmt, 9);
    s->sags = (size_t)sqlite3_column_int64(stmt, 10);
    s->sag_mm3 = sqlite3_column_double(stmt, 11);
    st = sr_cat_finish(cat, stmt, err, "read a run's scan");
    if (st == SR_OK)
        st = read_gaps(cat, r->id, s, err);
    if (st != SR_OK) {
        sr_run_scan_free(s);
        return st;
    }
    r->scan = s;
    return SR_OK;
}
