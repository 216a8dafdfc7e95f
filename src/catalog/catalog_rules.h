/*
 * catalog_rules.h: the repair rules and materials of the catalogue (tables
 * repair_rules, materials, material_process_limits of sql/001_init.sql and
 * sql/002_rules.sql): list, get, add, change one field, enable/disable a rule; read
 * materials with their process limits. The rows are the core's structs (sr_rule,
 * sr_material of advice/rule.h, checked there); this module stores and reads them, and
 * the catalogue side of recording (catalog_record.h) hands them to the rule engine
 * (rules.h). `symrec rules` and plain SQL edit the same rows, so a change applies to
 * the next advice without rebuilding.
 *
 * sr_rule_check runs before anything is written, so the database refuses nothing that
 * passes; each failure names the field.
 */
#ifndef SR_CATALOG_RULES_H
#define SR_CATALOG_RULES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "catalog/catalog.h"
#include "advice/rule.h"
#include "base/status.h"

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

/* ---- materials (sr_material: advice/rule.h) ---- */

/* By name, ignoring case. SR_E_NOTFOUND "no material 'X' in the catalogue". */
sr_status sr_catalog_material_get(sr_catalog *cat, const char *name, sr_material *out,
                                  sr_err *err);

/* Every material by name, with its limits. */
typedef int (*sr_material_fn)(const sr_material *m, void *user);
sr_status sr_catalog_material_list(sr_catalog *cat, sr_material_fn fn, void *user, sr_err *err);

/* A material to add, or the change of one (sr_catalog_material_set). */
typedef struct sr_material_new {
    const char *name;     /* add: required, 1..63 bytes, unique ignoring ASCII case */
    double density_g_cm3; /* g/cm^3, > 0 and finite; set: NaN = keep */
    const char *family;   /* one of sr_material_families (advice/rule.h); NULL = none
                           * (set: keep), "" = none (set: clear) */
    const char *notes;    /* free text, up to 255 bytes; NULL = "" (set: keep) */
} sr_material_new;

/* Adds a material with its density; the only way a material enters the catalogue (a
 * part naming an unknown material is refused, catalog.h). SR_E_EXISTS "material 'X' is
 * already in the catalogue" (any spelling), SR_E_RANGE for a bad field (named).
 * *out_id (may be NULL) only on success. */
sr_status sr_catalog_material_add(sr_catalog *cat, const sr_material_new *m, int64_t *out_id,
                                  sr_err *err);

/* Changes material `name` (found ignoring case): the fields of `change` that are set
 * (its name is ignored). For a material created without a density by an older
 * symrec, whose deposit masses have nothing to stand on. SR_E_NOTFOUND, SR_E_RANGE;
 * SR_E_INVALID when `change` sets nothing. */
sr_status sr_catalog_material_set(sr_catalog *cat, const char *name, const sr_material_new *change,
                                  sr_err *err);

#endif
