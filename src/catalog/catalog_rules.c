/*
 * catalog_rules.c: repair rules and materials in the catalogue (catalog_rules.h).
 * The table of rule fields is advice/rule.c's (sr_rule_field_at: name = column, kind,
 * place in sr_rule); it drives the reading of rows and the binding of inserts and
 * updates here, so a column added to repair_rules is one line there plus its name in
 * RULE_COLUMNS. The checks are sr_rule_check's; parameters_json is checked again by
 * SQLite's own json_valid before it is written.
 */
#include "catalog/catalog_rules.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/grow.h"
#include "catalog/catalog_int.h"

/* The columns read back: the fields, then id, created_at, updated_at. */
#define RULE_COLUMNS                                                                     \
    "name, priority, enabled, scope, symmetry_kind, class, material, material_family,"   \
    " location, min_volume_mm3, max_volume_mm3, min_depth_mm, max_depth_mm,"             \
    " min_lost_fraction, max_lost_fraction, min_depth_fraction, max_depth_fraction,"     \
    " min_section_fraction, max_section_fraction, feature, feature_min, feature_max,"    \
    " process, parameters_json, reason, source"
#define RULE_PARAMS                                                                      \
    "?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19," \
    " ?20, ?21, ?22, ?23, ?24, ?25, ?26"

/* ---- rows ---- */

static void read_rule(sqlite3_stmt *stmt, sr_rule *r)
{
    sr_rule_init(r);
    sr_rule_field_place f;
    for (size_t i = 0; sr_rule_field_at(i, &f); i++) {
        int col = (int)i;
        char *member = (char *)r + f.offset;
        bool is_null = sqlite3_column_type(stmt, col) == SQLITE_NULL;
        switch (f.kind) {
        case SR_RULE_FIELD_INT:
            *(int *)member = sqlite3_column_int(stmt, col);
            break;
        case SR_RULE_FIELD_NUMBER:
            *(double *)member = is_null ? NAN : sqlite3_column_double(stmt, col);
            break;
        default:
            sr_cat_column_text(stmt, col, member, f.size);
        }
    }
    size_t n = 0;
    while (sr_rule_field_name(n))
        n++;
    r->id = sqlite3_column_int64(stmt, (int)n);
    sr_cat_column_text(stmt, (int)n + 1, r->created_at, sizeof r->created_at);
    sr_cat_column_text(stmt, (int)n + 2, r->updated_at, sizeof r->updated_at);
}

static void bind_rule(sqlite3_stmt *stmt, const sr_rule *r)
{
    sr_rule_field_place f;
    for (size_t i = 0; sr_rule_field_at(i, &f); i++) {
        int idx = (int)i + 1;
        const char *member = (const char *)r + f.offset;
        switch (f.kind) {
        case SR_RULE_FIELD_INT:
            sqlite3_bind_int(stmt, idx, *(const int *)member);
            break;
        case SR_RULE_FIELD_NUMBER:
            if (isnan(*(const double *)member))
                sqlite3_bind_null(stmt, idx);
            else
                sqlite3_bind_double(stmt, idx, *(const double *)member);
            break;
        default:
            if (f.optional)
                sr_cat_bind_opt_text(stmt, idx, member);
            else
                sqlite3_bind_text(stmt, idx, member, -1, SQLITE_TRANSIENT);
        }
    }
}

sr_status sr_catalog_rule_list(sr_catalog *cat, bool enabled_only, sr_rule_fn fn, void *user,
                               sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  enabled_only ? "SELECT " RULE_COLUMNS ", id, created_at,"
                                                 " updated_at FROM repair_rules WHERE enabled = 1"
                                                 " ORDER BY priority, id"
                                               : "SELECT " RULE_COLUMNS ", id, created_at,"
                                                 " updated_at FROM repair_rules"
                                                 " ORDER BY priority, id",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "list repair rules");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            break;
        sr_rule r;
        read_rule(stmt, &r);
        if (fn(&r, user))
            break;
    }
    return sr_cat_finish(cat, stmt, err, "list repair rules");
}

typedef struct rule_vec {
    sr_rule *v;
    size_t count, cap;
    bool nomem;
} rule_vec;

static int push_rule(const sr_rule *r, void *user)
{
    rule_vec *rv = user;
    sr_rule *v = sr_grow(rv->v, rv->count, &rv->cap, sizeof *v);
    if (!v) {
        rv->nomem = true;
        return 1;
    }
    rv->v = v;
    rv->v[rv->count++] = *r;
    return 0;
}

sr_status sr_catalog_rule_load(sr_catalog *cat, bool enabled_only, sr_rule **out,
                               size_t *count, sr_err *err)
{
    rule_vec rv = {NULL, 0, 0, false};
    sr_status st = sr_catalog_rule_list(cat, enabled_only, push_rule, &rv, err);
    if (st == SR_OK && rv.nomem)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory reading repair rules");
    if (st != SR_OK) {
        free(rv.v);
        return st;
    }
    *out = rv.v;
    *count = rv.count;
    return SR_OK;
}

/* The row of `key`: name first, then numeric id. */
static sr_status rule_get(sr_catalog *cat, const char *key, sr_rule *out, sr_err *err)
{
    if (!key || !*key)
        return sr_err_set(err, SR_E_NOTFOUND, "no rule given");
    int64_t id = 0;
    bool numeric = sr_cat_parse_id(key, &id);
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT " RULE_COLUMNS ", id, created_at, updated_at"
                                  " FROM repair_rules WHERE name = ?1 OR id = ?2"
                                  " ORDER BY name = ?1 DESC LIMIT 1",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, key, -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(stmt, 2, numeric ? id : -1);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "read a repair rule");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no rule '%s' in the catalogue", key);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    sr_rule r;
    read_rule(stmt, &r);
    st = sr_cat_finish(cat, stmt, err, "read a repair rule");
    if (st != SR_OK)
        return st;
    *out = r;
    return SR_OK;
}

sr_status sr_catalog_rule_get(sr_catalog *cat, const char *key, sr_rule *out, sr_err *err)
{
    return rule_get(cat, key, out, err);
}

/* parameters_json must be a JSON object by SQLite's own reading. */
static sr_status check_json(sr_catalog *cat, const sr_rule *r, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "SELECT CASE WHEN json_valid(?1) THEN json_type(?1) = 'object' ELSE 0 END", &stmt,
        err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, r->parameters_json, -1, SQLITE_TRANSIENT);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "check parameters_json");
    bool ok = st == SR_OK && row && sqlite3_column_int(stmt, 0) == 1;
    sqlite3_finalize(stmt);
    if (st != SR_OK)
        return st;
    if (!ok)
        return sr_err_set(err, SR_E_RANGE, "bad parameters_json: expected a JSON object");
    return SR_OK;
}

sr_status sr_catalog_rule_add(sr_catalog *cat, const sr_rule *rule, int64_t *out_id,
                              sr_err *err)
{
    sr_status st = sr_rule_check(rule, err);
    if (st == SR_OK)
        st = check_json(cat, rule, err);
    if (st != SR_OK)
        return st;
    st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    sqlite3_stmt *stmt;
    st = sr_cat_prepare(cat, "INSERT INTO repair_rules (" RULE_COLUMNS ") VALUES (" RULE_PARAMS
                             ")", &stmt, err);
    if (st != SR_OK)
        goto fail;
    bind_rule(stmt, rule);
    st = sr_cat_exec(cat, stmt, err, "add a repair rule");
    if (st == SR_E_EXISTS)
        st = sr_err_set(err, SR_E_EXISTS, "rule '%s' already exists", rule->name);
    if (st != SR_OK)
        goto fail;
    int64_t id = sqlite3_last_insert_rowid(cat->db);
    st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        goto fail;
    if (out_id)
        *out_id = id;
    return SR_OK;
fail:
    sr_cat_rollback(cat);
    return st;
}

/* Rewrites every field of rule r->id, stamping updated_at. */
static sr_status rule_write(sr_catalog *cat, const sr_rule *r, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        "UPDATE repair_rules SET (" RULE_COLUMNS ", updated_at) = (" RULE_PARAMS
        ", strftime('%Y-%m-%dT%H:%M:%SZ', 'now')) WHERE id = ?27",
        &stmt, err);
    if (st != SR_OK)
        return st;
    bind_rule(stmt, r);
    sqlite3_bind_int64(stmt, 27, r->id);
    st = sr_cat_exec(cat, stmt, err, "change a repair rule");
    if (st == SR_E_EXISTS)
        st = sr_err_set(err, SR_E_EXISTS, "rule '%s' already exists", r->name);
    return st;
}

/* Reads rule `key`, applies change(), checks and writes it, in one transaction. */
static sr_status rule_change(sr_catalog *cat, const char *key, const char *field,
                             const char *value, sr_rule *out, sr_err *err)
{
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    sr_rule r;
    st = rule_get(cat, key, &r, err);
    if (st != SR_OK)
        goto fail;
    st = sr_rule_set_field(&r, field, value, err);
    if (st == SR_OK)
        st = sr_rule_check(&r, err);
    if (st == SR_OK)
        st = check_json(cat, &r, err);
    if (st == SR_OK)
        st = rule_write(cat, &r, err);
    if (st == SR_OK)
        st = rule_get(cat, r.name, &r, err);  /* as stored, with its new updated_at */
    if (st != SR_OK)
        goto fail;
    st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        goto fail;
    if (out)
        *out = r;
    return SR_OK;
fail:
    sr_cat_rollback(cat);
    return st;
}

sr_status sr_catalog_rule_set(sr_catalog *cat, const char *key, const char *field,
                              const char *value, sr_rule *out, sr_err *err)
{
    if (!field || !value)
        return sr_err_set(err, SR_E_RANGE, "no field or value given");
    if (sr_rule_field_kind_of(field) == SR_RULE_FIELD_UNKNOWN)
        return sr_err_set(err, SR_E_NOTFOUND, "unknown rule field '%s'", field);
    return rule_change(cat, key, field, value, out, err);
}

sr_status sr_catalog_rule_enable(sr_catalog *cat, const char *key, int enabled, sr_err *err)
{
    return rule_change(cat, key, "enabled", enabled ? "1" : "0", NULL, err);
}

/* ---- materials ---- */

static sr_status read_limits(sr_catalog *cat, sr_material *m, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT process, suitable, max_depth_mm, preheat_c, notes,"
                                  " source FROM material_process_limits WHERE material_id = ?1"
                                  " ORDER BY process",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, m->id);
    m->limit_count = 0;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "read material limits");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row || m->limit_count == SR_MATERIAL_MAX_LIMITS)
            break;
        sr_material_limit *l = &m->limits[m->limit_count++];
        sr_cat_column_text(stmt, 0, l->process, sizeof l->process);
        l->suitable = sqlite3_column_int(stmt, 1);
        l->max_depth_mm = sqlite3_column_type(stmt, 2) == SQLITE_NULL
                              ? NAN : sqlite3_column_double(stmt, 2);
        l->preheat_c = sqlite3_column_type(stmt, 3) == SQLITE_NULL
                           ? NAN : sqlite3_column_double(stmt, 3);
        sr_cat_column_text(stmt, 4, l->notes, sizeof l->notes);
        sr_cat_column_text(stmt, 5, l->source, sizeof l->source);
    }
    return sr_cat_finish(cat, stmt, err, "read material limits");
}

static void read_material(sqlite3_stmt *stmt, sr_material *m)
{
    memset(m, 0, sizeof *m);
    m->id = sqlite3_column_int64(stmt, 0);
    sr_cat_column_text(stmt, 1, m->name, sizeof m->name);
    m->density_g_cm3 = sqlite3_column_type(stmt, 2) == SQLITE_NULL
                           ? NAN : sqlite3_column_double(stmt, 2);
    sr_cat_column_text(stmt, 3, m->family, sizeof m->family);
    sr_cat_column_text(stmt, 4, m->notes, sizeof m->notes);
}

sr_status sr_catalog_material_get(sr_catalog *cat, const char *name, sr_material *out,
                                  sr_err *err)
{
    if (!name || !*name)
        return sr_err_set(err, SR_E_NOTFOUND, "no material given");
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT id, name, density_g_cm3, family, notes FROM materials"
                                  " WHERE name = ?1",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, name, -1, SQLITE_TRANSIENT);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "read a material");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no material '%s' in the catalogue", name);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    sr_material m;
    read_material(stmt, &m);
    st = sr_cat_finish(cat, stmt, err, "read a material");
    if (st == SR_OK)
        st = read_limits(cat, &m, err);
    if (st != SR_OK)
        return st;
    *out = m;
    return SR_OK;
}

sr_status sr_catalog_material_list(sr_catalog *cat, sr_material_fn fn, void *user, sr_err *err)
{
    /* Names first, then each material's limits: no statement is stepped inside fn. */
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "SELECT name FROM materials ORDER BY name", &stmt, err);
    if (st != SR_OK)
        return st;
    char (*names)[64] = NULL;
    size_t count = 0, cap = 0;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "list materials");
        if (st != SR_OK || !row)
            break;
        void *p = sr_grow(names, count, &cap, sizeof *names);
        if (!p) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory listing materials");
            break;
        }
        names = p;
        sr_cat_column_text(stmt, 0, names[count++], sizeof names[0]);
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        free(names);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "list materials");
    for (size_t i = 0; st == SR_OK && i < count; i++) {
        sr_material m;
        st = sr_catalog_material_get(cat, names[i], &m, err);
        if (st == SR_OK && fn(&m, user))
            break;
    }
    free(names);
    return st;
}

/* Checks the fields of a material to add (add: name and density required) or of a
 * change (only the fields set). */
static sr_status check_material(const sr_material_new *m, const char *name, bool add, sr_err *err)
{
    if (add && (!m->name || !*m->name))
        return sr_err_set(err, SR_E_RANGE, "a material needs a name");
    if (add && !sr_cat_len_ok(m->name, 1, 63))
        return sr_err_set(err, SR_E_RANGE, "bad material name '%.40s...': longer than 63 bytes",
                          m->name);
    if ((add || !isnan(m->density_g_cm3)) && !(isfinite(m->density_g_cm3) && m->density_g_cm3 > 0))
        return sr_err_set(err, SR_E_RANGE, "bad density of material '%s': expected g/cm³ > 0",
                          name);
    if (m->family && *m->family) {
        bool known = false;
        for (size_t i = 0; sr_material_families[i]; i++)
            known = known || strcmp(m->family, sr_material_families[i]) == 0;
        if (!known)
            return sr_err_set(err, SR_E_RANGE,
                              "bad family '%s': expected steel, stainless_steel, cast_iron, "
                              "aluminium, copper, titanium or nickel",
                              m->family);
    }
    if (!sr_cat_len_ok(m->notes, 0, 255))
        return sr_err_set(err, SR_E_RANGE, "bad notes of a material: longer than 255 bytes");
    return SR_OK;
}

sr_status sr_catalog_material_add(sr_catalog *cat, const sr_material_new *m, int64_t *out_id,
                                  sr_err *err)
{
    sr_status st = check_material(m, m->name, true, err);
    if (st != SR_OK)
        return st;
    st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    sqlite3_stmt *stmt;
    st = sr_cat_prepare(cat,
                        "INSERT INTO materials (name, density_g_cm3, family, notes)"
                        " VALUES (?1, ?2, ?3, coalesce(?4, ''))",
                        &stmt, err);
    if (st == SR_OK) {
        sqlite3_bind_text(stmt, 1, m->name, -1, SQLITE_TRANSIENT);
        sqlite3_bind_double(stmt, 2, m->density_g_cm3);
        sr_cat_bind_opt_text(stmt, 3, m->family);
        sr_cat_bind_opt_text(stmt, 4, m->notes);
        st = sr_cat_exec(cat, stmt, err, "add a material");
        if (st == SR_E_EXISTS)
            st = sr_err_set(err, SR_E_EXISTS, "material '%s' is already in the catalogue", m->name);
    }
    int64_t id = sqlite3_last_insert_rowid(cat->db);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK) {
        sr_cat_rollback(cat);
        return st;
    }
    if (out_id)
        *out_id = id;
    return SR_OK;
}

sr_status sr_catalog_material_set(sr_catalog *cat, const char *name, const sr_material_new *change,
                                  sr_err *err)
{
    if (!name || !*name)
        return sr_err_set(err, SR_E_NOTFOUND, "no material given");
    if (isnan(change->density_g_cm3) && !change->family && !change->notes)
        return sr_err_set(err, SR_E_INVALID, "nothing to change in material '%s'", name);
    sr_status st = check_material(change, name, false, err);
    if (st != SR_OK)
        return st;
    st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    sqlite3_stmt *stmt;
    /* ?2 NULL keeps the density; ?5 says whether ?3 (NULL = none) replaces the family */
    st = sr_cat_prepare(cat,
                        "UPDATE materials SET density_g_cm3 = coalesce(?2, density_g_cm3),"
                        " family = CASE WHEN ?5 THEN ?3 ELSE family END,"
                        " notes = coalesce(?4, notes) WHERE name = ?1",
                        &stmt, err);
    if (st == SR_OK) {
        sqlite3_bind_text(stmt, 1, name, -1, SQLITE_TRANSIENT);
        if (!isnan(change->density_g_cm3))
            sqlite3_bind_double(stmt, 2, change->density_g_cm3);
        sr_cat_bind_opt_text(stmt, 3, change->family);
        if (change->notes)
            sqlite3_bind_text(stmt, 4, change->notes, -1, SQLITE_TRANSIENT);
        sqlite3_bind_int(stmt, 5, change->family != NULL);
        st = sr_cat_exec(cat, stmt, err, "change a material");
    }
    if (st == SR_OK && sqlite3_changes(cat->db) == 0)
        st = sr_err_set(err, SR_E_NOTFOUND, "no material '%s' in the catalogue", name);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        sr_cat_rollback(cat);
    return st;
}
