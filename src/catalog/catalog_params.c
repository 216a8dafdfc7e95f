/*
 * catalog_params.c: named parameter sets (table parameter_sets): storage only:
 * get, put (insert or replace by name, ignoring ASCII case) and list. The seeded
 * sets 'coarse', 'medium' and 'default' come from sql/001_init.sql. The range checks
 * are sr_params_check's (src/run/run.c), the same as the table's CHECK constraints, so
 * a set that passes them is never refused by the database.
 */
#include "catalog/catalog_int.h"

#include <string.h>

#define PARAMS_COLUMNS                                                                  \
    "name, layers, sectors, gamma_axis, gamma_plane, delta_d, min_depth_mm, min_volume_mm3," \
    " notes"

static void read_params(sqlite3_stmt *stmt, sr_params *out)
{
    memset(out, 0, sizeof *out);
    sr_cat_column_text(stmt, 0, out->name, sizeof out->name);
    out->layers = sqlite3_column_int(stmt, 1);
    out->sectors = sqlite3_column_int(stmt, 2);
    out->gamma_axis = sqlite3_column_double(stmt, 3);
    out->gamma_plane = sqlite3_column_double(stmt, 4);
    out->delta_d = sqlite3_column_double(stmt, 5);
    out->min_depth_mm = sqlite3_column_double(stmt, 6);
    out->min_volume_mm3 = sqlite3_column_double(stmt, 7);
    sr_cat_column_text(stmt, 8, out->notes, sizeof out->notes);
}

sr_status sr_catalog_params_get(sr_catalog *cat, const char *name, sr_params *out,
                                sr_err *err)
{
    if (!name || !*name)
        return sr_err_set(err, SR_E_NOTFOUND, "no parameter set given");
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "SELECT " PARAMS_COLUMNS " FROM parameter_sets WHERE name = ?1", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, name, -1, SQLITE_TRANSIENT);
    bool row;
    sr_params p;
    st = sr_cat_step(cat, stmt, &row, err, "read a parameter set");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no parameter set '%s' in the catalogue", name);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    read_params(stmt, &p);
    st = sr_cat_finish(cat, stmt, err, "read a parameter set");
    if (st != SR_OK)
        return st;
    *out = p;
    return SR_OK;
}

sr_status sr_catalog_params_put(sr_catalog *cat, const sr_params *p, sr_err *err)
{
    sr_status st = sr_params_check(p, err);
    if (st != SR_OK)
        return st;
    st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    sqlite3_stmt *stmt;
    st = sr_cat_prepare(cat,
                        "INSERT INTO parameter_sets (" PARAMS_COLUMNS ")"
                        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)"
                        " ON CONFLICT (name) DO UPDATE SET name = excluded.name,"
                        " layers = excluded.layers, sectors = excluded.sectors,"
                        " gamma_axis = excluded.gamma_axis, gamma_plane = excluded.gamma_plane,"
                        " delta_d = excluded.delta_d, min_depth_mm = excluded.min_depth_mm,"
                        " min_volume_mm3 = excluded.min_volume_mm3, notes = excluded.notes",
                        &stmt, err);
    if (st != SR_OK)
        goto fail;
    sqlite3_bind_text(stmt, 1, p->name, -1, SQLITE_TRANSIENT);
    sqlite3_bind_int(stmt, 2, p->layers);
    sqlite3_bind_int(stmt, 3, p->sectors);
    sqlite3_bind_double(stmt, 4, p->gamma_axis);
    sqlite3_bind_double(stmt, 5, p->gamma_plane);
    sqlite3_bind_double(stmt, 6, p->delta_d);
    sqlite3_bind_double(stmt, 7, p->min_depth_mm);
    sqlite3_bind_double(stmt, 8, p->min_volume_mm3);
    sqlite3_bind_text(stmt, 9, p->notes, -1, SQLITE_TRANSIENT);
    st = sr_cat_exec(cat, stmt, err, "store a parameter set");
    if (st != SR_OK)
        goto fail;
    st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        goto fail;
    return SR_OK;
fail:
    sr_cat_rollback(cat);
    return st;
}

sr_status sr_catalog_params_list(sr_catalog *cat, sr_params_fn fn, void *user, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "SELECT " PARAMS_COLUMNS " FROM parameter_sets ORDER BY name", &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "list parameter sets");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            break;
        sr_params p;
        read_params(stmt, &p);
        if (fn(&p, user))
            break;
    }
    return sr_cat_finish(cat, stmt, err, "list parameter sets");
}
