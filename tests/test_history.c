/*
 * test_history.c: history queries (src/catalog_history.h) on a small catalogue built
 * through the public API: parts A (steel) and B (bronze), instances A1, A2, B1, and
 * five runs with known dates, sections (classes, volumes) and advice:
 *   run 1  A1  2024-01-10  chip 10 + chip 5    spray_forming       repair
 *   run 2  A1  2024-02-01  gouge 20            replace             replace
 *   run 3  A2  2024-02-29  chip 1              ded + weld_buildup  repair
 *   run 4  B1  2024-03-15  wear_band 100       (no advice)         none
 *   run 5  B1  2024-03-31  failed, no sections                     none
 * Each filter must return exactly the runs it should, newest first, with the
 * per-run figures; the summaries must give the known counts and averages; bad
 * filters fail with one line naming the field.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "catalog.h"
#include "catalog_history.h"
#include "catalog_runs.h"
#include "shapes.h"
#include "support/assert_near.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    sr_catalog *cat;
    int64_t inst[3];
    int64_t run[5];
} fixture;

typedef struct sec_spec {
    const char *cls;
    double volume;
} sec_spec;

static int64_t add_run(fixture *fx, int64_t inst, const char *when, int ok,
                       const sec_spec *secs, size_t nsec, const char *const *proc, size_t nproc)
{
    sr_run r;
    memset(&r, 0, sizeof r);
    r.instance_id = inst;
    r.symmetry = (sr_symmetry){SR_SYM_AXIAL, 0, 0};
    r.params = (sr_params){"default", 10, 12, 0.9, 0.8, 0.07, 0.2, 1.5, ""};
    snprintf(r.method, sizeof r.method, "paper");
    r.fit_quality = -1;
    r.ok = ok;
    if (!ok)
        snprintf(r.error, sizeof r.error, "cannot align");
    snprintf(r.started_at, sizeof r.started_at, "%s", when);
    sr_run_section s[4];
    memset(s, 0, sizeof s);
    for (size_t i = 0; i < nsec; i++) {
        s[i].index = i;
        s[i].z_max_mm = 1;
        s[i].volume_mm3 = secs[i].volume;
        snprintf(s[i].damage_class, sizeof s[i].damage_class, "%s", secs[i].cls);
    }
    sr_run_advice a[4];
    memset(a, 0, sizeof a);
    for (size_t i = 0; i < nproc; i++) {
        a[i].section_index = nsec ? 0 : -1;
        snprintf(a[i].process, sizeof a[i].process, "%s", proc[i]);
        snprintf(a[i].reason, sizeof a[i].reason, "because");
    }
    r.sections = s;
    r.section_count = nsec;
    r.advice = a;
    r.advice_count = nproc;
    sr_err err = {{0}};
    int64_t id;
    if (sr_catalog_run_add(fx->cat, &r, &id, &err) != SR_OK)
        fail_msg("run add: %s", err.msg);
    return id;
}

static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    assert_non_null(fx);
    assert_int_equal(tmpdir_make(&fx->dir), 0);
    char db[TMPDIR_PATH_MAX];
    tmpdir_join(&fx->dir, "cat.db", db);
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(db, SR_CATALOG_CREATE, &fx->cat, &err), SR_OK);
    sr_mesh m = {0};
    assert_int_equal(sr_shape_cylinder(10, 0, 20, 8, &m, &err), SR_OK);
    sr_part_new pa = {.number = "A", .name = "shaft", .material = "Steel", .mesh = &m};
    sr_part_new pb = {.number = "B", .name = "bush", .material = "Bronze", .mesh = &m};
    int64_t id;
    assert_int_equal(sr_catalog_part_add(fx->cat, &pa, &id, &err), SR_OK);
    assert_int_equal(sr_catalog_part_add(fx->cat, &pb, &id, &err), SR_OK);
    const char *parts[3] = {"A", "A", "B"}, *serials[3] = {"A1", "A2", "B1"};
    for (int i = 0; i < 3; i++) {
        sr_instance_new in = {.part = parts[i], .mesh = &m, .serial = serials[i]};
        assert_int_equal(sr_catalog_instance_add(fx->cat, &in, &fx->inst[i], &err), SR_OK);
    }
    sr_mesh_release(&m);
    const sec_spec s1[] = {{"chip", 10}, {"chip", 5}}, s2[] = {{"gouge", 20}},
                   s3[] = {{"chip", 1}}, s4[] = {{"wear_band", 100}};
    const char *p1[] = {"spray_forming"}, *p2[] = {"replace"},
               *p3[] = {"weld_buildup", "ded", "ded"};
    fx->run[0] = add_run(fx, fx->inst[0], "2024-01-10T08:00:00Z", 1, s1, 2, p1, 1);
    fx->run[1] = add_run(fx, fx->inst[0], "2024-02-01T00:00:00Z", 1, s2, 1, p2, 1);
    fx->run[2] = add_run(fx, fx->inst[1], "2024-02-29T23:59:59Z", 1, s3, 1, p3, 3);
    fx->run[3] = add_run(fx, fx->inst[2], "2024-03-15T12:00:00Z", 1, s4, 1, NULL, 0);
    fx->run[4] = add_run(fx, fx->inst[2], "2024-03-31T10:00:00Z", 0, NULL, 0, NULL, 0);
    *state = fx;
    return 0;
}

static int teardown(void **state)
{
    fixture *fx = *state;
    sr_catalog_close(fx->cat);
    tmpdir_remove(&fx->dir);
    free(fx);
    return 0;
}

typedef struct rows {
    sr_history_row v[16];
    size_t n;
} rows;

static int collect(const sr_history_row *r, void *user)
{
    rows *rs = user;
    assert_true(rs->n < 16);
    rs->v[rs->n++] = *r;
    return 0;
}

static rows query(fixture *fx, const sr_history_filter *f)
{
    rows rs;
    memset(&rs, 0, sizeof rs);
    sr_err err = {{0}};
    if (sr_catalog_history(fx->cat, f, collect, &rs, &err) != SR_OK)
        fail_msg("history: %s", err.msg);
    return rs;
}

/* The run numbers (1..5) of the rows, as a string: "3 2 1". */
static const char *ids(const fixture *fx, const rows *rs)
{
    static char buf[64];
    buf[0] = '\0';
    for (size_t i = 0; i < rs->n; i++)
        for (int k = 0; k < 5; k++)
            if (rs->v[i].run_id == fx->run[k])
                snprintf(buf + strlen(buf), sizeof buf - strlen(buf), "%s%d", i ? " " : "",
                         k + 1);
    return buf;
}

static void all_runs_newest_first_with_their_figures(void **state)
{
    fixture *fx = *state;
    rows rs = query(fx, NULL);
    assert_string_equal(ids(fx, &rs), "5 4 3 2 1");
    const sr_history_row *r1 = &rs.v[4], *r3 = &rs.v[2], *r5 = &rs.v[0];
    assert_string_equal(r1->part_number, "A");
    assert_string_equal(r1->serial, "A1");
    assert_string_equal(r1->material, "Steel");
    assert_string_equal(r1->date, "2024-01-10");
    assert_int_equal(r1->section_count, 2);
    assert_near(r1->missing_volume_mm3, 15, 1e-12);
    assert_string_equal(r1->classes, "chip");
    assert_string_equal(r1->processes, "spray_forming");
    assert_int_equal(r1->outcome, SR_OUTCOME_REPAIR);
    assert_string_equal(r3->processes, "ded,weld_buildup");
    assert_int_equal(rs.v[3].outcome, SR_OUTCOME_REPLACE);
    assert_int_equal(rs.v[1].outcome, SR_OUTCOME_NONE);
    assert_false(r5->ok);
    assert_int_equal(r5->section_count, 0);
    assert_near(r5->missing_volume_mm3, 0, 0);
    assert_string_equal(r5->classes, "");
}

static void filters_return_exactly_their_runs(void **state)
{
    fixture *fx = *state;
    sr_history_filter f = {0};
    f.part = "a"; /* part numbers ignore ASCII case */
    rows rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "3 2 1");
    f.part = "2"; /* by id */
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "5 4");
    memset(&f, 0, sizeof f);
    f.instance_id = fx->inst[0];
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "2 1");
    memset(&f, 0, sizeof f);
    f.material = "BRONZE";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "5 4");
    memset(&f, 0, sizeof f);
    f.since = "2024-02-01"; /* inclusive at both ends, whole days */
    f.until = "2024-02-29";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "3 2");
    f.since = NULL;
    f.until = "2024-01-10";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "1");
    f.since = "2024-03-01";
    f.until = NULL;
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "5 4");
    /* combined */
    memset(&f, 0, sizeof f);
    f.part = "A";
    f.material = "steel";
    f.since = "2024-02-01";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "3 2");
    f.instance_id = fx->inst[1];
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "3");
    /* no match: no rows, no error */
    memset(&f, 0, sizeof f);
    f.part = "A";
    f.material = "Bronze";
    rs = query(fx, &f);
    assert_int_equal(rs.n, 0);
}

static void summary_counts_classes_volumes_outcomes_and_months(void **state)
{
    fixture *fx = *state;
    sr_history_summary s;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_history_summary(fx->cat, NULL, &s, &err), SR_OK);
    assert_int_equal(s.runs, 5);
    assert_int_equal(s.failed, 1);
    assert_int_equal(s.repair, 2);
    assert_int_equal(s.replace, 1);
    assert_int_equal(s.none, 2);
    assert_near(s.repair_fraction, 2.0 / 3.0, 1e-12);
    assert_near(s.avg_missing_volume_mm3, (15 + 20 + 1 + 100 + 0) / 5.0, 1e-12);
    assert_int_equal(s.part_count, 2);
    assert_string_equal(s.parts[0].part_number, "A");
    assert_int_equal(s.parts[0].runs, 3);
    assert_near(s.parts[0].avg_missing_volume_mm3, 36.0 / 3, 1e-12);
    assert_string_equal(s.parts[0].top_class, "chip");
    assert_int_equal(s.parts[0].top_class_sections, 3);
    assert_int_equal(s.parts[0].sections, 4);
    assert_int_equal(s.parts[0].repair, 2);
    assert_int_equal(s.parts[0].replace, 1);
    assert_string_equal(s.parts[1].top_class, "wear_band");
    assert_near(s.parts[1].avg_missing_volume_mm3, 50, 1e-12);
    assert_int_equal(s.month_count, 3);
    assert_string_equal(s.months[0].month, "2024-01");
    assert_int_equal(s.months[0].runs, 1);
    assert_string_equal(s.months[1].month, "2024-02");
    assert_int_equal(s.months[1].runs, 2);
    assert_int_equal(s.months[2].runs, 2);
    sr_history_summary_release(&s);

    sr_history_filter f = {0};
    f.material = "Bronze";
    assert_int_equal(sr_catalog_history_summary(fx->cat, &f, &s, &err), SR_OK);
    assert_int_equal(s.runs, 2);
    assert_true(isnan(s.repair_fraction));
    assert_int_equal(s.part_count, 1);
    sr_history_summary_release(&s);
}

static void expect_refused(fixture *fx, const sr_history_filter *f, sr_status want,
                           const char *msg)
{
    sr_err err = {{0}};
    rows rs;
    memset(&rs, 0, sizeof rs);
    assert_int_equal(sr_catalog_history(fx->cat, f, collect, &rs, &err), want);
    assert_msg_has(err, msg);
    assert_int_equal(rs.n, 0);
    sr_err e2 = {{0}};
    sr_history_summary s;
    memset(&s, 0xab, sizeof s);
    assert_int_equal(sr_catalog_history_summary(fx->cat, f, &s, &e2), want);
    assert_string_equal(e2.msg, err.msg);
    assert_int_equal(sr_catalog_history_check(fx->cat, f, &e2), want);
}

static void bad_dates_are_refused_naming_the_field(void **state)
{
    fixture *fx = *state;
    sr_history_filter f = {0};
    f.since = "2024-02-30";
    expect_refused(fx, &f, SR_E_RANGE, "bad since date '2024-02-30'");
    f.since = NULL;
    f.until = "24-01-01";
    expect_refused(fx, &f, SR_E_RANGE, "bad until date '24-01-01'");
    f.since = "2024-03-02";
    f.until = "2024-03-01";
    expect_refused(fx, &f, SR_E_RANGE, "since 2024-03-02 is after until 2024-03-01");
}

static void unknown_part_instance_and_material_are_not_found(void **state)
{
    fixture *fx = *state;
    sr_history_filter f = {0};
    f.part = "NOPE";
    expect_refused(fx, &f, SR_E_NOTFOUND, "no part 'NOPE' in the catalogue");
    f.part = NULL;
    f.instance_id = 99;
    expect_refused(fx, &f, SR_E_NOTFOUND, "no instance 99 in the catalogue");
    f.instance_id = 0;
    f.material = "Unobtainium";
    expect_refused(fx, &f, SR_E_NOTFOUND, "no material 'Unobtainium' in the catalogue");
}

static void the_last_day_of_a_year_and_a_leap_day_are_whole_days(void **state)
{
    fixture *fx = *state;
    add_run(fx, fx->inst[0], "2024-12-31T23:59:59Z", 1, NULL, 0, NULL, 0);
    sr_history_filter f = {0};
    f.since = "2024-12-31";
    f.until = "2024-12-31";
    rows rs = query(fx, &f);
    assert_int_equal(rs.n, 1);
    f.since = f.until = "2024-02-29";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "3");
}

static int stop_after_one(const sr_history_row *r, void *user)
{
    (void)r;
    (*(int *)user)++;
    return 1;
}

static void a_callback_can_stop_the_query(void **state)
{
    fixture *fx = *state;
    int n = 0;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_history(fx->cat, NULL, stop_after_one, &n, &err), SR_OK);
    assert_int_equal(n, 1);
}

static void outcome_names(void **state)
{
    (void)state;
    assert_string_equal(sr_history_outcome_str(SR_OUTCOME_NONE), "none");
    assert_string_equal(sr_history_outcome_str(SR_OUTCOME_REPAIR), "repair");
    assert_string_equal(sr_history_outcome_str(SR_OUTCOME_REPLACE), "replace");
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(all_runs_newest_first_with_their_figures),
        T(filters_return_exactly_their_runs),
        T(summary_counts_classes_volumes_outcomes_and_months),
        T(bad_dates_are_refused_naming_the_field),
        T(unknown_part_instance_and_material_are_not_found),
        T(the_last_day_of_a_year_and_a_leap_day_are_whole_days),
        T(a_callback_can_stop_the_query),
        cmocka_unit_test(outcome_names),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
