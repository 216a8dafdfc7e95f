/*
 * jsonbuf.h: a JSON text built in memory: the one JSON writer, for the library's JSON
 * columns (sections.features_json, advice.details_json) and, through the thin layer
 * cli/json_out.h, for the CLI's --json output. It appends to a growable heap string
 * (the library may not print). Commas are placed by the writer; strings are escaped
 * (quotes, backslashes, control characters, DEL and the C1 controls U+0080-U+009F:
 * \b \f \n \r \t by name, the rest as \u00XX; invalid UTF-8 bytes become U+FFFD) so
 * the result
 * always passes SQLite's json_valid; numbers are written in the shortest form that
 * reads back to the same double, and NaN or infinities as null.
 *
 * Out of memory is sticky: later calls do nothing and sr_jsonbuf_take reports it, so a
 * builder needs one check at the end.
 *
 *   sr_jsonbuf jb;
 *   sr_jsonbuf_init(&jb);
 *   sr_jsonbuf_object_begin(&jb);
 *   sr_jsonbuf_key(&jb, "depth_mm"); sr_jsonbuf_number(&jb, 2.5);
 *   sr_jsonbuf_object_end(&jb);
 *   char *text;
 *   if (sr_jsonbuf_take(&jb, &text, err) == SR_OK) ... free(text);
 */
#ifndef SR_JSONBUF_H
#define SR_JSONBUF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base/status.h"

#define SR_JSONBUF_MAX_DEPTH 16

typedef struct sr_jsonbuf {
    char *s;
    size_t len, cap;
    int depth;
    bool need_comma[SR_JSONBUF_MAX_DEPTH + 1];
    bool after_key;
    bool nomem;                 /* an allocation failed (or nesting too deep) */
} sr_jsonbuf;

void sr_jsonbuf_init(sr_jsonbuf *jb);
/* Frees the text (if not taken); accepts a zeroed or released builder. */
void sr_jsonbuf_release(sr_jsonbuf *jb);

void sr_jsonbuf_object_begin(sr_jsonbuf *jb);
void sr_jsonbuf_object_end(sr_jsonbuf *jb);
void sr_jsonbuf_array_begin(sr_jsonbuf *jb);
void sr_jsonbuf_array_end(sr_jsonbuf *jb);
/* The key of the next member of the current object. */
void sr_jsonbuf_key(sr_jsonbuf *jb, const char *key);
/* The same for a key already escaped (len bytes, e.g. as it stands between the quotes
 * of a stored JSON text), written unchanged. */
void sr_jsonbuf_key_raw(sr_jsonbuf *jb, const char *key, size_t len);
void sr_jsonbuf_string(sr_jsonbuf *jb, const char *s);   /* NULL writes null */
void sr_jsonbuf_number(sr_jsonbuf *jb, double v);        /* non-finite writes null */
void sr_jsonbuf_int(sr_jsonbuf *jb, int64_t v);
void sr_jsonbuf_bool(sr_jsonbuf *jb, bool v);
void sr_jsonbuf_null(sr_jsonbuf *jb);
/* Inserts `json` as one value, unchecked: the caller guarantees it is valid JSON
 * (e.g. a column the database checked with json_valid). NULL or "" writes null. */
void sr_jsonbuf_raw(sr_jsonbuf *jb, const char *json);

/* Writes v into buf in the shortest %.Ng (N = 15..17) that reads back to v ("null"
 * when not finite, "0" for -0) and returns buf. */
#define SR_JSONBUF_NUMBER_SIZE 40
const char *sr_jsonbuf_format_number(double v, char buf[SR_JSONBUF_NUMBER_SIZE]);

/* Hands the text over (heap, NUL-terminated; free() it) and resets the builder.
 * SR_E_NOMEM if any append failed (then nothing is handed over). */
sr_status sr_jsonbuf_take(sr_jsonbuf *jb, char **out, sr_err *err);

#endif
