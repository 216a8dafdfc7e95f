/*
 * catalog_record.h: the catalogue side of recording a run, the one place where the
 * features, the advice and the record of a run meet the catalogue: the rule engine
 * (advice/rules.h) is pure and takes its rules and material as rows, and this module
 * reads those rows (the enabled repair rules, the part's material with its process
 * limits) from the catalogue, hands them in, and stores the described run.
 *
 * Every caller that records or shows a run's advice goes through here alike
 * (`symrec reconstruct`, and `symrec demo` through it, and the tests), so a recorded
 * run and an unrecorded one (a --mesh run) are described and advised the same way.
 * A run with no catalogue file to hand takes the seeded rules of sql/ from a
 * catalogue in memory (sr_catalog_open_memory, catalog.h).
 */
#ifndef SR_CATALOG_RECORD_H
#define SR_CATALOG_RECORD_H

#include <stdint.h>

#include "catalog/catalog.h"
#include "run/run.h"
#include "base/status.h"

/* Describes every section of `run` and replaces its advice (advice/rules.h's
 * sr_advise_run) from the catalogue's enabled rules and the material named `material`
 * (NULL or "" = none; a name the catalogue does not know is kept as the material's
 * name with family and limits unknown). part_volume_mm3 <= 0 = unknown. All or
 * nothing: on failure the run is as it was. */
sr_status sr_catalog_advise_run(sr_catalog *cat, const char *material, double part_volume_mm3,
                                sr_run *run, sr_err *err);

/* sr_catalog_advise_run for the part of the run's instance: its material, and its
 * intact volume when the part has a mesh. run->instance_id 0 = no instance (a mesh
 * file): no material, part volume unknown. SR_E_NOTFOUND when the instance is not in
 * the catalogue. The run is only read from the catalogue, never written: a read-only
 * or in-memory catalogue will do. All or nothing. */
sr_status sr_catalog_run_describe(sr_catalog *cat, sr_run *run, sr_err *err);

/* Features + advice + record: sr_catalog_run_describe, then sr_catalog_run_add (one
 * transaction). The run is left described (sections' damage_class and features_json,
 * the advice), so the caller can show what was stored. *out_id only on success; on a
 * failure to store the run keeps its description. */
sr_status sr_catalog_run_record(sr_catalog *cat, sr_run *run, int64_t *out_id, sr_err *err);

#endif
