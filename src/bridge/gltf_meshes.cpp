/*
 * gltf_meshes.cpp: the triangles of a loaded glTF model (see mesh_io_int.hpp): every
 * accessor and bufferView range-checked before a byte is read, triangle lists, strips
 * and fans, the default scene's node hierarchy walked with each node's transform, mesh
 * instances placed (a mirroring transform flips the winding) and merged for
 * sr_mesh_read, or kept apart with names and colours for sr_scene_read. A file symrec
 * wrote (its one root node's extras name the symrec frame) is turned back from glTF's
 * Y up to symrec's Z up; the file's unit (the caller's for a merged mesh, metres for
 * sr_scene_read) is scaled to mm in the same transform.
 */
#include "bridge/mesh_io_int.hpp"

#include <tiny_gltf.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace sr_meshio {

namespace {

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
        /* A singular transform (a scale of 0 on some axis) flattens the mesh into a
         * plane, line or point: no solid part (envelope.h's rule on degenerate input). */
        if (sr_xform_det(in.xf) == 0)
            return rfail(err, SR_E_INVALID, path,
                         "node %d's transform is singular (a scale of 0?): it flattens mesh %d "
                         "to no volume",
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

size_t default_scene(const tinygltf::Model &m)
{
    return m.defaultScene >= 0 && (size_t)m.defaultScene < m.scenes.size() ? (size_t)m.defaultScene
                                                                           : 0;
}

/* Whether symrec wrote the file (sr_scene_write): the default scene has one root node
 * whose extras name the symrec frame. Its transform takes symrec's mm, Z up, to glTF's
 * metres, Y up. */
bool symrec_frame(const tinygltf::Model &m)
{
    if (m.scenes.empty())
        return false;
    const std::vector<int> &roots = m.scenes[default_scene(m)].nodes;
    if (roots.size() != 1 || roots[0] < 0 || (size_t)roots[0] >= m.nodes.size())
        return false;
    const tinygltf::Value &x = m.nodes[(size_t)roots[0]].extras;
    return x.IsObject() && x.Has("symrec_frame") && x.Get("symrec_frame").IsString();
}

/* Mesh instances of the default scene (or scene 0); every mesh once, untransformed
 * but for the unit, when the file has no scene. The transforms take the file's numbers
 * to mm (times mm_per_unit) in the glTF scene's frame (Y up), but for a file symrec
 * wrote, which is turned back to Z up (y = -z', z = y'). */
sr_status gltf_instances(const char *path, const tinygltf::Model &m, double mm_per_unit,
                         std::vector<Instance> &out, sr_err *err)
{
    double id[12] = {mm_per_unit, 0, 0, 0, 0, mm_per_unit, 0, 0, 0, 0, mm_per_unit, 0};
    if (m.scenes.empty()) {
        for (size_t i = 0; i < m.meshes.size(); i++) {
            Instance in;
            in.mesh = (int)i;
            memcpy(in.xf, id, sizeof id);
            out.push_back(in);
        }
        return SR_OK;
    }
    double top[12];
    memcpy(top, id, sizeof top);
    if (symrec_frame(m)) {
        static const double y_up_to_z_up[12] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0};
        sr_xform_mul(top, id, y_up_to_z_up);
    }
    for (int root : m.scenes[default_scene(m)].nodes) {
        sr_status st = visit_node(path, m, root, top, 0, out, err);
        if (st != SR_OK)
            return st;
    }
    return SR_OK;
}

/* A mesh copy placed by a node transform; a mirroring transform flips the triangles so
 * that they stay outward-facing. The linear part's entries within 1e-12 of 0 or +-1 are
 * rounding (a quarter turn from the rounded sqrt(0.5), a scale of 0.001 times 1000):
 * they are made exact, so symrec's own file reads back to the very coordinates it
 * wrote and a 90-degree turn moves no vertex off its grid. */
sr_status place(const sr_mesh &src, const double xf_in[12], sr_mesh *out)
{
    double xf[12];
    memcpy(xf, xf_in, sizeof xf);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double &e = xf[4 * r + c];
            if (std::fabs(e) < 1e-12)
                e = 0;
            else if (std::fabs(std::fabs(e) - 1) < 1e-12)
                e = std::copysign(1.0, e);
        }
    sr_mesh c;
    sr_status st = sr_mesh_copy(&c, &src);
    if (st != SR_OK)
        return st;
    sr_mesh_map(&c, xf);
    *out = c;
    return SR_OK;
}

} // namespace

sr_status read_gltf_merged(const char *path, sr_format fmt, const Bytes &file, bool files_allowed,
                           double mm_per_unit, sr_mesh *out, sr_err *err)
{
    tinygltf::Model model;
    sr_status st = gltf_load(path, fmt, file, files_allowed, model, err);
    if (st != SR_OK)
        return st;
    std::vector<Instance> inst;
    st = gltf_instances(path, model, mm_per_unit, inst, err);
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

sr_status scene_read(const char *path, sr_scene *out, sr_err *err)
{
    sr_format fmt = sr_format_from_path(path);
    if (fmt != SR_FMT_GLTF && fmt != SR_FMT_GLB)
        return rfail(err, SR_E_UNSUPPORTED, path, "a scene needs a .gltf or .glb file");
    Bytes file;
    sr_status st = read_file(path, MESH_FILE_MAX, file, err);
    if (st != SR_OK)
        return st;
    tinygltf::Model model;
    st = gltf_load(path, fmt, file, true, model, err);
    if (st != SR_OK)
        return st;
    std::vector<Instance> inst;
    st = gltf_instances(path, model, sr_unit_mm(SR_UNIT_M), inst, err);
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
        /* a mesh no node places is in metres (glTF's unit), scaled to mm */
        double mm[12] = {1000, 0, 0, 0, 0, 1000, 0, 0, 0, 0, 1000, 0};
        if (place(raw.m, first ? first->xf : mm, &p.mesh.m) != SR_OK)
            return rfail(err, SR_E_NOMEM, path, "out of memory for mesh %zu", mi);
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
        st = sr_envelope_check_mesh(p.mesh.m.xyz, p.mesh.m.vertex_count, p.mesh.m.tri,
                                    p.mesh.m.tri_count, path, err);
        if (st != SR_OK)
            return st;
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

} // namespace sr_meshio
