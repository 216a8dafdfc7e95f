/*
 * check_glb.c: checks of a GLB container's header and chunks (see file_check.h), and of
 * the nesting depth of JSON text, before tinygltf parses either.
 *
 * The shared tokenizer, numbers and messages are in check_common.c (check_int.h).
 */
#include "io/check_int.h"

#include <string.h>

#define GLB_JSON 0x4E4F534Au
#define GLB_BIN 0x004E4942u

sr_status sr_file_check_glb(const unsigned char *data, size_t size, const char *name,
                            sr_glb_layout *out, sr_err *err)
{
    return sr_file_check_glb_head(data, size, size, name, out, err);
}

sr_status sr_file_check_glb_head(const unsigned char *data, size_t known, size_t size,
                                 const char *name, sr_glb_layout *out, sr_err *err)
{
    if (known > size)
        known = size;
    if (known < 20 && known < size)
        return fc_fail(err, SR_E_FORMAT, name, "GLB header not among the %zu bytes given", known);
    if (size < 12 || memcmp(data, "glTF", 4) != 0)
        return fc_fail(err, SR_E_FORMAT, name, "not a GLB file (no 'glTF' magic)");
    uint32_t version = fc_le32(data + 4), length = fc_le32(data + 8);
    if (version != 2)
        return fc_fail(err, SR_E_UNSUPPORTED, name, "GLB version %u (only 2 is supported)",
                       version);
    if (length != size)
        return fc_fail(err, SR_E_FORMAT, name, "GLB header says %u bytes, file holds %zu", length,
                       size);
    if (size < 20)
        return fc_fail(err, SR_E_FORMAT, name, "GLB has no JSON chunk");
    uint32_t json_len = fc_le32(data + 12), json_type = fc_le32(data + 16);
    if (json_type != GLB_JSON)
        return fc_fail(err, SR_E_FORMAT, name, "first GLB chunk is not JSON");
    if (json_len == 0 || json_len > size - 20)
        return fc_fail(err, SR_E_FORMAT, name,
                       "GLB JSON chunk length %u does not fit the %zu bytes after its header",
                       json_len, size - 20);
    sr_glb_layout g = {20, json_len, 0, 0, 0};
    size_t pos = 20 + (size_t)json_len;
    for (int chunk = 1; pos < size; chunk++) {
        if (size - pos >= 8 && pos + 8 > known)
            return fc_fail(err, SR_E_FORMAT, name,
                           "GLB chunk %d's header at byte %zu is past the %zu bytes given", chunk,
                           pos, known);
        uint32_t len = size - pos >= 8 ? fc_le32(data + pos) : 0;
        uint32_t type = size - pos >= 8 ? fc_le32(data + pos + 4) : 0;
        const char *what = type == GLB_BIN ? "BIN" : type == GLB_JSON ? "JSON" : "unknown";
        /* Bytes after the BIN chunk that make no chunk of their own are the BIN chunk's
         * own when its length is too small: say so, not "stray" or "unknown chunk". */
        if (size - pos < 8 || (type != GLB_BIN && type != GLB_JSON && len > size - pos - 8)) {
            size_t tail = size - (g.has_bin ? g.bin_offset + g.bin_size : pos);
            if (g.has_bin)
                return fc_fail(err, SR_E_FORMAT, name,
                               "GLB BIN chunk length %zu is too small: the %zu bytes after it "
                               "make no valid chunk",
                               g.bin_size, tail);
            if (size - pos < 8)
                return fc_fail(err, SR_E_FORMAT, name, "GLB has %zu stray bytes after chunk %d",
                               size - pos, chunk - 1);
        }
        if (len > size - pos - 8)
            return fc_fail(err, SR_E_FORMAT, name,
                           "GLB %s chunk length %u runs past the end of the file (%zu bytes after "
                           "its 8-byte header)", what, len, size - pos - 8);
        if (chunk == 1 && type == GLB_BIN) {
            g.has_bin = 1;
            g.bin_offset = pos + 8;
            g.bin_size = len;
        } else if (type == GLB_BIN || type == GLB_JSON) {
            return fc_fail(err, SR_E_FORMAT, name, "GLB chunk %d is a misplaced %s chunk", chunk,
                           what);
        }
        pos += 8 + (size_t)len;
    }
    *out = g;
    return SR_OK;
}

sr_status sr_file_check_json_depth(const unsigned char *text, size_t size, size_t max_depth,
                                   const char *name, sr_err *err)
{
    size_t depth = 0;
    int in_string = 0;
    for (size_t i = 0; i < size; i++) {
        unsigned char c = text[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = 0;
        } else if (c == '"') {
            in_string = 1;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth)
                return fc_fail(err, SR_E_FORMAT, name, "JSON nests deeper than %zu levels",
                               max_depth);
        } else if ((c == ']' || c == '}') && depth) {
            depth--;
        }
    }
    return SR_OK;
}
