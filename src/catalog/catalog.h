/*
 * catalog.h: the symrec catalogue, an SQLite file holding parts (models) with their
 * intact meshes, damaged instances with their scans, the symmetry chosen for each,
 * named parameter sets, and (filled by later work) reconstruction runs, layer
 * polylines, missing sections, repair rules and advice, materials.
 *
 * This module is the only owner of a sqlite3 handle (an opaque sr_catalog). The schema
 * and its numbered migrations are the files in sql/, compiled into the binary and keyed
 * by PRAGMA user_version; PRAGMA application_id marks a symrec catalogue. Every write is
 * one BEGIN IMMEDIATE transaction that rolls back on any error, so a failed call leaves
 * the catalogue as it was. WAL mode and a busy timeout let two processes share a file.
 * Meshes are stored as compact blobs (src/catalog/mesh_blob.h) and load back at memory speed.
 *
 * Strings in the *_info structs are fixed-size; inputs longer than the field are
 * refused with SR_E_RANGE rather than truncated.
 */
#ifndef SR_CATALOG_H
#define SR_CATALOG_H

#include <stdbool.h>
#include <stdint.h>

#include "mesh/mesh.h"
#include "mesh/units.h"
#include "base/status.h"
#include "base/symmetry.h"
#include "run/run.h"

typedef struct sr_catalog sr_catalog;

/* Current schema version: the highest migration number in sql/. */
int sr_catalog_schema_latest(void);

/* 'SYMR' as PRAGMA application_id. */
#define SR_CATALOG_APP_ID 0x53594d52

enum {
    SR_CATALOG_CREATE = 1,   /* create the file (and apply all migrations) if missing */
    SR_CATALOG_READONLY = 2, /* open read-only; never migrates (an older schema is
                              * refused, SR_E_VERSION) */
    SR_CATALOG_UPGRADE = 4,  /* with READONLY: a file of an older schema is opened
                              * read-write instead and migrated (the handle is then
                              * writable); a current one stays read-only */
};

/* Opens (and with SR_CATALOG_CREATE creates) a catalogue and brings its schema up to
 * date. Refuses a file that is not SQLite, not a symrec catalogue (application_id), or
 * from a newer schema version (SR_E_VERSION). *out only on success.
 *
 * Read-only (SR_CATALOG_READONLY) works on a file or folder this process cannot
 * write: SQLite's reader of a WAL file needs a -shm file beside it, so when that
 * cannot be made and no -wal file (or an empty one) exists - nothing can be half
 * written: a writer needs one - the file is read as immutable (SQLite's
 * "immutable=1"). */
sr_status sr_catalog_open(const char *path, unsigned flags, sr_catalog **out, sr_err *err);

/* Whether a write transaction can start: *readonly false after a BEGIN IMMEDIATE
 * that was rolled back at once, true when the handle is read-only, the file cannot
 * be written, or SQLite cannot write beside it (a read-only folder). Returns SR_OK in
 * both cases; another failure (busy after the timeout, I/O) is returned as a status
 * with err set and *readonly true. For a command to refuse before it spends time on
 * what it would record. */
sr_status sr_catalog_check_writable(sr_catalog *cat, bool *readonly, sr_err *err);

/* Creates a new catalogue in memory with every migration applied, so it holds only the
 * seeded rows of sql/ (parameter sets, repair rules, materials); it is gone when
 * closed. For work that needs the built-in defaults without a catalogue file (a --mesh
 * reconstruction's advice). sr_catalog_path gives ":memory:". *out only on success. */
sr_status sr_catalog_open_memory(sr_catalog **out, sr_err *err);

/* Closes; accepts NULL. */
void sr_catalog_close(sr_catalog *cat);

/* The schema version of the open file (PRAGMA user_version). */
int sr_catalog_schema_version(sr_catalog *cat);

/* The schema version the file had when this handle opened it, before the migrations
 * opening applied: 0 for a file opening created (or an empty one it filled), less
 * than sr_catalog_schema_version when it migrated the file, equal when it did not. */
int sr_catalog_schema_opened(sr_catalog *cat);

/* The file the catalogue was opened from. */
const char *sr_catalog_path(const sr_catalog *cat);

/* ---- parts (models) ---- */

typedef struct sr_part_info {
    int64_t id;
    char number[64];            /* the shop's part number, unique */
    char name[128];
    char material[64];          /* material name ("" if none) */
    char notes[512];
    int64_t mesh_id;            /* intact model mesh (0 if none) */
    size_t vertex_count, tri_count;
    double volume_mm3, area_mm2;
    double bbox_min[3], bbox_max[3];
    char source_unit[4];        /* unit the mesh file was drawn in ("mm", "cm", "m", "in";
                                 * "" without a mesh); the figures are mm whatever it was */
    char created_at[32];        /* UTC, ISO 8601 */
    int64_t instance_count;
    sr_symmetry symmetry;       /* part-level symmetry; kind SR_SYM_NONE if not set */
} sr_part_info;

typedef struct sr_part_new {
    const char *number;         /* required, 1..63 chars */
    const char *name;           /* required, 1..127 chars */
    const char *material;       /* optional; must be in the materials table (added there
                                 * with its density: sr_catalog_material_add) */
    const char *notes;          /* optional */
    const sr_mesh *mesh;        /* optional intact model (validated before storing) */
    const char *source_file;    /* optional: where the mesh came from */
    sr_unit source_unit;        /* the unit that file was drawn in (the mesh is mm);
                                 * SR_UNIT_DEFAULT = mm */
    sr_symmetry symmetry;       /* optional: kind SR_SYM_NONE = not set */
    int allow_open;             /* non-zero: store a mesh that is not a closed solid */
} sr_part_new;

/* Adds a part (and its mesh) in one transaction. SR_E_EXISTS if the number is taken.
 * A part's mesh is its intact model, so it must be a closed solid: every edge shared by
 * two triangles traversed in opposite directions, enclosing a positive volume. Any
 * other mesh is refused (SR_E_INVALID, the edge counts or the volume named) unless
 * allow_open is set. A material not in the catalogue is refused (SR_E_NOTFOUND "no
 * material 'X' in the catalogue"): it would have no density. */
sr_status sr_catalog_part_add(sr_catalog *cat, const sr_part_new *part, int64_t *out_id,
                              sr_err *err);

/* Finds a part by its number, or by its numeric id when no number matches `key`.
 * SR_E_NOTFOUND with "no part 'X' in the catalogue" otherwise. */
sr_status sr_catalog_part_find(sr_catalog *cat, const char *key, sr_part_info *out,
                               sr_err *err);

/* Filters for listing; NULL/zeroed fields match everything. name and number match as
 * case-insensitive substrings, material exactly (case-insensitive). */
typedef struct sr_part_filter {
    const char *name;
    const char *number;
    const char *material;
} sr_part_filter;

/* Calls fn for each matching part, ordered by number. fn returns non-zero to stop. */
typedef int (*sr_part_fn)(const sr_part_info *part, void *user);
sr_status sr_catalog_part_list(sr_catalog *cat, const sr_part_filter *filter, sr_part_fn fn,
                               void *user, sr_err *err);

/* Loads a part's intact mesh. SR_E_NOTFOUND if the part has none. */
sr_status sr_catalog_part_mesh(sr_catalog *cat, int64_t part_id, sr_mesh *out, sr_err *err);

/* Sets (replaces) the symmetry of a part. */
sr_status sr_catalog_part_set_symmetry(sr_catalog *cat, int64_t part_id,
                                       const sr_symmetry *sym, sr_err *err);

/* ---- damaged instances ---- */

typedef struct sr_instance_info {
    int64_t id;
    int64_t part_id;
    char part_number[64];
    char serial[64];
    char received[32];          /* date received, YYYY-MM-DD ("" if unknown) */
    char notes[512];
    int64_t mesh_id;
    size_t vertex_count, tri_count;
    double volume_mm3, area_mm2;
    double bbox_min[3], bbox_max[3];
    char source_unit[4]; /* unit the scan file was drawn in ("mm", "cm", "m", "in") */
    char created_at[32];
    sr_symmetry symmetry;       /* instance override, else the part's; NONE if neither */
} sr_instance_info;

typedef struct sr_instance_new {
    const char *part;           /* part number or id */
    const sr_mesh *mesh;        /* required: the damaged scan */
    const char *serial;         /* optional */
    const char *received;       /* optional YYYY-MM-DD; default today (UTC) */
    const char *notes;          /* optional */
    const char *source_file;    /* optional */
    sr_unit source_unit;        /* the unit that file was drawn in; SR_UNIT_DEFAULT = mm */
    sr_symmetry symmetry;       /* optional override; SR_SYM_NONE = use the part's */
} sr_instance_new;

sr_status sr_catalog_instance_add(sr_catalog *cat, const sr_instance_new *inst,
                                  int64_t *out_id, sr_err *err);

/* By numeric id. SR_E_NOTFOUND with "no instance N in the catalogue". */
sr_status sr_catalog_instance_get(sr_catalog *cat, int64_t id, sr_instance_info *out,
                                  sr_err *err);

/* Instances of one part (part = number or id), or all when part is NULL; by id. */
typedef int (*sr_instance_fn)(const sr_instance_info *inst, void *user);
sr_status sr_catalog_instance_list(sr_catalog *cat, const char *part, sr_instance_fn fn,
                                   void *user, sr_err *err);

sr_status sr_catalog_instance_mesh(sr_catalog *cat, int64_t instance_id, sr_mesh *out,
                                   sr_err *err);

/* ---- named parameter sets (sr_params and sr_params_check: run/run.h) ---- */

/* SR_E_NOTFOUND if there is no set of that name. "default" is seeded. */
sr_status sr_catalog_params_get(sr_catalog *cat, const char *name, sr_params *out,
                                sr_err *err);
/* Inserts or replaces a set (checked first). */
sr_status sr_catalog_params_put(sr_catalog *cat, const sr_params *p, sr_err *err);
typedef int (*sr_params_fn)(const sr_params *p, void *user);
sr_status sr_catalog_params_list(sr_catalog *cat, sr_params_fn fn, void *user, sr_err *err);

/* Loads any stored mesh by its id (meshes table). */
sr_status sr_catalog_mesh_load(sr_catalog *cat, int64_t mesh_id, sr_mesh *out, sr_err *err);

/* ---- additions (catalogue module) ---- */

/* Sets (replaces) the symmetry override of one instance; kind SR_SYM_NONE removes the
 * override, so the instance falls back to its part's symmetry. (Likewise kind
 * SR_SYM_NONE in sr_catalog_part_set_symmetry removes the part's symmetry.)
 * SR_E_NOTFOUND "no instance N in the catalogue"; SR_E_RANGE for a bad symmetry. */
sr_status sr_catalog_instance_set_symmetry(sr_catalog *cat, int64_t instance_id,
                                           const sr_symmetry *sym, sr_err *err);

/* ---- corrections: change or remove a part or an instance ---- */

/* What to change in a part; a field left NULL (set_symmetry false) is kept. Valid
 * when zeroed (changes nothing, which sr_catalog_part_set refuses). */
typedef struct sr_part_change {
    const char *number;   /* a new part number, 1..63 bytes, not taken */
    const char *name;     /* 1..127 bytes */
    const char *material; /* a material in the catalogue */
    const char *notes;    /* "" clears */
    bool set_symmetry;    /* true: `symmetry` replaces the part's (kind NONE clears) */
    sr_symmetry symmetry;
} sr_part_change;

/* Changes part `key` (number or id) in one transaction. SR_E_NOTFOUND for the part or
 * the material, SR_E_EXISTS for a number taken, SR_E_RANGE for a bad field,
 * SR_E_INVALID when `change` changes nothing. Runs keep what they recorded. */
sr_status sr_catalog_part_set(sr_catalog *cat, const char *key, const sr_part_change *change,
                              sr_err *err);

/* What to change in an instance; NULL keeps a field, "" clears it (serial and date
 * become unknown, notes empty). */
typedef struct sr_instance_change {
    const char *serial;   /* up to 63 bytes */
    const char *received; /* YYYY-MM-DD, a real date */
    const char *notes;    /* up to 511 bytes */
} sr_instance_change;

/* Changes instance `id` in one transaction. SR_E_NOTFOUND, SR_E_RANGE (bad date or
 * length, named), SR_E_INVALID when `change` changes nothing. */
sr_status sr_catalog_instance_set(sr_catalog *cat, int64_t id, const sr_instance_change *change,
                                  sr_err *err);

/* What a removal took, or would take, with it. */
typedef struct sr_removal {
    int64_t instances; /* instances removed (a part's) */
    int64_t runs;      /* runs removed, with their layers, sections and advice */
    int64_t meshes;    /* stored meshes that nothing refers to any more */
} sr_removal;

enum {
    SR_CATALOG_WITH_RUNS = 1, /* remove the instances and runs that refer to the row too */
};

/* Removes part `key` (number or id), or instance `id`, in one transaction, with its
 * symmetry and the meshes that only it (and what goes with it) referred to. While
 * instances or runs refer to the row it is refused unless flags has
 * SR_CATALOG_WITH_RUNS: SR_E_INVALID "part 'P' has 2 instances and 3 runs ..." and
 * nothing changes. With the flag they go too, and the history summary cells
 * (sql/004_history_summary.sql) lose exactly their runs. *out (may be NULL) says what
 * went, on success. SR_E_NOTFOUND for an unknown part or instance. */
sr_status sr_catalog_part_remove(sr_catalog *cat, const char *key, unsigned flags, sr_removal *out,
                                 sr_err *err);
sr_status sr_catalog_instance_remove(sr_catalog *cat, int64_t id, unsigned flags, sr_removal *out,
                                     sr_err *err);

/* ---- the file as a whole ---- */

/* Writes a consistent copy of the catalogue to `path` (SQLite's VACUUM INTO, inside
 * one read transaction, so writers elsewhere may go on), first to a temporary file
 * beside it, then moved into place. An existing `path` is refused (SR_E_EXISTS)
 * unless `force`, then replaced. Works on a read-only handle. */
sr_status sr_catalog_backup(sr_catalog *cat, const char *path, bool force, sr_err *err);

/* One problem found by sr_catalog_check: `what` is one line. */
typedef int (*sr_check_fn)(const char *what, void *user);

/* What sr_catalog_check read. */
typedef struct sr_check_info {
    int64_t application_id; /* PRAGMA application_id */
    int schema_version;     /* PRAGMA user_version */
    int64_t problems;       /* lines passed to fn */
    int64_t no_density;     /* materials without a density (older symrec made them); not
                             * a problem, but their deposit masses cannot be known */
} sr_check_info;

/* Checks the file: SQLite's integrity_check, foreign_key_check, the application id and
 * schema version, and symrec's own invariants (the history summary cells agree with
 * the runs they sum). Calls fn once per problem found (fn returns non-zero to stop).
 * Returns SR_OK when the checks could run, whatever they found (out->problems says);
 * an error status only when they could not. */
sr_status sr_catalog_check(sr_catalog *cat, sr_check_fn fn, void *user, sr_check_info *out,
                           sr_err *err);

/* Notes on the calls above:
 * - List callbacks run while the catalogue is being read: they may read (find, load a
 *   mesh) but must not write through the same handle.
 * - sr_catalog_params_list goes by name; sr_catalog_params_put matches an existing set
 *   by name ignoring ASCII case and then takes the new spelling.
 * - Part numbers, material and parameter set names are unique ignoring ASCII case.
 * - A handle is for one thread at a time; use one handle per thread or process. */

#endif
