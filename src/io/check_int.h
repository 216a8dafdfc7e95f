/*
 * check_int.h: the private interface between the files that implement file_check.h.
 * Not installed, not used outside src/io/.
 *
 *   check_common.c  messages, growing arrays, the line reader and tokenizer of the text
 *                   formats, strict decimal numbers, collected faces
 *   check_stl.c     binary and ASCII STL, and blanking an ASCII STL's names
 *   check_obj.c     OBJ, and commenting out its mtllib lines
 *   check_off.c     ASCII OFF
 *   check_ply.c     PLY header and body (ascii, binary little and big endian)
 *   check_glb.c     GLB container chunks and JSON nesting depth
 *   envelope.c      the physical envelope of envelope.h (uses fc_fail only)
 *
 * Every helper works on [s, e) ranges of the file in memory and never reads past e.
 */
#ifndef SR_CHECK_INT_H
#define SR_CHECK_INT_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>

#include "base/status.h"
#include "io/file_check.h"

/* ---- messages and arrays ---- */

/* Sets err (when not NULL) to "cannot read 'name': <fmt...>" and returns status. */
sr_status fc_fail(sr_err *err, sr_status status, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Grows *ptr (elements of elem bytes, capacity *cap) to hold at least need elements.
 * Returns 0 (with *ptr and *cap unchanged) when out of memory or the size overflows. */
int fc_grow(void **ptr, size_t *cap, size_t need, size_t elem);

/* ---- bytes ---- */

static inline uint32_t fc_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* ---- text ---- */

/* Offset of the first byte that cannot be in a text file (controls other than
 * \t \n \v \f \r, and DEL), or size if there is none. Bytes >= 0x80 are text (UTF-8). */
size_t fc_first_binary_byte(const unsigned char *data, size_t size);

static inline int fc_blank(int c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* A line [p, e) of the file and where the next one starts. */
typedef struct fc_line_reader {
    const char *pos, *end;
    size_t number;     /* 1-based number of the line last returned */
} fc_line_reader;

/* The next line in [*s, *e) (without its '\n'); 0 at the end of the file. */
int fc_next_line(fc_line_reader *r, const char **s, const char **e);

/* Next whitespace-separated token of [*p, e); stops at '#' when hash_comments. */
int fc_next_token(const char **p, const char *e, const char **ts, const char **te,
                  int hash_comments);

/* Token equals word, ignoring case (STL keywords). */
static inline int fc_token_is(const char *s, const char *e, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(e - s) == n && strncasecmp(s, word, n) == 0;
}

/* Token equals word exactly (OBJ and PLY keywords: their readers are case-sensitive). */
static inline int fc_token_eq(const char *s, const char *e, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(e - s) == n && memcmp(s, word, n) == 0;
}

/* Copies a token for messages (shortened, NUL-terminated); returns buf. */
const char *fc_token_str(const char *s, const char *e, char buf[40]);

/* A decimal number [s, e): [+-] digits [. digits] [e [+-] digits], at least one digit,
 * or [+-] nan / inf / infinity (returned as such, for the caller to refuse). */
int fc_parse_real(const char *s, const char *e, double *out);

/* A decimal integer [s, e) with optional sign, |value| < 2^62. */
int fc_parse_int(const char *s, const char *e, long long *out);

/* "a NaN" or "an infinite", for messages about v. */
static inline const char *fc_nonfinite_word(double v)
{
    return isnan(v) ? "a NaN" : "an infinite";
}

/* ---- faces ---- */

/* Faces being collected (OBJ, OFF, PLY). */
typedef struct fc_face_acc {
    size_t size_cap, index_cap, index_count;
} fc_face_acc;

/* Appends a face of k corners idx to f (face_size, face_index, tri_count and, when a
 * vertex repeats, degenerate_tris). Returns 0 when out of memory. */
int fc_add_face(sr_file_facts *f, fc_face_acc *a, const uint32_t *idx, size_t k);

/* Face corners of one record, grown as needed. */
typedef struct fc_corner_buf {
    uint32_t *v;
    size_t cap;
} fc_corner_buf;

#endif
