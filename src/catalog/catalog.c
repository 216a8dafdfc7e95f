/*
 * catalog.c: opening, checking and migrating a symrec catalogue, and the statement
 * and transaction helpers every catalog*.c file goes through (catalog_int.h).
 *
 * Opening trusts nothing on disk. The file's header fields are read first, without
 * writing anything: a file that is not SQLite, carries another application_id, holds
 * tables of some other program, or has a newer schema is refused before WAL mode or
 * a migration could touch it. Migrations are the sql/NNN_name.sql files compiled into
 * the binary (sr_sql_files); file N brings user_version N-1 to N inside one
 * BEGIN IMMEDIATE transaction, and sets user_version itself (no SQL is assembled
 * here). The version is re-read inside the transaction, so two processes opening a
 * new file at once migrate it once. Any error rolls the step back. Migrations run
 * with foreign keys off, as SQLite's procedure for rebuilding a table requires (with
 * them on, dropping a parent table would cascade into its children); instead
 * PRAGMA foreign_key_check must come back empty before each COMMIT. Foreign keys are
 * switched on for the connection once the schema is current.
 *
 * Parts, instances and symmetries live in catalog_parts.c and catalog_instances.c,
 * parameter sets in catalog_params.c, mesh rows in catalog_mesh.c.
 */
#include "catalog/catalog_int.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* How long a call waits for another process's write lock before giving up. */
#define BUSY_TIMEOUT_MS 5000

/* ---- statement and transaction helpers ---- */

static sr_status status_of(int rc)
{
    switch (rc & 0xff) {
    case SQLITE_NOMEM:
        return SR_E_NOMEM;
    case SQLITE_IOERR:
    case SQLITE_FULL:
    case SQLITE_CANTOPEN:
        return SR_E_IO;
    case SQLITE_TOOBIG:
        return SR_E_RANGE;
    case SQLITE_NOTADB:
        return SR_E_VERSION;
    case SQLITE_CONSTRAINT:
        if (rc == SQLITE_CONSTRAINT_UNIQUE || rc == SQLITE_CONSTRAINT_PRIMARYKEY)
            return SR_E_EXISTS;
        return SR_E_DB;
    default:
        return SR_E_DB;
    }
}

sr_status sr_cat_db_error(sr_catalog *cat, sr_err *err, const char *what, ...)
{
    int rc = sqlite3_extended_errcode(cat->db);
    sr_status st = status_of(rc);
    if (err) {
        char doing[256];
        va_list ap;
        va_start(ap, what);
        vsnprintf(doing, sizeof doing, what, ap);
        va_end(ap);
        int primary = rc & 0xff;
        if (primary == SQLITE_BUSY || primary == SQLITE_LOCKED)
            sr_err_set(err, st,
                       "cannot %s in '%s': the catalogue is busy (another process is writing)",
                       doing, cat->path);
        else
            sr_err_set(err, st, "cannot %s in '%s': %s", doing, cat->path,
                       sqlite3_errmsg(cat->db));
    }
    return st;
}

sr_status sr_cat_prepare(sr_catalog *cat, const char *sql, sqlite3_stmt **out, sr_err *err)
{
    *out = NULL;
    if (sqlite3_prepare_v2(cat->db, sql, -1, out, NULL) != SQLITE_OK) {
        sqlite3_finalize(*out);
        *out = NULL;
        return sr_cat_db_error(cat, err, "prepare a statement");
    }
    return SR_OK;
}

sr_status sr_cat_step(sr_catalog *cat, sqlite3_stmt *stmt, bool *row, sr_err *err,
                      const char *what)
{
    int rc = sqlite3_step(stmt);
    if (rc == SQLITE_DONE) {
        if (row)
            *row = false;
        return SR_OK;
    }
    if (rc == SQLITE_ROW && row) {
        *row = true;
        return SR_OK;
    }
    if (rc == SQLITE_ROW)
        return sr_err_set(err, SR_E_INTERNAL, "cannot %s in '%s': unexpected result row", what,
                          cat->path);
    return sr_cat_db_error(cat, err, "%s", what);
}

sr_status sr_cat_finish(sr_catalog *cat, sqlite3_stmt *stmt, sr_err *err, const char *what)
{
    if (sqlite3_finalize(stmt) != SQLITE_OK)
        return sr_cat_db_error(cat, err, "%s", what);
    return SR_OK;
}

sr_status sr_cat_exec(sr_catalog *cat, sqlite3_stmt *stmt, sr_err *err, const char *what)
{
    sr_status st = sr_cat_step(cat, stmt, NULL, err, what);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, what);
}

/* Runs one fixed statement (BEGIN, COMMIT, a PRAGMA without result). */
static sr_status exec_sql(sr_catalog *cat, const char *sql, sr_err *err, const char *what)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    return sr_cat_exec(cat, stmt, err, what);
}

sr_status sr_cat_begin(sr_catalog *cat, sr_err *err)
{
    if (cat->readonly)
        return sr_err_set(err, SR_E_DB, "cannot write to '%s': the catalogue is open read-only",
                          cat->path);
    return exec_sql(cat, "BEGIN IMMEDIATE", err, "start a write transaction");
}

sr_status sr_cat_commit(sr_catalog *cat, sr_err *err)
{
    return exec_sql(cat, "COMMIT", err, "commit");
}

void sr_cat_rollback(sr_catalog *cat)
{
    /* After some errors (disk full, I/O) SQLite has already rolled back. */
    if (sqlite3_get_autocommit(cat->db))
        return;
    sqlite3_stmt *stmt = NULL;
    if (sqlite3_prepare_v2(cat->db, "ROLLBACK", -1, &stmt, NULL) == SQLITE_OK)
        sqlite3_step(stmt);
    sqlite3_finalize(stmt);
}

int sr_cat_bind_opt_text(sqlite3_stmt *stmt, int index, const char *s)
{
    if (!s || !*s)
        return sqlite3_bind_null(stmt, index);
    return sqlite3_bind_text(stmt, index, s, -1, SQLITE_TRANSIENT);
}

void sr_cat_column_text(sqlite3_stmt *stmt, int col, char *dst, size_t size)
{
    const unsigned char *s = sqlite3_column_text(stmt, col);
    size_t n = s ? (size_t)sqlite3_column_bytes(stmt, col) : 0;
    if (n >= size) {
        n = size - 1;
        while (n > 0 && (s[n] & 0xc0) == 0x80)  /* do not split a UTF-8 character */
            n--;
    }
    if (n)
        memcpy(dst, s, n);
    dst[n] = '\0';
}

bool sr_cat_len_ok(const char *s, size_t min, size_t max)
{
    if (!s)
        return min == 0;
    size_t n = strlen(s);
    return n >= min && n <= max;
}

bool sr_cat_parse_id(const char *s, int64_t *out)
{
    if (!s || !*s || *s == '0')
        return false;
    int64_t v = 0;
    for (const char *p = s; *p; p++) {
        if (*p < '0' || *p > '9')
            return false;
        int d = *p - '0';
        if (v > (INT64_MAX - d) / 10)
            return false;
        v = v * 10 + d;
    }
    *out = v;
    return true;
}

/* ---- migrations ---- */

/* The number of a migration file "NNN_name.sql", or 0 when the name is not one. */
static int migration_number(const char *name)
{
    int n = 0, digits = 0;
    for (; name[digits] >= '0' && name[digits] <= '9'; digits++) {
        if (digits >= 6)
            return 0;
        n = n * 10 + (name[digits] - '0');
    }
    if (digits == 0 || name[digits] != '_')
        return 0;
    size_t len = strlen(name);
    if (len < 4 || strcmp(name + len - 4, ".sql") != 0)
        return 0;
    return n;
}

int sr_cat_schema_latest_of(const sr_sql_file *files)
{
    int latest = 0;
    for (const sr_sql_file *f = files; f->name; f++) {
        int n = migration_number(f->name);
        if (n > latest)
            latest = n;
    }
    return latest;
}

int sr_catalog_schema_latest(void)
{
    return sr_cat_schema_latest_of(sr_sql_files);
}

/* The migration file with number n; NULL when missing or not unique. */
static const sr_sql_file *migration_file(const sr_sql_file *files, int n)
{
    const sr_sql_file *found = NULL;
    for (const sr_sql_file *f = files; f->name; f++) {
        if (migration_number(f->name) == n) {
            if (found)
                return NULL;
            found = f;
        }
    }
    return found;
}

/* Reads one integer result (a PRAGMA or count). */
static sr_status query_int(sr_catalog *cat, const char *sql, int64_t *out, sr_err *err,
                           const char *what)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, what);
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_DB, "cannot %s in '%s': no result", what, cat->path);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    *out = sqlite3_column_int64(stmt, 0);
    return sr_cat_finish(cat, stmt, err, what);
}

/* Runs every statement of a migration file's text. */
static sr_status run_script(sr_catalog *cat, const sr_sql_file *file, sr_err *err)
{
    const char *sql = file->text;
    while (sql && *sql) {
        sqlite3_stmt *stmt = NULL;
        const char *tail = NULL;
        if (sqlite3_prepare_v2(cat->db, sql, -1, &stmt, &tail) != SQLITE_OK)
            return sr_cat_db_error(cat, err, "apply migration %s", file->name);
        if (!stmt)  /* only comments or white space left */
            break;
        int rc;
        while ((rc = sqlite3_step(stmt)) == SQLITE_ROW)
            ;
        if (rc != SQLITE_DONE) {
            sr_status st = sr_cat_db_error(cat, err, "apply migration %s", file->name);
            sqlite3_finalize(stmt);
            return st;
        }
        if (sqlite3_finalize(stmt) != SQLITE_OK)
            return sr_cat_db_error(cat, err, "apply migration %s", file->name);
        sql = tail;
    }
    return SR_OK;
}

/* Fails when the migration left a row whose foreign key points nowhere. */
static sr_status foreign_key_check(sr_catalog *cat, const sr_sql_file *file, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "PRAGMA foreign_key_check", &stmt, err);
    if (st != SR_OK)
        return st;
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "check foreign keys");
    if (st == SR_OK && row)
        st = sr_err_set(err, SR_E_INTERNAL,
                        "cannot apply migration %s to '%s': it leaves a row of table '%s' "
                        "with a broken foreign key",
                        file->name, cat->path, (const char *)sqlite3_column_text(stmt, 0));
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, "check foreign keys");
}

/* Applies migration n (user_version n-1 -> n) in one transaction, unless another
 * process did it first. */
static sr_status migrate_one(sr_catalog *cat, const sr_sql_file *file, int n, sr_err *err)
{
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    int64_t version, app_id;
    st = query_int(cat, "PRAGMA user_version", &version, err, "read the schema version");
    if (st != SR_OK)
        goto fail;
    if (version >= n) {  /* another process migrated while we waited for the lock */
        st = sr_cat_commit(cat, err);
        if (st != SR_OK)
            goto fail;
        return SR_OK;
    }
    if (version != n - 1) {
        st = sr_err_set(err, SR_E_VERSION, "'%s' has schema version %lld, migration %s needs %d",
                        cat->path, (long long)version, file->name, n - 1);
        goto fail;
    }
    st = run_script(cat, file, err);
    if (st != SR_OK)
        goto fail;
    st = query_int(cat, "PRAGMA user_version", &version, err, "read the schema version");
    if (st != SR_OK)
        goto fail;
    if (version != n) {
        st = sr_err_set(err, SR_E_INTERNAL,
                        "cannot apply migration %s to '%s': it left user_version %lld, not %d",
                        file->name, cat->path, (long long)version, n);
        goto fail;
    }
    st = foreign_key_check(cat, file, err);
    if (st != SR_OK)
        goto fail;
    st = query_int(cat, "PRAGMA application_id", &app_id, err, "read the application id");
    if (st != SR_OK)
        goto fail;
    if (app_id != SR_CATALOG_APP_ID) {
        st = sr_err_set(err, SR_E_INTERNAL,
                        "cannot apply migration %s to '%s': application_id is 0x%08llx after it",
                        file->name, cat->path, (unsigned long long)(uint32_t)app_id);
        goto fail;
    }
    st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        goto fail;
    return SR_OK;
fail:
    sr_cat_rollback(cat);
    return st;
}

/* Checks the header fields of a file that is open but untouched. */
static sr_status check_identity(sr_catalog *cat, int latest, bool create, int64_t *out_version,
                                sr_err *err)
{
    int64_t app_id, version, objects;
    sr_status st = query_int(cat, "PRAGMA application_id", &app_id, err, "read the application id");
    if (st == SR_OK)
        st = query_int(cat, "PRAGMA user_version", &version, err, "read the schema version");
    if (st == SR_OK)
        st = query_int(cat, "SELECT count(*) FROM sqlite_schema", &objects, err,
                       "read the schema");
    if (st != SR_OK) {
        if ((sqlite3_extended_errcode(cat->db) & 0xff) == SQLITE_NOTADB)
            return sr_err_set(err, SR_E_VERSION,
                              "'%s' is not a symrec catalogue (file is not a database)", cat->path);
        return st;
    }
    if (app_id != SR_CATALOG_APP_ID) {
        if (app_id != 0)
            return sr_err_set(err, SR_E_VERSION,
                              "'%s' is not a symrec catalogue (application_id 0x%08llx)", cat->path,
                              (unsigned long long)(uint32_t)app_id);
        if (objects != 0 || version != 0)
            return sr_err_set(err, SR_E_VERSION,
                              "'%s' is not a symrec catalogue (an SQLite database of another "
                              "program)",
                              cat->path);
        if (!create)
            return sr_err_set(err, SR_E_VERSION,
                              "'%s' is not a symrec catalogue (empty database; create it first)",
                              cat->path);
    }
    if (version < 0)
        return sr_err_set(err, SR_E_VERSION,
                          "'%s' is not a symrec catalogue (schema version %lld)", cat->path,
                          (long long)version);
    if (version > latest)
        return sr_err_set(err, SR_E_VERSION,
                          "'%s' has schema version %lld, this symrec knows up to %d: upgrade "
                          "symrec",
                          cat->path, (long long)version, latest);
    *out_version = version;
    return SR_OK;
}

/* WAL mode for a writable handle. PRAGMA journal_mode returns the mode now in force;
 * a file system without shared memory keeps the rollback journal, which is still
 * correct, only less concurrent. */
static sr_status set_wal(sr_catalog *cat, sr_err *err)
{
    if (cat->readonly)
        return SR_OK;
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, "PRAGMA journal_mode=WAL", &stmt, err);
    if (st != SR_OK)
        return st;
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "switch to WAL mode");
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, "switch to WAL mode");
}

/* Foreign keys on for this connection (outside any transaction, where the pragma
 * works), checked by reading it back. */
static sr_status set_foreign_keys(sr_catalog *cat, sr_err *err)
{
    sr_status st = exec_sql(cat, "PRAGMA foreign_keys=ON", err, "enable foreign keys");
    if (st != SR_OK)
        return st;
    int64_t fk;
    st = query_int(cat, "PRAGMA foreign_keys", &fk, err, "enable foreign keys");
    if (st == SR_OK && fk != 1)
        st = sr_err_set(err, SR_E_UNSUPPORTED,
                        "cannot open '%s': this SQLite library has no foreign key support",
                        cat->path);
    return st;
}

/* Opens cat->db on filename (a path, or a URI with SQLITE_OPEN_URI) with the
 * sqlite3_open_v2 flags given; messages name cat->path. */
static sr_status connect(sr_catalog *cat, const char *filename, int oflags, sr_err *err)
{
    int rc = sqlite3_open_v2(filename, &cat->db, oflags, NULL);
    if (rc != SQLITE_OK)
        return sr_err_set(err, status_of(rc) == SR_E_NOMEM ? SR_E_NOMEM : SR_E_IO,
                          "cannot open catalogue '%s': %s", cat->path,
                          cat->db ? sqlite3_errmsg(cat->db) : sqlite3_errstr(rc));
    sqlite3_extended_result_codes(cat->db, 1);
    sqlite3_busy_timeout(cat->db, BUSY_TIMEOUT_MS);
    return SR_OK;
}

/* Whether a read-only open that failed may be retried as immutable: SQLite said it
 * could not open or write a side file (the -shm of a WAL catalogue in a read-only
 * folder), and there is no -wal file (or an empty one) whose committed pages the file
 * alone would lack. */
static bool immutable_fits(sr_catalog *cat)
{
    int rc = sqlite3_extended_errcode(cat->db) & 0xff;
    if (rc != SQLITE_CANTOPEN && rc != SQLITE_READONLY)
        return false;
    size_t n = strlen(cat->path);
    char *wal = malloc(n + 5);
    if (!wal)
        return false;
    memcpy(wal, cat->path, n);
    memcpy(wal + n, "-wal", 5);
    struct stat sb;
    bool none = stat(wal, &sb) != 0 ? errno == ENOENT : sb.st_size == 0;
    free(wal);
    return none;
}

/* Opens path read-only through a "file:...?immutable=1" URI (the path
 * percent-encoded, so '?', '#' and '%' in a name stay part of it). */
static sr_status connect_immutable(sr_catalog *cat, const char *path, sr_err *err)
{
    static const char hex[] = "0123456789ABCDEF";
    size_t n = strlen(path);
    char *uri = malloc(3 * n + 32);
    if (!uri)
        return sr_err_set(err, SR_E_NOMEM, "cannot open catalogue '%s': out of memory", path);
    char *u = uri + sprintf(uri, "file:");
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)path[i];
        if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
            strchr("/-._~", c)) {
            *u++ = (char)c;
        } else {
            *u++ = '%';
            *u++ = hex[c >> 4];
            *u++ = hex[c & 15];
        }
    }
    strcpy(u, "?immutable=1");
    sr_status st = connect(cat, uri, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, err);
    free(uri);
    return st;
}

sr_status sr_cat_open_with(const char *path, unsigned flags, const sr_sql_file *files,
                           sr_catalog **out, sr_err *err)
{
    const bool readonly = (flags & SR_CATALOG_READONLY) != 0;
    const bool create = (flags & SR_CATALOG_CREATE) != 0 && !readonly;
    if (!path || !*path)
        return sr_err_set(err, SR_E_RANGE, "no catalogue file given");

    const int latest = sr_cat_schema_latest_of(files);
    for (int n = 1; n <= latest; n++)
        if (!migration_file(files, n))
            return sr_err_set(err, SR_E_INTERNAL,
                              "built-in schema is broken: migration %03d missing or repeated", n);

    struct stat sb;
    if (stat(path, &sb) != 0) {
        if (errno != ENOENT || !create)
            return sr_err_set(err, SR_E_IO, "cannot open catalogue '%s': %s", path,
                              errno == ENOENT ? "no such file" : strerror(errno));
    } else if (S_ISDIR(sb.st_mode)) {
        return sr_err_set(err, SR_E_IO, "cannot open catalogue '%s': is a directory", path);
    }

    sr_catalog *cat = calloc(1, sizeof *cat);
    char *path_copy = strdup(path);
    if (!cat || !path_copy) {
        free(cat);
        free(path_copy);
        return sr_err_set(err, SR_E_NOMEM, "cannot open catalogue '%s': out of memory", path);
    }
    cat->path = path_copy;
    cat->readonly = readonly;

    int oflags = readonly ? SQLITE_OPEN_READONLY
                          : SQLITE_OPEN_READWRITE | (create ? SQLITE_OPEN_CREATE : 0);
    sr_status st = connect(cat, path, oflags, err);
    if (st != SR_OK)
        goto fail;

    int64_t version;
    st = check_identity(cat, latest, create, &version, err);
    if (st != SR_OK && readonly && immutable_fits(cat)) {
        /* A WAL catalogue in a folder this process cannot write, with no -wal file:
         * SQLite cannot make the -shm file a reader needs, but nothing can be half
         * written either (a writer needs the -wal file, and there is none or an empty
         * one), so the file alone is the whole catalogue: read it as immutable. */
        sqlite3_close_v2(cat->db);
        cat->db = NULL;
        sr_err_clear(err);
        st = connect_immutable(cat, path, err);
        if (st == SR_OK)
            st = check_identity(cat, latest, create, &version, err);
    }
    if (st == SR_OK && readonly && version < latest) {
        if (flags & SR_CATALOG_UPGRADE) { /* migrate it once, through a writable handle */
            sr_catalog_close(cat);
            return sr_cat_open_with(path,
                                    flags & ~(unsigned)(SR_CATALOG_READONLY | SR_CATALOG_UPGRADE),
                                    files, out, err);
        }
        st = sr_err_set(err, SR_E_VERSION,
                        "'%s' has schema version %lld, this symrec needs %d: open it once "
                        "read-write to upgrade it",
                        path, (long long)version, latest);
    }
    if (st != SR_OK)
        goto fail;
    st = set_wal(cat, err);
    if (st != SR_OK)
        goto fail;
    cat->schema_opened = (int)version;
    for (int n = (int)version + 1; n <= latest; n++) {
        st = migrate_one(cat, migration_file(files, n), n, err);
        if (st != SR_OK)
            goto fail;
    }
    st = set_foreign_keys(cat, err);
    if (st != SR_OK)
        goto fail;
    st = query_int(cat, "PRAGMA user_version", &version, err, "read the schema version");
    if (st != SR_OK)
        goto fail;
    if (version > latest) {  /* a newer symrec migrated it while we were opening */
        st = sr_err_set(err, SR_E_VERSION,
                        "'%s' has schema version %lld, this symrec knows up to %d: upgrade symrec",
                        path, (long long)version, latest);
        goto fail;
    }
    cat->schema_version = (int)version;
    *out = cat;
    return SR_OK;
fail:
    sr_catalog_close(cat);
    return st;
}

sr_status sr_catalog_open(const char *path, unsigned flags, sr_catalog **out, sr_err *err)
{
    return sr_cat_open_with(path, flags, sr_sql_files, out, err);
}

sr_status sr_catalog_check_writable(sr_catalog *cat, bool *readonly, sr_err *err)
{
    *readonly = true;
    if (cat->readonly || sqlite3_db_readonly(cat->db, "main") == 1)
        return SR_OK;
    sr_status st = exec_sql(cat, "BEGIN IMMEDIATE", err, "start a write transaction");
    if (st != SR_OK) {
        int rc = sqlite3_extended_errcode(cat->db) & 0xff;
        if (rc == SQLITE_READONLY || rc == SQLITE_CANTOPEN || rc == SQLITE_PERM) {
            sr_err_clear(err);
            return SR_OK;
        }
        return st;
    }
    sr_cat_rollback(cat);
    *readonly = false;
    return SR_OK;
}

sr_status sr_catalog_open_memory(sr_catalog **out, sr_err *err)
{
    /* SQLite's own name for a private in-memory database; a file of that name in the
     * working directory is not opened (SQLite never treats ":memory:" as a path). */
    return sr_cat_open_with(":memory:", SR_CATALOG_CREATE, sr_sql_files, out, err);
}

void sr_catalog_close(sr_catalog *cat)
{
    if (!cat)
        return;
    /* Every statement is finalized by the call that prepared it, so close cannot be
     * refused with SQLITE_BUSY; sqlite3_close_v2 would defer it if one were left. */
    sqlite3_close_v2(cat->db);
    free(cat->path);
    free(cat);
}

int sr_catalog_schema_opened(sr_catalog *cat)
{
    return cat->schema_opened;
}

int sr_catalog_schema_version(sr_catalog *cat)
{
    return cat->schema_version;
}

const char *sr_catalog_path(const sr_catalog *cat)
{
    return cat->path;
}
