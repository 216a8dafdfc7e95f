/*
 * catalog_run_read.c: reading the record of reconstruction runs back (API in
 * catalog_runs.h; catalog_runs.c writes it and owns the blob codec, catalog_int.h):
 * one run (sr_catalog_run_get), its restored mesh alone, the listing and the count.
 *
 * Reading a run back gives sections and advice always, the layers and the meshes on
 * request (they are the bulk of a run). Listings read one summary row per run with the
 * section count, the missing volume and the process advised for section 0.
 */
#include "catalog/catalog_int.h"

#include <stdlib.h>
#include <string.h>

#include "catalog/catalog_runs.h"

/* ---- reading ---- */

/* A copy of a text column, NULL for SQL NULL. *fail set when out of memory. */
static char *column_dup(sqlite3_stmt *stmt, int col, bool *fail)
{
    const unsigned char *t = sqlite3_column_text(stmt, col);
    if (!t)
        return NULL;
    size_t n = (size_t)sqlite3_column_bytes(stmt, col);
    char *s = malloc(n + 1);
    if (!s) {
        *fail = true;
        return NULL;
    }
    memcpy(s, t, n);
    s[n] = '\0';
    return s;
}

/* Columns of the run row: 0 instance_id, 1 part number, 2..4 symmetry, 5..12 params,
 * 13 method, 14 alignment, 15 alignment_given, 16 fit_quality, 17 status, 18 error,
 * 19 software_version, 20 started_at, 21 finished_at, 22 restored_mesh_id,
 * 23 timings_json, 24..27 restored mesh vertex_count, tri_count, format, data,
 * 28 the symmetry proposal's fit_json (sql/007_symmetry_proposal.sql; NULL = none); 29,
 * 30 the sections found and not built (sql/013_unbuilt_sections.sql; 0 = none). */
static sr_status read_run_row(sr_catalog *cat, int64_t id, unsigned what, sr_run *r,
                              sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT r.instance_id, p.number, r.symmetry_kind, r.symmetry_order,"
        " r.symmetry_shift_mm, r.params_name, r.layers, r.sectors, r.gamma_axis,"
        " r.gamma_plane, r.delta_d, r.min_depth_mm, r.min_volume_mm3, r.method, r.alignment,"
        " r.alignment_given, r.fit_quality, r.status, r.error, r.software_version,"
        " r.started_at, r.finished_at, r.restored_mesh_id, r.timings_json,"
        " me.vertex_count, me.tri_count, me.format_version,"
        " CASE WHEN ?2 THEN me.data END,"
        " (SELECT f.fit_json FROM run_symmetry_fit f WHERE f.run_id = r.id),"
        " coalesce((SELECT u.sections FROM run_unbuilt u WHERE u.run_id = r.id), 0),"
        " coalesce((SELECT u.volume_mm3 FROM run_unbuilt u WHERE u.run_id = r.id), 0)"
        " FROM runs r JOIN instances i ON i.id = r.instance_id"
        " JOIN parts p ON p.id = i.part_id"
        " LEFT JOIN meshes me ON me.id = r.restored_mesh_id"
        " WHERE r.id = ?1",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    sqlite3_bind_int(stmt, 2, (what & SR_RUN_WITH_MESHES) ? 1 : 0);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "read a run");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no run %lld in the catalogue", (long long)id);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    r->id = id;
    r->instance_id = sqlite3_column_int64(stmt, 0);
    sr_cat_column_text(stmt, 1, r->part_number, sizeof r->part_number);
    sr_cat_column_symmetry(stmt, 2, &r->symmetry);
    sr_params *p = &r->params;
    sr_cat_column_text(stmt, 5, p->name, sizeof p->name);
    p->layers = sqlite3_column_int(stmt, 6);
    p->sectors = sqlite3_column_int(stmt, 7);
    p->gamma_axis = sqlite3_column_double(stmt, 8);
    p->gamma_plane = sqlite3_column_double(stmt, 9);
    p->delta_d = sqlite3_column_double(stmt, 10);
    p->min_depth_mm = sqlite3_column_double(stmt, 11);
    p->min_volume_mm3 = sqlite3_column_double(stmt, 12);
    sr_cat_column_text(stmt, 13, r->method, sizeof r->method);
    if (sqlite3_column_type(stmt, 14) == SQLITE_BLOB && sqlite3_column_bytes(stmt, 14) == 96) {
        const unsigned char *b = sqlite3_column_blob(stmt, 14);
        r->has_alignment = 1;
        for (int i = 0; i < 12; i++)
            r->alignment[i] = sr_cat_get_f64(b + 8 * i);
    }
    r->alignment_given = sqlite3_column_int(stmt, 15);
    r->fit_quality = sqlite3_column_type(stmt, 16) == SQLITE_NULL
                         ? -1
                         : sqlite3_column_double(stmt, 16);
    const char *status = (const char *)sqlite3_column_text(stmt, 17);
    r->ok = status && strcmp(status, "ok") == 0;
    sr_cat_column_text(stmt, 18, r->error, sizeof r->error);
    sr_cat_column_text(stmt, 19, r->software_version, sizeof r->software_version);
    sr_cat_column_text(stmt, 20, r->started_at, sizeof r->started_at);
    sr_cat_column_text(stmt, 21, r->finished_at, sizeof r->finished_at);
    bool fail = false;
    r->timings_json = column_dup(stmt, 23, &fail);
    r->symmetry_fit_json = column_dup(stmt, 28, &fail);
    r->unbuilt_sections = (size_t)sqlite3_column_int64(stmt, 29);
    r->unbuilt_mm3 = sqlite3_column_double(stmt, 30);
    if (fail)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory reading run %lld", (long long)id);
    if (st == SR_OK && (what & SR_RUN_WITH_MESHES) &&
        sqlite3_column_type(stmt, 22) != SQLITE_NULL)
        st = sr_cat_mesh_from_row(cat, stmt, 24, sqlite3_column_int64(stmt, 22), &r->restored,
                                  err);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, "read a run");
}

static sr_status read_layers(sr_catalog *cat, sr_run *r, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT layer_index, z_mm, damaged, restored,"
                                  " (SELECT count(*) FROM run_layers WHERE run_id = ?1)"
                                  " FROM run_layers WHERE run_id = ?1 ORDER BY layer_index",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, r->id);
    size_t n = 0, count = 0, sectors = 0;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "read a run's layers");
        if (st != SR_OK || !row)
            break;
        size_t bytes = (size_t)sqlite3_column_bytes(stmt, 2);
        if (n == 0) {
            count = (size_t)sqlite3_column_int64(stmt, 4);
            sectors = bytes / 16;
            if (sectors == 0 || count > SIZE_MAX / 16 / sectors) {
                st = sr_err_set(err, SR_E_FORMAT, "cannot read run %lld from '%s': empty layer",
                                (long long)r->id, cat->path);
                break;
            }
            r->layer_z = malloc(count * sizeof *r->layer_z);
            r->damaged_xy = malloc(count * sectors * 2 * sizeof(double));
            r->restored_xy = malloc(count * sectors * 2 * sizeof(double));
            if (!r->layer_z || !r->damaged_xy || !r->restored_xy) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu layers of %zu sectors",
                                count, sectors);
                break;
            }
        }
        if (n >= count || sqlite3_column_int64(stmt, 0) != (sqlite3_int64)n ||
            bytes != sectors * 16 || (size_t)sqlite3_column_bytes(stmt, 3) != bytes) {
            st = sr_err_set(err, SR_E_FORMAT,
                            "cannot read run %lld from '%s': layer %zu is missing or of "
                            "another size",
                            (long long)r->id, cat->path, n);
            break;
        }
        const unsigned char *d = sqlite3_column_blob(stmt, 2);
        const unsigned char *s = sqlite3_column_blob(stmt, 3);
        if (!d || !s) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory reading run %lld", (long long)r->id);
            break;
        }
        r->layer_z[n] = sqlite3_column_double(stmt, 1);
        for (size_t k = 0; k < 2 * sectors; k++) {
            r->damaged_xy[n * sectors * 2 + k] = sr_cat_get_f64(d + 8 * k);
            r->restored_xy[n * sectors * 2 + k] = sr_cat_get_f64(s + 8 * k);
        }
        n++;
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    r->layer_count = n;
    r->sectors = n ? sectors : 0;
    return sr_cat_finish(cat, stmt, err, "read a run's layers");
}

static sr_status read_sections(sr_catalog *cat, sr_run *r, unsigned what, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT s.id, s.section_index, s.layer_first, s.layer_last, s.z_min_mm, s.z_max_mm,"
        " s.angle_from_deg, s.angle_to_deg, s.side, s.volume_mm3, s.area_mm2,"
        " s.depth_max_mm, s.depth_mean_mm, s.class, s.features_json, s.patch_mesh_id,"
        " me.vertex_count, me.tri_count, me.format_version, CASE WHEN ?2 THEN me.data END,"
        " (SELECT count(*) FROM sections WHERE run_id = ?1)"
        " FROM sections s LEFT JOIN meshes me ON me.id = s.patch_mesh_id"
        " WHERE s.run_id = ?1 ORDER BY s.section_index",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, r->id);
    sqlite3_bind_int(stmt, 2, (what & SR_RUN_WITH_MESHES) ? 1 : 0);
    size_t n = 0;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "read a run's sections");
        if (st != SR_OK || !row)
            break;
        if (n == 0) {
            size_t count = (size_t)sqlite3_column_int64(stmt, 20);
            r->sections = calloc(count ? count : 1, sizeof *r->sections);
            if (!r->sections) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu sections", count);
                break;
            }
            r->section_count = count;
        }
        if (n >= r->section_count) {
            st = sr_err_set(err, SR_E_DB, "cannot read run %lld: sections changed while read",
                            (long long)r->id);
            break;
        }
        sr_run_section *s = &r->sections[n++];
        s->id = sqlite3_column_int64(stmt, 0);
        s->index = (size_t)sqlite3_column_int64(stmt, 1);
        s->layer_first = (size_t)sqlite3_column_int64(stmt, 2);
        s->layer_last = (size_t)sqlite3_column_int64(stmt, 3);
        s->z_min_mm = sqlite3_column_double(stmt, 4);
        s->z_max_mm = sqlite3_column_double(stmt, 5);
        s->has_angles = sqlite3_column_type(stmt, 6) != SQLITE_NULL;
        s->angle_from_deg = sqlite3_column_double(stmt, 6);
        s->angle_to_deg = sqlite3_column_double(stmt, 7);
        s->side = sqlite3_column_int(stmt, 8);
        s->volume_mm3 = sqlite3_column_double(stmt, 9);
        s->area_mm2 = sqlite3_column_double(stmt, 10);
        s->depth_max_mm = sqlite3_column_double(stmt, 11);
        s->depth_mean_mm = sqlite3_column_double(stmt, 12);
        sr_cat_column_text(stmt, 13, s->damage_class, sizeof s->damage_class);
        bool fail = false;
        s->features_json = column_dup(stmt, 14, &fail);
        if (fail) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory reading run %lld", (long long)r->id);
            break;
        }
        if ((what & SR_RUN_WITH_MESHES) && sqlite3_column_type(stmt, 15) != SQLITE_NULL) {
            st = sr_cat_mesh_from_row(cat, stmt, 16, sqlite3_column_int64(stmt, 15), &s->patch,
                                      err);
            if (st != SR_OK)
                break;
        }
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    r->section_count = n;
    return sr_cat_finish(cat, stmt, err, "read a run's sections");
}

static sr_status read_advice(sr_catalog *cat, sr_run *r, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT coalesce(s.section_index, -1), coalesce(a.rule_id, 0), coalesce(ru.name, ''),"
        " a.process, a.reason, a.details_json,"
        " (SELECT count(*) FROM advice WHERE run_id = ?1)"
        " FROM advice a LEFT JOIN sections s ON s.id = a.section_id"
        " LEFT JOIN repair_rules ru ON ru.id = a.rule_id"
        " WHERE a.run_id = ?1 ORDER BY a.id",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, r->id);
    size_t n = 0;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "read a run's advice");
        if (st != SR_OK || !row)
            break;
        if (n == 0) {
            size_t count = (size_t)sqlite3_column_int64(stmt, 6);
            r->advice = calloc(count ? count : 1, sizeof *r->advice);
            if (!r->advice) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory for %zu advice", count);
                break;
            }
            r->advice_count = count;
        }
        if (n >= r->advice_count) {
            st = sr_err_set(err, SR_E_DB, "cannot read run %lld: advice changed while read",
                            (long long)r->id);
            break;
        }
        sr_run_advice *a = &r->advice[n++];
        a->section_index = (long)sqlite3_column_int64(stmt, 0);
        a->rule_id = sqlite3_column_int64(stmt, 1);
        sr_cat_column_text(stmt, 2, a->rule_name, sizeof a->rule_name);
        sr_cat_column_text(stmt, 3, a->process, sizeof a->process);
        sr_cat_column_text(stmt, 4, a->reason, sizeof a->reason);
        bool fail = false;
        a->details_json = column_dup(stmt, 5, &fail);
        if (fail) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory reading run %lld", (long long)r->id);
            break;
        }
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    r->advice_count = n;
    return sr_cat_finish(cat, stmt, err, "read a run's advice");
}

sr_status sr_catalog_run_get(sr_catalog *cat, int64_t id, unsigned what, sr_run *out,
                             sr_err *err)
{
    sr_run r;
    memset(&r, 0, sizeof r);
    /* One read transaction, so the parts of the run come from one snapshot; inside a
     * caller's transaction (or a listing's pending read) that one is used instead. */
    bool own = sqlite3_get_autocommit(cat->db) != 0;
    sr_status st = SR_OK;
    if (own) {
        sqlite3_stmt *begin;
        st = sr_cat_prepare(cat, "BEGIN", &begin, err);
        if (st == SR_OK)
            st = sr_cat_exec(cat, begin, err, "read a run");
        if (st != SR_OK)
            return st;
    }
    st = read_run_row(cat, id, what, &r, err);
    if (st == SR_OK && (what & SR_RUN_WITH_LAYERS))
        st = read_layers(cat, &r, err);
    if (st == SR_OK)
        st = read_sections(cat, &r, what, err);
    if (st == SR_OK)
        st = read_advice(cat, &r, err);
    if (st == SR_OK)
        st = sr_cat_nominal_read(cat, &r, err);
    if (st == SR_OK)
        st = sr_cat_scan_read(cat, &r, err);
    if (own) {
        sqlite3_stmt *end;
        sr_status st2 = sr_cat_prepare(cat, "COMMIT", &end, st == SR_OK ? err : NULL);
        if (st2 == SR_OK)
            st2 = sr_cat_exec(cat, end, st == SR_OK ? err : NULL, "read a run");
        if (st == SR_OK)
            st = st2;
        sr_cat_rollback(cat);   /* only if COMMIT failed and left it open */
    }
    if (st != SR_OK) {
        sr_run_release(&r);
        return st;
    }
    *out = r;
    return SR_OK;
}

sr_status sr_catalog_run_restored_mesh(sr_catalog *cat, int64_t id, sr_mesh *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT r.restored_mesh_id, me.vertex_count, me.tri_count,"
                                  " me.format_version, me.data"
                                  " FROM runs r LEFT JOIN meshes me ON me.id = r.restored_mesh_id"
                                  " WHERE r.id = ?1",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    bool row;
    sr_mesh m;
    st = sr_cat_step(cat, stmt, &row, err, "load a run's restored mesh");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no run %lld in the catalogue", (long long)id);
    if (st == SR_OK && sqlite3_column_type(stmt, 0) == SQLITE_NULL)
        st = sr_err_set(err, SR_E_NOTFOUND, "run %lld has no restored mesh in the catalogue",
                        (long long)id);
    if (st == SR_OK)
        st = sr_cat_mesh_from_row(cat, stmt, 1, sqlite3_column_int64(stmt, 0), &m, err);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "load a run's restored mesh");
    if (st != SR_OK) {
        sr_mesh_release(&m);
        return st;
    }
    *out = m;
    return SR_OK;
}

/* ---- listing ---- */

sr_status sr_catalog_run_list(sr_catalog *cat, const sr_run_filter *filter, sr_run_fn fn,
                              void *user, sr_err *err)
{
    int64_t part_id = 0;
    if (filter && filter->part) {
        sr_status st = sr_cat_part_resolve(cat, filter->part, &part_id, err);
        if (st != SR_OK)
            return st;
    }
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "SELECT r.id, r.instance_id, p.number, coalesce(i.serial, ''), coalesce(m.name, ''),"
        " r.symmetry_kind, r.symmetry_order, r.symmetry_shift_mm, r.method, r.status,"
        " r.started_at,"
        " (SELECT count(*) FROM sections s WHERE s.run_id = r.id),"
        " (SELECT coalesce(sum(s.volume_mm3), 0) FROM sections s WHERE s.run_id = r.id),"
        " coalesce((SELECT a.process FROM advice a JOIN sections s ON s.id = a.section_id"
        "           WHERE a.run_id = r.id AND s.section_index = 0 ORDER BY a.id LIMIT 1), ''),"
        " coalesce((SELECT u.sections FROM run_unbuilt u WHERE u.run_id = r.id), 0)"
        " FROM runs r JOIN instances i ON i.id = r.instance_id"
        " JOIN parts p ON p.id = i.part_id"
        " LEFT JOIN materials m ON m.id = p.material_id"
        " WHERE (?1 = 0 OR r.instance_id = ?1) AND (?2 = 0 OR i.part_id = ?2)"
        " ORDER BY r.started_at DESC, r.id DESC",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, filter ? filter->instance_id : 0);
    sqlite3_bind_int64(stmt, 2, part_id);
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "list runs");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            break;
        sr_run_summary s;
        memset(&s, 0, sizeof s);
        s.id = sqlite3_column_int64(stmt, 0);
        s.instance_id = sqlite3_column_int64(stmt, 1);
        sr_cat_column_text(stmt, 2, s.part_number, sizeof s.part_number);
        sr_cat_column_text(stmt, 3, s.serial, sizeof s.serial);
        sr_cat_column_text(stmt, 4, s.material, sizeof s.material);
        sr_cat_column_symmetry(stmt, 5, &s.symmetry);
        sr_cat_column_text(stmt, 8, s.method, sizeof s.method);
        const char *status = (const char *)sqlite3_column_text(stmt, 9);
        s.ok = status && strcmp(status, "ok") == 0;
        sr_cat_column_text(stmt, 10, s.started_at, sizeof s.started_at);
        s.section_count = (size_t)sqlite3_column_int64(stmt, 11);
        s.missing_volume_mm3 = sqlite3_column_double(stmt, 12);
        sr_cat_column_text(stmt, 13, s.process, sizeof s.process);
        s.unbuilt_sections = (size_t)sqlite3_column_int64(stmt, 14);
        if (fn(&s, user))
            break;
    }
    return sr_cat_finish(cat, stmt, err, "list runs");
}

sr_status sr_catalog_run_count(sr_catalog *cat, int64_t *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "SELECT count(*) FROM runs", &stmt, err);
    if (st != SR_OK)
        return st;
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "count runs");
    int64_t n = st == SR_OK && row ? sqlite3_column_int64(stmt, 0) : 0;
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "count runs");
    if (st == SR_OK)
        *out = n;
    return st;
}
