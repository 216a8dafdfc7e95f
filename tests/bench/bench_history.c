/*
 * bench_history.c: history query figures for `make bench` (called from bench_main.c,
 * section 5): a catalogue with 100,000 runs (200 parts of 12 materials, 2,000
 * instances, runs spread over 2023-2024 with 1-3 sections each and their advice, 5 %
 * failed, about 10 % advised 'replace'), filled by direct prepared inserts in one
 * transaction, then sr_catalog_history / sr_catalog_history_summary timed on it:
 * by part, by material, by a one-month date range, and the summaries (whole history
 * and one material). Target: under 50 ms each (issue 5). Works in a fresh
 * /tmp/symrec-bench-XXXXXX directory it removes.
 */
#include <sqlite3.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "catalog.h"
#include "catalog_history.h"

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

/* Fills the catalogue (schema made by sr_catalog_open) in one transaction. */
static int fill(const char *path)
{
    sqlite3 *db;
    if (sqlite3_open(path, &db) != SQLITE_OK)
        return -1;
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

static void time_summary(sr_catalog *cat, const char *what, const sr_history_filter *f)
{
    double first = 0, best = 1e9;
    sr_history_summary s = {0};
    for (int k = 0; k < 6; k++) {
        sr_err err = {{0}};
        sr_history_summary_release(&s);
        double t = now();
        sr_status st = sr_catalog_history_summary(cat, f, &s, &err);
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
    printf("  %-34s %6zu runs  %6.1f ms (first %5.1f ms) — target < 50 ms: %s\n", what, s.runs,
           1e3 * best, 1e3 * first, best < 0.050 ? "met" : "MISSED");
    printf("  %-34s %zu parts, %zu months, repair %zu / replace %zu / none %zu\n", "", s.part_count,
           s.month_count, s.repair, s.replace, s.none);
    sr_history_summary_release(&s);
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
    double t = now();
    int rc = fill(db);
    t = now() - t;
    if (rc == 0) {
        printf("  catalogue with %d runs (%d parts, %d materials, %d instances, ~2 sections "
               "and advice per run) filled in %.1f s (one transaction)\n",
               N_RUNS, N_PARTS, N_MATERIALS, N_INSTANCES, t);
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
            time_summary(cat, "summary --part P-0042", &by_part);
            time_summary(cat, "summary --material material-07", &by_mat);
            time_summary(cat, "summary one month", &by_month);
            time_summary(cat, "summary, whole history", NULL);
            sr_catalog_close(cat);
        }
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
    }
    rmdir(dir);
}
