/*
 * catalog_history.c: history queries over the run record (API in catalog_history.h;
 * indexes in sql/003_history.sql).
 *
 * Every statement is a compile-time SQL literal with bound parameters:
 *   ?1 instance id (0 = any), ?2 part id (0 = any), ?3 material id (0 = any),
 *   ?4 lower bound of started_at (the since day, or "" = open),
 *   ?5 exclusive upper bound (the day after until, or "~" = open: it sorts after
 *      every date), ?6 the verdict of the run's latest inspection (NULL = any; schema
 *      9's run_latest_inspection).
 * SQLite plans a statement once, before the values are bound, so a single statement
 * with "?1 = 0 OR ..." terms could not use any index for the condition that matters.
 * Each query therefore comes in five variants, one per driving condition (instance,
 * part, material, date range, none), made by the macros below: the driving condition
 * is a plain term the planner takes to an index, and the others are checked on each
 * row with unary '+' so they are not mistaken for better index candidates.
 *
 * Per-run figures: the sections by a LEFT JOIN grouped per run, the processes by one
 * correlated subquery, each a range read of a covering index of 003. The outcome is derived
 * here from the full process list before it is cut to its field.
 *
 * Summaries come one of two ways, aggregated here the same way:
 *   - from the cells of sql/004_history_summary.sql (running totals per part and month,
 *     kept by triggers), when the filter selects whole cells: any part, material, and
 *     dates that are whole months (since the 1st, until the last day of a month), no
 *     instance, and no 'irregular' start time in the months at the range's ends. A
 *     few thousand cells instead of every run: the whole history of 100,000 runs in
 *     a few milliseconds instead of half a second;
 *   - otherwise from the runs: one light row per run (part, month, status, volume,
 *     outcome) plus the class counts per part in one grouped query.
 * Both give the same counts; the average volumes agree to the rounding of the sums
 * (tests/test_history.c compares them field by field).
 */
#include "catalog/catalog_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/grow.h"
#include "catalog/catalog_history.h"
#include "inspect/inspect.h"

/* ---- the statements ---- */

enum { BY_ALL, BY_INSTANCE, BY_PART, BY_MATERIAL, BY_DATE, BY_COUNT };

#define W_ALL " WHERE 1"
#define W_INSTANCE " WHERE r.instance_id = ?1"
#define W_PART " WHERE i.part_id = ?2"
#define W_MATERIAL " WHERE p.material_id = ?3"
#define W_DATE " WHERE r.started_at >= ?4 AND r.started_at < ?5"

#define H_FROM                                                                            \
    " FROM runs r JOIN instances i ON i.id = r.instance_id"                              \
    " JOIN parts p ON p.id = i.part_id"                                                    \
    " LEFT JOIN materials m ON m.id = p.material_id"

#define H_REST                                                                                     \
    " AND (?1 = 0 OR +r.instance_id = ?1) AND (?2 = 0 OR +i.part_id = ?2)"                         \
    " AND (?3 = 0 OR +p.material_id = ?3)"                                                         \
    " AND +r.started_at >= ?4 AND +r.started_at < ?5"                                              \
    " AND (?6 IS NULL OR EXISTS (SELECT 1 FROM run_latest_inspection v"                            \
    " WHERE v.run_id = r.id AND v.verdict = ?6))"

/* The verdict of the run's latest inspection (NULL = never inspected). */
#define H_VERDICT " (SELECT v.verdict FROM run_latest_inspection v WHERE v.run_id = r.id)"

/* The sections come by a LEFT JOIN grouped per run (one pass over the covering index,
 * cheaper than three correlated subqueries); the classes and processes come as they
 * are stored and are made distinct and sorted here. */
#define H_ROWS_SELECT                                                                              \
    "SELECT r.id, r.instance_id, r.started_at, p.number, coalesce(i.serial, ''),"                  \
    " coalesce(m.name, ''), r.symmetry_kind, r.symmetry_order, r.symmetry_shift_mm,"               \
    " r.method, r.status, count(s.id), total(s.volume_mm3), group_concat(s.class, ','),"           \
    " (SELECT group_concat(a.process, ',') FROM advice a WHERE a.run_id = r.id)," H_VERDICT

#define H_ROWS(W)                                                                         \
    H_ROWS_SELECT H_FROM " LEFT JOIN sections s ON s.run_id = r.id" W H_REST             \
    " GROUP BY r.id ORDER BY r.started_at DESC, r.id DESC"

static const char *const rows_sql[BY_COUNT] = {
    H_ROWS(W_ALL), H_ROWS(W_INSTANCE), H_ROWS(W_PART), H_ROWS(W_MATERIAL), H_ROWS(W_DATE),
};

/* One light row per run for the summaries; the outcome as 0 none, 1 repair, 2 replace. */
#define H_RUNS(W)                                                                                  \
    "SELECT p.number, substr(r.started_at, 1, 7), r.status,"                                       \
    " (SELECT coalesce(sum(s.volume_mm3), 0) FROM sections s WHERE s.run_id = r.id),"              \
    " coalesce((SELECT max(CASE WHEN a.process LIKE 'replace%' THEN 2 ELSE 1 END)"                 \
    "           FROM advice a WHERE a.run_id = r.id), 0)," H_VERDICT H_FROM W H_REST

static const char *const runs_sql[BY_COUNT] = {
    H_RUNS(W_ALL), H_RUNS(W_INSTANCE), H_RUNS(W_PART), H_RUNS(W_MATERIAL), H_RUNS(W_DATE),
};

/* Sections per part and class. */
#define H_CLASSES(W)                                                                      \
    "SELECT p.number, s.class, count(*)" H_FROM " JOIN sections s ON s.run_id = r.id" W    \
    H_REST " GROUP BY p.number, s.class"

static const char *const classes_sql[BY_COUNT] = {
    H_CLASSES(W_ALL), H_CLASSES(W_INSTANCE), H_CLASSES(W_PART), H_CLASSES(W_MATERIAL),
    H_CLASSES(W_DATE),
};

/* The same from the cells of 004: ?2 part id, ?3 material id (0 = any), ?4 first month
 * ('YYYY-MM', "" = open), ?5 the month after the last ("~" = open). No instance
 * variant: an instance is not a cell. */
#define C_FROM " FROM history_cells c JOIN parts p ON p.id = c.part_id"
#define K_FROM " FROM history_class_cells k JOIN parts p ON p.id = k.part_id"
#define C_REST(t)                                                                         \
    " AND (?2 = 0 OR +" t ".part_id = ?2) AND (?3 = 0 OR +p.material_id = ?3)"             \
    " AND +" t ".month >= ?4 AND +" t ".month < ?5"

#define C_RUNS(W)                                                                         \
    "SELECT p.number, c.month, c.runs, c.failed, c.advised, c.replaced, c.volume_mm3"      \
    C_FROM W C_REST("c") " AND c.runs > 0"

static const char *const cell_runs_sql[BY_COUNT] = {
    C_RUNS(" WHERE 1"), NULL, C_RUNS(" WHERE c.part_id = ?2"),
    C_RUNS(" WHERE p.material_id = ?3"), C_RUNS(" WHERE c.month >= ?4 AND c.month < ?5"),
};

#define C_CLASSES(W)                                                                      \
    "SELECT p.number, k.class, sum(k.sections)" K_FROM W C_REST("k")                       \
    " AND k.sections > 0 GROUP BY k.part_id, k.class"

static const char *const cell_classes_sql[BY_COUNT] = {
    C_CLASSES(" WHERE 1"), NULL, C_CLASSES(" WHERE k.part_id = ?2"),
    C_CLASSES(" WHERE p.material_id = ?3"), C_CLASSES(" WHERE k.month >= ?4 AND k.month < ?5"),
};

/* Runs per verdict from the cells of 009 (history_verdict_cells). */
#define V_FROM " FROM history_verdict_cells x JOIN parts p ON p.id = x.part_id"
#define C_VERDICTS(W)                                                                              \
    "SELECT x.verdict, sum(x.runs)" V_FROM W C_REST("x") " AND x.runs > 0 GROUP BY x.verdict"

static const char *const cell_verdicts_sql[BY_COUNT] = {
    C_VERDICTS(" WHERE 1"),
    NULL,
    C_VERDICTS(" WHERE x.part_id = ?2"),
    C_VERDICTS(" WHERE p.material_id = ?3"),
    C_VERDICTS(" WHERE x.month >= ?4 AND x.month < ?5"),
};

/* ---- the filter ---- */

static bool digits(const char *s, int n)
{
    for (int i = 0; i < n; i++)
        if (s[i] < '0' || s[i] > '9')
            return false;
    return true;
}

static int month_days(int y, int m)
{
    static const int mdays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    return mdays[m - 1] + (m == 2 && leap);
}

/* A real calendar day written 'YYYY-MM-DD'; its parts in *y, *m, *d. */
static bool parse_day(const char *s, int *y, int *m, int *d)
{
    if (strlen(s) != 10 || s[4] != '-' || s[7] != '-' || !digits(s, 4) || !digits(s + 5, 2) ||
        !digits(s + 8, 2))
        return false;
    *y = atoi(s);
    *m = atoi(s + 5);
    *d = atoi(s + 8);
    return *y >= 1 && *m >= 1 && *m <= 12 && *d >= 1 && *d <= month_days(*y, *m);
}

typedef struct bound_filter {
    int by;
    int64_t instance_id, part_id, material_id;
    char since[11];
    char until_next[40];       /* the day after until, or "~" */
    bool whole_months;         /* since a 1st (or open), until a month's last day (or open) */
    char since_month[8];       /* 'YYYY-MM' of since, or "" */
    char until_month[16];      /* 'YYYY-MM' of until_next, or "~" */
    const char *verdict;       /* NULL = any */
} bound_filter;

static sr_status resolve_material(sr_catalog *cat, const char *name, int64_t *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "SELECT id FROM materials WHERE name = ?1", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, name, -1, SQLITE_STATIC);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "look up a material");
    int64_t id = st == SR_OK && row ? sqlite3_column_int64(stmt, 0) : 0;
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "look up a material");
    if (st != SR_OK)
        return st;
    if (!row)
        return sr_err_set(err, SR_E_NOTFOUND, "no material '%s' in the catalogue", name);
    *out = id;
    return SR_OK;
}

/* A catalogue from before schema 9 (one made by older migrations, as the tests make)
 * has no inspections: an empty stand-in for the view the statements read, in the
 * connection's temp schema, so the same statements run on it. */
static sr_status verdict_view(sr_catalog *cat, sr_err *err)
{
    if (cat->schema_version >= 9)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "CREATE TEMP VIEW IF NOT EXISTS run_latest_inspection AS"
                                  " SELECT NULL AS run_id, NULL AS verdict WHERE 0",
                                  &stmt, err);
    return st == SR_OK ? sr_cat_exec(cat, stmt, err, "read the history") : st;
}

static sr_status check_instance(sr_catalog *cat, int64_t id, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "SELECT 1 FROM instances WHERE id = ?1", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "look up an instance");
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "look up an instance");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no instance %lld in the catalogue", (long long)id);
    return st;
}

static sr_status bind_filter(sr_catalog *cat, const sr_history_filter *f, bound_filter *b,
                             sr_err *err)
{
    memset(b, 0, sizeof *b);
    strcpy(b->until_next, "~");
    strcpy(b->until_month, "~");
    b->whole_months = true;
    sr_status vst = verdict_view(cat, err);
    if (vst != SR_OK || !f)
        return vst;
    int y, m, d;
    if (f->since) {
        if (!parse_day(f->since, &y, &m, &d))
            return sr_err_set(err, SR_E_RANGE, "bad since date '%s': expected YYYY-MM-DD",
                              f->since);
        memcpy(b->since, f->since, 11);
        memcpy(b->since_month, f->since, 7);
        b->since_month[7] = '\0';
        b->whole_months = d == 1;
    }
    if (f->until) {
        if (!parse_day(f->until, &y, &m, &d))
            return sr_err_set(err, SR_E_RANGE, "bad until date '%s': expected YYYY-MM-DD",
                              f->until);
        if (f->since && strcmp(f->since, f->until) > 0)
            return sr_err_set(err, SR_E_RANGE, "bad date range: since %s is after until %s",
                              f->since, f->until);
        if (++d > month_days(y, m)) {
            d = 1;
            if (++m > 12) {
                m = 1;
                y++;
            }
        }
        if (y > 9999) {
            strcpy(b->until_next, "~");
        } else {
            snprintf(b->until_next, sizeof b->until_next, "%04d-%02d-%02d", y,
                     m, d);
            snprintf(b->until_month, sizeof b->until_month, "%04d-%02d", y, m);
        }
        b->whole_months = b->whole_months && d == 1;
    }
    if (f->instance_id < 0)
        return sr_err_set(err, SR_E_RANGE, "bad instance id %lld", (long long)f->instance_id);
    if (f->verdict && sr_inspect_verdict_parse(f->verdict) < 0)
        return sr_err_set(err, SR_E_RANGE, "bad verdict '%s': expected pass, machine or rework",
                          f->verdict);
    b->verdict = f->verdict;
    sr_status st;
    if (f->instance_id > 0) {
        st = check_instance(cat, f->instance_id, err);
        if (st != SR_OK)
            return st;
        b->instance_id = f->instance_id;
    }
    if (f->part) {
        st = sr_cat_part_resolve(cat, f->part, &b->part_id, err);
        if (st != SR_OK)
            return st;
    }
    if (f->material) {
        st = resolve_material(cat, f->material, &b->material_id, err);
        if (st != SR_OK)
            return st;
    }
    b->by = b->instance_id ? BY_INSTANCE
            : b->part_id   ? BY_PART
            : b->material_id ? BY_MATERIAL
            : (f->since || f->until) ? BY_DATE
                                     : BY_ALL;
    return SR_OK;
}

/* Prepares sql[b->by] with the filter bound: days for the statements over the runs,
 * months for those over the cells (`cells`). */
static sr_status prepare_filtered(sr_catalog *cat, const char *const *sql, const bound_filter *b,
                                  bool cells, sqlite3_stmt **out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql[b->by], &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, b->instance_id);
    sqlite3_bind_int64(stmt, 2, b->part_id);
    sqlite3_bind_int64(stmt, 3, b->material_id);
    sqlite3_bind_text(stmt, 4, cells ? b->since_month : b->since, -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(stmt, 5, cells ? b->until_month : b->until_next, -1, SQLITE_TRANSIENT);
    if (!cells)
        sr_cat_bind_opt_text(stmt, 6, b->verdict);
    *out = stmt;
    return SR_OK;
}

sr_status sr_catalog_history_check(sr_catalog *cat, const sr_history_filter *filter,
                                   sr_err *err)
{
    bound_filter b;
    return bind_filter(cat, filter, &b, err);
}

/* ---- rows ---- */

const char *sr_history_outcome_str(sr_history_outcome o)
{
    switch (o) {
    case SR_OUTCOME_REPAIR:
        return "repair";
    case SR_OUTCOME_REPLACE:
        return "replace";
    default:
        return "none";
    }
}

static int str_cmp(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* Writes the distinct items of the comma list `list` in byte order into a field of
 * `size` bytes, cut after the last whole item that fits. Items never hold commas
 * (a class or process with one would read as two; the rules name them without). */
static sr_status copy_list(const char *list, char *dst, size_t size)
{
    dst[0] = '\0';
    if (!list || !*list)
        return SR_OK;
    size_t n = 1;
    for (const char *p = list; *p; p++)
        n += *p == ',';
    char *copy = strdup(list);
    char **items = malloc(n * sizeof *items);
    if (!copy || !items) {
        free(copy);
        free(items);
        return SR_E_NOMEM;
    }
    size_t k = 0;
    for (char *p = copy, *next; p; p = next) {
        next = strchr(p, ',');
        if (next)
            *next++ = '\0';
        items[k++] = p;
    }
    qsort(items, k, sizeof *items, str_cmp);
    size_t len = 0;
    for (size_t i = 0; i < k; i++) {
        if (i && strcmp(items[i], items[i - 1]) == 0)
            continue;
        size_t il = strlen(items[i]);
        if (len + (len ? 1 : 0) + il + 1 > size)
            break;
        if (len)
            dst[len++] = ',';
        memcpy(dst + len, items[i], il);
        len += il;
        dst[len] = '\0';
    }
    free(items);
    free(copy);
    return SR_OK;
}

/* The outcome from the full process list: any item beginning 'replace' (ASCII case
 * ignored, as LIKE does in the summary query) is a replace. */
static sr_history_outcome outcome_of(const char *list)
{
    if (!list || !*list)
        return SR_OUTCOME_NONE;
    for (const char *p = list; p; p = strchr(p, ',')) {
        if (*p == ',')
            p++;
        if (strncasecmp(p, "replace", 7) == 0)
            return SR_OUTCOME_REPLACE;
    }
    return SR_OUTCOME_REPAIR;
}

sr_status sr_catalog_history(sr_catalog *cat, const sr_history_filter *filter,
                             sr_history_fn fn, void *user, sr_err *err)
{
    bound_filter b;
    sr_status st = bind_filter(cat, filter, &b, err);
    if (st != SR_OK)
        return st;
    sqlite3_stmt *stmt;
    st = prepare_filtered(cat, rows_sql, &b, false, &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "query the history");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            break;
        sr_history_row r;
        memset(&r, 0, sizeof r);
        r.run_id = sqlite3_column_int64(stmt, 0);
        r.instance_id = sqlite3_column_int64(stmt, 1);
        sr_cat_column_text(stmt, 2, r.started_at, sizeof r.started_at);
        memcpy(r.date, r.started_at, 10);
        r.date[10] = '\0';
        sr_cat_column_text(stmt, 3, r.part_number, sizeof r.part_number);
        sr_cat_column_text(stmt, 4, r.serial, sizeof r.serial);
        sr_cat_column_text(stmt, 5, r.material, sizeof r.material);
        sr_cat_column_symmetry(stmt, 6, &r.symmetry);
        sr_cat_column_text(stmt, 9, r.method, sizeof r.method);
        const char *status = (const char *)sqlite3_column_text(stmt, 10);
        r.ok = status && strcmp(status, "ok") == 0;
        r.section_count = (size_t)sqlite3_column_int64(stmt, 11);
        r.missing_volume_mm3 = sqlite3_column_double(stmt, 12);
        const char *processes = (const char *)sqlite3_column_text(stmt, 14);
        r.outcome = outcome_of(processes);
        sr_cat_column_text(stmt, 15, r.verdict, sizeof r.verdict);
        if (copy_list((const char *)sqlite3_column_text(stmt, 13), r.classes,
                      sizeof r.classes) != SR_OK ||
            copy_list(processes, r.processes, sizeof r.processes) != SR_OK) {
            sqlite3_finalize(stmt);
            return sr_err_set(err, SR_E_NOMEM, "out of memory reading the history");
        }
        if (fn(&r, user))
            break;
    }
    return sr_cat_finish(cat, stmt, err, "query the history");
}

/* ---- summaries ---- */

typedef struct part_acc {
    sr_history_part out;
    double volume_sum;
} part_acc;

typedef struct summary_acc {
    part_acc *parts;
    size_t part_count, part_cap;
    sr_history_month *months;
    size_t month_count, month_cap;
    double volume_sum;
} summary_acc;

/* The part's accumulator (parts kept sorted by number, found by bisection). */
static part_acc *part_slot(summary_acc *a, const char *number)
{
    size_t lo = 0, hi = a->part_count;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = strcmp(a->parts[mid].out.part_number, number);
        if (c == 0)
            return &a->parts[mid];
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    part_acc *p = sr_grow(a->parts, a->part_count, &a->part_cap, sizeof *p);
    if (!p)
        return NULL;
    a->parts = p;
    memmove(a->parts + lo + 1, a->parts + lo, (a->part_count - lo) * sizeof *a->parts);
    a->part_count++;
    part_acc *slot = &a->parts[lo];
    memset(slot, 0, sizeof *slot);
    snprintf(slot->out.part_number, sizeof slot->out.part_number, "%s", number);
    return slot;
}

static sr_history_month *month_slot(summary_acc *a, const char *month)
{
    size_t lo = 0, hi = a->month_count;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = strcmp(a->months[mid].month, month);
        if (c == 0)
            return &a->months[mid];
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    sr_history_month *p = sr_grow(a->months, a->month_count, &a->month_cap, sizeof *p);
    if (!p)
        return NULL;
    a->months = p;
    memmove(a->months + lo + 1, a->months + lo, (a->month_count - lo) * sizeof *a->months);
    a->month_count++;
    sr_history_month *slot = &a->months[lo];
    memset(slot, 0, sizeof *slot);
    snprintf(slot->month, sizeof slot->month, "%s", month);
    return slot;
}

/* Adds `runs` runs of part `number` started in `month`, with their figures. */
static sr_status acc_runs(summary_acc *a, sr_history_summary *s, const char *number,
                          const char *month, size_t runs, size_t failed, size_t repair,
                          size_t replace, double volume, sr_err *err)
{
    part_acc *p = part_slot(a, number ? number : "");
    sr_history_month *mo = p ? month_slot(a, month ? month : "") : NULL;
    if (!mo)
        return sr_err_set(err, SR_E_NOMEM, "out of memory summarising the history");
    s->runs += runs;
    p->out.runs += runs;
    mo->runs += runs;
    s->failed += failed;
    a->volume_sum += volume;
    p->volume_sum += volume;
    s->replace += replace;
    p->out.replace += replace;
    s->repair += repair;
    p->out.repair += repair;
    s->none += runs - repair - replace;
    return SR_OK;
}

/* Adds n runs whose latest inspection said `verdict` (NULL = none). */
static void count_verdict(sr_history_summary *s, const char *verdict, size_t n)
{
    switch (verdict ? sr_inspect_verdict_parse(verdict) : -1) {
    case SR_INSPECT_PASS: s->pass += n; break;
    case SR_INSPECT_MACHINE: s->machine += n; break;
    case SR_INSPECT_REWORK: s->rework += n; break;
    default: break;
    }
}

/* The runs per verdict from the cells. */
static sr_status read_cell_verdicts(sr_catalog *cat, const bound_filter *b, sr_history_summary *s,
                                    sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = prepare_filtered(cat, cell_verdicts_sql, b, true, &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "summarise the verdicts");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            return sr_cat_finish(cat, stmt, err, "summarise the verdicts");
        int64_t n = sqlite3_column_int64(stmt, 1);
        count_verdict(s, (const char *)sqlite3_column_text(stmt, 0), n > 0 ? (size_t)n : 0);
    }
}

/* One row per run (`cells` false) or per cell (`cells` true). */
static sr_status read_runs(sr_catalog *cat, const bound_filter *b, bool cells, summary_acc *a,
                           sr_history_summary *s, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = prepare_filtered(cat, cells ? cell_runs_sql : runs_sql, b, cells, &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "summarise the history");
        if (st != SR_OK)
            break;
        if (!row)
            return sr_cat_finish(cat, stmt, err, "summarise the history");
        const char *number = (const char *)sqlite3_column_text(stmt, 0);
        const char *month = (const char *)sqlite3_column_text(stmt, 1);
        if (cells) {
            /* runs, failed, advised, replaced, volume; clamped so that a damaged cell
             * cannot make a count wrap */
            int64_t n = sqlite3_column_int64(stmt, 2), f = sqlite3_column_int64(stmt, 3),
                    adv = sqlite3_column_int64(stmt, 4), rep = sqlite3_column_int64(stmt, 5);
            rep = rep < 0 ? 0 : rep > n ? n : rep;
            adv = adv < rep ? rep : adv > n ? n : adv;
            f = f < 0 ? 0 : f > n ? n : f;
            st = acc_runs(a, s, number, month, (size_t)n, (size_t)f, (size_t)(adv - rep),
                          (size_t)rep, sqlite3_column_double(stmt, 6), err);
        } else {
            /* status, volume, outcome (0 none, 1 repair, 2 replace) */
            const char *status = (const char *)sqlite3_column_text(stmt, 2);
            int outcome = sqlite3_column_int(stmt, 4);
            st = acc_runs(a, s, number, month, 1, !status || strcmp(status, "ok") != 0,
                          outcome == 1, outcome == 2, sqlite3_column_double(stmt, 3), err);
            count_verdict(s, (const char *)sqlite3_column_text(stmt, 5), 1);
        }
        if (st != SR_OK)
            break;
    }
    sqlite3_finalize(stmt);
    return st;
}

static sr_status read_classes(sr_catalog *cat, const bound_filter *b, bool cells,
                              summary_acc *a, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st =
        prepare_filtered(cat, cells ? cell_classes_sql : classes_sql, b, cells, &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "summarise the damage classes");
        if (st != SR_OK)
            break;
        if (!row)
            return sr_cat_finish(cat, stmt, err, "summarise the damage classes");
        const char *number = (const char *)sqlite3_column_text(stmt, 0);
        const char *cls = (const char *)sqlite3_column_text(stmt, 1);
        size_t n = (size_t)sqlite3_column_int64(stmt, 2);
        part_acc *p = part_slot(a, number ? number : "");
        if (!p) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory summarising the history");
            break;
        }
        p->out.sections += n;
        /* rows come by class within a part (GROUP BY order), so a strict > keeps the
         * alphabetically first of a tie; the order is not relied on: ties compare */
        if (cls && (n > p->out.top_class_sections ||
                    (n == p->out.top_class_sections &&
                     (!p->out.top_class[0] || strcmp(cls, p->out.top_class) < 0)))) {
            p->out.top_class_sections = n;
            snprintf(p->out.top_class, sizeof p->out.top_class, "%s", cls);
        }
    }
    sqlite3_finalize(stmt);
    return st;
}

/* Whether the cells answer this filter exactly (see the top of the file): schema 4,
 * no instance, whole months, and no irregular start time in the first month or the
 * month after the last (the only months where a day bound and a month bound can
 * disagree). */
static sr_status cells_answer(sr_catalog *cat, const bound_filter *b, bool *out, sr_err *err)
{
    *out = false;
    if (cat->schema_version < 9 || b->by == BY_INSTANCE || !b->whole_months || b->verdict)
        return SR_OK;
    if (!b->since_month[0] && strcmp(b->until_month, "~") == 0) {
        *out = true;
        return SR_OK;
    }
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT EXISTS (SELECT 1 FROM history_cells"
                                  " WHERE month IN (?1, ?2) AND irregular <> 0)",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_text(stmt, 1, b->since_month, -1, SQLITE_STATIC);
    sqlite3_bind_text(stmt, 2, b->until_month, -1, SQLITE_STATIC);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "summarise the history");
    bool irregular = st == SR_OK && row && sqlite3_column_int(stmt, 0) != 0;
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "summarise the history");
    if (st == SR_OK)
        *out = !irregular;
    return st;
}

sr_status sr_cat_history_summary_way(sr_catalog *cat, const sr_history_filter *filter,
                                     sr_cat_summary_way way, sr_history_summary *out,
                                     bool *used_cells, sr_err *err)
{
    bound_filter b;
    sr_status st = bind_filter(cat, filter, &b, err);
    if (st != SR_OK)
        return st;
    bool cells = false;
    if (way != SR_CAT_SUMMARY_RUNS) {
        st = cells_answer(cat, &b, &cells, err);
        if (st != SR_OK)
            return st;
        if (way == SR_CAT_SUMMARY_CELLS && !cells)
            return sr_err_set(err, SR_E_INVALID,
                              "the history summary cells cannot answer this filter");
    }
    summary_acc a;
    memset(&a, 0, sizeof a);
    sr_history_summary s;
    memset(&s, 0, sizeof s);
    st = read_runs(cat, &b, cells, &a, &s, err);
    if (st == SR_OK)
        st = read_classes(cat, &b, cells, &a, err);
    if (st == SR_OK && cells)
        st = read_cell_verdicts(cat, &b, &s, err);
    if (st == SR_OK && a.part_count) {
        s.parts = malloc(a.part_count * sizeof *s.parts);
        if (!s.parts)
            st = sr_err_set(err, SR_E_NOMEM, "out of memory summarising the history");
    }
    if (st != SR_OK) {
        free(a.parts);
        free(a.months);
        return st;
    }
    for (size_t i = 0; i < a.part_count; i++) {
        part_acc *p = &a.parts[i];
        p->out.avg_missing_volume_mm3 = p->out.runs ? p->volume_sum / (double)p->out.runs : 0;
        s.parts[i] = p->out;
    }
    s.part_count = a.part_count;
    free(a.parts);
    s.months = a.months;
    s.month_count = a.month_count;
    s.avg_missing_volume_mm3 = s.runs ? a.volume_sum / (double)s.runs : 0;
    s.repair_fraction =
        s.repair + s.replace ? (double)s.repair / (double)(s.repair + s.replace) : NAN;
    if (used_cells)
        *used_cells = cells;
    *out = s;
    return SR_OK;
}

sr_status sr_catalog_history_summary(sr_catalog *cat, const sr_history_filter *filter,
                                     sr_history_summary *out, sr_err *err)
{
    return sr_cat_history_summary_way(cat, filter, SR_CAT_SUMMARY_AUTO, out, NULL, err);
}

void sr_history_summary_release(sr_history_summary *s)
{
    if (!s)
        return;
    free(s->parts);
    free(s->months);
    memset(s, 0, sizeof *s);
}
