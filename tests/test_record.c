/*
 * test_record.c: the catalogue side of recording a run (src/catalog/catalog_record.h),
 * on run records built inline (tests/support/synth_run.h: a shaft of radius 20 stepping
 * to 30 at z = 50, with a 2 mm deep chip dug on the plain stretch). A run recorded
 * through sr_catalog_run_record reads back with its features and advice, worked out
 * from the seeded rules and the part's material; a run without an instance (a mesh
 * file) is described from the rules alone, also in a catalogue in memory; a run of an
 * unknown instance records nothing.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "catalog/catalog.h"
#include "catalog/catalog_record.h"
#include "catalog/catalog_runs.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/json_query.h"
#include "support/synth_run.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char path[TMPDIR_PATH_MAX];
    sr_catalog *cat;
    int64_t instance;
    sr_run run;
} fixture;

/* A catalogue with one part of material 42CrMo4 (a 100 mm cube, so the chip is a small
 * fraction of it) and one instance; the run is that instance's, with the chip. */
static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    assert_non_null(fx);
    assert_int_equal(tmpdir_make(&fx->dir), 0);
    tmpdir_join(&fx->dir, "cat.db", fx->path);
    sr_err err;
    sr_err_clear(&err);
    if (sr_catalog_open(fx->path, SR_CATALOG_CREATE, &fx->cat, &err) != SR_OK)
        fail_msg("open: %s", err.msg);
    sr_mesh m;
    const double lo[3] = {0, 0, 0}, hi[3] = {100, 100, 100};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    sr_part_new p = {.number = "P-1", .name = "shaft", .material = "42CrMo4", .mesh = &m,
                     .symmetry = {SR_SYM_AXIAL, 0, 0}};
    int64_t part_id;
    assert_int_equal(sr_catalog_part_add(fx->cat, &p, &part_id, &err), SR_OK);
    sr_instance_new in = {.part = "P-1", .mesh = &m, .serial = "S-1"};
    assert_int_equal(sr_catalog_instance_add(fx->cat, &in, &fx->instance, &err), SR_OK);
    sr_mesh_release(&m);
    synth_run_make(&fx->run, 100, 72, 20.0, 30.0, 50.0);
    fx->run.instance_id = fx->instance;
    assert_int_equal(sr_catalog_params_get(fx->cat, "default", &fx->run.params, &err), SR_OK);
    synth_run_dig(&fx->run, 20, 24, 9, 6, 2.0, 0);
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

static int64_t run_count(sr_catalog *cat)
{
    int64_t n = -1;
    assert_int_equal(sr_catalog_run_count(cat, &n, NULL), SR_OK);
    return n;
}

/* The advice for section i (-1: the whole part); fails if there is none. */
static const sr_run_advice *advice_for(const sr_run *run, long i)
{
    const sr_run_advice *a = synth_run_advice_for(run, i);
    if (!a)
        fail_msg("no advice for section %ld", i);
    return a;
}

static void a_recorded_run_reads_back_with_its_features_and_advice(void **state)
{
    fixture *fx = *state;
    sr_err err;
    sr_err_clear(&err);
    int64_t id = 0;
    if (sr_catalog_run_record(fx->cat, &fx->run, &id, &err) != SR_OK)
        fail_msg("record: %s", err.msg);
    assert_true(id > 0);
    /* the run in hand is left described */
    assert_string_equal(fx->run.sections[0].damage_class, "chip");
    assert_non_null(fx->run.sections[0].features_json);
    const sr_run_advice *given = advice_for(&fx->run, 0);

    sr_run back;
    assert_int_equal(sr_catalog_run_get(fx->cat, id, 0, &back, &err), SR_OK);
    assert_int_equal(back.section_count, 1);
    assert_string_equal(back.sections[0].damage_class, "chip");
    assert_non_null(back.sections[0].features_json);
    assert_true(jq_valid(back.sections[0].features_json));
    char *location = jq_text(back.sections[0].features_json, "$.location");
    assert_string_equal(location, "body");
    free(location);
    assert_int_equal(back.advice_count, fx->run.advice_count);
    const sr_run_advice *a = advice_for(&back, 0);
    assert_string_equal(a->process, given->process);
    assert_string_equal(a->rule_name, given->rule_name);
    assert_true(a->rule_id > 0);
    assert_string_equal(a->reason, given->reason);
    /* the part's material, with the catalogue's row for it */
    char *material = jq_text(a->details_json, "$.material");
    assert_string_equal(material, "42CrMo4");
    free(material);
    assert_near(jq_num(a->details_json, "$.density_g_cm3"), 7.85, 1e-12);
    assert_near(jq_num(a->details_json, "$.lost_fraction"),
                back.sections[0].volume_mm3 / 1e6, 1e-9);
    sr_run_release(&back);
    assert_int_equal(run_count(fx->cat), 1);
}

static void a_run_without_an_instance_is_described_from_the_rules_alone(void **state)
{
    fixture *fx = *state;
    fx->run.instance_id = 0;
    sr_err err;
    sr_err_clear(&err);
    if (sr_catalog_run_describe(fx->cat, &fx->run, &err) != SR_OK)
        fail_msg("describe: %s", err.msg);
    assert_string_equal(fx->run.sections[0].damage_class, "chip");
    assert_non_null(fx->run.sections[0].features_json);
    const sr_run_advice *a = advice_for(&fx->run, 0);
    assert_true(a->rule_id > 0);
    char *material = jq_text(a->details_json, "$.material");
    assert_null(material);  /* JSON null: no part, so no material */
    free(material);
    assert_int_equal(run_count(fx->cat), 0);  /* described, not recorded */
}

static void the_catalogue_in_memory_gives_the_same_advice_as_a_fresh_file(void **state)
{
    fixture *fx = *state;
    fx->run.instance_id = 0;
    sr_err err;
    sr_err_clear(&err);
    assert_int_equal(sr_catalog_run_describe(fx->cat, &fx->run, &err), SR_OK);
    sr_run_advice from_file = *advice_for(&fx->run, 0);
    char *details_file = strdup(from_file.details_json);
    assert_non_null(details_file);

    sr_catalog *mem = NULL;
    if (sr_catalog_open_memory(&mem, &err) != SR_OK)
        fail_msg("open memory: %s", err.msg);
    assert_string_equal(sr_catalog_path(mem), ":memory:");
    assert_int_equal(sr_catalog_schema_version(mem), sr_catalog_schema_latest());
    assert_int_equal(sr_catalog_run_describe(mem, &fx->run, &err), SR_OK);
    const sr_run_advice *a = advice_for(&fx->run, 0);
    assert_string_equal(a->process, from_file.process);
    assert_string_equal(a->rule_name, from_file.rule_name);
    assert_string_equal(a->details_json, details_file);
    free(details_file);
    sr_catalog_close(mem);
}

static void a_run_of_an_unknown_instance_records_nothing(void **state)
{
    fixture *fx = *state;
    fx->run.instance_id = fx->instance + 99;
    sr_err err;
    sr_err_clear(&err);
    int64_t id = -7;
    assert_int_equal(sr_catalog_run_record(fx->cat, &fx->run, &id, &err), SR_E_NOTFOUND);
    assert_non_null(strstr(err.msg, "no instance"));
    assert_int_equal(id, -7);
    assert_int_equal(fx->run.advice_count, 0);  /* all or nothing: not described either */
    assert_string_equal(fx->run.sections[0].damage_class, "unclassified");
    assert_int_equal(run_count(fx->cat), 0);
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(a_recorded_run_reads_back_with_its_features_and_advice),
        T(a_run_without_an_instance_is_described_from_the_rules_alone),
        T(the_catalogue_in_memory_gives_the_same_advice_as_a_fresh_file),
        T(a_run_of_an_unknown_instance_records_nothing),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
