/*
 * write_text.cpp: OBJ, OFF and PLY (ASCII and binary little endian) serialised in memory
 * by the mesh bridge itself, with shortest round-trip doubles (std::to_chars): OpenMesh 9
 * writes every format in float precision. STL is written by openmesh_io.cpp.
 */
#include "bridge/mesh_io_int.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <string>

namespace sr_meshio {

namespace {

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

} // namespace

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

} // namespace sr_meshio
