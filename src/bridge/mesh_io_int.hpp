/*
 * mesh_io_int.hpp: the private interface between the C++ files that implement
 * mesh_io.h. Not installed, not used outside src/bridge/.
 *
 *   io_bytes.cpp     messages, reading a whole file, the atomic write
 *   openmesh_io.cpp  STL, OBJ, PLY and OFF read through OpenMesh; STL written by it
 *   read_gltf.cpp    a glTF/GLB loaded into a tinygltf model, guarded and pre-checked
 *   gltf_meshes.cpp  the loaded model's triangles: merged, or as a scene of meshes
 *   write_text.cpp   OBJ, OFF and PLY written by us in full double precision
 *   write_glb.cpp    glTF and GLB written through tinygltf
 *   mesh_io_api.cpp  the extern "C" entry points, dispatch by format, the exception
 *                    barrier
 *
 * Every function here returns a status and, on failure, sets err to one line naming the
 * file ("cannot read 'x.stl': ..."); out-parameters are written only on success. None
 * of them catches exceptions: mesh_io_api.cpp's entry points do.
 */
#ifndef SR_MESH_IO_INT_HPP
#define SR_MESH_IO_INT_HPP

extern "C" {
#include "bridge/mesh_io.h"
#include "io/envelope.h"
#include "io/file_check.h"
#include "mesh/mesh_float.h"
}

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <streambuf>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace sr_meshio {

/* Largest mesh file read into memory, every format (mesh_io.h says why); below
 * tinygltf's unsigned int length too. */
const size_t MESH_FILE_MAX = SR_MESH_FILE_MAX;
/* Largest external glTF buffer file. */
const size_t GLTF_BUFFER_MAX = (size_t)1 << 31;
/* Deepest JSON nesting and node hierarchy accepted in a glTF. */
const size_t JSON_DEPTH_MAX = 64;
const int NODE_DEPTH_MAX = 64;

/* ---- messages (io_bytes.cpp) ---- */

/* err := "cannot read 'path': <fmt...>" (rfail) or "cannot write ..." (wfail); returns st. */
sr_status rfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
sr_status wfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* errno as a lower-case phrase. */
std::string errno_text(int e);

/* First line of a library's message, shortened. */
std::string first_line(const std::string &s);

/* ---- whole files (io_bytes.cpp) ---- */

/* An ostream sink appending to a string we own, its room reserved up front: a writer's
 * many small writes go to memory without an ostringstream's regrowth and the copy its
 * str() makes (0.4 s of the 89 MB STL of a 1.85M-triangle part). The writers' bytes go through one. */
class StringSink : public std::streambuf
{
  public:
    explicit StringSink(std::string &out) : out_(out) {}

  protected:
    std::streamsize xsputn(const char *s, std::streamsize n) override
    {
        out_.append(s, (size_t)n);
        return n;
    }
    int_type overflow(int_type c) override
    {
        if (!traits_type::eq_int_type(c, traits_type::eof()))
            out_.push_back(traits_type::to_char_type(c));
        return traits_type::not_eof(c);
    }

  private:
    std::string &out_;
};

/* A file's bytes, owned (malloc'ed, NUL appended after size). */
struct Bytes {
    unsigned char *data = nullptr;
    size_t size = 0;
    Bytes() = default;
    Bytes(const Bytes &) = delete;
    Bytes &operator=(const Bytes &) = delete;
    ~Bytes() { free(data); }
};

/* Reads a whole regular, non-empty file of at most `limit` bytes (NUL appended). The
 * size is checked (fstat) before anything is read or allocated; a larger file is
 * refused with SR_E_UNSUPPORTED, naming the limit. */
sr_status read_file(const char *path, size_t limit, Bytes &out, sr_err *err);

/* read_file in steps: opens path (*fd, to be closed by the caller) and gives its size,
 * with read_file's checks and messages; */
sr_status open_regular(const char *path, size_t limit, int *fd, size_t *size, sr_err *err);
/* reads n bytes at offset of the open file ("file shrank" when it ends first); */
sr_status read_at(int fd, size_t offset, void *buf, size_t n, const char *path, sr_err *err);
/* reads the whole file of size bytes into out (NUL appended). */
sr_status read_whole(int fd, size_t size, const char *path, Bytes &out, sr_err *err);

/* The folder part of path: "." when it has none, "/" for a file in the root. */
std::string dir_of(const std::string &path);

/* A file written atomically: a new temporary file in the target's folder (open), the
 * bytes (write, any number of times), then fsync, rename over the target and fsync of
 * the folder (commit). Destroyed uncommitted, or when commit fails, nothing is left. */
class AtomicFile
{
  public:
    AtomicFile() = default;
    AtomicFile(const AtomicFile &) = delete;
    AtomicFile &operator=(const AtomicFile &) = delete;
    ~AtomicFile();
    sr_status open(const char *path, sr_err *err);
    /* false once a write failed (commit then reports it) */
    bool write(const void *bytes, size_t size);
    sr_status commit(sr_err *err);

  private:
    std::string path_, tmp_;
    int fd_ = -1, errno_ = 0;
    bool committed_ = false;
};

/* Writes bytes to path atomically (AtomicFile). */
sr_status write_file_atomic(const char *path, const void *bytes, size_t size, sr_err *err);

/* An ostream sink into an AtomicFile through a buffer of 1 MiB: a writer's bytes go to
 * the file as they come, never all in memory. Counts them and keeps the first ones, as
 * many as keep(what is kept so far) asks for (a binary STL's 84-byte header; a GLB's
 * header, JSON chunk and the BIN chunk's header). */
class FileSink : public std::streambuf
{
  public:
    typedef size_t (*Keep)(const std::string &head);
    FileSink(AtomicFile &f, Keep keep) : f_(f), keep_(keep), buf_(1 << 20)
    {
        setp(buf_.data(), buf_.data() + buf_.size());
    }
    size_t size() const { return written_ + (size_t)(pptr() - pbase()); }
    const std::string &head() const { return head_; }
    /* the bytes still buffered to the file; false when a write failed */
    bool flush() { return sync() == 0; }

  protected:
    int_type overflow(int_type c) override
    {
        if (sync() != 0)
            return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }
    int sync() override
    {
        size_t n = (size_t)(pptr() - pbase()), i = 0;
        for (size_t want;
             head_.size() == written_ + i && i < n && (want = keep_(head_)) > head_.size();) {
            size_t take = std::min(n - i, want - head_.size());
            head_.append(pbase() + i, take);
            i += take;
        }
        bool ok = f_.write(pbase(), n);
        written_ += n;
        setp(buf_.data(), buf_.data() + buf_.size());
        return ok ? 0 : -1;
    }

  private:
    AtomicFile &f_;
    Keep keep_;
    std::vector<char> buf_;
    size_t written_ = 0;
    std::string head_;
};

/* ---- meshes ---- */

/* An sr_mesh released when it goes out of scope unless moved out (m reset to {}). */
struct MeshGuard {
    sr_mesh m = {};
    MeshGuard() = default;
    MeshGuard(MeshGuard &&o) noexcept : m(o.m) { o.m = sr_mesh{}; }
    MeshGuard(const MeshGuard &) = delete;
    MeshGuard &operator=(const MeshGuard &) = delete;
    ~MeshGuard() { sr_mesh_release(&m); }
};

inline uint32_t rd_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Mesh fit for writing: triangles, finite coordinates, indices in range
 * (mesh_io_api.cpp). `what` names it in messages ("mesh", "mesh 2"). */
sr_status check_for_write(const char *path, const sr_mesh *mesh, const char *what, sr_err *err);

/* ---- readers ---- */

/* STL, OBJ, PLY or OFF (fmt) from the file's bytes, checked before and after OpenMesh
 * parses them (openmesh_io.cpp). file's bytes may be rewritten in place (names, mtllib). */
sr_status read_openmesh(const char *path, sr_format fmt, Bytes &file, sr_mesh *out,
                        sr_err *err);

/* The same for a binary STL of facets facets (sr_file_stl_binary_count) read from the
 * open file fd a run of facets at a time, never whole: checked, parsed by OpenMesh and
 * compared, each from a fresh read (openmesh_io.cpp). */
sr_status read_stl_binary_file(const char *path, int fd, size_t facets, sr_mesh *out, sr_err *err);

/* A .gltf or .glb file's bytes (fmt) loaded into model (read_gltf.cpp). With
 * files_allowed, external buffers are read from path's folder (never outside it);
 * without (bytes from memory), any external buffer is refused. */
sr_status gltf_load(const char *path, sr_format fmt, const Bytes &file, bool files_allowed,
                    tinygltf::Model &model, sr_err *err);

/* A glTF/GLB file's mesh instances, placed and merged into one mesh (gltf_meshes.cpp);
 * file and files_allowed as for gltf_load; the file's numbers are multiplied by
 * mm_per_unit (1000 for glTF's metres) as they are placed. */
sr_status read_gltf_merged(const char *path, sr_format fmt, const Bytes &file, bool files_allowed,
                           double mm_per_unit, sr_mesh *out, sr_err *err);

/* A glTF/GLB file's meshes apart, with names and colours (gltf_meshes.cpp). */
sr_status scene_read(const char *path, sr_scene *out, sr_err *err);

/* ---- writers ---- */

/* Binary or ASCII STL of m, through OpenMesh, into *out (openmesh_io.cpp). */
sr_status encode_stl(const char *path, const sr_mesh &m, bool ascii, std::string *out,
                     sr_err *err);

/* Binary STL of m, through OpenMesh, written to path atomically as it is made (a
 * restored scan of millions of triangles is 50 bytes a facet: never all in memory);
 * the same bytes as encode_stl's (openmesh_io.cpp). */
sr_status write_stl_binary(const char *path, const sr_mesh &m, sr_err *err);

/* OBJ, OFF or PLY (fmt; PLY binary unless ascii) of m (write_text.cpp). */
std::string encode_text(const sr_mesh &m, sr_format fmt, bool ascii);

/* Several meshes to a .gltf or .glb file, written atomically (write_glb.cpp). */
sr_status scene_write(const char *path, const sr_scene_mesh *meshes, size_t count,
                      const char *extras_json, sr_err *err, const float *const *rgb = nullptr);

} // namespace sr_meshio

#endif
