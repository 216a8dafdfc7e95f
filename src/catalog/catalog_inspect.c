/*
 * catalog_inspect.c: inspections in the catalogue (catalog_inspect.h; tables of
 * sql/009_inspection.sql). The transform is stored as the run's alignment is: 12
 * little-endian doubles (sr_cat_put_f64).
 */
#include "catalog/catalog_inspect.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/version.h"
#include "catalog/catalog_int.h"

#define INSPECT_SCHEMA 9

static sr_status insert_sections(sr_catalog *cat, int64_t id, const sr_inspect_result *r,
                                 sr_err *err)
{
    sr_status st = SR_OK;
    for (size_t k = 0; st == SR_OK && k < r->section_count; k++) {
        const sr_inspect_section *s = &r->sections[k];
        sqlite3_stmt *stmt;
        st = sr_cat_prepare(cat,
                            "INSERT INTO inspection_sections (inspection_id, section_index,"
                            " patch_mm3, underfill_mm3, underfill_depth_mm, overbuild_mm3,"
                            " stock_min_mm, stock_max_mm, stock_mean_mm, stock_share,"
                            " under_share, dev_mean_mm, dev_rms_mm, dev_min_mm, dev_max_mm,"
                            " samples, verdict, reasons) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7,"
                            " ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18)",
                            &stmt, err);
        if (st != SR_OK)
            break;
        sqlite3_bind_int64(stmt, 1, id);
        sqlite3_bind_int64(stmt, 2, (sqlite3_int64)s->index);
        const double v[] = {s->patch_mm3,     s->underfill_mm3, s->underfill_depth_mm,
                            s->overbuild_mm3, s->stock_min_mm,  s->stock_max_mm,
                            s->stock_mean_mm, s->stock_share,   s->under_share,
                            s->dev_mean_mm,   s->dev_rms_mm,    s->dev_min_mm,
                            s->dev_max_mm};
        for (int i = 0; i < 13; i++)
            sqlite3_bind_double(stmt, 3 + i, v[i]);
        sqlite3_bind_int64(stmt, 16, (sqlite3_int64)s->samples);
        sqlite3_bind_text(stmt, 17, sr_inspect_verdict_str(s->verdict), -1, SQLITE_STATIC);
        sqlite3_bind_text(stmt, 18, s->reasons, -1, SQLITE_STATIC);
        st = sr_cat_exec(cat, stmt, err, "record an inspection's sections");
    }
    return st;
}

static sr_status run_exists(sr_catalog *cat, int64_t run_id, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "SELECT 1 FROM runs WHERE id = ?1", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    bool row = false;
    st = sr_cat_step(cat, stmt, &row, err, "look up a run");
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "look up a run");
    if (st == SR_OK && !row)
        return sr_err_set(err, SR_E_NOTFOUND, "no run %lld in the catalogue", (long long)run_id);
    return st;
}

sr_status sr_catalog_inspection_add(sr_catalog *cat, int64_t run_id, const sr_mesh *scan,
                                    const char *source_file, const sr_inspect_result *r,
                                    int64_t *out_id, sr_err *err)
{
    if (cat->schema_version < INSPECT_SCHEMA)
        return sr_err_set(err, SR_E_VERSION,
                          "the catalogue '%s' predates inspections (schema %d): open it "
                          "writable to upgrade it",
                          cat->path, cat->schema_version);
    sr_cat_mesh_row mesh = {0};
    sr_status st = scan ? sr_cat_mesh_row_build(cat, scan, "scan", source_file, &mesh, err) : SR_OK;
    if (st != SR_OK)
        return st;
    st = sr_cat_begin(cat, err);
    if (st != SR_OK) {
        sr_cat_mesh_row_release(&mesh);
        return st;
    }
    st = run_exists(cat, run_id, err);
    int64_t mesh_id = 0, id = 0;
    if (st == SR_OK && scan)
        st = sr_cat_mesh_row_insert(cat, &mesh, &mesh_id, err);
    sqlite3_stmt *stmt = NULL;
    if (st == SR_OK)
        st = sr_cat_prepare(
            cat,
            "INSERT INTO inspections (run_id, scan_mesh_id, transform, registered, coverage,"
            " reg_tol_mm, allowance_mm, tolerance_mm, volumes_exact, outside_samples,"
            " outside_share, outside_max_mm, outside_rms_mm, outside_overbuild_mm3, verdict,"
            " reasons, software_version, inspected_at) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8,"
            " ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17,"
            " strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))",
            &stmt, err);
    if (st == SR_OK) {
        unsigned char xf[96];
        for (int i = 0; i < 12; i++)
            sr_cat_put_f64(xf + 8 * i, r->transform[i]);
        sqlite3_bind_int64(stmt, 1, run_id);
        if (mesh_id)
            sqlite3_bind_int64(stmt, 2, mesh_id);
        sqlite3_bind_blob(stmt, 3, xf, sizeof xf, SQLITE_TRANSIENT);
        sqlite3_bind_int(stmt, 4, r->registered ? 1 : 0);
        sqlite3_bind_double(stmt, 5, r->coverage);
        sqlite3_bind_double(stmt, 6, r->reg_tol_mm);
        sqlite3_bind_double(stmt, 7, r->allowance_mm);
        sqlite3_bind_double(stmt, 8, r->tolerance_mm);
        sqlite3_bind_int(stmt, 9, r->volumes_exact ? 1 : 0);
        sqlite3_bind_int64(stmt, 10, (sqlite3_int64)r->outside_samples);
        sqlite3_bind_double(stmt, 11, r->outside_share);
        sqlite3_bind_double(stmt, 12, r->outside_max_mm);
        sqlite3_bind_double(stmt, 13, r->outside_rms_mm);
        sqlite3_bind_double(stmt, 14, r->outside_overbuild_mm3);
        sqlite3_bind_text(stmt, 15, sr_inspect_verdict_str(r->verdict), -1, SQLITE_STATIC);
        sqlite3_bind_text(stmt, 16, r->reasons, -1, SQLITE_STATIC);
        sqlite3_bind_text(stmt, 17, SR_VERSION, -1, SQLITE_STATIC);
        st = sr_cat_exec(cat, stmt, err, "record an inspection");
    }
    if (st == SR_OK) {
        id = sqlite3_last_insert_rowid(cat->db);
        st = insert_sections(cat, id, r, err);
    }
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    else
        sr_cat_rollback(cat);
    sr_cat_mesh_row_release(&mesh);
    if (st == SR_OK && out_id)
        *out_id = id;
    return st;
}

sr_status sr_catalog_inspection_latest(sr_catalog *cat, int64_t run_id, sr_inspection_info *out,
                                       bool *found, sr_err *err)
{
    *found = false;
    if (cat->schema_version < INSPECT_SCHEMA)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT v.id, v.run_id, coalesce(v.scan_mesh_id, 0), v.verdict, v.reasons,"
        " v.allowance_mm, v.tolerance_mm, v.registered, v.coverage, v.inspected_at,"
        " (SELECT count(*) FROM inspection_sections s WHERE s.inspection_id = v.id),"
        " v.transform"
        " FROM inspections v WHERE v.run_id = ?1 ORDER BY v.inspected_at DESC, v.id DESC"
        " LIMIT 1",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    bool row = false;
    st = sr_cat_step(cat, stmt, &row, err, "read an inspection");
    if (st == SR_OK && row) {
        memset(out, 0, sizeof *out);
        out->id = sqlite3_column_int64(stmt, 0);
        out->run_id = sqlite3_column_int64(stmt, 1);
        out->scan_mesh_id = sqlite3_column_int64(stmt, 2);
        sr_cat_column_text(stmt, 3, out->verdict, sizeof out->verdict);
        sr_cat_column_text(stmt, 4, out->reasons, sizeof out->reasons);
        out->allowance_mm = sqlite3_column_double(stmt, 5);
        out->tolerance_mm = sqlite3_column_double(stmt, 6);
        out->registered = sqlite3_column_int(stmt, 7);
        out->coverage = sqlite3_column_double(stmt, 8);
        sr_cat_column_text(stmt, 9, out->inspected_at, sizeof out->inspected_at);
        out->section_count = (size_t)sqlite3_column_int64(stmt, 10);
        const unsigned char *xf = sqlite3_column_blob(stmt, 11);
        if (xf && sqlite3_column_bytes(stmt, 11) == 96)
            for (int i = 0; i < 12; i++)
                out->transform[i] = sr_cat_get_f64(xf + 8 * i);
        else
            out->transform[0] = out->transform[5] = out->transform[10] = 1;
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "read an inspection");
    if (st == SR_OK)
        *found = row;
    return st;
}

sr_status sr_catalog_inspection_sections(sr_catalog *cat, int64_t id, sr_inspect_section **out,
                                         size_t *count, sr_err *err)
{
    *out = NULL;
    *count = 0;
    if (cat->schema_version < INSPECT_SCHEMA)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT section_index, patch_mm3, underfill_mm3, underfill_depth_mm, overbuild_mm3,"
        " stock_min_mm, stock_max_mm, stock_mean_mm, stock_share, under_share, dev_mean_mm,"
        " dev_rms_mm, dev_min_mm, dev_max_mm, samples, verdict, reasons"
        " FROM inspection_sections WHERE inspection_id = ?1 ORDER BY section_index",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    sr_inspect_section *v = NULL;
    size_t n = 0, cap = 0;
    bool row = true;
    while (st == SR_OK) {
        st = sr_cat_step(cat, stmt, &row, err, "read an inspection's sections");
        if (st != SR_OK || !row)
            break;
        if (n == cap) {
            size_t nc = cap ? 2 * cap : 8;
            sr_inspect_section *p = realloc(v, nc * sizeof *p);
            if (!p) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory");
                break;
            }
            v = p;
            cap = nc;
        }
        sr_inspect_section *s = &v[n++];
        memset(s, 0, sizeof *s);
        s->index = (size_t)sqlite3_column_int64(stmt, 0);
        double *f[] = {&s->patch_mm3,     &s->underfill_mm3, &s->underfill_depth_mm,
                       &s->overbuild_mm3, &s->stock_min_mm,  &s->stock_max_mm,
                       &s->stock_mean_mm, &s->stock_share,   &s->under_share,
                       &s->dev_mean_mm,   &s->dev_rms_mm,    &s->dev_min_mm,
                       &s->dev_max_mm};
        for (int i = 0; i < 13; i++)
            *f[i] = sqlite3_column_double(stmt, 1 + i);
        s->samples = (size_t)sqlite3_column_int64(stmt, 14);
        char verdict[16];
        sr_cat_column_text(stmt, 15, verdict, sizeof verdict);
        int vd = sr_inspect_verdict_parse(verdict);
        s->verdict = vd < 0 ? SR_INSPECT_REWORK : (sr_inspect_verdict)vd;
        sr_cat_column_text(stmt, 16, s->reasons, sizeof s->reasons);
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        free(v);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "read an inspection's sections");
    if (st != SR_OK) {
        free(v);
        return st;
    }
    *out = v;
    *count = n;
    return SR_OK;
}
