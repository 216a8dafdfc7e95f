/*
 * catalog_runs.h: the record of reconstruction runs in the catalogue (tables runs,
 * run_layers, sections, advice of sql/001_init.sql): what was run (instance, symmetry,
 * every parameter, method, version), what was found (alignment, per-layer polyline
 * pairs, missing sections with their features and patch meshes, the restored mesh),
 * what the rules advised, and how long each phase took.
 *
 * The run record itself (sr_run, sr_run_section, sr_run_advice, sr_run_release) is the
 * core's, in run/run.h; this module stores it. A run is written in one transaction
 * (all rows or none) and read back whole or as a summary for listings. The structs own
 * their heap fields once they come from sr_catalog_run_get (free with sr_run_release);
 * for sr_catalog_run_add the caller's arrays are only read.
 */
#ifndef SR_CATALOG_RUNS_H
#define SR_CATALOG_RUNS_H

#include <stddef.h>
#include <stdint.h>

#include "catalog/catalog.h"
#include "run/run.h"
#include "mesh/mesh.h"
#include "base/status.h"
#include "base/symmetry.h"

/* Writes the whole run (run row, layers, sections with patch meshes, advice, restored
 * mesh) in one transaction. Checks fields first (SR_E_RANGE naming the field);
 * SR_E_NOTFOUND if the instance does not exist. *out_id only on success. */
sr_status sr_catalog_run_add(sr_catalog *cat, const sr_run *run, int64_t *out_id,
                             sr_err *err);

enum {
    SR_RUN_WITH_LAYERS = 1,     /* read the per-layer polylines */
    SR_RUN_WITH_MESHES = 2,     /* read the patch meshes and the restored mesh */
};

/* Reads run `id` back (sections and advice always; layers/meshes by `what`).
 * SR_E_NOTFOUND "no run N in the catalogue". Release with sr_run_release.
 * Without SR_RUN_WITH_LAYERS, layer_count and sectors are 0 and the arrays NULL (the
 * grid size as run is in params); without SR_RUN_WITH_MESHES the patch and restored
 * meshes are empty. A section's patch or the restored mesh is empty too when the run
 * kept none. fit_quality < 0 and has_alignment 0 read back as stored (NULL). */
sr_status sr_catalog_run_get(sr_catalog *cat, int64_t id, unsigned what, sr_run *out,
                             sr_err *err);

/* One line of a listing. */
typedef struct sr_run_summary {
    int64_t id, instance_id;
    char part_number[64];
    char serial[64];
    char material[64];
    sr_symmetry symmetry;
    char method[16];
    int ok;
    char started_at[32];
    size_t section_count;
    double missing_volume_mm3;  /* sum of the sections' volumes */
    char process[64];           /* the advice for the largest section ("" = none) */
    size_t unbuilt_sections;    /* found missing, no closed patch built (run_unbuilt) */
} sr_run_summary;

typedef struct sr_run_filter {
    int64_t instance_id;        /* 0 = any */
    const char *part;           /* part number or id; NULL = any */
} sr_run_filter;

/* Calls fn for each matching run, newest first. fn returns non-zero to stop. */
typedef int (*sr_run_fn)(const sr_run_summary *run, void *user);
sr_status sr_catalog_run_list(sr_catalog *cat, const sr_run_filter *filter, sr_run_fn fn,
                              void *user, sr_err *err);

/* Number of runs in the catalogue (for `catalog info`). */
sr_status sr_catalog_run_count(sr_catalog *cat, int64_t *out, sr_err *err);

/* ---- additions (runs module) ---- */

/* Loads only the restored mesh of run `id` (for `compare run:N`). SR_E_NOTFOUND "no run
 * N in the catalogue" or "run N has no restored mesh in the catalogue". *out only on
 * success. */
sr_status sr_catalog_run_restored_mesh(sr_catalog *cat, int64_t id, sr_mesh *out,
                                       sr_err *err);

/* Notes on sr_catalog_run_add:
 * - Field checks: instance_id > 0; a symmetry kind; params pass sr_params_check;
 *   method 1..15 bytes; alignment finite; fit_quality <= 1 (< 0 stored as NULL); a
 *   failed run (ok 0) needs its error; finished_at not before started_at; the JSON
 *   texts valid JSON; layers with their three arrays; sections with distinct indices,
 *   layer_first <= layer_last, z_min <= z_max, angles in [0, 360) with from <= to <=
 *   from + 360, side -1/0/1, finite non-negative figures, damage_class non-empty;
 *   advice naming a section of the run (or -1) and a non-empty process. Meshes must
 *   pass sr_mesh_validate (SR_E_INVALID naming "patch of section N" or "restored
 *   mesh"). All of these are refused before the transaction starts.
 * - Inside the transaction: SR_E_NOTFOUND for an unknown instance or rule_id; any
 *   failure rolls back every row of the run (meshes included).
 * - started_at "" is stored as the time of writing; software_version "" as SR_VERSION;
 *   side 0 and has_angles 0 as NULL columns; rule_id 0 as NULL. */

#endif
