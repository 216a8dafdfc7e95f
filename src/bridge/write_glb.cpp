/*
 * write_glb.cpp: glTF and GLB written through tinygltf 2.7 (see mesh_io.h's
 * sr_scene_write): one node, mesh and material per input mesh, positions as float32 with
 * POSITION min/max, under one root node that takes symrec's mm, Z up, to glTF's metres,
 * Y up; vertex colours, when given, as COLOR_0 (float32 VEC3); the caller's extras
 * JSON as the asset's extras; the result checked (a GLB's
 * chunks by src/io/) before the atomic write.
 */
#include "bridge/mesh_io_int.hpp"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

namespace sr_meshio {

namespace {

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

/* How much of a GLB being written to keep for its check: the 20 bytes of header and
 * JSON chunk header, then the JSON chunk and the next chunk's header. */
size_t glb_head(const std::string &head)
{
    if (head.size() < 20)
        return 20;
    const unsigned char *h = (const unsigned char *)head.data();
    return 28 + (size_t)rd_le32(h + 12);
}

void append_bytes(std::vector<unsigned char> &buf, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    buf.insert(buf.end(), b, b + n);
}

} // namespace

sr_status scene_write(const char *path, const sr_scene_mesh *meshes, size_t count,
                      const char *extras_json, sr_err *err, const float *const *rgb)
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
    /* the geometry's bytes sized up front: grown by doubling, a restored scan of a
     * million triangles held its 21 MB twice over while they were copied */
    std::vector<unsigned char> bin;
    size_t geometry = 0;
    for (size_t i = 0; i < count; i++)
        if (meshes[i].mesh && geometry <= (size_t)INT32_MAX)
            geometry += 12 * (meshes[i].mesh->vertex_count * (rgb && rgb[i] ? 2 : 1) +
                              meshes[i].mesh->tri_count);
    bin.reserve(std::min(geometry, (size_t)INT32_MAX));
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
        const float *col = rgb ? rgb[i] : nullptr;
        size_t pos_bytes = m.vertex_count * 12, idx_bytes = m.tri_count * 12,
               col_bytes = col ? m.vertex_count * 12 : 0;
        for (size_t k = 0; col && k < 3 * m.vertex_count; k++)
            if (!(col[k] >= 0.0f && col[k] <= 1.0f))
                return wfail(err, SR_E_RANGE, path,
                             "mesh %zu vertex colour component %zu is %g, not in 0..1", i, k,
                             (double)col[k]);
        if (bin.size() + pos_bytes + idx_bytes + col_bytes > (size_t)INT32_MAX)
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
        int cai = -1;
        if (col) {
            /* after the indices, 4-aligned as they are */
            tinygltf::BufferView cv;
            cv.buffer = 0;
            cv.byteOffset = bin.size();
            cv.byteLength = col_bytes;
            cv.target = TINYGLTF_TARGET_ARRAY_BUFFER;
            for (size_t k = 0; k < 3 * m.vertex_count; k++) {
                uint32_t u;
                memcpy(&u, &col[k], 4);
                unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8),
                                      (unsigned char)(u >> 16), (unsigned char)(u >> 24)};
                append_bytes(bin, b, 4);
            }
            tinygltf::Accessor ca;
            ca.bufferView = (int)model.bufferViews.size();
            model.bufferViews.push_back(cv);
            ca.byteOffset = 0;
            ca.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
            ca.count = m.vertex_count;
            ca.type = TINYGLTF_TYPE_VEC3;
            cai = (int)model.accessors.size();
            model.accessors.push_back(ca);
        }

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
        if (cai >= 0)
            prim.attributes["COLOR_0"] = cai;
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
    }
    /* the root: symrec's mm, Z up, to glTF's metres, Y up (x to x, z to y, y to -z: a
     * rotation of -90 degrees about X); the readers know it by its extras */
    tinygltf::Node root;
    root.name = "symrec frame (children in mm, Z up)";
    root.scale = {0.001, 0.001, 0.001};
    root.rotation = {-0.7071067811865476, 0.0, 0.0, 0.7071067811865476};
    for (size_t i = 0; i < count; i++)
        root.children.push_back((int)i);
    tinygltf::Value::Object frame;
    frame["symrec_frame"] = tinygltf::Value(std::string("children in mm, Z up"));
    root.extras = tinygltf::Value(std::move(frame));
    scene.nodes.push_back((int)model.nodes.size());
    model.nodes.push_back(std::move(root));
    tinygltf::Buffer buffer;
    buffer.data = std::move(bin);
    model.buffers.push_back(std::move(buffer));
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    /* written as tinygltf makes it (its BIN chunk is a copy of the geometry already) */
    AtomicFile file;
    sr_status st = file.open(path, err);
    if (st != SR_OK)
        return st;
    bool glb = fmt == SR_FMT_GLB;
    FileSink sink(
        file, glb ? glb_head : [](const std::string &) { return (size_t)0; });
    bool ok;
    {
        std::ostream os(&sink);
        tinygltf::TinyGLTF w;
        ok = w.WriteGltfSceneToStream(&model, os, !glb, glb);
    }
    if (!sink.flush())
        return file.commit(err); /* the failed write's error (a full disk) */
    if (!ok)
        return wfail(err, SR_E_INTERNAL, path, "tinygltf could not serialise the scene");
    if (glb) {
        sr_glb_layout layout;
        sr_err inner;
        if (sr_file_check_glb_head((const unsigned char *)sink.head().data(), sink.head().size(),
                                   sink.size(), path, &layout, &inner) != SR_OK ||
            !layout.has_bin)
            return wfail(err, SR_E_INTERNAL, path, "tinygltf wrote a bad GLB (%s)", inner.msg);
    }
    return file.commit(err);
}

} // namespace sr_meshio
