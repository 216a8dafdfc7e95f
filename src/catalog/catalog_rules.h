/*
 * catalog_rules.h: the repair rules and materials of the catalogue (tables
 * repair_rules, materials, material_process_limits of sql/001_init.sql and
 * sql/002_rules.sql): list, get, add, change one field, enable/disable a rule; read
 * materials with their process limits. The rule engine (rules.h) reads rules through
 * this API; `symrec rules` and plain SQL edit the same rows, so a change applies to the
 * next advice without rebuilding.
 *
 * In sr_rule an unset (NULL) numeric condition is NaN and an unset text condition "".
 * sr_rule_check applies the table's CHECK constraints (and a few more: known classes,
 * locations, families, processes, feature names) before anything is written, so the
 * database refuses nothing that passes; each failure names the field.
 */
#ifndef SR_CATALOG_RULES_H
#define SR_CATALOG_RULES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "catalog/catalog.h"
#include "base/status.h"

typedef struct sr_rule {
    int64_t id;                 /* row id (ignored by add) */
    char name[64];              /* unique, ignoring ASCII case */
    int priority;               /* lower first */
    int enabled;                /* 1 applied, 0 kept but not applied */
    char scope[16];             /* "section" or "part" */
    /* conditions; "" / NaN = any */
    char symmetry_kind[16];     /* axial, mirror, glide */
    char damage_class[32];      /* column class: chip, gouge, wear_band, broken_feature, crack */
    char material[64];          /* material name, ignoring case */
    char material_family[32];   /* steel, stainless_steel, cast_iron, aluminium, copper, ... */
    char location[16];          /* shoulder, end_face, body, ear, arm, edge */
    double min_volume_mm3, max_volume_mm3;
    double min_depth_mm, max_depth_mm;
    double min_lost_fraction, max_lost_fraction;      /* whole part: lost / part volume */
    double min_depth_fraction, max_depth_fraction;    /* depth_max / local radius */
    double min_section_fraction, max_section_fraction;/* section volume / part volume */
    char feature[64];           /* any numeric figure of section_features.h by name */
    double feature_min, feature_max;
    /* conclusion */
    char process[64];           /* spray_forming, ded, weld_buildup, replace, ... */
    char parameters_json[1024]; /* a JSON object, e.g. {"layer_mm":0.5} */
    char reason[512];           /* shown with the advice; {figure} is filled in */
    char source[512];           /* where the thresholds come from */
    char created_at[32], updated_at[32];  /* UTC; updated "" = never changed */
} sr_rule;

/* The processes a rule may conclude (the build plan knows spray_forming, ded and
 * weld_buildup). */
extern const char *const sr_rule_processes[];
extern const char *const sr_rule_classes[];
extern const char *const sr_rule_locations[];
extern const char *const sr_material_families[];

/* A rule with every condition unset, priority 100, enabled, scope "section". */
void sr_rule_init(sr_rule *rule);

/* Checks every field (the table's constraints and the known names above); the message
 * names the field, e.g. "bad max_depth_mm -1: expected a number >= 0". SR_E_RANGE. */
sr_status sr_rule_check(const sr_rule *rule, sr_err *err);

/* Kind of a field's value, for printing: */
typedef enum sr_rule_field_kind {
    SR_RULE_FIELD_UNKNOWN = -1,     /* no such field */
    SR_RULE_FIELD_TEXT = 0,         /* text; an optional one may be unset */
    SR_RULE_FIELD_NUMBER,           /* a double; an optional one may be unset */
    SR_RULE_FIELD_INT,              /* priority, enabled */
    SR_RULE_FIELD_JSON,             /* parameters_json: a JSON object */
} sr_rule_field_kind;

sr_rule_field_kind sr_rule_field_kind_of(const char *name);

/* Name of field i (0, 1, ...) that sr_catalog_rule_set accepts, in table order; NULL
 * past the last. */
const char *sr_rule_field_name(size_t i);

/* Sets one field of a rule struct from text: numbers for numeric fields, `null` clears
 * a condition (refused for required fields), 0/1 (or true/false) for enabled. The value
 * is parsed and checked alone; whole-rule checks (min <= max) are sr_rule_check's.
 * SR_E_NOTFOUND "unknown rule field 'x'", SR_E_RANGE for a bad value. */
sr_status sr_rule_set_field(sr_rule *rule, const char *field, const char *value, sr_err *err);

/* Writes one field of `rule` as text into buf ("null" when unset): the inverse of
 * sr_rule_set_field (numbers round-trip). SR_E_NOTFOUND for an unknown field. */
sr_status sr_rule_get_field(const sr_rule *rule, const char *field, char *buf, size_t size,
                            sr_err *err);

/* Calls fn for every rule (enabled_only: only enabled ones) in the order the engine
 * tries them: priority, then id. fn returns non-zero to stop. */
typedef int (*sr_rule_fn)(const sr_rule *rule, void *user);
sr_status sr_catalog_rule_list(sr_catalog *cat, bool enabled_only, sr_rule_fn fn, void *user,
                               sr_err *err);

/* All rules into a heap array (free()), same order. *out and *count only on success. */
sr_status sr_catalog_rule_load(sr_catalog *cat, bool enabled_only, sr_rule **out,
                               size_t *count, sr_err *err);

/* By name (ignoring case), or by numeric id when no name matches.
 * SR_E_NOTFOUND "no rule 'X' in the catalogue". */
sr_status sr_catalog_rule_get(sr_catalog *cat, const char *key, sr_rule *out, sr_err *err);

/* Adds a rule (checked first). SR_E_EXISTS if the name is taken. */
sr_status sr_catalog_rule_add(sr_catalog *cat, const sr_rule *rule, int64_t *out_id,
                              sr_err *err);

/* Sets one field of rule `key` (see sr_rule_set_field) in one transaction: reads the
 * row, changes the field, checks the whole rule, writes it. *out (may be NULL) gets the
 * rule as stored. */
sr_status sr_catalog_rule_set(sr_catalog *cat, const char *key, const char *field,
                              const char *value, sr_rule *out, sr_err *err);

/* Enables (1) or disables (0) rule `key`. */
sr_status sr_catalog_rule_enable(sr_catalog *cat, const char *key, int enabled, sr_err *err);

/* ---- materials ---- */

typedef struct sr_material_limit {
    char process[64];
    int suitable;               /* 1 usable, 0 not */
    double max_depth_mm;        /* NaN = no limit known */
    double preheat_c;           /* NaN = none / not known */
    char notes[256];
    char source[256];
} sr_material_limit;

#define SR_MATERIAL_MAX_LIMITS 16

typedef struct sr_material {
    int64_t id;
    char name[64];
    double density_g_cm3;       /* NaN = not known */
    char family[32];            /* "" = not known */
    char notes[256];
    sr_material_limit limits[SR_MATERIAL_MAX_LIMITS];
    size_t limit_count;         /* by process name; more rows than fit are not read */
} sr_material;

/* By name, ignoring case. SR_E_NOTFOUND "no material 'X' in the catalogue". */
sr_status sr_catalog_material_get(sr_catalog *cat, const char *name, sr_material *out,
                                  sr_err *err);

/* Every material by name, with its limits. */
typedef int (*sr_material_fn)(const sr_material *m, void *user);
sr_status sr_catalog_material_list(sr_catalog *cat, sr_material_fn fn, void *user, sr_err *err);

/* The limit row of `process` for material m; NULL if none. */
const sr_material_limit *sr_material_limit_of(const sr_material *m, const char *process);

#endif
