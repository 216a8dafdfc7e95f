/*
 * read_gltf.cpp: loading a glTF or GLB file into a tinygltf 2.7 model, guarded (see
 * mesh_io_int.hpp). tinygltf accepts bad input silently (shared/DEPENDENCY-NOTES.md), so
 * it gets the file's bytes from us (read whole by the caller, or given in memory, where
 * no external file is opened at all), a GLB's chunks checked by src/io/, the JSON's depth,
 * buffer sizes and URIs pre-checked with nlohmann::json, and tinygltf given FsCallbacks
 * that refuse files outside the input's folder, directories and huge files, with image
 * decoding off. What is done with the loaded model is gltf_meshes.cpp's.
 */
#include "bridge/mesh_io_int.hpp"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace sr_meshio {

namespace {

/* The input's folder and what the file callbacks refused. */
struct FsGuard {
    bool files_allowed = true; /* false: bytes from memory, no external file at all */
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
    if (!g.files_allowed) {
        *why = "is an external file, which a read from memory does not open";
        return SR_E_UNSUPPORTED;
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

const char *const IGNORABLE_EXTENSIONS[] = {"KHR_materials_", "KHR_texture_",
                                            "KHR_lights_punctual"};

/* What a required extension does, for the message. */
const char *extension_says(const std::string &ext)
{
    if (ext == "KHR_draco_mesh_compression")
        return " (Draco-compressed geometry)";
    if (ext == "EXT_meshopt_compression" || ext == "KHR_meshopt_compression")
        return " (meshoptimizer-compressed buffers)";
    if (ext == "KHR_mesh_quantization")
        return " (quantised vertex attributes)";
    return "";
}

/* extensionsRequired first: a file that needs one symrec cannot read is refused by
 * its name, before tinygltf fails on what the extension changed (a Draco file's
 * accessors have no bufferView, a meshopt file's buffers no uri). */
sr_status gltf_required_extensions(const char *path, const nlohmann::json &j, sr_err *err)
{
    auto req = j.find("extensionsRequired");
    if (req == j.end())
        return SR_OK;
    if (!req->is_array())
        return rfail(err, SR_E_FORMAT, path, "glTF 'extensionsRequired' is not an array");
    for (const nlohmann::json &e : *req) {
        if (!e.is_string())
            return rfail(err, SR_E_FORMAT, path, "glTF 'extensionsRequired' holds a non-string");
        std::string ext = e.get<std::string>();
        bool fine = false;
        for (const char *ok_ext : IGNORABLE_EXTENSIONS)
            fine |= ext.compare(0, strlen(ok_ext), ok_ext) == 0;
        if (!fine)
            return rfail(err, SR_E_UNSUPPORTED, path,
                         "requires glTF extension '%s'%s, which symrec does not read: write "
                         "the file without it (e.g. gltf-transform's 'copy' from an uncompressed "
                         "source) or export STL/PLY",
                         ext.c_str(), extension_says(ext));
    }
    return SR_OK;
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
    st = gltf_required_extensions(path, j, err);
    if (st != SR_OK)
        return st;
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

} // namespace

sr_status gltf_load(const char *path, sr_format fmt, const Bytes &file, bool files_allowed,
                    tinygltf::Model &model, sr_err *err)
{
    sr_status st;
    FsGuard g;
    g.files_allowed = files_allowed;
    if (files_allowed) {
        std::string dir = dir_of(path);
        char *real = realpath(dir.c_str(), nullptr);
        if (!real)
            return rfail(err, SR_E_IO, path, "cannot resolve its folder: %s",
                         errno_text(errno).c_str());
        g.folder = real;
        free(real);
        if (g.folder == "/")
            g.folder.clear();   /* so that folder + "/" is "/" */
    } else {
        g.folder = "/nonexistent-symrec-memory"; /* matches no path: nothing is opened */
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
    return SR_OK; /* extensionsRequired: checked before (gltf_required_extensions) */
}

} // namespace sr_meshio
