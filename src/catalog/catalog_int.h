/*
 * catalog_int.h: private interface shared by the catalog*.c files (the SQLite style
 * split of one module into several files behind one public header, catalog.h). Not
 * for use outside src/catalog*.c, except by the catalogue's own white-box tests.
 *
 * It holds the handle's layout and the few helpers every statement goes through, so
 * that a later file (runs, history, rules) adds a feature without repeating them:
 *   - sr_cat_prepare / sr_cat_step / sr_cat_finish: prepared statements, every result
 *     checked, the SQLite message turned into one sr_err line naming the file;
 *   - sr_cat_begin / sr_cat_commit / sr_cat_rollback: one BEGIN IMMEDIATE write
 *     transaction per public call, rolled back on any error;
 *   - binding and reading helpers for optional text and fixed-size fields;
 *   - mesh rows: built (validated, encoded) before the transaction, inserted inside it,
 *     decoded from a result row.
 *
 * Pattern of a write (see catalog_parts.c):
 *     check arguments (no transaction yet)
 *     st = sr_cat_begin(cat, err);                 if (st) return st;
 *     ... statements, each failure: goto fail ...
 *     st = sr_cat_commit(cat, err);                if (st) goto fail;
 *     return SR_OK;
 *   fail:
 *     sr_cat_rollback(cat);                        (keeps err as set by the failure)
 *     return st;
 */
#ifndef SR_CATALOG_INT_H
#define SR_CATALOG_INT_H

#include <sqlite3.h>
#include <stdbool.h>
#include <stdint.h>

#include "catalog/catalog.h"
#include "catalog/sql_embedded.h"

struct sr_catalog {
    sqlite3 *db;
    char *path;             /* as given to sr_catalog_open (for messages) */
    int schema_version;     /* user_version after opening */
    int schema_opened;      /* user_version found, before any migration (0: new file) */
    bool readonly;
};

/* Opens like sr_catalog_open, with the migrations taken from `files` (a table ending
 * with { NULL, NULL }, like sr_sql_files) instead of the built-in ones. For tests of
 * the migration machinery (a failing migration must roll back). */
sr_status sr_cat_open_with(const char *path, unsigned flags, const sr_sql_file *files,
                           sr_catalog **out, sr_err *err);

/* The highest migration number in `files` (0 if none). */
int sr_cat_schema_latest_of(const sr_sql_file *files);

/* Turns the connection's last SQLite error into a status and one line:
 * "cannot <what> in '<path>': <sqlite message>". SQLITE_BUSY/LOCKED gets
 * "... is busy (another process is writing)". Status by error class: SR_E_NOMEM,
 * SR_E_IO (disk full, I/O), SR_E_RANGE (too big), SR_E_EXISTS (unique constraint),
 * SR_E_VERSION (not a database), SR_E_DB otherwise. `what` is printf-style. */
sr_status sr_cat_db_error(sr_catalog *cat, sr_err *err, const char *what, ...)
    __attribute__((format(printf, 3, 4)));

/* Prepares one statement of static SQL text. On error *out is NULL. */
sr_status sr_cat_prepare(sr_catalog *cat, const char *sql, sqlite3_stmt **out, sr_err *err);

/* Steps once. Returns SR_OK and sets *row (true = SQLITE_ROW, false = SQLITE_DONE);
 * any other result is an error ("cannot <what> ..."). row may be NULL when the
 * statement returns no rows (then a row is an error too). */
sr_status sr_cat_step(sr_catalog *cat, sqlite3_stmt *stmt, bool *row, sr_err *err,
                      const char *what);

/* Finalizes a statement (NULL accepted). Returns SR_OK or the error finalize reports;
 * use it on success paths. On failure paths plain sqlite3_finalize is enough. */
sr_status sr_cat_finish(sr_catalog *cat, sqlite3_stmt *stmt, sr_err *err, const char *what);

/* Runs a statement that returns no rows to completion, then finalizes it (always). */
sr_status sr_cat_exec(sr_catalog *cat, sqlite3_stmt *stmt, sr_err *err, const char *what);

/* BEGIN IMMEDIATE: takes the write lock now, waiting up to the busy timeout.
 * SR_E_DB for a read-only handle. */
sr_status sr_cat_begin(sr_catalog *cat, sr_err *err);
/* COMMIT. On failure the caller must still call sr_cat_rollback. */
sr_status sr_cat_commit(sr_catalog *cat, sr_err *err);
/* ROLLBACK if a transaction is open; never touches err (the first error is kept). */
void sr_cat_rollback(sr_catalog *cat);

/* Binds text, or NULL when s is NULL or "". */
int sr_cat_bind_opt_text(sqlite3_stmt *stmt, int index, const char *s);
/* Copies column `col` (text, NULL -> "") into a fixed field of `size` bytes. Values
 * never exceed the field (the schema checks the byte lengths); a longer one, from a
 * file edited by hand, is cut at a character boundary rather than overflowing. */
void sr_cat_column_text(sqlite3_stmt *stmt, int col, char *dst, size_t size);

/* True when s is non-NULL and strlen(s) is in [min, max]. */
bool sr_cat_len_ok(const char *s, size_t min, size_t max);

/* Figures of a stored mesh, as shown in part and instance listings. */
typedef struct sr_cat_mesh_figures {
    size_t vertex_count, tri_count;
    double volume_mm3, area_mm2;
    double bbox_min[3], bbox_max[3];
} sr_cat_mesh_figures;

/* Reads the 10 columns vertex_count, tri_count, volume_mm3, area_mm2, bbox_min_x..z,
 * bbox_max_x..z starting at column `col` (NULLs, from a LEFT JOIN without a mesh,
 * read as zeros). */
void sr_cat_column_figures(sqlite3_stmt *stmt, int col, sr_cat_mesh_figures *out);

/* A mesh row made ready outside the write transaction: validated, figures computed,
 * blob encoded, so the write lock is held only for the I/O. */
typedef struct sr_cat_mesh_row {
    sr_cat_mesh_figures fig;
    int closed;             /* sr_mesh_is_closed */
    void *blob;             /* sr_mesh_blob_encode output, owned */
    size_t blob_size;
    const char *source_file; /* borrowed; NULL or "" = none */
    sr_unit source_unit;     /* unit the source file was drawn in; SR_UNIT_DEFAULT = mm */
} sr_cat_mesh_row;

/* Validates `mesh` (sr_mesh_validate, naming `what`) and fills *out. SR_E_INVALID for a
 * bad mesh, SR_E_RANGE for one too large for the catalogue, SR_E_NOMEM. Release with
 * sr_cat_mesh_row_release (accepts a zeroed row). */
sr_status sr_cat_mesh_row_build(sr_catalog *cat, const sr_mesh *mesh, const char *what,
                                const char *source_file, sr_cat_mesh_row *out, sr_err *err);
void sr_cat_mesh_row_release(sr_cat_mesh_row *row);

/* Inserts a built row into meshes, inside the caller's transaction. */
sr_status sr_cat_mesh_row_insert(sr_catalog *cat, const sr_cat_mesh_row *row,
                                 int64_t *out_id, sr_err *err);

/* Decodes the mesh of a result row whose columns from `col` are vertex_count,
 * tri_count, format_version, data (of mesh `mesh_id`, named in messages), checking
 * the blob against the row. Call before the statement is stepped again. */
sr_status sr_cat_mesh_from_row(sr_catalog *cat, sqlite3_stmt *stmt, int col, int64_t mesh_id,
                               sr_mesh *out, sr_err *err);

/* Resolves a part key (number, or numeric id when no number matches) to its id.
 * SR_E_NOTFOUND "no part 'X' in the catalogue". Usable inside a transaction. */
sr_status sr_cat_part_resolve(sr_catalog *cat, const char *key, int64_t *out_id, sr_err *err);

/* Parses a whole string as a positive int64 id; false otherwise. */
bool sr_cat_parse_id(const char *s, int64_t *out);

/* Reads the symmetry columns kind, order_n, shift_mm at `col` (NULL kind = NONE). */
void sr_cat_column_symmetry(sqlite3_stmt *stmt, int col, sr_symmetry *out);

/* Sets (or with kind NONE clears) the symmetry row of a part (instance_id 0) or an
 * instance (part_id 0), inside the caller's transaction. */
sr_status sr_cat_symmetry_write(sr_catalog *cat, int64_t part_id, int64_t instance_id,
                                const sr_symmetry *sym, sr_err *err);

/* ---- the run record's blobs (catalog_runs.c, read back in catalog_run_read.c) ---- */

/* Writes v to p[0..7] as a little-endian IEEE double, byte by byte, so the alignment and
 * layer outline blobs read the same on any host (their layout: catalog_runs.c). */
void sr_cat_put_f64(unsigned char *p, double v);

/* catalog_nominal.c: a run's nominal record (sr_run_nominal; n NULL writes nothing)
 * inserted for run_id inside the caller's transaction, and read back into r->nominal
 * (left NULL when the run has none). */
sr_status sr_cat_nominal_insert(sr_catalog *cat, const sr_run_nominal *n, int64_t run_id,
                                sr_err *err);
sr_status sr_cat_nominal_read(sr_catalog *cat, sr_run *r, sr_err *err);

/* catalog_scan.c: a run's scan record (sr_run_scan, its gaps; s NULL writes nothing)
 * inserted for run_id inside the caller's transaction, and read back into r->scan (left
 * NULL when the run has none). */
sr_status sr_cat_scan_insert(sr_catalog *cat, const sr_run_scan *s, int64_t run_id, sr_err *err);
sr_status sr_cat_scan_read(sr_catalog *cat, sr_run *r, sr_err *err);
/* Reads the double sr_cat_put_f64 wrote at p[0..7]. */
double sr_cat_get_f64(const unsigned char *p);

/* ---- history summaries (catalog_history.c) ---- */

struct sr_history_filter;
struct sr_history_summary;

/* Which way a history summary is computed: AUTO as sr_catalog_history_summary (the
 * summary cells of sql/004 when they answer the filter exactly, else the runs); RUNS
 * always from the runs; CELLS only from the cells (SR_E_INVALID "the history summary
 * cells cannot answer this filter" when they cannot). *used_cells (may be NULL) tells
 * which way was taken, on success. For the tests and the bench that compare the two. */
typedef enum sr_cat_summary_way {
    SR_CAT_SUMMARY_AUTO = 0,
    SR_CAT_SUMMARY_RUNS,
    SR_CAT_SUMMARY_CELLS,
} sr_cat_summary_way;
sr_status sr_cat_history_summary_way(sr_catalog *cat, const struct sr_history_filter *filter,
                                     sr_cat_summary_way way, struct sr_history_summary *out,
                                     bool *used_cells, sr_err *err);

/* ---- shape descriptors (catalog_identify.c) ---- */

struct sr_shape_descriptor;

/* The stored form of a descriptor (mesh_descriptors.data): SR_CAT_DESCRIPTOR_BYTES,
 * 8-byte little-endian doubles: the version (SR_SHAPE_DESCRIPTOR_VERSION), the area,
 * the 3 spreads, the SR_SHAPE_D2_BINS D2 shares. */
#define SR_CAT_DESCRIPTOR_BYTES (8 * (5 + SR_SHAPE_D2_BINS))
/* The schema version that made table mesh_descriptors (sql/006_part_descriptor.sql). */
#define SR_CAT_DESCRIPTOR_SCHEMA 6
void sr_cat_descriptor_pack(const struct sr_shape_descriptor *d, unsigned char *out);
/* SR_E_FORMAT when size is not SR_CAT_DESCRIPTOR_BYTES, the version differs, or a
 * figure is negative or not finite. *out only on SR_OK. */
sr_status sr_cat_descriptor_unpack(const void *data, size_t size, struct sr_shape_descriptor *out,
                                   sr_err *err);

/* Stores (replaces) the shape descriptor of mesh `mesh_id`, inside the caller's
 * transaction. */
sr_status sr_cat_descriptor_put(sr_catalog *cat, int64_t mesh_id,
                                const struct sr_shape_descriptor *d, sr_err *err);

#endif
