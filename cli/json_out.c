/*
 * json_out.c: the CLI's --json writer (see json_out.h): a FILE and an in-memory
 * document built by base/jsonbuf.h, written whole by json_finish; and the JSON form
 * of the catalogue's records (part, instance, symmetry, parameter set) so that every
 * command prints a record with the same keys.
 *
 * Keys carry their unit (volume_mm3, area_mm2, shift_mm); absent values are null, never
 * a made-up zero.
 */
#include "json_out.h"

#include <assert.h>
#include <stdlib.h>

#include "base/symmetry.h"
#include "cli.h"

void json_init(json_out *j, FILE *f)
{
    j->f = f;
    sr_jsonbuf_init(&j->jb);
}

void json_object_begin(json_out *j) { sr_jsonbuf_object_begin(&j->jb); }
void json_object_end(json_out *j) { sr_jsonbuf_object_end(&j->jb); }
void json_array_begin(json_out *j) { sr_jsonbuf_array_begin(&j->jb); }
void json_array_end(json_out *j) { sr_jsonbuf_array_end(&j->jb); }
void json_key(json_out *j, const char *key) { sr_jsonbuf_key(&j->jb, key); }
void json_string(json_out *j, const char *s) { sr_jsonbuf_string(&j->jb, s); }
void json_number(json_out *j, double v) { sr_jsonbuf_number(&j->jb, v); }
void json_int(json_out *j, int64_t v) { sr_jsonbuf_int(&j->jb, v); }
void json_bool(json_out *j, bool v) { sr_jsonbuf_bool(&j->jb, v); }
void json_null(json_out *j) { sr_jsonbuf_null(&j->jb); }
void json_raw(json_out *j, const char *json) { sr_jsonbuf_raw(&j->jb, json); }

void json_key_raw(json_out *j, const char *key, size_t len)
{
    sr_jsonbuf_key_raw(&j->jb, key, len);
}

void json_nomem(json_out *j)
{
    j->jb.nomem = true;     /* the builder's sticky failure: later appends do nothing */
}

sr_status json_end(json_out *j, sr_err *err)
{
    /* a balanced document, unless building it stopped early */
    assert(j->jb.nomem || (j->jb.depth == 0 && !j->jb.after_key));
    char *text;
    sr_status st = sr_jsonbuf_take(&j->jb, &text, err);
    if (st != SR_OK)
        return st;
    fputs(text, j->f);
    fputc('\n', j->f);
    free(text);
    return SR_OK;
}

int json_finish(json_out *j)
{
    sr_err err;
    sr_err_clear(&err);
    sr_status st = json_end(j, &err);
    return st == SR_OK ? CLI_OK : cli_fail(st, &err);
}

void json_discard(json_out *j)
{
    sr_jsonbuf_release(&j->jb);
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
static void json_mesh_fields(json_out *j, int64_t mesh_id, size_t vertex_count, size_t tri_count,
                             double volume, double area, const double bmin[3], const double bmax[3],
                             const char *unit)
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
    json_key(j, "source_unit"); /* the unit the file was drawn in; the figures are mm */
    json_string(j, has && unit[0] ? unit : NULL);
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
    json_mesh_fields(j, p->mesh_id, p->vertex_count, p->tri_count, p->volume_mm3, p->area_mm2,
                     p->bbox_min, p->bbox_max, p->source_unit);
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
    json_mesh_fields(j, in->mesh_id, in->vertex_count, in->tri_count, in->volume_mm3, in->area_mm2,
                     in->bbox_min, in->bbox_max, in->source_unit);
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
