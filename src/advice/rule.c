/*
 * rule.c: the plain-data side of repair rules and materials (rule.h). One table of
 * field descriptors (name = column, kind, place in sr_rule) drives the defaults, the
 * checks, the text form used by `symrec rules set/show`, and (through sr_rule_field_at)
 * the catalogue's reading and binding of rows, so a column added to repair_rules is
 * one line here. The checks mirror the CHECK constraints of sql/001_init.sql and
 * sql/002_rules.sql.
 */
#include "advice/rule.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

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

bool sr_rule_field_at(size_t i, sr_rule_field_place *out)
{
    if (i >= FIELD_COUNT)
        return false;
    const field_desc *f = &fields[i];
    out->name = f->name;
    out->kind = sr_rule_field_kind_of(f->name);
    out->optional = f->kind != K_TEXT && f->kind != K_JSON && f->kind != K_INT &&
                    f->kind != K_BOOL;
    out->offset = f->offset;
    out->size = f->size;
    return true;
}

/* ---- materials ---- */

const sr_material_limit *sr_material_limit_of(const sr_material *m, const char *process)
{
    for (size_t i = 0; i < m->limit_count; i++)
        if (strcasecmp(m->limits[i].process, process) == 0)
            return &m->limits[i];
    return NULL;
}
