/*
 * test_mesh_blob.c: the catalogue's mesh blob format (src/catalog/mesh_blob.h): exact bytes of
 * the header, bit-identical round trips, and refusal of every kind of bad blob
 * (truncated, trailing bytes, bad magic, unknown version, impossible counts, index
 * out of range, non-finite coordinate) with the output left untouched.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "catalog/mesh_blob.h"

/* A tetrahedron whose coordinates include values a text format would not keep:
 * -0, a subnormal, 0.1, a large value and an odd-mantissa fraction. */
static void make_tet(sr_mesh *m)
{
    static const double v[4][3] = {{0.0, -0.0, 4.9406564584124654e-324},
                                   {0.1, 0.0, 0.0},
                                   {0.0, 1e300, 0.0},
                                   {1.0 / 3.0, 2.0 / 7.0, -123456.789}};
    static const uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    assert_int_equal(sr_mesh_alloc(m, 4, 4), SR_OK);
    memcpy(m->xyz, v, sizeof v);
    memcpy(m->tri, f, sizeof f);
}

/* Encodes `m` into a fresh buffer of exactly the right size. */
static unsigned char *encode(const sr_mesh *m, size_t *size)
{
    *size = sr_mesh_blob_size(m);
    assert_true(*size > 0);
    unsigned char *buf = malloc(*size);
    assert_non_null(buf);
    assert_int_equal(sr_mesh_blob_encode(m, buf, *size), SR_OK);
    return buf;
}

static void put_u32(unsigned char *p, uint32_t x)
{
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(x >> (8 * i));
}

static void put_u64(unsigned char *p, uint64_t x)
{
    for (int i = 0; i < 8; i++)
        p[i] = (unsigned char)(x >> (8 * i));
}

/* Decoding must fail with `want`, leave *out untouched and name `words` in the
 * message. */
static void expect_refused(const void *blob, size_t size, sr_status want, const char *words)
{
    sr_mesh out = {(double *)0x1, (uint32_t *)0x2, 77, 88};  /* sentinel, never freed */
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_blob_decode(blob, size, &out, &err), want);
    assert_ptr_equal(out.xyz, (double *)0x1);
    assert_ptr_equal(out.tri, (uint32_t *)0x2);
    assert_int_equal(out.vertex_count, 77);
    assert_int_equal(out.tri_count, 88);
    if (!strstr(err.msg, words))
        fail_msg("message '%s' does not contain '%s'", err.msg, words);
}

static void size_is_header_plus_arrays(void **state)
{
    sr_mesh m;
    make_tet(&m);
    assert_int_equal(sr_mesh_blob_size(&m), 24 + 24 * 4 + 12 * 4);
    sr_mesh empty = {0};
    assert_int_equal(sr_mesh_blob_size(&empty), 24);
    sr_mesh huge = {0};
    huge.vertex_count = (size_t)UINT32_MAX + 1;
    assert_int_equal(sr_mesh_blob_size(&huge), 0);
    sr_mesh_release(&m);
}

static void header_bytes_are_little_endian(void **state)
{
    sr_mesh m;
    make_tet(&m);
    size_t size;
    unsigned char *b = encode(&m, &size);
    static const unsigned char want[24] = {'S', 'R', 'M', '1', 1, 0, 0, 0, 4, 0, 0, 0,
                                           0,   0,   0,   0,   4, 0, 0, 0, 0, 0, 0, 0};
    assert_memory_equal(b, want, 24);
    /* x of vertex 1 is 0.1 = 0x3FB999999999999A, stored low byte first */
    static const unsigned char tenth[8] = {0x9a, 0x99, 0x99, 0x99, 0x99, 0x99, 0xb9, 0x3f};
    assert_memory_equal(b + 24 + 24, tenth, 8);
    /* the first index triple {0, 2, 1} right after the 96 bytes of coordinates */
    static const unsigned char tri0[12] = {0, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0};
    assert_memory_equal(b + 24 + 96, tri0, 12);
    free(b);
    sr_mesh_release(&m);
}

static void round_trip_is_bit_identical(void **state)
{
    sr_mesh m, back;
    make_tet(&m);
    size_t size;
    unsigned char *b = encode(&m, &size);
    assert_int_equal(sr_mesh_blob_decode(b, size, &back, NULL), SR_OK);
    assert_int_equal(back.vertex_count, 4);
    assert_int_equal(back.tri_count, 4);
    assert_memory_equal(back.xyz, m.xyz, 4 * 3 * sizeof(double));
    assert_memory_equal(back.tri, m.tri, 4 * 3 * sizeof(uint32_t));
    assert_true(signbit(back.xyz[1]));  /* -0 kept */
    uint32_t version = 0;
    size_t v = 0, t = 0;
    assert_int_equal(sr_mesh_blob_peek(b, size, &version, &v, &t, NULL), SR_OK);
    assert_int_equal(version, SR_MESH_BLOB_VERSION);
    assert_int_equal(v, 4);
    assert_int_equal(t, 4);
    free(b);
    sr_mesh_release(&m);
    sr_mesh_release(&back);
}

static void empty_mesh_round_trips(void **state)
{
    sr_mesh empty = {0}, back;
    unsigned char b[24];
    assert_int_equal(sr_mesh_blob_encode(&empty, b, sizeof b), SR_OK);
    assert_int_equal(sr_mesh_blob_decode(b, sizeof b, &back, NULL), SR_OK);
    assert_int_equal(back.vertex_count, 0);
    assert_int_equal(back.tri_count, 0);
    sr_mesh_release(&back);
}

static void encode_refuses_small_buffer(void **state)
{
    sr_mesh m;
    make_tet(&m);
    size_t size = sr_mesh_blob_size(&m);
    unsigned char *b = malloc(size);
    memset(b, 0xee, size);
    assert_int_equal(sr_mesh_blob_encode(&m, b, size - 1), SR_E_RANGE);
    for (size_t i = 0; i < size; i++)
        assert_int_equal(b[i], 0xee);
    free(b);
    sr_mesh_release(&m);
}

static void decode_refuses_truncated_blob(void **state)
{
    sr_mesh m;
    make_tet(&m);
    size_t size;
    unsigned char *b = encode(&m, &size);
    expect_refused(b, size - 1, SR_E_FORMAT, "truncated");
    expect_refused(b, size - 12, SR_E_FORMAT, "truncated");
    expect_refused(b, 23, SR_E_FORMAT, "shorter than its 24-byte header");
    expect_refused(b, 0, SR_E_FORMAT, "truncated");
    free(b);
    sr_mesh_release(&m);
}

static void decode_refuses_trailing_bytes(void **state)
{
    sr_mesh m;
    make_tet(&m);
    size_t size;
    unsigned char *b = encode(&m, &size);
    unsigned char *longer = calloc(1, size + 1);
    memcpy(longer, b, size);
    expect_refused(longer, size + 1, SR_E_FORMAT, "trailing bytes");
    free(longer);
    free(b);
    sr_mesh_release(&m);
}

static void decode_refuses_bad_magic(void **state)
{
    sr_mesh m;
    make_tet(&m);
    size_t size;
    unsigned char *b = encode(&m, &size);
    b[0] = 'X';
    expect_refused(b, size, SR_E_FORMAT, "bad magic");
    free(b);
    sr_mesh_release(&m);
}

static void decode_refuses_unknown_version(void **state)
{
    sr_mesh m;
    make_tet(&m);
    size_t size;
    unsigned char *b = encode(&m, &size);
    put_u32(b + 4, 2);
    expect_refused(b, size, SR_E_UNSUPPORTED, "format version 2, this symrec reads 1");
    put_u32(b + 4, 0);
    expect_refused(b, size, SR_E_UNSUPPORTED, "format version 0");
    free(b);
    sr_mesh_release(&m);
}

static void decode_refuses_impossible_counts(void **state)
{
    /* A header claiming 2^40 vertices must be refused from the header alone, without
     * trying to allocate. */
    unsigned char b[24] = {'S', 'R', 'M', '1'};
    put_u32(b + 4, 1);
    put_u64(b + 8, UINT64_C(1) << 40);
    put_u64(b + 16, 1);
    expect_refused(b, sizeof b, SR_E_FORMAT, "impossible counts");
    /* Counts that would overflow 64-bit size arithmetic if multiplied unchecked. */
    put_u64(b + 8, UINT64_MAX / 12);
    expect_refused(b, sizeof b, SR_E_FORMAT, "impossible counts");
    /* Plausible counts, but the blob is only the header. */
    put_u64(b + 8, 3);
    expect_refused(b, sizeof b, SR_E_FORMAT, "header says 3 vertices and 1 triangles");
}

static void decode_refuses_index_out_of_range(void **state)
{
    sr_mesh m;
    make_tet(&m);
    m.tri[3 * 2 + 1] = 4;  /* triangle 2, == vertex_count */
    size_t size;
    unsigned char *b = encode(&m, &size);
    expect_refused(b, size, SR_E_FORMAT, "triangle 2 has vertex index 4 out of range");
    free(b);
    m.tri[3 * 2 + 1] = UINT32_MAX;
    b = encode(&m, &size);
    expect_refused(b, size, SR_E_FORMAT, "out of range");
    free(b);
    sr_mesh_release(&m);
}

static void decode_refuses_nonfinite_coordinate(void **state)
{
    sr_mesh m;
    make_tet(&m);
    m.xyz[3 * 3 + 2] = NAN;
    size_t size;
    unsigned char *b = encode(&m, &size);
    expect_refused(b, size, SR_E_FORMAT, "vertex 3 has a NaN or infinite coordinate");
    free(b);
    m.xyz[3 * 3 + 2] = 0;
    m.xyz[0] = -INFINITY;
    b = encode(&m, &size);
    expect_refused(b, size, SR_E_FORMAT, "vertex 0 has a NaN");
    free(b);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(size_is_header_plus_arrays),
        cmocka_unit_test(header_bytes_are_little_endian),
        cmocka_unit_test(round_trip_is_bit_identical),
        cmocka_unit_test(empty_mesh_round_trips),
        cmocka_unit_test(encode_refuses_small_buffer),
        cmocka_unit_test(decode_refuses_truncated_blob),
        cmocka_unit_test(decode_refuses_trailing_bytes),
        cmocka_unit_test(decode_refuses_bad_magic),
        cmocka_unit_test(decode_refuses_unknown_version),
        cmocka_unit_test(decode_refuses_impossible_counts),
        cmocka_unit_test(decode_refuses_index_out_of_range),
        cmocka_unit_test(decode_refuses_nonfinite_coordinate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
