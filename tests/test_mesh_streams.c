/*
 * test_mesh_streams.c: mesh files read and written a run at a time, never held whole.
 * A binary STL file is read a run of facets at a time, never held
 * whole (src/bridge/mesh_io_api.cpp, openmesh_io.cpp's read_stl_binary_file); its
 * bytes in memory go the whole-buffer way (sr_mesh_read_memory). Both must give the
 * same mesh and the same refusals. A wavy sheet of 72,200 facets (more than two runs
 * of the check and the comparison, 32,768 facets, and three of the reader's 1 MiB
 * windows) with degenerate facets on the runs' edges reads to the same vertices and
 * triangles both ways, each triangle the file's facet; a NaN and a corner outside the
 * physical envelope in later runs are refused with the facet named as in the file.
 * Writing: a binary STL goes to its file as OpenMesh makes it, through a 1 MiB buffer
 * (mesh_io_int.hpp's FileSink); the sheet written (3.6 MB) reads back the same, 84 + 50
 * bytes a facet, and a refused write leaves neither the file nor a temporary one. A GLB
 * of the sheet goes to its file as tinygltf makes it, checked from the bytes kept (its
 * header, JSON chunk and BIN chunk header: sr_file_check_glb_head), and reads back the
 * same; the check refuses a head that stops before the BIN chunk's header.
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
#include "io/file_check.h"
#include "mesh/mesh.h"
#include "support/tmpdir.h"

#define GRID 190                        /* quads a side */
#define FACETS (2 * GRID * GRID)        /* 72,200 */
#define SIZE (84 + 50 * (size_t)FACETS) /* 3.6 MB */

/* facets made degenerate (a corner repeated): each side of the runs' edges, the last */
static const size_t flat[] = {32767, 32768, 65535, 65536, FACETS - 1};

static void put_f32(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(u >> (8 * i));
}

static float get_f32(const unsigned char *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* The sheet z = sin x cos y over [0, 19] mm squared, unround coordinates. */
static unsigned char *wavy_sheet(void)
{
    unsigned char *b = calloc(SIZE, 1);
    assert_non_null(b);
    memcpy(b, "wavy sheet", 10);
    b[80] = (unsigned char)(FACETS & 0xff);
    b[81] = (unsigned char)(FACETS >> 8 & 0xff);
    b[82] = (unsigned char)(FACETS >> 16 & 0xff);
    size_t t = 0;
    for (int i = 0; i < GRID; i++)
        for (int j = 0; j < GRID; j++) {
            double x[4] = {0.1 * i, 0.1 * (i + 1), 0.1 * (i + 1), 0.1 * i};
            double y[4] = {0.1 * j, 0.1 * j, 0.1 * (j + 1), 0.1 * (j + 1)};
            const int corner[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (int h = 0; h < 2; h++, t++)
                for (int k = 0; k < 3; k++) {
                    int c = corner[h][k];
                    unsigned char *p = b + 84 + 50 * t + 12 + 12 * k;
                    put_f32(p, (float)(x[c] + 1.0 / 3.0));
                    put_f32(p + 4, (float)(y[c] - 1.0 / 7.0));
                    put_f32(p + 8, (float)(sin(x[c]) * cos(y[c])));
                }
        }
    for (size_t f = 0; f < sizeof flat / sizeof *flat; f++) /* corner 2 onto corner 0 */
        memcpy(b + 84 + 50 * flat[f] + 12 + 24, b + 84 + 50 * flat[f] + 12, 12);
    return b;
}

static void read_both(void **state, const unsigned char *bytes, const char *name, sr_status want,
                      sr_mesh *from_file, sr_mesh *from_memory, char file_msg[256],
                      char memory_msg[256])
{
    char path[TMPDIR_PATH_MAX];
    tmpdir_join(*state, name, path);
    assert_int_equal(tmpdir_write_file(path, bytes, SIZE), 0);
    sr_err e1 = {{0}}, e2 = {{0}};
    assert_int_equal(sr_mesh_read(path, from_file, &e1), want);
    /* the same name in messages: they must be the same line */
    assert_int_equal(sr_mesh_read_memory(bytes, SIZE, SR_FMT_STL, path, from_memory, &e2), want);
    strcpy(file_msg, e1.msg);
    strcpy(memory_msg, e2.msg);
}

static void a_big_binary_stl_reads_the_same_from_file_and_memory(void **state)
{
    unsigned char *b = wavy_sheet();
    sr_mesh f = {0}, m = {0};
    char m1[256], m2[256];
    read_both(state, b, "wavy.stl", SR_OK, &f, &m, m1, m2);
    size_t nflat = sizeof flat / sizeof *flat;
    assert_int_equal(f.tri_count, FACETS - nflat);
    assert_int_equal(m.tri_count, f.tri_count);
    assert_int_equal(f.vertex_count, (GRID + 1) * (GRID + 1));
    assert_int_equal(m.vertex_count, f.vertex_count);
    assert_memory_equal(f.tri, m.tri, 3 * f.tri_count * sizeof *f.tri);
    assert_memory_equal(f.xyz, m.xyz, 3 * f.vertex_count * sizeof *f.xyz);
    /* triangle by triangle the file's facets, the flat ones left out */
    size_t facet = 0, skip = 0;
    for (size_t t = 0; t < f.tri_count; t++, facet++) {
        while (skip < nflat && facet == flat[skip]) {
            facet++;
            skip++;
        }
        const unsigned char *rec = b + 84 + 50 * facet + 12;
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                assert_true(f.xyz[3 * f.tri[3 * t + k] + j] ==
                            (double)get_f32(rec + 12 * k + 4 * j));
    }
    while (skip < nflat && facet == flat[skip]) { /* the last facet is flat */
        facet++;
        skip++;
    }
    assert_int_equal(facet, FACETS);
    sr_mesh_release(&f);
    sr_mesh_release(&m);
    free(b);
}

static void refusals_name_the_facet_in_a_later_run(void **state)
{
    unsigned char *b = wavy_sheet();
    sr_mesh f = {0}, m = {0};
    char m1[256], m2[256];

    put_f32(b + 84 + 50 * 40000 + 12 + 12 + 8, NAN); /* facet 40000, corner 1, z */
    read_both(state, b, "nan.stl", SR_E_INVALID, &f, &m, m1, m2);
    assert_non_null(strstr(m1, "binary STL triangle 40000 has a NaN coordinate"));
    assert_string_equal(m1, m2);

    put_f32(b + 84 + 50 * 40000 + 12 + 12 + 8, 0.25f);
    put_f32(b + 84 + 50 * 70001 + 12 + 24 + 4, 2e6f); /* facet 70001, corner 2, y */
    read_both(state, b, "far.stl", SR_E_INVALID, &f, &m, m1, m2);
    assert_non_null(strstr(m1, "facet 70001 corner 2 coordinate y = 2e+06 is outside the "
                               "physical envelope"));
    assert_string_equal(m1, m2);

    /* every facet flat: nothing to read either way */
    put_f32(b + 84 + 50 * 70001 + 12 + 24 + 4, 0.5f);
    for (size_t t = 0; t < FACETS; t++)
        memcpy(b + 84 + 50 * t + 12 + 12, b + 84 + 50 * t + 12, 12);
    read_both(state, b, "flat.stl", SR_E_INVALID, &f, &m, m1, m2);
    assert_non_null(strstr(m1, "contains no triangles (all degenerate)"));
    assert_string_equal(m1, m2);
    free(b);
}

/* Names in dir other than "." and "..". */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

/* The sheet read from its bytes into *m, written to `name` in the test's folder (path),
 * no temporary file left beside it, and read back into *back: as many triangles and
 * vertices. */
static void sheet_written_and_read_back(void **state, const char *name, sr_mesh *m, sr_mesh *back,
                                        char path[TMPDIR_PATH_MAX])
{
    unsigned char *b = wavy_sheet();
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_read_memory(b, SIZE, SR_FMT_STL, "wavy.stl", m, &err), SR_OK);
    free(b);
    tmpdir_join(*state, name, path);
    assert_int_equal(sr_mesh_write(path, m, NULL, &err), SR_OK);
    assert_int_equal(entries(((const tmpdir *)*state)->path), 1);
    assert_int_equal(sr_mesh_read(path, back, &err), SR_OK);
    assert_int_equal(back->tri_count, m->tri_count);
    assert_int_equal(back->vertex_count, m->vertex_count);
}

static void a_big_binary_stl_is_written_as_it_is_made(void **state)
{
    sr_mesh m = {0}, back = {0};
    sr_err err = {{0}};
    char path[TMPDIR_PATH_MAX];
    sheet_written_and_read_back(state, "out.stl", &m, &back, path);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal((size_t)st.st_size, 84 + 50 * m.tri_count);
    assert_memory_equal(back.tri, m.tri, 3 * m.tri_count * sizeof *m.tri);
    assert_memory_equal(back.xyz, m.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    sr_mesh_release(&back);

    /* every vertex at one float position (a picometre apart): refused, nothing left */
    for (size_t v = 0; v < m.vertex_count; v++)
        m.xyz[3 * v + 2] = m.xyz[3 * v + 1] = m.xyz[3 * v] = 1.0 + 1e-12 * (double)v;
    tmpdir_join(*state, "flat.stl", path);
    assert_int_equal(sr_mesh_write(path, &m, NULL, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "flat.stl"));
    assert_int_equal(entries(((const tmpdir *)*state)->path), 1);
    sr_mesh_release(&m);
}

static unsigned char *file_bytes(const char *path, size_t *size)
{
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    unsigned char *b = malloc((size_t)st.st_size);
    assert_non_null(b);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(b, 1, (size_t)st.st_size, f), (size_t)st.st_size);
    fclose(f);
    *size = (size_t)st.st_size;
    return b;
}

static void a_glb_is_written_as_it_is_made(void **state)
{
    sr_mesh m = {0}, back = {0};
    sr_err err = {{0}};
    char path[TMPDIR_PATH_MAX];
    sheet_written_and_read_back(state, "wavy.glb", &m, &back, path);
    for (size_t i = 0; i < 3 * m.vertex_count; i++)
        assert_true(fabs(back.xyz[i] - m.xyz[i]) < 1e-6);
    sr_mesh_release(&back);
    sr_mesh_release(&m);

    /* the file's head alone checks as the whole file does */
    size_t size;
    unsigned char *g = file_bytes(path, &size);
    assert_true(size > 1u << 20); /* past the sink's buffer */
    uint32_t json =
        (uint32_t)g[12] | (uint32_t)g[13] << 8 | (uint32_t)g[14] << 16 | (uint32_t)g[15] << 24;
    sr_glb_layout whole, head;
    assert_int_equal(sr_file_check_glb(g, size, path, &whole, &err), SR_OK);
    assert_int_equal(sr_file_check_glb_head(g, 28 + json, size, path, &head, &err), SR_OK);
    assert_true(head.has_bin && whole.has_bin);
    assert_int_equal(head.bin_offset, whole.bin_offset);
    assert_int_equal(head.bin_size, whole.bin_size);
    assert_int_equal(head.bin_offset + head.bin_size, size);
    assert_int_equal(sr_file_check_glb_head(g, 24 + json, size, path, &head, &err), SR_E_FORMAT);
    assert_non_null(strstr(err.msg, "header at byte"));
    assert_non_null(strstr(err.msg, "past the"));
    free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(a_big_binary_stl_reads_the_same_from_file_and_memory,
                                        tmpdir_setup, tmpdir_teardown),
        cmocka_unit_test_setup_teardown(refusals_name_the_facet_in_a_later_run, tmpdir_setup,
                                        tmpdir_teardown),
        cmocka_unit_test_setup_teardown(a_big_binary_stl_is_written_as_it_is_made, tmpdir_setup,
                                        tmpdir_teardown),
        cmocka_unit_test_setup_teardown(a_glb_is_written_as_it_is_made, tmpdir_setup,
                                        tmpdir_teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
