/*
 * catalog_parts.c: parts (the shop's models), their materials and the symmetry rows
 * of parts and instances. A part is added with its material, intact mesh and
 * symmetry in one transaction; a part key is its number or, when no number matches,
 * its numeric id (so "1042" finds part number 1042 before part id 1042).
 */
#include "catalog/catalog_int.h"

#include <stdio.h>
#include <string.h>

#include "align/shape_descriptor.h"

/* One SELECT for a part's listing row, shared by find and list. Columns:
 * 0 id, 1 number, 2 name, 3 material, 4 notes, 5 mesh_id, 6..15 mesh figures,
 * 16 created_at, 17 instance count, 18..20 symmetry kind, order, shift, 21 the mesh's
 * source unit (NULL without a mesh). */
#define PART_SELECT                                                                                \
    "SELECT p.id, p.number, p.name, coalesce(m.name, ''), p.notes, coalesce(p.mesh_id, 0),"        \
    " me.vertex_count, me.tri_count, me.volume_mm3, me.area_mm2,"                                  \
    " me.bbox_min_x, me.bbox_min_y, me.bbox_min_z, me.bbox_max_x, me.bbox_max_y,"                  \
    " me.bbox_max_z, p.created_at,"                                                                \
    " (SELECT count(*) FROM instances i WHERE i.part_id = p.id),"                                  \
    " s.kind, s.order_n, s.shift_mm, me.source_unit"                                               \
    " FROM parts p"                                                                                \
    " LEFT JOIN materials m ON m.id = p.material_id"                                               \
    " LEFT JOIN meshes me ON me.id = p.mesh_id"                                                    \
    " LEFT JOIN symmetries s ON s.part_id = p.id"

static void read_part(sqlite3_stmt *stmt, sr_part_info *out)
{
    memset(out, 0, sizeof *out);
    out->id = sqlite3_column_int64(stmt, 0);
    sr_cat_column_text(stmt, 1, out->number, sizeof out->number);
    sr_cat_column_text(stmt, 2, out->name, sizeof out->name);
    sr_cat_column_text(stmt, 3, out->material, sizeof out->material);
    sr_cat_column_text(stmt, 4, out->notes, sizeof out->notes);
    out->mesh_id = sqlite3_column_int64(stmt, 5);
    sr_cat_mesh_figures f;
    sr_cat_column_figures(stmt, 6, &f);
    out->vertex_count = f.vertex_count;
    out->tri_count = f.tri_count;
    out->volume_mm3 = f.volume_mm3;
    out->area_mm2 = f.area_mm2;
    memcpy(out->bbox_min, f.bbox_min, sizeof f.bbox_min);
    memcpy(out->bbox_max, f.bbox_max, sizeof f.bbox_max);
    sr_cat_column_text(stmt, 16, out->created_at, sizeof out->created_at);
    out->instance_count = sqlite3_column_int64(stmt, 17);
    sr_cat_column_symmetry(stmt, 18, &out->symmetry);
    sr_cat_column_text(stmt, 21, out->source_unit, sizeof out->source_unit);
}

void sr_cat_column_symmetry(sqlite3_stmt *stmt, int col, sr_symmetry *out)
{
    memset(out, 0, sizeof *out);
    const char *kind = (const char *)sqlite3_column_text(stmt, col);
    if (!kind)
        return;
    sr_sym_kind k;
    if (sr_sym_kind_parse(kind, "kind", &k, NULL) != SR_OK)
        return;  /* impossible: the schema's CHECK allows only the three names */
    out->kind = k;
    out->order = sqlite3_column_int(stmt, col + 1);
    out->shift_mm = sqlite3_column_double(stmt, col + 2);
}

/* Runs a one-column id look-up; *found false when no row. */
static sr_status lookup_id(sr_catalog *cat, const char *sql, const char *text, int64_t id,
                           bool *found, int64_t *out_id, sr_err *err, const char *what)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    if (text)
        sqlite3_bind_text(stmt, 1, text, -1, SQLITE_TRANSIENT);
    else
        sqlite3_bind_int64(stmt, 1, id);
    st = sr_cat_step(cat, stmt, found, err, what);
    if (st == SR_OK && *found && out_id)
        *out_id = sqlite3_column_int64(stmt, 0);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, what);
}

sr_status sr_cat_part_resolve(sr_catalog *cat, const char *key, int64_t *out_id, sr_err *err)
{
    if (!key || !*key)
        return sr_err_set(err, SR_E_NOTFOUND, "no part given");
    bool found;
    sr_status st = lookup_id(cat, "SELECT id FROM parts WHERE number = ?1", key, 0, &found,
                             out_id, err, "find a part");
    if (st != SR_OK || found)
        return st;
    int64_t id;
    if (sr_cat_parse_id(key, &id)) {
        st = lookup_id(cat, "SELECT id FROM parts WHERE id = ?1", NULL, id, &found, out_id, err,
                       "find a part");
        if (st != SR_OK || found)
            return st;
    }
    return sr_err_set(err, SR_E_NOTFOUND, "no part '%s' in the catalogue", key);
}

sr_status sr_cat_symmetry_write(sr_catalog *cat, int64_t part_id, int64_t instance_id,
                                const sr_symmetry *sym, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "DELETE FROM symmetries WHERE part_id = ?1 OR instance_id = ?2", &stmt, err);
    if (st != SR_OK)
        return st;
    /* Binding NULL for the absent key: "x = NULL" matches nothing. */
    if (part_id)
        sqlite3_bind_int64(stmt, 1, part_id);
    if (instance_id)
        sqlite3_bind_int64(stmt, 2, instance_id);
    st = sr_cat_exec(cat, stmt, err, "replace a symmetry");
    if (st != SR_OK || sym->kind == SR_SYM_NONE)
        return st;
    st = sr_cat_prepare(cat,
                        "INSERT INTO symmetries (part_id, instance_id, kind, order_n, shift_mm)"
                        " VALUES (?1, ?2, ?3, ?4, ?5)",
                        &stmt, err);
    if (st != SR_OK)
        return st;
    if (part_id)
        sqlite3_bind_int64(stmt, 1, part_id);
    if (instance_id)
        sqlite3_bind_int64(stmt, 2, instance_id);
    sqlite3_bind_text(stmt, 3, sr_sym_kind_name(sym->kind), -1, SQLITE_STATIC);
    sqlite3_bind_int(stmt, 4, sym->order);
    sqlite3_bind_double(stmt, 5, sym->shift_mm);
    return sr_cat_exec(cat, stmt, err, "store a symmetry");
}

/* The id of material `name` (found ignoring ASCII case). A material enters the
 * catalogue only with its density (sr_catalog_material_add), so an unknown name is
 * refused rather than created empty: SR_E_NOTFOUND "no material 'X' in the catalogue". */
static sr_status material_id(sr_catalog *cat, const char *name, int64_t *out_id, sr_err *err)
{
    bool found;
    sr_status st = lookup_id(cat, "SELECT id FROM materials WHERE name = ?1", name, 0, &found,
                             out_id, err, "find a material");
    if (st == SR_OK && !found)
        st = sr_err_set(err, SR_E_NOTFOUND, "no material '%s' in the catalogue", name);
    return st;
}

/* A part's intact model must enclose its volume: closed, consistently oriented, its
 * volume positive (outward). Says what is wrong and how to store it anyway. */
static sr_status check_closed_solid(const sr_part_new *p, sr_err *err)
{
    const char *what = p->source_file && *p->source_file ? p->source_file : "its mesh";
    sr_status st = sr_mesh_validate(p->mesh, what, NULL, err);
    if (st != SR_OK)
        return st;
    sr_mesh_edges e;
    st = sr_mesh_edge_stats(p->mesh, &e);
    if (st != SR_OK)
        return sr_err_set(err, st, "cannot check the mesh of part '%s'", p->number);
    if (e.boundary_edges || e.nonmanifold_edges || e.misoriented_edges)
        return sr_err_set(err, SR_E_INVALID,
                          "part '%s': '%s' is not a closed solid (%zu boundary, %zu "
                          "non-manifold, %zu misoriented edges); a part's mesh is its intact "
                          "model (store it anyway with --allow-open)",
                          p->number, what, e.boundary_edges, e.nonmanifold_edges,
                          e.misoriented_edges);
    double volume = sr_mesh_volume(p->mesh);
    if (!(volume > 0))
        return sr_err_set(err, SR_E_INVALID,
                          "part '%s': '%s' encloses no volume (%.6g mm³: %s); a part's mesh is "
                          "its intact model (store it anyway with --allow-open)",
                          p->number, what, volume,
                          volume < 0 ? "its triangles face inward" : "it is flat");
    return SR_OK;
}

static sr_status check_part_new(const sr_part_new *p, sr_err *err)
{
    if (!p->number || !*p->number)
        return sr_err_set(err, SR_E_RANGE, "a part needs a number");
    if (!sr_cat_len_ok(p->number, 1, 63))
        return sr_err_set(err, SR_E_RANGE, "bad part number '%.40s...': longer than 63 bytes",
                          p->number);
    if (!p->name || !*p->name)
        return sr_err_set(err, SR_E_RANGE, "part '%s' needs a name", p->number);
    if (!sr_cat_len_ok(p->name, 1, 127))
        return sr_err_set(err, SR_E_RANGE, "bad name of part '%s': longer than 127 bytes",
                          p->number);
    if (!sr_cat_len_ok(p->material, 0, 63))
        return sr_err_set(err, SR_E_RANGE, "bad material of part '%s': longer than 63 bytes",
                          p->number);
    if (!sr_cat_len_ok(p->notes, 0, 511))
        return sr_err_set(err, SR_E_RANGE, "bad notes of part '%s': longer than 511 bytes",
                          p->number);
    if (p->symmetry.kind != SR_SYM_NONE) {
        sr_status st = sr_symmetry_check(&p->symmetry, err);
        if (st != SR_OK)
            return st;
    }
    return p->mesh && !p->allow_open ? check_closed_solid(p, err) : SR_OK;
}

sr_status sr_catalog_part_add(sr_catalog *cat, const sr_part_new *part, int64_t *out_id,
                              sr_err *err)
{
    sr_status st = check_part_new(part, err);
    if (st != SR_OK)
        return st;
    sr_cat_mesh_row mesh_row = {0};
    sr_shape_descriptor desc;
    if (part->mesh) {
        char what[128];
        if (part->source_file && *part->source_file)
            snprintf(what, sizeof what, "%s", part->source_file);
        else
            snprintf(what, sizeof what, "mesh of part %s", part->number);
        st = sr_cat_mesh_row_build(cat, part->mesh, what, part->source_file, &mesh_row, err);
        if (st == SR_OK) /* for `symrec identify`: computed now, stored with the mesh */
            st = sr_shape_descriptor_compute(part->mesh, what, &desc, err);
        if (st != SR_OK) {
            sr_cat_mesh_row_release(&mesh_row);
            return st;
        }
        mesh_row.source_unit = part->source_unit;
    }

    st = sr_cat_begin(cat, err);
    if (st != SR_OK) {
        sr_cat_mesh_row_release(&mesh_row);
        return st;
    }
    bool taken;
    st = lookup_id(cat, "SELECT id FROM parts WHERE number = ?1", part->number, 0, &taken, NULL,
                   err, "add a part");
    if (st != SR_OK)
        goto fail;
    if (taken) {
        st = sr_err_set(err, SR_E_EXISTS, "part '%s' is already in the catalogue", part->number);
        goto fail;
    }
    int64_t mat_id = 0, mesh_id = 0, part_id;
    if (part->material && *part->material) {
        st = material_id(cat, part->material, &mat_id, err);
        if (st != SR_OK)
            goto fail;
    }
    if (part->mesh) {
        st = sr_cat_mesh_row_insert(cat, &mesh_row, &mesh_id, err);
        /* (a handle kept at an older schema, as the migration tests make, has no
         * table for it: the first identification after migrating computes it) */
        if (st == SR_OK && cat->schema_version >= SR_CAT_DESCRIPTOR_SCHEMA)
            st = sr_cat_descriptor_put(cat, mesh_id, &desc, err);
        if (st != SR_OK)
            goto fail;
    }
    sqlite3_stmt *stmt;
    st = sr_cat_prepare(cat,
                        "INSERT INTO parts (number, name, material_id, notes, mesh_id)"
                        " VALUES (?1, ?2, ?3, coalesce(?4, ''), ?5)",
                        &stmt, err);
    if (st != SR_OK)
        goto fail;
    sqlite3_bind_text(stmt, 1, part->number, -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(stmt, 2, part->name, -1, SQLITE_TRANSIENT);
    if (mat_id)
        sqlite3_bind_int64(stmt, 3, mat_id);
    sr_cat_bind_opt_text(stmt, 4, part->notes);
    if (mesh_id)
        sqlite3_bind_int64(stmt, 5, mesh_id);
    st = sr_cat_exec(cat, stmt, err, "add a part");
    if (st != SR_OK)
        goto fail;
    part_id = sqlite3_last_insert_rowid(cat->db);
    if (part->symmetry.kind != SR_SYM_NONE) {
        st = sr_cat_symmetry_write(cat, part_id, 0, &part->symmetry, err);
        if (st != SR_OK)
            goto fail;
    }
    st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        goto fail;
    sr_cat_mesh_row_release(&mesh_row);
    if (out_id)
        *out_id = part_id;
    return SR_OK;
fail:
    sr_cat_rollback(cat);
    sr_cat_mesh_row_release(&mesh_row);
    return st;
}

/* Runs PART_SELECT + `where` with one bound key; *found false when no row. */
static sr_status part_query(sr_catalog *cat, const char *sql, const char *text, int64_t id,
                            bool *found, sr_part_info *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, sql, &stmt, err);
    if (st != SR_OK)
        return st;
    if (text)
        sqlite3_bind_text(stmt, 1, text, -1, SQLITE_TRANSIENT);
    else
        sqlite3_bind_int64(stmt, 1, id);
    st = sr_cat_step(cat, stmt, found, err, "find a part");
    if (st == SR_OK && *found)
        read_part(stmt, out);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, "find a part");
}

sr_status sr_catalog_part_find(sr_catalog *cat, const char *key, sr_part_info *out,
                               sr_err *err)
{
    if (!key || !*key)
        return sr_err_set(err, SR_E_NOTFOUND, "no part given");
    sr_part_info info;
    bool found;
    sr_status st = part_query(cat, PART_SELECT " WHERE p.number = ?1", key, 0, &found, &info, err);
    int64_t id;
    if (st == SR_OK && !found && sr_cat_parse_id(key, &id))
        st = part_query(cat, PART_SELECT " WHERE p.id = ?1", NULL, id, &found, &info, err);
    if (st != SR_OK)
        return st;
    if (!found)
        return sr_err_set(err, SR_E_NOTFOUND, "no part '%s' in the catalogue", key);
    *out = info;
    return SR_OK;
}

sr_status sr_catalog_part_list(sr_catalog *cat, const sr_part_filter *filter, sr_part_fn fn,
                               void *user, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat,
        PART_SELECT
        " WHERE (?1 IS NULL OR instr(lower(p.name), lower(?1)) > 0)"
        " AND (?2 IS NULL OR instr(lower(p.number), lower(?2)) > 0)"
        " AND (?3 IS NULL OR m.name = ?3)"
        " ORDER BY p.number, p.id",
        &stmt, err);
    if (st != SR_OK)
        return st;
    if (filter) {
        sr_cat_bind_opt_text(stmt, 1, filter->name);
        sr_cat_bind_opt_text(stmt, 2, filter->number);
        sr_cat_bind_opt_text(stmt, 3, filter->material);
    }
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "list parts");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            break;
        sr_part_info info;
        read_part(stmt, &info);
        if (fn(&info, user))
            break;
    }
    return sr_cat_finish(cat, stmt, err, "list parts");
}

sr_status sr_catalog_part_mesh(sr_catalog *cat, int64_t part_id, sr_mesh *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT p.number, p.mesh_id, me.vertex_count, me.tri_count,"
                                  " me.format_version, me.data"
                                  " FROM parts p LEFT JOIN meshes me ON me.id = p.mesh_id"
                                  " WHERE p.id = ?1",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, part_id);
    bool row;
    sr_mesh m;
    st = sr_cat_step(cat, stmt, &row, err, "load a part's mesh");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no part %lld in the catalogue", (long long)part_id);
    if (st == SR_OK && sqlite3_column_type(stmt, 1) == SQLITE_NULL)
        st = sr_err_set(err, SR_E_NOTFOUND, "part '%s' has no mesh in the catalogue",
                        (const char *)sqlite3_column_text(stmt, 0));
    if (st == SR_OK)
        st = sr_cat_mesh_from_row(cat, stmt, 2, sqlite3_column_int64(stmt, 1), &m, err);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "load a part's mesh");
    if (st != SR_OK) {
        sr_mesh_release(&m);
        return st;
    }
    *out = m;
    return SR_OK;
}

sr_status sr_catalog_part_set_symmetry(sr_catalog *cat, int64_t part_id,
                                       const sr_symmetry *sym, sr_err *err)
{
    if (sym->kind != SR_SYM_NONE) {
        sr_status st = sr_symmetry_check(sym, err);
        if (st != SR_OK)
            return st;
    }
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    bool found;
    st = lookup_id(cat, "SELECT id FROM parts WHERE id = ?1", NULL, part_id, &found, NULL, err,
                   "set a part's symmetry");
    if (st == SR_OK && !found)
        st = sr_err_set(err, SR_E_NOTFOUND, "no part %lld in the catalogue", (long long)part_id);
    if (st == SR_OK)
        st = sr_cat_symmetry_write(cat, part_id, 0, sym, err);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        sr_cat_rollback(cat);
    return st;
}

sr_status sr_catalog_part_set(sr_catalog *cat, const char *key, const sr_part_change *ch,
                              sr_err *err)
{
    if (!ch->number && !ch->name && !ch->material && !ch->notes && !ch->set_symmetry)
        return sr_err_set(err, SR_E_INVALID, "nothing to change in part '%s'", key ? key : "");
    if (ch->number && !sr_cat_len_ok(ch->number, 1, 63))
        return sr_err_set(err, SR_E_RANGE, "bad part number '%.40s': expected 1..63 bytes",
                          ch->number);
    if (ch->name && !sr_cat_len_ok(ch->name, 1, 127))
        return sr_err_set(err, SR_E_RANGE, "bad name of part '%s': expected 1..127 bytes", key);
    if (ch->material && !sr_cat_len_ok(ch->material, 1, 63))
        return sr_err_set(err, SR_E_RANGE, "bad material of part '%s': expected 1..63 bytes", key);
    if (ch->notes && !sr_cat_len_ok(ch->notes, 0, 511))
        return sr_err_set(err, SR_E_RANGE, "bad notes of part '%s': longer than 511 bytes", key);
    if (ch->set_symmetry && ch->symmetry.kind != SR_SYM_NONE) {
        sr_status st = sr_symmetry_check(&ch->symmetry, err);
        if (st != SR_OK)
            return st;
    }
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    int64_t part_id, mat_id = 0;
    st = sr_cat_part_resolve(cat, key, &part_id, err);
    if (st == SR_OK && ch->material)
        st = material_id(cat, ch->material, &mat_id, err);
    if (st == SR_OK && ch->number) {
        bool taken;
        int64_t other = 0;
        st = lookup_id(cat, "SELECT id FROM parts WHERE number = ?1", ch->number, 0, &taken, &other,
                       err, "change a part");
        if (st == SR_OK && taken && other != part_id)
            st = sr_err_set(err, SR_E_EXISTS, "part '%s' is already in the catalogue", ch->number);
    }
    sqlite3_stmt *stmt;
    if (st == SR_OK)
        st = sr_cat_prepare(cat,
                            "UPDATE parts SET number = coalesce(?2, number),"
                            " name = coalesce(?3, name), material_id = coalesce(?4, material_id),"
                            " notes = coalesce(?5, notes) WHERE id = ?1",
                            &stmt, err);
    if (st == SR_OK) {
        sqlite3_bind_int64(stmt, 1, part_id);
        if (ch->number)
            sqlite3_bind_text(stmt, 2, ch->number, -1, SQLITE_TRANSIENT);
        if (ch->name)
            sqlite3_bind_text(stmt, 3, ch->name, -1, SQLITE_TRANSIENT);
        if (mat_id)
            sqlite3_bind_int64(stmt, 4, mat_id);
        if (ch->notes)
            sqlite3_bind_text(stmt, 5, ch->notes, -1, SQLITE_TRANSIENT);
        st = sr_cat_exec(cat, stmt, err, "change a part");
    }
    if (st == SR_OK && ch->set_symmetry)
        st = sr_cat_symmetry_write(cat, part_id, 0, &ch->symmetry, err);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        sr_cat_rollback(cat);
    return st;
}
