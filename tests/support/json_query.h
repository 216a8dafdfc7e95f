/*
 * json_query.h: reads values out of a JSON text with SQLite's JSON functions (an
 * in-memory connection), for tests of the library's JSON columns. Paths are SQLite
 * JSON paths ("$.class", "$.rules_fired[0]", "$.rules_unevaluated").
 */
#ifndef SR_TEST_JSON_QUERY_H
#define SR_TEST_JSON_QUERY_H

#include <stdbool.h>

/* json_valid(json). */
bool jq_valid(const char *json);
/* The value at path as text (strings unquoted, numbers printed by SQLite, containers
 * as JSON), malloc'd; NULL when missing or JSON null. */
char *jq_text(const char *json, const char *path);
/* The number at path; NaN when missing, null or not a number. */
double jq_num(const char *json, const char *path);
/* json_array_length at path; -1 when missing or not an array. */
long jq_len(const char *json, const char *path);
/* Whether the string array at path holds s. */
bool jq_has(const char *json, const char *path, const char *s);

#endif
