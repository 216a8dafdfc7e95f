/*
 * catalog_instances.c: damaged instances of parts, each with its scan (a mesh row)
 * and an optional symmetry override. An instance is added with its mesh and override
 * in one transaction, so an unknown part or a refused value leaves no orphan mesh.
 * An instance's effective symmetry is its override, else its part's.
 */
#include "catalog/catalog_int.h"

#include <stdio.h>
#include <string.h>

/* Columns: 0 id, 1 part_id, 2 part number, 3 serial, 4 received, 5 notes, 6 mesh_id,
 * 7..16 mesh figures, 17 created_at, 18..20 override symmetry, 21..23 part symmetry,
 * 24 the scan's source unit. */
#define INSTANCE_SELECT                                                                            \
    "SELECT i.id, i.part_id, p.number, coalesce(i.serial, ''), coalesce(i.received, ''),"          \
    " i.notes, i.mesh_id,"                                                                         \
    " me.vertex_count, me.tri_count, me.volume_mm3, me.area_mm2,"                                  \
    " me.bbox_min_x, me.bbox_min_y, me.bbox_min_z, me.bbox_max_x, me.bbox_max_y,"                  \
    " me.bbox_max_z, i.created_at,"                                                                \
    " si.kind, si.order_n, si.shift_mm, sp.kind, sp.order_n, sp.shift_mm, me.source_unit"          \
    " FROM instances i"                                                                            \
    " JOIN parts p ON p.id = i.part_id"                                                            \
    " JOIN meshes me ON me.id = i.mesh_id"                                                         \
    " LEFT JOIN symmetries si ON si.instance_id = i.id"                                            \
    " LEFT JOIN symmetries sp ON sp.part_id = i.part_id"

static void read_instance(sqlite3_stmt *stmt, sr_instance_info *out)
{
    memset(out, 0, sizeof *out);
    out->id = sqlite3_column_int64(stmt, 0);
    out->part_id = sqlite3_column_int64(stmt, 1);
    sr_cat_column_text(stmt, 2, out->part_number, sizeof out->part_number);
    sr_cat_column_text(stmt, 3, out->serial, sizeof out->serial);
    sr_cat_column_text(stmt, 4, out->received, sizeof out->received);
    sr_cat_column_text(stmt, 5, out->notes, sizeof out->notes);
    out->mesh_id = sqlite3_column_int64(stmt, 6);
    sr_cat_mesh_figures f;
    sr_cat_column_figures(stmt, 7, &f);
    out->vertex_count = f.vertex_count;
    out->tri_count = f.tri_count;
    out->volume_mm3 = f.volume_mm3;
    out->area_mm2 = f.area_mm2;
    memcpy(out->bbox_min, f.bbox_min, sizeof f.bbox_min);
    memcpy(out->bbox_max, f.bbox_max, sizeof f.bbox_max);
    sr_cat_column_text(stmt, 17, out->created_at, sizeof out->created_at);
    sr_cat_column_symmetry(stmt, 18, &out->symmetry);
    if (out->symmetry.kind == SR_SYM_NONE)
        sr_cat_column_symmetry(stmt, 21, &out->symmetry);
    sr_cat_column_text(stmt, 24, out->source_unit, sizeof out->source_unit);
}

/* True for a real calendar date written YYYY-MM-DD (years 0001..9999). */
static bool date_ok(const char *s)
{
    if (strlen(s) != 10 || s[4] != '-' || s[7] != '-')
        return false;
    for (int i = 0; i < 10; i++)
        if (i != 4 && i != 7 && (s[i] < '0' || s[i] > '9'))
            return false;
    int y = (s[0] - '0') * 1000 + (s[1] - '0') * 100 + (s[2] - '0') * 10 + (s[3] - '0');
    int m = (s[5] - '0') * 10 + (s[6] - '0');
    int d = (s[8] - '0') * 10 + (s[9] - '0');
    static const int days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (y < 1 || m < 1 || m > 12 || d < 1)
        return false;
    bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    return d <= days[m - 1] + (m == 2 && leap);
}

static sr_status check_instance_new(const sr_instance_new *in, sr_err *err)
{
    if (!in->part || !*in->part)
        return sr_err_set(err, SR_E_RANGE, "an instance needs a part (number or id)");
    if (!in->mesh)
        return sr_err_set(err, SR_E_INVALID, "an instance of part '%s' needs a mesh (its scan)",
                          in->part);
    if (!sr_cat_len_ok(in->serial, 0, 63))
        return sr_err_set(err, SR_E_RANGE, "bad serial '%.40s...': longer than 63 bytes",
                          in->serial);
    if (in->received && *in->received && !date_ok(in->received))
        return sr_err_set(err, SR_E_RANGE, "bad received date '%.40s': expected YYYY-MM-DD",
                          in->received);
    if (!sr_cat_len_ok(in->notes, 0, 511))
        return sr_err_set(err, SR_E_RANGE, "bad notes of an instance of part '%s': longer than "
                          "511 bytes", in->part);
    if (in->symmetry.kind != SR_SYM_NONE)
        return sr_symmetry_check(&in->symmetry, err);
    return SR_OK;
}

sr_status sr_catalog_instance_add(sr_catalog *cat, const sr_instance_new *inst,
                                  int64_t *out_id, sr_err *err)
{
    sr_status st = check_instance_new(inst, err);
    if (st != SR_OK)
        return st;
    char what[128];
    if (inst->source_file && *inst->source_file)
        snprintf(what, sizeof what, "%s", inst->source_file);
    else
        snprintf(what, sizeof what, "scan of part %s", inst->part);
    sr_cat_mesh_row mesh_row = {0};
    st = sr_cat_mesh_row_build(cat, inst->mesh, what, inst->source_file, &mesh_row, err);
    if (st != SR_OK)
        return st;
    mesh_row.source_unit = inst->source_unit;

    st = sr_cat_begin(cat, err);
    if (st != SR_OK) {
        sr_cat_mesh_row_release(&mesh_row);
        return st;
    }
    int64_t part_id, mesh_id, inst_id;
    sqlite3_stmt *stmt;
    st = sr_cat_part_resolve(cat, inst->part, &part_id, err);
    if (st != SR_OK)
        goto fail;
    st = sr_cat_mesh_row_insert(cat, &mesh_row, &mesh_id, err);
    if (st != SR_OK)
        goto fail;
    st = sr_cat_prepare(cat,
                        "INSERT INTO instances (part_id, serial, received, notes, mesh_id)"
                        " VALUES (?1, ?2, coalesce(?3, date('now')), coalesce(?4, ''), ?5)",
                        &stmt, err);
    if (st != SR_OK)
        goto fail;
    sqlite3_bind_int64(stmt, 1, part_id);
    sr_cat_bind_opt_text(stmt, 2, inst->serial);
    sr_cat_bind_opt_text(stmt, 3, inst->received);
    sr_cat_bind_opt_text(stmt, 4, inst->notes);
    sqlite3_bind_int64(stmt, 5, mesh_id);
    st = sr_cat_exec(cat, stmt, err, "add an instance");
    if (st != SR_OK)
        goto fail;
    inst_id = sqlite3_last_insert_rowid(cat->db);
    if (inst->symmetry.kind != SR_SYM_NONE) {
        st = sr_cat_symmetry_write(cat, 0, inst_id, &inst->symmetry, err);
        if (st != SR_OK)
            goto fail;
    }
    st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        goto fail;
    sr_cat_mesh_row_release(&mesh_row);
    if (out_id)
        *out_id = inst_id;
    return SR_OK;
fail:
    sr_cat_rollback(cat);
    sr_cat_mesh_row_release(&mesh_row);
    return st;
}

sr_status sr_catalog_instance_get(sr_catalog *cat, int64_t id, sr_instance_info *out,
                                  sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat, INSTANCE_SELECT " WHERE i.id = ?1", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, id);
    bool row;
    sr_instance_info info;
    st = sr_cat_step(cat, stmt, &row, err, "find an instance");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no instance %lld in the catalogue", (long long)id);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    read_instance(stmt, &info);
    st = sr_cat_finish(cat, stmt, err, "find an instance");
    if (st != SR_OK)
        return st;
    *out = info;
    return SR_OK;
}

sr_status sr_catalog_instance_list(sr_catalog *cat, const char *part, sr_instance_fn fn,
                                   void *user, sr_err *err)
{
    int64_t part_id = 0;
    if (part) {
        sr_status st = sr_cat_part_resolve(cat, part, &part_id, err);
        if (st != SR_OK)
            return st;
    }
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, INSTANCE_SELECT " WHERE (?1 IS NULL OR i.part_id = ?1) ORDER BY i.id", &stmt, err);
    if (st != SR_OK)
        return st;
    if (part)
        sqlite3_bind_int64(stmt, 1, part_id);
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "list instances");
        if (st != SR_OK) {
            sqlite3_finalize(stmt);
            return st;
        }
        if (!row)
            break;
        sr_instance_info info;
        read_instance(stmt, &info);
        if (fn(&info, user))
            break;
    }
    return sr_cat_finish(cat, stmt, err, "list instances");
}

sr_status sr_catalog_instance_mesh(sr_catalog *cat, int64_t instance_id, sr_mesh *out,
                                   sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT i.mesh_id, me.vertex_count, me.tri_count,"
                                  " me.format_version, me.data"
                                  " FROM instances i JOIN meshes me ON me.id = i.mesh_id"
                                  " WHERE i.id = ?1",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, instance_id);
    bool row;
    sr_mesh m;
    st = sr_cat_step(cat, stmt, &row, err, "load an instance's mesh");
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no instance %lld in the catalogue",
                        (long long)instance_id);
    if (st == SR_OK)
        st = sr_cat_mesh_from_row(cat, stmt, 1, sqlite3_column_int64(stmt, 0), &m, err);
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    st = sr_cat_finish(cat, stmt, err, "load an instance's mesh");
    if (st != SR_OK) {
        sr_mesh_release(&m);
        return st;
    }
    *out = m;
    return SR_OK;
}

sr_status sr_catalog_instance_set_symmetry(sr_catalog *cat, int64_t instance_id,
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
    sqlite3_stmt *stmt = NULL;
    bool row = false;
    st = sr_cat_prepare(cat, "SELECT 1 FROM instances WHERE id = ?1", &stmt, err);
    if (st == SR_OK) {
        sqlite3_bind_int64(stmt, 1, instance_id);
        st = sr_cat_step(cat, stmt, &row, err, "set an instance's symmetry");
        if (st == SR_OK)
            st = sr_cat_finish(cat, stmt, err, "set an instance's symmetry");
        else
            sqlite3_finalize(stmt);
    }
    if (st == SR_OK && !row)
        st = sr_err_set(err, SR_E_NOTFOUND, "no instance %lld in the catalogue",
                        (long long)instance_id);
    if (st == SR_OK)
        st = sr_cat_symmetry_write(cat, 0, instance_id, sym, err);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        sr_cat_rollback(cat);
    return st;
}

sr_status sr_catalog_instance_set(sr_catalog *cat, int64_t id, const sr_instance_change *ch,
                                  sr_err *err)
{
    if (!ch->serial && !ch->received && !ch->notes)
        return sr_err_set(err, SR_E_INVALID, "nothing to change in instance %lld", (long long)id);
    if (ch->serial && !sr_cat_len_ok(ch->serial, 0, 63))
        return sr_err_set(err, SR_E_RANGE, "bad serial '%.40s...': longer than 63 bytes",
                          ch->serial);
    if (ch->received && *ch->received && !date_ok(ch->received))
        return sr_err_set(err, SR_E_RANGE, "bad received date '%.40s': expected YYYY-MM-DD",
                          ch->received);
    if (ch->notes && !sr_cat_len_ok(ch->notes, 0, 511))
        return sr_err_set(err, SR_E_RANGE, "bad notes of instance %lld: longer than 511 bytes",
                          (long long)id);
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    /* ?5/?6/?7 say whether serial/received/notes change; "" binds as NULL (unknown) */
    sqlite3_stmt *stmt;
    st = sr_cat_prepare(cat,
                        "UPDATE instances SET serial = CASE WHEN ?5 THEN ?2 ELSE serial END,"
                        " received = CASE WHEN ?6 THEN ?3 ELSE received END,"
                        " notes = CASE WHEN ?7 THEN coalesce(?4, '') ELSE notes END"
                        " WHERE id = ?1",
                        &stmt, err);
    if (st == SR_OK) {
        sqlite3_bind_int64(stmt, 1, id);
        sr_cat_bind_opt_text(stmt, 2, ch->serial);
        sr_cat_bind_opt_text(stmt, 3, ch->received);
        sr_cat_bind_opt_text(stmt, 4, ch->notes);
        sqlite3_bind_int(stmt, 5, ch->serial != NULL);
        sqlite3_bind_int(stmt, 6, ch->received != NULL);
        sqlite3_bind_int(stmt, 7, ch->notes != NULL);
        st = sr_cat_exec(cat, stmt, err, "change an instance");
    }
    if (st == SR_OK && sqlite3_changes(cat->db) == 0)
        st = sr_err_set(err, SR_E_NOTFOUND, "no instance %lld in the catalogue", (long long)id);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK)
        sr_cat_rollback(cat);
    return st;
}
