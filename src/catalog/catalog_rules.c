/*
 * catalog_rules.c: repair rules and materials in the catalogue (catalog_rules.h).
 * One table of field descriptors (name = column, kind, place in sr_rule) drives the
 * reading of rows, the binding of inserts and updates, the text form used by
 * `symrec rules set/show`, and the checks, so a column added to repair_rules is one
 * line here. The checks mirror the CHECK constraints of sql/001_init.sql and
 * sql/002_rules.sql; parameters_json is checked by SQLite's own json_valid.
 */
#include "catalog/catalog_rules.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "catalog/catalog_int.h"
#include "base/jsonbuf.h"
#include "advice/section_features.h"

const char *const sr_rule_processes[] = {"spray_forming", "ded", "weld_buildup", "machining",
                                         "inspect", "replace", "manual_review", NULL};
const char *const sr_rule_classes[] = {"chip", "gouge", "wear_band", "broken_feature", "crack",
                                       NULL};
const char *const sr_rule_locations[] = {"shoulder", "end_face", "body", "ear", "arm", "edge",
                                         NULL};
const char *const sr_material_families[] = {"steel", "stainless_steel", "cast_iron",
                                            "aluminium", "copper", "titanium", "nickel", NULL};
static const char *const scopes[] = {"section", "part", NULL};
static const char *const symmetry_kinds[] = {"axial", "mirror", "glide", NULL};

typedef enum kind {
    K_TEXT,         /* required text, 1..size-1 bytes (enum if `names`) */
    K_OPT_TEXT,     /* optional text ("" = NULL) */
    K_INT,          /* priority */
    K_BOOL,         /* enabled */
    K_REAL,         /* optional number >= 0 */
    K_FRACTION,     /* optional number in [0, 1] */
    K_ANY_REAL,     /* optional finite number */
    K_JSON,         /* required JSON object */
} kind;

typedef struct field_desc {
    const char *name;           /* column and CLI name */
    kind kind;
    size_t offset, size;        /* in sr_rule */
    const char *const *names;   /* allowed values of a text field; NULL = any */
} field_desc;

#define F(col, member, k, names) {col, k, offsetof(sr_rule, member), sizeof(((sr_rule *)0)->member), names}
static const field_desc fields[] = {
    F("name", name, K_TEXT, NULL),
    F("priority", priority, K_INT, NULL),
    F("enabled", enabled, K_BOOL, NULL),
    F("scope", scope, K_TEXT, scopes),
    F("symmetry_kind", symmetry_kind, K_OPT_TEXT, symmetry_kinds),
    F("class", damage_class, K_OPT_TEXT, sr_rule_classes),
    F("material", material, K_OPT_TEXT, NULL),
    F("material_family", material_family, K_OPT_TEXT, sr_material_families),
    F("location", location, K_OPT_TEXT, sr_rule_locations),
    F("min_volume_mm3", min_volume_mm3, K_REAL, NULL),
    F("max_volume_mm3", max_volume_mm3, K_REAL, NULL),
    F("min_depth_mm", min_depth_mm, K_REAL, NULL),
    F("max_depth_mm", max_depth_mm, K_REAL, NULL),
    F("min_lost_fraction", min_lost_fraction, K_FRACTION, NULL),
    F("max_lost_fraction", max_lost_fraction, K_FRACTION, NULL),
    F("min_depth_fraction", min_depth_fraction, K_FRACTION, NULL),
    F("max_depth_fraction", max_depth_fraction, K_FRACTION, NULL),
    F("min_section_fraction", min_section_fraction, K_FRACTION, NULL),
    F("max_section_fraction", max_section_fraction, K_FRACTION, NULL),
    F("feature", feature, K_OPT_TEXT, NULL),
    F("feature_min", feature_min, K_ANY_REAL, NULL),
    F("feature_max", feature_max, K_ANY_REAL, NULL),
    F("process", process, K_TEXT, sr_rule_processes),
    F("parameters_json", parameters_json, K_JSON, NULL),
    F("reason", reason, K_TEXT, NULL),
    F("source", source, K_TEXT, NULL),
};
#undef F
#define FIELD_COUNT (sizeof fields / sizeof fields[0])

static const field_desc *find_field(const char *name)
{
    for (size_t i = 0; i < FIELD_COUNT; i++)
        if (strcmp(fields[i].name, name) == 0)
            return &fields[i];
    return NULL;
}

sr_rule_field_kind sr_rule_field_kind_of(const char *name)
{
    const field_desc *f = name ? find_field(name) : NULL;
    if (!f)
        return SR_RULE_FIELD_UNKNOWN;
    switch (f->kind) {
    case K_TEXT:
    case K_OPT_TEXT:
        return SR_RULE_FIELD_TEXT;
    case K_INT:
    case K_BOOL:
        return SR_RULE_FIELD_INT;
    case K_JSON:
        return SR_RULE_FIELD_JSON;
    default:
        return SR_RULE_FIELD_NUMBER;
    }
}

const char *sr_rule_field_name(size_t i)
{
    return i < FIELD_COUNT ? fields[i].name : NULL;
}

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

static char *text_of(sr_rule *r, const field_desc *f) { return (char *)r + f->offset; }
static const char *ctext_of(const sr_rule *r, const field_desc *f)
{
    return (const char *)r + f->offset;
}
static double *real_of(sr_rule *r, const field_desc *f) { return (double *)((char *)r + f->offset); }
static double creal_of(const sr_rule *r, const field_desc *f)
{
    return *(const double *)((const char *)r + f->offset);
}
static int cint_of(const sr_rule *r, const field_desc *f)
{
    return *(const int *)((const char *)r + f->offset);
}


static bool in_list(const char *const *names, const char *s)
{
    for (size_t i = 0; names[i]; i++)
        if (strcmp(names[i], s) == 0)
            return true;
    return false;
}

static void join_list(const char *const *names, char *buf, size_t size)
{
    buf[0] = '\0';
    for (size_t i = 0; names[i]; i++) {
        size_t len = strlen(buf);
        snprintf(buf + len, size - len, "%s%s", i ? ", " : "", names[i]);
    }
}

void sr_rule_init(sr_rule *rule)
{
    memset(rule, 0, sizeof *rule);
    rule->priority = 100;
    rule->enabled = 1;
    strcpy(rule->scope, "section");
    strcpy(rule->parameters_json, "{}");
    for (size_t i = 0; i < FIELD_COUNT; i++)
        if (fields[i].kind == K_REAL || fields[i].kind == K_FRACTION ||
            fields[i].kind == K_ANY_REAL)
            *real_of(rule, &fields[i]) = NAN;
}

/* One field alone. */
static sr_status check_field(const sr_rule *r, const field_desc *f, sr_err *err)
{
    char list[200];
    switch (f->kind) {
    case K_TEXT:
    case K_OPT_TEXT:
    case K_JSON: {
        const char *s = ctext_of(r, f);
        size_t len = strnlen(s, f->size);
        if (len == f->size)
            return sr_err_set(err, SR_E_RANGE, "bad %s: longer than %zu bytes", f->name,
                              f->size - 1);
        if (len == 0 && f->kind != K_OPT_TEXT)
            return sr_err_set(err, SR_E_RANGE, "bad %s: empty (it is required)", f->name);
        if (len > 0 && f->names && !in_list(f->names, s)) {
            join_list(f->names, list, sizeof list);
            return sr_err_set(err, SR_E_RANGE, "bad %s '%s': expected one of %s", f->name, s,
                              list);
        }
        if (len > 0 && strcmp(f->name, "feature") == 0 && !sr_features_is_figure(s))
            return sr_err_set(err, SR_E_RANGE, "bad feature '%s': not a figure of a section "
                              "(see section_features.h)", s);
        if (f->kind == K_JSON) {
            const char *p = s + strspn(s, " \t\r\n");
            if (*p != '{')
                return sr_err_set(err, SR_E_RANGE, "bad %s: expected a JSON object", f->name);
        }
        return SR_OK;
    }
    case K_INT:
        return SR_OK;
    case K_BOOL:
        if (cint_of(r, f) != 0 && cint_of(r, f) != 1)
            return sr_err_set(err, SR_E_RANGE, "bad %s %d: expected 0 or 1", f->name,
                              cint_of(r, f));
        return SR_OK;
    case K_REAL:
    case K_FRACTION:
    case K_ANY_REAL: {
        double v = creal_of(r, f);
        if (isnan(v))
            return SR_OK;
        if (!isfinite(v))
            return sr_err_set(err, SR_E_RANGE, "bad %s: expected a finite number", f->name);
        if (f->kind == K_REAL && v < 0)
            return sr_err_set(err, SR_E_RANGE, "bad %s %g: expected a number >= 0", f->name, v);
        if (f->kind == K_FRACTION && (v < 0 || v > 1))
            return sr_err_set(err, SR_E_RANGE, "bad %s %g: expected a fraction 0..1", f->name,
                              v);
        return SR_OK;
    }
    }
    return SR_OK;
}

static sr_status check_pair(const char *lo_name, double lo, const char *hi_name, double hi,
                            sr_err *err)
{
    if (!isnan(lo) && !isnan(hi) && lo > hi)
        return sr_err_set(err, SR_E_RANGE, "bad %s %g: greater than %s %g", lo_name, lo,
                          hi_name, hi);
    return SR_OK;
}

sr_status sr_rule_check(const sr_rule *r, sr_err *err)
{
    for (size_t i = 0; i < FIELD_COUNT; i++) {
        sr_status st = check_field(r, &fields[i], err);
        if (st != SR_OK)
            return st;
    }
    sr_status st;
    if ((st = check_pair("min_volume_mm3", r->min_volume_mm3, "max_volume_mm3",
                         r->max_volume_mm3, err)) != SR_OK ||
        (st = check_pair("min_depth_mm", r->min_depth_mm, "max_depth_mm", r->max_depth_mm,
                         err)) != SR_OK ||
        (st = check_pair("min_lost_fraction", r->min_lost_fraction, "max_lost_fraction",
                         r->max_lost_fraction, err)) != SR_OK ||
        (st = check_pair("min_depth_fraction", r->min_depth_fraction, "max_depth_fraction",
                         r->max_depth_fraction, err)) != SR_OK ||
        (st = check_pair("min_section_fraction", r->min_section_fraction,
                         "max_section_fraction", r->max_section_fraction, err)) != SR_OK ||
        (st = check_pair("feature_min", r->feature_min, "feature_max", r->feature_max, err)) !=
            SR_OK)
        return st;
    if (!r->feature[0] && (!isnan(r->feature_min) || !isnan(r->feature_max)))
        return sr_err_set(err, SR_E_RANGE, "bad %s: no feature named to compare",
                          isnan(r->feature_min) ? "feature_max" : "feature_min");
    return SR_OK;
}

/* Parses a whole string as a finite double. */
static bool parse_real(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno == ERANGE || !isfinite(v))
        return false;
    *out = v;
    return true;
}

sr_status sr_rule_set_field(sr_rule *r, const char *name, const char *value, sr_err *err)
{
    const field_desc *f = find_field(name);
    if (!f)
        return sr_err_set(err, SR_E_NOTFOUND, "unknown rule field '%s'", name);
    bool null = strcmp(value, "null") == 0;
    bool nullable = f->kind == K_OPT_TEXT || f->kind == K_REAL || f->kind == K_FRACTION ||
                    f->kind == K_ANY_REAL;
    if (null && !nullable)
        return sr_err_set(err, SR_E_RANGE, "field '%s' cannot be null (it is required)", name);
    sr_rule t = *r;
    switch (f->kind) {
    case K_TEXT:
    case K_OPT_TEXT:
    case K_JSON:
        if (null) {
            text_of(&t, f)[0] = '\0';
        } else {
            if (strlen(value) >= f->size)
                return sr_err_set(err, SR_E_RANGE, "bad %s: longer than %zu bytes", name,
                                  f->size - 1);
            if (!*value && f->kind == K_OPT_TEXT)
                return sr_err_set(err, SR_E_RANGE, "bad %s: empty (write null to clear it)",
                                  name);
            memcpy(text_of(&t, f), value, strlen(value) + 1);
        }
        break;
    case K_INT: {
        double v;
        if (!parse_real(value, &v) || v != floor(v) || fabs(v) > 1e9)
            return sr_err_set(err, SR_E_RANGE, "bad %s '%s': expected a whole number", name,
                              value);
        t.priority = (int)v;
        break;
    }
    case K_BOOL:
        if (strcmp(value, "1") == 0 || strcmp(value, "true") == 0)
            t.enabled = 1;
        else if (strcmp(value, "0") == 0 || strcmp(value, "false") == 0)
            t.enabled = 0;
        else
            return sr_err_set(err, SR_E_RANGE, "bad %s '%s': expected 0 or 1", name, value);
        break;
    case K_REAL:
    case K_FRACTION:
    case K_ANY_REAL: {
        double v = NAN;
        if (!null && !parse_real(value, &v))
            return sr_err_set(err, SR_E_RANGE, "bad %s '%s': expected a number or null", name,
                              value);
        *real_of(&t, f) = v;
        break;
    }
    }
    sr_status st = check_field(&t, f, err);
    if (st != SR_OK)
        return st;
    *r = t;
    return SR_OK;
}

sr_status sr_rule_get_field(const sr_rule *r, const char *name, char *buf, size_t size,
                            sr_err *err)
{
    const field_desc *f = find_field(name);
    if (!f)
        return sr_err_set(err, SR_E_NOTFOUND, "unknown rule field '%s'", name);
    switch (f->kind) {
    case K_TEXT:
    case K_JSON:
        snprintf(buf, size, "%s", ctext_of(r, f));
        break;
    case K_OPT_TEXT:
        snprintf(buf, size, "%s", ctext_of(r, f)[0] ? ctext_of(r, f) : "null");
        break;
    case K_INT:
    case K_BOOL:
        snprintf(buf, size, "%d", cint_of(r, f));
        break;
    default: {
        char num[SR_JSONBUF_NUMBER_SIZE];
        snprintf(buf, size, "%s", sr_jsonbuf_format_number(creal_of(r, f), num));
    }
    }
    return SR_OK;
}

/* ---- rows ---- */

static void read_rule(sqlite3_stmt *stmt, sr_rule *r)
{
    sr_rule_init(r);
    for (size_t i = 0; i < FIELD_COUNT; i++) {
        const field_desc *f = &fields[i];
        int col = (int)i;
        bool is_null = sqlite3_column_type(stmt, col) == SQLITE_NULL;
        switch (f->kind) {
        case K_TEXT:
        case K_OPT_TEXT:
        case K_JSON:
            sr_cat_column_text(stmt, col, text_of(r, f), f->size);
            break;
        case K_INT:
            r->priority = sqlite3_column_int(stmt, col);
            break;
        case K_BOOL:
            r->enabled = sqlite3_column_int(stmt, col);
            break;
        default:
            *real_of(r, f) = is_null ? NAN : sqlite3_column_double(stmt, col);
        }
    }
    r->id = sqlite3_column_int64(stmt, (int)FIELD_COUNT);
    sr_cat_column_text(stmt, (int)FIELD_COUNT + 1, r->created_at, sizeof r->created_at);
    sr_cat_column_text(stmt, (int)FIELD_COUNT + 2, r->updated_at, sizeof r->updated_at);
}

static void bind_rule(sqlite3_stmt *stmt, const sr_rule *r)
{
    for (size_t i = 0; i < FIELD_COUNT; i++) {
        const field_desc *f = &fields[i];
        int idx = (int)i + 1;
        switch (f->kind) {
        case K_TEXT:
        case K_JSON:
            sqlite3_bind_text(stmt, idx, ctext_of(r, f), -1, SQLITE_TRANSIENT);
            break;
        case K_OPT_TEXT:
            sr_cat_bind_opt_text(stmt, idx, ctext_of(r, f));
            break;
        case K_INT:
        case K_BOOL:
            sqlite3_bind_int(stmt, idx, cint_of(r, f));
            break;
        default:
            if (isnan(creal_of(r, f)))
                sqlite3_bind_null(stmt, idx);
            else
                sqlite3_bind_double(stmt, idx, creal_of(r, f));
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
    if (rv->count == rv->cap) {
        size_t cap = rv->cap ? 2 * rv->cap : 16;
        sr_rule *v = realloc(rv->v, cap * sizeof *v);
        if (!v) {
            rv->nomem = true;
            return 1;
        }
        rv->v = v;
        rv->cap = cap;
    }
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
    if (!find_field(field))
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
        if (count == cap) {
            cap = cap ? 2 * cap : 16;
            void *p = realloc(names, cap * sizeof *names);
            if (!p) {
                st = sr_err_set(err, SR_E_NOMEM, "out of memory listing materials");
                break;
            }
            names = p;
        }
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

const sr_material_limit *sr_material_limit_of(const sr_material *m, const char *process)
{
    for (size_t i = 0; i < m->limit_count; i++)
        if (strcasecmp(m->limits[i].process, process) == 0)
            return &m->limits[i];
    return NULL;
}
