/*
 * json_out.c: the JSON writer behind every --json (see json_out.h), and the JSON form
 * of the catalogue's records (part, instance, symmetry, parameter set) so that every
 * command prints a record with the same keys.
 *
 * Keys carry their unit (volume_mm3, area_mm2, shift_mm); absent values are null, never
 * a made-up zero.
 */
#include "json_out.h"

#include <assert.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/symmetry.h"

void json_init(json_out *j, FILE *f)
{
    memset(j, 0, sizeof *j);
    j->f = f;
}

/* Called before every value: the comma between siblings, none after a key. */
static void before_value(json_out *j)
{
    if (j->after_key) {
        j->after_key = false;
        return;
    }
    if (j->need_comma[j->depth])
        fputc(',', j->f);
    j->need_comma[j->depth] = true;
}

static void open_container(json_out *j, char c)
{
    before_value(j);
    fputc(c, j->f);
    assert(j->depth < JSON_MAX_DEPTH);
    j->depth++;
    j->need_comma[j->depth] = false;
}

static void close_container(json_out *j, char c)
{
    assert(j->depth > 0 && !j->after_key);
    j->depth--;
    fputc(c, j->f);
}

void json_object_begin(json_out *j) { open_container(j, '{'); }
void json_object_end(json_out *j) { close_container(j, '}'); }
void json_array_begin(json_out *j) { open_container(j, '['); }
void json_array_end(json_out *j) { close_container(j, ']'); }

void json_key(json_out *j, const char *key)
{
    assert(!j->after_key);
    before_value(j);
    json_write_string(j->f, key);
    fputc(':', j->f);
    j->after_key = true;
}

/* Length of the valid UTF-8 sequence at s (1..4), or 0 if the bytes there are not
 * one (stray continuation byte, overlong form, surrogate, beyond U+10FFFF, cut off). */
static size_t utf8_len(const unsigned char *s)
{
    unsigned c = s[0];
    size_t n;
    uint32_t cp;
    if (c < 0x80)
        return 1;
    if (c >= 0xc2 && c <= 0xdf) {
        n = 2;
        cp = c & 0x1f;
    } else if (c >= 0xe0 && c <= 0xef) {
        n = 3;
        cp = c & 0x0f;
    } else if (c >= 0xf0 && c <= 0xf4) {
        n = 4;
        cp = c & 0x07;
    } else {
        return 0;
    }
    for (size_t i = 1; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80)
            return 0;       /* also stops at the terminating NUL */
        cp = (cp << 6) | (s[i] & 0x3f);
    }
    if ((n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000) || cp > 0x10ffff ||
        (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    return n;
}

void json_write_string(FILE *f, const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    fputc('"', f);
    while (*p) {
        unsigned c = *p;
        switch (c) {
        case '"': fputs("\\\"", f); p++; continue;
        case '\\': fputs("\\\\", f); p++; continue;
        case '\b': fputs("\\b", f); p++; continue;
        case '\f': fputs("\\f", f); p++; continue;
        case '\n': fputs("\\n", f); p++; continue;
        case '\r': fputs("\\r", f); p++; continue;
        case '\t': fputs("\\t", f); p++; continue;
        default: break;
        }
        if (c < 0x20 || c == 0x7f) {
            fprintf(f, "\\u%04x", c);
            p++;
            continue;
        }
        size_t n = utf8_len(p);
        if (n == 0) {
            fputs("\\ufffd", f);
            p++;
            continue;
        }
        fwrite(p, 1, n, f);
        p += n;
    }
    fputc('"', f);
}

void json_write_number(FILE *f, double v)
{
    if (!isfinite(v)) {
        fputs("null", f);
        return;
    }
    if (v == 0) {
        fputs("0", f);      /* also -0: JSON readers differ on "-0" */
        return;
    }
    char buf[40];
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    fputs(buf, f);
}

void json_string(json_out *j, const char *s)
{
    before_value(j);
    if (s)
        json_write_string(j->f, s);
    else
        fputs("null", j->f);
}

void json_number(json_out *j, double v)
{
    before_value(j);
    json_write_number(j->f, v);
}

void json_int(json_out *j, int64_t v)
{
    before_value(j);
    fprintf(j->f, "%" PRId64, v);
}

void json_bool(json_out *j, bool v)
{
    before_value(j);
    fputs(v ? "true" : "false", j->f);
}

void json_null(json_out *j)
{
    before_value(j);
    fputs("null", j->f);
}

void json_finish(json_out *j)
{
    assert(j->depth == 0);
    fputc('\n', j->f);
}

/* ---- records ---- */

void json_symmetry(json_out *j, const sr_symmetry *sym)
{
    if (sym->kind == SR_SYM_NONE) {
        json_null(j);
        return;
    }
    json_object_begin(j);
    json_key(j, "kind");
    json_string(j, sr_sym_kind_name(sym->kind));
    if (sym->kind == SR_SYM_AXIAL) {
        json_key(j, "order");           /* 0 = continuous */
        json_int(j, sym->order);
    }
    if (sym->kind == SR_SYM_GLIDE) {
        json_key(j, "shift_mm");        /* 0 = found by search */
        json_number(j, sym->shift_mm);
    }
    json_object_end(j);
}

static void json_vec3(json_out *j, const double v[3])
{
    json_array_begin(j);
    for (int i = 0; i < 3; i++)
        json_number(j, v[i]);
    json_array_end(j);
}

/* The mesh summary fields shared by parts and instances; null when there is no mesh. */
static void json_mesh_fields(json_out *j, int64_t mesh_id, size_t vertex_count,
                             size_t tri_count, double volume, double area,
                             const double bmin[3], const double bmax[3])
{
    bool has = mesh_id != 0;
    json_key(j, "mesh_id");
    if (has)
        json_int(j, mesh_id);
    else
        json_null(j);
    json_key(j, "vertices");
    json_int(j, (int64_t)vertex_count);
    json_key(j, "triangles");
    json_int(j, (int64_t)tri_count);
    json_key(j, "volume_mm3");
    has ? json_number(j, volume) : json_null(j);
    json_key(j, "area_mm2");
    has ? json_number(j, area) : json_null(j);
    json_key(j, "bbox_min_mm");
    has ? json_vec3(j, bmin) : json_null(j);
    json_key(j, "bbox_max_mm");
    has ? json_vec3(j, bmax) : json_null(j);
}

void json_part(json_out *j, const sr_part_info *p)
{
    json_object_begin(j);
    json_part_members(j, p);
    json_object_end(j);
}

void json_part_members(json_out *j, const sr_part_info *p)
{
    json_key(j, "id");
    json_int(j, p->id);
    json_key(j, "number");
    json_string(j, p->number);
    json_key(j, "name");
    json_string(j, p->name);
    json_key(j, "material");
    json_string(j, p->material);
    json_key(j, "notes");
    json_string(j, p->notes);
    json_mesh_fields(j, p->mesh_id, p->vertex_count, p->tri_count, p->volume_mm3,
                     p->area_mm2, p->bbox_min, p->bbox_max);
    json_key(j, "symmetry");
    json_symmetry(j, &p->symmetry);
    json_key(j, "instance_count");
    json_int(j, p->instance_count);
    json_key(j, "created_at");
    json_string(j, p->created_at);
}

void json_instance(json_out *j, const sr_instance_info *in)
{
    json_object_begin(j);
    json_instance_members(j, in);
    json_object_end(j);
}

void json_instance_members(json_out *j, const sr_instance_info *in)
{
    json_key(j, "id");
    json_int(j, in->id);
    json_key(j, "part_id");
    json_int(j, in->part_id);
    json_key(j, "part_number");
    json_string(j, in->part_number);
    json_key(j, "serial");
    json_string(j, in->serial);
    json_key(j, "received");
    json_string(j, in->received[0] ? in->received : NULL);
    json_key(j, "notes");
    json_string(j, in->notes);
    json_mesh_fields(j, in->mesh_id, in->vertex_count, in->tri_count, in->volume_mm3,
                     in->area_mm2, in->bbox_min, in->bbox_max);
    json_key(j, "symmetry");
    json_symmetry(j, &in->symmetry);
    json_key(j, "created_at");
    json_string(j, in->created_at);
}

void json_params(json_out *j, const sr_params *p)
{
    json_object_begin(j);
    json_key(j, "name");
    json_string(j, p->name);
    json_key(j, "layers");
    json_int(j, p->layers);
    json_key(j, "sectors");
    json_int(j, p->sectors);
    json_key(j, "gamma_axis");
    json_number(j, p->gamma_axis);
    json_key(j, "gamma_plane");
    json_number(j, p->gamma_plane);
    json_key(j, "delta_d");
    json_number(j, p->delta_d);
    json_key(j, "min_depth_mm");
    json_number(j, p->min_depth_mm);
    json_key(j, "min_volume_mm3");
    json_number(j, p->min_volume_mm3);
    json_key(j, "notes");
    json_string(j, p->notes);
    json_object_end(j);
}
