/*
 * json_out.h: the CLI's --json output: one compact JSON value on one line, written to
 * a FILE. A thin layer over the library's builder (base/jsonbuf.h), which owns the
 * JSON text itself: commas, string escaping (invalid UTF-8 bytes become U+FFFD),
 * numbers in the shortest form that reads back to the same double, NaN and infinities
 * as null. The document is built in memory and written whole by json_finish, so a
 * command that fails half-way prints no half-written JSON (json_discard). Also the
 * JSON form of the catalogue's records (json_out.c) and of a run (cmd_run.c).
 */
#ifndef SR_CLI_JSON_OUT_H
#define SR_CLI_JSON_OUT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "base/jsonbuf.h"
#include "base/status.h"
#include "catalog/catalog.h"

typedef struct json_out {
    FILE *f;       /* where json_finish writes the document */
    sr_jsonbuf jb; /* the document so far */
} json_out;

/* Starts a document for f; json_finish or json_discard ends it. */
void json_init(json_out *j, FILE *f);

void json_object_begin(json_out *j);
void json_object_end(json_out *j);
void json_array_begin(json_out *j);
void json_array_end(json_out *j);

/* The key of the next member of the current object. */
void json_key(json_out *j, const char *key);

void json_string(json_out *j, const char *s); /* NULL writes null */
void json_number(json_out *j, double v);      /* non-finite writes null */
void json_int(json_out *j, int64_t v);
void json_bool(json_out *j, bool v);
void json_null(json_out *j);
/* Inserts `json` as one value, unchecked: valid JSON text the caller vouches for (a
 * stored column, compacted). NULL or "" writes null. */
void json_raw(json_out *j, const char *json);
/* The key of the next member as it stands between a stored text's quotes (escapes
 * included, len bytes), written unchanged. */
void json_key_raw(json_out *j, const char *key, size_t len);
/* Marks the document out of memory (a caller's own allocation for a value failed):
 * json_finish then writes nothing and reports it. */
void json_nomem(json_out *j);

/* Writes the document and a newline to the FILE and releases it. SR_E_NOMEM, with
 * nothing written, if building it ran out of memory. */
sr_status json_end(json_out *j, sr_err *err);
/* json_end for a command: CLI_OK, or CLI_FAIL after one error line on stderr. */
int json_finish(json_out *j);
/* Releases a document that is not to be written (the command failed after
 * json_init). */
void json_discard(json_out *j);

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
/* A symmetry fit's JSON object as it is (run/run_symfit.h), null for NULL. */
void cli_symfit_json(json_out *j, const char *fit_json);
/* The nominal record as one object (null when n is NULL): cli/nominal_out.c. */
void json_run_nominal(json_out *j, const sr_run_nominal *n);
/* An input scan's description as one object (cli/scan_out.c). */
struct sr_scan_desc;
void json_scan(json_out *j, const struct sr_scan_desc *d);
/* The run record's scan gaps (run.h's sr_run_scan) as an object; null when s is NULL. */
void json_run_scan(json_out *j, const sr_run_scan *s);

#endif
