/*
 * openmesh_io.cpp: everything of the mesh bridge that touches OpenMesh 9: reading STL, OBJ,
 * PLY and OFF, and writing STL (see mesh_io_int.hpp). OpenMesh accepts bad input
 * silently (shared/DEPENDENCY-NOTES.md), so every read here is:
 *   1. the file's bytes in memory, read by us (io_bytes.cpp) or given (a fuzz target);
 *      a binary STL read from a file is never held whole: each step below reads it
 *      again, a run of facets at a time (read_stl_binary_file);
 *   2. checked by src/io/ (pure C): sizes, counts, NaN/Inf, indices, PLY header, and
 *      every coordinate inside the physical envelope (io/envelope.h); these checks
 *      also return what the file holds;
 *   3. parsed by OpenMesh from that memory (never by path: no second open, and its OBJ
 *      reader gets no chance to open an mtllib), into a Collector that records vertices
 *      and faces as delivered, with no topology to lose faces to;
 *   4. compared with step 2: same vertex count, same faces, same coordinates (to float
 *      rounding). Any disagreement is an error naming how much was lost.
 * OpenMesh 9 reads and writes every format in float precision, so the coordinates of
 * OBJ/OFF/PLY come from step 2 (double, as written, checked against OpenMesh's floats)
 * and those formats are written by write_text.cpp; STL, a float format, is written here.
 *
 * OpenMesh prints to omerr/omlog (connected to std::cerr/std::clog): during each call
 * those two streams write into a buffer of ours instead, which becomes the detail of an
 * error; nothing reaches the console. That swap and OpenMesh's global reader registry
 * are guarded by one mutex.
 */
#include "bridge/mesh_io_int.hpp"

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

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <iostream>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <vector>

namespace sr_meshio {

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<Traits> OmMesh;

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

/* An istream source over an open file read a run of bytes at a time (pread), never
 * whole; seekable. A failed read ends the stream and is kept in failed(). */
class FileBuf : public std::streambuf
{
  public:
    FileBuf(int fd, size_t size) : fd_(fd), size_(size), buf_(std::min(size, RUN_BYTES))
    {
        setg(buf_.data(), buf_.data(), buf_.data());
    }
    bool failed() const { return failed_; }

  protected:
    int_type underflow() override
    {
        size_t at = base_ + (size_t)(egptr() - eback());
        return fill(at) ? traits_type::to_int_type(*gptr()) : traits_type::eof();
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir,
                     std::ios_base::openmode which) override
    {
        if (!(which & std::ios_base::in))
            return pos_type(off_type(-1));
        off_type here = off_type(base_ + (size_t)(gptr() - eback()));
        off_type from = dir == std::ios_base::beg   ? 0
                        : dir == std::ios_base::cur ? here
                                                    : off_type(size_);
        off_type pos = from + off;
        if (pos < 0 || pos > off_type(size_))
            return pos_type(off_type(-1));
        size_t held = (size_t)(egptr() - eback());
        if ((size_t)pos >= base_ && (size_t)pos <= base_ + held) {
            setg(eback(), eback() + ((size_t)pos - base_), egptr());
        } else {
            base_ = (size_t)pos; /* nothing held: the next read starts there */
            setg(buf_.data(), buf_.data(), buf_.data());
        }
        return pos_type(pos);
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override
    {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }

  private:
    static constexpr size_t RUN_BYTES = 1 << 20;
    bool fill(size_t at)
    {
        if (at >= size_ || failed_)
            return false;
        size_t n = std::min(buf_.size(), size_ - at);
        if (read_at(fd_, at, buf_.data(), n, "", nullptr) != SR_OK) {
            failed_ = true;
            return false;
        }
        base_ = at;
        setg(buf_.data(), buf_.data(), buf_.data() + n);
        return true;
    }
    int fd_;
    size_t size_, base_ = 0; /* base_: the file offset of the buffer's first byte */
    std::vector<char> buf_;
    bool failed_ = false;
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
    /* Room for what the file holds, so that the arrays never double past it (an STL's
     * vertices: a closed surface has about half as many as triangles). */
    void reserve(const sr_file_facts &f, sr_format fmt)
    {
        size_t nv = fmt == SR_FMT_STL ? f.face_count / 2 + 16 : f.vertex_count;
        xyz.reserve(3 * nv);
        face_size.reserve(f.face_count);
        face_index.reserve(f.tri_count + 2 * f.face_count); /* the corners of all faces */
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

/* Float reading of a double agrees with it: OpenMesh parses into float, and may round
 * a decimal string to float directly (one ulp from rounding via double). */
bool float_agrees(double om, double exact)
{
    if (om == exact || om == (double)(float)exact)
        return true;
    double tol = std::max(std::fabs(exact), (double)FLT_MIN) * 2.4e-7;
    return std::fabs(om - exact) <= tol;
}

bool same_corner(const double *a, const float *b)
{
    return std::fabs(a[0] - b[0]) <= FLT_MIN && std::fabs(a[1] - b[1]) <= FLT_MIN &&
           std::fabs(a[2] - b[2]) <= FLT_MIN;
}

bool same_float_corner(const float *a, const float *b)
{
    const double d[3] = {a[0], a[1], a[2]};
    return same_corner(d, b);
}

bool repeats_vertex(const uint32_t *idx, size_t k)
{
    for (size_t i = 0; i < k; i++)
        for (size_t j = i + 1; j < k; j++)
            if (idx[i] == idx[j])
                return true;
    return false;
}

/* An ASCII STL's facets, as its check returned them. */
struct CheckedFacets {
    const float *corners;
    const float *at(size_t t, sr_err *) const { return corners + 9 * t; }
};

/* A binary STL's facets in file order, decoded from its bytes in memory or from the
 * open file a run of facets at a time. */
class BinaryFacets
{
  public:
    explicit BinaryFacets(const unsigned char *file_bytes) : mem_(file_bytes) {}
    BinaryFacets(int fd, size_t facets, const char *path) : fd_(fd), n_(facets), path_(path) {}
    /* Facet t's nine corner coordinates, valid until the next call; nullptr (err set)
     * when the file cannot be read again. */
    const float *at(size_t t, sr_err *err)
    {
        const unsigned char *rec;
        if (mem_) {
            rec = mem_ + SR_STL_HEADER_BYTES + SR_STL_FACET_BYTES * t;
        } else {
            if (t < first_ || t >= first_ + held_) {
                held_ = std::min(RUN, n_ - t);
                run_.resize(SR_STL_FACET_BYTES * RUN);
                if (read_at(fd_, SR_STL_HEADER_BYTES + SR_STL_FACET_BYTES * t, run_.data(),
                            SR_STL_FACET_BYTES * held_, path_, err) != SR_OK) {
                    held_ = 0;
                    return nullptr;
                }
                first_ = t;
            }
            rec = run_.data() + SR_STL_FACET_BYTES * (t - first_);
        }
        sr_file_stl_facet(rec, c_);
        return c_;
    }

  private:
    static constexpr size_t RUN = 1 << 15;
    const unsigned char *mem_ = nullptr;
    int fd_ = -1;
    size_t n_ = 0, first_ = 0, held_ = 0;
    const char *path_ = "";
    std::vector<unsigned char> run_;
    float c_[9] = {};
};

/* STL: OpenMesh welds corners and drops degenerate facets itself. Its faces must be the
 * file's non-degenerate facets (of tri_count, degenerate of them), in order, corner for
 * corner. The result keeps only the vertices those faces use. */
template <class Facets>
sr_status stl_result(const char *path, size_t tri_count, size_t degenerate, Facets &facets,
                     const Collector &c, sr_mesh *out, sr_err *err)
{
    size_t expect = tri_count - degenerate;
    size_t got = c.n_faces();
    if (got != expect) {
        if (got < expect)
            return rfail(err, SR_E_FORMAT, path,
                         "OpenMesh lost %zu of %zu triangles (%zu degenerate ones dropped as "
                         "expected)",
                         expect - got, tri_count, degenerate);
        return rfail(err, SR_E_FORMAT, path, "OpenMesh read %zu triangles, the file holds %zu",
                     got, expect);
    }
    for (size_t i = 0; i < got; i++)
        if (c.face_size[i] != 3)
            return rfail(err, SR_E_FORMAT, path, "OpenMesh made a %u-gon of triangle %zu",
                         c.face_size[i], i);
    size_t facet = 0;
    for (size_t i = 0; i < got; i++, facet++) {
        const float *q = nullptr;
        for (; facet < tri_count; facet++) {
            if (!(q = facets.at(facet, err)))
                return SR_E_IO;
            if (!(same_float_corner(q, q + 3) || same_float_corner(q, q + 6) ||
                  same_float_corner(q + 3, q + 6)))
                break;
        }
        for (int k = 0; k < 3; k++)
            if (facet >= tri_count ||
                !same_corner(&c.xyz[3 * (size_t)c.face_index[3 * i + k]], q + 3 * k))
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

} // namespace

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
    /* Before OpenMesh, which parses into float: a value beyond float range would come
     * back as inf and lose its face ("bad vertex index"), not as what it is. (An STL's
     * check holds its corners to the envelope itself.) */
    if (fmt != SR_FMT_STL) {
        st = sr_envelope_check_points(facts.f.xyz, facts.f.vertex_count, 0, path, err);
        if (st != SR_OK)
            return st;
    }
    if (facts.f.tri_count == facts.f.degenerate_tris)
        return rfail(err, SR_E_INVALID, path, "contains no triangles%s",
                     facts.f.tri_count ? " (all degenerate)" : "");

    /* OFF: OpenMesh 9's reader takes a comment for data (read 0 vertices), a face's
     * colour for the next face's corner count, and hung on fuzzed files. It reads a
     * plain restatement of the checked file instead (every vertex with 17 digits, every
     * face, nothing else), so it checks the numbers the check parsed and cannot
     * contradict the file over syntax it misreads. */
    std::string plain;
    if (fmt == SR_FMT_OFF) {
        std::ostringstream os;
        os.precision(17);
        os << "OFF\n" << facts.f.vertex_count << ' ' << facts.f.face_count << " 0\n";
        for (size_t v = 0; v < facts.f.vertex_count; v++)
            os << facts.f.xyz[3 * v] << ' ' << facts.f.xyz[3 * v + 1] << ' '
               << facts.f.xyz[3 * v + 2] << '\n';
        size_t at = 0;
        for (size_t i = 0; i < facts.f.face_count; i++) {
            os << facts.f.face_size[i];
            for (uint32_t k = 0; k < facts.f.face_size[i]; k++)
                os << ' ' << facts.f.face_index[at + k];
            at += facts.f.face_size[i];
            os << '\n';
        }
        plain = os.str();
    }
    Collector c;
    c.reserve(facts.f, fmt);
    bool ok;
    std::string log;
    {
        OmSession session;
        MemBuf mb(plain.empty() ? file.data : (const unsigned char *)plain.data(),
                  plain.empty() ? file.size : plain.size());
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
    if (fmt == SR_FMT_STL && facts.f.binary) {
        BinaryFacets facets(file.data);
        return stl_result(path, facts.f.tri_count, facts.f.degenerate_tris, facets, c, out, err);
    }
    if (fmt == SR_FMT_STL) {
        CheckedFacets facets{facts.f.corners};
        return stl_result(path, facts.f.tri_count, facts.f.degenerate_tris, facets, c, out, err);
    }
    return indexed_result(path, facts.f, c, out, err);
}

sr_status read_stl_binary_file(const char *path, int fd, size_t facets, sr_mesh *out, sr_err *err)
{
    /* 1. the check, a run of facets at a time */
    size_t degenerate = 0;
    {
        const size_t run = 1 << 15;
        std::vector<unsigned char> bytes(SR_STL_FACET_BYTES * std::min(run, facets));
        for (size_t first = 0; first < facets; first += run) {
            size_t k = std::min(run, facets - first);
            sr_status st = read_at(fd, SR_STL_HEADER_BYTES + SR_STL_FACET_BYTES * first,
                                   bytes.data(), SR_STL_FACET_BYTES * k, path, err);
            if (st == SR_OK)
                st = sr_file_check_stl_facets(bytes.data(), k, first, path, &degenerate, err);
            if (st != SR_OK)
                return st;
        }
    }
    if (degenerate == facets)
        return rfail(err, SR_E_INVALID, path, "contains no triangles (all degenerate)");
    /* 2. OpenMesh reads the file through a window of it */
    sr_file_facts f = {};
    f.binary = 1;
    f.face_count = f.tri_count = facets;
    f.vertex_count = 3 * facets;
    Collector c;
    c.reserve(f, SR_FMT_STL);
    bool ok, failed;
    std::string log;
    {
        OmSession session;
        FileBuf fb(fd, SR_STL_HEADER_BYTES + SR_STL_FACET_BYTES * facets);
        std::istream in(&fb);
        OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary;
        ok = OpenMesh::IO::IOManager().read(in, ".stl", c, opt);
        failed = fb.failed();
        log = session.text();
    }
    if (failed)
        return rfail(err, SR_E_IO, path, "the file could not be read again (it changed or went)");
    if (!ok)
        return rfail(err, SR_E_FORMAT, path, "OpenMesh could not read it (%s)",
                     first_line(log).c_str());
    /* 3. compared with the file, read once more */
    BinaryFacets from_file(fd, facets, path);
    return stl_result(path, facets, degenerate, from_file, c, out, err);
}

/* Serves an OpenMesh writer our arrays as they are: the faces are the triangles that
 * repeat no vertex, in order, each with its corners in order; no topology is built (an
 * OpenMesh mesh built for writing took 1.7 s of a 1.85M-triangle part's run, its
 * add_face splitting the non-manifold corners a writer of STL does not need). What a
 * writer asks of faces, vertices and points is what ExporterT gives for a mesh of double
 * points without normals, colours or texture coordinates. */
#define NO_COLOURS(H)                                                                              \
    OpenMesh::Vec3uc color(H) const override                                                       \
    {                                                                                              \
        return OpenMesh::Vec3uc(0, 0, 0);                                                          \
    }                                                                                              \
    OpenMesh::Vec4uc colorA(H) const override                                                      \
    {                                                                                              \
        return OpenMesh::Vec4uc(0, 0, 0, 0);                                                       \
    }                                                                                              \
    OpenMesh::Vec3ui colori(H) const override                                                      \
    {                                                                                              \
        return OpenMesh::Vec3ui(0, 0, 0);                                                          \
    }                                                                                              \
    OpenMesh::Vec4ui colorAi(H) const override                                                     \
    {                                                                                              \
        return OpenMesh::Vec4ui(0, 0, 0, 0);                                                       \
    }                                                                                              \
    OpenMesh::Vec3f colorf(H) const override                                                       \
    {                                                                                              \
        return OpenMesh::Vec3f(0, 0, 0);                                                           \
    }                                                                                              \
    OpenMesh::Vec4f colorAf(H) const override                                                      \
    {                                                                                              \
        return OpenMesh::Vec4f(0, 0, 0, 0);                                                        \
    }
class ArrayExporter : public OpenMesh::IO::BaseExporter
{
  public:
    typedef OpenMesh::VertexHandle VH;
    typedef OpenMesh::FaceHandle FH;
    typedef OpenMesh::HalfedgeHandle HH;
    typedef OpenMesh::EdgeHandle EH;
    typedef OpenMesh::Attributes::StatusInfo Status;

    explicit ArrayExporter(const sr_mesh &m) : m_(m)
    {
        for (size_t t = 0; t < m.tri_count; t++)
            if (!repeats_vertex(m.tri + 3 * t, 3))
                faces_.push_back((uint32_t)t);
    }

    OpenMesh::Vec3f point(VH v) const override
    {
        const double *p = m_.xyz + 3 * (size_t)v.idx();
        return OpenMesh::Vec3f((float)p[0], (float)p[1], (float)p[2]);
    }
    OpenMesh::Vec3d pointd(VH v) const override
    {
        const double *p = m_.xyz + 3 * (size_t)v.idx();
        return OpenMesh::Vec3d(p[0], p[1], p[2]);
    }
    bool is_point_double() const override { return true; }
    bool is_normal_double() const override { return true; }
    unsigned int get_vhandles(FH f, std::vector<VH> &vh) const override
    {
        const uint32_t *c = m_.tri + 3 * (size_t)faces_[(size_t)f.idx()];
        vh.assign({VH((int)c[0]), VH((int)c[1]), VH((int)c[2])});
        return 3;
    }
    size_t n_vertices() const override { return m_.vertex_count; }
    size_t n_faces() const override { return faces_.size(); }
    size_t n_edges() const override { return 0; }
    bool is_triangle_mesh() const override { return true; }

    /* nothing else is kept: zeros, as ExporterT gives without the attribute */
    OpenMesh::Vec3f normal(VH) const override { return OpenMesh::Vec3f(0, 0, 0); }
    OpenMesh::Vec3d normald(VH) const override { return OpenMesh::Vec3d(0, 0, 0); }
    NO_COLOURS(VH)
    OpenMesh::Vec2f texcoord(VH) const override { return OpenMesh::Vec2f(0, 0); }
    OpenMesh::Vec2f texcoord(HH) const override { return OpenMesh::Vec2f(0, 0); }
    Status status(VH) const override { return Status(); }
    HH getHeh(FH, VH) const override { return HH(); }
    unsigned int get_face_texcoords(std::vector<OpenMesh::Vec2f> &t) const override
    {
        t.clear();
        return 0;
    }
    OpenMesh::Vec3f normal(FH) const override { return OpenMesh::Vec3f(0, 0, 0); }
    OpenMesh::Vec3d normald(FH) const override { return OpenMesh::Vec3d(0, 0, 0); }
    NO_COLOURS(FH)
    Status status(FH) const override { return Status(); }
    NO_COLOURS(EH)
    Status status(EH) const override { return Status(); }
    int get_halfedge_id(VH) override { return -1; }
    int get_halfedge_id(FH) override { return -1; }
    int get_next_halfedge_id(HH) override { return -1; }
    int get_to_vertex_id(HH) override { return -1; }
    int get_face_id(HH) override { return -1; }
    Status status(HH) const override { return Status(); }

  private:
    const sr_mesh &m_;
    std::vector<uint32_t> faces_;
};
#undef NO_COLOURS

namespace
{

/* STL of m through OpenMesh's writer into os, of the mesh as float makes it; *expect:
 * the triangles the stream must hold. */
sr_status stl_to_stream(const char *path, const sr_mesh &m, bool ascii, std::ostream &os,
                        size_t *expect_out, sr_err *err)
{
    size_t expect = 0;
    for (size_t t = 0; t < m.tri_count; t++)
        expect += !repeats_vertex(m.tri + 3 * t, 3);
    if (expect == 0)
        return wfail(err, SR_E_INVALID, path, "mesh has no non-degenerate triangles");
    for (size_t i = 0; i < 3 * m.vertex_count; i++)
        if (!std::isfinite((float)m.xyz[i]))
            return wfail(err, SR_E_RANGE, path, "vertex %zu is beyond float range for STL", i / 3);
    /* as a reader will weld it: vertices at one float position one, the triangles that
     * then repeat a vertex and the flaps left out (a closed mesh stays closed in the
     * file) */
    size_t welds = sr_mesh_float_welds(&m);
    MeshGuard fm;
    if (welds == SIZE_MAX || (welds > 0 && sr_mesh_float_ready(&m, &fm.m, nullptr) != SR_OK))
        return wfail(err, SR_E_NOMEM, path, "out of memory for %zu triangles", m.tri_count);
    const sr_mesh &written = welds > 0 ? fm.m : m; /* no weld: the writer rounds it alike */
    expect = 0;
    for (size_t t = 0; t < written.tri_count; t++)
        expect += !repeats_vertex(written.tri + 3 * t, 3);
    if (expect == 0)
        return wfail(err, SR_E_INVALID, path,
                     "mesh has no triangles left at float precision (every one flat or paired)");
    bool ok;
    size_t faces;
    std::string log;
    {
        OmSession session;
        ArrayExporter ex(written);
        faces = ex.n_faces();
        OpenMesh::IO::Options opt = ascii ? OpenMesh::IO::Options::Default
                                          : OpenMesh::IO::Options::Binary;
        ok = faces == expect && OpenMesh::IO::IOManager().write(os, ".stl", ex, opt, 17);
        log = session.text();
    }
    if (faces != expect)
        return wfail(err, SR_E_INTERNAL, path, "OpenMesh kept %zu of %zu triangles", faces, expect);
    if (!ok)
        return wfail(err, SR_E_INTERNAL, path, "OpenMesh could not write STL (%s)",
                     first_line(log).c_str());
    *expect_out = expect;
    return SR_OK;
}

/* A binary STL as OpenMesh wrote it: 84 + 50 n bytes, n in the header. */
sr_status check_binary_written(const char *path, size_t size, const unsigned char *head,
                               size_t expect, sr_err *err)
{
    if (size != 84 + 50 * expect || rd_le32(head + 80) != expect)
        return wfail(err, SR_E_INTERNAL, path,
                     "OpenMesh wrote %zu bytes of binary STL, %zu triangles need %zu", size, expect,
                     84 + 50 * expect);
    return SR_OK;
}

} // namespace

/* STL through OpenMesh's writer, into memory (ArrayExporter), of the mesh as float
 * makes it (sr_mesh_float_ready). Triangles that repeat a vertex cannot be stored (and
 * no reader would keep them); non-manifold ones are written as they are, STL having no
 * topology. */
sr_status encode_stl(const char *path, const sr_mesh &m, bool ascii, std::string *out, sr_err *err)
{
    out->clear();
    size_t expect = 0;
    StringSink sink(*out);
    std::ostream os(&sink);
    sr_status st = stl_to_stream(path, m, ascii, os, &expect, err);
    if (st != SR_OK)
        return st;
    if (!ascii) {
        if (out->size() < 84)
            return wfail(err, SR_E_INTERNAL, path, "OpenMesh wrote %zu bytes of binary STL",
                         out->size());
        return check_binary_written(path, out->size(), (const unsigned char *)out->data(), expect,
                                    err);
    }
    size_t n = 0;
    for (size_t at = out->find("endfacet"); at != std::string::npos;
         at = out->find("endfacet", at + 8))
        n++;
    if (n != expect)
        return wfail(err, SR_E_INTERNAL, path, "OpenMesh wrote %zu of %zu facets", n, expect);
    return SR_OK;
}

sr_status write_stl_binary(const char *path, const sr_mesh &m, sr_err *err)
{
    AtomicFile file;
    sr_status st = file.open(path, err);
    if (st != SR_OK)
        return st;
    size_t expect = 0;
    FileSink sink(file, [](const std::string &) { return (size_t)84; });
    {
        std::ostream os(&sink);
        st = stl_to_stream(path, m, false, os, &expect, err);
    }
    if (!sink.flush())
        return file.commit(
            err); /* the failed write's error (a full disk), whatever OpenMesh said */
    if (st != SR_OK)
        return st;
    if (sink.head().size() < 84)
        return wfail(err, SR_E_INTERNAL, path, "OpenMesh wrote %zu bytes of binary STL",
                     sink.size());
    st = check_binary_written(path, sink.size(), (const unsigned char *)sink.head().data(), expect,
                              err);
    if (st != SR_OK)
        return st;
    return file.commit(err);
}

} // namespace sr_meshio
