/*
 * mesh_blob.c: encoding and decoding of the catalogue's mesh blob (format in
 * mesh_blob.h). On a little-endian host with IEEE doubles the arrays are copied with
 * memcpy; elsewhere each value is assembled byte by byte, so the stored bytes are the
 * same on every host. Decoding trusts nothing in the blob: sizes are checked without
 * overflow before anything is allocated, and every index and coordinate is checked
 * before the mesh is handed out.
 */
#include "catalog/mesh_blob.h"

#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <string.h>

_Static_assert(sizeof(double) == 8 && DBL_MANT_DIG == 53, "IEEE-754 binary64 doubles needed");

#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define HOST_LE 1
#else
#define HOST_LE 0
#endif

/* Size of a blob with v vertices and t triangles, or 0 when it would overflow. */
static size_t blob_size(uint64_t v, uint64_t t)
{
    if (v > SR_MESH_MAX_COUNT || t > SR_MESH_MAX_COUNT)
        return 0;
    /* v, t < 2^32, so each product < 2^37 and the sum fits in uint64_t. */
    uint64_t total = SR_MESH_BLOB_HEADER_SIZE + 24 * v + 12 * t;
    if (total > SIZE_MAX)
        return 0;
    return (size_t)total;
}

size_t sr_mesh_blob_size(const sr_mesh *mesh)
{
    return blob_size(mesh->vertex_count, mesh->tri_count);
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

static uint32_t get_u32(const unsigned char *p)
{
    uint32_t x = 0;
    for (int i = 0; i < 4; i++)
        x |= (uint32_t)p[i] << (8 * i);
    return x;
}

static uint64_t get_u64(const unsigned char *p)
{
    uint64_t x = 0;
    for (int i = 0; i < 8; i++)
        x |= (uint64_t)p[i] << (8 * i);
    return x;
}

sr_status sr_mesh_blob_encode(const sr_mesh *mesh, void *buf, size_t size)
{
    size_t need = sr_mesh_blob_size(mesh);
    if (need == 0 || size < need)
        return SR_E_RANGE;
    unsigned char *p = buf;
    memcpy(p, SR_MESH_BLOB_MAGIC, 4);
    put_u32(p + 4, SR_MESH_BLOB_VERSION);
    put_u64(p + 8, mesh->vertex_count);
    put_u64(p + 16, mesh->tri_count);
    p += SR_MESH_BLOB_HEADER_SIZE;
    size_t coords = 3 * mesh->vertex_count, idx = 3 * mesh->tri_count;
    if (HOST_LE) {
        if (coords)
            memcpy(p, mesh->xyz, coords * sizeof(double));
        p += coords * sizeof(double);
        if (idx)
            memcpy(p, mesh->tri, idx * sizeof(uint32_t));
    } else {
        for (size_t i = 0; i < coords; i++, p += 8) {
            uint64_t bits;
            memcpy(&bits, &mesh->xyz[i], 8);
            put_u64(p, bits);
        }
        for (size_t i = 0; i < idx; i++, p += 4)
            put_u32(p, mesh->tri[i]);
    }
    return SR_OK;
}

sr_status sr_mesh_blob_peek(const void *blob, size_t size, uint32_t *version,
                            size_t *vertex_count, size_t *tri_count, sr_err *err)
{
    const unsigned char *p = blob;
    if (size < SR_MESH_BLOB_HEADER_SIZE)
        return sr_err_set(err, SR_E_FORMAT,
                          "mesh blob truncated: %zu bytes, shorter than its %d-byte header",
                          size, SR_MESH_BLOB_HEADER_SIZE);
    if (memcmp(p, SR_MESH_BLOB_MAGIC, 4) != 0)
        return sr_err_set(err, SR_E_FORMAT, "mesh blob has a bad magic (expected '%s')",
                          SR_MESH_BLOB_MAGIC);
    uint32_t ver = get_u32(p + 4);
    if (ver != SR_MESH_BLOB_VERSION)
        return sr_err_set(err, SR_E_UNSUPPORTED,
                          "mesh blob has format version %" PRIu32 ", this symrec reads %d",
                          ver, SR_MESH_BLOB_VERSION);
    uint64_t v = get_u64(p + 8), t = get_u64(p + 16);
    size_t need = blob_size(v, t);
    if (need == 0)
        return sr_err_set(err, SR_E_FORMAT,
                          "mesh blob header has impossible counts (%" PRIu64 " vertices, %" PRIu64
                          " triangles)",
                          v, t);
    if (size != need)
        return sr_err_set(err, SR_E_FORMAT,
                          "mesh blob %s: header says %" PRIu64 " vertices and %" PRIu64
                          " triangles (%zu bytes), blob holds %zu bytes",
                          size < need ? "truncated" : "has trailing bytes", v, t, need, size);
    if (version)
        *version = ver;
    if (vertex_count)
        *vertex_count = (size_t)v;
    if (tri_count)
        *tri_count = (size_t)t;
    return SR_OK;
}

/* True when the double with these bits is NaN or infinite (exponent all ones). */
static int bits_nonfinite(uint64_t bits)
{
    return (bits & UINT64_C(0x7ff0000000000000)) == UINT64_C(0x7ff0000000000000);
}

sr_status sr_mesh_blob_decode(const void *blob, size_t size, sr_mesh *out, sr_err *err)
{
    size_t v, t;
    sr_status st = sr_mesh_blob_peek(blob, size, NULL, &v, &t, err);
    if (st != SR_OK)
        return st;
    sr_mesh m;
    if (sr_mesh_alloc(&m, v, t) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM,
                          "mesh blob: cannot allocate %zu vertices and %zu triangles", v, t);
    const unsigned char *p = (const unsigned char *)blob + SR_MESH_BLOB_HEADER_SIZE;
    const size_t coords = 3 * v, idx = 3 * t;
    if (HOST_LE) {
        if (coords)
            memcpy(m.xyz, p, coords * sizeof(double));
        if (idx)
            memcpy(m.tri, p + coords * sizeof(double), idx * sizeof(uint32_t));
    } else {
        for (size_t i = 0; i < coords; i++) {
            uint64_t bits = get_u64(p + 8 * i);
            memcpy(&m.xyz[i], &bits, 8);
        }
        const unsigned char *q = p + coords * 8;
        for (size_t i = 0; i < idx; i++)
            m.tri[i] = get_u32(q + 4 * i);
    }

    /* Validation as branch-free reductions (fast); the slow search for the first
     * offender runs only when something is wrong. */
    uint32_t max_index = 0;
    for (size_t i = 0; i < idx; i++)
        max_index = m.tri[i] > max_index ? m.tri[i] : max_index;
    if (idx && (size_t)max_index >= v) {
        size_t bad = 0;
        while (m.tri[bad] < v)
            bad++;
        uint32_t bad_index = m.tri[bad];
        sr_mesh_release(&m);
        return sr_err_set(err, SR_E_FORMAT,
                          "mesh blob: triangle %zu has vertex index %" PRIu32
                          " out of range (%zu vertices)",
                          bad / 3, bad_index, v);
    }
    int nonfinite = 0;
    for (size_t i = 0; i < coords; i++) {
        uint64_t bits;
        memcpy(&bits, &m.xyz[i], 8);
        nonfinite |= bits_nonfinite(bits);
    }
    if (nonfinite) {
        size_t bad = 0;
        while (isfinite(m.xyz[bad]))
            bad++;
        sr_mesh_release(&m);
        return sr_err_set(err, SR_E_FORMAT,
                          "mesh blob: vertex %zu has a NaN or infinite coordinate", bad / 3);
    }
    *out = m;
    return SR_OK;
}
