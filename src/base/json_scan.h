/*
 * json_scan.h: a small reader of JSON text stored by other modules (a run's timings,
 * a section's features, an advice's details), for the few places that walk such a
 * text instead of querying it in SQLite: the members of an object, each value as the
 * span of text it takes. It does not decode strings or numbers (the caller does, with
 * strtod for a number) and does not validate: the catalogue checks every stored text
 * with json_valid. It is bounded by the terminating NUL, so a damaged text gives a short
 * walk or no value, never a read past the end.
 */
#ifndef SR_JSON_SCAN_H
#define SR_JSON_SCAN_H

#include <stdbool.h>
#include <stddef.h>

/* p past any JSON whitespace (space, tab, newline, carriage return). p not NULL. */
const char *sr_json_skip_space(const char *p);

/* The end of the JSON value starting at p (just after it: after a string's closing
 * quote, an object's or array's closing bracket, a number's or word's last character),
 * or NULL when there is none (p at a ',', '}', ']' or the end). */
const char *sr_json_value_end(const char *p);

/* Called for each member of an object: the raw key (without its quotes, escapes as
 * written, key_len bytes) and the value's span [val, end). */
typedef void (*sr_json_member_fn)(const char *key, size_t key_len, const char *val, const char *end,
                                  void *user);

/* Calls fn for each member of the JSON object `text` (leading whitespace allowed), in
 * order, until the object ends or the text stops making sense. True when the walk
 * reached the object's closing '}' (so every member was seen); false for NULL, a text
 * that is not an object, or one that breaks off (fn has seen the members before). */
bool sr_json_for_members(const char *text, sr_json_member_fn fn, void *user);

#endif
