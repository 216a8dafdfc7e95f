/*
 * test_rules.c: repair rules and materials in a fresh catalogue (sql/002_rules.sql,
 * src/catalog/catalog_rules.h) and the rule engine (src/advice/rules.h) on run records built inline
 * (tests/support/synth_run.h: a shaft of radius 20 stepping to 30 at z = 50). Checks
 * that the seed rules give spray forming for a small chip and "replace" beyond 25 %
 * lost volume; that editing a rule through the API or with plain SQL on the file
 * changes the next advice; that unevaluable rules are reported, disabled rules do not
 * fire, priorities order the rules, and materials block processes they do not suit;
 * and every error path of the rule API.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "catalog/catalog.h"
#include "catalog/catalog_rules.h"
#include "advice/rules.h"
#include "catalog/catalog_record.h"
#include "support/assert_near.h"
#include "support/json_query.h"
#include "support/synth_run.h"
#include "support/tmpdir.h"

#define PI 3.14159265358979323846

typedef struct fixture {
    tmpdir dir;
    char path[TMPDIR_PATH_MAX];
    sr_catalog *cat;
    sr_run run;
} fixture;

static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    assert_non_null(fx);
    assert_int_equal(tmpdir_make(&fx->dir), 0);
    tmpdir_join(&fx->dir, "cat.db", fx->path);
    sr_err err;
    if (sr_catalog_open(fx->path, SR_CATALOG_CREATE, &fx->cat, &err) != SR_OK)
        fail_msg("open: %s", err.msg);
    synth_run_make(&fx->run, 100, 72, 20.0, 30.0, 50.0);
    *state = fx;
    return 0;
}

static int teardown(void **state)
{
    fixture *fx = *state;
    synth_run_free(&fx->run);
    sr_catalog_close(fx->cat);
    tmpdir_remove(&fx->dir);
    free(fx);
    return 0;
}

/* Volume of the shaft: radius 20 for z 0..50, 30 for 50..100 (as a 72-gon). */
static double shaft_volume(void)
{
    double a = 72 * 0.5 * sin(2 * PI / 72);
    return a * 400 * 50 + a * 900 * 50;
}

/* A 2 mm deep chip, 30 deg x 5 layers, on the plain stretch (z 20..25). */
static void small_chip(fixture *fx)
{
    synth_run_dig(&fx->run, 20, 24, 9, 6, 2.0, 0);
}

static void advise(fixture *fx, const char *material, double volume)
{
    sr_err err;
    sr_err_clear(&err);
    if (sr_catalog_advise_run(fx->cat, material, volume, &fx->run, &err) != SR_OK)
        fail_msg("sr_catalog_advise_run: %s", err.msg);
}

/* The advice for section i (-1: the whole part); fails if there is none. */
static const sr_run_advice *advice_for(const fixture *fx, long i)
{
    const sr_run_advice *a = synth_run_advice_for(&fx->run, i);
    if (!a)
        fail_msg("no advice for section %ld", i);
    return a;
}

static bool has_advice_for(const fixture *fx, long i)
{
    for (size_t k = 0; k < fx->run.advice_count; k++)
        if (fx->run.advice[k].section_index == i)
            return true;
    return false;
}

static void set_rule(fixture *fx, const char *rule, const char *field, const char *value)
{
    sr_err err;
    sr_err_clear(&err);
    if (sr_catalog_rule_set(fx->cat, rule, field, value, NULL, &err) != SR_OK)
        fail_msg("rule set %s %s %s: %s", rule, field, value, err.msg);
}

static void add_rule(fixture *fx, const char *name, int priority, const char *process,
                     const char *field, const char *value)
{
    sr_rule r;
    sr_rule_init(&r);
    snprintf(r.name, sizeof r.name, "%s", name);
    r.priority = priority;
    snprintf(r.process, sizeof r.process, "%s", process);
    snprintf(r.reason, sizeof r.reason, "test rule %s", name);
    snprintf(r.source, sizeof r.source, "test");
    sr_err err;
    sr_err_clear(&err);
    if (field && sr_rule_set_field(&r, field, value, &err) != SR_OK)
        fail_msg("set_field: %s", err.msg);
    if (sr_catalog_rule_add(fx->cat, &r, NULL, &err) != SR_OK)
        fail_msg("rule add: %s", err.msg);
}

static void sql_on_file(const fixture *fx, const char *sql)
{
    sqlite3 *db;
    assert_int_equal(sqlite3_open(fx->path, &db), SQLITE_OK);
    char *msg = NULL;
    if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK)
        fail_msg("sql: %s", msg);
    sqlite3_close(db);
}

static bool unevaluated_has(const char *details, const char *rule, const char *why)
{
    long n = jq_len(details, "$.rules_unevaluated");
    for (long i = 0; i < n; i++) {
        char path[64];
        snprintf(path, sizeof path, "$.rules_unevaluated[%ld].rule", i);
        char *name = jq_text(details, path);
        snprintf(path, sizeof path, "$.rules_unevaluated[%ld].why", i);
        char *text = jq_text(details, path);
        bool hit = name && text && strcmp(name, rule) == 0 && strstr(text, why);
        free(name);
        free(text);
        if (hit)
            return true;
    }
    return false;
}

/* ---- the seed rules ---- */

static void small_chip_gets_spray_forming_from_the_seed_rules(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    advise(fx, NULL, shaft_volume());
    assert_string_equal(fx->run.sections[0].damage_class, "chip");
    assert_non_null(fx->run.sections[0].features_json);
    assert_int_equal(fx->run.advice_count, 1);   /* no whole-part advice */
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(a->process, "spray_forming");
    assert_string_equal(a->rule_name, "spray-small-loss");
    assert_true(a->rule_id > 0);
    assert_non_null(strstr(a->reason, "2 mm deep"));   /* {depth_max_mm} filled in */
    assert_true(jq_valid(a->details_json));
    char *applied = jq_text(a->details_json, "$.applied");
    assert_string_equal(applied, "spray-small-loss");
    free(applied);
    /* every rule that held, in order: the applied one first, the catch-all last */
    char *first = jq_text(a->details_json, "$.rules_fired[0]");
    assert_string_equal(first, "spray-small-loss");
    free(first);
    assert_true(jq_has(a->details_json, "$.rules_fired", "ded-medium-depth"));
    assert_true(jq_has(a->details_json, "$.rules_fired", "catch-all-review"));
    assert_false(jq_has(a->details_json, "$.rules_fired", "weld-buildup-deep"));
    assert_near(jq_num(a->details_json, "$.parameters.layer_mm"), 0.25, 0);
    assert_near(jq_num(a->details_json, "$.lost_fraction"),
                fx->run.sections[0].volume_mm3 / shaft_volume(), 1e-12);
}

static void more_than_a_quarter_lost_gets_replace(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    double vol = fx->run.sections[0].volume_mm3;
    advise(fx, NULL, 3.0 * vol);   /* a third of the part is missing */
    assert_int_equal(fx->run.advice_count, 2);
    const sr_run_advice *whole = &fx->run.advice[0];
    assert_int_equal(whole->section_index, -1);
    assert_string_equal(whole->process, "replace");
    assert_string_equal(whole->rule_name, "replace-beyond-25pct");
    assert_non_null(strstr(whole->reason, "beyond repair"));
    assert_non_null(strstr(whole->reason, "33.3 %"));
    /* the section still gets its own advice, which points at the part advice */
    char *pa = jq_text(advice_for(fx, 0)->details_json, "$.part_advice");
    assert_string_equal(pa, "replace-beyond-25pct");
    free(pa);
}

static void a_fifth_lost_is_not_replaced(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    advise(fx, NULL, 5.0 * fx->run.sections[0].volume_mm3);
    assert_false(has_advice_for(fx, -1));
}

/* ---- editing rules changes the advice ---- */

static void editing_a_rule_through_the_api_changes_the_advice(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    advise(fx, NULL, shaft_volume());
    assert_string_equal(advice_for(fx, 0)->process, "spray_forming");
    set_rule(fx, "spray-small-loss", "max_depth_mm", "1.5");
    advise(fx, NULL, shaft_volume());
    assert_string_equal(advice_for(fx, 0)->process, "ded");
    assert_string_equal(advice_for(fx, 0)->rule_name, "ded-medium-depth");
}

static void editing_a_rule_with_plain_sql_changes_the_advice(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    sql_on_file(fx, "UPDATE repair_rules SET max_depth_mm = 1 WHERE name = 'spray-small-loss'");
    advise(fx, NULL, shaft_volume());
    assert_string_equal(advice_for(fx, 0)->process, "ded");
    sql_on_file(fx, "UPDATE repair_rules SET max_depth_mm = 5 WHERE name = 'spray-small-loss'");
    advise(fx, NULL, shaft_volume());
    assert_string_equal(advice_for(fx, 0)->process, "spray_forming");
    /* the trigger stamped the edit */
    sr_rule r;
    assert_int_equal(sr_catalog_rule_get(fx->cat, "spray-small-loss", &r, NULL), SR_OK);
    assert_true(strlen(r.updated_at) == 20);
    assert_near(r.max_depth_mm, 5.0, 0);
}

static void disabled_rules_do_not_fire(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    assert_int_equal(sr_catalog_rule_enable(fx->cat, "spray-small-loss", 0, NULL), SR_OK);
    advise(fx, NULL, shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(a->process, "ded");
    assert_false(jq_has(a->details_json, "$.rules_fired", "spray-small-loss"));
    assert_int_equal(sr_catalog_rule_enable(fx->cat, "spray-small-loss", 1, NULL), SR_OK);
    advise(fx, NULL, shaft_volume());
    assert_string_equal(advice_for(fx, 0)->process, "spray_forming");
}

static void lower_priority_number_wins(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    add_rule(fx, "weld-everything", 1, "weld_buildup", "max_depth_mm", "100");
    advise(fx, NULL, shaft_volume());
    assert_string_equal(advice_for(fx, 0)->rule_name, "weld-everything");
    set_rule(fx, "weld-everything", "priority", "2000");
    advise(fx, NULL, shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(a->rule_name, "spray-small-loss");
    /* still held, now listed after the catch-all (priority 1000) */
    char *last = jq_text(a->details_json, "$.rules_fired[#-1]");
    assert_string_equal(last, "weld-everything");
    free(last);
}

static void no_rule_at_all_gives_manual_review_without_a_rule(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    sql_on_file(fx, "UPDATE repair_rules SET enabled = 0");
    advise(fx, NULL, shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(a->process, "manual_review");
    assert_int_equal(a->rule_id, 0);
    assert_non_null(strstr(a->reason, "no enabled rule applies"));
    assert_int_equal(jq_len(a->details_json, "$.rules_fired"), 0);
}

/* ---- unevaluable rules are reported ---- */

static void material_rule_without_a_material_is_reported(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    add_rule(fx, "cast-iron-spray", 5, "spray_forming", "material_family", "cast_iron");
    advise(fx, NULL, shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(a->rule_name, "spray-small-loss");
    assert_true(unevaluated_has(a->details_json, "cast-iron-spray", "the part has no material"));
    assert_near(jq_num(a->details_json, "$.rules_unevaluated[0].outranks_applied"), 1, 0);
}

static void unknown_material_has_no_family(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    add_rule(fx, "cast-iron-spray", 5, "spray_forming", "material_family", "cast_iron");
    advise(fx, "Unobtainium", shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_true(unevaluated_has(a->details_json, "cast-iron-spray", "not in the catalogue"));
    char *m = jq_text(a->details_json, "$.material");
    assert_string_equal(m, "Unobtainium");
    free(m);
}

static void feature_the_section_lacks_is_reported(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    /* position_from_plane exists only for planar sections */
    add_rule(fx, "far-from-plane", 5, "ded", "feature", "position_from_plane");
    advise(fx, NULL, shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_true(unevaluated_has(a->details_json, "far-from-plane",
                                "the section has no feature 'position_from_plane'"));
    assert_string_equal(a->rule_name, "spray-small-loss");
}

static void rule_false_on_another_condition_is_not_unevaluated(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    sr_rule r;
    sr_rule_init(&r);
    strcpy(r.name, "cracks-in-bronze");
    strcpy(r.process, "replace");
    strcpy(r.reason, "x");
    strcpy(r.source, "test");
    strcpy(r.damage_class, "crack");
    strcpy(r.material, "CuSn12");
    assert_int_equal(sr_catalog_rule_add(fx->cat, &r, NULL, NULL), SR_OK);
    advise(fx, NULL, shaft_volume());
    /* class is chip: false whatever the material, so nothing to report */
    assert_false(unevaluated_has(advice_for(fx, 0)->details_json, "cracks-in-bronze", ""));
}

static void part_volume_unknown_reports_the_replace_rule(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    advise(fx, NULL, 0);
    const sr_run_advice *a = advice_for(fx, 0);
    assert_false(has_advice_for(fx, -1));
    assert_true(unevaluated_has(a->details_json, "replace-beyond-25pct", "part volume unknown"));
    /* spray-small-loss has max_section_fraction: unknown too, so ded-medium-depth applies */
    assert_true(unevaluated_has(a->details_json, "spray-small-loss", "part volume unknown"));
    assert_string_equal(a->rule_name, "ded-medium-depth");
}

/* ---- materials ---- */

static void material_that_forbids_a_process_blocks_its_rule(void **state)
{
    fixture *fx = *state;
    synth_run_dig(&fx->run, 10, 29, 0, 18, 12.0, 0);   /* broken feature, 12 mm deep */
    advise(fx, "EN AW-7075", shaft_volume());
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(fx->run.sections[0].damage_class, "broken_feature");
    /* DED and welding do not suit 7075: both passed over, the catch-all applies */
    assert_string_equal(a->process, "manual_review");
    assert_string_equal(a->rule_name, "catch-all-review");
    assert_int_equal(jq_len(a->details_json, "$.rules_blocked"), 2);
    char *why = jq_text(a->details_json, "$.rules_blocked[0].why");
    assert_non_null(strstr(why, "'ded' is not suitable for EN AW-7075"));
    free(why);
}

static void suitable_material_gives_preheat_and_mass(void **state)
{
    fixture *fx = *state;
    synth_run_dig(&fx->run, 10, 29, 0, 18, 12.0, 0);
    advise(fx, "42crmo4", shaft_volume());   /* names ignore case */
    const sr_run_advice *a = advice_for(fx, 0);
    assert_string_equal(a->process, "ded");
    assert_string_equal(a->rule_name, "broken-feature-ded");
    assert_near(jq_num(a->details_json, "$.preheat_c"), 250, 0);
    assert_near(jq_num(a->details_json, "$.density_g_cm3"), 7.85, 0);
    assert_near(jq_num(a->details_json, "$.missing_mass_g"),
                fx->run.sections[0].volume_mm3 * 7.85 / 1000.0, 1e-9);
}

static void materials_are_seeded_with_densities_and_limits(void **state)
{
    fixture *fx = *state;
    sr_material m;
    assert_int_equal(sr_catalog_material_get(fx->cat, "Ti-6Al-4V", &m, NULL), SR_OK);
    assert_near(m.density_g_cm3, 4.43, 0);
    assert_string_equal(m.family, "titanium");
    assert_int_equal(m.limit_count, 3);
    assert_non_null(sr_material_limit_of(&m, "ded"));
    assert_int_equal(sr_catalog_material_get(fx->cat, "EN-GJL-250", &m, NULL), SR_OK);
    assert_int_equal(sr_material_limit_of(&m, "weld_buildup")->suitable, 0);
    assert_near(sr_material_limit_of(&m, "ded")->max_depth_mm, 3.0, 0);
    sr_err err;
    assert_int_equal(sr_catalog_material_get(fx->cat, "nonesuch", &m, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "no material 'nonesuch'");
}

static int count_material(const sr_material *m, void *user)
{
    (void)m;
    (*(int *)user)++;
    return 0;
}

static void material_list_gives_every_material(void **state)
{
    fixture *fx = *state;
    int n = 0;
    assert_int_equal(sr_catalog_material_list(fx->cat, count_material, &n, NULL), SR_OK);
    assert_int_equal(n, 9);
}

/* ---- the rule API ---- */

static void seed_rules_each_have_a_source_and_a_catch_all_exists(void **state)
{
    fixture *fx = *state;
    sr_rule *rules;
    size_t n;
    assert_int_equal(sr_catalog_rule_load(fx->cat, false, &rules, &n, NULL), SR_OK);
    assert_int_equal(n, 9);
    bool catch_all = false;
    for (size_t i = 0; i < n; i++) {
        assert_true(strlen(rules[i].source) > 4);
        assert_int_equal(sr_rule_check(&rules[i], NULL), SR_OK);
        if (i)
            assert_true(rules[i - 1].priority <= rules[i].priority);
        catch_all |= rules[i].priority == 1000 && strcmp(rules[i].process, "manual_review") == 0;
    }
    assert_true(catch_all);
    free(rules);
}

static void rule_found_by_id_and_name(void **state)
{
    fixture *fx = *state;
    sr_rule a, b;
    assert_int_equal(sr_catalog_rule_get(fx->cat, "SPRAY-SMALL-LOSS", &a, NULL), SR_OK);
    char id[32];
    snprintf(id, sizeof id, "%lld", (long long)a.id);
    assert_int_equal(sr_catalog_rule_get(fx->cat, id, &b, NULL), SR_OK);
    assert_string_equal(b.name, "spray-small-loss");
}

static void unknown_rule_is_not_found(void **state)
{
    fixture *fx = *state;
    sr_rule r;
    sr_err err;
    assert_int_equal(sr_catalog_rule_get(fx->cat, "nonesuch", &r, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "no rule 'nonesuch' in the catalogue");
    assert_int_equal(sr_catalog_rule_set(fx->cat, "nonesuch", "priority", "1", NULL, &err),
                     SR_E_NOTFOUND);
    assert_msg_has(err, "no rule 'nonesuch'");
}

static void unknown_field_is_refused(void **state)
{
    fixture *fx = *state;
    sr_err err;
    assert_int_equal(sr_catalog_rule_set(fx->cat, "spray-small-loss", "depth", "1", NULL, &err),
                     SR_E_NOTFOUND);
    assert_msg_has(err, "unknown rule field 'depth'");
}

static void bad_values_are_refused_and_change_nothing(void **state)
{
    fixture *fx = *state;
    static const char *const cases[][3] = {
        {"max_depth_mm", "-1", "bad max_depth_mm -1: expected a number >= 0"},
        {"max_depth_mm", "deep", "bad max_depth_mm 'deep': expected a number or null"},
        {"max_depth_mm", "inf", "expected a number or null"},
        {"max_section_fraction", "1.5", "expected a fraction 0..1"},
        {"process", "null", "field 'process' cannot be null"},
        {"process", "glue", "bad process 'glue': expected one of spray_forming"},
        {"class", "dent", "bad class 'dent'"},
        {"location", "bore", "bad location 'bore'"},
        {"feature", "depth", "bad feature 'depth'"},
        {"enabled", "2", "bad enabled '2'"},
        {"priority", "1.5", "bad priority '1.5': expected a whole number"},
        {"parameters_json", "{\"layer_mm\":", "bad parameters_json: expected a JSON object"},
        {"parameters_json", "[1]", "bad parameters_json: expected a JSON object"},
        {"min_depth_mm", "5", "bad min_depth_mm 5: greater than max_depth_mm 3"},
        {"feature_min", "1", "bad feature_min: no feature named to compare"},
        {"name", "catch-all-review", "already exists"},
    };
    sr_rule before, after;
    assert_int_equal(sr_catalog_rule_get(fx->cat, "spray-small-loss", &before, NULL), SR_OK);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sr_err err;
        sr_err_clear(&err);
        sr_status st = sr_catalog_rule_set(fx->cat, "spray-small-loss", cases[i][0], cases[i][1],
                                           NULL, &err);
        if (st == SR_OK)
            fail_msg("set %s %s was accepted", cases[i][0], cases[i][1]);
        if (!strstr(err.msg, cases[i][2]))
            fail_msg("set %s %s: '%s' lacks '%s'", cases[i][0], cases[i][1], err.msg,
                     cases[i][2]);
    }
    assert_int_equal(sr_catalog_rule_get(fx->cat, "spray-small-loss", &after, NULL), SR_OK);
    assert_int_equal(memcmp(&before, &after, sizeof before), 0);
}

static void null_clears_a_condition_and_fields_round_trip(void **state)
{
    fixture *fx = *state;
    sr_rule r;
    char buf[64];
    assert_int_equal(sr_catalog_rule_set(fx->cat, "spray-small-loss", "max_depth_mm", "null",
                                         &r, NULL), SR_OK);
    assert_true(isnan(r.max_depth_mm));
    assert_int_equal(sr_rule_get_field(&r, "max_depth_mm", buf, sizeof buf, NULL), SR_OK);
    assert_string_equal(buf, "null");
    assert_int_equal(sr_catalog_rule_set(fx->cat, "spray-small-loss", "max_depth_mm", "0.1",
                                         &r, NULL), SR_OK);
    assert_int_equal(sr_rule_get_field(&r, "max_depth_mm", buf, sizeof buf, NULL), SR_OK);
    assert_string_equal(buf, "0.1");
    assert_int_equal(sr_rule_get_field(&r, "class", buf, sizeof buf, NULL), SR_OK);
    assert_string_equal(buf, "null");
    for (size_t i = 0; sr_rule_field_name(i); i++)
        assert_int_equal(sr_rule_get_field(&r, sr_rule_field_name(i), buf, sizeof buf, NULL),
                         SR_OK);
}

static void adding_a_duplicate_name_is_refused(void **state)
{
    fixture *fx = *state;
    sr_rule r;
    assert_int_equal(sr_catalog_rule_get(fx->cat, "spray-small-loss", &r, NULL), SR_OK);
    strcpy(r.name, "Spray-Small-Loss");
    sr_err err;
    assert_int_equal(sr_catalog_rule_add(fx->cat, &r, NULL, &err), SR_E_EXISTS);
    assert_msg_has(err, "rule 'Spray-Small-Loss' already exists");
}

static void adding_an_incomplete_rule_is_refused(void **state)
{
    fixture *fx = *state;
    sr_rule r;
    sr_rule_init(&r);
    strcpy(r.name, "x");
    strcpy(r.process, "ded");
    sr_err err;
    assert_int_equal(sr_catalog_rule_add(fx->cat, &r, NULL, &err), SR_E_RANGE);
    assert_msg_has(err, "bad reason: empty");
}

static void advise_failure_leaves_the_run_as_it_was(void **state)
{
    fixture *fx = *state;
    small_chip(fx);
    advise(fx, NULL, shaft_volume());
    char *features = strdup(fx->run.sections[0].features_json);
    const sr_run_advice *before = fx->run.advice;
    synth_run_dig(&fx->run, 20, 24, 30, 6, 2.0, 0);
    fx->run.sections[1].layer_last = 500;
    sr_err err;
    assert_int_equal(sr_catalog_advise_run(fx->cat, NULL, shaft_volume(), &fx->run, &err), SR_E_RANGE);
    assert_msg_has(err, "section 1");
    assert_ptr_equal(fx->run.advice, before);
    assert_int_equal(fx->run.advice_count, 1);
    assert_string_equal(fx->run.sections[0].features_json, features);
    free(features);
}

static void evaluate_is_three_valued(void **state)
{
    (void)state;
    sr_run run;
    synth_run_make(&run, 100, 72, 20.0, 30.0, 50.0);
    synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    sr_features f;
    assert_int_equal(sr_features_compute(&run, 0, NULL, &f, NULL), SR_OK);
    sr_rule r;
    sr_rule_init(&r);
    sr_rule_part part = {NULL, NULL, SR_SYM_AXIAL, 0, NAN};
    char why[200];
    strcpy(r.material, "C45");
    assert_int_equal(sr_rule_evaluate(&r, &part, &f, 1, why, sizeof why), SR_RULE_UNKNOWN);
    assert_non_null(strstr(why, "no material"));
    r.max_depth_mm = 1;   /* false: depth 2 */
    assert_int_equal(sr_rule_evaluate(&r, &part, &f, 1, why, sizeof why), SR_RULE_NO);
    r.max_depth_mm = 3;
    part.material = "c45";
    assert_int_equal(sr_rule_evaluate(&r, &part, &f, 1, why, sizeof why), SR_RULE_YES);
    strcpy(r.symmetry_kind, "mirror");
    assert_int_equal(sr_rule_evaluate(&r, &part, &f, 1, why, sizeof why), SR_RULE_NO);
    synth_run_free(&run);
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(small_chip_gets_spray_forming_from_the_seed_rules),
        T(more_than_a_quarter_lost_gets_replace),
        T(a_fifth_lost_is_not_replaced),
        T(editing_a_rule_through_the_api_changes_the_advice),
        T(editing_a_rule_with_plain_sql_changes_the_advice),
        T(disabled_rules_do_not_fire),
        T(lower_priority_number_wins),
        T(no_rule_at_all_gives_manual_review_without_a_rule),
        T(material_rule_without_a_material_is_reported),
        T(unknown_material_has_no_family),
        T(feature_the_section_lacks_is_reported),
        T(rule_false_on_another_condition_is_not_unevaluated),
        T(part_volume_unknown_reports_the_replace_rule),
        T(material_that_forbids_a_process_blocks_its_rule),
        T(suitable_material_gives_preheat_and_mass),
        T(materials_are_seeded_with_densities_and_limits),
        T(material_list_gives_every_material),
        T(seed_rules_each_have_a_source_and_a_catch_all_exists),
        T(rule_found_by_id_and_name),
        T(unknown_rule_is_not_found),
        T(unknown_field_is_refused),
        T(bad_values_are_refused_and_change_nothing),
        T(null_clears_a_condition_and_fields_round_trip),
        T(adding_a_duplicate_name_is_refused),
        T(adding_an_incomplete_rule_is_refused),
        T(advise_failure_leaves_the_run_as_it_was),
        cmocka_unit_test(evaluate_is_three_valued),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
