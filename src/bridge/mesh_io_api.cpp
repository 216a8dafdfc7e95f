/*
 * mesh_io_api.cpp: the C interface of mesh_io.h: formats by extension, sr_mesh_read,
 * sr_mesh_read_memory and sr_mesh_write dispatched by format to the readers and writers
 * of the other bridge files, the checks every read result passes (validation and the
 * physical envelope of io/envelope.h), the check that a mesh is fit for writing, and the
 * exception barrier: every extern "C" entry point catches all exceptions.
 *
 * sr_mesh_read reads the file's bytes and goes on exactly as sr_mesh_read_memory does
 * (mesh_from_bytes), so the path the fuzz targets exercise is the real one; a binary
 * STL file alone is read a run of facets at a time (read_stl_binary_file), with the
 * same checks, messages and result as its bytes in memory would give. A read
 * result is scaled to mm (the stated unit, or the format's own) before the envelope
 * check, so the envelope's limits are millimetres whatever the file's unit.
 */
#include "bridge/mesh_io_int.hpp"

#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <strings.h>
#include <unistd.h>

namespace sr_meshio {

/* Mesh fit for writing: triangles, finite coordinates, indices in range. */
sr_status check_for_write(const char *path, const sr_mesh *mesh, const char *what, sr_err *err)
{
    if (!mesh || mesh->tri_count == 0 || mesh->vertex_count == 0)
        return wfail(err, SR_E_INVALID, path, "%s has no triangles", what);
    if (mesh->vertex_count > SR_MESH_MAX_COUNT || mesh->tri_count > SR_MESH_MAX_COUNT)
        return wfail(err, SR_E_RANGE, path, "%s is too large", what);
    sr_mesh_report r;
    if (sr_mesh_validate(mesh, what, &r, nullptr) != SR_OK) {
        if (r.nonfinite_vertices)
            return wfail(err, SR_E_INVALID, path,
                         "%s has %zu vertices with NaN or infinite coordinates", what,
                         r.nonfinite_vertices);
        return wfail(err, SR_E_INVALID, path, "%s has %zu triangles with an index out of range",
                     what, r.bad_indices);
    }
    return SR_OK;
}

namespace {

const char *const KNOWN_EXTENSIONS = "unknown extension (known: .stl .obj .ply .off .gltf .glb)";

/* What every read result passes on the way out: scaled to mm (a glTF's scale went into
 * its node transforms), validated and held to the physical envelope. */
sr_status finish_read(const char *name, sr_format fmt, sr_unit unit, MeshGuard &g, sr_mesh *out,
                      sr_err *err)
{
    /* in mm: the unit the envelope and every later stage speak */
    double mm = sr_unit_mm(unit == SR_UNIT_DEFAULT ? sr_format_unit(fmt) : unit);
    if (fmt != SR_FMT_GLTF && fmt != SR_FMT_GLB && mm != 1.0)
        for (size_t i = 0; i < 3 * g.m.vertex_count; i++)
            g.m.xyz[i] *= mm;
    sr_status st = sr_mesh_validate(&g.m, name, nullptr, err);
    if (st != SR_OK)
        return st;
    /* after glTF node transforms: the coordinates every later stage sees */
    st = sr_envelope_check_mesh(g.m.xyz, g.m.vertex_count, g.m.tri, g.m.tri_count, name, err);
    if (st != SR_OK)
        return st;
    *out = g.m;
    g.m = sr_mesh{};
    return SR_OK;
}

/* The one read path of bytes in memory: a file's bytes (owned, NUL appended; an
 * OpenMesh format's may be rewritten in place) in format fmt, checked, parsed and
 * finished. files_allowed: a glTF may name external buffers beside `name`. */
sr_status mesh_from_bytes(const char *name, sr_format fmt, sr_unit unit, Bytes &file,
                          bool files_allowed, sr_mesh *out, sr_err *err)
{
    MeshGuard g;
    sr_status st;
    if (fmt == SR_FMT_GLTF || fmt == SR_FMT_GLB) {
        double mm = sr_unit_mm(unit == SR_UNIT_DEFAULT ? sr_format_unit(fmt) : unit);
        st = read_gltf_merged(name, fmt, file, files_allowed, mm, &g.m, err);
    } else {
        st = read_openmesh(name, fmt, file, &g.m, err);
    }
    if (st != SR_OK)
        return st;
    return finish_read(name, fmt, unit, g, out, err);
}

struct FdGuard {
    int fd = -1;
    FdGuard() = default;
    FdGuard(const FdGuard &) = delete;
    FdGuard &operator=(const FdGuard &) = delete;
    ~FdGuard()
    {
        if (fd >= 0)
            close(fd);
    }
};

/* A file: a binary STL (by its size) is read a run of facets at a time, never whole
 * (a scanner's millions of facets: the file's bytes are 50 a facet, more than the mesh
 * they make); any other file whole, then as bytes. */
sr_status mesh_read(const char *path, sr_unit unit, sr_mesh *out, sr_err *err)
{
    if (!path || !out)
        return sr_err_set(err, SR_E_INVALID, "no file name given");
    sr_format fmt = sr_format_from_path(path);
    if (fmt == SR_FMT_UNKNOWN)
        return rfail(err, SR_E_UNSUPPORTED, path, "%s", KNOWN_EXTENSIONS);
    FdGuard fd;
    size_t size;
    sr_status st = open_regular(path, MESH_FILE_MAX, &fd.fd, &size, err);
    if (st != SR_OK)
        return st;
    if (fmt == SR_FMT_STL && size >= SR_STL_HEADER_BYTES) {
        unsigned char head[SR_STL_HEADER_BYTES];
        st = read_at(fd.fd, 0, head, sizeof head, path, err);
        if (st != SR_OK)
            return st;
        size_t facets = sr_file_stl_binary_count(head, size);
        if (facets) {
            MeshGuard g;
            st = read_stl_binary_file(path, fd.fd, facets, &g.m, err);
            if (st != SR_OK)
                return st;
            return finish_read(path, fmt, unit, g, out, err);
        }
    }
    Bytes file;
    st = read_whole(fd.fd, size, path, file, err);
    if (st != SR_OK)
        return st;
    return mesh_from_bytes(path, fmt, unit, file, true, out, err);
}

sr_status mesh_read_memory(const unsigned char *data, size_t size, sr_format fmt, const char *name,
                           sr_mesh *out, sr_err *err)
{
    if (!name)
        name = "(memory)";
    if (!out || (!data && size))
        return rfail(err, SR_E_INVALID, name, "no output or no bytes given");
    if (fmt != SR_FMT_STL && fmt != SR_FMT_OBJ && fmt != SR_FMT_PLY && fmt != SR_FMT_OFF &&
        fmt != SR_FMT_GLTF && fmt != SR_FMT_GLB)
        return rfail(err, SR_E_UNSUPPORTED, name,
                     "unknown format (known: stl obj ply off gltf glb)");
    if (size == 0)
        return rfail(err, SR_E_IO, name, "empty file");
    if (size > MESH_FILE_MAX)
        return rfail(err, SR_E_UNSUPPORTED, name,
                     "file too large (%zu bytes; mesh files are "
                     "limited to 2 GiB, %zu bytes)",
                     size, MESH_FILE_MAX);
    /* the readers may rewrite the bytes in place and count on a NUL after them */
    Bytes file;
    file.data = (unsigned char *)malloc(size + 1);
    if (!file.data)
        return rfail(err, SR_E_NOMEM, name, "out of memory for %zu bytes", size);
    memcpy(file.data, data, size);
    file.data[size] = 0;
    file.size = size;
    return mesh_from_bytes(name, fmt, SR_UNIT_DEFAULT, file, false, out, err);
}

sr_status mesh_write(const char *path, const sr_mesh *mesh, const sr_write_opts *opts, sr_err *err)
{
    if (!path)
        return sr_err_set(err, SR_E_INVALID, "no file name given");
    sr_format fmt = sr_format_from_path(path);
    if (fmt == SR_FMT_UNKNOWN)
        return wfail(err, SR_E_UNSUPPORTED, path, "%s", KNOWN_EXTENSIONS);
    sr_status st = check_for_write(path, mesh, "mesh", err);
    if (st != SR_OK)
        return st;
    bool ascii = opts && opts->ascii;
    if (fmt == SR_FMT_GLTF || fmt == SR_FMT_GLB) {
        sr_scene_mesh one = {nullptr, mesh, {0.8f, 0.8f, 0.8f, 1.0f}};
        return scene_write(path, &one, 1, nullptr, err);
    }
    if (fmt == SR_FMT_STL && !ascii)
        return write_stl_binary(path, *mesh, err);
    std::string bytes;
    if (fmt == SR_FMT_STL) {
        st = encode_stl(path, *mesh, ascii, &bytes, err);
        if (st != SR_OK)
            return st;
    } else {
        bytes = encode_text(*mesh, fmt, ascii);
    }
    return write_file_atomic(path, bytes.data(), bytes.size(), err);
}

} // namespace

} // namespace sr_meshio

using namespace sr_meshio;

/* ---- the C interface ------------------------------------------------------------------------ */

/* The end of every entry point: no exception crosses into C. */
#define CATCH_ALL(err, verb, path)                                                             \
    catch (const std::bad_alloc &)                                                             \
    {                                                                                          \
        return sr_err_set(err, SR_E_NOMEM, "cannot %s '%s': out of memory", verb,              \
                          path ? path : "");                                                   \
    }                                                                                          \
    catch (const std::exception &ex)                                                           \
    {                                                                                          \
        return sr_err_set(err, SR_E_INTERNAL, "cannot %s '%s': unexpected exception: %s", verb, \
                          path ? path : "", ex.what());                                        \
    }                                                                                          \
    catch (...)                                                                                \
    {                                                                                          \
        return sr_err_set(err, SR_E_INTERNAL, "cannot %s '%s': unexpected exception", verb,    \
                          path ? path : "");                                                   \
    }

extern "C" sr_format sr_format_from_path(const char *path)
{
    if (!path)
        return SR_FMT_UNKNOWN;
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base)
        return SR_FMT_UNKNOWN;
    static const struct {
        const char *ext;
        sr_format fmt;
    } table[] = {{"stl", SR_FMT_STL}, {"obj", SR_FMT_OBJ},   {"ply", SR_FMT_PLY},
                 {"off", SR_FMT_OFF}, {"gltf", SR_FMT_GLTF}, {"glb", SR_FMT_GLB}};
    for (const auto &t : table)
        if (strcasecmp(dot + 1, t.ext) == 0)
            return t.fmt;
    return SR_FMT_UNKNOWN;
}

extern "C" const char *sr_format_name(sr_format format)
{
    switch (format) {
    case SR_FMT_STL: return "stl";
    case SR_FMT_OBJ: return "obj";
    case SR_FMT_PLY: return "ply";
    case SR_FMT_OFF: return "off";
    case SR_FMT_GLTF: return "gltf";
    case SR_FMT_GLB: return "glb";
    default: return "unknown";
    }
}

extern "C" sr_unit sr_format_unit(sr_format format)
{
    return format == SR_FMT_GLTF || format == SR_FMT_GLB ? SR_UNIT_M : SR_UNIT_MM;
}

extern "C" sr_status sr_mesh_read(const char *path, sr_mesh *out, sr_err *err)
{
    return sr_mesh_read_units(path, SR_UNIT_DEFAULT, out, err);
}

extern "C" sr_status sr_mesh_read_units(const char *path, sr_unit unit, sr_mesh *out, sr_err *err)
{
    try {
        return mesh_read(path, unit, out, err);
    }
    CATCH_ALL(err, "read", path)
}

extern "C" sr_status sr_mesh_read_memory(const unsigned char *data, size_t size, sr_format fmt,
                                         const char *name, sr_mesh *out, sr_err *err)
{
    try {
        return mesh_read_memory(data, size, fmt, name, out, err);
    }
    CATCH_ALL(err, "read", name)
}

extern "C" sr_status sr_mesh_write(const char *path, const sr_mesh *mesh,
                                   const sr_write_opts *opts, sr_err *err)
{
    try {
        return mesh_write(path, mesh, opts, err);
    }
    CATCH_ALL(err, "write", path)
}

extern "C" sr_status sr_scene_write(const char *path, const sr_scene_mesh *meshes, size_t count,
                                    const char *extras_json, sr_err *err)
{
    try {
        if (!path)
            return sr_err_set(err, SR_E_INVALID, "no file name given");
        return scene_write(path, meshes, count, extras_json, err);
    }
    CATCH_ALL(err, "write", path)
}

extern "C" sr_status sr_scene_write_coloured(const char *path, const sr_scene_mesh *meshes,
                                             const float *const *rgb, size_t count,
                                             const char *extras_json, sr_err *err)
{
    try {
        if (!path)
            return sr_err_set(err, SR_E_INVALID, "no file name given");
        return scene_write(path, meshes, count, extras_json, err, rgb);
    }
    CATCH_ALL(err, "write", path)
}

extern "C" sr_status sr_scene_read(const char *path, sr_scene *out, sr_err *err)
{
    try {
        if (!path || !out)
            return sr_err_set(err, SR_E_INVALID, "no file name given");
        return scene_read(path, out, err);
    }
    CATCH_ALL(err, "read", path)
}

extern "C" void sr_scene_release(sr_scene *scene)
{
    if (!scene)
        return;
    for (size_t i = 0; i < scene->count; i++) {
        if (scene->meshes)
            sr_mesh_release(&scene->meshes[i]);
        if (scene->names)
            free(scene->names[i]);
    }
    free(scene->meshes);
    free(scene->names);
    free(scene->rgba);
    free(scene->extras_json);
    memset(scene, 0, sizeof *scene);
}
