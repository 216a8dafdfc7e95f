/*
 * test_history.c: history queries (src/catalog/catalog_history.h) on a small catalogue built
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

#include "catalog/catalog.h"
#include "catalog/catalog_history.h"
#include "catalog/catalog_inspect.h"
#include "catalog/catalog_int.h"
#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "mesh/shapes.h"
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

/* The parts' materials, Steel and Bronze: a part may name only a material the
 * catalogue holds. */
static void add_materials(sr_catalog *cat)
{
    sr_material_new steel = {.name = "Steel", .density_g_cm3 = 7.85, .family = "steel"};
    sr_material_new bronze = {.name = "Bronze", .density_g_cm3 = 8.7, .family = "copper"};
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_material_add(cat, &steel, NULL, &err), SR_OK);
    assert_int_equal(sr_catalog_material_add(cat, &bronze, NULL, &err), SR_OK);
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
    add_materials(fx->cat);
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

/* ---- the summary cells of sql/004 against the runs ---- */

/* Both summaries field by field. The test volumes are exact binary fractions, so the
 * sums are exact in any order and the averages must be equal, not merely close. */
static void assert_same_summary(const sr_history_summary *a, const sr_history_summary *b,
                                const char *what)
{
    if (a->pass != b->pass || a->machine != b->machine || a->rework != b->rework)
        fail_msg("%s: verdicts pass %zu/%zu machine %zu/%zu rework %zu/%zu", what, a->pass, b->pass,
                 a->machine, b->machine, a->rework, b->rework);
    if (a->runs != b->runs || a->failed != b->failed || a->repair != b->repair ||
        a->replace != b->replace || a->none != b->none)
        fail_msg("%s: runs %zu/%zu failed %zu/%zu repair %zu/%zu replace %zu/%zu none %zu/%zu",
                 what, a->runs, b->runs, a->failed, b->failed, a->repair, b->repair, a->replace,
                 b->replace, a->none, b->none);
    if (!(isnan(a->repair_fraction) && isnan(b->repair_fraction)) &&
        a->repair_fraction != b->repair_fraction)
        fail_msg("%s: repair fraction %.17g vs %.17g", what, a->repair_fraction,
                 b->repair_fraction);
    if (a->avg_missing_volume_mm3 != b->avg_missing_volume_mm3)
        fail_msg("%s: average volume %.17g vs %.17g", what, a->avg_missing_volume_mm3,
                 b->avg_missing_volume_mm3);
    if (a->part_count != b->part_count || a->month_count != b->month_count)
        fail_msg("%s: %zu/%zu parts, %zu/%zu months", what, a->part_count, b->part_count,
                 a->month_count, b->month_count);
    for (size_t i = 0; i < a->part_count; i++) {
        const sr_history_part *p = &a->parts[i], *q = &b->parts[i];
        if (strcmp(p->part_number, q->part_number) != 0 || p->runs != q->runs ||
            p->avg_missing_volume_mm3 != q->avg_missing_volume_mm3 ||
            strcmp(p->top_class, q->top_class) != 0 ||
            p->top_class_sections != q->top_class_sections || p->sections != q->sections ||
            p->repair != q->repair || p->replace != q->replace)
            fail_msg("%s: part %s/%s: runs %zu/%zu avg %.17g/%.17g top %s/%s %zu/%zu "
                     "sections %zu/%zu repair %zu/%zu replace %zu/%zu",
                     what, p->part_number, q->part_number, p->runs, q->runs,
                     p->avg_missing_volume_mm3, q->avg_missing_volume_mm3, p->top_class,
                     q->top_class, p->top_class_sections, q->top_class_sections, p->sections,
                     q->sections, p->repair, q->repair, p->replace, q->replace);
    }
    for (size_t i = 0; i < a->month_count; i++)
        if (strcmp(a->months[i].month, b->months[i].month) != 0 ||
            a->months[i].runs != b->months[i].runs)
            fail_msg("%s: month %s/%s: %zu/%zu runs", what, a->months[i].month,
                     b->months[i].month, a->months[i].runs, b->months[i].runs);
}

/* The filters the cells answer, each compared both ways; returns the total runs of the
 * whole history. The automatic way must take the cells for every one of them. */
static size_t cells_equal_runs(sr_catalog *cat, const char *when)
{
    static const sr_history_filter filters[] = {
        {0},
        {.part = "A"},
        {.part = "B"},
        {.material = "steel"},
        {.material = "Bronze"},
        {.since = "2024-02-01", .until = "2024-02-29"},
        {.since = "2024-01-01", .until = "2024-03-31"},
        {.since = "2024-02-01"},
        {.until = "2024-02-29"},
        {.part = "A", .since = "2024-02-01", .until = "2024-02-29"},
        {.material = "Bronze", .since = "2024-03-01"},
        {.since = "2024-05-01", .until = "2024-06-30"}, /* empty */
    };
    size_t total = 0;
    for (size_t i = 0; i < sizeof filters / sizeof filters[0]; i++) {
        sr_history_summary runs, cells, autos;
        bool used = false;
        sr_err err = {{0}};
        if (sr_cat_history_summary_way(cat, &filters[i], SR_CAT_SUMMARY_RUNS, &runs, &used,
                                       &err) != SR_OK)
            fail_msg("%s, filter %zu, runs: %s", when, i, err.msg);
        assert_false(used);
        if (sr_cat_history_summary_way(cat, &filters[i], SR_CAT_SUMMARY_CELLS, &cells, &used,
                                       &err) != SR_OK)
            fail_msg("%s, filter %zu, cells: %s", when, i, err.msg);
        assert_true(used);
        assert_int_equal(sr_catalog_history_summary(cat, &filters[i], &autos, &err), SR_OK);
        char what[96];
        snprintf(what, sizeof what, "%s, filter %zu", when, i);
        assert_same_summary(&cells, &runs, what);
        assert_same_summary(&autos, &runs, what);
        if (i == 0)
            total = runs.runs;
        sr_history_summary_release(&runs);
        sr_history_summary_release(&cells);
        sr_history_summary_release(&autos);
    }
    return total;
}

static void raw(sr_catalog *cat, const char *sql)
{
    char *msg = NULL;
    if (sqlite3_exec(cat->db, sql, NULL, NULL, &msg) != SQLITE_OK) {
        fail_msg("%s: %s", sql, msg ? msg : "?");
        sqlite3_free(msg);
    }
}

static int64_t raw_count(sr_catalog *cat, const char *sql)
{
    sqlite3_stmt *st;
    assert_int_equal(sqlite3_prepare_v2(cat->db, sql, -1, &st, NULL), SQLITE_OK);
    assert_int_equal(sqlite3_step(st), SQLITE_ROW);
    int64_t n = sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    return n;
}

/* More runs of both parts and all outcomes over four months, for the cell tests. */
static void more_runs(fixture *fx)
{
    const sec_spec s1[] = {{"gouge", 2.5}, {"chip", 0.75}, {"crack", 4}},
                   s2[] = {{"wear_band", 8}}, s3[] = {{"chip", 16}, {"chip", 0.5}};
    const char *rep[] = {"ded", "replace"}, *one[] = {"spray_forming"},
               *two[] = {"replace", "REPLACE: beyond repair"};
    add_run(fx, fx->inst[1], "2024-01-31T23:59:59Z", 1, s1, 3, rep, 2);
    add_run(fx, fx->inst[2], "2024-02-01T00:00:00Z", 1, s2, 1, one, 1);
    add_run(fx, fx->inst[0], "2024-04-02T09:00:00Z", 1, s3, 2, two, 2);
    add_run(fx, fx->inst[2], "2024-04-30T09:00:00Z", 0, NULL, 0, NULL, 0);
    add_run(fx, fx->inst[1], "2024-03-01T00:00:00Z", 1, s2, 1, NULL, 0);
}

static void summary_cells_equal_the_runs_after_inserts(void **state)
{
    fixture *fx = *state;
    assert_int_equal(cells_equal_runs(fx->cat, "the fixture"), 5);
    more_runs(fx);
    assert_int_equal(cells_equal_runs(fx->cat, "more runs"), 10);
    /* one cell per part and month with runs: A 01 02 03 04, B 02 03 04 */
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM history_cells"), 7);
    assert_int_equal(raw_count(fx->cat, "SELECT sum(runs) FROM history_cells"), 10);
}

static void summary_cells_follow_deletes(void **state)
{
    fixture *fx = *state;
    more_runs(fx);
    char sql[160];
    /* a run with sections and advice (cascades) */
    snprintf(sql, sizeof sql, "DELETE FROM runs WHERE id = %lld", (long long)fx->run[0]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "run 1 deleted"), 9);
    /* one section (its advice goes with it), then one advice of another run */
    raw(fx->cat, "DELETE FROM sections WHERE id = (SELECT min(id) FROM sections"
                 " WHERE class = 'chip')");
    assert_int_equal(cells_equal_runs(fx->cat, "a section deleted"), 9);
    /* 'replace' advice: run 2 had only that (now none), a run of A2 had it with 'ded'
     * (now repair), a run of A1 keeps its 'REPLACE: beyond repair' (still replace) */
    raw(fx->cat, "DELETE FROM advice WHERE process = 'replace'");
    assert_int_equal(cells_equal_runs(fx->cat, "replace advice deleted"), 9);
    raw(fx->cat, "DELETE FROM advice WHERE process = 'ded'");
    assert_int_equal(cells_equal_runs(fx->cat, "ded advice deleted"), 9);
    /* an instance with all its runs (B1: runs 4, 5 and two more) */
    snprintf(sql, sizeof sql, "DELETE FROM instances WHERE id = %lld", (long long)fx->inst[2]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "instance B1 deleted"), 5);
    /* part B has no runs left: no cell of it remains */
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM history_cells c JOIN parts p"
                                        " ON p.id = c.part_id WHERE p.number = 'B'"),
                     0);
    /* with foreign keys off (plain sqlite3): the run's rows stay behind, orphaned, and
     * count in neither way */
    raw(fx->cat, "PRAGMA foreign_keys = OFF");
    snprintf(sql, sizeof sql, "DELETE FROM runs WHERE id = %lld", (long long)fx->run[1]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "run 2 deleted, foreign keys off"), 4);
    raw(fx->cat, "DELETE FROM sections WHERE run_id NOT IN (SELECT id FROM runs)");
    raw(fx->cat, "DELETE FROM advice WHERE run_id NOT IN (SELECT id FROM runs)");
    assert_int_equal(cells_equal_runs(fx->cat, "orphans deleted"), 4);
    raw(fx->cat, "PRAGMA foreign_keys = ON");
    /* every run deleted: no cells at all */
    raw(fx->cat, "DELETE FROM runs");
    assert_int_equal(cells_equal_runs(fx->cat, "all runs deleted"), 0);
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM history_cells"), 0);
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM history_class_cells"), 0);
}

static int count_problem(const char *what, void *user)
{
    print_message("problem: %s\n", what);
    (*(int *)user)++;
    return 0;
}

/* sr_catalog_instance_remove / part_remove: refused while runs refer to the row, then
 * with SR_CATALOG_WITH_RUNS the cells lose exactly the runs that went. */
static void removals_with_runs_keep_the_cells_equal_to_the_runs(void **state)
{
    fixture *fx = *state;
    more_runs(fx);
    sr_err err = {{0}};
    sr_removal r = {-1, -1, -1};
    sr_part_info b;
    assert_int_equal(sr_catalog_part_find(fx->cat, "B", &b, &err), SR_OK);
    int64_t meshes = raw_count(fx->cat, "SELECT count(*) FROM meshes");

    /* refused, naming what would go; nothing changes */
    assert_int_equal(sr_catalog_instance_remove(fx->cat, fx->inst[1], 0, &r, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "instance 2 has 3 runs; nothing removed (--with-runs removes "
                                 "them too)");
    assert_int_equal(sr_catalog_part_remove(fx->cat, "B", 0, &r, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "part 'B' has 1 instance and 4 runs; nothing removed "
                                 "(--with-runs removes them too)");
    assert_int_equal(r.runs, -1); /* written only on success */
    assert_int_equal(cells_equal_runs(fx->cat, "refused removals"), 10);
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM meshes"), meshes);

    /* instance A2 with its 3 runs, and its scan */
    assert_int_equal(
        sr_catalog_instance_remove(fx->cat, fx->inst[1], SR_CATALOG_WITH_RUNS, &r, &err), SR_OK);
    assert_int_equal(r.instances, 0);
    assert_int_equal(r.runs, 3);
    assert_int_equal(r.meshes, 1);
    assert_int_equal(cells_equal_runs(fx->cat, "instance A2 removed"), 7);
    /* part B with instance B1, its 4 runs, the scan and the part's mesh */
    assert_int_equal(sr_catalog_part_remove(fx->cat, "B", SR_CATALOG_WITH_RUNS, &r, &err), SR_OK);
    assert_int_equal(r.instances, 1);
    assert_int_equal(r.runs, 4);
    assert_int_equal(r.meshes, 2);
    /* (cells_equal_runs filters by part B, which is gone: the check below compares
     * every cell with the runs instead) */
    assert_int_equal(raw_count(fx->cat, "SELECT sum(runs) FROM history_cells"), 3);
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM runs"), 3);
    char sql[128];
    snprintf(sql, sizeof sql, "SELECT count(*) FROM history_cells WHERE part_id = %lld",
             (long long)b.id);
    assert_int_equal(raw_count(fx->cat, sql), 0);
    snprintf(sql, sizeof sql, "SELECT count(*) FROM history_class_cells WHERE part_id = %lld",
             (long long)b.id);
    assert_int_equal(raw_count(fx->cat, sql), 0);
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM meshes"), meshes - 3);
    assert_int_equal(raw_count(fx->cat, "SELECT count(*) FROM sections s WHERE NOT EXISTS"
                                        " (SELECT 1 FROM runs r WHERE r.id = s.run_id)"),
                     0);
    assert_int_equal(sr_catalog_part_find(fx->cat, "B", &b, &err), SR_E_NOTFOUND);
    int problems = 0;
    sr_check_info info;
    assert_int_equal(sr_catalog_check(fx->cat, count_problem, &problems, &info, &err), SR_OK);
    assert_int_equal(problems, 0);
    assert_int_equal(info.problems, 0);
}

/* sr_catalog_check compares the cells with the runs: a cell edited by hand is found. */
static void check_finds_cells_that_disagree_with_the_runs(void **state)
{
    fixture *fx = *state;
    sr_err err = {{0}};
    sr_check_info info;
    int problems = 0;
    raw(fx->cat, "UPDATE history_cells SET volume_mm3 = volume_mm3 + 1"
                 " WHERE month = '2024-01'");
    raw(fx->cat, "UPDATE history_class_cells SET sections = sections + 1 WHERE class = 'gouge'");
    assert_int_equal(sr_catalog_check(fx->cat, count_problem, &problems, &info, &err), SR_OK);
    assert_int_equal(problems, 2);
    assert_int_equal(info.problems, 2);
    assert_int_equal(info.application_id, SR_CATALOG_APP_ID);
    assert_int_equal(info.schema_version, sr_catalog_schema_latest());
}

static void summary_cells_follow_updates(void **state)
{
    fixture *fx = *state;
    more_runs(fx);
    char sql[200];
    /* a run's outcome: a repair advice becomes replace, then back */
    raw(fx->cat, "UPDATE advice SET process = 'replace' WHERE process = 'spray_forming'");
    assert_int_equal(cells_equal_runs(fx->cat, "advice now replace"), 10);
    raw(fx->cat, "UPDATE advice SET process = 'weld_buildup' WHERE process LIKE 'replace%'");
    assert_int_equal(cells_equal_runs(fx->cat, "no replace left"), 10);
    /* an advice moved to another run (a run without advice) */
    snprintf(sql, sizeof sql,
             "UPDATE advice SET run_id = %lld, section_id = NULL WHERE id ="
             " (SELECT min(id) FROM advice)",
             (long long)fx->run[3]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "advice moved"), 10);
    /* a run's start moves to another month, its status flips */
    snprintf(sql, sizeof sql,
             "UPDATE runs SET started_at = '2024-04-15T00:00:00Z', status = 'failed',"
             " error = 'x' WHERE id = %lld",
             (long long)fx->run[0]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "run 1 moved to April, failed"), 10);
    /* a run moves to an instance of the other part */
    snprintf(sql, sizeof sql, "UPDATE runs SET instance_id = %lld WHERE id = %lld",
             (long long)fx->inst[2], (long long)fx->run[1]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "run 2 moved to part B"), 10);
    /* a section's class and volume */
    raw(fx->cat, "UPDATE sections SET class = 'crack', volume_mm3 = 64 WHERE class = 'wear_band'");
    assert_int_equal(cells_equal_runs(fx->cat, "sections reclassified"), 10);
    /* an instance moves to the other part with its runs */
    snprintf(sql, sizeof sql, "UPDATE instances SET part_id = (SELECT id FROM parts WHERE"
                              " number = 'B') WHERE id = %lld",
             (long long)fx->inst[1]);
    raw(fx->cat, sql);
    assert_int_equal(cells_equal_runs(fx->cat, "instance A2 moved to part B"), 10);
    /* a part's material changes: nothing to move, the answer follows */
    raw(fx->cat, "UPDATE parts SET material_id = (SELECT id FROM materials WHERE name ="
                 " 'Bronze') WHERE number = 'A'");
    assert_int_equal(cells_equal_runs(fx->cat, "part A now bronze"), 10);
    /* an update of other columns changes nothing */
    raw(fx->cat, "UPDATE runs SET method = 'robust'");
    assert_int_equal(cells_equal_runs(fx->cat, "method changed"), 10);
}

static void summary_takes_the_runs_when_cells_cannot_answer(void **state)
{
    fixture *fx = *state;
    sr_history_filter by_instance = {.instance_id = fx->inst[0]};
    sr_history_filter mid_month = {.since = "2024-02-02"};
    sr_history_filter to_mid_month = {.until = "2024-02-28"};
    const sr_history_filter *fs[] = {&by_instance, &mid_month, &to_mid_month};
    for (int i = 0; i < 3; i++) {
        sr_history_summary s;
        bool used = true;
        sr_err err = {{0}};
        assert_int_equal(sr_cat_history_summary_way(fx->cat, fs[i], SR_CAT_SUMMARY_AUTO, &s,
                                                    &used, &err),
                         SR_OK);
        assert_false(used);
        sr_history_summary_release(&s);
        memset(&s, 0xab, sizeof s);
        assert_int_equal(sr_cat_history_summary_way(fx->cat, fs[i], SR_CAT_SUMMARY_CELLS, &s,
                                                    &used, &err),
                         SR_E_INVALID);
        assert_msg_has(err, "cannot answer this filter");
    }
    /* the instance's summary itself: runs 1 and 2 */
    sr_history_summary s;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_history_summary(fx->cat, &by_instance, &s, &err), SR_OK);
    assert_int_equal(s.runs, 2);
    assert_int_equal(s.replace, 1);
    sr_history_summary_release(&s);
}

static void an_irregular_start_time_sends_its_months_to_the_runs(void **state)
{
    fixture *fx = *state;
    /* '2024-02' sorts before '2024-02-01': a day filter from 2024-02-01 leaves it out,
     * but it sits in the February cell */
    add_run(fx, fx->inst[0], "2024-02", 1, NULL, 0, NULL, 0);
    sr_history_filter from_feb = {.since = "2024-02-01"};
    sr_history_filter to_jan = {.until = "2024-01-31"};
    sr_history_filter march = {.since = "2024-03-01", .until = "2024-03-31"};
    sr_history_summary runs, s;
    bool used;
    sr_err err = {{0}};
    assert_int_equal(sr_cat_history_summary_way(fx->cat, &from_feb, SR_CAT_SUMMARY_AUTO, &s,
                                                &used, &err),
                     SR_OK);
    assert_false(used);
    assert_int_equal(s.runs, 4); /* runs 2..5, not the irregular one */
    sr_history_summary_release(&s);
    assert_int_equal(sr_cat_history_summary_way(fx->cat, &to_jan, SR_CAT_SUMMARY_AUTO, &s,
                                                &used, &err),
                     SR_OK);
    assert_false(used);
    assert_int_equal(s.runs, 2); /* run 1 and, by the day filter, the irregular one */
    sr_history_summary_release(&s);
    /* months away from it still come from the cells, and agree */
    assert_int_equal(sr_cat_history_summary_way(fx->cat, &march, SR_CAT_SUMMARY_AUTO, &s,
                                                &used, &err),
                     SR_OK);
    assert_true(used);
    assert_int_equal(sr_cat_history_summary_way(fx->cat, &march, SR_CAT_SUMMARY_RUNS, &runs,
                                                NULL, &err),
                     SR_OK);
    assert_same_summary(&s, &runs, "march");
    sr_history_summary_release(&s);
    sr_history_summary_release(&runs);
    /* the whole history counts it in its month either way */
    assert_int_equal(sr_cat_history_summary_way(fx->cat, NULL, SR_CAT_SUMMARY_CELLS, &s, &used,
                                                &err),
                     SR_OK);
    assert_int_equal(sr_cat_history_summary_way(fx->cat, NULL, SR_CAT_SUMMARY_RUNS, &runs, NULL,
                                                &err),
                     SR_OK);
    assert_same_summary(&s, &runs, "whole history");
    assert_int_equal(s.runs, 6);
    assert_int_equal(s.months[1].runs, 3);
    sr_history_summary_release(&s);
    sr_history_summary_release(&runs);
}

/* A catalogue made at schema version 3 (before the cells) with runs, then opened by
 * this build: migration 004 fills the cells from the runs already there. */
static void migration_004_backfills_the_cells(void **state)
{
    (void)state;
    fixture fx;
    memset(&fx, 0, sizeof fx);
    assert_int_equal(tmpdir_make(&fx.dir), 0);
    char db[TMPDIR_PATH_MAX];
    tmpdir_join(&fx.dir, "v3.db", db);
    sr_sql_file v3[4];
    for (int i = 0; i < 3; i++)
        v3[i] = sr_sql_files[i];
    v3[3] = (sr_sql_file){NULL, NULL};
    assert_string_equal(v3[2].name, "003_history.sql");
    sr_err err = {{0}};
    assert_int_equal(sr_cat_open_with(db, SR_CATALOG_CREATE, v3, &fx.cat, &err), SR_OK);
    assert_int_equal(raw_count(fx.cat, "PRAGMA user_version"), 3);
    assert_int_equal(raw_count(fx.cat, "SELECT count(*) FROM sqlite_schema WHERE name ="
                                       " 'history_cells'"),
                     0);
    sr_mesh m = {0};
    assert_int_equal(sr_shape_cylinder(10, 0, 20, 8, &m, &err), SR_OK);
    add_materials(fx.cat);
    sr_part_new pa = {.number = "A", .name = "shaft", .material = "Steel", .mesh = &m};
    sr_part_new pb = {.number = "B", .name = "bush", .material = "Bronze", .mesh = &m};
    int64_t id;
    assert_int_equal(sr_catalog_part_add(fx.cat, &pa, &id, &err), SR_OK);
    assert_int_equal(sr_catalog_part_add(fx.cat, &pb, &id, &err), SR_OK);
    const char *parts[3] = {"A", "A", "B"};
    for (int i = 0; i < 3; i++) {
        sr_instance_new in = {.part = parts[i], .mesh = &m};
        assert_int_equal(sr_catalog_instance_add(fx.cat, &in, &fx.inst[i], &err), SR_OK);
    }
    sr_mesh_release(&m);
    const sec_spec s1[] = {{"chip", 10}, {"chip", 5}}, s2[] = {{"gouge", 20}};
    const char *p1[] = {"spray_forming"}, *p2[] = {"replace"};
    add_run(&fx, fx.inst[0], "2024-01-10T08:00:00Z", 1, s1, 2, p1, 1);
    add_run(&fx, fx.inst[0], "2024-02-01T00:00:00Z", 1, s2, 1, p2, 1);
    add_run(&fx, fx.inst[2], "2024-03-31T10:00:00Z", 0, NULL, 0, NULL, 0);
    more_runs(&fx);
    sr_history_summary before;
    assert_int_equal(sr_catalog_history_summary(fx.cat, NULL, &before, &err), SR_OK);
    sr_catalog_close(fx.cat);

    assert_int_equal(sr_catalog_open(db, 0, &fx.cat, &err), SR_OK);
    assert_int_equal(raw_count(fx.cat, "PRAGMA user_version"), sr_catalog_schema_latest());
    assert_int_equal(raw_count(fx.cat, "SELECT sum(runs) FROM history_cells"), 8);
    assert_int_equal(raw_count(fx.cat, "SELECT sum(sections) FROM history_class_cells"), 10);
    sr_history_summary after;
    bool used = false;
    assert_int_equal(sr_cat_history_summary_way(fx.cat, NULL, SR_CAT_SUMMARY_CELLS, &after,
                                                &used, &err),
                     SR_OK);
    assert_true(used);
    assert_same_summary(&after, &before, "backfilled vs version 3");
    assert_int_equal(after.runs, 8);
    assert_int_equal(after.replace, 3);
    assert_int_equal(after.failed, 2);
    sr_history_summary_release(&after);
    sr_history_summary_release(&before);
    assert_int_equal(cells_equal_runs(fx.cat, "backfilled"), 8);
    /* and the triggers run from then on */
    add_run(&fx, fx.inst[1], "2024-02-10T00:00:00Z", 1, s2, 1, p2, 1);
    assert_int_equal(cells_equal_runs(fx.cat, "a run after the upgrade"), 9);
    sr_catalog_close(fx.cat);
    tmpdir_remove(&fx.dir);
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

/* An inspection of run `run` (catalog_inspect.h) with only a verdict. */
static void inspect_run(fixture *fx, int64_t run, sr_inspect_verdict v)
{
    sr_inspect_result r;
    memset(&r, 0, sizeof r);
    sr_xform_identity(r.transform);
    r.tolerance_mm = 0.1;
    r.allowance_mm = 0.5;
    r.verdict = v;
    snprintf(r.reasons, sizeof r.reasons, "as the test says");
    sr_err err = {{0}};
    int64_t id = 0;
    if (sr_catalog_inspection_add(fx->cat, run, NULL, NULL, &r, &id, &err) != SR_OK)
        fail_msg("inspection add: %s", err.msg);
    assert_true(id > 0);
}

static void the_latest_inspection_is_the_outcome_filtered_and_summed(void **state)
{
    fixture *fx = *state;
    inspect_run(fx, fx->run[0], SR_INSPECT_REWORK);
    inspect_run(fx, fx->run[0], SR_INSPECT_PASS); /* the same second: the later id wins */
    inspect_run(fx, fx->run[1], SR_INSPECT_MACHINE);
    inspect_run(fx, fx->run[3], SR_INSPECT_REWORK);
    sr_history_filter f = {0};
    rows rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "5 4 3 2 1");
    assert_string_equal(rs.v[0].verdict, "");
    assert_string_equal(rs.v[1].verdict, "rework");
    assert_string_equal(rs.v[2].verdict, "");
    assert_string_equal(rs.v[3].verdict, "machine");
    assert_string_equal(rs.v[4].verdict, "pass");
    f.verdict = "pass";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "1");
    f.verdict = "rework";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "4");
    f.part = "A";
    rs = query(fx, &f);
    assert_string_equal(ids(fx, &rs), "");
    sr_history_summary s;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_history_summary(fx->cat, NULL, &s, &err), SR_OK);
    assert_int_equal(s.pass, 1);
    assert_int_equal(s.machine, 1);
    assert_int_equal(s.rework, 1);
    sr_history_summary_release(&s);
    f = (sr_history_filter){.verdict = "machine"};
    assert_int_equal(sr_catalog_history_summary(fx->cat, &f, &s, &err), SR_OK);
    assert_int_equal(s.runs, 1);
    assert_int_equal(s.machine, 1);
    sr_history_summary_release(&s);
    cells_equal_runs(fx->cat, "inspected");
    /* the latest inspection taken away: run 1 is rework again */
    char sql[160];
    snprintf(sql, sizeof sql,
             "DELETE FROM inspections WHERE id = (SELECT max(id) FROM inspections"
             " WHERE run_id = %lld)",
             (long long)fx->run[0]);
    raw(fx->cat, sql);
    assert_int_equal(sr_catalog_history_summary(fx->cat, NULL, &s, &err), SR_OK);
    assert_int_equal(s.pass, 0);
    assert_int_equal(s.rework, 2);
    sr_history_summary_release(&s);
    cells_equal_runs(fx->cat, "an inspection deleted");
    /* a run, an instance moved and an instance removed with its runs */
    snprintf(sql, sizeof sql, "DELETE FROM runs WHERE id = %lld", (long long)fx->run[1]);
    raw(fx->cat, sql);
    cells_equal_runs(fx->cat, "a run deleted");
    raw(fx->cat, "UPDATE instances SET part_id = (SELECT id FROM parts WHERE number = 'A')"
                 " WHERE serial = 'B1'");
    cells_equal_runs(fx->cat, "an instance moved");
    assert_int_equal(
        sr_catalog_instance_remove(fx->cat, fx->inst[0], SR_CATALOG_WITH_RUNS, NULL, &err), SR_OK);
    cells_equal_runs(fx->cat, "an instance removed");
    assert_int_equal(raw_count(fx->cat, "SELECT sum(runs) FROM history_verdict_cells"), 1);
    /* an inspection is a measurement: it is not changed */
    char *msg = NULL;
    assert_int_not_equal(
        sqlite3_exec(fx->cat->db, "UPDATE inspections SET verdict = 'pass'", NULL, NULL, &msg),
        SQLITE_OK);
    assert_non_null(strstr(msg, "an inspection is not changed"));
    sqlite3_free(msg);
    /* a verdict the catalogue does not know */
    f = (sr_history_filter){.verdict = "fail"};
    assert_int_equal(sr_catalog_history_check(fx->cat, &f, &err), SR_E_RANGE);
    assert_string_equal(err.msg, "bad verdict 'fail': expected pass, machine or rework");
    inspect_run(fx, fx->run[3], SR_INSPECT_PASS);
    cells_equal_runs(fx->cat, "inspected again");
    /* catalog check: the verdict cells agree with the inspections, until tampered with */
    int problems = 0;
    sr_check_info info;
    assert_int_equal(sr_catalog_check(fx->cat, count_problem, &problems, &info, &err), SR_OK);
    assert_int_equal(problems, 0);
    raw(fx->cat, "UPDATE history_verdict_cells SET runs = runs + 1 WHERE verdict = 'pass'");
    assert_int_equal(sr_catalog_check(fx->cat, count_problem, &problems, &info, &err), SR_OK);
    assert_int_equal(problems, 1);
    assert_int_equal(
        sr_catalog_inspection_add(fx->cat, 999, NULL, NULL, &(sr_inspect_result){0}, NULL, &err),
        SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no run 999 in the catalogue");
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
        T(summary_cells_equal_the_runs_after_inserts),
        T(the_latest_inspection_is_the_outcome_filtered_and_summed),
        T(summary_cells_follow_deletes),
        T(summary_cells_follow_updates),
        T(removals_with_runs_keep_the_cells_equal_to_the_runs),
        T(check_finds_cells_that_disagree_with_the_runs),
        T(summary_takes_the_runs_when_cells_cannot_answer),
        T(an_irregular_start_time_sends_its_months_to_the_runs),
        cmocka_unit_test(migration_004_backfills_the_cells),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
