/*
 * json_query.c: JSON look-ups for tests through SQLite's JSON functions
 * (json_query.h).
 */
#include "support/json_query.h"

#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static sqlite3 *db(void)
{
    static sqlite3 *conn;
    if (!conn && sqlite3_open(":memory:", &conn) != SQLITE_OK) {
        fprintf(stderr, "json_query: cannot open sqlite\n");
        abort();
    }
    return conn;
}

/* Runs sql with ?1 = json, ?2 = path (and ?3 = s) and returns its statement at the
 * first row, or NULL. */
static sqlite3_stmt *query(const char *sql, const char *json, const char *path, const char *s)
{
    sqlite3_stmt *st;
    if (sqlite3_prepare_v2(db(), sql, -1, &st, NULL) != SQLITE_OK)
        return NULL;
    sqlite3_bind_text(st, 1, json, -1, SQLITE_TRANSIENT);
    if (path)
        sqlite3_bind_text(st, 2, path, -1, SQLITE_TRANSIENT);
    if (s)
        sqlite3_bind_text(st, 3, s, -1, SQLITE_TRANSIENT);
    if (sqlite3_step(st) != SQLITE_ROW) {
        sqlite3_finalize(st);
        return NULL;
    }
    return st;
}

bool jq_valid(const char *json)
{
    if (!json)
        return false;
    sqlite3_stmt *st = query("SELECT json_valid(?1)", json, NULL, NULL);
    bool ok = st && sqlite3_column_int(st, 0) == 1;
    sqlite3_finalize(st);
    return ok;
}

char *jq_text(const char *json, const char *path)
{
    sqlite3_stmt *st = query("SELECT json_extract(?1, ?2)", json, path, NULL);
    char *out = NULL;
    if (st && sqlite3_column_type(st, 0) != SQLITE_NULL)
        out = strdup((const char *)sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    return out;
}

double jq_num(const char *json, const char *path)
{
    sqlite3_stmt *st = query("SELECT json_extract(?1, ?2)", json, path, NULL);
    double v = NAN;
    if (st && (sqlite3_column_type(st, 0) == SQLITE_FLOAT ||
               sqlite3_column_type(st, 0) == SQLITE_INTEGER))
        v = sqlite3_column_double(st, 0);
    sqlite3_finalize(st);
    return v;
}

long jq_len(const char *json, const char *path)
{
    sqlite3_stmt *st = query("SELECT json_array_length(?1, ?2)", json, path, NULL);
    long n = -1;
    if (st && sqlite3_column_type(st, 0) != SQLITE_NULL)
        n = (long)sqlite3_column_int64(st, 0);
    sqlite3_finalize(st);
    return n;
}

bool jq_has(const char *json, const char *path, const char *s)
{
    sqlite3_stmt *st = query("SELECT count(*) FROM json_each(?1, ?2) WHERE value = ?3", json,
                             path, s);
    bool has = st && sqlite3_column_int(st, 0) > 0;
    sqlite3_finalize(st);
    return has;
}
