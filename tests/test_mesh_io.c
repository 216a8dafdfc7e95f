/*
 * test_mesh_io.c: reading and writing mesh files (src/bridge/mesh_io_api.cpp and the
 * byte checks of src/io/). Every input file is written by the test itself into a
 * fresh temporary directory: a closed octahedron with unround coordinates goes through
 * every format and must come back with the same vertices, triangles and volume; then
 * one case per kind of bad input, each asserting the status and the message.
 */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <cmocka.h>

#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "support/assert_near.h"
#include "support/read_expect.h"
#include "support/tmpdir.h"

/* ---- fixtures ---------------------------------------------------------------------- */

/* Octahedron with half-axes A, B, C around (CX, CY, CZ): 6 vertices, 8 outward
 * triangles, volume 4/3 A B C. The coordinates are not exact in float or in decimal. */
#define A 1.1
#define B 2.3
#define C 0.7
#define CX 0.1
#define CY 0.2
#define CZ (1.0 / 3.0)
static const uint32_t octa_tri[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                        {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

static void make_octa(sr_mesh *m)
{
    const double v[6][3] = {{CX + A, CY, CZ}, {CX - A, CY, CZ}, {CX, CY + B, CZ},
                            {CX, CY - B, CZ}, {CX, CY, CZ + C}, {CX, CY, CZ - C}};
    assert_int_equal(sr_mesh_alloc(m, 6, 8), SR_OK);
    memcpy(m->xyz, v, sizeof v);
    memcpy(m->tri, octa_tri, sizeof octa_tri);
}

static double octa_volume(void)
{
    return 4.0 / 3.0 * A * B * C;
}

/* Each test gets its own directory (cmocka state: tmpdir_setup). */
static const char *path_in(void **state, const char *name, char buf[TMPDIR_PATH_MAX])
{
    return tmpdir_join(*state, name, buf);
}

/* ---- binary STL built by hand ------------------------------------------------------- */

static void put_f32(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(u >> (8 * i));
}

/* Binary STL of the octahedron's 8 triangles with header text `head` and header count
 * `count`, followed by `extra` zero bytes; returns its size. buf holds >= 84+400+extra. */
static size_t octa_stl_binary(unsigned char *buf, const char *head, uint32_t count, size_t extra)
{
    sr_mesh m;
    make_octa(&m);
    memset(buf, 0, 84 + 400 + extra);
    memcpy(buf, head, strlen(head));
    for (int i = 0; i < 4; i++)
        buf[80 + i] = (unsigned char)(count >> (8 * i));
    for (int t = 0; t < 8; t++) {
        unsigned char *rec = buf + 84 + 50 * t;
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                put_f32(rec + 12 + 12 * k + 4 * j, (float)m.xyz[3 * m.tri[3 * t + k] + j]);
    }
    sr_mesh_release(&m);
    return 84 + 400 + extra;
}

/* ASCII STL of the octahedron: "solid NAME", facets, "endsolid NAME"; with `bad` the
 * text of one coordinate of facet 1 is replaced, and `more` is an extra facet. */
static void octa_stl_ascii(char *buf, size_t cap, const char *name, const char *bad,
                           const char *more)
{
    sr_mesh m;
    make_octa(&m);
    size_t n = (size_t)snprintf(buf, cap, "solid %s\n", name);
    for (int t = 0; t < 8; t++) {
        n += (size_t)snprintf(buf + n, cap - n, "  facet normal 0 0 0\n    outer loop\n");
        for (int k = 0; k < 3; k++) {
            const double *p = m.xyz + 3 * m.tri[3 * t + k];
            if (bad && t == 1 && k == 0)
                n += (size_t)snprintf(buf + n, cap - n, "      vertex %s %.9g %.9g\n", bad,
                                      p[1], p[2]);
            else
                n += (size_t)snprintf(buf + n, cap - n, "      vertex %.9g %.9g %.9g\n", p[0],
                                      p[1], p[2]);
        }
        n += (size_t)snprintf(buf + n, cap - n, "    endloop\n  endfacet\n");
    }
    if (more)
        n += (size_t)snprintf(buf + n, cap - n, "%s", more);
    snprintf(buf + n, cap - n, "endsolid %s\n", name);
    assert_true(n < cap - 64);
    sr_mesh_release(&m);
}

/* OBJ of the octahedron with extra lines appended. */
static void octa_obj(char *buf, size_t cap, const char *vertex2, const char *more)
{
    sr_mesh m;
    make_octa(&m);
    size_t n = 0;
    for (int v = 0; v < 6; v++) {
        if (vertex2 && v == 2)
            n += (size_t)snprintf(buf + n, cap - n, "%s\n", vertex2);
        else
            n += (size_t)snprintf(buf + n, cap - n, "v %.17g %.17g %.17g\n", m.xyz[3 * v],
                                  m.xyz[3 * v + 1], m.xyz[3 * v + 2]);
    }
    for (int t = 0; t < 8; t++)
        n += (size_t)snprintf(buf + n, cap - n, "f %u %u %u\n", m.tri[3 * t] + 1,
                              m.tri[3 * t + 1] + 1, m.tri[3 * t + 2] + 1);
    if (more)
        snprintf(buf + n, cap - n, "%s", more);
    sr_mesh_release(&m);
}

/* ---- round trips ------------------------------------------------------------------- */

/* Same triangles (in order), corners at the same points within tol (relative, 1 mm
 * floor), same volume within vol_tol (relative). */
static void assert_same_octa(const sr_mesh *got, double tol, double vol_tol)
{
    sr_mesh ref;
    make_octa(&ref);
    assert_int_equal(got->vertex_count, 6);
    assert_int_equal(got->tri_count, 8);
    for (size_t t = 0; t < 8; t++)
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++) {
                double a = got->xyz[3 * got->tri[3 * t + k] + j];
                double b = ref.xyz[3 * ref.tri[3 * t + k] + j];
                assert_near(a, b, tol * fmax(1.0, fabs(b)));
            }
    assert_near(sr_mesh_volume(got), octa_volume(), vol_tol * octa_volume());
    assert_true(sr_mesh_is_closed(got));
    sr_mesh_release(&ref);
}

/* No temporary file may be left next to what was written. */
static void assert_no_temp_files(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".tmp")) {
            print_error("temporary file left behind: %s\n", e->d_name);
            closedir(d);
            fail();
        }
    closedir(d);
}

static void round_trip(void **state, const char *name, int ascii, double tol, double vol_tol)
{
    char path[TMPDIR_PATH_MAX];
    path_in(state, name, path);
    sr_mesh m, back = {0};
    make_octa(&m);
    sr_write_opts opts = {.ascii = ascii};
    sr_err err = {{0}};
    sr_status st = sr_mesh_write(path, &m, &opts, &err);
    if (st)
        print_error("write: %s\n", err.msg);
    assert_int_equal(st, SR_OK);
    st = sr_mesh_read(path, &back, &err);
    if (st)
        print_error("read: %s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_same_octa(&back, tol, vol_tol);
    assert_no_temp_files(((tmpdir *)*state)->path);
    sr_mesh_release(&back);
    sr_mesh_release(&m);
}

static void stl_binary_round_trip_keeps_geometry(void **state)
{
    round_trip(state, "octa.stl", 0, 1e-6, 1e-6);
    char path[TMPDIR_PATH_MAX];
    struct stat st;
    assert_int_equal(stat(path_in(state, "octa.stl", path), &st), 0);
    assert_int_equal(st.st_size, 84 + 50 * 8);
}

static void stl_ascii_round_trip_keeps_geometry(void **state)
{
    round_trip(state, "octa.stl", 1, 1e-6, 1e-6);
    char path[TMPDIR_PATH_MAX];
    size_t n;
    unsigned char *text = tmpdir_read_file(path_in(state, "octa.stl", path), &n);
    assert_non_null(text);
    assert_memory_equal(text, "solid", 5);
    free(text);
}

static void obj_round_trip_is_exact(void **state)
{
    round_trip(state, "octa.obj", 0, 0.0, 1e-14);
}

static void ply_binary_round_trip_is_exact(void **state)
{
    round_trip(state, "octa.ply", 0, 0.0, 1e-14);
    char path[TMPDIR_PATH_MAX];
    size_t n;
    unsigned char *bytes = tmpdir_read_file(path_in(state, "octa.ply", path), &n);
    assert_non_null(bytes);
    assert_non_null(strstr((char *)bytes, "format binary_little_endian 1.0"));
    free(bytes);
}

static void ply_ascii_round_trip_is_exact(void **state)
{
    round_trip(state, "octa.ply", 1, 0.0, 1e-14);
}

static void off_round_trip_is_exact(void **state)
{
    round_trip(state, "octa.off", 0, 0.0, 1e-14);
}

/* A glTF that requires an extension symrec does not read is refused by the extension's
 * name before tinygltf trips over what it changed: a Draco file's accessor without a
 * bufferView, a meshopt file's buffer without a uri. */
static void gltf_required_extension_is_named_first(void **state)
{
    char path[TMPDIR_PATH_MAX];
    const char *draco =
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
        "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"extensions\":"
        "{\"KHR_draco_mesh_compression\":{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}}}]}],"
        "\"accessors\":[{\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
        "\"buffers\":[{\"byteLength\":4,\"uri\":\"data:application/"
        "octet-stream;base64,AAAAAA==\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":4}],"
        "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]}";
    assert_int_equal(tmpdir_write_text(path_in(state, "draco.gltf", path), draco), 0);
    expect_read_error(path, SR_E_UNSUPPORTED,
                      "requires glTF extension 'KHR_draco_mesh_compression' (Draco-compressed");
    const char *meshopt =
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsRequired\":[\"EXT_meshopt_compression\"],"
        "\"buffers\":[{\"byteLength\":4,\"uri\":\"data:application/octet-stream;base64,AAAAAA==\"},"
        "{\"byteLength\":1200,\"extensions\":{\"EXT_meshopt_compression\":{\"fallback\":true}}}]}";
    assert_int_equal(tmpdir_write_text(path_in(state, "meshopt.gltf", path), meshopt), 0);
    expect_read_error(path, SR_E_UNSUPPORTED, "'EXT_meshopt_compression' (meshoptimizer");
    const char *bad = "{\"asset\":{\"version\":\"2.0\"},\"extensionsRequired\":\"x\"}";
    assert_int_equal(tmpdir_write_text(path_in(state, "bad.gltf", path), bad), 0);
    expect_read_error(path, SR_E_FORMAT, "'extensionsRequired' is not an array");
}

static void gltf_round_trip_keeps_geometry(void **state)
{
    round_trip(state, "octa.gltf", 0, 1e-6, 1e-6);
}

static void glb_round_trip_keeps_geometry(void **state)
{
    round_trip(state, "octa.glb", 0, 1e-6, 1e-6);
}

static void write_replaces_existing_file(void **state)
{
    char path[TMPDIR_PATH_MAX];
    path_in(state, "octa.obj", path);
    assert_int_equal(tmpdir_write_text(path, "old content\n"), 0);
    round_trip(state, "octa.obj", 0, 0.0, 1e-14);
}

static void scene_round_trip_keeps_names_colours_extras(void **state)
{
    char path[TMPDIR_PATH_MAX], path2[TMPDIR_PATH_MAX];
    sr_mesh octa, moved;
    make_octa(&octa);
    make_octa(&moved);
    for (size_t i = 0; i < 6; i++)
        moved.xyz[3 * i] += 10.0;
    sr_scene_mesh in[2] = {{"damaged part", &octa, {0.8f, 0.1f, 0.1f, 1.0f}},
                           {"patch", &moved, {0.1f, 0.6f, 0.9f, 0.5f}}};
    const char *extras = "{\"run\": 42, \"units\": \"mm\", \"big\": 5000000000, "
                         "\"nested\": {\"ok\": true, \"list\": [1, 2.5, null]}}";
    const char *names[2] = {"scene.gltf", "scene.glb"};
    for (int f = 0; f < 2; f++) {
        path_in(state, names[f], path);
        sr_err err = {{0}};
        assert_int_equal(sr_scene_write(path, in, 2, extras, &err), SR_OK);
        sr_scene s = {0};
        sr_status st = sr_scene_read(path, &s, &err);
        if (st)
            print_error("%s\n", err.msg);
        assert_int_equal(st, SR_OK);
        assert_int_equal(s.count, 2);
        assert_string_equal(s.names[0], "damaged part");
        assert_string_equal(s.names[1], "patch");
        for (int k = 0; k < 4; k++) {
            assert_true(s.rgba[0][k] == in[0].rgba[k]);
            assert_true(s.rgba[1][k] == in[1].rgba[k]);
        }
        assert_non_null(s.extras_json);
        assert_has(s.extras_json, "\"run\":42");
        assert_has(s.extras_json, "\"units\":\"mm\"");
        assert_has(s.extras_json, "\"ok\":true");
        assert_near(sr_mesh_volume(&s.meshes[0]), octa_volume(), 1e-6 * octa_volume());
        double lo[3], hi[3];
        sr_mesh_bbox(&s.meshes[1], lo, hi);
        assert_near(lo[0], CX - A + 10.0, 1e-5);
        /* the merged read holds both */
        sr_mesh all = {0};
        assert_int_equal(sr_mesh_read(path, &all, &err), SR_OK);
        assert_int_equal(all.tri_count, 16);
        assert_near(sr_mesh_volume(&all), 2 * octa_volume(), 1e-6 * octa_volume());
        sr_mesh_release(&all);
        sr_scene_release(&s);
        assert_int_equal(s.count, 0);
        sr_scene_release(&s);   /* a zeroed scene */
    }
    sr_scene_release(NULL);
    /* what a viewer sees: generator, blend for the translucent patch, POSITION bounds */
    size_t n;
    unsigned char *text = tmpdir_read_file(path_in(state, "scene.gltf", path2), &n);
    assert_non_null(text);
    assert_has((char *)text, "\"generator\": \"symrec\"");
    assert_has((char *)text, "\"alphaMode\": \"BLEND\"");
    assert_has((char *)text, "\"min\"");
    assert_has((char *)text, "data:application/octet-stream;base64,");
    free(text);
    sr_mesh_release(&octa);
    sr_mesh_release(&moved);
}

static void scene_write_refuses_bad_extras_and_colours(void **state)
{
    char path[TMPDIR_PATH_MAX];
    path_in(state, "s.glb", path);
    sr_mesh octa;
    make_octa(&octa);
    sr_scene_mesh in = {"x", &octa, {0.5f, 0.5f, 0.5f, 1.0f}};
    sr_err err = {{0}};
    assert_int_equal(sr_scene_write(path, &in, 1, "[1, 2]", &err), SR_E_INVALID);
    assert_has(err.msg, "extras are not a JSON object");
    assert_int_equal(sr_scene_write(path, &in, 1, "{broken", &err), SR_E_INVALID);
    in.rgba[3] = 1.5f;
    assert_int_equal(sr_scene_write(path, &in, 1, NULL, &err), SR_E_RANGE);
    assert_has(err.msg, "colour component 3");
    struct stat st;
    assert_int_not_equal(stat(path, &st), 0);   /* nothing written */
    sr_mesh_release(&octa);
}

/* ---- files that are not there, or not files -------------------------------------------- */

static void missing_file_is_io_error(void **state)
{
    char path[TMPDIR_PATH_MAX];
    expect_read_error(path_in(state, "nothing.stl", path), SR_E_IO, "no such file");
}

static void empty_file_is_io_error(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "empty.obj", path), "", 0), 0);
    expect_read_error(path, SR_E_IO, "empty file");
}

static void directory_is_io_error(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(mkdir(path_in(state, "folder.stl", path), 0700), 0);
    expect_read_error(path, SR_E_IO, "is a directory");
}

static void unknown_extension_is_unsupported(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "part.xyz", path), "1 2 3\n"), 0);
    expect_read_error(path, SR_E_UNSUPPORTED, "unknown extension");
    assert_int_equal(sr_format_from_path("a/b.STL"), SR_FMT_STL);
    assert_int_equal(sr_format_from_path("dir.stl/file"), SR_FMT_UNKNOWN);
    assert_int_equal(sr_format_from_path(".glb"), SR_FMT_UNKNOWN);
    assert_string_equal(sr_format_name(SR_FMT_GLB), "glb");
    assert_string_equal(sr_format_name((sr_format)99), "unknown");
}

static void garbage_bytes_are_refused(void **state)
{
    unsigned char junk[300];
    for (size_t i = 0; i < sizeof junk; i++)
        junk[i] = (unsigned char)(i * 37 + 11);
    junk[0] = 0x01;   /* not "solid" */
    char path[TMPDIR_PATH_MAX];
    const struct {
        const char *name;
        sr_status st;
        const char *part;
    } cases[] = {
        {"junk.stl", SR_E_FORMAT, "binary STL"},
        {"junk.obj", SR_E_FORMAT, "not a text OBJ file"},
        {"junk.off", SR_E_FORMAT, "not an OFF file"},
        {"junk.ply", SR_E_FORMAT, "not a PLY file"},
        {"junk.glb", SR_E_FORMAT, "not a GLB file"},
        {"junk.gltf", SR_E_FORMAT, "malformed glTF JSON"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        assert_int_equal(tmpdir_write_file(path_in(state, cases[i].name, path), junk, sizeof junk),
                         0);
        expect_read_error(path, cases[i].st, cases[i].part);
    }
}

/* ---- binary STL ------------------------------------------------------------------------ */

static void truncated_binary_stl_names_both_counts(void **state)
{
    unsigned char buf[84 + 400];
    octa_stl_binary(buf, "binary", 5000, 0);
    char path[TMPDIR_PATH_MAX], want[TMPDIR_PATH_MAX + 100];
    /* 12 whole triangles: cut a 20-triangle file short */
    unsigned char big[84 + 50 * 12 + 30];
    memset(big, 0, sizeof big);
    memcpy(big, buf, 84 + 400);
    assert_int_equal(tmpdir_write_file(path_in(state, "cut.stl", path), big, sizeof big), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_E_FORMAT);
    snprintf(want, sizeof want,
             "cannot read '%s': truncated binary STL (header says 5000 triangles, file holds 12)",
             path);
    assert_string_equal(err.msg, want);
}

static void binary_stl_count_too_big_is_truncation(void **state)
{
    unsigned char buf[84 + 400];
    size_t n = octa_stl_binary(buf, "binary", 9, 0);
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "lie.stl", path), buf, n), 0);
    expect_read_error(path, SR_E_FORMAT,
                      "truncated binary STL (header says 9 triangles, file holds 8)");
}

static void binary_stl_count_too_small_is_refused(void **state)
{
    unsigned char buf[84 + 400];
    size_t n = octa_stl_binary(buf, "binary", 6, 0);
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "lie.stl", path), buf, n), 0);
    expect_read_error(path, SR_E_FORMAT, "binary STL header says 6 triangles, file holds 8");
}

static void binary_stl_trailing_bytes_are_refused(void **state)
{
    unsigned char buf[84 + 400 + 7];
    size_t n = octa_stl_binary(buf, "binary", 8, 7);
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "tail.stl", path), buf, n), 0);
    expect_read_error(path, SR_E_FORMAT, "binary STL has 7 trailing bytes after its 8 triangles");
}

static void binary_stl_reads_exactly(void **state)
{
    unsigned char buf[84 + 400];
    size_t n = octa_stl_binary(buf, "binary", 8, 0);
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "ok.stl", path), buf, n), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    assert_same_octa(&m, 1e-6, 1e-6);
    sr_mesh_release(&m);
}

static void binary_stl_starting_with_solid_loads_as_binary(void **state)
{
    unsigned char buf[84 + 400];
    size_t n = octa_stl_binary(buf, "solid octahedron exported as binary", 8, 0);
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "solid.stl", path), buf, n), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    assert_same_octa(&m, 1e-6, 1e-6);
    sr_mesh_release(&m);
    /* the same file cut short is a truncated binary STL, never an empty ASCII one */
    assert_int_equal(tmpdir_write_file(path, buf, n - 50), 0);
    expect_read_error(path, SR_E_FORMAT,
                      "truncated binary STL (header says 8 triangles, file holds 7)");
}

static void nan_in_binary_stl_is_invalid(void **state)
{
    unsigned char buf[84 + 400];
    size_t n = octa_stl_binary(buf, "binary", 8, 0);
    put_f32(buf + 84 + 50 * 3 + 12 + 4, NAN);   /* triangle 3, first corner, y */
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "nan.stl", path), buf, n), 0);
    expect_read_error(path, SR_E_INVALID, "binary STL triangle 3 has a NaN coordinate");
}

static void degenerate_binary_stl_triangle_is_dropped(void **state)
{
    unsigned char buf[84 + 450];
    octa_stl_binary(buf, "binary", 9, 50);
    /* triangle 8: corners (1,2,3), (1,2,3), (4,5,6) */
    unsigned char *rec = buf + 84 + 50 * 8 + 12;
    const float c[9] = {1, 2, 3, 1, 2, 3, 4, 5, 6};
    for (int i = 0; i < 9; i++)
        put_f32(rec + 4 * i, c[i]);
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "degen.stl", path), buf, sizeof buf), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    assert_same_octa(&m, 1e-6, 1e-6);   /* 8 triangles, 6 vertices: no stray corner kept */
    sr_mesh_release(&m);
}

static void non_manifold_stl_keeps_every_triangle(void **state)
{
    /* three triangles on one edge: OpenMesh's own importer would split vertices */
    unsigned char buf[84 + 150] = "binary";
    const float c[3][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0},
                           {1, 0, 0, 0, 0, 0, 0, -1, 0},
                           {0, 0, 0, 1, 0, 0, 0, 0, 1}};
    buf[80] = 3;
    for (int t = 0; t < 3; t++)
        for (int i = 0; i < 9; i++)
            put_f32(buf + 84 + 50 * t + 12 + 4 * i, c[t][i]);
    char path[TMPDIR_PATH_MAX], out[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "fin.stl", path), buf, sizeof buf), 0);
    sr_mesh m = {0}, back = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    assert_int_equal(m.tri_count, 3);
    assert_int_equal(m.vertex_count, 5);
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.nonmanifold_edges, 1);
    /* and written back through OpenMesh, nothing is lost either */
    assert_int_equal(sr_mesh_write(path_in(state, "fin2.stl", out), &m, NULL, &err), SR_OK);
    assert_int_equal(sr_mesh_read(out, &back, &err), SR_OK);
    assert_int_equal(back.tri_count, 3);
    assert_int_equal(back.vertex_count, 5);
    sr_mesh_release(&back);
    sr_mesh_release(&m);
}

static float get_f32(const unsigned char *p)
{
    uint32_t u = 0;
    for (int i = 0; i < 4; i++)
        u |= (uint32_t)p[i] << (8 * i);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void binary_stl_is_written_facet_for_facet(void **state)
{
    /* four triangles, the third repeating a vertex: three facets, in order, each
     * corner as given (rounded to float), each normal the unit normal of its corners */
    const double xyz[] = {0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 4, 1.1, 2.2, 3.3};
    const uint32_t tri[] = {0, 2, 1, 0, 1, 3, 1, 1, 2, 4, 3, 2};
    sr_mesh m = {(double *)xyz, (uint32_t *)tri, 5, 4};
    char path[TMPDIR_PATH_MAX];
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_write(path_in(state, "facets.stl", path), &m, NULL, &err), SR_OK);
    size_t n;
    unsigned char *b = tmpdir_read_file(path, &n);
    assert_non_null(b);
    assert_int_equal(n, 84 + 50 * 3);
    assert_int_equal(b[80] | b[81] << 8 | b[82] << 16 | b[83] << 24, 3);
    const int kept[3] = {0, 1, 3};
    for (int f = 0; f < 3; f++) {
        const unsigned char *rec = b + 84 + 50 * f;
        const uint32_t *c = tri + 3 * kept[f];
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                assert_true(get_f32(rec + 12 + 12 * k + 4 * j) == (float)xyz[3 * c[k] + j]);
        double u[3], w[3], nrm[3];
        for (int j = 0; j < 3; j++) {
            u[j] = xyz[3 * c[1] + j] - xyz[3 * c[0] + j];
            w[j] = xyz[3 * c[2] + j] - xyz[3 * c[0] + j];
        }
        nrm[0] = u[1] * w[2] - u[2] * w[1];
        nrm[1] = u[2] * w[0] - u[0] * w[2];
        nrm[2] = u[0] * w[1] - u[1] * w[0];
        double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        for (int j = 0; j < 3; j++)
            assert_true(fabs(get_f32(rec + 4 * j) - nrm[j] / len) < 1e-6);
    }
    free(b);
}

/* ---- ASCII STL ------------------------------------------------------------------------- */

static void ascii_stl_named_outer_shell_keeps_all_facets(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_stl_ascii(text, sizeof text, "outer_shell", NULL, NULL);
    assert_int_equal(tmpdir_write_text(path_in(state, "shell.stl", path), text), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    sr_status st = sr_mesh_read(path, &m, &err);
    if (st)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_same_octa(&m, 1e-6, 1e-6);
    sr_mesh_release(&m);
}

static void nan_in_ascii_stl_is_invalid(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_stl_ascii(text, sizeof text, "part", "nan", NULL);
    assert_int_equal(tmpdir_write_text(path_in(state, "nan.stl", path), text), 0);
    expect_read_error(path, SR_E_INVALID, "facet 1 has a NaN coordinate (line 11)");
}

static void degenerate_ascii_stl_facet_is_dropped(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_stl_ascii(text, sizeof text, "part", NULL,
                   "facet normal 0 0 0\nouter loop\nvertex 1 2 3\nvertex 4 5 6\n"
                   "vertex 1 2 3\nendloop\nendfacet\n");
    assert_int_equal(tmpdir_write_text(path_in(state, "degen.stl", path), text), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    assert_same_octa(&m, 1e-6, 1e-6);
    sr_mesh_release(&m);
}

static void ascii_stl_cut_inside_a_facet_is_refused(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_stl_ascii(text, sizeof text, "part", NULL, NULL);
    *strstr(text, "      vertex") = '\0';   /* facet 0 ends right after "outer loop" */
    assert_int_equal(tmpdir_write_text(path_in(state, "cut.stl", path), text), 0);
    expect_read_error(path, SR_E_FORMAT, "facet 0 is cut off after 0 vertices");
}

static void empty_ascii_stl_has_no_triangles(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "none.stl", path), "solid x\nendsolid x\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "contains no triangles");
}

/* ---- OBJ --------------------------------------------------------------------------------- */

static void inf_in_obj_is_invalid(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_obj(text, sizeof text, "v 0.1 inf 0.3", NULL);
    assert_int_equal(tmpdir_write_text(path_in(state, "inf.obj", path), text), 0);
    expect_read_error(path, SR_E_INVALID, "vertex 2 has an infinite coordinate (line 3)");
}

static void obj_index_out_of_range_is_invalid(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_obj(text, sizeof text, NULL, "f 1 2 9\n");
    assert_int_equal(tmpdir_write_text(path_in(state, "range.obj", path), text), 0);
    expect_read_error(path, SR_E_INVALID, "face on line 15 uses vertex 9, file has 6");
}

static void obj_index_zero_is_invalid(void **state)
{
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_obj(text, sizeof text, NULL, "f 0 1 2\n");
    assert_int_equal(tmpdir_write_text(path_in(state, "zero.obj", path), text), 0);
    expect_read_error(path, SR_E_INVALID, "face on line 15 uses vertex index 0");
}

static void obj_degenerate_face_is_dropped_and_polygons_fanned(void **state)
{
    /* the octahedron's top as one quad-free fan, plus a face with a repeated vertex, a
     * negative (relative) reference, texture/normal references and an mtllib that must
     * not be opened */
    char text[4096], path[TMPDIR_PATH_MAX];
    octa_obj(text, sizeof text, NULL,
             "mtllib ../../../etc/passwd\nf 1 1 2\nvt 0 0\nf -6/1 -5/1 -4/1\n");
    assert_int_equal(tmpdir_write_text(path_in(state, "mixed.obj", path), text), 0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    sr_status st = sr_mesh_read(path, &m, &err);
    if (st)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_int_equal(m.tri_count, 9);   /* 8 + the relative one; the degenerate one dropped */
    assert_int_equal(m.tri[3 * 8], 0);
    assert_int_equal(m.tri[3 * 8 + 1], 1);
    assert_int_equal(m.tri[3 * 8 + 2], 2);
    sr_mesh_release(&m);

    /* a quad is fanned into two triangles */
    assert_int_equal(tmpdir_write_text(path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"), 0);
    assert_int_equal(sr_mesh_read(path, &m, &err), SR_OK);
    assert_int_equal(m.tri_count, 2);
    assert_near(sr_mesh_area(&m), 1.0, 1e-15);
    sr_mesh_release(&m);
}

/* ---- OFF and PLY --------------------------------------------------------------------------- */

static void off_huge_count_is_refused_before_reading(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "huge.off", path),
                                       "OFF\n4000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                     0);
    expect_read_error(path, SR_E_FORMAT, "OFF header declares 4000000000 vertices");
}

/* Found by tests/fuzz/fuzz_off.c: OpenMesh reads a number after a face's indices as
 * the next face's corner count (only a COFF face line has its rest taken as a colour);
 * "3 3 6 7333...3" made it loop 4 billion times. */
static void off_content_after_the_faces_is_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "more.off", path),
                                       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                       "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n# end\n\n"
                                       "3 32\n"),
                     0);
    expect_read_error(path, SR_E_FORMAT, "line 13: more after the 4 faces the header declares");
}

/* fuzz_off: OpenMesh reads the counts from the line after the header keyword. */
static void off_counts_on_the_header_line_are_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "one.off", path),
                                       "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                     0);
    expect_read_error(path, SR_E_FORMAT,
                      "line 1: '3' after 'OFF': the counts must be on the next line");
}

/* Valid OFF as other tools write it: comments, blank lines and face colours (plain or
 * COFF), read as the tetrahedron they describe (OpenMesh once read the comment file as
 * 0 vertices, and a colour as the next face's corner count); more than a colour after
 * a face's indices is refused. */
static void off_comments_and_face_colours_are_read(void **state)
{
    static const char body[] = "4 4 0\n# vertices\n0 0 0\n1 0 0 # x\n\n0 1 0\n0 0 1\n"
                               "3 0 2 1 255 0 0\n3 0 1 3 0 255 0\n3 1 2 3 0 0 255 128\n"
                               "3 0 3 2 7333333333333333333333333333\n";
    static const char *const heads[] = {"OFF", "COFF", "OFF # a comment"};
    for (int h = 0; h < 3; h++) {
        char path[TMPDIR_PATH_MAX], text[512];
        snprintf(text, sizeof text, "# made by a tool\n%s\n%s", heads[h], body);
        assert_int_equal(tmpdir_write_text(path_in(state, "colour.off", path), text), 0);
        sr_mesh m;
        sr_err err = {{0}};
        if (sr_mesh_read(path, &m, &err) != SR_OK)
            fail_msg("%s: %s", heads[h], err.msg);
        assert_int_equal(m.vertex_count, 4);
        assert_int_equal(m.tri_count, 4);
        assert_true(fabs(sr_mesh_volume(&m) - 1.0 / 6.0) < 1e-12);
        sr_mesh_release(&m);
    }
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "five.off", path),
                                       "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1 2 3 4 5\n"),
                     0);
    expect_read_error(path, SR_E_FORMAT, "line 6: face 0 has '5' after its 3 indices");
    assert_int_equal(tmpdir_write_text(path_in(state, "word.off", path),
                                       "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 red\n"),
                     0);
    expect_read_error(path, SR_E_FORMAT, "face 0 has 'red' after its 3 indices");
}

static void off_face_index_out_of_range_is_invalid(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "bad.off", path),
                                       "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "face 0 (line 6) uses vertex 3, file has 3");
}

static const char ply_head[] = "ply\nformat ascii 1.0\ncomment made by a test\n";

static void ply_header_cut_after_element_is_refused(void **state)
{
    char text[256], path[TMPDIR_PATH_MAX];
    snprintf(text, sizeof text, "%selement vertex", ply_head);
    assert_int_equal(tmpdir_write_text(path_in(state, "cut.ply", path), text), 0);
    expect_read_error(path, SR_E_FORMAT, "PLY header line 4: 'element' needs a name and a count");
}

static void ply_header_cut_after_property_is_refused(void **state)
{
    char text[256], path[TMPDIR_PATH_MAX];
    snprintf(text, sizeof text, "%selement vertex 3\nproperty float", ply_head);
    assert_int_equal(tmpdir_write_text(path_in(state, "cut.ply", path), text), 0);
    expect_read_error(path, SR_E_FORMAT, "PLY header line 5: 'property' is missing its name");
}

static void ply_header_non_numeric_count_is_refused(void **state)
{
    char text[256], path[TMPDIR_PATH_MAX];
    snprintf(text, sizeof text, "%selement vertex lots\nproperty float x\nend_header\n", ply_head);
    assert_int_equal(tmpdir_write_text(path_in(state, "nan.ply", path), text), 0);
    expect_read_error(path, SR_E_FORMAT, "element count 'lots' is not a number");
}

static void ply_header_without_end_is_refused(void **state)
{
    char text[256], path[TMPDIR_PATH_MAX];
    snprintf(text, sizeof text, "%selement vertex 3\nproperty float x\nproperty float y\n",
             ply_head);
    assert_int_equal(tmpdir_write_text(path_in(state, "open.ply", path), text), 0);
    expect_read_error(path, SR_E_FORMAT, "PLY header has no end_header");
}

static void ply_huge_count_is_refused(void **state)
{
    char text[512], path[TMPDIR_PATH_MAX];
    snprintf(text, sizeof text,
             "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
             "property float x\nproperty float y\nproperty float z\nend_header\n%s",
             "0123456789ab");
    assert_int_equal(tmpdir_write_text(path_in(state, "huge.ply", path), text), 0);
    expect_read_error(path, SR_E_FORMAT, "PLY header declares 4000000000 'vertex' elements");
}

static void ply_face_index_out_of_range_is_invalid(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "range.ply", path),
                                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 1\n"
                                       "property list uchar int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "PLY face 0 uses vertex 5, file has 3");
}

static void ply_list_length_type_openmesh_cannot_read_is_unsupported(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "short.ply", path),
                                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 1\n"
                                       "property list ushort int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                     0);
    expect_read_error(path, SR_E_UNSUPPORTED, "PLY face list length type 'ushort'");
}

static void nonfinite_coordinates_in_off_ply_are_invalid(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "nan.off", path),
                                       "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "vertex 1 has a NaN coordinate (line 4)");
    assert_int_equal(
        tmpdir_write_text(path_in(state, "inf.ply", path),
                          "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n"
                          "property double y\nproperty double z\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n1 0 0\n0 1 -inf\n3 0 1 2\n"),
        0);
    expect_read_error(path, SR_E_INVALID, "PLY vertex 2 has an infinite coordinate");
}

static void ply_with_extra_elements_and_properties_reads(void **state)
{
    /* CRLF lines, an edge element OpenMesh does not know, a colour property and a quad:
     * the geometry must come through exactly */
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(
        tmpdir_write_text(path_in(state, "extra.ply", path),
                          "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty double x\r\n"
                          "property double y\r\nproperty double z\r\nproperty uchar red\r\n"
                          "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\n"
                          "element face 1\r\nproperty list uchar int vertex_indices\r\n"
                          "end_header\r\n0.1 0 0 255\r\n1 0 0 0\r\n1 1 0 0\r\n0 1 0 0\r\n"
                          "0 1\r\n4 0 1 2 3\r\n"),
        0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    sr_status st = sr_mesh_read(path, &m, &err);
    if (st)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.tri_count, 2);
    assert_true(m.xyz[0] == 0.1);   /* double, not OpenMesh's float */
    sr_mesh_release(&m);
}

static void ply_truncated_body_is_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "short.ply", path),
                                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 1\n"
                                       "property list uchar int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
                     0);
    expect_read_error(path, SR_E_FORMAT, "PLY body ends inside face 0 of 1");
}

/* ---- glTF ------------------------------------------------------------------------------- */

/* One triangle in an external buffer: 3 float positions (36 bytes), 3 uint32 indices. */
static void write_tri_bin(const char *path, const uint32_t idx[3])
{
    unsigned char b[48];
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; i++)
        put_f32(b + 4 * i, p[i]);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 4; k++)
            b[36 + 4 * i + k] = (unsigned char)(idx[i] >> (8 * k));
    assert_int_equal(tmpdir_write_file(path, b, sizeof b), 0);
}

static void write_tri_gltf(const char *path, const char *uri, const char *byte_length,
                           unsigned position_count)
{
    char text[2048];
    snprintf(
        text, sizeof text,
        "{\"asset\": {\"version\": \"2.0\"},\n"
        " \"buffers\": [{\"uri\": \"%s\", \"byteLength\": %s}],\n"
        " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 36},\n"
        "                   {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 12}],\n"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": %u,\n"
        "                  \"type\": \"VEC3\", \"min\": [0,0,0], \"max\": [1,1,0]},\n"
        "                 {\"bufferView\": 1, \"componentType\": 5125, \"count\": 3,\n"
        "                  \"type\": \"SCALAR\"}],\n"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],\n"
        " \"nodes\": [{\"mesh\": 0, \"translation\": [5, 0, 0]}],\n"
        " \"scenes\": [{\"nodes\": [0]}], \"scene\": 0}\n",
        uri, byte_length, position_count);
    assert_int_equal(tmpdir_write_text(path, text), 0);
}

static const uint32_t good_idx[3] = {0, 1, 2};

static void gltf_strips_short_indices_and_unindexed_triangles_read(void **state)
{
    /* a unit square as a 4-vertex strip with uint16 indices, one unindexed triangle on
     * its own accessor, and a points primitive that is not a surface */
    unsigned char b[56];
    const float p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    for (int i = 0; i < 12; i++)
        put_f32(b + 4 * i, p[i]);
    const unsigned char idx[8] = {0, 0, 1, 0, 2, 0, 3, 0};
    memcpy(b + 48, idx, 8);
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "strip.bin", bin), b, sizeof b), 0);
    assert_int_equal(
        tmpdir_write_text(
            path_in(state, "strip.gltf", path),
            "{\"asset\": {\"version\": \"2.0\"},\n"
            " \"buffers\": [{\"uri\": \"strip.bin\", \"byteLength\": 56}],\n"
            " \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 48},\n"
            "                   {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 8}],\n"
            " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": "
            "\"VEC3\"},\n"
            "                 {\"bufferView\": 1, \"componentType\": 5123, \"count\": 4, \"type\": "
            "\"SCALAR\"},\n"
            "                 {\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": "
            "\"VEC3\"}],\n"
            " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1, "
            "\"mode\": 5},\n"
            "                                {\"attributes\": {\"POSITION\": 2}},\n"
            "                                {\"attributes\": {\"POSITION\": 0}, \"mode\": "
            "0}]}]}\n"),
        0);
    sr_mesh m = {0};
    sr_err err = {{0}};
    sr_status st = sr_mesh_read_units(path, SR_UNIT_MM, &m, &err); /* numbers as written */
    if (st)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_int_equal(m.tri_count, 3);
    assert_int_equal(m.vertex_count, 7);
    assert_near(sr_mesh_area(&m), 1.5, 1e-15);
    /* the strip's second triangle keeps the strip's winding: (1, 3, 2) */
    assert_int_equal(m.tri[3], 1);
    assert_int_equal(m.tri[4], 3);
    assert_int_equal(m.tri[5], 2);
    sr_mesh_release(&m);
}

static void nan_in_gltf_is_invalid(void **state)
{
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    write_tri_bin(path_in(state, "tri.bin", bin), good_idx);
    size_t n;
    unsigned char *b = tmpdir_read_file(bin, &n);
    assert_non_null(b);
    put_f32(b + 4 * 4, NAN);   /* vertex 1, y */
    assert_int_equal(tmpdir_write_file(bin, b, n), 0);
    free(b);
    write_tri_gltf(path_in(state, "nan.gltf", path), "tri.bin", "48", 3);
    expect_read_error(path, SR_E_INVALID, "mesh 0 primitive 0 vertex 1 has a NaN coordinate");
}

static void gltf_with_external_buffer_reads_and_places(void **state)
{
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    write_tri_bin(path_in(state, "tri.bin", bin), good_idx);
    write_tri_gltf(path_in(state, "tri.gltf", path), "tri.bin", "48", 3);
    sr_mesh m = {0};
    sr_err err = {{0}};
    sr_status st = sr_mesh_read(path, &m, &err);
    if (st)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_int_equal(m.tri_count, 1);
    assert_int_equal(m.vertex_count, 3);
    /* x = 1, moved by the node's translation 5: 6 m, glTF's unit, is 6000 mm */
    assert_true(m.xyz[3] == 6000.0);
    sr_mesh_release(&m);
}

static void gltf_buffer_uri_leaving_folder_is_refused(void **state)
{
    char bin[TMPDIR_PATH_MAX], sub[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    write_tri_bin(path_in(state, "x.bin", bin), good_idx);
    assert_int_equal(mkdir(path_in(state, "sub", sub), 0700), 0);
    path_in(state, "sub/model.gltf", path);
    write_tri_gltf(path, "../x.bin", "48", 3);
    expect_read_error(path, SR_E_INVALID, "buffer 0 uri '../x.bin' leaves the file's folder");
    write_tri_gltf(path, "%2e%2e/x.bin", "48", 3);   /* the same, percent-encoded */
    expect_read_error(path, SR_E_INVALID, "leaves the file's folder");
}

static void gltf_absolute_buffer_uri_is_refused(void **state)
{
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    write_tri_bin(path_in(state, "tri.bin", bin), good_idx);
    write_tri_gltf(path_in(state, "abs.gltf", path), bin, "48", 3);   /* exists, right size */
    expect_read_error(path, SR_E_INVALID, "is an absolute path");
}

static void gltf_buffer_uri_naming_directory_is_refused(void **state)
{
    char dir[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    assert_int_equal(mkdir(path_in(state, "data.bin", dir), 0700), 0);
    write_tri_gltf(path_in(state, "dir.gltf", path), "data.bin", "48", 3);
    expect_read_error(path, SR_E_INVALID, "buffer 0 uri 'data.bin' names a directory");
}

static void gltf_huge_buffer_byte_length_is_refused(void **state)
{
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    write_tri_bin(path_in(state, "tri.bin", bin), good_idx);
    write_tri_gltf(path_in(state, "huge.gltf", path), "tri.bin", "1000000000000000", 3);
    expect_read_error(path, SR_E_FORMAT,
                      "buffer 0 declares byteLength 1000000000000000 but 'tri.bin' holds 48 bytes");
    write_tri_gltf(path, "data:application/octet-stream;base64,AAAAAA==", "1000000000000000", 3);
    expect_read_error(path, SR_E_FORMAT, "its data URI holds 4 bytes");
}

static void gltf_accessor_beyond_buffer_is_refused(void **state)
{
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    write_tri_bin(path_in(state, "tri.bin", bin), good_idx);
    write_tri_gltf(path_in(state, "count.gltf", path), "tri.bin", "48", 4);
    expect_read_error(path, SR_E_FORMAT, "POSITION accessor 0 (offset 0, 4 elements of 12 bytes");
}

static void gltf_index_beyond_vertex_count_is_invalid(void **state)
{
    char bin[TMPDIR_PATH_MAX], path[TMPDIR_PATH_MAX];
    const uint32_t bad[3] = {0, 1, 3};
    write_tri_bin(path_in(state, "tri.bin", bin), bad);
    write_tri_gltf(path_in(state, "index.gltf", path), "tri.bin", "48", 3);
    expect_read_error(path, SR_E_INVALID, "index 2 is 3, not below the vertex count 3");
}

static void glb_bin_length_overstated_by_8_is_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    path_in(state, "octa.glb", path);
    sr_mesh m;
    make_octa(&m);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_OK);
    sr_mesh_release(&m);
    size_t n;
    unsigned char *b = tmpdir_read_file(path, &n);
    assert_non_null(b);
    uint32_t json_len = (uint32_t)b[12] | (uint32_t)b[13] << 8 | (uint32_t)b[14] << 16 |
                        (uint32_t)b[15] << 24;
    unsigned char *bin = b + 20 + json_len;
    assert_memory_equal(bin + 4, "BIN", 3);
    uint32_t len = (uint32_t)bin[0] | (uint32_t)bin[1] << 8 | (uint32_t)bin[2] << 16 |
                   (uint32_t)bin[3] << 24;
    assert_int_equal(20 + json_len + 8 + len, n);
    len += 8;
    for (int i = 0; i < 4; i++)
        bin[i] = (unsigned char)(len >> (8 * i));
    assert_int_equal(tmpdir_write_file(path, b, n), 0);
    free(b);
    expect_read_error(path, SR_E_FORMAT, "GLB BIN chunk length");
}

/* ---- writing ------------------------------------------------------------------------------ */

static void write_to_missing_directory_is_io_error(void **state)
{
    char path[TMPDIR_PATH_MAX], want[TMPDIR_PATH_MAX + 64];
    path_in(state, "no/such/dir/part.stl", path);
    sr_mesh m;
    make_octa(&m);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_IO);
    snprintf(want, sizeof want, "cannot write '%s': no such directory", path);
    assert_has(err.msg, want);
    path_in(state, "no/such/dir/part.glb", path);
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_IO);
    assert_has(err.msg, "no such directory");
    sr_mesh_release(&m);
}

static void write_over_directory_leaves_nothing_behind(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(mkdir(path_in(state, "taken.obj", path), 0700), 0);
    sr_mesh m;
    make_octa(&m);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_IO);
    assert_has(err.msg, "is a directory");
    assert_no_temp_files(((tmpdir *)*state)->path);
    sr_mesh_release(&m);
}

static void write_refuses_bad_meshes(void **state)
{
    char path[TMPDIR_PATH_MAX];
    path_in(state, "bad.stl", path);
    sr_mesh m;
    make_octa(&m);
    sr_err err = {{0}};
    m.xyz[4] = NAN;
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_INVALID);
    assert_has(err.msg, "NaN or infinite");
    m.xyz[4] = 1e300;   /* fine in OBJ, beyond float range for STL */
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_RANGE);
    path_in(state, "bad.xyz", path);
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_UNSUPPORTED);
    sr_mesh empty = {0};
    path_in(state, "bad.obj", path);
    assert_int_equal(sr_mesh_write(path, &empty, NULL, &err), SR_E_INVALID);
    assert_has(err.msg, "has no triangles");
    sr_mesh_release(&m);
}

#define T(name) cmocka_unit_test_setup_teardown(name, tmpdir_setup, tmpdir_teardown)

int main(void)
{
    const struct CMUnitTest tests[] = {
        T(stl_binary_round_trip_keeps_geometry),
        T(stl_ascii_round_trip_keeps_geometry),
        T(obj_round_trip_is_exact),
        T(ply_binary_round_trip_is_exact),
        T(ply_ascii_round_trip_is_exact),
        T(off_round_trip_is_exact),
        T(gltf_round_trip_keeps_geometry),
        T(gltf_required_extension_is_named_first),
        T(glb_round_trip_keeps_geometry),
        T(write_replaces_existing_file),
        T(scene_round_trip_keeps_names_colours_extras),
        T(scene_write_refuses_bad_extras_and_colours),
        T(missing_file_is_io_error),
        T(empty_file_is_io_error),
        T(directory_is_io_error),
        T(unknown_extension_is_unsupported),
        T(garbage_bytes_are_refused),
        T(truncated_binary_stl_names_both_counts),
        T(binary_stl_count_too_big_is_truncation),
        T(binary_stl_count_too_small_is_refused),
        T(binary_stl_trailing_bytes_are_refused),
        T(binary_stl_reads_exactly),
        T(binary_stl_starting_with_solid_loads_as_binary),
        T(nan_in_binary_stl_is_invalid),
        T(degenerate_binary_stl_triangle_is_dropped),
        T(non_manifold_stl_keeps_every_triangle),
        T(binary_stl_is_written_facet_for_facet),
        T(ascii_stl_named_outer_shell_keeps_all_facets),
        T(nan_in_ascii_stl_is_invalid),
        T(degenerate_ascii_stl_facet_is_dropped),
        T(ascii_stl_cut_inside_a_facet_is_refused),
        T(empty_ascii_stl_has_no_triangles),
        T(inf_in_obj_is_invalid),
        T(obj_index_out_of_range_is_invalid),
        T(obj_index_zero_is_invalid),
        T(obj_degenerate_face_is_dropped_and_polygons_fanned),
        T(off_huge_count_is_refused_before_reading),
        T(off_content_after_the_faces_is_refused),
        T(off_comments_and_face_colours_are_read),
        T(off_counts_on_the_header_line_are_refused),
        T(off_face_index_out_of_range_is_invalid),
        T(ply_header_cut_after_element_is_refused),
        T(ply_header_cut_after_property_is_refused),
        T(ply_header_non_numeric_count_is_refused),
        T(ply_header_without_end_is_refused),
        T(ply_huge_count_is_refused),
        T(ply_face_index_out_of_range_is_invalid),
        T(ply_list_length_type_openmesh_cannot_read_is_unsupported),
        T(nonfinite_coordinates_in_off_ply_are_invalid),
        T(ply_with_extra_elements_and_properties_reads),
        T(ply_truncated_body_is_refused),
        T(gltf_with_external_buffer_reads_and_places),
        T(gltf_strips_short_indices_and_unindexed_triangles_read),
        T(nan_in_gltf_is_invalid),
        T(gltf_buffer_uri_leaving_folder_is_refused),
        T(gltf_absolute_buffer_uri_is_refused),
        T(gltf_buffer_uri_naming_directory_is_refused),
        T(gltf_huge_buffer_byte_length_is_refused),
        T(gltf_accessor_beyond_buffer_is_refused),
        T(gltf_index_beyond_vertex_count_is_invalid),
        T(glb_bin_length_overstated_by_8_is_refused),
        T(write_to_missing_directory_is_io_error),
        T(write_over_directory_leaves_nothing_behind),
        T(write_refuses_bad_meshes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
