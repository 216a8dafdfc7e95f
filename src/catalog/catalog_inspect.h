/*
 * catalog_inspect.h: inspections of repaired parts in the catalogue (tables
 * inspections, inspection_sections of sql/009_inspection.sql; the figures are
 * inspect/inspect.h's sr_inspect_result). Each inspection is added in one
 * transaction with its scan and never changed; a run's outcome is its latest
 * inspection's verdict, which `run show`, `history` and the summaries show.
 */
#ifndef SR_CATALOG_INSPECT_H
#define SR_CATALOG_INSPECT_H

#include <stdbool.h>
#include <stdint.h>

#include "base/status.h"
#include "catalog/catalog.h"
#include "inspect/inspect.h"
#include "mesh/mesh.h"

/* Records inspection `r` of run `run_id` with the scan as read (`scan`, its own
 * frame; NULL = not kept; source_file may be NULL) in one transaction. SR_E_NOTFOUND
 * "no run N in the catalogue"; SR_E_VERSION when the catalogue predates schema 9 (a
 * read-only one that was not migrated). *out_id (may be NULL) only on success. */
sr_status sr_catalog_inspection_add(sr_catalog *cat, int64_t run_id, const sr_mesh *scan,
                                    const char *source_file, const sr_inspect_result *r,
                                    int64_t *out_id, sr_err *err);

/* One inspection as stored (its sections' figures are not read here). */
typedef struct sr_inspection_info {
    int64_t id, run_id;
    int64_t scan_mesh_id; /* 0 = not kept */
    char verdict[8];      /* "pass", "machine", "rework" */
    char reasons[512];
    double allowance_mm, tolerance_mm;
    int registered;
    double coverage;
    size_t section_count;
    char inspected_at[32];
    double transform[12]; /* scan -> restored model frame (3x4 row-major) */
} sr_inspection_info;

/* The latest inspection of run `run_id` into *out and *found true; *found false when
 * the run has none (or the catalogue predates schema 9). The run is not checked. */
sr_status sr_catalog_inspection_latest(sr_catalog *cat, int64_t run_id, sr_inspection_info *out,
                                       bool *found, sr_err *err);

/* The per-section figures of inspection `id` (sr_inspect_section, reasons included),
 * by section index, into *out (heap, free(); NULL when none) and *count. SR_E_NOMEM;
 * an inspection without rows gives none. */
sr_status sr_catalog_inspection_sections(sr_catalog *cat, int64_t id, sr_inspect_section **out,
                                         size_t *count, sr_err *err);

#endif
