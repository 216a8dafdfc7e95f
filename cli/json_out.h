/*
 * json_out.h: the CLI's JSON writer for --json output: one compact JSON value on one
 * line, commas placed by the writer, strings escaped (quotes, backslashes, control
 * characters; invalid UTF-8 bytes become U+FFFD), numbers in the shortest form that
 * reads back to the same double, NaN and infinities written as null (JSON has no
 * token for them).
 */
#ifndef SR_CLI_JSON_OUT_H
#define SR_CLI_JSON_OUT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "catalog/catalog.h"

#define JSON_MAX_DEPTH 16

typedef struct json_out {
    FILE *f;
    int depth;
    bool need_comma[JSON_MAX_DEPTH + 1];
    bool after_key;
} json_out;

void json_init(json_out *j, FILE *f);

void json_object_begin(json_out *j);
void json_object_end(json_out *j);
void json_array_begin(json_out *j);
void json_array_end(json_out *j);

/* The key of the next member of the current object. */
void json_key(json_out *j, const char *key);

void json_string(json_out *j, const char *s);       /* NULL writes null */
void json_number(json_out *j, double v);            /* non-finite writes null */
void json_int(json_out *j, int64_t v);
void json_bool(json_out *j, bool v);
void json_null(json_out *j);

/* Ends the document with a newline. */
void json_finish(json_out *j);

/* Writes s as a quoted, escaped JSON string (exposed for tests of the escaping). */
void json_write_string(FILE *f, const char *s);

/* Writes v in the shortest %.Ng (N = 15..17) that reads back to v; null if v is not
 * finite. */
void json_write_number(FILE *f, double v);

/* The catalogue's records as JSON objects, shared by the commands that print them. */
void json_symmetry(json_out *j, const sr_symmetry *sym);
void json_part(json_out *j, const sr_part_info *p);
void json_instance(json_out *j, const sr_instance_info *in);
void json_params(json_out *j, const sr_params *p);
/* The members alone, for a caller that adds more to the same object. */
void json_part_members(json_out *j, const sr_part_info *p);
void json_instance_members(json_out *j, const sr_instance_info *in);

/* A run's description as `run show --json` and `reconstruct --json` write it
 * (cli/cmd_run.c): a section's "features" object (its figures, "class", then the
 * members of its features_json), and the "advice" array. */
void json_run_features(json_out *j, const sr_run_section *s);
void json_run_advice(json_out *j, const sr_run *r);

#endif
