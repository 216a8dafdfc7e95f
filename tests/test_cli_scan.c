/*
 * test_cli_scan.c: `reconstruct` of an open scan through the CLI (cli/scan_out.c,
 * src/mesh/scan_close.c): a tube (radii 20 and 6, z 0..30, 64 sides) with a chip in its
 * top two thirds (radius 16 over 0.6 rad from z 20 up, tapering from z 10), written
 * without the face it stood on (z = 0: two rims, the outer and the bore's, one plane).
 * Known answers: the base is a scan gap, closed in its plane and recorded as such
 * (scan_gaps: 2 gaps, 'plane', 64 edges each, the outer one 2 * 64 * 20 sin(pi/64) mm
 * of rim), not a section; the one section is the chip, its volume within 10 % of the
 * chip's exact volume (intact - damaged, both closed meshes built here); the restored
 * part written is closed (`check` finds no boundary edge). One reconstruction: the case
 * stays out of `make valgrind` (its name matches VALGRIND_SKIP's
 * reconstruct_of_a_mesh_file_*).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "mesh/shapes.h"
#include "support/json_query.h"
#include "support/run_cmd.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

#define CHIP_RAD 0.6

static double outer(double theta, size_t ring, void *user)
{
    bool chipped = *(const bool *)user;
    if (!chipped || theta >= CHIP_RAD || ring < 1)
        return 20;
    return ring == 1 ? 20 : 16; /* rings at z 0, 10, 20, 30: the chip from 20 up */
}

static double inner(double theta, size_t ring, void *user)
{
    (void)theta, (void)ring, (void)user;
    return 6;
}

static void tube(bool chipped, sr_mesh *out)
{
    static const double z[4] = {0, 10, 20, 30};
    sr_revolve_opts o = {0};
    o.segments = 64;
    o.ring_count = 4;
    o.ring_z = z;
    o.outer = outer;
    o.inner = inner;
    o.user = &chipped;
    assert_int_equal(sr_shape_revolve(&o, out, NULL), SR_OK);
}

/* Writes m as OBJ without the triangles lying at z = 0. */
static void write_open_obj(const sr_mesh *m, const char *path)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    for (size_t v = 0; v < m->vertex_count; v++)
        fprintf(f, "v %.17g %.17g %.17g\n", m->xyz[3 * v], m->xyz[3 * v + 1], m->xyz[3 * v + 2]);
    size_t dropped = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        const uint32_t *c = m->tri + 3 * t;
        if (m->xyz[3 * c[0] + 2] == 0 && m->xyz[3 * c[1] + 2] == 0 && m->xyz[3 * c[2] + 2] == 0) {
            dropped++;
            continue;
        }
        fprintf(f, "f %u %u %u\n", c[0] + 1, c[1] + 1, c[2] + 1);
    }
    assert_int_equal(fclose(f), 0);
    assert_int_equal(dropped, 128); /* the annulus: two triangles per side */
}

static void reconstruct_of_a_mesh_file_open_scan_keeps_the_gaps_apart(void **state)
{
    (void)state;
    sr_mesh intact, damaged;
    tube(false, &intact);
    tube(true, &damaged);
    double chip = sr_mesh_volume(&intact) - sr_mesh_volume(&damaged);
    assert_true(chip > 700 && chip < 820); /* 760.6 mm³ */
    tmpdir dir;
    assert_int_equal(tmpdir_make(&dir), 0);
    char scan[TMPDIR_PATH_MAX], out[TMPDIR_PATH_MAX], restored[TMPDIR_PATH_MAX];
    tmpdir_join(&dir, "scan.obj", scan);
    tmpdir_join(&dir, "out", out);
    write_open_obj(&damaged, scan);
    const char *bin = sr_test_bin();
    char *o = NULL, *e = NULL;
    int code = sr_test_run((const char *[]){bin, "reconstruct", "--mesh", scan, "--symmetry",
                                            "axial", "--out", out, "--json", NULL},
                           NULL, &o, &e);
    if (code != 0)
        fail_msg("reconstruct failed (%d): %s", code, e);
    assert_int_equal(jq_len(o, "$.scan_gaps.gaps"), 2);
    for (int i = 0; i < 2; i++) {
        char path[64], *by;
        snprintf(path, sizeof path, "$.scan_gaps.gaps[%d].closed_by", i);
        by = jq_text(o, path);
        assert_string_equal(by, "plane");
        free(by);
        snprintf(path, sizeof path, "$.scan_gaps.gaps[%d].edges", i);
        assert_true(jq_num(o, path) == 64);
    }
    assert_true(fabs(jq_num(o, "$.scan_gaps.gaps[0].length_mm") - 128 * 20 * sin(M_PI / 64)) <
                1e-9);
    assert_int_equal(jq_len(o, "$.sections"), 1);
    double got = jq_num(o, "$.sections[0].volume_mm3");
    if (!(fabs(got - chip) <= 0.1 * chip))
        fail_msg("the section holds %.1f mm³, the chip %.1f mm³", got, chip);
    free(o);
    free(e);
    tmpdir_join(&dir, "out/restored.stl", restored);
    code = sr_test_run((const char *[]){bin, "check", restored, "--json", NULL}, NULL, &o, &e);
    assert_int_equal(code, 0);
    assert_true(jq_num(o, "$.scan.boundary_edges") == 0);
    free(o);
    free(e);
    tmpdir_remove(&dir);
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(reconstruct_of_a_mesh_file_open_scan_keeps_the_gaps_apart),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
