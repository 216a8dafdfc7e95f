/*
 * mesh_io.h: reading and writing mesh files, the pure-C face of the C++ bridge
 * (src/bridge/mesh_io_api.cpp and the files mesh_io_int.hpp lists). OpenMesh reads and
 * writes STL (ASCII and binary), OBJ, PLY and OFF; tinygltf reads and writes glTF and
 * GLB. Nothing C++ crosses this header.
 *
 * Every file is checked before it is handed to a library (the faults listed in
 * shared/DEPENDENCY-NOTES.md: lying STL counts, truncated PLY headers, huge OFF
 * counts, glTF path traversal, GLB chunk overruns...) and the result is checked after
 * (no triangle silently lost, no NaN/Inf, no index out of range). Every error comes
 * back as a status plus one line naming the file:
 *   cannot read 'x.stl': truncated binary STL (header says 5000 triangles, file holds 12)
 * Writes go to a temporary file in the same folder, are fsync'ed and renamed over the
 * target, so a failed write never leaves a half-written file.
 */
#ifndef SR_MESH_IO_H
#define SR_MESH_IO_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "mesh/units.h"
#include "base/status.h"

typedef enum sr_format {
    SR_FMT_UNKNOWN = 0,
    SR_FMT_STL,
    SR_FMT_OBJ,
    SR_FMT_PLY,
    SR_FMT_OFF,
    SR_FMT_GLTF,
    SR_FMT_GLB,
} sr_format;

/* Format from the file name's extension (case-insensitive); SR_FMT_UNKNOWN otherwise. */
sr_format sr_format_from_path(const char *path);

/* Lower-case extension name of a format ("stl", ...), "unknown" otherwise. */
const char *sr_format_name(sr_format format);

/* The unit a format's numbers are in when the caller states none: SR_UNIT_M for glTF and
 * GLB (glTF's own unit, metres), SR_UNIT_MM for STL, OBJ, PLY and OFF (which state no
 * unit; a shop's CAD writes mm). SR_UNIT_MM for SR_FMT_UNKNOWN. */
sr_unit sr_format_unit(sr_format format);

/* Largest mesh file read, in bytes: 2 GiB. Scans run to 1-5 M triangles; an ASCII STL
 * of 5 M triangles takes about 1.4 GB, the same as binary STL 250 MB, so 2 GiB holds
 * every real scan in any format, and a file above it is refused from its size (stat)
 * before a byte is read (reading is done whole into memory). */
#define SR_MESH_FILE_MAX ((size_t)1 << 31)

/* Reads a mesh file (format from the extension) into *out, vertices welded where the
 * format shares them. A glTF/GLB file's meshes are merged into one. On success *out
 * is a validated mesh (non-empty, finite, indices in range) inside the physical
 * envelope of io/envelope.h (|coordinate| <= 1e6 mm, bounding box >= 1e-3 mm, some
 * triangle with an area; triangles that repeat a vertex dropped); on failure *out is
 * untouched. A file larger than SR_MESH_FILE_MAX is refused without being read. The
 * file's bytes go through sr_mesh_read_memory's path; a binary STL (by its size) is
 * read a run of facets at a time, never held whole, with the same checks, messages
 * and result as its bytes in memory would give. The file is read in its format's
 * own unit (sr_format_unit) and scaled to mm: sr_mesh_read_units with SR_UNIT_DEFAULT.
 *
 * glTF/GLB: the default scene's node transforms are applied, so the coordinates are
 * the scene's, in the glTF frame (Y up). A file symrec wrote (sr_scene_write: its one
 * root node says so in its extras) is turned back into symrec's frame (Z up), so a
 * write and a read give the same millimetre coordinates; a foreign file keeps its
 * axes. */
sr_status sr_mesh_read(const char *path, sr_mesh *out, sr_err *err);

/* sr_mesh_read with the unit the file's numbers are in stated (SR_UNIT_DEFAULT: the
 * format's own): every coordinate is multiplied by sr_unit_mm(unit) before the
 * physical envelope (which is in mm) is checked, so *out is in mm. */
sr_status sr_mesh_read_units(const char *path, sr_unit unit, sr_mesh *out, sr_err *err);

/* The same check-and-read path on a file's bytes in memory (data, size; not modified,
 * need not be NUL-terminated; size at most SR_MESH_FILE_MAX) in format fmt; name is
 * the file name for messages ("cannot read 'name': ..."). A glTF buffer may only be a
 * data URI or the GLB BIN chunk: external buffer files are refused in memory. The
 * entry point of the fuzz targets (tests/fuzz/). */
sr_status sr_mesh_read_memory(const unsigned char *data, size_t size, sr_format fmt,
                              const char *name, sr_mesh *out, sr_err *err);

/* Options for writing; zero is the default (binary STL/PLY, full double precision). */
typedef struct sr_write_opts {
    int ascii;   /* non-zero: ASCII STL/PLY instead of binary */
} sr_write_opts;

/* Writes a mesh (format from the extension). opts may be NULL. Atomic (temp+rename). */
sr_status sr_mesh_write(const char *path, const sr_mesh *mesh, const sr_write_opts *opts,
                        sr_err *err);

/* One mesh of a glTF scene. */
typedef struct sr_scene_mesh {
    const char *name;        /* mesh and node name; may be NULL */
    const sr_mesh *mesh;
    float rgba[4];           /* base colour of its material, linear 0..1 */
} sr_scene_mesh;

/* Writes several meshes, one node + mesh + material each, to a .gltf (buffer embedded
 * as a data URI) or .glb file. extras_json, if non-NULL, is a JSON object stored as the
 * asset's `extras` (metadata such as run id, units). Positions are float32 as glTF
 * requires, with POSITION min/max set, in symrec's mm with Z up; so that the file means
 * what glTF says (metres, Y up), the scene has one root node carrying the change of
 * frame (scale 0.001 and a rotation of -90 degrees about X: x to x, z to y, y to -z),
 * the meshes' nodes its children, and the root's extras say so
 * ({"symrec_frame": "children in mm, Z up"}), which the readers undo exactly.
 * sr_mesh_write's glTF/GLB is the same with one mesh. */
sr_status sr_scene_write(const char *path, const sr_scene_mesh *meshes, size_t count,
                         const char *extras_json, sr_err *err);

/* sr_scene_write with vertex colours: rgb[i] (NULL, or rgb NULL, = none for mesh i)
 * holds meshes[i].mesh->vertex_count x 3 components in 0..1, linear as glTF says,
 * written as the mesh's COLOR_0 (float32 VEC3; the material's base colour multiplies
 * them, so give such a mesh white). */
sr_status sr_scene_write_coloured(const char *path, const sr_scene_mesh *meshes,
                                  const float *const *rgb, size_t count, const char *extras_json,
                                  sr_err *err);

/* A glTF scene read back: meshes with their names and colours. */
typedef struct sr_scene {
    size_t count;
    sr_mesh *meshes;         /* count meshes, owned */
    char **names;            /* count strings (maybe ""), owned */
    float (*rgba)[4];        /* count colours, owned */
    char *extras_json;       /* the asset's extras as JSON text, or NULL; owned */
} sr_scene;

/* Reads every mesh of a glTF/GLB file separately, in metres (glTF's unit) scaled to mm,
 * placed by its nodes, a file symrec wrote turned back to Z up (as sr_mesh_read). External
 * buffers must lie inside the file's own folder. Each mesh must lie inside the physical
 * envelope (as sr_mesh_read's). On failure *out is untouched. */
sr_status sr_scene_read(const char *path, sr_scene *out, sr_err *err);

/* Frees a scene; accepts NULL and a zeroed scene. */
void sr_scene_release(sr_scene *scene);

#endif
