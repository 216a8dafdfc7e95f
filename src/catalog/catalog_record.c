/*
 * catalog_record.c: the catalogue side of recording a run (catalog_record.h): reads the
 * enabled rules and the part's material, lets the pure rule engine describe and advise
 * the run (advice/rules.h), and stores it (catalog_runs.h). No SQL of its own: every
 * statement is the other catalogue files'.
 */
#include "catalog/catalog_record.h"

#include <stdlib.h>

#include "advice/rules.h"
#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"

sr_status sr_catalog_advise_run(sr_catalog *cat, const char *material, double part_volume_mm3,
                                sr_run *run, sr_err *err)
{
    sr_rule *rules = NULL;
    size_t rule_count = 0;
    sr_material info;
    const sr_material *known = NULL;
    sr_status st = sr_catalog_rule_load(cat, true, &rules, &rule_count, err);
    if (st == SR_OK && material && *material) {
        st = sr_catalog_material_get(cat, material, &info, err);
        if (st == SR_OK) {
            known = &info;
        } else if (st == SR_E_NOTFOUND) {
            sr_err_clear(err);
            st = SR_OK;
        }
    }
    if (st == SR_OK)
        st = sr_advise_run(rules, rule_count, material, known, part_volume_mm3, run, err);
    free(rules);
    return st;
}

sr_status sr_catalog_run_describe(sr_catalog *cat, sr_run *run, sr_err *err)
{
    if (run->instance_id == 0)
        return sr_catalog_advise_run(cat, NULL, 0, run, err);
    sr_instance_info inst;
    sr_part_info part;
    sr_status st = sr_catalog_instance_get(cat, run->instance_id, &inst, err);
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, inst.part_number, &part, err);
    if (st != SR_OK)
        return st;
    return sr_catalog_advise_run(cat, part.material, part.mesh_id ? part.volume_mm3 : 0, run,
                                 err);
}

sr_status sr_catalog_run_record(sr_catalog *cat, sr_run *run, int64_t *out_id, sr_err *err)
{
    sr_status st = sr_catalog_run_describe(cat, run, err);
    if (st != SR_OK)
        return st;
    return sr_catalog_run_add(cat, run, out_id, err);
}
