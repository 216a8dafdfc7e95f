/*
 * test_mesh_units.c: the units and frame of mesh files (issue 18, item 3): a file read
 * in a stated unit is scaled to mm before the envelope is checked (mesh_io.h's
 * sr_mesh_read_units; the default is the format's own: mm for STL, metres for glTF),
 * and the glTF/GLB symrec writes means metres with Y up (one root node carrying scale
 * 0.001 and a -90 degree turn about X, marked in its extras), which symrec reads back to
 * the very mm, Z-up coordinates it wrote; a foreign glTF keeps its axes.
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

#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/json_query.h"
#include "support/read_expect.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

static const char *path_in(void **state, const char *name, char buf[TMPDIR_PATH_MAX])
{
    return tmpdir_join(*state, name, buf);
}

/* An axis-aligned box lo..hi written to path (format from its extension). */
static void write_box(const char *path, const double lo[3], const double hi[3])
{
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_shape_box(lo, hi, &m, &err), SR_OK);
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_OK);
    sr_mesh_release(&m);
}

static void read_ok(const char *path, sr_unit unit, sr_mesh *m)
{
    sr_err err = {{0}};
    sr_status st = sr_mesh_read_units(path, unit, m, &err);
    if (st != SR_OK)
        fail_msg("cannot read %s: %s", path, err.msg);
}

static void an_inch_stl_read_in_inches_is_in_mm(void **state)
{
    char path[TMPDIR_PATH_MAX];
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    write_box(path_in(state, "inch.stl", path), lo, hi);
    sr_mesh m = {0};
    read_ok(path, SR_UNIT_IN, &m);
    assert_near(sr_mesh_volume(&m), 16387.064, 1e-9); /* 25.4^3 mm³ */
    double bmin[3], bmax[3];
    sr_mesh_bbox(&m, bmin, bmax);
    for (int k = 0; k < 3; k++)
        assert_true(bmax[k] - bmin[k] == 25.4);
    sr_mesh_release(&m);
    /* the same file by default (mm, STL's unit): 1 mm³ */
    read_ok(path, SR_UNIT_DEFAULT, &m);
    assert_near(sr_mesh_volume(&m), 1.0, 1e-12);
    sr_mesh_release(&m);
}

static void a_cm_ply_read_in_cm_is_in_mm(void **state)
{
    char path[TMPDIR_PATH_MAX];
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 3, 4};
    write_box(path_in(state, "cm.ply", path), lo, hi);
    sr_mesh m = {0};
    read_ok(path, SR_UNIT_CM, &m);
    assert_near(sr_mesh_volume(&m), 24000.0, 1e-9); /* 20 x 30 x 40 mm */
    sr_mesh_release(&m);
}

static void formats_state_their_own_unit(void **state)
{
    (void)state;
    assert_int_equal(sr_format_unit(SR_FMT_GLTF), SR_UNIT_M);
    assert_int_equal(sr_format_unit(SR_FMT_GLB), SR_UNIT_M);
    assert_int_equal(sr_format_unit(SR_FMT_STL), SR_UNIT_MM);
    assert_int_equal(sr_format_unit(SR_FMT_OBJ), SR_UNIT_MM);
    assert_int_equal(sr_format_unit(SR_FMT_PLY), SR_UNIT_MM);
    assert_int_equal(sr_format_unit(SR_FMT_OFF), SR_UNIT_MM);
}

/* A foreign glTF (no symrec frame): one triangle (0,0,0) (0.05,0,0) (0,0.02,0) m, its
 * node moved 0.1 m along y, the buffer as a data URI. */
static void write_foreign_gltf(const char *path)
{
    const float p[9] = {0, 0, 0, 0.05f, 0, 0, 0, 0.02f, 0};
    const uint32_t idx[3] = {0, 1, 2};
    unsigned char b[48];
    memcpy(b, p, 36);
    memcpy(b + 36, idx, 12);
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char b64[65];
    for (int i = 0, o = 0; i < 48; i += 3, o += 4) {
        unsigned v = (unsigned)b[i] << 16 | (unsigned)b[i + 1] << 8 | b[i + 2];
        b64[o] = tab[v >> 18];
        b64[o + 1] = tab[(v >> 12) & 63];
        b64[o + 2] = tab[(v >> 6) & 63];
        b64[o + 3] = tab[v & 63];
    }
    b64[64] = 0;
    char text[2048];
    snprintf(
        text, sizeof text,
        "{\"asset\": {\"version\": \"2.0\", \"generator\": \"elsewhere\"},\n"
        " \"buffers\": [{\"uri\": \"data:application/octet-stream;base64,%s\","
        " \"byteLength\": 48}],\n"
        " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36},"
        " {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 12}],\n"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3,"
        " \"type\": \"VEC3\", \"min\": [0,0,0], \"max\": [0.05,0.02,0]},\n"
        "  {\"bufferView\": 1, \"componentType\": 5125, \"count\": 3, \"type\": \"SCALAR\"}],\n"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],\n"
        " \"nodes\": [{\"mesh\": 0, \"translation\": [0, 0.1, 0]}],\n"
        " \"scenes\": [{\"nodes\": [0]}], \"scene\": 0}\n",
        b64);
    assert_int_equal(tmpdir_write_text(path, text), 0);
}

static void a_foreign_gltf_is_read_in_metres_and_keeps_its_axes(void **state)
{
    char path[TMPDIR_PATH_MAX];
    write_foreign_gltf(path_in(state, "foreign.gltf", path));
    sr_mesh m = {0};
    read_ok(path, SR_UNIT_DEFAULT, &m);
    assert_int_equal(m.vertex_count, 3);
    /* 0.05 m along x, 0.02 m along y (Y stays Y), moved 0.1 m along y: in mm */
    assert_near(m.xyz[3], 50.0, 1e-5);
    assert_near(m.xyz[1], 100.0, 1e-5);
    assert_near(m.xyz[7], 120.0, 1e-5);
    assert_true(m.xyz[2] == 0 && m.xyz[5] == 0 && m.xyz[8] == 0);
    sr_mesh_release(&m);
    /* stated in mm, the numbers are taken as written */
    read_ok(path, SR_UNIT_MM, &m);
    assert_near(m.xyz[7], 0.12, 1e-8);
    sr_mesh_release(&m);
}

/* A part that is not symmetric under the turn (so a lost or doubled turn shows), with
 * coordinates float32 holds exactly (glTF stores float32). */
static void make_part(sr_mesh *m)
{
    const double lo[3] = {-12.5, 3.25, 0.125}, hi[3] = {40.75, 20.5, 61.0};
    sr_err err = {{0}};
    assert_int_equal(sr_shape_box(lo, hi, m, &err), SR_OK);
    /* shear the top so no axis swap maps it onto itself */
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->xyz[3 * v + 2] > 1)
            m->xyz[3 * v] += 7.5;
}

static void symrec_gltf_and_glb_read_back_the_same_mm_coordinates(void **state)
{
    sr_mesh part = {0};
    make_part(&part);
    const char *names[2] = {"part.glb", "part.gltf"};
    for (int i = 0; i < 2; i++) {
        char path[TMPDIR_PATH_MAX];
        sr_err err = {{0}};
        assert_int_equal(sr_mesh_write(path_in(state, names[i], path), &part, NULL, &err), SR_OK);
        sr_mesh back = {0};
        read_ok(path, SR_UNIT_DEFAULT, &back);
        assert_int_equal(back.vertex_count, part.vertex_count);
        assert_int_equal(back.tri_count, part.tri_count);
        for (size_t k = 0; k < 3 * part.vertex_count; k++)
            if (back.xyz[k] != part.xyz[k])
                fail_msg("%s: coordinate %zu is %.17g, wrote %.17g", names[i], k, back.xyz[k],
                         part.xyz[k]);
        assert_memory_equal(back.tri, part.tri, 3 * part.tri_count * sizeof *part.tri);
        sr_mesh_release(&back);

        /* sr_scene_read reads the same, by mesh */
        sr_scene sc = {0};
        assert_int_equal(sr_scene_read(path, &sc, &err), SR_OK);
        assert_int_equal(sc.count, 1);
        assert_memory_equal(sc.meshes[0].xyz, part.xyz, 3 * part.vertex_count * sizeof(double));
        sr_scene_release(&sc);
    }
    sr_mesh_release(&part);
}

/* The JSON chunk of a GLB file, NUL-terminated (the caller frees). */
static char *glb_json(const char *path)
{
    size_t n;
    unsigned char *b = tmpdir_read_file(path, &n);
    assert_non_null(b);
    assert_true(n > 20 && memcmp(b, "glTF", 4) == 0 && memcmp(b + 16, "JSON", 4) == 0);
    uint32_t len =
        (uint32_t)b[12] | (uint32_t)b[13] << 8 | (uint32_t)b[14] << 16 | (uint32_t)b[15] << 24;
    assert_true(20 + (size_t)len <= n);
    char *json = malloc(len + 1);
    assert_non_null(json);
    memcpy(json, b + 20, len);
    json[len] = 0;
    free(b);
    return json;
}

static void the_glb_root_node_turns_mm_z_up_into_metres_y_up(void **state)
{
    sr_mesh a = {0}, b = {0};
    make_part(&a);
    make_part(&b);
    const sr_scene_mesh meshes[2] = {{"damaged", &a, {0.5f, 0.5f, 0.5f, 1}},
                                     {"patch 1", &b, {0.1f, 0.7f, 0.9f, 1}}};
    char path[TMPDIR_PATH_MAX];
    sr_err err = {{0}};
    assert_int_equal(sr_scene_write(path_in(state, "scene.glb", path), meshes, 2, NULL, &err),
                     SR_OK);
    char *json = glb_json(path);
    assert_true(jq_valid(json));
    assert_int_equal(jq_len(json, "$.scenes[0].nodes"), 1);
    int root = (int)jq_num(json, "$.scenes[0].nodes[0]");
    char p[128];
    snprintf(p, sizeof p, "$.nodes[%d].scale", root);
    assert_int_equal(jq_len(json, p), 3);
    for (int k = 0; k < 3; k++) {
        snprintf(p, sizeof p, "$.nodes[%d].scale[%d]", root, k);
        assert_true(jq_num(json, p) == 0.001);
    }
    /* -90 degrees about X: x to x, y to -z, z to y */
    const double q[4] = {-sqrt(0.5), 0, 0, sqrt(0.5)};
    for (int k = 0; k < 4; k++) {
        snprintf(p, sizeof p, "$.nodes[%d].rotation[%d]", root, k);
        assert_near(jq_num(json, p), q[k], 1e-15);
    }
    snprintf(p, sizeof p, "$.nodes[%d].children", root);
    assert_int_equal(jq_len(json, p), 2);
    snprintf(p, sizeof p, "$.nodes[%d].extras.symrec_frame", root);
    char *frame = jq_text(json, p);
    assert_non_null(frame);
    assert_string_equal(frame, "children in mm, Z up");
    free(frame);
    /* the meshes themselves stay in mm: POSITION max of mesh 0 is the part's */
    assert_near(jq_num(json, "$.accessors[0].max[2]"), 61.0, 0);
    free(json);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void the_envelope_holds_in_mm_after_scaling(void **state)
{
    char path[TMPDIR_PATH_MAX];
    /* 2000 x 10 x 10: a fine mm part, but 2 km in metres (|coordinate| <= 1e6 mm) */
    const double lo[3] = {0, 0, 0}, hi[3] = {2000, 10, 10};
    write_box(path_in(state, "long.stl", path), lo, hi);
    sr_mesh m = {0};
    read_ok(path, SR_UNIT_MM, &m);
    sr_mesh_release(&m);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read_units(path, SR_UNIT_M, &m, &err), SR_E_INVALID);
    assert_has(err.msg, "coordinate x = 2e+06 is outside the physical envelope");
    assert_null(m.xyz);
    /* 0.0005 across: under the 1e-3 mm floor as mm, half a millimetre as metres */
    const double hi2[3] = {0.0005, 0.0004, 0.0003};
    write_box(path_in(state, "tiny.stl", path), lo, hi2);
    assert_int_equal(sr_mesh_read_units(path, SR_UNIT_MM, &m, &err), SR_E_INVALID);
    read_ok(path, SR_UNIT_M, &m);
    assert_near(sr_mesh_volume(&m), 0.5 * 0.4 * 0.3, 1e-8); /* float32 STL */
    sr_mesh_release(&m);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, tmpdir_setup, tmpdir_teardown)
    struct CMUnitTest tests[] = {
        T(an_inch_stl_read_in_inches_is_in_mm),
        T(a_cm_ply_read_in_cm_is_in_mm),
        T(formats_state_their_own_unit),
        T(a_foreign_gltf_is_read_in_metres_and_keeps_its_axes),
        T(symrec_gltf_and_glb_read_back_the_same_mm_coordinates),
        T(the_glb_root_node_turns_mm_z_up_into_metres_y_up),
        T(the_envelope_holds_in_mm_after_scaling),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
