/*
 * catalog_runs.c: the record of reconstruction runs (tables runs, run_layers, sections,
 * advice of sql/001_init.sql; API in catalog_runs.h).
 *
 * Writing a run: every field is checked and every mesh (restored part, patches) is
 * validated and encoded before the write transaction, so a bad run is refused with
 * SR_E_RANGE / SR_E_INVALID naming the field and nothing is touched. Then one
 * BEGIN IMMEDIATE transaction inserts the restored mesh, the run row, its layers, each
 * section with its patch mesh, and the advice (section_index resolved to the section
 * row just written, a rule id checked against repair_rules); any failure in there rolls
 * the whole run back, so a run is in the catalogue completely or not at all.
 *
 * Blobs: the alignment is 12 little-endian doubles (96 bytes, 3 by 4 row-major); a
 * layer's outlines are sectors by (x, y) little-endian doubles each, NaN where a sector
 * has no point. They are encoded byte by byte so the file reads the same on any host.
 *
 * Reading a run back gives sections and advice always, the layers and the meshes on
 * request (they are the bulk of a run). Listings read one summary row per run with the
 * section count, the missing volume and the process advised for section 0.
 */
#include "catalog/catalog_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "catalog/catalog_runs.h"
#include "base/version.h"

/* ---- little-endian doubles ---- */

static void put_f64(unsigned char *p, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    for (int i = 0; i < 8; i++)
        p[i] = (unsigned char)(u >> (8 * i));
}

static double get_f64(const unsigned char *p)
{
    uint64_t u = 0;
    for (int i = 0; i < 8; i++)
        u |= (uint64_t)p[i] << (8 * i);
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

/* ---- checks before the transaction ---- */

/* True when a fixed field holds a NUL-terminated string of at least min bytes. */
static bool field_ok(const char *field, size_t size, size_t min)
{
    const char *nul = memchr(field, '\0', size);
    return nul && (size_t)(nul - field) >= min;
}

/* Asks SQLite's json_valid about an optional JSON text (the same test as the
 * schema's CHECK, so a text accepted here is never refused by the table). */
static sr_status json_ok(sr_catalog *cat, const char *text, const char *what, sr_err *err)
{
    if (!text)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "SELECT json_valid(?1)", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, text, -1, SQLITE_STATIC);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "check JSON");
    int valid = st == SR_OK && row ? sqlite3_column_int(stmt, 0) : 0;
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "check JSON");
    if (st == SR_OK && !valid)
        st = sr_err_set(err, SR_E_RANGE, "bad %s: not valid JSON", what);
    return st;
}

static bool finite_nonneg(double x)
{
    return isfinite(x) && x >= 0;
}

static sr_status check_section(sr_catalog *cat, const sr_run_section *s, size_t i, sr_err *err)
{
    if (s->layer_last < s->layer_first)
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: layer_last %zu < layer_first %zu",
                          i, s->layer_last, s->layer_first);
    if (s->layer_last > INT64_MAX || s->index > INT64_MAX)
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: index or layer out of range", i);
    if (!isfinite(s->z_min_mm) || !isfinite(s->z_max_mm) || s->z_max_mm < s->z_min_mm)
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: z range %g..%g mm", i, s->z_min_mm,
                          s->z_max_mm);
    if (s->has_angles) {
        double from = s->angle_from_deg, to = s->angle_to_deg;
        if (!(from >= 0 && from < 360) || !(to >= from && to - from <= 360))
            return sr_err_set(err, SR_E_RANGE,
                              "bad section %zu: angles %g..%g deg (expected from in [0, 360), "
                              "from <= to <= from + 360)",
                              i, from, to);
    }
    if (s->side < -1 || s->side > 1)
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: side %d (expected -1, 0 or 1)", i,
                          s->side);
    if (!finite_nonneg(s->volume_mm3))
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: volume_mm3 %g", i, s->volume_mm3);
    if (!finite_nonneg(s->area_mm2))
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: area_mm2 %g", i, s->area_mm2);
    if (!finite_nonneg(s->depth_max_mm))
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: depth_max_mm %g", i,
                          s->depth_max_mm);
    if (!finite_nonneg(s->depth_mean_mm))
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: depth_mean_mm %g", i,
                          s->depth_mean_mm);
    if (!field_ok(s->damage_class, sizeof s->damage_class, 1))
        return sr_err_set(err, SR_E_RANGE, "bad section %zu: damage_class must be 1..%zu bytes",
                          i, sizeof s->damage_class - 1);
    char what[64];
    snprintf(what, sizeof what, "features_json of section %zu", i);
    return json_ok(cat, s->features_json, what, err);
}

static sr_status check_run(sr_catalog *cat, const sr_run *run, sr_err *err)
{
    if (run->instance_id <= 0)
        return sr_err_set(err, SR_E_RANGE, "bad instance_id %lld: a run needs an instance",
                          (long long)run->instance_id);
    if (run->symmetry.kind == SR_SYM_NONE)
        return sr_err_set(err, SR_E_RANGE, "bad symmetry: a run needs axial, mirror or glide");
    sr_status st = sr_symmetry_check(&run->symmetry, err);
    if (st != SR_OK)
        return st;
    sr_err detail;
    st = sr_params_check(&run->params, &detail);
    if (st != SR_OK)
        return sr_err_set(err, st, "bad params: %s", detail.msg);
    if (!field_ok(run->method, sizeof run->method, 1))
        return sr_err_set(err, SR_E_RANGE, "bad method: expected 1..%zu bytes",
                          sizeof run->method - 1);
    if (run->has_alignment)
        for (int i = 0; i < 12; i++)
            if (!isfinite(run->alignment[i]))
                return sr_err_set(err, SR_E_RANGE, "bad alignment: element %d is not finite", i);
    if (run->alignment_given != 0 && run->alignment_given != 1)
        return sr_err_set(err, SR_E_RANGE, "bad alignment_given %d: expected 0 or 1",
                          run->alignment_given);
    if (isnan(run->fit_quality) || run->fit_quality > 1)
        return sr_err_set(err, SR_E_RANGE, "bad fit_quality %g: expected 0..1 (< 0 = none)",
                          run->fit_quality);
    if (run->ok != 0 && run->ok != 1)
        return sr_err_set(err, SR_E_RANGE, "bad ok %d: expected 0 or 1", run->ok);
    if (!field_ok(run->error, sizeof run->error, run->ok ? 0 : 1))
        return sr_err_set(err, SR_E_RANGE, "bad error: a failed run needs its error line");
    if (!field_ok(run->software_version, sizeof run->software_version, 0) ||
        !field_ok(run->started_at, sizeof run->started_at, 0) ||
        !field_ok(run->finished_at, sizeof run->finished_at, 0))
        return sr_err_set(err, SR_E_RANGE,
                          "bad software_version, started_at or finished_at: not terminated");
    if (run->finished_at[0] && run->started_at[0] &&
        strcmp(run->finished_at, run->started_at) < 0)
        return sr_err_set(err, SR_E_RANGE, "bad finished_at '%s': before started_at '%s'",
                          run->finished_at, run->started_at);
    st = json_ok(cat, run->timings_json, "timings_json", err);
    if (st != SR_OK)
        return st;

    if (run->layer_count > 0) {
        if (run->sectors < 1 || !run->layer_z || !run->damaged_xy || !run->restored_xy)
            return sr_err_set(err, SR_E_RANGE,
                              "bad layers: %zu layers need sectors >= 1 and the z, damaged "
                              "and restored arrays",
                              run->layer_count);
        if (run->sectors > SIZE_MAX / 16 / run->layer_count ||
            run->sectors * 16 > (size_t)sqlite3_limit(cat->db, SQLITE_LIMIT_LENGTH, -1))
            return sr_err_set(err, SR_E_RANGE, "bad layers: %zu sectors is too many",
                              run->sectors);
        for (size_t l = 0; l < run->layer_count; l++)
            if (!isfinite(run->layer_z[l]))
                return sr_err_set(err, SR_E_RANGE, "bad layer_z of layer %zu: not finite", l);
    }
    if (run->section_count > 0 && !run->sections)
        return sr_err_set(err, SR_E_RANGE, "bad sections: %zu sections and no array",
                          run->section_count);
    for (size_t i = 0; i < run->section_count; i++) {
        st = check_section(cat, &run->sections[i], i, err);
        if (st != SR_OK)
            return st;
        for (size_t k = 0; k < i; k++)
            if (run->sections[k].index == run->sections[i].index)
                return sr_err_set(err, SR_E_RANGE,
                                  "bad section %zu: index %zu is used by section %zu too", i,
                                  run->sections[i].index, k);
    }
    if (run->advice_count > 0 && !run->advice)
        return sr_err_set(err, SR_E_RANGE, "bad advice: %zu entries and no array",
                          run->advice_count);
    for (size_t i = 0; i < run->advice_count; i++) {
        const sr_run_advice *a = &run->advice[i];
        if (a->section_index < -1)
            return sr_err_set(err, SR_E_RANGE, "bad advice %zu: section_index %ld", i,
                              a->section_index);
        if (a->section_index >= 0) {
            bool found = false;
            for (size_t k = 0; k < run->section_count && !found; k++)
                found = run->sections[k].index == (size_t)a->section_index;
            if (!found)
                return sr_err_set(err, SR_E_RANGE,
                                  "bad advice %zu: no section with index %ld in the run", i,
                                  a->section_index);
        }
        if (a->rule_id < 0)
            return sr_err_set(err, SR_E_RANGE, "bad advice %zu: rule_id %lld", i,
                              (long long)a->rule_id);
        if (!field_ok(a->process, sizeof a->process, 1))
            return sr_err_set(err, SR_E_RANGE, "bad advice %zu: process must be 1..%zu bytes", i,
                              sizeof a->process - 1);
        if (!field_ok(a->reason, sizeof a->reason, 0))
            return sr_err_set(err, SR_E_RANGE, "bad advice %zu: reason not terminated", i);
        char what[64];
        snprintf(what, sizeof what, "details_json of advice %zu", i);
        st = json_ok(cat, a->details_json, what, err);
        if (st != SR_OK)
            return st;
    }
    return SR_OK;
}

/* ---- writing ---- */

/* Meshes of a run made ready before the transaction. */
typedef struct mesh_rows {
    sr_cat_mesh_row restored;
    bool have_restored;
    sr_cat_mesh_row *patch;     /* section_count rows; zeroed = no patch */
    size_t count;
} mesh_rows;

static void mesh_rows_release(mesh_rows *m)
{
    sr_cat_mesh_row_release(&m->restored);
    for (size_t i = 0; i < m->count; i++)
        sr_cat_mesh_row_release(&m->patch[i]);
    free(m->patch);
    memset(m, 0, sizeof *m);
}

static sr_status mesh_rows_build(sr_catalog *cat, const sr_run *run, mesh_rows *out,
                                 sr_err *err)
{
    memset(out, 0, sizeof *out);
    sr_status st = SR_OK;
    if (run->restored.tri_count > 0) {
        st = sr_cat_mesh_row_build(cat, &run->restored, "restored mesh", NULL, &out->restored,
                                   err);
        if (st != SR_OK)
            return st;
        out->have_restored = true;
    }
    if (run->section_count == 0)
        return SR_OK;
    out->patch = calloc(run->section_count, sizeof *out->patch);
    if (!out->patch) {
        mesh_rows_release(out);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu sections", run->section_count);
    }
    out->count = run->section_count;
    for (size_t i = 0; i < run->section_count; i++) {
        if (run->sections[i].patch.tri_count == 0)
            continue;
        char what[64];
        snprintf(what, sizeof what, "patch of section %zu", i);
        st = sr_cat_mesh_row_build(cat, &run->sections[i].patch, what, NULL, &out->patch[i], err);
        if (st != SR_OK) {
            mesh_rows_release(out);
            return st;
        }
    }
    return SR_OK;
}

/* SR_OK when `sql` (one bound id) returns a row, else SR_E_NOTFOUND "no <noun> N in
 * the catalogue". */
static sr_status must_exist(sr_catalog *cat, const char *sql, int64_t id, const char *noun,
                            sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "record a run");
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "record a run");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no %s %lld in the catalogue", noun, (long long)id);
    return st;
}

static sr_status insert_run_row(sr_catalog *cat, const sr_run *run, int64_t restored_id,
                                int64_t *out_id, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "INSERT INTO runs (instance_id, symmetry_kind, symmetry_order, symmetry_shift_mm,"
        " params_name, layers, sectors, gamma_axis, gamma_plane, delta_d, min_depth_mm,"
        " min_volume_mm3, method, alignment, alignment_given, fit_quality, status, error,"
        " software_version, started_at, finished_at, restored_mesh_id, timings_json)"
        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16,"
        " ?17, ?18, ?19, coalesce(?20, strftime('%Y-%m-%dT%H:%M:%SZ', 'now')), ?21, ?22, ?23)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    const sr_params *p = &run->params;
    sqlite3_bind_int64(stmt, 1, run->instance_id);
    sqlite3_bind_text(stmt, 2, sr_sym_kind_name(run->symmetry.kind), -1, SQLITE_STATIC);
    sqlite3_bind_int(stmt, 3, run->symmetry.kind == SR_SYM_AXIAL ? run->symmetry.order : 0);
    sqlite3_bind_double(stmt, 4, run->symmetry.kind == SR_SYM_GLIDE ? run->symmetry.shift_mm : 0);
    sqlite3_bind_text(stmt, 5, p->name, -1, SQLITE_STATIC);
    sqlite3_bind_int(stmt, 6, p->layers);
    sqlite3_bind_int(stmt, 7, p->sectors);
    sqlite3_bind_double(stmt, 8, p->gamma_axis);
    sqlite3_bind_double(stmt, 9, p->gamma_plane);
    sqlite3_bind_double(stmt, 10, p->delta_d);
    sqlite3_bind_double(stmt, 11, p->min_depth_mm);
    sqlite3_bind_double(stmt, 12, p->min_volume_mm3);
    sqlite3_bind_text(stmt, 13, run->method, -1, SQLITE_STATIC);
    unsigned char blob[96];
    if (run->has_alignment) {
        for (int i = 0; i < 12; i++)
            put_f64(blob + 8 * i, run->alignment[i]);
        sqlite3_bind_blob(stmt, 14, blob, sizeof blob, SQLITE_STATIC);
    }
    sqlite3_bind_int(stmt, 15, run->alignment_given);
    if (run->fit_quality >= 0)
        sqlite3_bind_double(stmt, 16, run->fit_quality);
    sqlite3_bind_text(stmt, 17, run->ok ? "ok" : "failed", -1, SQLITE_STATIC);
    if (!run->ok)
        sqlite3_bind_text(stmt, 18, run->error, -1, SQLITE_STATIC);
    sqlite3_bind_text(stmt, 19, run->software_version[0] ? run->software_version : SR_VERSION,
                      -1, SQLITE_STATIC);
    sr_cat_bind_opt_text(stmt, 20, run->started_at);
    sr_cat_bind_opt_text(stmt, 21, run->finished_at);
    if (restored_id)
        sqlite3_bind_int64(stmt, 22, restored_id);
    if (run->timings_json)
        sqlite3_bind_text(stmt, 23, run->timings_json, -1, SQLITE_STATIC);
    st = sr_cat_exec(cat, stmt, err, "record a run");
    if (st == SR_OK)
        *out_id = sqlite3_last_insert_rowid(cat->db);
    return st;
}

static sr_status insert_layers(sr_catalog *cat, const sr_run *run, int64_t run_id, sr_err *err)
{
    if (run->layer_count == 0)
        return SR_OK;
    size_t bytes = run->sectors * 16;
    unsigned char *dam = malloc(bytes), *res = malloc(bytes);
    if (!dam || !res) {
        free(dam);
        free(res);
        return sr_err_set(err, SR_E_NOMEM, "out of memory for a layer of %zu sectors",
                          run->sectors);
    }
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "INSERT INTO run_layers (run_id, layer_index, z_mm, damaged,"
                                  " restored) VALUES (?1, ?2, ?3, ?4, ?5)",
                                  &stmt, err);
    for (size_t l = 0; st == SR_OK && l < run->layer_count; l++) {
        const double *d = run->damaged_xy + l * run->sectors * 2;
        const double *r = run->restored_xy + l * run->sectors * 2;
        for (size_t k = 0; k < 2 * run->sectors; k++) {
            put_f64(dam + 8 * k, d[k]);
            put_f64(res + 8 * k, r[k]);
        }
        sqlite3_reset(stmt);
        sqlite3_bind_int64(stmt, 1, run_id);
        sqlite3_bind_int64(stmt, 2, (sqlite3_int64)l);
        sqlite3_bind_double(stmt, 3, run->layer_z[l]);
        sqlite3_bind_blob64(stmt, 4, dam, bytes, SQLITE_STATIC);
        sqlite3_bind_blob64(stmt, 5, res, bytes, SQLITE_STATIC);
        st = sr_cat_step(cat, stmt, NULL, err, "record a run's layers");
    }
    if (stmt) {
        if (st == SR_OK)
            st = sr_cat_finish(cat, stmt, err, "record a run's layers");
        else
            sqlite3_finalize(stmt);
    }
    free(dam);
    free(res);
    return st;
}

static sr_status insert_section(sr_catalog *cat, const sr_run_section *s, int64_t run_id,
                                int64_t patch_id, int64_t *out_id, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "INSERT INTO sections (run_id, section_index, layer_first, layer_last, z_min_mm,"
        " z_max_mm, angle_from_deg, angle_to_deg, side, volume_mm3, area_mm2, depth_max_mm,"
        " depth_mean_mm, class, patch_mesh_id, features_json)"
        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    sqlite3_bind_int64(stmt, 2, (sqlite3_int64)s->index);
    sqlite3_bind_int64(stmt, 3, (sqlite3_int64)s->layer_first);
    sqlite3_bind_int64(stmt, 4, (sqlite3_int64)s->layer_last);
    sqlite3_bind_double(stmt, 5, s->z_min_mm);
    sqlite3_bind_double(stmt, 6, s->z_max_mm);
    if (s->has_angles) {
        sqlite3_bind_double(stmt, 7, s->angle_from_deg);
        sqlite3_bind_double(stmt, 8, s->angle_to_deg);
    }
    if (s->side)
        sqlite3_bind_int(stmt, 9, s->side);
    sqlite3_bind_double(stmt, 10, s->volume_mm3);
    sqlite3_bind_double(stmt, 11, s->area_mm2);
    sqlite3_bind_double(stmt, 12, s->depth_max_mm);
    sqlite3_bind_double(stmt, 13, s->depth_mean_mm);
    sqlite3_bind_text(stmt, 14, s->damage_class, -1, SQLITE_STATIC);
    if (patch_id)
        sqlite3_bind_int64(stmt, 15, patch_id);
    if (s->features_json)
        sqlite3_bind_text(stmt, 16, s->features_json, -1, SQLITE_STATIC);
    st = sr_cat_exec(cat, stmt, err, "record a run's sections");
    if (st == SR_OK)
        *out_id = sqlite3_last_insert_rowid(cat->db);
    return st;
}

static sr_status insert_advice(sr_catalog *cat, const sr_run_advice *a, int64_t run_id,
                               int64_t section_id, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "INSERT INTO advice (run_id, section_id, rule_id, process,"
                                  " reason, details_json)"
                                  " VALUES (?1, ?2, ?3, ?4, ?5, coalesce(?6, '{}'))",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    if (section_id)
        sqlite3_bind_int64(stmt, 2, section_id);
    if (a->rule_id)
        sqlite3_bind_int64(stmt, 3, a->rule_id);
    sqlite3_bind_text(stmt, 4, a->process, -1, SQLITE_STATIC);
    sqlite3_bind_text(stmt, 5, a->reason, -1, SQLITE_STATIC);
    if (a->details_json)
        sqlite3_bind_text(stmt, 6, a->details_json, -1, SQLITE_STATIC);
    return sr_cat_exec(cat, stmt, err, "record a run's advice");
}

sr_status sr_catalog_run_add(sr_catalog *cat, const sr_run *run, int64_t *out_id, sr_err *err)
{
    sr_status st = check_run(cat, run, err);
    if (st != SR_OK)
        return st;
    mesh_rows meshes;
    st = mesh_rows_build(cat, run, &meshes, err);
    if (st != SR_OK)
        return st;
    int64_t *section_ids = NULL;
    if (run->section_count > 0) {
        section_ids = calloc(run->section_count, sizeof *section_ids);
        if (!section_ids) {
            mesh_rows_release(&meshes);
            return sr_err_set(err, SR_E_NOMEM, "out of memory for %zu sections",
                              run->section_count);
        }
    }

    st = sr_cat_begin(cat, err);
    if (st != SR_OK) {
        mesh_rows_release(&meshes);
        free(section_ids);
        return st;
    }
    int64_t run_id = 0, restored_id = 0;
    st = must_exist(cat, "SELECT 1 FROM instances WHERE id = ?1", run->instance_id,
                    "instance", err);
    if (st == SR_OK && meshes.have_restored)
        st = sr_cat_mesh_row_insert(cat, &meshes.restored, &restored_id, err);
    if (st == SR_OK)
        st = insert_run_row(cat, run, restored_id, &run_id, err);
    if (st == SR_OK)
        st = insert_layers(cat, run, run_id, err);
    for (size_t i = 0; st == SR_OK && i < run->section_count; i++) {
        int64_t patch_id = 0;
        if (meshes.patch[i].blob)
            st = sr_cat_mesh_row_insert(cat, &meshes.patch[i], &patch_id, err);
        if (st == SR_OK)
            st = insert_section(cat, &run->sections[i], run_id, patch_id, &section_ids[i], err);
    }
    for (size_t i = 0; st == SR_OK && i < run->advice_count; i++) {
        const sr_run_advice *a = &run->advice[i];
        int64_t section_id = 0;
        for (size_t k = 0; a->section_index >= 0 && k < run->section_count; k++)
            if (run->sections[k].index == (size_t)a->section_index)
                section_id = section_ids[k];
        if (a->rule_id)
            st = must_exist(cat, "SELECT 1 FROM repair_rules WHERE id = ?1", a->rule_id,
                            "repair rule", err);
        if (st == SR_OK)
            st = insert_advice(cat, a, run_id, section_id, err);
    }
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        sr_cat_rollback(cat);
    mesh_rows_release(&meshes);
    free(section_ids);
    if (st == SR_OK && out_id)
        *out_id = run_id;
    return st;
}

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
 * 23 timings_json, 24..27 restored mesh vertex_count, tri_count, format, data. */
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
        " CASE WHEN ?2 THEN me.data END"
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
            r->alignment[i] = get_f64(b + 8 * i);
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
            r->damaged_xy[n * sectors * 2 + k] = get_f64(d + 8 * k);
            r->restored_xy[n * sectors * 2 + k] = get_f64(s + 8 * k);
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
        "           WHERE a.run_id = r.id AND s.section_index = 0 ORDER BY a.id LIMIT 1), '')"
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
