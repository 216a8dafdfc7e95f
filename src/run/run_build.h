/*
 * run_build.h: turns one reconstruction (reconstruct.h's sr_recon_result) into the run
 * record (run/run.h's sr_run, which the catalogue stores): what was asked (instance,
 * symmetry, parameter set, method), the alignment and its fit, the per-layer polyline
 * pairs of the paper (Polylines(0,.) the damaged outline, Polylines(1,.) the restored
 * one), the missing sections with copies of their patch meshes, a copy of the restored
 * mesh and the timings. Pure C, no I/O, no SQLite: the caller records it with
 * sr_catalog_run_record (catalog_record.h: features, advice, then the record).
 *
 * Sections leave here with damage_class "unclassified", no features_json and no
 * advice: the classifier and the rules engine fill those before the run is stored.
 */
#ifndef SR_RUN_BUILD_H
#define SR_RUN_BUILD_H

#include <stdint.h>

#include "run/run.h"
#include "nominal.h"
#include "reconstruct.h"

/* Builds *out (heap-owned, free with sr_run_release) from `result`, which is only
 * read. `sym` is the symmetry as asked; the run records it as used (a glide's shift is
 * the one the analysis applied). `params` is the parameter set as used: its values are
 * copied, with layers and sectors taken from the result's grid. `method` is 1..15
 * bytes ("paper", "robust"). Layers: layer_count = grid layers, sectors = grid
 * sectors; the damaged point of a cell is the grid's farthest point (x, y), NaN, NaN
 * when the sector has no surface point; the restored point is the damaged point where
 * the cell is not damaged, else the point at the restored radius on the sector's
 * centre angle (sr_sector_angle), as analyse.h restores it. Sections: index i in the
 * result's order (largest first); axial sections carry the arc [from, to) in degrees
 * with to = from + arc (so it may exceed 360; a full ring is 0..360); planar sections
 * carry side +1 when the arc's middle lies on the side the plane normal (canonical
 * +x, turned by the plane angle found) points to, else -1. fit_quality is the
 * alignment's fit_score; started_at = finished_at - total time, finished_at = now (UTC).
 * ok = 1, software_version = SR_VERSION, timings_json {"align":s,"slice":s,
 * "analyse":s,"patch":s,"union":s,"total":s}. SR_E_RANGE for a bad method or
 * a result whose grid and analysis disagree; SR_E_NOMEM. *out only on success. */
sr_status sr_run_from_result(const sr_recon_result *result, int64_t instance_id,
                             const sr_symmetry *sym, const sr_params *params,
                             const char *method, sr_run *out, sr_err *err);

/* The nominal's second opinion (nominal.h) as the run records it (run/run_nominal.c):
 * the figures copied, each kept piece's volume, thickness, section, share near no section and centroid.
 * reference is "symmetry" or "nominal" (SR_E_RANGE otherwise). *out (heap, free with
 * sr_run_nominal_free, or with the run once set as run->nominal) only on success. */
sr_status sr_run_nominal_from(const sr_nominal_result *nr, const char *reference,
                              sr_run_nominal **out, sr_err *err);

/* The current time as UTC ISO 8601 'YYYY-MM-DDTHH:MM:SSZ' (the catalogue's format),
 * offset by `offset_s` seconds (negative = earlier). */
void sr_run_utc_time(double offset_s, char out[32]);

#endif
