/*
 * file_check.h: pure-C checks of a mesh file's bytes, run before the bytes are handed
 * to a parsing library (OpenMesh, tinygltf) and used again after it returns.
 *
 * The libraries accept bad input silently (shared/DEPENDENCY-NOTES.md): OpenMesh reads
 * a binary STL with a lying triangle count as an empty ASCII file, drops faces with an
 * index out of range, hangs on a truncated PLY header, throws bad_alloc on a huge OFF
 * count; tinygltf reads past a GLB chunk whose length is overstated by 8 bytes. The
 * checks here refuse such files with one line naming the file and what is wrong, and
 * return the facts a reader's result must agree with: how many vertices and faces the
 * file holds, the coordinates as written (in double precision: OpenMesh 9 reads every
 * format as float), the faces' vertex indices, and the triangles a reader is expected
 * to drop because they repeat a vertex.
 *
 * Every function works on a whole file in memory (data, size) and never reads past it;
 * `name` is the file name used in messages ("cannot read 'name': ..."). Numbers are
 * parsed with strtod, so the C library's LC_NUMERIC must use '.' (symrec never calls
 * setlocale; a ',' locale makes every decimal number fail loudly, never silently).
 * Nothing here allocates more than the file can justify: declared counts are checked
 * against the file size before any array is sized by them.
 */
#ifndef SR_FILE_CHECK_H
#define SR_FILE_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "base/status.h"

/* What a mesh file holds, as found by a check. Zeroed by sr_file_facts_release. */
typedef struct sr_file_facts {
    int binary;              /* STL/PLY: the body is binary */
    size_t vertex_count;     /* OBJ/OFF/PLY: vertices in the file; STL: 3 * face_count */
    size_t face_count;       /* faces (STL facets, OBJ `f` lines, OFF/PLY face records) */
    size_t tri_count;        /* triangles those faces make once fanned: sum of (k - 2) */
    size_t degenerate_tris;  /* of tri_count, triangles in faces a reader drops because
                                a vertex repeats (STL: two corners at the same point) */
    double *xyz;             /* OBJ/OFF/PLY: vertex_count by 3, coordinates as written;
                                owned */
    float *corners;          /* ASCII STL: each facet's three corners by 3 (vertex_count
                                by 3), as the float format stores them; owned. A binary
                                STL's are its bytes (sr_file_stl_facet) */
    uint32_t *face_size;     /* OBJ/OFF/PLY: face_count corner counts (each >= 3); owned */
    uint32_t *face_index;    /* OBJ/OFF/PLY: the faces' 0-based vertex indices back to
                                back, sum(face_size) entries, all < vertex_count; owned */
} sr_file_facts;

/* Frees the arrays and zeroes *facts; accepts NULL and a zeroed struct. */
void sr_file_facts_release(sr_file_facts *facts);

/*
 * Each check returns SR_OK and fills *out (which the caller releases), or fails with
 * *out untouched:
 *   SR_E_FORMAT   malformed, truncated, or counts that disagree with the file size
 *   SR_E_INVALID  a NaN/Inf coordinate (or one beyond float range in STL), a face
 *                 index that is 0 (OBJ), negative or not below the vertex count
 *   SR_E_UNSUPPORTED  a variant the readers do not handle (4OFF, nOFF, binary OFF)
 *   SR_E_NOMEM
 * A file with no faces passes (face_count 0): the caller decides that it is empty.
 */

/* Binary STL: the size must be 84 + 50 n for the header's n, every coordinate finite.
 * A file starting with "solid" is binary when its size matches 84 + 50 n (n > 0) or it
 * holds non-text bytes; otherwise ASCII, where each "outer loop" line must be followed
 * by exactly three "vertex x y z" lines. Both: every corner within the physical
 * envelope (envelope.h). */
sr_status sr_file_check_stl(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err);

#define SR_STL_HEADER_BYTES 84 /* 80 bytes of header, the facet count */
#define SR_STL_FACET_BYTES 50  /* normal, three corners (12 floats), attribute count */

/* n > 0 when a file of size bytes whose first 84 bytes are header is a binary STL of n
 * facets by size (84 + 50 n): what sr_file_check_stl takes for binary whatever the
 * header says (a file read a run of facets at a time); 0 otherwise. */
size_t sr_file_stl_binary_count(const unsigned char *header, size_t size);

/* The binary check of sr_file_check_stl on count facet records (50 bytes each) that are
 * the file's facets first on: finite, in the envelope; adds the degenerate ones (two
 * corners at one point) to *degenerate. Messages name facets as counted in the file. */
sr_status sr_file_check_stl_facets(const unsigned char *records, size_t count, size_t first,
                                   const char *name, size_t *degenerate, sr_err *err);

/* One binary STL facet record's corners, as stored. */
void sr_file_stl_facet(const unsigned char *record, float corners[9]);

/* Rewrites an ASCII STL in place, size unchanged, so that a line-based reader sees only
 * facet structure: every line whose first word is not facet, outer, vertex, endloop or
 * endfacet (solid and endsolid lines with their names, anything else) becomes spaces.
 * OpenMesh takes any line containing "outer" (as in `solid outer_shell`) for the start of
 * a facet and loses the first real one. Call only after sr_file_check_stl said ASCII. */
void sr_file_stl_blank_names(unsigned char *data, size_t size);

/* OBJ: `v` lines need three finite numbers; `f` lines at least three vertex references
 * (`i`, `i/t`, `i//n`, `i/t/n`), negative ones relative to the vertices defined so far,
 * positive ones (forward references allowed) at most the file's vertex count. */
sr_status sr_file_check_obj(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err);

/* Comments out `mtllib` lines in place (first byte becomes '#'), so a reader opens no
 * other file. */
void sr_file_obj_drop_mtllib(unsigned char *data, size_t size);

/* ASCII OFF ([ST][C][N]OFF): three counts, plausible against the file size, then one
 * vertex per line (first three numbers taken) and one face per line (k, then k
 * indices, and nothing after them: OpenMesh reads a face colour as the next face), then
 * nothing but blank lines and comments. */
sr_status sr_file_check_off(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err);

/* PLY (ascii, binary_little_endian, binary_big_endian 1.0): a strict header (every
 * line known, `element NAME COUNT` with a decimal count, `property TYPE NAME` or
 * `property list CTYPE ITYPE NAME`, `end_header` present, counts plausible against the
 * file size), then the whole body walked: a `vertex` element with x, y, z and a `face`
 * element with an integer list `vertex_indices` (or `vertex_index`); other elements
 * and properties are stepped over. Bytes after the last element are refused. */
sr_status sr_file_check_ply(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err);

/* Where a GLB's chunks lie (offsets from the start of the file). */
typedef struct sr_glb_layout {
    size_t json_offset, json_size;   /* JSON chunk payload */
    size_t bin_offset, bin_size;     /* BIN chunk payload; 0, 0 when there is none */
    int has_bin;
} sr_glb_layout;

/* GLB container: magic "glTF", version 2, total length equal to the file size, a JSON
 * chunk first, then an optional BIN chunk and any further chunks, each 8-byte chunk
 * header and payload inside the file. */
sr_status sr_file_check_glb(const unsigned char *data, size_t size, const char *name,
                            sr_glb_layout *out, sr_err *err);

/* The same check of a GLB of size bytes of which only the first `known` are given (a
 * file written as it was made: its header, JSON chunk and the chunk headers after it
 * kept, the payloads gone to the file): a chunk header past them is refused. */
sr_status sr_file_check_glb_head(const unsigned char *data, size_t known, size_t size,
                                 const char *name, sr_glb_layout *out, sr_err *err);

/* JSON nesting: refuses text whose arrays/objects nest deeper than max_depth (a
 * recursive parser would exhaust the stack). Strings are skipped, escapes honoured. */
sr_status sr_file_check_json_depth(const unsigned char *text, size_t size, size_t max_depth,
                                   const char *name, sr_err *err);

#endif
