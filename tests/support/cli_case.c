/*
 * cli_case.c: running symrec and checking its result for the CLI test files (see
 * cli_case.h).
 */
#include "support/cli_case.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog.h"
#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "mesh/shapes.h"
#include "support/run_cmd.h"
#include "support/synth_run.h"

void cli_case_run_under(cli_result *r, const char *const *prefix, const char *const *words)
{
    const char *argv[64];
    size_t n = 0;
    for (size_t i = 0; prefix && prefix[i]; i++) {
        assert_true(n < 62);
        argv[n++] = prefix[i];
    }
    argv[n++] = sr_test_bin();
    for (size_t i = 0; words[i]; i++) {
        assert_true(n < 63);
        argv[n++] = words[i];
    }
    argv[n] = NULL;
    r->code = prefix ? sr_test_run_native(argv, NULL, &r->out, &r->err)
                     : sr_test_run(argv, NULL, &r->out, &r->err);
    if (r->code < 0)
        fail_msg("cannot run %s (set SYMREC_BIN)", argv[0]);
}

void cli_case_run(cli_result *r, const char *const *words)
{
    cli_case_run_under(r, NULL, words);
}

void cli_result_free(cli_result *r)
{
    free(r->out);
    free(r->err);
    r->out = r->err = NULL;
}

void cli_expect_ok(const cli_result *r)
{
    if (r->code != 0)
        fail_msg("expected success, got exit %d; stderr: %s", r->code, r->err);
}

void cli_expect_error(const cli_result *r, const char *needle)
{
    if (r->code != 1)
        fail_msg("expected exit 1, got %d; stderr: %s", r->code, r->err);
    static const char prefix[] = "symrec: error: ";
    if (strncmp(r->err, prefix, sizeof prefix - 1) != 0)
        fail_msg("stderr does not start with '%s': %s", prefix, r->err);
    const char *nl = strchr(r->err, '\n');
    if (!nl || nl[1] != '\0')
        fail_msg("stderr is not exactly one line: %s", r->err);
    if (needle && !strstr(r->err, needle))
        fail_msg("stderr lacks '%s': %s", needle, r->err);
    assert_string_equal(r->out, "");
}

void cli_expect_contains(const char *haystack, const char *needle)
{
    if (!strstr(haystack, needle))
        fail_msg("'%s' not found in: %s", needle, haystack);
}

bool cli_path_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int cli_path_mode(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0 ? (int)(st.st_mode & 07777) : -1;
}

void cli_case_synth_catalogue(const char *db, const char *serial, const char *material,
                              const char *mesh_path)
{
    sr_mesh m;
    sr_mesh_init(&m);
    assert_int_equal(sr_shape_cylinder(10.0, 0.0, 12.0, 32, &m, NULL), SR_OK);
    if (mesh_path)
        assert_int_equal(sr_mesh_write(mesh_path, &m, NULL, NULL), SR_OK);
    sr_catalog *cat = NULL;
    sr_err err;
    sr_err_clear(&err);
    int64_t id;
    assert_int_equal(sr_catalog_open(db, SR_CATALOG_CREATE, &cat, &err), SR_OK);
    sr_material known;
    if (material && sr_catalog_material_get(cat, material, &known, &err) == SR_E_NOTFOUND) {
        sr_material_new mat = {.name = material, .density_g_cm3 = 7.85, .family = "steel"};
        if (sr_catalog_material_add(cat, &mat, NULL, &err) != SR_OK)
            fail_msg("cannot add material '%s': %s", material, err.msg);
    }
    sr_part_new part = {.number = "P1",
                        .name = "shaft",
                        .material = material,
                        .mesh = &m,
                        .symmetry = {SR_SYM_AXIAL, 0, 0}};
    if (sr_catalog_part_add(cat, &part, &id, &err) != SR_OK)
        fail_msg("cannot add the part: %s", err.msg);
    sr_instance_new inst = {.part = "P1", .mesh = &m, .serial = serial};
    if (sr_catalog_instance_add(cat, &inst, &id, &err) != SR_OK)
        fail_msg("cannot add the instance: %s", err.msg);
    sr_run run;
    synth_run_make(&run, 12, 72, 10.0, 10.0, 0.0);
    run.instance_id = id;
    run.has_alignment = 1;
    run.alignment[0] = run.alignment[5] = run.alignment[10] = 1; /* 3x4, identity */
    run.fit_quality = 0.9;
    synth_run_dig(&run, 1, 10, 2, 8, 2.0, 0);
    synth_run_dig(&run, 4, 6, 30, 8, 2.0, 0);
    assert_int_equal(sr_catalog_params_get(cat, "default", &run.params, &err), SR_OK);
    run.params.layers = 12;
    run.params.sectors = 72;
    if (sr_catalog_run_add(cat, &run, &id, &err) != SR_OK)
        fail_msg("cannot add the run: %s", err.msg);
    synth_run_free(&run);
    sr_catalog_close(cat);
    sr_mesh_release(&m);
}
