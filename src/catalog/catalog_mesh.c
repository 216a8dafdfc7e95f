/*
 * catalog_mesh.c: the meshes table. A mesh is validated, measured (volume, area,
 * bounding box, closedness) and encoded (src/catalog/mesh_blob.h) before the write
 * transaction starts, so the write lock is held only while SQLite copies the bytes.
 * Loading checks the blob against the row's counts, so a blob edited or damaged on
 * disk is reported, never handed out.
 */
#include "catalog/catalog_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "catalog/mesh_blob.h"

sr_status sr_cat_mesh_row_build(sr_catalog *cat, const sr_mesh *mesh, const char *what,
                                const char *source_file, sr_cat_mesh_row *out, sr_err *err)
{
    sr_status st = sr_mesh_validate(mesh, what, NULL, err);
    if (st != SR_OK)
        return st;
    size_t size = sr_mesh_blob_size(mesh);
    int limit = sqlite3_limit(cat->db, SQLITE_LIMIT_LENGTH, -1);
    if (size == 0 || size > (size_t)limit)
        return sr_err_set(err, SR_E_RANGE,
                          "'%s' is too large for the catalogue (%zu triangles, %zu bytes; the "
                          "limit is %d bytes)",
                          what, mesh->tri_count, size, limit);
    sr_cat_mesh_row row = {0};
    row.fig.vertex_count = mesh->vertex_count;
    row.fig.tri_count = mesh->tri_count;
    sr_mesh_bbox(mesh, row.fig.bbox_min, row.fig.bbox_max);
    row.fig.volume_mm3 = sr_mesh_volume(mesh);
    row.fig.area_mm2 = sr_mesh_area(mesh);
    if (!isfinite(row.fig.volume_mm3) || !isfinite(row.fig.area_mm2))
        return sr_err_set(err, SR_E_RANGE,
                          "'%s' has coordinates too large to measure (volume or area overflows)",
                          what);
    row.closed = sr_mesh_is_closed(mesh) ? 1 : 0;
    row.source_file = source_file;
    row.blob = malloc(size);
    if (!row.blob)
        return sr_err_set(err, SR_E_NOMEM, "cannot store '%s': out of memory (%zu bytes)", what,
                          size);
    row.blob_size = size;
    st = sr_mesh_blob_encode(mesh, row.blob, size);
    if (st != SR_OK) {
        free(row.blob);
        return sr_err_set(err, SR_E_INTERNAL, "cannot encode '%s'", what);
    }
    *out = row;
    return SR_OK;
}

void sr_cat_mesh_row_release(sr_cat_mesh_row *row)
{
    if (!row)
        return;
    free(row->blob);
    memset(row, 0, sizeof *row);
}

sr_status sr_cat_mesh_row_insert(sr_catalog *cat, const sr_cat_mesh_row *row,
                                 int64_t *out_id, sr_err *err)
{
    sqlite3_stmt *stmt;
    /* A mesh in mm (every one symrec builds, and most files) leaves source_unit to the
     * column's DEFAULT 'mm' (sql/005_mesh_units.sql): the row is the same, and the
     * statement also runs on the older schemas the migration tests build. */
    bool mm = row->source_unit == SR_UNIT_DEFAULT || row->source_unit == SR_UNIT_MM;
    sr_status st = sr_cat_prepare(
        cat,
        mm ? "INSERT INTO meshes (vertex_count, tri_count, volume_mm3, area_mm2,"
             " bbox_min_x, bbox_min_y, bbox_min_z, bbox_max_x, bbox_max_y, bbox_max_z,"
             " closed, source_file, format_version, data)"
             " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)"
           : "INSERT INTO meshes (vertex_count, tri_count, volume_mm3, area_mm2,"
             " bbox_min_x, bbox_min_y, bbox_min_z, bbox_max_x, bbox_max_y, bbox_max_z,"
             " closed, source_file, format_version, data, source_unit)"
             " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    const sr_cat_mesh_figures *f = &row->fig;
    sqlite3_bind_int64(stmt, 1, (sqlite3_int64)f->vertex_count);
    sqlite3_bind_int64(stmt, 2, (sqlite3_int64)f->tri_count);
    sqlite3_bind_double(stmt, 3, f->volume_mm3);
    sqlite3_bind_double(stmt, 4, f->area_mm2);
    for (int i = 0; i < 3; i++) {
        sqlite3_bind_double(stmt, 5 + i, f->bbox_min[i]);
        sqlite3_bind_double(stmt, 8 + i, f->bbox_max[i]);
    }
    sqlite3_bind_int(stmt, 11, row->closed);
    sr_cat_bind_opt_text(stmt, 12, row->source_file);
    sqlite3_bind_int(stmt, 13, SR_MESH_BLOB_VERSION);
    if (!mm)
        sqlite3_bind_text(stmt, 15, sr_unit_name(row->source_unit), -1, SQLITE_STATIC);
    /* SQLITE_STATIC: the row outlives the statement, which is finalized below. */
    if (sqlite3_bind_blob64(stmt, 14, row->blob, row->blob_size, SQLITE_STATIC) != SQLITE_OK) {
        st = sr_cat_db_error(cat, err, "store a mesh of %zu bytes", row->blob_size);
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_exec(cat, stmt, err, "store a mesh");
    if (st != SR_OK)
        return st;
    *out_id = sqlite3_last_insert_rowid(cat->db);
    return SR_OK;
}

void sr_cat_column_figures(sqlite3_stmt *stmt, int col, sr_cat_mesh_figures *out)
{
    out->vertex_count = (size_t)sqlite3_column_int64(stmt, col);
    out->tri_count = (size_t)sqlite3_column_int64(stmt, col + 1);
    out->volume_mm3 = sqlite3_column_double(stmt, col + 2);
    out->area_mm2 = sqlite3_column_double(stmt, col + 3);
    for (int i = 0; i < 3; i++) {
        out->bbox_min[i] = sqlite3_column_double(stmt, col + 4 + i);
        out->bbox_max[i] = sqlite3_column_double(stmt, col + 7 + i);
    }
}

sr_status sr_cat_mesh_from_row(sr_catalog *cat, sqlite3_stmt *stmt, int col, int64_t mesh_id,
                               sr_mesh *out, sr_err *err)
{
    sqlite3_int64 v = sqlite3_column_int64(stmt, col);
    sqlite3_int64 t = sqlite3_column_int64(stmt, col + 1);
    int version = sqlite3_column_int(stmt, col + 2);
    if (version != SR_MESH_BLOB_VERSION)
        return sr_err_set(err, SR_E_UNSUPPORTED,
                          "cannot load mesh %lld from '%s': blob format version %d, this symrec "
                          "reads %d: upgrade symrec",
                          (long long)mesh_id, cat->path, version, SR_MESH_BLOB_VERSION);
    const void *blob = sqlite3_column_blob(stmt, col + 3);
    if (!blob && sqlite3_errcode(cat->db) == SQLITE_NOMEM)
        return sr_err_set(err, SR_E_NOMEM, "cannot load mesh %lld from '%s': out of memory",
                          (long long)mesh_id, cat->path);
    size_t size = (size_t)sqlite3_column_bytes(stmt, col + 3);
    sr_err detail;
    sr_mesh m;
    sr_status st = sr_mesh_blob_decode(blob, size, &m, &detail);
    if (st != SR_OK)
        return sr_err_set(err, st, "cannot load mesh %lld from '%s': %s", (long long)mesh_id,
                          cat->path, detail.msg);
    if ((sqlite3_int64)m.vertex_count != v || (sqlite3_int64)m.tri_count != t) {
        sr_err_set(err, SR_E_FORMAT,
                   "cannot load mesh %lld from '%s': the row says %lld vertices and %lld "
                   "triangles, its blob holds %zu and %zu",
                   (long long)mesh_id, cat->path, (long long)v, (long long)t, m.vertex_count,
                   m.tri_count);
        sr_mesh_release(&m);
        return SR_E_FORMAT;
    }
    *out = m;
    return SR_OK;
}

sr_status sr_catalog_mesh_load(sr_catalog *cat, int64_t mesh_id, sr_mesh *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "SELECT vertex_count, tri_count, format_version, data FROM meshes WHERE id = ?1",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, mesh_id);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "load a mesh");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no mesh %lld in the catalogue", (long long)mesh_id);
    sr_mesh m;
    if (st == SR_OK)
        st = sr_cat_mesh_from_row(cat, stmt, 0, mesh_id, &m, err);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "load a mesh");
    if (st != SR_OK) {
        sr_mesh_release(&m);
        return st;
    }
    *out = m;
    return SR_OK;
}
