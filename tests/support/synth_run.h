/*
 * synth_run.h: run records built inline for the feature and rule tests: a layer grid
 * of `layers` layers 1 mm apart (layer l at z = l + 0.5, so the part spans z 0..layers)
 * and `sectors` equal sectors, whose restored outline is a circle of radius r_low below
 * z = z_step and r_high from it (a shaft with a shoulder), and whose damaged outline is
 * the restored one with sections dug out. Each dug section's figures (range, depth,
 * volume by the cell formula of patch.h) are exact.
 */
#ifndef SR_TEST_SYNTH_RUN_H
#define SR_TEST_SYNTH_RUN_H

#include <stddef.h>

#include "catalog/catalog_runs.h"

/* A run with the grid above and no sections; the caller frees with synth_run_free. */
void synth_run_make(sr_run *run, size_t layers, size_t sectors, double r_low, double r_high,
                    double z_step);

/* Digs a section: layers l0..l1, sectors j0 .. j0 + count - 1 (wrapping), each cell's
 * damaged radius = restored - depth (no point when depth >= restored). planar_side 0:
 * an axial section with its angular range; +1/-1: a planar section on that side (no
 * angles). Appends the section (index = its order) and returns it. */
sr_run_section *synth_run_dig(sr_run *run, size_t l0, size_t l1, size_t j0, size_t count,
                              double depth, int planar_side);

/* The first advice for section i of `run` (-1: the whole part); NULL if there is
 * none. */
const sr_run_advice *synth_run_advice_for(const sr_run *run, long i);

/* Frees everything synth_run_make/dig allocated and what the code under test put in
 * (features_json, advice details). */
void synth_run_free(sr_run *run);

#endif
