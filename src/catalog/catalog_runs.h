/*
 * catalog_runs.h: the record of reconstruction runs in the catalogue (tables runs,
 * run_layers, sections, advice of sql/001_init.sql): what was run (instance, symmetry,
 * every parameter, method, version), what was found (alignment, per-layer polyline
 * pairs, missing sections with their features and patch meshes, the restored mesh),
 * what the rules advised, and how long each phase took.
 *
 * A run is written in one transaction (all rows or none) and read back whole or as a
 * summary for listings. The structs own their heap fields once they come from
 * sr_catalog_run_get (free with sr_run_release); for sr_catalog_run_add the caller's
 * arrays are only read.
 */
#ifndef SR_CATALOG_RUNS_H
#define SR_CATALOG_RUNS_H

#include <stddef.h>
#include <stdint.h>

#include "catalog/catalog.h"
#include "mesh/mesh.h"
#include "base/status.h"
#include "base/symmetry.h"

/* One missing section of a run, with its feature-level description. */
typedef struct sr_run_section {
    int64_t id;                 /* row id (read back; ignored by add) */
    size_t index;               /* 0 first (largest volume) */
    size_t layer_first, layer_last;
    double z_min_mm, z_max_mm;  /* aligned frame */
    int has_angles;             /* axial: 1, with the angular range below */
    double angle_from_deg;      /* [0, 360) */
    double angle_to_deg;        /* counter-clockwise end, may exceed 360 when wrapping */
    int side;                   /* planar: +1 / -1 side of the plane; 0 for axial */
    double volume_mm3, area_mm2, depth_max_mm, depth_mean_mm;
    char damage_class[32];      /* 'chip', 'gouge', 'wear_band', 'broken_feature', 'crack' ... */
    char *features_json;        /* further features as one JSON object; NULL = none */
    sr_mesh patch;              /* closed patch, scan frame; empty (0 triangles) = not kept */
} sr_run_section;

/* One piece of advice: for a section (section_index >= 0) or the whole part (-1). */
typedef struct sr_run_advice {
    long section_index;
    int64_t rule_id;            /* the rule that gave it; 0 = none (built in / deleted) */
    char rule_name[64];         /* read back (from the rule row, "" when gone) */
    char process[64];           /* 'spray_forming', 'ded', 'weld_buildup', 'replace', ... */
    char reason[512];
    char *details_json;         /* the plan and the rules fired, one JSON object; NULL = {} */
} sr_run_advice;

typedef struct sr_run {
    int64_t id;                 /* read back; ignored by add */
    int64_t instance_id;        /* required */
    char part_number[64];       /* read back */
    sr_symmetry symmetry;       /* as used (glide: the shift found) */
    sr_params params;           /* every parameter as used, with the set's name */
    char method[16];            /* 'paper' or 'robust' */
    int has_alignment;          /* 0 when the run failed before aligning */
    double alignment[12];       /* scan -> aligned frame, 3x4 row-major (mesh.h) */
    int alignment_given;        /* 1 = set by the user */
    double fit_quality;         /* 0..1; < 0 = not reached */
    int ok;                     /* 1 ok, 0 failed (then error says why) */
    char error[512];
    char software_version[32];  /* SR_VERSION */
    char started_at[32], finished_at[32]; /* UTC ISO 8601; finished "" = did not finish */
    char *timings_json;         /* {"align":0.1,...} seconds; NULL = none */

    size_t layer_count, sectors;
    double *layer_z;            /* layer_count heights, aligned frame */
    double *damaged_xy;         /* layer_count x sectors x (x, y); NaN = no point */
    double *restored_xy;        /* same shape */

    sr_run_section *sections;
    size_t section_count;
    sr_run_advice *advice;
    size_t advice_count;
    sr_mesh restored;           /* scan frame; empty = none */
} sr_run;

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

/* Frees the heap fields of a run read by sr_catalog_run_get (and zeroes it). */
void sr_run_release(sr_run *run);

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
