/*
 * rule.h: a repair rule and a material as plain data, owned by the rule engine
 * (rules.h): the row of the repair_rules table (sr_rule: conditions on a section or the
 * whole part, and the process it concludes), with its checks and its text form field
 * by field, and a material with its per-process limits (sr_material). No I/O, no
 * SQLite: the catalogue (catalog_rules.h) stores and reads these structs, `symrec
 * rules` prints and edits them through the field functions below.
 *
 * In sr_rule an unset (NULL) numeric condition is NaN and an unset text condition "".
 * sr_rule_check applies the table's CHECK constraints (sql/001_init.sql,
 * sql/002_rules.sql) and a few more (known classes, locations, families, processes,
 * feature names); each failure names the field.
 */
#ifndef SR_RULE_H
#define SR_RULE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

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

/* Where field i (table order, as sr_rule_field_name) lives in sr_rule: for the
 * catalogue, which reads and binds the columns of a row by this table. */
typedef struct sr_rule_field_place {
    const char *name;           /* column name */
    sr_rule_field_kind kind;
    bool optional;              /* text: "" is stored as NULL; numbers: NaN as NULL */
    size_t offset, size;        /* of the member in sr_rule (an int for INT fields, a
                                 * double for NUMBER ones, a char array for the rest) */
} sr_rule_field_place;

/* Writes field i's place to *out and returns true; false past the last field. */
bool sr_rule_field_at(size_t i, sr_rule_field_place *out);

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

/* The limit row of `process` for material m; NULL if none. */
const sr_material_limit *sr_material_limit_of(const sr_material *m, const char *process);

#endif
