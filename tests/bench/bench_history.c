/*
 * bench_history.c: history query figures for `make bench` (called from bench_main.c,
 * section 5): a catalogue with 100,000 runs (200 parts of 12 materials, 2,000
 * instances, runs spread over 2023-2024 with 1-3 sections each and their advice, 5 %
 * failed, about 10 % advised 'replace'), filled by direct prepared inserts in one
 * transaction, then sr_catalog_history / sr_catalog_history_summary timed on it:
 * by part, by material, by a one-month date range, and the summaries (whole history
 * and one material). Target: under 50 ms each (issue 5). Works in a fresh
 * /tmp/symrec-bench-XXXXXX directory it removes.
 *
 * The inserts go through the triggers of sql/004_history_summary.sql like any other
 * write, so the summary cells are filled the way a shop's catalogue fills them. What
 * the triggers cost is measured by filling a second catalogue with them dropped. The
 * whole-history summary is also timed from the runs (the way it went before 004) and
 * compared with the one from the cells.
 */
#include <math.h>
#include <sqlite3.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "catalog/catalog.h"
#include "catalog/catalog_history.h"
#include "catalog/catalog_int.h"
#include "catalog/catalog_runs.h"

void bench_history(void);

#define N_RUNS 100000
#define N_PARTS 200
#define N_MATERIALS 12
#define N_INSTANCES 2000

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint32_t rnd(uint32_t n)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state % n);
}

static int exec(sqlite3 *db, const char *sql)
{
    char *msg = NULL;
    if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK) {
        printf("  bench_history: %s: %s\n", sql, msg ? msg : "?");
        sqlite3_free(msg);
        return -1;
    }
    return 0;
}

static int prep(sqlite3 *db, const char *sql, sqlite3_stmt **out)
{
    if (sqlite3_prepare_v2(db, sql, -1, out, NULL) != SQLITE_OK) {
        printf("  bench_history: cannot prepare '%s': %s\n", sql, sqlite3_errmsg(db));
        return -1;
    }
    return 0;
}

static int done(sqlite3 *db, sqlite3_stmt *s)
{
    int rc = sqlite3_step(s);
    sqlite3_reset(s);
    if (rc != SQLITE_DONE) {
        printf("  bench_history: insert failed: %s\n", sqlite3_errmsg(db));
        return -1;
    }
    return 0;
}

/* Fills the catalogue (schema made by sr_catalog_open) in one transaction; with
 * `triggers` 0 the summary triggers of 004 are dropped first (to measure their cost). */
static int fill(const char *path, int triggers)
{
    sqlite3 *db;
    if (sqlite3_open(path, &db) != SQLITE_OK)
        return -1;
    rng_state = 0x9E3779B97F4A7C15ull; /* the same catalogue every time */
    if (!triggers) {
        static const char *const names[] = {
            "history_runs_insert", "history_runs_delete", "history_runs_update_old",
            "history_runs_update_new", "history_instances_delete",
            "history_instances_update_old", "history_instances_update_new",
            "history_sections_insert", "history_sections_delete", "history_sections_update",
            "history_advice_insert", "history_advice_delete", "history_advice_update"};
        char sql[96];
        for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
            snprintf(sql, sizeof sql, "DROP TRIGGER %s", names[i]);
            if (exec(db, sql)) {
                sqlite3_close(db);
                return -1;
            }
        }
    }
    static const char *const classes[] = {"chip", "gouge", "wear_band", "broken_feature",
                                          "crack"};
    static const char *const processes[] = {"spray_forming", "ded", "weld_buildup"};
    sqlite3_stmt *mat = NULL, *part = NULL, *inst = NULL, *run = NULL, *sec = NULL,
                 *adv = NULL;
    int rc = -1;
    if (exec(db, "PRAGMA foreign_keys = ON; BEGIN") ||
        exec(db, "INSERT INTO meshes (id, vertex_count, tri_count, volume_mm3, area_mm2,"
                 " bbox_min_x, bbox_min_y, bbox_min_z, bbox_max_x, bbox_max_y, bbox_max_z,"
                 " closed, format_version, data) VALUES (1, 3, 1, 0, 0, 0, 0, 0, 1, 1, 0, 0,"
                 " 1, zeroblob(108))") ||
        prep(db, "INSERT INTO materials (id, name) VALUES (?1, ?2)", &mat) ||
        prep(db, "INSERT INTO parts (id, number, name, material_id) VALUES (?1, ?2, 'part', ?3)",
             &part) ||
        prep(db, "INSERT INTO instances (id, part_id, serial, mesh_id) VALUES (?1, ?2, ?3, 1)",
             &inst) ||
        prep(db, "INSERT INTO runs (id, instance_id, symmetry_kind, params_name, layers,"
                 " sectors, gamma_axis, gamma_plane, delta_d, min_depth_mm, min_volume_mm3,"
                 " method, status, error, software_version, started_at, finished_at)"
                 " VALUES (?1, ?2, 'axial', 'default', 320, 240, 0.9, 0.9, 0.1, 0.1, 1,"
                 " 'robust', ?3, ?4, 'bench', ?5, ?5)",
             &run) ||
        prep(db, "INSERT INTO sections (run_id, section_index, layer_first, layer_last,"
                 " z_min_mm, z_max_mm, volume_mm3, area_mm2, depth_max_mm, depth_mean_mm,"
                 " class) VALUES (?1, ?2, 0, 10, 0, 5, ?3, 10, 1, 0.5, ?4)",
             &sec) ||
        prep(db, "INSERT INTO advice (run_id, section_id, process, reason)"
                 " VALUES (?1, ?2, ?3, 'bench')",
             &adv))
        goto out;
    char text[64];
    for (int i = 1; i <= N_MATERIALS; i++) {
        snprintf(text, sizeof text, "material-%02d", i);
        sqlite3_bind_int(mat, 1, 1000 + i);    /* above the seeded materials (002_rules.sql) */
        sqlite3_bind_text(mat, 2, text, -1, SQLITE_TRANSIENT);
        if (done(db, mat))
            goto out;
    }
    for (int i = 1; i <= N_PARTS; i++) {
        snprintf(text, sizeof text, "P-%04d", i);
        sqlite3_bind_int(part, 1, i);
        sqlite3_bind_text(part, 2, text, -1, SQLITE_TRANSIENT);
        sqlite3_bind_int(part, 3, 1000 + 1 + (i - 1) % N_MATERIALS);
        if (done(db, part))
            goto out;
    }
    for (int i = 1; i <= N_INSTANCES; i++) {
        snprintf(text, sizeof text, "SN-%05d", i);
        sqlite3_bind_int(inst, 1, i);
        sqlite3_bind_int(inst, 2, 1 + (i - 1) % N_PARTS);
        sqlite3_bind_text(inst, 3, text, -1, SQLITE_TRANSIENT);
        if (done(db, inst))
            goto out;
    }
    time_t t0 = 1672531200; /* 2023-01-01T00:00:00Z */
    for (int i = 1; i <= N_RUNS; i++) {
        time_t t = t0 + (time_t)rnd(730u * 86400u);
        struct tm tm;
        gmtime_r(&t, &tm);
        strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
        bool failed = rnd(20) == 0;
        sqlite3_bind_int(run, 1, i);
        sqlite3_bind_int(run, 2, 1 + (int)rnd(N_INSTANCES));
        sqlite3_bind_text(run, 3, failed ? "failed" : "ok", -1, SQLITE_STATIC);
        if (failed)
            sqlite3_bind_text(run, 4, "bench failure", -1, SQLITE_STATIC);
        else
            sqlite3_bind_null(run, 4);
        sqlite3_bind_text(run, 5, text, -1, SQLITE_TRANSIENT);
        if (done(db, run))
            goto out;
        if (failed)
            continue;
        int nsec = 1 + (int)rnd(3);
        bool replace = rnd(10) == 0;
        for (int k = 0; k < nsec; k++) {
            sqlite3_bind_int(sec, 1, i);
            sqlite3_bind_int(sec, 2, k);
            sqlite3_bind_double(sec, 3, 5.0 + rnd(2000) / 10.0);
            sqlite3_bind_text(sec, 4, classes[rnd(5)], -1, SQLITE_STATIC);
            if (done(db, sec))
                goto out;
            sqlite3_bind_int(adv, 1, i);
            sqlite3_bind_int64(adv, 2, sqlite3_last_insert_rowid(db));
            sqlite3_bind_text(adv, 3, replace ? "replace" : processes[rnd(3)], -1,
                              SQLITE_STATIC);
            if (done(db, adv))
                goto out;
        }
    }
    if (exec(db, "COMMIT"))
        goto out;
    rc = 0;
out:
    sqlite3_finalize(mat);
    sqlite3_finalize(part);
    sqlite3_finalize(inst);
    sqlite3_finalize(run);
    sqlite3_finalize(sec);
    sqlite3_finalize(adv);
    sqlite3_close(db);
    return rc;
}

static int count_row(const sr_history_row *row, void *user)
{
    (void)row;
    (*(size_t *)user)++;
    return 0;
}

/* Times one history query: the first run and the best of 5, with the rows returned. */
static void time_rows(sr_catalog *cat, const char *what, const sr_history_filter *f)
{
    double first = 0, best = 1e9;
    size_t rows = 0;
    for (int k = 0; k < 6; k++) {
        sr_err err = {{0}};
        rows = 0;
        double t = now();
        sr_status st = sr_catalog_history(cat, f, count_row, &rows, &err);
        t = now() - t;
        if (st != SR_OK) {
            printf("  %-34s FAILED: %s\n", what, err.msg);
            return;
        }
        if (k == 0)
            first = t;
        else if (t < best)
            best = t;
    }
    printf("  %-34s %6zu runs  %6.1f ms (first %5.1f ms) — target < 50 ms: %s\n", what, rows,
           1e3 * best, 1e3 * first, best < 0.050 ? "met" : "MISSED");
}

static void time_summary(sr_catalog *cat, const char *what, const sr_history_filter *f,
                         sr_cat_summary_way way)
{
    double first = 0, best = 1e9;
    sr_history_summary s = {0};
    bool cells = false;
    for (int k = 0; k < 6; k++) {
        sr_err err = {{0}};
        sr_history_summary_release(&s);
        double t = now();
        sr_status st = sr_cat_history_summary_way(cat, f, way, &s, &cells, &err);
        t = now() - t;
        if (st != SR_OK) {
            printf("  %-34s FAILED: %s\n", what, err.msg);
            return;
        }
        if (k == 0)
            first = t;
        else if (t < best)
            best = t;
    }
    printf("  %-34s %6zu runs  %6.1f ms (first %5.1f ms)%s%s\n", what, s.runs, 1e3 * best,
           1e3 * first, way == SR_CAT_SUMMARY_RUNS ? " — for comparison" : " — target < 50 ms: ",
           way == SR_CAT_SUMMARY_RUNS ? "" : best < 0.050 ? "met" : "MISSED");
    printf("  %-34s %zu parts, %zu months, repair %zu / replace %zu / none %zu (from the %s)\n",
           "", s.part_count, s.month_count, s.repair, s.replace, s.none,
           cells ? "summary cells" : "runs");
    sr_history_summary_release(&s);
}

/* Adds `n` runs through sr_catalog_run_add (one transaction each, as `symrec
 * reconstruct` records a run: 2 sections, 2 advice, no meshes or layers); seconds. */
static double add_runs_api(const char *path, int n)
{
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_catalog_open(path, 0, &cat, &err) != SR_OK)
        return -1;
    sr_run_section sec[2];
    memset(sec, 0, sizeof sec);
    for (int k = 0; k < 2; k++) {
        sec[k].index = (size_t)k;
        sec[k].z_max_mm = 5;
        sec[k].volume_mm3 = 12.5 + k;
        snprintf(sec[k].damage_class, sizeof sec[k].damage_class, k ? "chip" : "gouge");
    }
    sr_run_advice adv[2];
    memset(adv, 0, sizeof adv);
    for (int k = 0; k < 2; k++) {
        adv[k].section_index = k;
        snprintf(adv[k].process, sizeof adv[k].process, "spray_forming");
        snprintf(adv[k].reason, sizeof adv[k].reason, "bench");
    }
    sr_run r;
    memset(&r, 0, sizeof r);
    r.symmetry = (sr_symmetry){SR_SYM_AXIAL, 0, 0};
    r.params = (sr_params){"default", 320, 240, 0.9, 0.9, 0.1, 0.1, 1, ""};
    snprintf(r.method, sizeof r.method, "robust");
    r.fit_quality = -1;
    r.ok = 1;
    r.sections = sec;
    r.section_count = 2;
    r.advice = adv;
    r.advice_count = 2;
    double t = now();
    for (int i = 0; i < n; i++) {
        r.instance_id = 1 + i % N_INSTANCES;
        snprintf(r.started_at, sizeof r.started_at, "2024-%02d-15T12:00:00Z", 1 + i % 12);
        int64_t id;
        if (sr_catalog_run_add(cat, &r, &id, &err) != SR_OK) {
            printf("  run add FAILED: %s\n", err.msg);
            sr_catalog_close(cat);
            return -1;
        }
    }
    t = now() - t;
    sr_catalog_close(cat);
    return t;
}

/* The whole-history summary from the cells against the one from the runs: counts must
 * be equal, volumes equal to rounding. */
static void compare_ways(sr_catalog *cat)
{
    sr_history_summary a = {0}, b = {0};
    sr_err err = {{0}};
    if (sr_cat_history_summary_way(cat, NULL, SR_CAT_SUMMARY_CELLS, &a, NULL, &err) != SR_OK ||
        sr_cat_history_summary_way(cat, NULL, SR_CAT_SUMMARY_RUNS, &b, NULL, &err) != SR_OK) {
        printf("  compare FAILED: %s\n", err.msg);
        sr_history_summary_release(&a);
        return;
    }
    bool same = a.runs == b.runs && a.failed == b.failed && a.repair == b.repair &&
                a.replace == b.replace && a.none == b.none && a.part_count == b.part_count &&
                a.month_count == b.month_count;
    double rel = fabs(a.avg_missing_volume_mm3 - b.avg_missing_volume_mm3) /
                 b.avg_missing_volume_mm3;
    for (size_t i = 0; same && i < a.part_count; i++) {
        const sr_history_part *p = &a.parts[i], *q = &b.parts[i];
        same = strcmp(p->part_number, q->part_number) == 0 && p->runs == q->runs &&
               strcmp(p->top_class, q->top_class) == 0 &&
               p->top_class_sections == q->top_class_sections && p->sections == q->sections &&
               p->repair == q->repair && p->replace == q->replace;
        double r = fabs(p->avg_missing_volume_mm3 - q->avg_missing_volume_mm3) /
                   q->avg_missing_volume_mm3;
        if (r > rel)
            rel = r;
    }
    for (size_t i = 0; same && i < a.month_count; i++)
        same = strcmp(a.months[i].month, b.months[i].month) == 0 &&
               a.months[i].runs == b.months[i].runs;
    printf("  cells vs runs, whole history: counts %s, average volumes within %.1e relative\n",
           same ? "identical" : "DIFFER", rel);
    sr_history_summary_release(&a);
    sr_history_summary_release(&b);
}

void bench_history(void)
{
    char dir[] = "/tmp/symrec-bench-XXXXXX";
    if (!mkdtemp(dir)) {
        printf("  cannot make a temporary folder\n");
        return;
    }
    char db[128];
    snprintf(db, sizeof db, "%s/history.db", dir);
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_catalog_open(db, SR_CATALOG_CREATE, &cat, &err) != SR_OK) {
        printf("  cannot create the catalogue: %s\n", err.msg);
        rmdir(dir);
        return;
    }
    sr_catalog_close(cat);
    /* the same catalogue without the summary triggers, for their cost */
    char db0[128];
    snprintf(db0, sizeof db0, "%s/no-triggers.db", dir);
    double t0 = -1;
    if (sr_catalog_open(db0, SR_CATALOG_CREATE, &cat, &err) == SR_OK) {
        sr_catalog_close(cat);
        t0 = now();
        t0 = fill(db0, 0) == 0 ? now() - t0 : -1;
    }
    double t = now();
    int rc = fill(db, 1);
    t = now() - t;
    if (rc == 0) {
        printf("  catalogue with %d runs (%d parts, %d materials, %d instances, ~2 sections "
               "and advice per run) filled in %.1f s (one transaction, through the summary "
               "triggers)\n",
               N_RUNS, N_PARTS, N_MATERIALS, N_INSTANCES, t);
        if (t0 > 0)
            printf("  summary triggers' cost, bulk fill: %.1f s without them, %.1f s with: "
                   "+%.0f us per run with its sections and advice\n",
                   t0, t, 1e6 * (t - t0) / N_RUNS);
        cat = NULL;
        if (sr_catalog_open(db, 0, &cat, &err) != SR_OK) {
            printf("  cannot reopen the catalogue: %s\n", err.msg);
        } else {
            sr_history_filter by_part = {.part = "P-0042"};
            sr_history_filter by_mat = {.material = "material-07"};
            sr_history_filter by_month = {.since = "2024-03-01", .until = "2024-03-31"};
            sr_history_filter by_inst = {.instance_id = 1234};
            sr_history_filter mat_quarter = {.material = "material-07", .since = "2024-01-01",
                                             .until = "2024-03-31"};
            time_rows(cat, "history --part P-0042", &by_part);
            time_rows(cat, "history --instance 1234", &by_inst);
            time_rows(cat, "history --material material-07", &by_mat);
            time_rows(cat, "history --since/--until one month", &by_month);
            time_rows(cat, "history --material + one quarter", &mat_quarter);
            sr_history_filter by_day = {.since = "2024-03-02", .until = "2024-03-31"};
            sr_history_filter by_year = {.since = "2024-01-01", .until = "2024-12-31"};
            time_summary(cat, "summary --part P-0042", &by_part, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary --material material-07", &by_mat, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary one month", &by_month, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary one year", &by_year, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary 2024-03-02..31 (days)", &by_day, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary --instance 1234", &by_inst, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary, whole history", NULL, SR_CAT_SUMMARY_AUTO);
            time_summary(cat, "summary, whole history, from runs", NULL, SR_CAT_SUMMARY_RUNS);
            compare_ways(cat);
            sr_catalog_close(cat);
        }
        /* the triggers' cost the way runs are really recorded (after the queries, which
         * see 100,000 runs), alternating between the two catalogues so that both see
         * the same load of the machine */
        double api0 = 0, api1 = 0;
        int api_n = 0;
        for (int round = 0; round < 4 && t0 > 0; round++) {
            double a0 = add_runs_api(db0, 100), a1 = add_runs_api(db, 100);
            if (a0 < 0 || a1 < 0)
                break;
            api0 += a0;
            api1 += a1;
            api_n += 100;
        }
        if (api_n)
            printf("  summary triggers' cost, sr_catalog_run_add (one transaction per run, "
                   "%d runs): %.2f ms per run without them, %.2f ms with: %+.0f us per run\n",
                   api_n, 1e3 * api0 / api_n, 1e3 * api1 / api_n, 1e6 * (api1 - api0) / api_n);
    }
    if (getenv("SYMREC_BENCH_KEEP")) { /* developer aid: keep the catalogue to study */
        printf("  kept %s\n", db);
        return;
    }
    static const char *const suffix[] = {"", "-wal", "-shm", "-journal"};
    char p[160];
    for (int i = 0; i < 4; i++) {
        snprintf(p, sizeof p, "%s%s", db, suffix[i]);
        unlink(p);
        snprintf(p, sizeof p, "%s%s", db0, suffix[i]);
        unlink(p);
    }
    rmdir(dir);
}
