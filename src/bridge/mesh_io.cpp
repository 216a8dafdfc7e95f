/*
 * mesh_io.cpp: the C++ bridge for mesh files (see mesh_io.h). OpenMesh 9 parses STL,
 * OBJ, PLY and OFF; tinygltf 2.7 parses and serialises glTF/GLB. Both accept bad input
 * silently (shared/DEPENDENCY-NOTES.md), so every read here is:
 *   1. the file read into memory by us (missing, empty, directory, unreadable: SR_E_IO);
 *   2. checked by src/io/file_check.c (pure C): sizes, counts, NaN/Inf, indices, PLY
 *      header, GLB chunks; these checks also return what the file holds;
 *   3. parsed by the library from that memory (never by path: no second open, and
 *      OpenMesh's OBJ reader gets no chance to open an mtllib), into a Collector that
 *      records vertices and faces as delivered, with no topology to lose faces to;
 *   4. compared with step 2: same vertex count, same faces, same coordinates (to float
 *      rounding). Any disagreement is an error naming how much was lost.
 * OpenMesh 9 reads and writes every format in float precision, so the coordinates of
 * OBJ/OFF/PLY come from step 2 (double, as written, checked against OpenMesh's floats),
 * and OBJ/OFF/PLY are written here with shortest round-trip doubles (std::to_chars);
 * STL, a float format, is written by OpenMesh. glTF input goes through FsCallbacks
 * that refuse files outside the input's folder, directories and huge files, with image
 * decoding off; its JSON is pre-checked with nlohmann::json (buffer sizes and URIs) and
 * every accessor and bufferView is range-checked before a byte is read.
 *
 * Every write is serialised in memory, checked, written to a temporary file in the
 * target's folder, fsync'ed and renamed over the target.
 *
 * OpenMesh prints to omerr/omlog (connected to std::cerr/std::clog): during each call
 * those two streams write into a buffer of ours instead, which becomes the detail of an
 * error; nothing reaches the console. That swap and OpenMesh's global reader registry
 * are guarded by one mutex. Every extern "C" entry point catches all exceptions.
 */
extern "C" {
#include "bridge/mesh_io.h"
#include "io/file_check.h"
}

/* OpenMesh's property vectors trip GCC 12's -Wmaybe-uninitialized inside libstdc++. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#pragma GCC diagnostic pop
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <iostream>
#include <limits.h>
#include <map>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace {

/* Largest mesh file read into memory; tinygltf takes an unsigned int length. */
const size_t MESH_FILE_MAX = (size_t)1 << 32;
const size_t GLTF_FILE_MAX = (size_t)UINT32_MAX;
/* Largest external glTF buffer file. */
const size_t GLTF_BUFFER_MAX = (size_t)1 << 31;
/* Deepest JSON nesting and node hierarchy accepted in a glTF. */
const size_t JSON_DEPTH_MAX = 64;
const int NODE_DEPTH_MAX = 64;

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<Traits> OmMesh;

/* ---- messages ---------------------------------------------------------------------- */

sr_status vfail(sr_err *err, sr_status st, const char *verb, const char *path, const char *fmt,
                va_list ap)
{
    if (err) {
        char detail[400];
        vsnprintf(detail, sizeof detail, fmt, ap);
        sr_err_set(err, st, "cannot %s '%s': %s", verb, path, detail);
    }
    return st;
}

sr_status rfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
sr_status rfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, st, "read", path, fmt, ap);
    va_end(ap);
    return st;
}

sr_status wfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
sr_status wfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, st, "write", path, fmt, ap);
    va_end(ap);
    return st;
}

/* errno as a lower-case phrase. */
std::string errno_text(int e)
{
    switch (e) {
    case ENOENT: return "no such file";
    case ENOTDIR: return "a path component is not a directory";
    case EACCES: case EPERM: return "permission denied";
    case EISDIR: return "is a directory";
    case ENAMETOOLONG: return "name too long";
    case ELOOP: return "too many symbolic links";
    case EROFS: return "read-only file system";
    case ENOSPC: return "no space left on device";
    case EDQUOT: return "disk quota exceeded";
    default: break;
    }
    std::string s = strerror(e);
    if (!s.empty() && s[0] >= 'A' && s[0] <= 'Z')
        s[0] = (char)(s[0] - 'A' + 'a');
    return s;
}

/* First line of a library's message, shortened. */
std::string first_line(const std::string &s)
{
    size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos)
        return "no detail";
    size_t b = s.find_first_of("\r\n", a);
    std::string l = s.substr(a, b == std::string::npos ? std::string::npos : b - a);
    if (l.size() > 160)
        l = l.substr(0, 157) + "...";
    return l;
}

/* ---- whole files --------------------------------------------------------------------- */

struct Bytes {
    unsigned char *data = nullptr;
    size_t size = 0;
    Bytes() = default;
    Bytes(const Bytes &) = delete;
    Bytes &operator=(const Bytes &) = delete;
    ~Bytes() { free(data); }
};

/* Reads a whole regular, non-empty file of at most `limit` bytes (NUL appended). */
sr_status read_file(const char *path, size_t limit, Bytes &out, sr_err *err)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd < 0)
        return rfail(err, SR_E_IO, path, "%s", errno_text(errno).c_str());
    struct stat st;
    sr_status rc = SR_OK;
    if (fstat(fd, &st) != 0)
        rc = rfail(err, SR_E_IO, path, "%s", errno_text(errno).c_str());
    else if (S_ISDIR(st.st_mode))
        rc = rfail(err, SR_E_IO, path, "is a directory");
    else if (!S_ISREG(st.st_mode))
        rc = rfail(err, SR_E_IO, path, "not a regular file");
    else if (st.st_size == 0)
        rc = rfail(err, SR_E_IO, path, "empty file");
    else if ((unsigned long long)st.st_size > limit)
        rc = rfail(err, SR_E_UNSUPPORTED, path, "file too large (%lld bytes, at most %zu)",
                   (long long)st.st_size, limit);
    if (rc != SR_OK) {
        close(fd);
        return rc;
    }
    size_t size = (size_t)st.st_size;
    unsigned char *buf = (unsigned char *)malloc(size + 1);
    if (!buf) {
        close(fd);
        return rfail(err, SR_E_NOMEM, path, "out of memory for %zu bytes", size);
    }
    size_t got = 0;
    while (got < size) {
        ssize_t n = read(fd, buf + got, size - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            int e = n < 0 ? errno : 0;
            free(buf);
            close(fd);
            if (e)
                return rfail(err, SR_E_IO, path, "%s", errno_text(e).c_str());
            return rfail(err, SR_E_IO, path, "file shrank while being read");
        }
        got += (size_t)n;
    }
    close(fd);
    buf[size] = 0;
    out.data = buf;
    out.size = size;
    return SR_OK;
}

std::string dir_of(const std::string &path)
{
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos)
        return ".";
    if (slash == 0)
        return "/";
    return path.substr(0, slash);
}

std::atomic<unsigned> temp_counter{0};

/* Writes bytes to path atomically: a new temporary file in the same folder, fsync,
 * rename over path, fsync of the folder. On failure nothing is left behind. */
sr_status write_file_atomic(const char *path, const void *bytes, size_t size, sr_err *err)
{
    std::string dir = dir_of(path);
    std::string tmp;
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; attempt++) {
        tmp = dir + "/.symrec-" + std::to_string((long)getpid()) + "-" +
              std::to_string(temp_counter++) + ".tmp";
        fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST)
            break;
    }
    if (fd < 0) {
        int e = errno;
        struct stat st;
        if ((e == ENOENT || e == ENOTDIR) && stat(dir.c_str(), &st) != 0)
            return wfail(err, SR_E_IO, path, "no such directory '%s'", dir.c_str());
        return wfail(err, SR_E_IO, path, "%s", errno_text(e).c_str());
    }
    const unsigned char *p = (const unsigned char *)bytes;
    size_t done = 0;
    int e = 0;
    while (done < size) {
        ssize_t n = write(fd, p + done, size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            e = n < 0 ? errno : EIO;
            break;
        }
        done += (size_t)n;
    }
    if (!e && fsync(fd) != 0)
        e = errno;
    if (close(fd) != 0 && !e)
        e = errno;
    if (!e && rename(tmp.c_str(), path) != 0)
        e = errno;
    if (e) {
        unlink(tmp.c_str());
        return wfail(err, SR_E_IO, path, "%s", errno_text(e).c_str());
    }
    int dfd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);   /* best effort: some file systems refuse fsync on a directory */
        close(dfd);
    }
    return SR_OK;
}

/* ---- OpenMesh plumbing ---------------------------------------------------------------- */

std::mutex om_mutex;

/* Holds the OpenMesh lock and captures everything OpenMesh prints meanwhile. omerr and
 * omlog are connected to std::cerr and std::clog (omout to std::cout), whose buffers are
 * swapped for ours during the session. (Reconnecting the mostreams instead would leak:
 * OpenMesh's disconnect forgets a target without deleting it.) */
class OmSession {
public:
    OmSession() : lock_(om_mutex)
    {
        static std::once_flag once;
        std::call_once(once, [] {
            omout().disable();   /* std::cout is the CLI's; nothing of OpenMesh goes there */
            omlog().enable();
        });
        cerr_ = std::cerr.rdbuf(text_.rdbuf());
        clog_ = std::clog.rdbuf(text_.rdbuf());
    }
    ~OmSession()
    {
        omerr().flush();   /* a last line without '\n' lands here, not on the console later */
        omlog().flush();
        std::cerr.rdbuf(cerr_);
        std::clog.rdbuf(clog_);
    }
    OmSession(const OmSession &) = delete;
    OmSession &operator=(const OmSession &) = delete;
    std::string text() const { return text_.str(); }

private:
    std::lock_guard<std::mutex> lock_;
    std::ostringstream text_;
    std::streambuf *cerr_ = nullptr, *clog_ = nullptr;
};

/* An istream source over memory we own (no copy). */
class MemBuf : public std::streambuf {
public:
    MemBuf(const unsigned char *p, size_t n)
    {
        char *b = (char *)p;
        setg(b, b, b + n);
    }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir,
                     std::ios_base::openmode which) override
    {
        if (!(which & std::ios_base::in))
            return pos_type(off_type(-1));
        off_type base = dir == std::ios_base::beg   ? 0
                        : dir == std::ios_base::cur ? off_type(gptr() - eback())
                                                    : off_type(egptr() - eback());
        off_type pos = base + off;
        if (pos < 0 || pos > off_type(egptr() - eback()))
            return pos_type(off_type(-1));
        setg(eback(), eback() + pos, egptr());
        return pos_type(pos);
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override
    {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }
};

/* Receives what an OpenMesh reader delivers: vertices and polygons as they come, no
 * topology (which would drop non-manifold faces), nothing else kept. */
class Collector : public OpenMesh::IO::BaseImporter {
public:
    typedef OpenMesh::VertexHandle VH;
    typedef OpenMesh::FaceHandle FH;
    typedef OpenMesh::HalfedgeHandle HH;
    typedef OpenMesh::EdgeHandle EH;

    std::vector<double> xyz;
    std::vector<uint32_t> face_size, face_index;
    size_t bad_faces = 0;           /* faces with an invalid vertex handle */

    VH add_vertex(const OpenMesh::Vec3f &p) override { return push(p[0], p[1], p[2]); }
    VH add_vertex(const OpenMesh::Vec3d &p) override { return push(p[0], p[1], p[2]); }
    VH add_vertex() override { return push(0, 0, 0); }
    void set_point(VH vh, const OpenMesh::Vec3f &p) override
    {
        if (vh.is_valid() && (size_t)vh.idx() < n_vertices())
            for (int k = 0; k < 3; k++)
                xyz[3 * (size_t)vh.idx() + k] = p[k];
    }
    FH add_face(const VHandles &v) override
    {
        for (const VH &h : v)
            if (!h.is_valid() || (size_t)h.idx() >= n_vertices()) {
                bad_faces++;
                return FH();
            }
        face_size.push_back((uint32_t)v.size());
        for (const VH &h : v)
            face_index.push_back((uint32_t)h.idx());
        return FH((int)face_size.size() - 1);
    }
    size_t n_vertices() const override { return xyz.size() / 3; }
    size_t n_faces() const override { return face_size.size(); }
    size_t n_edges() const override { return 0; }

    /* Everything else a reader may hand over is not needed. */
    HH add_edge(VH, VH) override { return HH(); }
    FH add_face(HH) override { return FH(); }
    void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec2f> &) override {}
    void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec3f> &) override {}
    void set_face_texindex(FH, int) override {}
    void set_halfedge(VH, HH) override {}
    void set_normal(VH, const OpenMesh::Vec3f &) override {}
    void set_normal(VH, const OpenMesh::Vec3d &) override {}
    void set_color(VH, const OpenMesh::Vec3uc &) override {}
    void set_color(VH, const OpenMesh::Vec4uc &) override {}
    void set_color(VH, const OpenMesh::Vec3f &) override {}
    void set_color(VH, const OpenMesh::Vec4f &) override {}
    void set_texcoord(VH, const OpenMesh::Vec2f &) override {}
    void set_status(VH, const OpenMesh::Attributes::StatusInfo &) override {}
    void set_next(HH, HH) override {}
    void set_face(HH, FH) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HH, const OpenMesh::Vec2f &) override {}
    void set_texcoord(VH, const OpenMesh::Vec3f &) override {}
    void set_texcoord(HH, const OpenMesh::Vec3f &) override {}
    void set_status(HH, const OpenMesh::Attributes::StatusInfo &) override {}
    void set_color(EH, const OpenMesh::Vec3uc &) override {}
    void set_color(EH, const OpenMesh::Vec4uc &) override {}
    void set_color(EH, const OpenMesh::Vec3f &) override {}
    void set_color(EH, const OpenMesh::Vec4f &) override {}
    void set_status(EH, const OpenMesh::Attributes::StatusInfo &) override {}
    void set_normal(FH, const OpenMesh::Vec3f &) override {}
    void set_normal(FH, const OpenMesh::Vec3d &) override {}
    void set_color(FH, const OpenMesh::Vec3uc &) override {}
    void set_color(FH, const OpenMesh::Vec4uc &) override {}
    void set_color(FH, const OpenMesh::Vec3f &) override {}
    void set_color(FH, const OpenMesh::Vec4f &) override {}
    void set_status(FH, const OpenMesh::Attributes::StatusInfo &) override {}
    void add_texture_information(int, std::string) override {}

private:
    VH push(double x, double y, double z)
    {
        if (n_vertices() >= (size_t)INT_MAX)
            throw std::bad_alloc();   /* OpenMesh handles are int */
        xyz.push_back(x);
        xyz.push_back(y);
        xyz.push_back(z);
        return VH((int)n_vertices() - 1);
    }
};

struct Facts {
    sr_file_facts f = {};
    Facts() = default;
    Facts(const Facts &) = delete;
    Facts &operator=(const Facts &) = delete;
    ~Facts() { sr_file_facts_release(&f); }
};

struct MeshGuard {
    sr_mesh m = {};
    MeshGuard() = default;
    MeshGuard(MeshGuard &&o) noexcept : m(o.m) { o.m = sr_mesh{}; }
    MeshGuard(const MeshGuard &) = delete;
    MeshGuard &operator=(const MeshGuard &) = delete;
    ~MeshGuard() { sr_mesh_release(&m); }
};

/* Float reading of a double agrees with it: OpenMesh parses into float, and may round
 * a decimal string to float directly (one ulp from rounding via double). */
bool float_agrees(double om, double exact)
{
    if (om == exact || om == (double)(float)exact)
        return true;
    double tol = std::max(std::fabs(exact), (double)FLT_MIN) * 2.4e-7;
    return std::fabs(om - exact) <= tol;
}

bool same_corner(const double *a, const double *b)
{
    return std::fabs(a[0] - b[0]) <= FLT_MIN && std::fabs(a[1] - b[1]) <= FLT_MIN &&
           std::fabs(a[2] - b[2]) <= FLT_MIN;
}

bool repeats_vertex(const uint32_t *idx, size_t k)
{
    for (size_t i = 0; i < k; i++)
        for (size_t j = i + 1; j < k; j++)
            if (idx[i] == idx[j])
                return true;
    return false;
}

/* STL: OpenMesh welds corners and drops degenerate facets itself. Its faces must be the
 * file's non-degenerate facets, in order, corner for corner. The result keeps only the
 * vertices those faces use. */
sr_status stl_result(const char *path, const sr_file_facts &f, const Collector &c, sr_mesh *out,
                     sr_err *err)
{
    size_t expect = f.tri_count - f.degenerate_tris;
    size_t got = c.n_faces();
    if (got != expect) {
        if (got < expect)
            return rfail(err, SR_E_FORMAT, path,
                         "OpenMesh lost %zu of %zu triangles (%zu degenerate ones dropped as "
                         "expected)", expect - got, f.tri_count, f.degenerate_tris);
        return rfail(err, SR_E_FORMAT, path, "OpenMesh read %zu triangles, the file holds %zu",
                     got, expect);
    }
    for (size_t i = 0; i < got; i++)
        if (c.face_size[i] != 3)
            return rfail(err, SR_E_FORMAT, path, "OpenMesh made a %u-gon of triangle %zu",
                         c.face_size[i], i);
    size_t facet = 0;
    for (size_t i = 0; i < got; i++, facet++) {
        while (facet < f.tri_count) {
            const double *q = f.xyz + 9 * facet;
            if (!(same_corner(q, q + 3) || same_corner(q, q + 6) || same_corner(q + 3, q + 6)))
                break;
            facet++;
        }
        for (int k = 0; k < 3; k++)
            if (facet >= f.tri_count || !same_corner(&c.xyz[3 * (size_t)c.face_index[3 * i + k]],
                                                     f.xyz + 9 * facet + 3 * k))
                return rfail(err, SR_E_FORMAT, path,
                             "OpenMesh read triangle %zu differently from the file", facet);
    }
    /* Keep used vertices only, in order of first use. */
    std::vector<uint32_t> remap(c.n_vertices(), UINT32_MAX);
    size_t nv = 0;
    for (uint32_t v : c.face_index)
        if (remap[v] == UINT32_MAX)
            remap[v] = (uint32_t)nv++;
    MeshGuard g;
    if (sr_mesh_alloc(&g.m, nv, got) != SR_OK)
        return rfail(err, SR_E_NOMEM, path, "out of memory for %zu triangles", got);
    for (size_t v = 0; v < c.n_vertices(); v++)
        if (remap[v] != UINT32_MAX)
            for (int k = 0; k < 3; k++)
                g.m.xyz[3 * remap[v] + k] = c.xyz[3 * v + k];
    for (size_t i = 0; i < 3 * got; i++)
        g.m.tri[i] = remap[c.face_index[i]];
    *out = g.m;
    g.m = sr_mesh{};
    return SR_OK;
}

/* OBJ/OFF/PLY: OpenMesh must deliver every vertex (to float precision) and every face
 * (all corners) of the file. The result has the file's vertices in double precision and
 * its faces fanned into triangles, faces that repeat a vertex dropped. */
sr_status indexed_result(const char *path, const sr_file_facts &f, const Collector &c,
                         sr_mesh *out, sr_err *err)
{
    if (c.bad_faces)
        return rfail(err, SR_E_INVALID, path, "OpenMesh found %zu faces with a bad vertex index",
                     c.bad_faces);
    if (c.n_vertices() != f.vertex_count)
        return rfail(err, SR_E_FORMAT, path, "OpenMesh read %zu vertices, the file holds %zu",
                     c.n_vertices(), f.vertex_count);
    for (size_t i = 0; i < 3 * f.vertex_count; i++)
        if (!float_agrees(c.xyz[i], f.xyz[i]))
            return rfail(err, SR_E_FORMAT, path,
                         "OpenMesh read vertex %zu as %.9g, the file says %.17g", i / 3,
                         c.xyz[i], f.xyz[i]);
    /* Readers may skip a face that repeats a vertex (OpenMesh's OBJ reader does, its
     * OFF and PLY readers deliver it); every other face must arrive, in order. */
    size_t j = 0, at = 0, at_c = 0, lost = 0, first_lost = 0;
    for (size_t i = 0; i < f.face_count; i++) {
        uint32_t k = f.face_size[i];
        const uint32_t *idx = f.face_index + at;
        at += k;
        if (j < c.n_faces() && c.face_size[j] == k &&
            memcmp(&c.face_index[at_c], idx, k * sizeof(uint32_t)) == 0) {
            at_c += c.face_size[j++];
        } else if (!repeats_vertex(idx, k)) {
            if (!lost++)
                first_lost = i;
        }
    }
    if (j != c.n_faces())
        return rfail(err, SR_E_FORMAT, path, "OpenMesh read face %zu differently from the file",
                     first_lost);
    if (lost)
        return rfail(err, SR_E_FORMAT, path, "OpenMesh lost %zu of %zu faces (first: face %zu)",
                     lost, f.face_count, first_lost);
    size_t tris = f.tri_count - f.degenerate_tris;
    MeshGuard g;
    if (sr_mesh_alloc(&g.m, f.vertex_count, tris) != SR_OK)
        return rfail(err, SR_E_NOMEM, path, "out of memory for %zu triangles", tris);
    if (f.vertex_count)
        memcpy(g.m.xyz, f.xyz, f.vertex_count * 3 * sizeof(double));
    size_t t = 0;
    at = 0;
    for (size_t i = 0; i < f.face_count; i++) {
        const uint32_t *idx = f.face_index + at;
        uint32_t k = f.face_size[i];
        at += k;
        if (repeats_vertex(idx, k))
            continue;
        for (uint32_t j = 1; j + 1 < k; j++) {
            g.m.tri[3 * t] = idx[0];
            g.m.tri[3 * t + 1] = idx[j];
            g.m.tri[3 * t + 2] = idx[j + 1];
            t++;
        }
    }
    *out = g.m;
    g.m = sr_mesh{};
    return SR_OK;
}

sr_status read_openmesh(const char *path, sr_format fmt, Bytes &file, sr_mesh *out,
                        sr_err *err)
{
    Facts facts;
    sr_status st;
    const char *ext;
    switch (fmt) {
    case SR_FMT_STL:
        st = sr_file_check_stl(file.data, file.size, path, &facts.f, err);
        ext = ".stl";
        if (st == SR_OK && !facts.f.binary)
            sr_file_stl_blank_names(file.data, file.size);
        break;
    case SR_FMT_OBJ:
        st = sr_file_check_obj(file.data, file.size, path, &facts.f, err);
        ext = ".obj";
        if (st == SR_OK)
            sr_file_obj_drop_mtllib(file.data, file.size);
        break;
    case SR_FMT_OFF:
        st = sr_file_check_off(file.data, file.size, path, &facts.f, err);
        ext = ".off";
        break;
    case SR_FMT_PLY:
        st = sr_file_check_ply(file.data, file.size, path, &facts.f, err);
        ext = ".ply";
        break;
    default:
        return rfail(err, SR_E_INTERNAL, path, "not an OpenMesh format");
    }
    if (st != SR_OK)
        return st;
    if (facts.f.tri_count == facts.f.degenerate_tris)
        return rfail(err, SR_E_INVALID, path, "contains no triangles%s",
                     facts.f.tri_count ? " (all degenerate)" : "");

    Collector c;
    bool ok;
    std::string log;
    {
        OmSession session;
        MemBuf mb(file.data, file.size);
        std::istream in(&mb);
        OpenMesh::IO::Options opt;
        if (fmt == SR_FMT_STL && facts.f.binary)
            opt += OpenMesh::IO::Options::Binary;
        ok = OpenMesh::IO::IOManager().read(in, ext, c, opt);
        log = session.text();
    }
    if (!ok)
        return rfail(err, SR_E_FORMAT, path, "OpenMesh could not read it (%s)",
                     first_line(log).c_str());
    if (fmt == SR_FMT_STL)
        return stl_result(path, facts.f, c, out, err);
    return indexed_result(path, facts.f, c, out, err);
}

/* ---- glTF reading ------------------------------------------------------------------------ */

/* The input's folder and what the file callbacks refused. */
struct FsGuard {
    std::string folder;       /* realpath of the folder holding the glTF, no trailing '/' */
    std::string refusal;      /* first refusal, for the message when tinygltf fails */
    sr_status refusal_status = SR_OK;
};

int hex_value(unsigned char c)
{
    return c >= '0' && c <= '9' ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : 0;   /* as tinygltf: "%zz" decodes to a NUL byte */
}

/* Exactly as tinygltf's dlib::urldecode, so that we check the name it will open. */
std::string url_decode(const std::string &s)
{
    std::string o;
    for (size_t i = 0; i < s.size(); i++) {
        if (s[i] == '+') {
            o += ' ';
        } else if (s[i] == '%' && s.size() > i + 2) {
            o += (char)(hex_value((unsigned char)s[i + 1]) << 4 |
                        hex_value((unsigned char)s[i + 2]));
            i += 2;
        } else {
            o += s[i];
        }
    }
    return o;
}

/* Checks an external file name (URI already decoded) against the folder policy. On
 * success *full is its path and *size its size. */
sr_status check_external(const FsGuard &g, const std::string &rel, std::string *full,
                         size_t *size, std::string *why)
{
    if (rel.empty()) {
        *why = "is empty";
        return SR_E_INVALID;
    }
    if (rel[0] == '/') {
        *why = "is an absolute path";
        return SR_E_INVALID;
    }
    if (rel.find(':') != std::string::npos || rel.find('\\') != std::string::npos) {
        *why = "is not a plain relative file name";
        return SR_E_INVALID;
    }
    if (rel.find('\0') != std::string::npos) {
        *why = "contains a NUL byte";
        return SR_E_INVALID;
    }
    for (size_t a = 0; a <= rel.size();) {
        size_t b = rel.find('/', a);
        if (b == std::string::npos)
            b = rel.size();
        if (rel.compare(a, b - a, "..") == 0) {
            *why = "leaves the file's folder";
            return SR_E_INVALID;
        }
        a = b + 1;
    }
    std::string p = g.folder + "/" + rel;
    char *real = realpath(p.c_str(), nullptr);
    if (!real) {
        *why = errno == ENOENT ? "does not exist" : "cannot be opened: " + errno_text(errno);
        return SR_E_IO;
    }
    std::string r(real);
    free(real);
    if (r.compare(0, g.folder.size() + 1, g.folder + "/") != 0) {
        *why = "leaves the file's folder (through a link)";
        return SR_E_INVALID;
    }
    struct stat st;
    if (stat(r.c_str(), &st) != 0) {
        *why = "cannot be opened: " + errno_text(errno);
        return SR_E_IO;
    }
    if (S_ISDIR(st.st_mode)) {
        *why = "names a directory";
        return SR_E_INVALID;
    }
    if (!S_ISREG(st.st_mode)) {
        *why = "is not a regular file";
        return SR_E_INVALID;
    }
    if ((unsigned long long)st.st_size > GLTF_BUFFER_MAX) {
        *why = "is larger than " + std::to_string(GLTF_BUFFER_MAX) + " bytes";
        return SR_E_UNSUPPORTED;
    }
    *full = r;
    *size = (size_t)st.st_size;
    return SR_OK;
}

/* tinygltf asks for JoinPath(base_dir, uri) and then JoinPath(".", uri); only names
 * under our folder are answered, the working directory never. */
bool fs_relative(const FsGuard &g, const std::string &abs, std::string *rel)
{
    std::string prefix = g.folder + "/";
    if (abs.compare(0, prefix.size(), prefix) != 0)
        return false;
    *rel = abs.substr(prefix.size());
    return true;
}

void note_refusal(FsGuard &g, sr_status st, const std::string &rel, const std::string &why)
{
    if (g.refusal.empty()) {
        g.refusal = "external file '" + rel + "' " + why;
        g.refusal_status = st;
    }
}

bool fs_file_exists(const std::string &abs, void *ud)
{
    FsGuard &g = *(FsGuard *)ud;
    std::string rel, full, why;
    size_t size;
    if (!fs_relative(g, abs, &rel))
        return false;
    sr_status st = check_external(g, rel, &full, &size, &why);
    if (st != SR_OK)
        note_refusal(g, st, rel, why);
    return st == SR_OK;
}

std::string fs_expand(const std::string &path, void *) { return path; }

bool fs_read(std::vector<unsigned char> *out, std::string *terr, const std::string &abs, void *ud)
{
    FsGuard &g = *(FsGuard *)ud;
    std::string rel, full, why;
    size_t size;
    sr_status st = fs_relative(g, abs, &rel) ? check_external(g, rel, &full, &size, &why)
                                             : SR_E_INVALID;
    if (st != SR_OK) {
        note_refusal(g, st, rel.empty() ? abs : rel, why.empty() ? "is outside the folder" : why);
        if (terr)
            *terr = "refused";
        return false;
    }
    Bytes b;
    if (read_file(full.c_str(), GLTF_BUFFER_MAX, b, nullptr) != SR_OK) {
        note_refusal(g, SR_E_IO, rel, "cannot be read");
        if (terr)
            *terr = "cannot be read";
        return false;
    }
    out->assign(b.data, b.data + b.size);
    return true;
}

bool fs_write(std::string *terr, const std::string &, const std::vector<unsigned char> &, void *)
{
    if (terr)
        *terr = "writing is disabled";
    return false;
}

bool no_images(tinygltf::Image *, const int, std::string *, std::string *, int, int,
               const unsigned char *, int, void *)
{
    return true;   /* images are not decoded: symrec needs geometry only */
}

/* Decoded size of a base64 data URI payload, or -1 when it is not base64. */
long long base64_size(const std::string &uri)
{
    size_t comma = uri.find(',');
    if (comma == std::string::npos || uri.rfind(";base64", comma) == std::string::npos)
        return -1;
    size_t n = uri.size() - comma - 1;
    if (n % 4)
        return -1;
    size_t pad = 0;
    if (n >= 1 && uri[uri.size() - 1] == '=')
        pad++;
    if (n >= 2 && uri[uri.size() - 2] == '=')
        pad++;
    return (long long)(n / 4 * 3 - pad);
}

/* Buffers declared in the JSON against the bytes that back them, before tinygltf. */
sr_status gltf_precheck(const char *path, const unsigned char *json, size_t n,
                        const sr_glb_layout *glb, const FsGuard &g, sr_err *err)
{
    sr_status st = sr_file_check_json_depth(json, n, JSON_DEPTH_MAX, path, err);
    if (st != SR_OK)
        return st;
    nlohmann::json j = nlohmann::json::parse(json, json + n, nullptr, false);
    if (j.is_discarded() || !j.is_object())
        return rfail(err, SR_E_FORMAT, path, "malformed glTF JSON");
    auto bufs = j.find("buffers");
    if (bufs == j.end())
        return SR_OK;
    if (!bufs->is_array())
        return rfail(err, SR_E_FORMAT, path, "glTF 'buffers' is not an array");
    for (size_t i = 0; i < bufs->size(); i++) {
        const nlohmann::json &b = (*bufs)[i];
        if (!b.is_object())
            return rfail(err, SR_E_FORMAT, path, "buffer %zu is not an object", i);
        auto bl = b.find("byteLength");
        if (bl == b.end() || !bl->is_number() || bl->get<double>() < 1 ||
            bl->get<double>() != std::floor(bl->get<double>()))
            return rfail(err, SR_E_FORMAT, path, "buffer %zu has no valid byteLength", i);
        double len = bl->get<double>();
        auto u = b.find("uri");
        if (u != b.end() && !u->is_string())
            return rfail(err, SR_E_FORMAT, path, "buffer %zu uri is not a string", i);
        if (u == b.end()) {
            if (!glb || i != 0)
                return rfail(err, SR_E_FORMAT, path, "buffer %zu has no uri", i);
            if (!glb->has_bin)
                return rfail(err, SR_E_FORMAT, path,
                             "buffer 0 needs the GLB BIN chunk, there is none");
            if (len > (double)glb->bin_size)
                return rfail(
                    err, SR_E_FORMAT, path,
                    "buffer 0 declares byteLength %.0f but the GLB BIN chunk holds %zu bytes", len,
                    glb->bin_size);
            continue;
        }
        std::string uri = u->get<std::string>();
        if (uri.compare(0, 5, "data:") == 0) {
            long long have = base64_size(uri);
            if (have < 0)
                return rfail(err, SR_E_FORMAT, path, "buffer %zu data URI is not base64", i);
            if (len != (double)have)
                return rfail(
                    err, SR_E_FORMAT, path,
                    "buffer %zu declares byteLength %.0f but its data URI holds %lld bytes", i, len,
                    have);
            continue;
        }
        std::string rel = url_decode(uri), full, why;
        size_t size = 0;
        st = check_external(g, rel, &full, &size, &why);
        if (st != SR_OK)
            return rfail(err, st, path, "buffer %zu uri '%s' %s", i, rel.c_str(), why.c_str());
        if (len != (double)size)
            return rfail(err, SR_E_FORMAT, path,
                         "buffer %zu declares byteLength %.0f but '%s' holds %zu bytes", i, len,
                         rel.c_str(), size);
    }
    return SR_OK;
}

const char *const IGNORABLE_EXTENSIONS[] = {"KHR_materials_", "KHR_texture_",
                                            "KHR_lights_punctual"};

sr_status gltf_load(const char *path, sr_format fmt, tinygltf::Model &model, sr_err *err)
{
    Bytes file;
    sr_status st = read_file(path, GLTF_FILE_MAX, file, err);
    if (st != SR_OK)
        return st;
    FsGuard g;
    {
        std::string dir = dir_of(path);
        char *real = realpath(dir.c_str(), nullptr);
        if (!real)
            return rfail(err, SR_E_IO, path, "cannot resolve its folder: %s",
                         errno_text(errno).c_str());
        g.folder = real;
        free(real);
        if (g.folder == "/")
            g.folder.clear();   /* so that folder + "/" is "/" */
    }
    sr_glb_layout glb = {};
    bool binary = fmt == SR_FMT_GLB;
    if (binary) {
        st = sr_file_check_glb(file.data, file.size, path, &glb, err);
        if (st != SR_OK)
            return st;
        st = gltf_precheck(path, file.data + glb.json_offset, glb.json_size, &glb, g, err);
    } else {
        st = gltf_precheck(path, file.data, file.size, nullptr, g, err);
    }
    if (st != SR_OK)
        return st;

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(no_images, nullptr);
    tinygltf::FsCallbacks fs = {fs_file_exists, fs_expand, fs_read, fs_write, &g};
    loader.SetFsCallbacks(fs);
    loader.SetStoreOriginalJSONForExtrasAndExtensions(true);
    std::string terr, twarn;
    bool ok = binary ? loader.LoadBinaryFromMemory(&model, &terr, &twarn, file.data,
                                                   (unsigned)file.size, g.folder)
                     : loader.LoadASCIIFromString(&model, &terr, &twarn, (const char *)file.data,
                                                  (unsigned)file.size, g.folder);
    if (!ok) {
        if (!g.refusal.empty())
            return rfail(err, g.refusal_status, path, "%s", g.refusal.c_str());
        return rfail(err, SR_E_FORMAT, path, "tinygltf: %s", first_line(terr).c_str());
    }
    for (const std::string &ext : model.extensionsRequired) {
        bool fine = false;
        for (const char *ok_ext : IGNORABLE_EXTENSIONS)
            fine |= ext.compare(0, strlen(ok_ext), ok_ext) == 0;
        if (!fine)
            return rfail(err, SR_E_UNSUPPORTED, path, "requires glTF extension '%s'", ext.c_str());
    }
    return SR_OK;
}

/* One accessor's bytes, range-checked against its bufferView and buffer. */
struct View {
    const unsigned char *base = nullptr;
    size_t stride = 0, count = 0;
    int component = 0;
};

sr_status accessor_view(const char *path, const tinygltf::Model &m, int index, const char *what,
                        size_t mesh, View *out, sr_err *err)
{
    if (index < 0 || (size_t)index >= m.accessors.size())
        return rfail(err, SR_E_FORMAT, path, "mesh %zu: %s accessor %d does not exist", mesh,
                     what, index);
    const tinygltf::Accessor &a = m.accessors[(size_t)index];
    if (a.sparse.isSparse)
        return rfail(err, SR_E_UNSUPPORTED, path, "mesh %zu: sparse %s accessor %d", mesh, what,
                     index);
    if (a.bufferView < 0 || (size_t)a.bufferView >= m.bufferViews.size())
        return rfail(err, SR_E_FORMAT, path, "mesh %zu: %s accessor %d has no bufferView", mesh,
                     what, index);
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
    if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
        return rfail(err, SR_E_FORMAT, path, "bufferView %d refers to no buffer", a.bufferView);
    const std::vector<unsigned char> &buf = m.buffers[(size_t)bv.buffer].data;
    if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset)
        return rfail(err, SR_E_FORMAT, path,
                     "bufferView %d (offset %zu, length %zu) runs past buffer %d (%zu bytes)",
                     a.bufferView, bv.byteOffset, bv.byteLength, bv.buffer, buf.size());
    size_t comp = 0;
    switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: comp = 1; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: comp = 2; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: comp = 4; break;
    case TINYGLTF_COMPONENT_TYPE_FLOAT: comp = 4; break;
    default: break;
    }
    bool position = strcmp(what, "POSITION") == 0;
    if (position
            ? (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.type != TINYGLTF_TYPE_VEC3)
            : (comp == 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
               a.type != TINYGLTF_TYPE_SCALAR))
        return rfail(err, SR_E_FORMAT, path,
                     "mesh %zu: %s accessor %d has component type %d, type %d (need %s)", mesh,
                     what, index, a.componentType, a.type,
                     position ? "float VEC3" : "unsigned byte/short/int SCALAR");
    size_t elem = comp * (position ? 3 : 1);
    size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (bv.byteStride && (bv.byteStride < elem || bv.byteStride > 252 || bv.byteStride % 4))
        return rfail(err, SR_E_FORMAT, path, "bufferView %d has a bad byteStride %zu",
                     a.bufferView, bv.byteStride);
    if (a.count == 0)
        return rfail(err, SR_E_FORMAT, path, "mesh %zu: %s accessor %d is empty", mesh, what,
                     index);
    /* offset + (count - 1) * stride + elem <= byteLength, without overflow */
    if (a.byteOffset > bv.byteLength || elem > bv.byteLength - a.byteOffset ||
        (a.count - 1) > (bv.byteLength - a.byteOffset - elem) / stride)
        return rfail(err, SR_E_FORMAT, path,
                     "mesh %zu: %s accessor %d (offset %zu, %zu elements of %zu bytes, stride %zu) "
                     "runs past its bufferView (%zu bytes)",
                     mesh, what, index, a.byteOffset, a.count, elem, stride, bv.byteLength);
    out->base = buf.data() + bv.byteOffset + a.byteOffset;
    out->stride = stride;
    out->count = a.count;
    out->component = a.componentType;
    return SR_OK;
}

uint32_t rd_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

uint32_t view_index(const View &v, size_t i)
{
    const unsigned char *p = v.base + i * v.stride;
    switch (v.component) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return (uint32_t)(p[0] | p[1] << 8);
    default: return rd_le32(p);
    }
}

/* The triangles of glTF mesh `mi` (all its triangle primitives; points and lines are
 * not surfaces and are skipped), untransformed. Triangles that repeat a vertex are
 * dropped, as the other readers do. */
sr_status gltf_mesh(const char *path, const tinygltf::Model &m, size_t mi, sr_mesh *out,
                    sr_err *err)
{
    const tinygltf::Mesh &mesh = m.meshes[mi];
    std::vector<double> xyz;
    std::vector<uint32_t> tri;
    std::map<int, uint32_t> base_of;   /* POSITION accessor -> first vertex */
    for (size_t pi = 0; pi < mesh.primitives.size(); pi++) {
        const tinygltf::Primitive &p = mesh.primitives[pi];
        int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
        if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE ||
            mode == TINYGLTF_MODE_LINE_LOOP || mode == TINYGLTF_MODE_LINE_STRIP)
            continue;
        if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            mode != TINYGLTF_MODE_TRIANGLE_FAN)
            return rfail(err, SR_E_FORMAT, path, "mesh %zu primitive %zu has unknown mode %d",
                         mi, pi, p.mode);
        auto pos = p.attributes.find("POSITION");
        if (pos == p.attributes.end())
            return rfail(err, SR_E_FORMAT, path, "mesh %zu primitive %zu has no POSITION", mi, pi);
        View pv;
        sr_status st = accessor_view(path, m, pos->second, "POSITION", mi, &pv, err);
        if (st != SR_OK)
            return st;
        uint32_t base;
        auto known = base_of.find(pos->second);
        if (known != base_of.end()) {
            base = known->second;
        } else {
            if (xyz.size() / 3 + pv.count > SR_MESH_MAX_COUNT)
                return rfail(err, SR_E_FORMAT, path, "mesh %zu has too many vertices", mi);
            base = (uint32_t)(xyz.size() / 3);
            base_of[pos->second] = base;
            for (size_t v = 0; v < pv.count; v++)
                for (int k = 0; k < 3; k++) {
                    uint32_t u = rd_le32(pv.base + v * pv.stride + 4 * (size_t)k);
                    float f;
                    memcpy(&f, &u, sizeof f);
                    if (!std::isfinite(f))
                        return rfail(err, SR_E_INVALID, path,
                                     "mesh %zu primitive %zu vertex %zu has %s coordinate", mi,
                                     pi, v, std::isnan(f) ? "a NaN" : "an infinite");
                    xyz.push_back(f);
                }
        }
        View iv;
        size_t n = pv.count;
        if (p.indices >= 0) {
            st = accessor_view(path, m, p.indices, "indices", mi, &iv, err);
            if (st != SR_OK)
                return st;
            n = iv.count;
        }
        auto corner = [&](size_t i) { return p.indices >= 0 ? view_index(iv, i) : (uint32_t)i; };
        if (mode == TINYGLTF_MODE_TRIANGLES && n % 3)
            return rfail(err, SR_E_FORMAT, path,
                         "mesh %zu primitive %zu has %zu indices, not a multiple of 3", mi, pi, n);
        for (size_t i = 0; i < n; i++)
            if (corner(i) >= pv.count)
                return rfail(
                    err, SR_E_INVALID, path,
                    "mesh %zu primitive %zu index %zu is %u, not below the vertex count %zu", mi,
                    pi, i, corner(i), pv.count);
        size_t tcount = mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 3 ? n - 2 : 0);
        for (size_t t = 0; t < tcount; t++) {
            uint32_t a, b, c;
            if (mode == TINYGLTF_MODE_TRIANGLES) {
                a = corner(3 * t), b = corner(3 * t + 1), c = corner(3 * t + 2);
            } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                a = corner(t), b = corner(t + 1 + t % 2), c = corner(t + 2 - t % 2);
            } else {
                a = corner(t + 1), b = corner(t + 2), c = corner(0);
            }
            if (a == b || b == c || a == c)
                continue;
            tri.push_back(base + a);
            tri.push_back(base + b);
            tri.push_back(base + c);
        }
    }
    MeshGuard g;
    if (sr_mesh_alloc(&g.m, xyz.size() / 3, tri.size() / 3) != SR_OK)
        return rfail(err, SR_E_NOMEM, path, "out of memory for mesh %zu", mi);
    if (!xyz.empty())
        memcpy(g.m.xyz, xyz.data(), xyz.size() * sizeof(double));
    if (!tri.empty())
        memcpy(g.m.tri, tri.data(), tri.size() * sizeof(uint32_t));
    *out = g.m;
    g.m = sr_mesh{};
    return SR_OK;
}

/* A node's local transform as 3x4 row-major (mesh.h layout). */
void node_xform(const tinygltf::Node &n, double m[12])
{
    sr_xform_identity(m);
    if (n.matrix.size() == 16) {
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                m[4 * r + c] = n.matrix[4 * (size_t)c + (size_t)r];   /* glTF is column-major */
        return;
    }
    double q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1}, t[3] = {0, 0, 0};
    if (n.rotation.size() == 4)
        for (int k = 0; k < 4; k++)
            q[k] = n.rotation[(size_t)k];
    if (n.scale.size() == 3)
        for (int k = 0; k < 3; k++)
            s[k] = n.scale[(size_t)k];
    if (n.translation.size() == 3)
        for (int k = 0; k < 3; k++)
            t[k] = n.translation[(size_t)k];
    double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (len > 0)
        for (double &v : q)
            v /= len;
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                      {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                      {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            m[4 * r + c] = R[r][c] * s[c];
        m[4 * r + 3] = t[r];
    }
}

struct Instance {
    int mesh;
    double xf[12];
};

sr_status visit_node(const char *path, const tinygltf::Model &m, int ni, const double parent[12],
                     int depth, std::vector<Instance> &out, sr_err *err)
{
    if (ni < 0 || (size_t)ni >= m.nodes.size())
        return rfail(err, SR_E_FORMAT, path, "node %d does not exist", ni);
    if (depth > NODE_DEPTH_MAX)
        return rfail(err, SR_E_FORMAT, path, "node hierarchy deeper than %d levels (a cycle?)",
                     NODE_DEPTH_MAX);
    const tinygltf::Node &n = m.nodes[(size_t)ni];
    Instance in;
    double local[12];
    node_xform(n, local);
    sr_xform_mul(in.xf, parent, local);
    if (n.mesh >= 0) {
        if ((size_t)n.mesh >= m.meshes.size())
            return rfail(err, SR_E_FORMAT, path, "node %d refers to mesh %d, which does not exist",
                         ni, n.mesh);
        in.mesh = n.mesh;
        out.push_back(in);
    }
    for (int child : n.children) {
        sr_status st = visit_node(path, m, child, in.xf, depth + 1, out, err);
        if (st != SR_OK)
            return st;
    }
    return SR_OK;
}

/* Mesh instances of the default scene (or scene 0); every mesh once, untransformed,
 * when the file has no scene. */
sr_status gltf_instances(const char *path, const tinygltf::Model &m, std::vector<Instance> &out,
                         sr_err *err)
{
    double id[12];
    sr_xform_identity(id);
    if (m.scenes.empty()) {
        for (size_t i = 0; i < m.meshes.size(); i++) {
            Instance in;
            in.mesh = (int)i;
            memcpy(in.xf, id, sizeof id);
            out.push_back(in);
        }
        return SR_OK;
    }
    size_t s = m.defaultScene >= 0 && (size_t)m.defaultScene < m.scenes.size()
                   ? (size_t)m.defaultScene : 0;
    for (int root : m.scenes[s].nodes) {
        sr_status st = visit_node(path, m, root, id, 0, out, err);
        if (st != SR_OK)
            return st;
    }
    return SR_OK;
}

double det3(const double m[12])
{
    return m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
           m[2] * (m[4] * m[9] - m[5] * m[8]);
}

/* A mesh copy placed by a node transform; a mirroring transform flips the triangles so
 * that they stay outward-facing. */
sr_status place(const sr_mesh &src, const double xf[12], sr_mesh *out)
{
    sr_mesh c;
    sr_status st = sr_mesh_copy(&c, &src);
    if (st != SR_OK)
        return st;
    sr_mesh_transform(&c, xf);
    if (det3(xf) < 0)
        sr_mesh_flip(&c);
    *out = c;
    return SR_OK;
}

sr_status read_gltf_merged(const char *path, sr_format fmt, sr_mesh *out, sr_err *err)
{
    tinygltf::Model model;
    sr_status st = gltf_load(path, fmt, model, err);
    if (st != SR_OK)
        return st;
    std::vector<Instance> inst;
    st = gltf_instances(path, model, inst, err);
    if (st != SR_OK)
        return st;
    std::vector<MeshGuard> meshes(model.meshes.size());
    std::vector<bool> done(model.meshes.size(), false);
    MeshGuard all;
    for (const Instance &in : inst) {
        size_t mi = (size_t)in.mesh;
        if (!done[mi]) {
            st = gltf_mesh(path, model, mi, &meshes[mi].m, err);
            if (st != SR_OK)
                return st;
            done[mi] = true;
        }
        if (meshes[mi].m.tri_count == 0)
            continue;
        MeshGuard placed;
        if (place(meshes[mi].m, in.xf, &placed.m) != SR_OK ||
            sr_mesh_append(&all.m, &placed.m) != SR_OK)
            return rfail(err, SR_E_NOMEM, path, "out of memory merging mesh %zu", mi);
    }
    if (all.m.tri_count == 0)
        return rfail(err, SR_E_INVALID, path, "contains no triangles");
    *out = all.m;
    all.m = sr_mesh{};
    return SR_OK;
}

/* ---- writing ------------------------------------------------------------------------------ */

void put_num(std::string &s, double v)
{
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);   /* shortest round-trip, '.' always */
    s.append(buf, r.ptr);
}

void put_uint(std::string &s, unsigned long long v)
{
    char buf[24];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

void put_le32(std::string &s, uint32_t u)
{
    char b[4] = {(char)(u & 0xff), (char)(u >> 8 & 0xff), (char)(u >> 16 & 0xff), (char)(u >> 24)};
    s.append(b, 4);
}

void put_le64(std::string &s, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put_le32(s, (uint32_t)u);
    put_le32(s, (uint32_t)(u >> 32));
}

std::string encode_text(const sr_mesh &m, sr_format fmt, bool ascii)
{
    std::string s;
    s.reserve(m.vertex_count * 60 + m.tri_count * 30 + 256);
    if (fmt == SR_FMT_OBJ) {
        s += "# written by symrec\n";
    } else if (fmt == SR_FMT_OFF) {
        s += "OFF\n";
        put_uint(s, m.vertex_count);
        s += ' ';
        put_uint(s, m.tri_count);
        s += " 0\n";
    } else {
        s += "ply\nformat ";
        s += ascii ? "ascii" : "binary_little_endian";
        s += " 1.0\ncomment written by symrec\nelement vertex ";
        put_uint(s, m.vertex_count);
        s += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
        put_uint(s, m.tri_count);
        s += "\nproperty list uchar uint vertex_indices\nend_header\n";
        if (!ascii) {
            for (size_t i = 0; i < 3 * m.vertex_count; i++)
                put_le64(s, m.xyz[i]);
            for (size_t t = 0; t < m.tri_count; t++) {
                s += (char)3;
                for (int k = 0; k < 3; k++)
                    put_le32(s, m.tri[3 * t + (size_t)k]);
            }
            return s;
        }
    }
    for (size_t v = 0; v < m.vertex_count; v++) {
        if (fmt == SR_FMT_OBJ)
            s += "v ";
        for (int k = 0; k < 3; k++) {
            put_num(s, m.xyz[3 * v + (size_t)k]);
            s += k < 2 ? ' ' : '\n';
        }
    }
    unsigned base = fmt == SR_FMT_OBJ ? 1 : 0;
    for (size_t t = 0; t < m.tri_count; t++) {
        s += fmt == SR_FMT_OBJ ? "f " : "3 ";
        for (int k = 0; k < 3; k++) {
            put_uint(s, (unsigned long long)m.tri[3 * t + (size_t)k] + base);
            s += k < 2 ? ' ' : '\n';
        }
    }
    return s;
}

/* STL through OpenMesh, into memory. Triangles that repeat a vertex cannot be stored
 * (and no reader would keep them); non-manifold ones are kept by duplicating vertices,
 * as OpenMesh's importer does. */
sr_status encode_stl(const char *path, const sr_mesh &m, bool ascii, std::string *out, sr_err *err)
{
    size_t expect = 0;
    for (size_t t = 0; t < m.tri_count; t++)
        expect += !repeats_vertex(m.tri + 3 * t, 3);
    if (expect == 0)
        return wfail(err, SR_E_INVALID, path, "mesh has no non-degenerate triangles");
    for (size_t i = 0; i < 3 * m.vertex_count; i++)
        if (!std::isfinite((float)m.xyz[i]))
            return wfail(err, SR_E_RANGE, path, "vertex %zu is beyond float range for STL", i / 3);
    OmMesh om;
    std::ostringstream os;
    bool ok;
    size_t faces;
    std::string log;
    {
        OmSession session;
        OpenMesh::IO::ImporterT<OmMesh> imp(om);
        imp.reserve((unsigned)m.vertex_count, (unsigned)(3 * m.tri_count), (unsigned)m.tri_count);
        std::vector<OpenMesh::VertexHandle> vh(m.vertex_count);
        for (size_t v = 0; v < m.vertex_count; v++)
            vh[v] =
                imp.add_vertex(OpenMesh::Vec3d(m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]));
        OpenMesh::IO::BaseImporter::VHandles f(3);
        for (size_t t = 0; t < m.tri_count; t++) {
            if (repeats_vertex(m.tri + 3 * t, 3))
                continue;
            for (int k = 0; k < 3; k++)
                f[(size_t)k] = vh[m.tri[3 * t + (size_t)k]];
            imp.add_face(f);
        }
        faces = om.n_faces();
        OpenMesh::IO::Options opt = ascii ? OpenMesh::IO::Options::Default
                                          : OpenMesh::IO::Options::Binary;
        ok = faces == expect && OpenMesh::IO::write_mesh(om, os, ".stl", opt, 17);
        log = session.text();
    }
    if (faces != expect)
        return wfail(err, SR_E_INTERNAL, path, "OpenMesh kept %zu of %zu triangles", faces, expect);
    if (!ok)
        return wfail(err, SR_E_INTERNAL, path, "OpenMesh could not write STL (%s)",
                     first_line(log).c_str());
    *out = os.str();
    if (!ascii) {
        if (out->size() != 84 + 50 * expect ||
            rd_le32((const unsigned char *)out->data() + 80) != expect)
            return wfail(err, SR_E_INTERNAL, path,
                         "OpenMesh wrote %zu bytes of binary STL, %zu triangles need %zu",
                         out->size(), expect, 84 + 50 * expect);
    } else {
        size_t n = 0;
        for (size_t at = out->find("endfacet"); at != std::string::npos;
             at = out->find("endfacet", at + 8))
            n++;
        if (n != expect)
            return wfail(err, SR_E_INTERNAL, path, "OpenMesh wrote %zu of %zu facets", n, expect);
    }
    return SR_OK;
}

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

/* JSON text to a tinygltf Value (Value(int) is 32-bit: larger integers become doubles). */
tinygltf::Value to_value(const nlohmann::json &j)
{
    switch (j.type()) {
    case nlohmann::json::value_t::boolean: return tinygltf::Value(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: {
        if (j.is_number_unsigned()
                ? j.get<unsigned long long>() <= (unsigned long long)INT_MAX
                : (j.get<long long>() >= INT_MIN && j.get<long long>() <= INT_MAX))
            return tinygltf::Value(j.get<int>());
        return tinygltf::Value(j.get<double>());
    }
    case nlohmann::json::value_t::number_float: return tinygltf::Value(j.get<double>());
    case nlohmann::json::value_t::string: return tinygltf::Value(j.get<std::string>());
    case nlohmann::json::value_t::array: {
        tinygltf::Value::Array a;
        for (const auto &e : j)
            a.push_back(to_value(e));
        return tinygltf::Value(std::move(a));
    }
    case nlohmann::json::value_t::object: {
        tinygltf::Value::Object o;
        for (auto it = j.begin(); it != j.end(); ++it)
            o[it.key()] = to_value(it.value());
        return tinygltf::Value(std::move(o));
    }
    default: return tinygltf::Value();
    }
}

/* The shortest decimal that reads back as f (0.8f is written 0.8, not 0.800000011920929). */
double float_decimal(float f)
{
    char b[32];
    auto r = std::to_chars(b, b + sizeof b, f);
    double d = f;
    std::from_chars(b, r.ptr, d);
    return d;
}

void append_bytes(std::vector<unsigned char> &buf, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    buf.insert(buf.end(), b, b + n);
}

sr_status scene_write(const char *path, const sr_scene_mesh *meshes, size_t count,
                      const char *extras_json, sr_err *err)
{
    sr_format fmt = sr_format_from_path(path);
    if (fmt != SR_FMT_GLTF && fmt != SR_FMT_GLB)
        return wfail(err, SR_E_UNSUPPORTED, path, "a scene needs a .gltf or .glb name");
    if (count == 0 || !meshes)
        return wfail(err, SR_E_INVALID, path, "scene has no meshes");
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "symrec";
    if (extras_json) {
        if (sr_file_check_json_depth((const unsigned char *)extras_json, strlen(extras_json),
                                     JSON_DEPTH_MAX, path, nullptr) != SR_OK)
            return wfail(err, SR_E_INVALID, path, "extras nest deeper than %zu levels",
                         JSON_DEPTH_MAX);
        nlohmann::json j = nlohmann::json::parse(extras_json, nullptr, false);
        if (j.is_discarded() || !j.is_object())
            return wfail(err, SR_E_INVALID, path, "extras are not a JSON object");
        model.asset.extras = to_value(j);
    }
    std::vector<unsigned char> bin;
    tinygltf::Scene scene;
    for (size_t i = 0; i < count; i++) {
        const sr_scene_mesh &sm = meshes[i];
        char what[32];
        snprintf(what, sizeof what, "mesh %zu", i);
        sr_status st = check_for_write(path, sm.mesh, what, err);
        if (st != SR_OK)
            return st;
        for (int k = 0; k < 4; k++)
            if (!(sm.rgba[k] >= 0.0f && sm.rgba[k] <= 1.0f))
                return wfail(err, SR_E_RANGE, path,
                             "mesh %zu colour component %d is %g, not in 0..1", i, k,
                             (double)sm.rgba[k]);
        const sr_mesh &m = *sm.mesh;
        size_t pos_bytes = m.vertex_count * 12, idx_bytes = m.tri_count * 12;
        if (bin.size() + pos_bytes + idx_bytes > (size_t)INT32_MAX)
            return wfail(err, SR_E_RANGE, path,
                         "scene too large for glTF (over %d bytes of geometry)", INT32_MAX);
        /* positions, float32, with min/max as the spec requires */
        std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
        size_t pos_off = bin.size();
        for (size_t v = 0; v < m.vertex_count; v++)
            for (int k = 0; k < 3; k++) {
                float f = (float)m.xyz[3 * v + (size_t)k];
                if (!std::isfinite(f))
                    return wfail(err, SR_E_RANGE, path, "mesh %zu vertex %zu is beyond float range",
                                 i, v);
                lo[(size_t)k] = std::min(lo[(size_t)k], (double)f);
                hi[(size_t)k] = std::max(hi[(size_t)k], (double)f);
                uint32_t u;
                memcpy(&u, &f, 4);
                unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8),
                                      (unsigned char)(u >> 16), (unsigned char)(u >> 24)};
                append_bytes(bin, b, 4);
            }
        size_t idx_off = bin.size();
        for (size_t t = 0; t < 3 * m.tri_count; t++) {
            uint32_t u = m.tri[t];
            unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8),
                                  (unsigned char)(u >> 16), (unsigned char)(u >> 24)};
            append_bytes(bin, b, 4);
        }
        /* both views are multiples of 4 bytes long, so every view starts 4-aligned */
        tinygltf::BufferView pv, iv;
        pv.buffer = iv.buffer = 0;
        pv.byteOffset = pos_off;
        pv.byteLength = pos_bytes;
        pv.target = TINYGLTF_TARGET_ARRAY_BUFFER;
        iv.byteOffset = idx_off;
        iv.byteLength = idx_bytes;
        iv.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
        int pvi = (int)model.bufferViews.size();
        model.bufferViews.push_back(pv);
        model.bufferViews.push_back(iv);
        tinygltf::Accessor pa, ia;
        pa.bufferView = pvi;
        pa.byteOffset = 0;
        pa.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        pa.count = m.vertex_count;
        pa.type = TINYGLTF_TYPE_VEC3;
        pa.minValues = lo;
        pa.maxValues = hi;
        ia.bufferView = pvi + 1;
        ia.byteOffset = 0;
        ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        ia.count = 3 * m.tri_count;
        ia.type = TINYGLTF_TYPE_SCALAR;
        int pai = (int)model.accessors.size();
        model.accessors.push_back(pa);
        model.accessors.push_back(ia);

        tinygltf::Material mat;
        mat.name = sm.name ? sm.name : "";
        mat.pbrMetallicRoughness.baseColorFactor = {
            float_decimal(sm.rgba[0]), float_decimal(sm.rgba[1]), float_decimal(sm.rgba[2]),
            float_decimal(sm.rgba[3])};
        mat.pbrMetallicRoughness.metallicFactor = 0.0;   /* plain colour, readable in any viewer */
        mat.doubleSided = false;
        mat.alphaMode = sm.rgba[3] < 1.0f ? "BLEND" : "OPAQUE";
        model.materials.push_back(mat);

        tinygltf::Primitive prim;
        prim.attributes["POSITION"] = pai;
        prim.indices = pai + 1;
        prim.material = (int)i;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        tinygltf::Mesh gm;
        gm.name = sm.name ? sm.name : "";
        gm.primitives.push_back(prim);
        model.meshes.push_back(gm);

        tinygltf::Node node;
        node.name = gm.name;
        node.mesh = (int)i;
        model.nodes.push_back(node);
        scene.nodes.push_back((int)i);
    }
    tinygltf::Buffer buffer;
    buffer.data = std::move(bin);
    model.buffers.push_back(std::move(buffer));
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    std::ostringstream os;
    tinygltf::TinyGLTF w;
    bool glb = fmt == SR_FMT_GLB;
    if (!w.WriteGltfSceneToStream(&model, os, !glb, glb))
        return wfail(err, SR_E_INTERNAL, path, "tinygltf could not serialise the scene");
    std::string bytes = os.str();
    if (glb) {
        sr_glb_layout layout;
        sr_err inner;
        if (sr_file_check_glb((const unsigned char *)bytes.data(), bytes.size(), path, &layout,
                              &inner) != SR_OK ||
            !layout.has_bin)
            return wfail(err, SR_E_INTERNAL, path, "tinygltf wrote a bad GLB (%s)", inner.msg);
    }
    return write_file_atomic(path, bytes.data(), bytes.size(), err);
}

sr_status scene_read(const char *path, sr_scene *out, sr_err *err)
{
    sr_format fmt = sr_format_from_path(path);
    if (fmt != SR_FMT_GLTF && fmt != SR_FMT_GLB)
        return rfail(err, SR_E_UNSUPPORTED, path, "a scene needs a .gltf or .glb file");
    tinygltf::Model model;
    sr_status st = gltf_load(path, fmt, model, err);
    if (st != SR_OK)
        return st;
    std::vector<Instance> inst;
    st = gltf_instances(path, model, inst, err);
    if (st != SR_OK)
        return st;
    struct Part {
        MeshGuard mesh;
        std::string name;
        float rgba[4];
    };
    std::vector<Part> parts;
    parts.reserve(model.meshes.size());
    for (size_t mi = 0; mi < model.meshes.size(); mi++) {
        MeshGuard raw;
        st = gltf_mesh(path, model, mi, &raw.m, err);
        if (st != SR_OK)
            return st;
        if (raw.m.tri_count == 0)
            continue;
        parts.emplace_back();
        Part &p = parts.back();
        const Instance *first = nullptr;
        for (const Instance &in : inst)
            if ((size_t)in.mesh == mi) {
                first = &in;
                break;
            }
        if (first) {
            if (place(raw.m, first->xf, &p.mesh.m) != SR_OK)
                return rfail(err, SR_E_NOMEM, path, "out of memory for mesh %zu", mi);
        } else {
            p.mesh.m = raw.m;
            raw.m = sr_mesh{};
        }
        p.name = model.meshes[mi].name;
        if (p.name.empty())
            for (const tinygltf::Node &n : model.nodes)
                if (n.mesh == (int)mi && !n.name.empty()) {
                    p.name = n.name;
                    break;
                }
        for (int k = 0; k < 4; k++)
            p.rgba[k] = 1.0f;
        for (const tinygltf::Primitive &prim : model.meshes[mi].primitives)
            if (prim.material >= 0 && (size_t)prim.material < model.materials.size()) {
                const std::vector<double> &c =
                    model.materials[(size_t)prim.material].pbrMetallicRoughness.baseColorFactor;
                if (c.size() == 4)
                    for (int k = 0; k < 4; k++)
                        p.rgba[k] = (float)c[(size_t)k];
                break;
            }
        sr_mesh_report rep;
        if (sr_mesh_validate(&p.mesh.m, path, &rep, nullptr) != SR_OK)
            return rfail(err, SR_E_INVALID, path,
                         "mesh %zu has %zu non-finite vertices after its node transform", mi,
                         rep.nonfinite_vertices);
    }
    if (parts.empty())
        return rfail(err, SR_E_INVALID, path, "contains no triangles");

    sr_scene s = {};
    size_t n = parts.size();
    s.meshes = (sr_mesh *)calloc(n, sizeof *s.meshes);
    s.names = (char **)calloc(n, sizeof *s.names);
    s.rgba = (float(*)[4])calloc(n, sizeof *s.rgba);
    bool ok = s.meshes && s.names && s.rgba;
    if (ok && !model.asset.extras_json_string.empty()) {
        s.extras_json = strdup(model.asset.extras_json_string.c_str());
        ok = s.extras_json != nullptr;
    }
    for (size_t i = 0; ok && i < n; i++) {
        s.names[i] = strdup(parts[i].name.c_str());
        ok = s.names[i] != nullptr;
    }
    if (!ok) {
        if (s.names)
            for (size_t i = 0; i < n; i++)
                free(s.names[i]);
        free(s.meshes);
        free(s.names);
        free(s.rgba);
        free(s.extras_json);
        return rfail(err, SR_E_NOMEM, path, "out of memory");
    }
    for (size_t i = 0; i < n; i++) {
        s.meshes[i] = parts[i].mesh.m;
        parts[i].mesh.m = sr_mesh{};
        memcpy(s.rgba[i], parts[i].rgba, sizeof parts[i].rgba);
    }
    s.count = n;
    *out = s;
    return SR_OK;
}

sr_status mesh_read(const char *path, sr_mesh *out, sr_err *err)
{
    if (!path || !out)
        return sr_err_set(err, SR_E_INVALID, "no file name given");
    sr_format fmt = sr_format_from_path(path);
    if (fmt == SR_FMT_UNKNOWN)
        return rfail(err, SR_E_UNSUPPORTED, path,
                     "unknown extension (known: .stl .obj .ply .off .gltf .glb)");
    MeshGuard g;
    sr_status st;
    if (fmt == SR_FMT_GLTF || fmt == SR_FMT_GLB) {
        st = read_gltf_merged(path, fmt, &g.m, err);
    } else {
        Bytes file;
        st = read_file(path, MESH_FILE_MAX, file, err);
        if (st == SR_OK)
            st = read_openmesh(path, fmt, file, &g.m, err);
    }
    if (st != SR_OK)
        return st;
    st = sr_mesh_validate(&g.m, path, nullptr, err);
    if (st != SR_OK)
        return st;
    *out = g.m;
    g.m = sr_mesh{};
    return SR_OK;
}

sr_status mesh_write(const char *path, const sr_mesh *mesh, const sr_write_opts *opts, sr_err *err)
{
    if (!path)
        return sr_err_set(err, SR_E_INVALID, "no file name given");
    sr_format fmt = sr_format_from_path(path);
    if (fmt == SR_FMT_UNKNOWN)
        return wfail(err, SR_E_UNSUPPORTED, path,
                     "unknown extension (known: .stl .obj .ply .off .gltf .glb)");
    sr_status st = check_for_write(path, mesh, "mesh", err);
    if (st != SR_OK)
        return st;
    bool ascii = opts && opts->ascii;
    if (fmt == SR_FMT_GLTF || fmt == SR_FMT_GLB) {
        sr_scene_mesh one = {nullptr, mesh, {0.8f, 0.8f, 0.8f, 1.0f}};
        return scene_write(path, &one, 1, nullptr, err);
    }
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

extern "C" sr_status sr_mesh_read(const char *path, sr_mesh *out, sr_err *err)
{
    try {
        return mesh_read(path, out, err);
    }
    CATCH_ALL(err, "read", path)
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
