/*
 * mesh_blob.h: the byte format in which the catalogue stores a mesh (the meshes.data
 * column): compact, versioned, little-endian, and laid out so that on a little-endian
 * host encoding and decoding are two memcpy calls plus one validating pass.
 *
 * Layout, version 1 (all integers and doubles little-endian, no padding):
 *   offset  size          field
 *   0       4             magic "SRM1"
 *   4       4             u32 format version (SR_MESH_BLOB_VERSION)
 *   8       8             u64 vertex_count (V)
 *   16      8             u64 tri_count (T)
 *   24      24 * V        V by 3 IEEE-754 doubles, x y z per vertex, millimetres
 *   24+24V  12 * T        T by 3 u32 vertex indices, counter-clockwise from outside
 * Total 24 + 24 V + 12 T bytes exactly. Geometry round-trips bit-identically (NaN
 * payloads and -0 included; a stored mesh never has NaN, decode refuses it).
 *
 * Pure C, no I/O, no SQLite.
 */
#ifndef SR_MESH_BLOB_H
#define SR_MESH_BLOB_H

#include <stddef.h>
#include <stdint.h>

#include "mesh/mesh.h"
#include "base/status.h"

#define SR_MESH_BLOB_MAGIC "SRM1"
#define SR_MESH_BLOB_VERSION 1
#define SR_MESH_BLOB_HEADER_SIZE 24

/* Bytes needed to encode `mesh`: 24 + 24 V + 12 T. Returns 0 when a count exceeds
 * SR_MESH_MAX_COUNT or the size does not fit in size_t (such a mesh cannot be
 * encoded). */
size_t sr_mesh_blob_size(const sr_mesh *mesh);

/* Writes the blob of `mesh` into buf (size bytes, at least sr_mesh_blob_size(mesh)).
 * Does not validate the geometry: the caller stores only meshes that passed
 * sr_mesh_validate. SR_E_RANGE (nothing written) when buf is too small or the mesh
 * cannot be encoded. */
sr_status sr_mesh_blob_encode(const sr_mesh *mesh, void *buf, size_t size);

/* Reads the header only: format version and counts, checking the magic, the version
 * and that `size` is exactly the size the counts imply. Any out-pointer may be NULL.
 * Errors as for sr_mesh_blob_decode. */
sr_status sr_mesh_blob_peek(const void *blob, size_t size, uint32_t *version,
                            size_t *vertex_count, size_t *tri_count, sr_err *err);

/* Decodes a blob into *out (a fresh mesh the caller releases; written only on
 * success). Refuses, with a message starting "mesh blob":
 *   SR_E_FORMAT       shorter than the header, bad magic, size not exactly
 *                     24 + 24 V + 12 T (truncated or trailing bytes), a NaN or
 *                     infinite coordinate, a vertex index >= V
 *   SR_E_UNSUPPORTED  a format version other than SR_MESH_BLOB_VERSION
 *   SR_E_NOMEM        the arrays cannot be allocated
 * An empty mesh (V = T = 0) is a valid blob. */
sr_status sr_mesh_blob_decode(const void *blob, size_t size, sr_mesh *out, sr_err *err);

#endif
