/*
 * catalog_identify.c: `symrec identify` on the catalogue (catalog_identify.h): the
 * parts' stored shape descriptors (table mesh_descriptors, sql/006_part_descriptor.sql),
 * their backfill, the descriptor pre-filter and the registration of the shortlist.
 *
 * The backfill of parts added before migration 006 happens here, when a scan is
 * identified: SQL cannot compute a descriptor, and computing them at open would slow
 * every command on a large catalogue for a feature it may not use. On a writable
 * catalogue the computed descriptors are stored in one transaction, so it happens
 * once; a read-only catalogue computes them on every run without storing.
 */
#include "catalog/catalog_identify.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "catalog/catalog_int.h"

#define DESC_BYTES SR_CAT_DESCRIPTOR_BYTES

void sr_cat_descriptor_pack(const sr_shape_descriptor *d, unsigned char *out)
{
    sr_cat_put_f64(out, SR_SHAPE_DESCRIPTOR_VERSION);
    sr_cat_put_f64(out + 8, d->area_mm2);
    for (int k = 0; k < 3; k++)
        sr_cat_put_f64(out + 16 + 8 * k, d->spread_mm[k]);
    for (int k = 0; k < SR_SHAPE_D2_BINS; k++)
        sr_cat_put_f64(out + 40 + 8 * k, d->d2[k]);
}

sr_status sr_cat_descriptor_unpack(const void *data, size_t size, sr_shape_descriptor *out,
                                   sr_err *err)
{
    const unsigned char *p = data;
    if (!p || size != DESC_BYTES)
        return sr_err_set(err, SR_E_FORMAT, "shape descriptor: %zu bytes, not %d", size,
                          DESC_BYTES);
    if (sr_cat_get_f64(p) != SR_SHAPE_DESCRIPTOR_VERSION)
        return sr_err_set(err, SR_E_FORMAT, "shape descriptor: version %g, not %d",
                          sr_cat_get_f64(p), SR_SHAPE_DESCRIPTOR_VERSION);
    sr_shape_descriptor d;
    d.area_mm2 = sr_cat_get_f64(p + 8);
    bool ok = isfinite(d.area_mm2) && d.area_mm2 >= 0;
    for (int k = 0; k < 3; k++) {
        d.spread_mm[k] = sr_cat_get_f64(p + 16 + 8 * k);
        ok = ok && isfinite(d.spread_mm[k]) && d.spread_mm[k] >= 0;
    }
    for (int k = 0; k < SR_SHAPE_D2_BINS; k++) {
        d.d2[k] = sr_cat_get_f64(p + 40 + 8 * k);
        ok = ok && isfinite(d.d2[k]) && d.d2[k] >= 0;
    }
    if (!ok)
        return sr_err_set(err, SR_E_FORMAT, "shape descriptor: a figure is negative or not finite");
    *out = d;
    return SR_OK;
}

sr_status sr_cat_descriptor_put(sr_catalog *cat, int64_t mesh_id, const sr_shape_descriptor *d,
                                sr_err *err)
{
    unsigned char blob[DESC_BYTES];
    sr_cat_descriptor_pack(d, blob);
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "INSERT OR REPLACE INTO mesh_descriptors (mesh_id, version, data) VALUES (?1, ?2, ?3)",
        &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, mesh_id);
    sqlite3_bind_int(stmt, 2, SR_SHAPE_DESCRIPTOR_VERSION);
    sqlite3_bind_blob(stmt, 3, blob, DESC_BYTES, SQLITE_TRANSIENT);
    return sr_cat_exec(cat, stmt, err, "store a shape descriptor");
}

sr_status sr_catalog_mesh_descriptor(sr_catalog *cat, int64_t mesh_id, sr_shape_descriptor *out,
                                     sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(
        cat, "SELECT data FROM mesh_descriptors WHERE mesh_id = ?1 AND version = ?2", &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int64(stmt, 1, mesh_id);
    sqlite3_bind_int(stmt, 2, SR_SHAPE_DESCRIPTOR_VERSION);
    bool row;
    st = sr_cat_step(cat, stmt, &row, err, "read a shape descriptor");
    if (st == SR_OK && !row)
        st =
            sr_err_set(err, SR_E_NOTFOUND, "mesh %lld has no shape descriptor", (long long)mesh_id);
    if (st == SR_OK)
        st = sr_cat_descriptor_unpack(sqlite3_column_blob(stmt, 0),
                                      (size_t)sqlite3_column_bytes(stmt, 0), out, err);
    sqlite3_finalize(stmt);
    return st;
}

/* One part with an intact mesh, as compared. */
typedef struct entry {
    int64_t part_id, mesh_id;
    char number[64], name[128];
    bool have;  /* desc read from the catalogue */
    bool fresh; /* desc computed here */
    sr_shape_descriptor desc;
    double dist;
} entry;

typedef struct entry_vec {
    entry *v;
    size_t count, cap;
} entry_vec;

/* Every part with an intact mesh, with its stored descriptor when it has a usable one. */
static sr_status read_entries(sr_catalog *cat, entry_vec *out, sr_err *err)
{
    sqlite3_stmt *stmt;
    sr_status st = sr_cat_prepare(cat,
                                  "SELECT p.id, p.mesh_id, p.number, p.name, d.data"
                                  " FROM parts p LEFT JOIN mesh_descriptors d"
                                  " ON d.mesh_id = p.mesh_id AND d.version = ?1"
                                  " WHERE p.mesh_id IS NOT NULL ORDER BY p.number",
                                  &stmt, err);
    if (st != SR_OK)
        return st;
    sqlite3_bind_int(stmt, 1, SR_SHAPE_DESCRIPTOR_VERSION);
    for (;;) {
        bool row;
        st = sr_cat_step(cat, stmt, &row, err, "read the parts' descriptors");
        if (st != SR_OK || !row)
            break;
        entry *v = sr_grow(out->v, out->count, &out->cap, sizeof *v);
        if (!v) {
            st = sr_err_set(err, SR_E_NOMEM, "out of memory reading the parts");
            break;
        }
        out->v = v;
        entry *e = &out->v[out->count++];
        memset(e, 0, sizeof *e);
        e->part_id = sqlite3_column_int64(stmt, 0);
        e->mesh_id = sqlite3_column_int64(stmt, 1);
        sr_cat_column_text(stmt, 2, e->number, sizeof e->number);
        sr_cat_column_text(stmt, 3, e->name, sizeof e->name);
        /* a damaged descriptor is computed again, like a missing one */
        e->have = sqlite3_column_type(stmt, 4) == SQLITE_BLOB &&
                  sr_cat_descriptor_unpack(sqlite3_column_blob(stmt, 4),
                                           (size_t)sqlite3_column_bytes(stmt, 4), &e->desc,
                                           NULL) == SR_OK;
    }
    if (st != SR_OK) {
        sqlite3_finalize(stmt);
        return st;
    }
    return sr_cat_finish(cat, stmt, err, "read the parts' descriptors");
}

/* Computes the missing descriptors; *computed counts them. */
static sr_status describe_missing(sr_catalog *cat, entry_vec *ev, size_t *computed, sr_err *err)
{
    *computed = 0;
    for (size_t i = 0; i < ev->count; i++) {
        entry *e = &ev->v[i];
        if (e->have)
            continue;
        sr_mesh m;
        sr_status st = sr_catalog_mesh_load(cat, e->mesh_id, &m, err);
        if (st != SR_OK)
            return st;
        char what[96];
        snprintf(what, sizeof what, "the mesh of part '%s'", e->number);
        st = sr_shape_descriptor_compute(&m, what, &e->desc, err);
        sr_mesh_release(&m);
        if (st != SR_OK)
            return st;
        e->fresh = true;
        (*computed)++;
    }
    return SR_OK;
}

/* Stores the descriptors computed here, in one transaction, when the catalogue can
 * be written; *stored counts them (0 when read-only). */
static sr_status store_fresh(sr_catalog *cat, const entry_vec *ev, size_t computed, size_t *stored,
                             sr_err *err)
{
    *stored = 0;
    bool readonly = true;
    if (!computed || sr_catalog_check_writable(cat, &readonly, NULL) != SR_OK || readonly)
        return SR_OK;
    sr_status st = sr_cat_begin(cat, err);
    if (st != SR_OK)
        return st;
    for (size_t i = 0; i < ev->count && st == SR_OK; i++)
        if (ev->v[i].fresh)
            st = sr_cat_descriptor_put(cat, ev->v[i].mesh_id, &ev->v[i].desc, err);
    if (st == SR_OK)
        st = sr_cat_commit(cat, err);
    if (st != SR_OK) {
        sr_cat_rollback(cat);
        return st;
    }
    *stored = computed;
    return SR_OK;
}

static int by_dist(const void *a, const void *b)
{
    const entry *x = a, *y = b;
    if (x->dist != y->dist)
        return x->dist < y->dist ? -1 : 1;
    return strcmp(x->number, y->number);
}

static int by_score(const void *a, const void *b)
{
    const sr_identify_candidate *x = a, *y = b;
    if (x->fit.score != y->fit.score)
        return x->fit.score > y->fit.score ? -1 : 1;
    return strcmp(x->number, y->number);
}

/* Registers the scan to the first n entries' meshes into res->cand. */
static sr_status fit_shortlist(sr_catalog *cat, sr_identify_scan *scan, const entry *e, size_t n,
                               sr_identify_result *res, sr_err *err)
{
    sr_mesh *meshes = calloc(n, sizeof *meshes);
    const sr_mesh **ptrs = calloc(n, sizeof *ptrs);
    sr_identify_fit *fits = calloc(n, sizeof *fits);
    res->cand = calloc(n, sizeof *res->cand);
    sr_status st = SR_OK;
    if (!meshes || !ptrs || !fits || !res->cand)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory identifying the scan");
    for (size_t i = 0; i < n && st == SR_OK; i++) {
        st = sr_catalog_mesh_load(cat, e[i].mesh_id, &meshes[i], err);
        ptrs[i] = &meshes[i];
    }
    if (st == SR_OK)
        st = sr_identify_fit_parts(scan, ptrs, n, fits, err);
    for (size_t i = 0; i < n && st == SR_OK; i++) {
        sr_identify_candidate *c = &res->cand[i];
        c->part_id = e[i].part_id;
        c->mesh_id = e[i].mesh_id;
        memcpy(c->number, e[i].number, sizeof c->number);
        memcpy(c->name, e[i].name, sizeof c->name);
        c->descriptor_distance = e[i].dist;
        c->fit = fits[i];
    }
    for (size_t i = 0; meshes && i < n; i++)
        sr_mesh_release(&meshes[i]);
    free(meshes);
    free(ptrs);
    free(fits);
    if (st == SR_OK)
        res->count = n;
    return st;
}

/* Whether candidates a and b are one design: b's intact mesh registered to a's (as
 * a scan is to a part) covers it and lacks nothing of it, within tol. */
static sr_status one_design(sr_catalog *cat, const sr_identify_candidate *a,
                            const sr_identify_candidate *b, double tol, bool *same, sr_err *err)
{
    *same = false;
    sr_mesh ma, mb;
    sr_mesh_init(&ma);
    sr_mesh_init(&mb);
    sr_identify_scan *sc = NULL;
    sr_identify_fit fit;
    const sr_mesh *parts[1] = {&ma};
    sr_status st = sr_catalog_mesh_load(cat, a->mesh_id, &ma, err);
    if (st == SR_OK)
        st = sr_catalog_mesh_load(cat, b->mesh_id, &mb, err);
    if (st == SR_OK)
        st = sr_identify_scan_make(&mb, tol, &sc, err);
    if (st == SR_OK)
        st = sr_identify_fit_parts(sc, parts, 1, &fit, err);
    if (st == SR_OK)
        *same = fit.coverage >= SR_IDENTIFY_SAME_COVERAGE &&
                fit.lacking <= SR_IDENTIFY_SAME_LACKING &&
                fit.rms_mm <= SR_IDENTIFY_MAX_RMS_TOL * fit.tol_mm;
    sr_identify_scan_free(sc);
    sr_mesh_release(&ma);
    sr_mesh_release(&mb);
    return st;
}

/* The verdict on the sorted candidates, and how many of the first are one design. */
static sr_status judge(sr_catalog *cat, sr_identify_result *res, sr_err *err)
{
    res->same_design = 1;
    if (!sr_identify_fit_matches(&res->cand[0].fit)) {
        res->verdict = SR_IDENTIFY_NO_MATCH;
        return SR_OK;
    }
    const sr_identify_candidate *first = &res->cand[0];
    size_t k = 1;
    while (k < res->count && res->cand[k].fit.score >= first->fit.score - SR_IDENTIFY_MARGIN) {
        bool same;
        sr_status st = one_design(cat, first, &res->cand[k], res->tol_mm, &same, err);
        if (st != SR_OK)
            return st;
        if (!same)
            break;
        /* kept next to the first, in the order of the scores */
        k++;
    }
    res->same_design = k;
    res->verdict = k < res->count && res->cand[k].fit.score >= first->fit.score - SR_IDENTIFY_MARGIN
                       ? SR_IDENTIFY_TOO_CLOSE
                       : SR_IDENTIFY_MATCH;
    return SR_OK;
}

void sr_identify_result_release(sr_identify_result *res)
{
    if (!res)
        return;
    free(res->cand);
    memset(res, 0, sizeof *res);
}

sr_status sr_catalog_identify(sr_catalog *cat, const sr_mesh *scan, const sr_identify_opts *opts,
                              sr_identify_result *out, sr_err *err)
{
    size_t top = opts && opts->top ? opts->top : SR_IDENTIFY_TOP_DEFAULT;
    double tol = opts ? opts->tol_mm : 0;
    if (top > SR_IDENTIFY_TOP_MAX)
        return sr_err_set(err, SR_E_RANGE, "top: %zu candidates, at most %d", top,
                          SR_IDENTIFY_TOP_MAX);
    if (!(tol >= 0) || !isfinite(tol))
        return sr_err_set(err, SR_E_RANGE, "tol: must be a distance >= 0 mm");
    sr_identify_scan *sc = NULL;
    sr_status st = sr_identify_scan_make(scan, tol, &sc, err);
    if (st != SR_OK)
        return st;
    entry_vec ev = {0};
    sr_identify_result res;
    memset(&res, 0, sizeof res);
    st = read_entries(cat, &ev, err);
    if (st == SR_OK && ev.count == 0)
        st = sr_err_set(err, SR_E_NOTFOUND,
                        "no part with an intact mesh in '%s' to identify against",
                        sr_catalog_path(cat));
    if (st == SR_OK)
        st = describe_missing(cat, &ev, &res.described, err);
    if (st == SR_OK)
        st = store_fresh(cat, &ev, res.described, &res.stored, err);
    if (st == SR_OK) {
        const sr_shape_descriptor *d = sr_identify_scan_descriptor(sc);
        for (size_t i = 0; i < ev.count; i++)
            ev.v[i].dist = sr_shape_descriptor_distance(d, &ev.v[i].desc);
        qsort(ev.v, ev.count, sizeof *ev.v, by_dist);
        /* the shortlist: at least SHORTLIST (or top), and every part about as close */
        size_t n = top > SR_IDENTIFY_SHORTLIST ? top : SR_IDENTIFY_SHORTLIST;
        while (n < SR_IDENTIFY_NEAR_MAX && n < ev.count &&
               ev.v[n].dist <= ev.v[0].dist + SR_IDENTIFY_NEAR_OCTAVES)
            n++;
        if (n > ev.count)
            n = ev.count;
        st = fit_shortlist(cat, sc, ev.v, n, &res, err);
    }
    if (st == SR_OK) {
        qsort(res.cand, res.count, sizeof *res.cand, by_score);
        res.parts = ev.count;
        res.registered = res.count;
        res.tol_mm = sr_identify_scan_tol(sc);
        st = judge(cat, &res, err);
    }
    if (st == SR_OK) {
        /* top, and every number of the matched design (cand[] holds all registered,
         * so the next design's score stays readable) */
        size_t keep = top > res.same_design ? top : res.same_design;
        if (res.count > keep)
            res.count = keep;
    }
    free(ev.v);
    sr_identify_scan_free(sc);
    if (st != SR_OK) {
        sr_identify_result_release(&res);
        return st;
    }
    *out = res;
    return SR_OK;
}
