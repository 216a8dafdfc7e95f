/*
 * catalog_runs.c: writing the record of reconstruction runs (tables runs, run_layers,
 * sections, advice of sql/001_init.sql; API in catalog_runs.h) and the byte codec of its
 * blobs (sr_cat_put_f64 / sr_cat_get_f64, catalog_int.h). Reading runs back (one run,
 * its restored mesh, listings, the count) is in catalog_run_read.c.
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

void sr_cat_put_f64(unsigned char *p, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    for (int i = 0; i < 8; i++)
        p[i] = (unsigned char)(u >> (8 * i));
}

double sr_cat_get_f64(const unsigned char *p)
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
    if (!(run->unbuilt_mm3 >= 0) || !isfinite(run->unbuilt_mm3))
        return sr_err_set(err, SR_E_RANGE, "bad unbuilt_mm3 %g: expected a volume >= 0",
                          run->unbuilt_mm3);
    st = json_ok(cat, run->timings_json, "timings_json", err);
    if (st == SR_OK)
        st = json_ok(cat, run->symmetry_fit_json, "symmetry_fit_json", err);
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
            sr_cat_put_f64(blob + 8 * i, run->alignment[i]);
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
            sr_cat_put_f64(dam + 8 * k, d[k]);
            sr_cat_put_f64(res + 8 * k, r[k]);
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

/* The proposal of `--symmetry auto` (sql/007_symmetry_proposal.sql): the columns are
 * read out of the fit's JSON object by SQLite, so they cannot disagree with it. */
static sr_status insert_symmetry_fit(sr_catalog *cat, const char *fit_json, int64_t run_id,
                                     sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "INSERT INTO run_symmetry_fit (run_id, kind, order_n, shift_mm, confidence,"
        " ambiguous, alternative, fit_json) VALUES (?1, json_extract(?2, '$.proposal.kind'),"
        " coalesce(json_extract(?2, '$.proposal.order'), 0),"
        " coalesce(json_extract(?2, '$.proposal.shift_mm'), 0),"
        " json_extract(?2, '$.confidence'), json_extract(?2, '$.ambiguous'),"
        " json_extract(?2, '$.alternative.kind'), ?2)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    sqlite3_bind_text(stmt, 2, fit_json, -1, SQLITE_STATIC);
    return sr_cat_exec(cat, stmt, err, "record a run's symmetry proposal");
}

/* The sections the run found and could not build (sql/013_unbuilt_sections.sql); no
 * row when there were none. */
static sr_status insert_unbuilt(sr_catalog *cat, const sr_run *run, int64_t run_id, sr_err *err)
{
    if (run->unbuilt_sections == 0)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "INSERT INTO run_unbuilt (run_id, sections, volume_mm3) VALUES (?1, ?2, ?3)", &stmt,
        err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, run_id);
    sqlite3_bind_int64(stmt, 2, (sqlite3_int64)run->unbuilt_sections);
    sqlite3_bind_double(stmt, 3, run->unbuilt_mm3);
    return sr_cat_exec(cat, stmt, err, "record a run's unbuilt sections");
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
    if (st == SR_OK && run->symmetry_fit_json)
        st = insert_symmetry_fit(cat, run->symmetry_fit_json, run_id, err);
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
        st = sr_cat_nominal_insert(cat, run->nominal, run_id, err);
    if (st == SR_OK)
        st = sr_cat_scan_insert(cat, run->scan, run_id, err);
    if (st == SR_OK)
        st = insert_unbuilt(cat, run, run_id, err);
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
