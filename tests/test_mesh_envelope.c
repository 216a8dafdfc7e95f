/*
 * test_mesh_envelope.c: what every mesh import refuses whatever its format (issue 17
 * items 1 and 6): coordinates outside the physical envelope of io/envelope.h (|x| <=
 * 1e6 mm, bounding box >= 1e-3 mm), meshes with no triangle of any area, a glTF node
 * scaled to 0, files over the 2 GiB limit (refused from their size, unread), and the
 * messages for an ASCII STL with a NUL byte and a GLB whose BIN chunk is too short.
 * Also sr_mesh_read_memory, the in-memory path that sr_mesh_read and the fuzz targets
 * share. The reproducers of ../shared/repro/ are read when that folder is there (the
 * cases are skipped when it is absent). Files are made by the test with the library's
 * writers, or by hand where a writer would refuse them.
 */
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "bridge/mesh_io.h"
#include "io/envelope.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/read_expect.h"
#include "support/tmpdir.h"

#define REPRO_DIR "../shared/repro"

static const char *path_in(void **state, const char *name, char buf[TMPDIR_PATH_MAX])
{
    return tmpdir_join(*state, name, buf);
}

static void expect_reads(const char *path, size_t tris)
{
    sr_mesh m = {0};
    sr_err err = {{0}};
    sr_status st = sr_mesh_read(path, &m, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_int_equal(m.tri_count, tris);
    sr_mesh_release(&m);
}

/* A box from lo to lo + size on every axis (12 triangles). */
static void make_box(sr_mesh *m, double lo, double size)
{
    double a[3] = {lo, lo, lo}, b[3] = {lo + size, lo + size, lo + size};
    assert_int_equal(sr_shape_box(a, b, m, NULL), SR_OK);
}

static void write_mesh(const char *path, const sr_mesh *m, int ascii)
{
    sr_write_opts o = {ascii};
    sr_err err = {{0}};
    sr_status st = sr_mesh_write(path, m, &o, &err);
    if (st != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(st, SR_OK);
}

/* Every format and variant: name suffix and ASCII flag. */
static const struct {
    const char *file;
    int ascii;
} formats[] = {{"b.stl", 0}, {"a.stl", 1}, {"m.obj", 0},  {"b.ply", 0},
               {"a.ply", 1}, {"m.off", 0}, {"m.gltf", 0}, {"m.glb", 0}};

/* ---- the reproducers ------------------------------------------------------------------ */

static void repro_files_are_refused_with_one_line(void **state)
{
    struct stat st;
    if (stat(REPRO_DIR "/brkt.stl", &st) != 0) {
        skip();
        return;
    }
    static const char *const bad[] = {
        REPRO_DIR "/crash_ply_3d58290a253f.ply", REPRO_DIR "/crash_ply_95af06b092fa.ply",
        REPRO_DIR "/min_ply_double_1e155.ply", REPRO_DIR "/recon_axial_ply_003.ply",
        REPRO_DIR "/min_ply_double_1e39.ply"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        expect_read_error(bad[i], SR_E_INVALID,
                          "is outside the physical envelope (|coordinate| <= 1e6 mm)");
    expect_read_error(REPRO_DIR "/crash_ply_3d58290a253f.ply", SR_E_INVALID,
                      "coordinate y = -5.486124068793689e+304");
    expect_read_error(REPRO_DIR "/min_ply_double_1e155.ply", SR_E_INVALID,
                      "vertex 3 coordinate z = 1e+155");
    expect_read_error(REPRO_DIR "/min_ply_double_1e39.ply", SR_E_INVALID,
                      "vertex 3 coordinate z = 1e+39");
    expect_reads(REPRO_DIR "/brkt.stl", 88);
}

/* ---- the envelope, in every format ----------------------------------------------------- */

static void coordinate_1e30_is_refused_in_every_format(void **state)
{
    sr_mesh m;
    make_box(&m, 0, 10);
    m.xyz[3 * 5 + 2] = 1e30; /* vertex 5, z: within float range, beyond the envelope */
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        char path[TMPDIR_PATH_MAX];
        write_mesh(path_in(state, formats[i].file, path), &m, formats[i].ascii);
        /* 1e+30, or 1.0000000150474662e+30 from the float formats */
        expect_read_error(path, SR_E_INVALID, "coordinate z = 1");
        expect_read_error(path, SR_E_INVALID, "e+30 is outside the physical envelope");
    }
    sr_mesh_release(&m);
}

static void part_of_1e_minus_30_mm_is_refused_in_every_format(void **state)
{
    sr_mesh m;
    make_box(&m, 0, 1e-30);
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        char path[TMPDIR_PATH_MAX];
        write_mesh(path_in(state, formats[i].file, path), &m, formats[i].ascii);
        expect_read_error(path, SR_E_INVALID,
                          "mm, is below the physical envelope (bounding box >= 1e-3 mm)");
    }
    sr_mesh_release(&m);
}

static void part_at_the_envelope_edge_reads_in_every_format(void **state)
{
    sr_mesh m;
    make_box(&m, 9e5, 10);
    m.xyz[0] = -9e5; /* one corner across the whole envelope */
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        char path[TMPDIR_PATH_MAX];
        write_mesh(path_in(state, formats[i].file, path), &m, formats[i].ascii);
        expect_reads(path, 12);
    }
    sr_mesh_release(&m);
    /* a micrometre part passes too */
    make_box(&m, 0, 1e-3);
    char path[TMPDIR_PATH_MAX];
    write_mesh(path_in(state, "um.obj", path), &m, 0);
    expect_reads(path, 12);
    sr_mesh_release(&m);
}

static void ply_double_1e39_is_refused_naming_vertex_and_value(void **state)
{
    sr_mesh m;
    make_box(&m, 0, 10);
    m.xyz[3 * 2 + 1] = -1e39; /* beyond float range: stored by a double PLY only */
    char path[TMPDIR_PATH_MAX];
    write_mesh(path_in(state, "d.ply", path), &m, 0);
    expect_read_error(path, SR_E_INVALID,
                      "vertex 2 coordinate y = -1e+39 is outside the physical envelope "
                      "(|coordinate| <= 1e6 mm)");
    sr_mesh_release(&m);
}

static void obj_beyond_float_range_is_not_a_bad_index(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "big.obj", path),
                                       "v 0 0 0\nv 1 0 0\nv 0 1e40 0\nv 0 0 1\n"
                                       "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n"),
                     0);
    expect_read_error(path, SR_E_INVALID,
                      "vertex 2 coordinate y = 1e+40 is outside the physical envelope");
}

static void ascii_stl_beyond_envelope_names_facet_and_corner(void **state)
{
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "far.stl", path),
                                       "solid x\nfacet normal 0 0 1\nouter loop\n"
                                       "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                       "endloop\nendfacet\n"
                                       "facet normal 0 0 1\nouter loop\n"
                                       "vertex 0 0 0\nvertex 2e6 0 0\nvertex 0 1 0\n"
                                       "endloop\nendfacet\nendsolid x\n"),
                     0);
    expect_read_error(path, SR_E_INVALID,
                      "facet 1 corner 1 coordinate x = 2e+06 is outside the physical envelope");
}

/* ---- glTF: after the node transforms ----------------------------------------------------- */

/* A 10 mm box written as .gltf, its node given `xform` (JSON members) by editing the
 * text the writer made. */
static void write_box_gltf_with(const char *path, const char *xform)
{
    sr_mesh m;
    make_box(&m, 0, 10);
    write_mesh(path, &m, 0);
    sr_mesh_release(&m);
    size_t n;
    char *text = (char *)tmpdir_read_file(path, &n);
    assert_non_null(text);
    char *at = strstr(text, "\"mesh\": 0");
    assert_non_null(at);
    at += strlen("\"mesh\": 0");
    size_t extra = strlen(xform) + 2;
    char *out = malloc(n + extra + 1);
    assert_non_null(out);
    size_t head = (size_t)(at - text);
    memcpy(out, text, head);
    snprintf(out + head, extra + 1, ", %s", xform);
    strcat(out, at);
    assert_int_equal(tmpdir_write_text(path, out), 0);
    free(out);
    free(text);
}

static void gltf_node_moved_outside_envelope_is_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    /* symrec's own glTF: the mesh node is under its mm, Z-up frame, so 2e6 mm (the
     * frame's scale 0.001 and the reader's 1000 leave a rounding in the last digit) */
    write_box_gltf_with(path_in(state, "far.gltf", path), "\"translation\": [0, 2e6, 0]");
    expect_read_error(path, SR_E_INVALID, "coordinate y = 2000000");
    expect_read_error(path, SR_E_INVALID,
                      "is outside the physical envelope (|coordinate| <= 1e6 mm)");
    sr_scene sc = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_scene_read(path, &sc, &err), SR_E_INVALID);
    assert_has(err.msg, "is outside the physical envelope");
    assert_int_equal(sc.count, 0);
}

static void gltf_node_scaled_to_zero_is_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    write_box_gltf_with(path_in(state, "flat.gltf", path), "\"scale\": [1, 1, 0]");
    expect_read_error(path, SR_E_INVALID, "node 0's transform is singular");
    write_box_gltf_with(path_in(state, "zero.gltf", path), "\"scale\": [0, 0, 0]");
    expect_read_error(path, SR_E_INVALID, "node 0's transform is singular");
    sr_scene sc = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_scene_read(path, &sc, &err), SR_E_INVALID);
    assert_has(err.msg, "is singular");
}

/* ---- degenerate input: one rule ----------------------------------------------------------- */

static void mesh_of_only_zero_area_triangles_is_refused(void **state)
{
    char path[TMPDIR_PATH_MAX];
    /* three distinct vertices on a line, in OBJ, OFF and ASCII STL */
    assert_int_equal(tmpdir_write_text(path_in(state, "line.obj", path),
                                       "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 3 2 1\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "none of its 2 triangles has an area");
    assert_int_equal(tmpdir_write_text(path_in(state, "line.off", path),
                                       "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "none of its 1 triangles has an area");
    assert_int_equal(tmpdir_write_text(path_in(state, "line.stl", path),
                                       "solid x\nfacet normal 0 0 1\nouter loop\n"
                                       "vertex 0 0 0\nvertex 1 0 0\nvertex 5 0 0\n"
                                       "endloop\nendfacet\nendsolid x\n"),
                     0);
    expect_read_error(path, SR_E_INVALID, "none of its 1 triangles has an area");
    /* as a mesh of repeated-vertex triangles is */
    assert_int_equal(
        tmpdir_write_text(path_in(state, "rep.obj", path), "v 0 0 0\nv 1 0 0\nv 2 1 0\nf 1 2 2\n"),
        0);
    expect_read_error(path, SR_E_INVALID, "contains no triangles");
}

static void zero_area_triangle_in_a_closed_mesh_is_kept(void **state)
{
    /* a tetrahedron whose base edge 0-1 is split at vertex 4 on it: triangle 0 4 1 has
     * no area but closes the T-junction; it stays, as the file has it */
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_text(path_in(state, "t.obj", path),
                                       "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\nv 1 0 0\n"
                                       "f 1 3 2\nf 1 5 4\nf 5 2 4\nf 2 3 4\nf 3 1 4\nf 1 2 5\n"),
                     0);
    expect_reads(path, 6);
}

/* ---- size, and the messages of item 6 ------------------------------------------------------ */

static void file_over_2_gib_is_refused_without_being_read(void **state)
{
    char path[TMPDIR_PATH_MAX];
    int fd = open(path_in(state, "huge.stl", path), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)SR_MESH_FILE_MAX + 1), 0); /* sparse */
    close(fd);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    expect_read_error(path, SR_E_UNSUPPORTED,
                      "file too large (2147483649 bytes; mesh files are limited to 2 GiB, "
                      "2147483648 bytes)");
    clock_gettime(CLOCK_MONOTONIC, &t1);
    /* refused from its size: reading 2 GiB would take seconds */
    assert_true((double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec) < 1.0);
    fd = open(path_in(state, "huge.glb", path), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)SR_MESH_FILE_MAX + 1), 0);
    close(fd);
    expect_read_error(path, SR_E_UNSUPPORTED, "mesh files are limited to 2 GiB");
}

static void ascii_stl_with_a_nul_byte_says_so(void **state)
{
    char text[512];
    snprintf(text, sizeof text,
             "solid a_name_long_enough_that_the_84_byte_header_of_a_binary_stl_is_all_text\n"
             "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
             "vertex 0 1 0\nendloop\nendfacet\nendsolid part\n");
    size_t n = strlen(text);
    size_t at = (size_t)(strstr(text, "endloop") - text);
    text[at] = '\0';
    char path[TMPDIR_PATH_MAX];
    assert_int_equal(tmpdir_write_file(path_in(state, "nul.stl", path), text, n), 0);
    char want[128];
    snprintf(want, sizeof want, "nor ASCII STL text (byte 0x00 at offset %zu)", at);
    expect_read_error(path, SR_E_FORMAT, want);
    expect_read_error(path, SR_E_FORMAT, "neither a binary STL");
}

static void glb_bin_chunk_too_short_says_so(void **state)
{
    sr_mesh m;
    make_box(&m, 0, 10);
    char path[TMPDIR_PATH_MAX];
    write_mesh(path_in(state, "box.glb", path), &m, 0);
    sr_mesh_release(&m);
    size_t n;
    unsigned char *b = tmpdir_read_file(path, &n);
    assert_non_null(b);
    uint32_t json_len =
        (uint32_t)b[12] | (uint32_t)b[13] << 8 | (uint32_t)b[14] << 16 | (uint32_t)b[15] << 24;
    unsigned char *bin = b + 20 + json_len; /* BIN chunk header: length, type */
    uint32_t len =
        (uint32_t)bin[0] | (uint32_t)bin[1] << 8 | (uint32_t)bin[2] << 16 | (uint32_t)bin[3] << 24;
    for (uint32_t cut = 4; cut <= 16; cut += 12) {
        uint32_t l = len - cut;
        for (int i = 0; i < 4; i++)
            bin[i] = (unsigned char)(l >> (8 * i));
        assert_int_equal(tmpdir_write_file(path, b, n), 0);
        char want[64];
        snprintf(want, sizeof want, "GLB BIN chunk length %u is too small", l);
        expect_read_error(path, SR_E_FORMAT, want);
    }
    free(b);
}

/* ---- the in-memory path ----------------------------------------------------------------- */

static void memory_read_is_the_file_read(void **state)
{
    sr_mesh m;
    make_box(&m, 0, 10);
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        char path[TMPDIR_PATH_MAX];
        write_mesh(path_in(state, formats[i].file, path), &m, formats[i].ascii);
        size_t n;
        unsigned char *b = tmpdir_read_file(path, &n);
        assert_non_null(b);
        sr_mesh a = {0}, f = {0};
        sr_err err = {{0}};
        assert_int_equal(sr_mesh_read_memory(b, n, sr_format_from_path(path), "mem", &a, &err),
                         SR_OK);
        assert_int_equal(sr_mesh_read(path, &f, &err), SR_OK);
        assert_int_equal(a.tri_count, f.tri_count);
        assert_int_equal(a.vertex_count, f.vertex_count);
        assert_memory_equal(a.xyz, f.xyz, 3 * a.vertex_count * sizeof(double));
        assert_memory_equal(a.tri, f.tri, 3 * a.tri_count * sizeof(uint32_t));
        sr_mesh_release(&a);
        sr_mesh_release(&f);
        /* a refusal names the given name */
        assert_int_not_equal(sr_mesh_read_memory(b, 10, sr_format_from_path(path), "ten", &a, &err),
                             SR_OK);
        assert_has(err.msg, "cannot read 'ten': ");
        free(b);
    }
    sr_mesh_release(&m);
}

static void memory_gltf_external_buffer_is_refused(void **state)
{
    static const char gltf[] =
        "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"uri\": \"tri.bin\", "
        "\"byteLength\": 48}]}";
    sr_mesh m = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read_memory((const unsigned char *)gltf, sizeof gltf - 1, SR_FMT_GLTF,
                                         "x.gltf", &m, &err),
                     SR_E_UNSUPPORTED);
    assert_has(err.msg, "cannot read 'x.gltf': buffer 0 uri 'tri.bin' is an external file");
    assert_int_equal(
        sr_mesh_read_memory((const unsigned char *)"", 0, SR_FMT_STL, "e.stl", &m, &err), SR_E_IO);
    assert_has(err.msg, "cannot read 'e.stl': empty file");
    assert_null(m.xyz);
}

#define T(name) cmocka_unit_test_setup_teardown(name, tmpdir_setup, tmpdir_teardown)

int main(void)
{
    const struct CMUnitTest tests[] = {
        T(repro_files_are_refused_with_one_line),
        T(coordinate_1e30_is_refused_in_every_format),
        T(part_of_1e_minus_30_mm_is_refused_in_every_format),
        T(part_at_the_envelope_edge_reads_in_every_format),
        T(ply_double_1e39_is_refused_naming_vertex_and_value),
        T(obj_beyond_float_range_is_not_a_bad_index),
        T(ascii_stl_beyond_envelope_names_facet_and_corner),
        T(gltf_node_moved_outside_envelope_is_refused),
        T(gltf_node_scaled_to_zero_is_refused),
        T(mesh_of_only_zero_area_triangles_is_refused),
        T(zero_area_triangle_in_a_closed_mesh_is_kept),
        T(file_over_2_gib_is_refused_without_being_read),
        T(ascii_stl_with_a_nul_byte_says_so),
        T(glb_bin_chunk_too_short_says_so),
        T(memory_read_is_the_file_read),
        T(memory_gltf_external_buffer_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
