/*
 * catalog_fix.c: correcting a catalogue as a whole: removing a part or an instance with
 * what refers to it, a consistent backup copy of the file, and a check of the file
 * (SQLite's own checks and symrec's invariants). Changing single fields of a part or
 * an instance lives beside their readers (catalog_parts.c, catalog_instances.c).
 *
 * A removal follows the schema's ON DELETE rules (sql/001_init.sql) on purpose rather
 * than leaning on them: instances -> runs is CASCADE, so deleting an instance would
 * drop its runs silently; it is refused here unless the caller asks for the runs to go
 * (SR_CATALOG_WITH_RUNS). The runs are deleted first, one statement, so the BEFORE
 * DELETE trigger on runs (sql/004_history_summary.sql) subtracts each from its history
 * cell while its sections and advice still exist; the instances then find no runs left
 * to subtract. Meshes are RESTRICT/SET NULL targets, never deleted by a cascade: the
 * ones the removed rows referred to are collected first and deleted afterwards when
 * nothing refers to them any more.
 */
#include "catalog/catalog_int.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/grow.h"

/* ---- removal ---- */

/* Runs a one-row, one-integer query, with ?1 bound to id when it has a parameter. */
static sr_status count_of(sr_catalog *cat, const char *sql, int64_t id, int64_t *out, sr_err *err,
                          const char *what)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    if (sqlite3_bind_parameter_count(stmt) > 0)
        sqlite3_bind_int64(stmt, 1, id);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, what);
    if (st == SR_OK && row)
        *out = sqlite3_column_int64(stmt, 0);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, what);
}

/* Runs one statement with ?1 bound to id. */
static sr_status exec_id(sr_catalog *cat, const char *sql, int64_t id, sr_err *err,
                         const char *what)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    return sr_cat_exec(cat, stmt, err, what);
}

typedef struct id_vec {
    int64_t *v;
    size_t count, cap;
} id_vec;

/* Appends the ids of a query (?1 = id) to *ids. */
static sr_status collect_ids(sr_catalog *cat, const char *sql, int64_t id, id_vec *ids, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "find the meshes to remove");
        if (st != SR_OK || !row)
            break;
        int64_t *v = sr_grow(ids->v, ids->count, &ids->cap, sizeof *v);
        if (!v) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory collecting meshes");
            break;
        }
        ids->v = v;
        ids->v[ids->count++] = sqlite3_column_int64(stmt, 0);
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, "find the meshes to remove");
}

/* Deletes each mesh of ids that nothing refers to any more; *gone counts them. */
static sr_status drop_orphan_meshes(sr_catalog *cat, const id_vec *ids, int64_t *gone, sr_err *err)
{
    *gone = 0;
    for (size_t i = 0; i < ids->count; i++) {
        sr_status st = exec_id(cat,
                               "DELETE FROM meshes WHERE id = ?1"
                               " AND NOT EXISTS (SELECT 1 FROM parts WHERE mesh_id = ?1)"
                               " AND NOT EXISTS (SELECT 1 FROM instances WHERE mesh_id = ?1)"
                               " AND NOT EXISTS (SELECT 1 FROM runs WHERE restored_mesh_id = ?1)"
                               " AND NOT EXISTS (SELECT 1 FROM sections WHERE patch_mesh_id = ?1)",
                               ids->v[i], err, "remove a mesh");
        if (st != SR_OK)
            return st;
        *gone += sqlite3_changes(cat->db);
    }
    return SR_OK;
}

static const char *plural(int64_t n, const char *one, const char *many)
{
    return n == 1 ? one : many;
}

/* The statements of one kind of removal; ?1 = the row's id. */
typedef struct removal_sql {
    const char *count_instances; /* NULL: an instance */
    const char *count_runs;
    const char *meshes; /* every mesh id the removed rows refer to */
    const char *delete_runs;
    const char *delete_rows; /* the instances, then (part) the part */
    const char *delete_part; /* NULL: an instance */
} removal_sql;

static const removal_sql part_sql = {
    "SELECT count(*) FROM instances WHERE part_id = ?1",
    "SELECT count(*) FROM runs r JOIN instances i ON i.id = r.instance_id WHERE i.part_id = ?1",
    "SELECT mesh_id FROM parts WHERE id = ?1 AND mesh_id IS NOT NULL"
    " UNION SELECT mesh_id FROM instances WHERE part_id = ?1"
    " UNION SELECT r.restored_mesh_id FROM runs r JOIN instances i ON i.id = r.instance_id"
    "  WHERE i.part_id = ?1 AND r.restored_mesh_id IS NOT NULL"
    " UNION SELECT s.patch_mesh_id FROM sections s JOIN runs r ON r.id = s.run_id"
    "  JOIN instances i ON i.id = r.instance_id"
    "  WHERE i.part_id = ?1 AND s.patch_mesh_id IS NOT NULL",
    "DELETE FROM runs WHERE instance_id IN (SELECT id FROM instances WHERE part_id = ?1)",
    "DELETE FROM instances WHERE part_id = ?1",
    "DELETE FROM parts WHERE id = ?1",
};

static const removal_sql instance_sql = {
    NULL,
    "SELECT count(*) FROM runs WHERE instance_id = ?1",
    "SELECT mesh_id FROM instances WHERE id = ?1"
    " UNION SELECT restored_mesh_id FROM runs WHERE instance_id = ?1"
    "  AND restored_mesh_id IS NOT NULL"
    " UNION SELECT s.patch_mesh_id FROM sections s JOIN runs r ON r.id = s.run_id"
    "  WHERE r.instance_id = ?1 AND s.patch_mesh_id IS NOT NULL",
    "DELETE FROM runs WHERE instance_id = ?1",
    "DELETE FROM instances WHERE id = ?1",
    NULL,
};

/* Removes the row `id` as `q` says, inside the caller's transaction; `name` names it
 * in messages ("part 'P-1'", "instance 4"). */
static sr_status remove_rows(sr_catalog *cat, const removal_sql *q, int64_t id, const char *name,
                             unsigned flags, sr_removal *out, sr_err *err)
{
    sr_removal r = {0, 0, 0};
    sr_status st = SR_OK;
    if (q->count_instances)
        st = count_of(cat, q->count_instances, id, &r.instances, err, "count instances");
    if (st == SR_OK)
        st = count_of(cat, q->count_runs, id, &r.runs, err, "count runs");
    if (st != SR_OK)
        return st;
    if ((r.instances || r.runs) && !(flags & SR_CATALOG_WITH_RUNS)) {
        char what[96];
        if (q->count_instances)
            snprintf(what, sizeof what, "%lld %s and %lld %s", (long long)r.instances,
                     plural(r.instances, "instance", "instances"), (long long)r.runs,
                     plural(r.runs, "run", "runs"));
        else
            snprintf(what, sizeof what, "%lld %s", (long long)r.runs,
                     plural(r.runs, "run", "runs"));
        return sr_err_set(err, SR_E_INVALID,
                          "%s has %s; nothing removed (--with-runs removes them too)", name, what);
    }
    id_vec meshes = {NULL, 0, 0};
    st = collect_ids(cat, q->meshes, id, &meshes, err);
    if (st == SR_OK)
        st = exec_id(cat, q->delete_runs, id, err, "remove runs");
    if (st == SR_OK)
        st = exec_id(cat, q->delete_rows, id, err, "remove instances");
    if (st == SR_OK && q->delete_part)
        st = exec_id(cat, q->delete_part, id, err, "remove a part");
    if (st == SR_OK)
        st = drop_orphan_meshes(cat, &meshes, &r.meshes, err);
    free(meshes.v);
    if (st == SR_OK)
        *out = r;
    return st;
}

sr_status sr_catalog_part_remove(sr_catalog *cat, const char *key, unsigned flags, sr_removal *out,
                                 sr_err *err)
{
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    int64_t part_id;
    sr_removal r;
    st = sr_cat_part_resolve(cat, key, &part_id, err);
    if (st == SR_OK) {
        char name[96];
        snprintf(name, sizeof name, "part '%s'", key);
        st = remove_rows(cat, &part_sql, part_id, name, flags, &r, err);
    }
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK) {
        sr_cat_rollback(cat);
        return st;
    }
    if (out)
        *out = r;
    return SR_OK;
}

sr_status sr_catalog_instance_remove(sr_catalog *cat, int64_t id, unsigned flags, sr_removal *out,
                                     sr_err *err)
{
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    int64_t found = 0;
    sr_removal r;
    st = count_of(cat, "SELECT count(*) FROM instances WHERE id = ?1", id, &found, err,
                  "find an instance");
    if (st == SR_OK && !found)
        st = sr_err_set(err, SR_E_NOTFOUND, "no instance %lld in the catalogue", (long long)id);
    if (st == SR_OK) {
        char name[48];
        snprintf(name, sizeof name, "instance %lld", (long long)id);
        st = remove_rows(cat, &instance_sql, id, name, flags, &r, err);
    }
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK) {
        sr_cat_rollback(cat);
        return st;
    }
    if (out)
        *out = r;
    return SR_OK;
}

/* ---- backup ---- */

/* Removes path + suffix; a missing file is fine. */
static bool unlink_beside(const char *path, const char *suffix)
{
    char name[4096];
    if (snprintf(name, sizeof name, "%s%s", path, suffix) >= (int)sizeof name)
        return false;
    return unlink(name) == 0 || errno == ENOENT;
}

sr_status sr_catalog_backup(sr_catalog *cat, const char *path, bool force, sr_err *err)
{
    if (!path || !*path)
        return sr_err_set(err, SR_E_RANGE, "no backup file given");
    struct stat target, source;
    bool exists = stat(path, &target) == 0;
    if (exists && !force)
        return sr_err_set(err, SR_E_EXISTS, "'%s' already exists (replace it with --force)", path);
    if (exists && stat(cat->path, &source) == 0 && source.st_dev == target.st_dev &&
        source.st_ino == target.st_ino)
        return sr_err_set(err, SR_E_INVALID, "'%s' is the catalogue itself", path);
    if (exists && !S_ISREG(target.st_mode))
        return sr_err_set(err, SR_E_IO, "cannot replace '%s': not a regular file", path);

    /* a temporary file beside the target, so the target appears whole or not at all */
    size_t len = strlen(path);
    char *tmp = malloc(len + 16);
    if (!tmp)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    memcpy(tmp, path, len);
    memcpy(tmp + len, ".tmp-XXXXXX", 12);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        sr_status st = sr_err_set(err, SR_E_IO, "cannot write '%s': %s", path, strerror(errno));
        free(tmp);
        return st;
    }
    if (stat(cat->path, &source) == 0)
        (void)fchmod(fd, (source.st_mode & 0666) | 0600); /* the copy is written next */
    close(fd);

    sqlite3 *dest = NULL;
    sr_status st = SR_OK;
    int rc = sqlite3_open_v2(tmp, &dest, SQLITE_OPEN_READWRITE, NULL);
    if (rc == SQLITE_OK) {
        /* one step of every page: the source stays in one read transaction, so the copy
         * is one consistent state even while another process writes (WAL) */
        sqlite3_backup *b = sqlite3_backup_init(dest, "main", cat->db, "main");
        if (b) {
            rc = sqlite3_backup_step(b, -1);
            int rc_finish = sqlite3_backup_finish(b);
            rc = rc == SQLITE_DONE ? rc_finish : rc;
        } else {
            rc = sqlite3_errcode(dest);
        }
    }
    if (rc != SQLITE_OK)
        st = sr_err_set(err, rc == SQLITE_FULL || rc == SQLITE_IOERR ? SR_E_IO : SR_E_DB,
                        "cannot back up '%s' to '%s': %s", cat->path, path,
                        dest ? sqlite3_errmsg(dest) : sqlite3_errstr(rc));
    if (sqlite3_close(dest) != SQLITE_OK && st == SR_OK)
        st = sr_err_set(err, SR_E_IO, "cannot back up '%s' to '%s': closing the copy failed",
                        cat->path, path);
    if (st == SR_OK && exists && (!unlink_beside(path, "-wal") || !unlink_beside(path, "-shm")))
        st = sr_err_set(err, SR_E_IO, "cannot replace '%s': its -wal or -shm file stays: %s", path,
                        strerror(errno));
    if (st == SR_OK) {
        /* link refuses a target that appeared meanwhile; --force replaces it. On a
         * file system without hard links, a rename after one more look. */
        bool renamed = exists;
        int moved = exists ? rename(tmp, path) : link(tmp, path);
        if (moved != 0 && !exists && errno != EEXIST && stat(path, &target) != 0) {
            renamed = true;
            moved = rename(tmp, path);
        }
        if (moved != 0 && errno == EEXIST)
            st =
                sr_err_set(err, SR_E_EXISTS, "'%s' already exists (replace it with --force)", path);
        else if (moved != 0)
            st = sr_err_set(err, SR_E_IO, "cannot write '%s': %s", path, strerror(errno));
        else if (renamed)
            tmp[0] = '\0'; /* moved: nothing to remove */
    }
    if (tmp[0])
        unlink(tmp);
    free(tmp);
    return st;
}

/* ---- check ---- */

typedef struct check_ctx {
    sr_check_fn fn;
    void *user;
    int64_t problems;
    bool stop;
} check_ctx;

static void problem(check_ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void problem(check_ctx *c, const char *fmt, ...)
{
    if (c->stop)
        return;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    c->problems++;
    if (c->fn(line, c->user))
        c->stop = true;
}

/* Runs a query whose rows are problems: each row's columns 0..n-1 passed to `line`. */
static sr_status each_row(sr_catalog *cat, const char *sql, check_ctx *c,
                          void (*line)(check_ctx *c, sqlite3_stmt *stmt), sr_err *err,
                          const char *what)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, what);
        if (st != SR_OK || !row || c->stop)
            break;
        line(c, stmt);
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, what);
}

static const char *col_text(sqlite3_stmt *stmt, int col)
{
    const char *s = (const char *)sqlite3_column_text(stmt, col);
    return s ? s : "?";
}

static void integrity_line(check_ctx *c, sqlite3_stmt *stmt)
{
    if (strcmp(col_text(stmt, 0), "ok") != 0)
        problem(c, "integrity: %s", col_text(stmt, 0));
}

static void foreign_key_line(check_ctx *c, sqlite3_stmt *stmt)
{
    problem(c, "foreign key: %s row %lld: %s refers to a missing %s row", col_text(stmt, 0),
            (long long)sqlite3_column_int64(stmt, 1), col_text(stmt, 3), col_text(stmt, 2));
}

static void cell_line(check_ctx *c, sqlite3_stmt *stmt)
{
    int64_t cells = sqlite3_column_int64(stmt, 2), runs = sqlite3_column_int64(stmt, 3);
    if (cells != runs)
        problem(c,
                "history summary: part id %lld, month %s: the cells count %lld runs, the "
                "runs table %lld",
                (long long)sqlite3_column_int64(stmt, 0), col_text(stmt, 1), (long long)cells,
                (long long)runs);
    else
        problem(c,
                "history summary: part id %lld, month %s: the cells' failures, advice or "
                "missing volume differ from its runs'",
                (long long)sqlite3_column_int64(stmt, 0), col_text(stmt, 1));
}

static void class_cell_line(check_ctx *c, sqlite3_stmt *stmt)
{
    problem(c,
            "history summary: part id %lld, month %s, class '%s': the cells count %lld "
            "sections, the runs %lld",
            (long long)sqlite3_column_int64(stmt, 0), col_text(stmt, 1), col_text(stmt, 2),
            (long long)sqlite3_column_int64(stmt, 3), (long long)sqlite3_column_int64(stmt, 4));
}

/* The history cells (sql/004) against the runs they sum, both ways; volumes agree to
 * rounding. */
#define CELLS_WANT                                                                                 \
    "WITH want AS (SELECT part_id, month, count(*) AS runs, sum(failed) AS failed,"                \
    " sum(advised) AS advised, sum(replaced) AS replaced, total(volume_mm3) AS volume,"            \
    " sum(irregular) AS irregular FROM history_run_figures GROUP BY part_id, month) "
static const char cells_sql[] = CELLS_WANT
    "SELECT w.part_id, w.month, coalesce(c.runs, 0), w.runs FROM want w"
    " LEFT JOIN history_cells c ON c.part_id = w.part_id AND c.month = w.month"
    " WHERE c.runs IS NOT w.runs OR c.failed IS NOT w.failed OR c.advised IS NOT w.advised"
    " OR c.replaced IS NOT w.replaced OR c.irregular IS NOT w.irregular"
    " OR abs(c.volume_mm3 - w.volume) > 1e-9 * max(1, abs(w.volume))"
    " UNION ALL SELECT c.part_id, c.month, c.runs, 0 FROM history_cells c"
    " WHERE NOT EXISTS (SELECT 1 FROM want w WHERE w.part_id = c.part_id AND w.month = c.month)"
    " ORDER BY 1, 2";
#define CLASS_WANT                                                                                 \
    "WITH want AS (SELECT k.part_id, k.month, s.class, count(*) AS sections"                       \
    " FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id"                              \
    " GROUP BY k.part_id, k.month, s.class) "
static const char class_cells_sql[] = CLASS_WANT
    "SELECT w.part_id, w.month, w.class, coalesce(c.sections, 0), w.sections FROM want w"
    " LEFT JOIN history_class_cells c"
    " ON c.part_id = w.part_id AND c.month = w.month AND c.class = w.class"
    " WHERE c.sections IS NOT w.sections"
    " UNION ALL SELECT c.part_id, c.month, c.class, c.sections, 0 FROM history_class_cells c"
    " WHERE NOT EXISTS (SELECT 1 FROM want w WHERE w.part_id = c.part_id"
    " AND w.month = c.month AND w.class = c.class)"
    " ORDER BY 1, 2, 3";

/* The verdict cells (sql/009) against the runs' latest inspections, both ways. */
#define VERDICT_WANT                                                                               \
    "WITH want AS (SELECT part_id, month, verdict, count(*) AS runs"                               \
    " FROM history_run_verdicts GROUP BY part_id, month, verdict) "
static const char verdict_cells_sql[] = VERDICT_WANT
    "SELECT w.part_id, w.month, w.verdict, coalesce(c.runs, 0), w.runs FROM want w"
    " LEFT JOIN history_verdict_cells c"
    " ON c.part_id = w.part_id AND c.month = w.month AND c.verdict = w.verdict"
    " WHERE c.runs IS NOT w.runs"
    " UNION ALL SELECT c.part_id, c.month, c.verdict, c.runs, 0 FROM history_verdict_cells c"
    " WHERE NOT EXISTS (SELECT 1 FROM want w WHERE w.part_id = c.part_id"
    " AND w.month = c.month AND w.verdict = c.verdict)"
    " ORDER BY 1, 2, 3";

static void verdict_cell_line(check_ctx *c, sqlite3_stmt *stmt)
{
    problem(c,
            "history summary: part id %lld, month %s, verdict '%s': the cells count %lld "
            "runs, the inspections %lld",
            (long long)sqlite3_column_int64(stmt, 0), col_text(stmt, 1), col_text(stmt, 2),
            (long long)sqlite3_column_int64(stmt, 3), (long long)sqlite3_column_int64(stmt, 4));
}

sr_status sr_catalog_check(sr_catalog *cat, sr_check_fn fn, void *user, sr_check_info *out,
                           sr_err *err)
{
    check_ctx c = {fn, user, 0, false};
    sr_check_info info = {0, 0, 0, 0};
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "PRAGMA application_id", &stmt, err);
    bool row = false;
    if (st == SR_OK)
        st = sr_cat_step(cat, stmt, &row, err, "read the application id");
    if (st == SR_OK && row)
        info.application_id = sqlite3_column_int64(stmt, 0);
    sqlite3_finalize(stmt);
    if (st != SR_OK)
        return st;
    info.schema_version = cat->schema_version;
    if ((uint32_t)info.application_id != SR_CATALOG_APP_ID)
        problem(&c, "application id is 0x%08llx, not symrec's 0x%08x",
                (unsigned long long)(uint32_t)info.application_id, SR_CATALOG_APP_ID);
    if (info.schema_version != sr_catalog_schema_latest())
        problem(&c, "schema version %d, this symrec's is %d", info.schema_version,
                sr_catalog_schema_latest());
    st = each_row(cat, "PRAGMA integrity_check(100)", &c, integrity_line, err,
                  "check the file's integrity");
    if (st == SR_OK)
        st = each_row(cat,
                      "SELECT f.\"table\", f.rowid, f.parent, coalesce(l.\"from\", '?')"
                      " FROM pragma_foreign_key_check AS f"
                      " LEFT JOIN pragma_foreign_key_list(f.\"table\") AS l"
                      " ON l.id = f.fkid AND l.seq = 0",
                      &c, foreign_key_line, err, "check the foreign keys");
    if (st == SR_OK && cat->schema_version >= 4)
        st = each_row(cat, cells_sql, &c, cell_line, err, "check the history summary");
    if (st == SR_OK && cat->schema_version >= 4)
        st = each_row(cat, class_cells_sql, &c, class_cell_line, err, "check the history summary");
    if (st == SR_OK && cat->schema_version >= 9)
        st = each_row(cat, verdict_cells_sql, &c, verdict_cell_line, err,
                      "check the history summary");
    if (st == SR_OK)
        st = count_of(cat, "SELECT count(*) FROM materials WHERE density_g_cm3 IS NULL", 0,
                      &info.no_density, err, "count materials without a density");
    if (st != SR_OK)
        return st;
    info.problems = c.problems;
    if (out)
        *out = info;
    return SR_OK;
}
