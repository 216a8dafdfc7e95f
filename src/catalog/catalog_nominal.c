/*
 * catalog_nominal.c: the nominal's second opinion on a run in the catalogue (tables
 * run_nominal, run_nominal_sections, run_nominal_pieces of sql/008_nominal.sql, with
 * the measuring method of sql/010_nominal_method.sql; the
 * record is run.h's sr_run_nominal). Written inside sr_catalog_run_add's transaction
 * (catalog_runs.c), read by sr_catalog_run_get (catalog_run_read.c). Blobs as the
 * run's alignment: little-endian doubles (sr_cat_put_f64).
 */
#include "catalog/catalog_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sr_status sr_cat_nominal_insert(sr_catalog *cat, const sr_run_nominal *n, int64_t run_id,
                                sr_err *err)
{
    if (!n)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "INSERT INTO run_nominal (run_id, reference, transform, coverage, rms_mm, tol_mm,"
        " nominal_mm3, symmetry_mm3, diff_mm3, diff_pct, sliver_mm, slivers, sliver_mm3,"
        " min_volume_mm3, scan_outside_mm3, scan_outside_limit_mm3, poor, note, seconds,"
        " method, cell_mm, exact_note)"
        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17,"
        " ?18, ?19, ?20, ?21, ?22)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    unsigned char xf[96];
    for (int i = 0; i < 12; i++)
        sr_cat_put_f64(xf + 8 * i, n->transform[i]);
    sqlite3_bind_int64(stmt, 1, run_id);
    sqlite3_bind_text(stmt, 2, n->reference, -1, SQLITE_STATIC);
    sqlite3_bind_blob(stmt, 3, xf, sizeof xf, SQLITE_TRANSIENT);
    const double v[] = {n->coverage,     n->rms_mm,   n->tol_mm,   n->nominal_mm3,
                        n->symmetry_mm3, n->diff_mm3, n->diff_pct, n->sliver_mm};
    for (int i = 0; i < 8; i++)
        sqlite3_bind_double(stmt, 4 + i, v[i]);
    sqlite3_bind_int64(stmt, 12, (sqlite3_int64)n->slivers);
    sqlite3_bind_double(stmt, 13, n->sliver_mm3);
    sqlite3_bind_double(stmt, 14, n->min_volume_mm3);
    sqlite3_bind_double(stmt, 15, n->extra_mm3);
    sqlite3_bind_double(stmt, 16, n->extra_limit_mm3);
    sqlite3_bind_int(stmt, 17, n->poor ? 1 : 0);
    sqlite3_bind_text(stmt, 18, n->note, -1, SQLITE_STATIC);
    sqlite3_bind_double(stmt, 19, n->seconds);
    if (n->method[0])
        sqlite3_bind_text(stmt, 20, n->method, -1, SQLITE_STATIC);
    else
        sqlite3_bind_null(stmt, 20);
    if (strcmp(n->method, "cells") == 0)
        sqlite3_bind_double(stmt, 21, n->cell_mm);
    else
        sqlite3_bind_null(stmt, 21);
    sqlite3_bind_text(stmt, 22, n->exact_note, -1, SQLITE_STATIC);
    st = sr_cat_exec(cat, stmt, err, "record a run's nominal");
    for (size_t i = 0; st == SR_OK && i < n->section_count; i++) {
        const sr_run_nominal_section *s = &n->sections[i];
        st =
            sr_cat_prepare(cat,
                           "INSERT INTO run_nominal_sections (run_id, section_index,"
                           " symmetry_mm3, nominal_mm3, diff_mm3, diff_pct, deviation_mean_mm,"
                           " deviation_max_mm, pieces) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
                           &stmt, err);
        if (st != SR_OK)
            break;
        sqlite3_bind_int64(stmt, 1, run_id);
        sqlite3_bind_int64(stmt, 2, (sqlite3_int64)s->index);
        sqlite3_bind_double(stmt, 3, s->symmetry_mm3);
        sqlite3_bind_double(stmt, 4, s->nominal_mm3);
        sqlite3_bind_double(stmt, 5, s->diff_mm3);
        sqlite3_bind_double(stmt, 6, s->diff_pct);
        if (s->pieces) {
            sqlite3_bind_double(stmt, 7, s->dev_mean_mm);
            sqlite3_bind_double(stmt, 8, s->dev_max_mm);
        }
        sqlite3_bind_int64(stmt, 9, (sqlite3_int64)s->pieces);
        st = sr_cat_exec(cat, stmt, err, "record a run's nominal sections");
    }
    for (size_t i = 0; st == SR_OK && i < n->piece_count; i++) {
        const sr_run_nominal_piece *p = &n->pieces[i];
        st = sr_cat_prepare(cat,
                            "INSERT INTO run_nominal_pieces (run_id, piece_index, volume_mm3,"
                            " thickness_mm, section_index, outside_mm3, centroid)"
                            " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
                            &stmt, err);
        if (st != SR_OK)
            break;
        unsigned char c[24];
        for (int k = 0; k < 3; k++)
            sr_cat_put_f64(c + 8 * k, p->centroid[k]);
        sqlite3_bind_int64(stmt, 1, run_id);
        sqlite3_bind_int64(stmt, 2, (sqlite3_int64)i);
        sqlite3_bind_double(stmt, 3, p->volume_mm3);
        sqlite3_bind_double(stmt, 4, p->thickness_mm);
        if (p->section >= 0)
            sqlite3_bind_int64(stmt, 5, p->section);
        sqlite3_bind_double(stmt, 6, p->outside_mm3);
        sqlite3_bind_blob(stmt, 7, c, sizeof c, SQLITE_TRANSIENT);
        st = sr_cat_exec(cat, stmt, err, "record a run's nominal pieces");
    }
    return st;
}

/* Reads the sections (what 0) or the pieces (what 1) of run_id's nominal into n. */
static sr_status read_rows(sr_catalog *cat, int64_t run_id, int what, sr_run_nominal *n,
                           sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        what == 0 ? "SELECT section_index, symmetry_mm3, nominal_mm3, diff_mm3, diff_pct,"
                    " deviation_mean_mm, deviation_max_mm, pieces FROM run_nominal_sections"
                    " WHERE run_id = ?1 ORDER BY section_index"
                  : "SELECT piece_index, volume_mm3, thickness_mm, section_index, outside_mm3,"
                    " centroid FROM run_nominal_pieces WHERE run_id = ?1 ORDER BY piece_index",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    size_t cap = 0, count = 0;
    void *arr = NULL;
    size_t size = what == 0 ? sizeof(sr_run_nominal_section) : sizeof(sr_run_nominal_piece);
    bool row = true;
    while (st == SR_OK &&
           (st = sr_cat_step(cat, stmt, &row, err, "read a run's nominal")) == SR_OK && row) {
        if (count == cap) {
            size_t nc = cap ? 2 * cap : 8;
            void *g = realloc(arr, nc * size);
            if (!g) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory reading a run's nominal");
                break;
            }
            arr = g;
            cap = nc;
        }
        if (what == 0) {
            sr_run_nominal_section *s = (sr_run_nominal_section *)arr + count;
            s->index = (size_t)sqlite3_column_int64(stmt, 0);
            s->symmetry_mm3 = sqlite3_column_double(stmt, 1);
            s->nominal_mm3 = sqlite3_column_double(stmt, 2);
            s->diff_mm3 = sqlite3_column_double(stmt, 3);
            s->diff_pct = sqlite3_column_double(stmt, 4);
            bool dev = sqlite3_column_type(stmt, 5) != SQLITE_NULL;
            s->dev_mean_mm = dev ? sqlite3_column_double(stmt, 5) : -1;
            s->dev_max_mm = dev ? sqlite3_column_double(stmt, 6) : -1;
            s->pieces = (size_t)sqlite3_column_int64(stmt, 7);
        } else {
            sr_run_nominal_piece *p = (sr_run_nominal_piece *)arr + count;
            p->volume_mm3 = sqlite3_column_double(stmt, 1);
            p->thickness_mm = sqlite3_column_double(stmt, 2);
            p->section = sqlite3_column_type(stmt, 3) == SQLITE_NULL
                             ? -1
                             : (long)sqlite3_column_int64(stmt, 3);
            p->outside_mm3 = sqlite3_column_double(stmt, 4);
            const unsigned char *c = sqlite3_column_blob(stmt, 5);
            for (int k = 0; k < 3; k++)
                p->centroid[k] =
                    c && sqlite3_column_bytes(stmt, 5) == 24 ? sr_cat_get_f64(c + 8 * k) : NAN;
        }
        count++;
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        free(arr);
        return st;
    }
    if (what == 0) {
        n->sections = arr;
        n->section_count = count;
    } else {
        n->pieces = arr;
        n->piece_count = count;
    }
    return sr_cat_finish(cat, stmt, err, "read a run's nominal");
}

sr_status sr_cat_nominal_read(sr_catalog *cat, sr_run *r, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT reference, transform, coverage, rms_mm, tol_mm, nominal_mm3, symmetry_mm3,"
        " diff_mm3, diff_pct, sliver_mm, slivers, sliver_mm3, min_volume_mm3,"
        " scan_outside_mm3, scan_outside_limit_mm3, poor, note, seconds, method, cell_mm,"
        " exact_note FROM run_nominal WHERE run_id = ?1",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, r->id);
    bool row = false;
    st = sr_cat_step(cat, stmt, &row, err, "read a run's nominal");
    if (st != SR_OK || !row) {
        if (st != SR_OK)
            sqlite3_finalize(stmt);
        return st != SR_OK ? st : sr_cat_finish(cat, stmt, err, "read a run's nominal");
    }
    sr_run_nominal *n = calloc(1, sizeof *n);
    if (!n) {
        sqlite3_finalize(stmt);
        return sr_err_set(err, SR_E_NOMEM, "out of memory reading a run's nominal");
    }
    sr_cat_column_text(stmt, 0, n->reference, sizeof n->reference);
    const unsigned char *xf = sqlite3_column_blob(stmt, 1);
    for (int i = 0; i < 12; i++)
        n->transform[i] =
            xf && sqlite3_column_bytes(stmt, 1) == 96 ? sr_cat_get_f64(xf + 8 * i) : NAN;
    double *v[] = {&n->coverage,     &n->rms_mm,   &n->tol_mm,   &n->nominal_mm3,
                   &n->symmetry_mm3, &n->diff_mm3, &n->diff_pct, &n->sliver_mm};
    for (int i = 0; i < 8; i++)
        *v[i] = sqlite3_column_double(stmt, 2 + i);
    n->slivers = (size_t)sqlite3_column_int64(stmt, 10);
    n->sliver_mm3 = sqlite3_column_double(stmt, 11);
    n->min_volume_mm3 = sqlite3_column_double(stmt, 12);
    n->extra_mm3 = sqlite3_column_double(stmt, 13);
    n->extra_limit_mm3 = sqlite3_column_double(stmt, 14);
    n->poor = sqlite3_column_int(stmt, 15);
    sr_cat_column_text(stmt, 16, n->note, sizeof n->note);
    n->seconds = sqlite3_column_double(stmt, 17);
    sr_cat_column_text(stmt, 18, n->method, sizeof n->method); /* NULL: "" */
    n->cell_mm = sqlite3_column_double(stmt, 19);
    sr_cat_column_text(stmt, 20, n->exact_note, sizeof n->exact_note);
    st = sr_cat_finish(cat, stmt, err, "read a run's nominal");
    if (st == SR_OK)
        st = read_rows(cat, r->id, 0, n, err);
    if (st == SR_OK)
        st = read_rows(cat, r->id, 1, n, err);
    if (st != SR_OK) {
        sr_run_nominal_free(n);
        return st;
    }
    r->nominal = n;
    return SR_OK;
}
