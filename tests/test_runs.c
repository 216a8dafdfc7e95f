/*
 * test_runs.c: the record of reconstruction runs (written by src/catalog/catalog_runs.c,
 * read back by catalog_run_read.c) and the building of a run from a reconstruction
 * (src/run/run_build.c): a run with layers, two sections, advice and meshes read back
 * field for field (NaN outline points included); an open scan's gaps and strays read back
 * apart from the sections; what is read without the layer/mesh
 * flags; listing order, filters and summaries; the count; every refused field leaving no
 * row in any table; a failure inside the transaction (an unknown rule) rolling back the
 * rows already written; not-found errors; release of a zeroed run; and a real
 * reconstruction of the demo shaft recorded and read back. Raw sqlite3 calls count rows
 * and add a repair rule (no API for rules here).
 */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include <sqlite3.h>

#include "catalog/catalog.h"
#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "reconstruct.h"
#include "mesh/scan_describe.h"
#include "mesh/shapes.h"
#include "run/run_build.h"
#include "run/run_scan.h"
#include "support/assert_near.h"
#include "base/version.h"

/* ---- fixture: a catalogue with two parts and three instances ---- */

typedef struct fixture {
    char dir[64];
    char db[128];
    sr_catalog *cat;
    int64_t part[2];        /* "P-1", "P-2" */
    int64_t inst[3];        /* two of P-1, one of P-2 */
    int64_t rule;           /* a repair rule row */
} fixture;

static void raw_exec(const char *path, const char *sql)
{
    sqlite3 *db = NULL;
    assert_int_equal(sqlite3_open_v2(path, &db, SQLITE_OPEN_READWRITE, NULL), SQLITE_OK);
    char *msg = NULL;
    if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK)
        fail_msg("%s: %s", sql, msg);
    assert_int_equal(sqlite3_close(db), SQLITE_OK);
}

static int64_t raw_int(const char *path, const char *sql)
{
    sqlite3 *db = NULL;
    assert_int_equal(sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL), SQLITE_OK);
    sqlite3_stmt *stmt = NULL;
    if (sqlite3_prepare_v2(db, sql, -1, &stmt, NULL) != SQLITE_OK)
        fail_msg("%s: %s", sql, sqlite3_errmsg(db));
    assert_int_equal(sqlite3_step(stmt), SQLITE_ROW);
    int64_t v = sqlite3_column_int64(stmt, 0);
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return v;
}

static void box_mesh(double x0, double size, sr_mesh *out)
{
    const double lo[3] = {x0, 0, 0}, hi[3] = {x0 + size, size, size};
    assert_int_equal(sr_shape_box(lo, hi, out, NULL), SR_OK);
}

static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    assert_non_null(fx);
    strcpy(fx->dir, "/tmp/symrec-test-XXXXXX");
    assert_non_null(mkdtemp(fx->dir));
    snprintf(fx->db, sizeof fx->db, "%s/cat.db", fx->dir);
    sr_err err = {{0}};
    if (sr_catalog_open(fx->db, SR_CATALOG_CREATE, &fx->cat, &err) != SR_OK)
        fail_msg("open: %s", err.msg);
    sr_mesh m;
    box_mesh(0, 10, &m);
    /* S355 is not seeded: a part may name only a material the catalogue holds */
    sr_material_new s355 = {.name = "S355", .density_g_cm3 = 7.85, .family = "steel"};
    assert_int_equal(sr_catalog_material_add(fx->cat, &s355, NULL, &err), SR_OK);
    const char *numbers[2] = {"P-1", "P-2"};
    for (int i = 0; i < 2; i++) {
        sr_part_new p = {.number = numbers[i], .name = "block", .material = "S355",
                         .mesh = &m, .symmetry = {SR_SYM_AXIAL, 0, 0}};
        assert_int_equal(sr_catalog_part_add(fx->cat, &p, &fx->part[i], &err), SR_OK);
    }
    const char *owner[3] = {"P-1", "P-1", "P-2"};
    const char *serial[3] = {"S-A", "S-B", "S-C"};
    for (int i = 0; i < 3; i++) {
        sr_instance_new in = {.part = owner[i], .mesh = &m, .serial = serial[i]};
        assert_int_equal(sr_catalog_instance_add(fx->cat, &in, &fx->inst[i], &err), SR_OK);
    }
    sr_mesh_release(&m);
    raw_exec(fx->db, "INSERT INTO repair_rules (name, process, reason, source)"
                     " VALUES ('spray-small-chip', 'spray_forming', 'small chip', 'test')");
    fx->rule = raw_int(fx->db, "SELECT id FROM repair_rules WHERE name = 'spray-small-chip'");
    *state = fx;
    return 0;
}

static int teardown(void **state)
{
    fixture *fx = *state;
    sr_catalog_close(fx->cat);
    DIR *d = opendir(fx->dir);
    if (d) {
        struct dirent *e;
        while ((e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            char p[512];
            snprintf(p, sizeof p, "%s/%s", fx->dir, e->d_name);
            unlink(p);
        }
        closedir(d);
    }
    rmdir(fx->dir);
    free(fx);
    return 0;
}

/* ---- a sample run: 3 layers x 4 sectors, 2 sections, 3 advice, meshes ---- */

typedef struct sample {
    sr_run run;
    double z[3];
    double dam[3 * 4 * 2], res[3 * 4 * 2];
    sr_run_section sec[2];
    sr_run_advice adv[3];
} sample;

static void sample_init(sample *s, const fixture *fx)
{
    memset(s, 0, sizeof *s);
    sr_run *r = &s->run;
    r->instance_id = fx->inst[0];
    r->symmetry = (sr_symmetry){SR_SYM_AXIAL, 6, 0};
    r->params = (sr_params){"my set", 3, 4, 0.9, 0.8, 0.07, 0.2, 1.5, "not stored"};
    snprintf(r->method, sizeof r->method, "paper");
    r->has_alignment = 1;
    for (int i = 0; i < 12; i++)
        r->alignment[i] = 0.1 * (i + 1) - 1.0 / 3.0;
    r->fit_quality = 0.875;
    r->ok = 1;
    snprintf(r->software_version, sizeof r->software_version, "9.8.7");
    snprintf(r->started_at, sizeof r->started_at, "2024-03-01T10:00:00Z");
    snprintf(r->finished_at, sizeof r->finished_at, "2024-03-01T10:00:02Z");
    r->timings_json = "{\"align\":0.5,\"total\":1.25}";
    r->layer_count = 3;
    r->sectors = 4;
    for (int l = 0; l < 3; l++)
        s->z[l] = 1.5 + 2.0 * l;
    for (int i = 0; i < 24; i++) {
        s->dam[i] = 0.25 * i - 2;
        s->res[i] = -0.125 * i + 1.0 / 7.0;
    }
    s->dam[5] = s->dam[6] = NAN;     /* layer 0, sector 2 has no point */
    s->res[23] = -0.0;
    r->layer_z = s->z;
    r->damaged_xy = s->dam;
    r->restored_xy = s->res;

    sr_run_section *a = &s->sec[0], *b = &s->sec[1];
    a->index = 0;
    a->layer_first = 0;
    a->layer_last = 2;
    a->z_min_mm = 0.5;
    a->z_max_mm = 6.5;
    a->has_angles = 1;
    a->angle_from_deg = 270;
    a->angle_to_deg = 450;
    a->volume_mm3 = 1000;
    a->area_mm2 = 600;
    a->depth_max_mm = 3.5;
    a->depth_mean_mm = 1.25;
    snprintf(a->damage_class, sizeof a->damage_class, "chip");
    a->features_json = "{\"arc_deg\":180,\"edge\":true}";
    box_mesh(0, 10, &a->patch);
    b->index = 1;
    b->layer_first = 1;
    b->layer_last = 1;
    b->z_min_mm = 2.5;
    b->z_max_mm = 4.5;
    b->side = -1;
    b->volume_mm3 = 2.5;
    b->area_mm2 = 9;
    b->depth_max_mm = 0.5;
    b->depth_mean_mm = 0.25;
    snprintf(b->damage_class, sizeof b->damage_class, "gouge");
    r->sections = s->sec;
    r->section_count = 2;

    s->adv[0] = (sr_run_advice){0, fx->rule, "", "spray_forming", "chip of 1000 mm3", NULL};
    s->adv[0].details_json = "{\"layers\":12}";
    s->adv[1] = (sr_run_advice){1, 0, "", "weld_buildup", "shallow gouge", NULL};
    s->adv[2] = (sr_run_advice){-1, 0, "", "inspect", "whole part: check runout", NULL};
    r->advice = s->adv;
    r->advice_count = 3;
    box_mesh(20, 5, &r->restored);
}

static void sample_release(sample *s)
{
    sr_mesh_release(&s->sec[0].patch);
    sr_mesh_release(&s->sec[1].patch);
    sr_mesh_release(&s->run.restored);
}

/* Rows in every table a run writes. */
typedef struct counts {
    int64_t runs, layers, sections, advice, meshes;
} counts;

static counts count_all(const fixture *fx)
{
    counts c;
    c.runs = raw_int(fx->db, "SELECT count(*) FROM runs");
    c.layers = raw_int(fx->db, "SELECT count(*) FROM run_layers");
    c.sections = raw_int(fx->db, "SELECT count(*) FROM sections");
    c.advice = raw_int(fx->db, "SELECT count(*) FROM advice");
    c.meshes = raw_int(fx->db, "SELECT count(*) FROM meshes");
    return c;
}

static void assert_counts_equal(counts a, counts b)
{
    assert_int_equal(a.runs, b.runs);
    assert_int_equal(a.layers, b.layers);
    assert_int_equal(a.sections, b.sections);
    assert_int_equal(a.advice, b.advice);
    assert_int_equal(a.meshes, b.meshes);
}

static void assert_mesh_equal(const sr_mesh *a, const sr_mesh *b)
{
    assert_int_equal(a->vertex_count, b->vertex_count);
    assert_int_equal(a->tri_count, b->tri_count);
    assert_memory_equal(a->xyz, b->xyz, a->vertex_count * 3 * sizeof(double));
    assert_memory_equal(a->tri, b->tri, a->tri_count * 3 * sizeof(uint32_t));
}

/* Bitwise: NaN and -0 must come back as they went in. */
static void assert_doubles_same(const double *a, const double *b, size_t n)
{
    assert_memory_equal(a, b, n * sizeof(double));
}

static int64_t add_ok(fixture *fx, const sr_run *run)
{
    sr_err err = {{0}};
    int64_t id = 0;
    if (sr_catalog_run_add(fx->cat, run, &id, &err) != SR_OK)
        fail_msg("run add: %s", err.msg);
    assert_true(id > 0);
    return id;
}

/* ---- round trip ---- */

static void run_round_trip_reads_back_every_field(void **state)
{
    fixture *fx = *state;
    sample s;
    sample_init(&s, fx);
    s.run.unbuilt_sections = 2; /* sql/013 */
    s.run.unbuilt_mm3 = 12.5;
    int64_t id = add_ok(fx, &s.run);
    sr_run r;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_get(fx->cat, id, SR_RUN_WITH_LAYERS | SR_RUN_WITH_MESHES, &r,
                                        &err),
                     SR_OK);
    const sr_run *w = &s.run;
    assert_int_equal(r.id, id);
    assert_int_equal(r.unbuilt_sections, 2);
    assert_true(r.unbuilt_mm3 == 12.5);
    assert_int_equal(r.instance_id, w->instance_id);
    assert_string_equal(r.part_number, "P-1");
    assert_int_equal(r.symmetry.kind, SR_SYM_AXIAL);
    assert_int_equal(r.symmetry.order, 6);
    assert_string_equal(r.params.name, "my set");
    assert_int_equal(r.params.layers, 3);
    assert_int_equal(r.params.sectors, 4);
    assert_true(r.params.gamma_axis == 0.9 && r.params.gamma_plane == 0.8);
    assert_true(r.params.delta_d == 0.07 && r.params.min_depth_mm == 0.2);
    assert_true(r.params.min_volume_mm3 == 1.5);
    assert_string_equal(r.method, "paper");
    assert_int_equal(r.has_alignment, 1);
    assert_doubles_same(r.alignment, w->alignment, 12);
    assert_int_equal(r.alignment_given, 0);
    assert_true(r.fit_quality == 0.875);
    assert_int_equal(r.ok, 1);
    assert_string_equal(r.error, "");
    assert_string_equal(r.software_version, "9.8.7");
    assert_string_equal(r.started_at, w->started_at);
    assert_string_equal(r.finished_at, w->finished_at);
    assert_string_equal(r.timings_json, w->timings_json);
    assert_int_equal(r.layer_count, 3);
    assert_int_equal(r.sectors, 4);
    assert_doubles_same(r.layer_z, s.z, 3);
    assert_doubles_same(r.damaged_xy, s.dam, 24);
    assert_doubles_same(r.restored_xy, s.res, 24);
    assert_int_equal(r.section_count, 2);
    for (size_t i = 0; i < 2; i++) {
        const sr_run_section *a = &r.sections[i], *b = &s.sec[i];
        assert_true(a->id > 0);
        assert_int_equal(a->index, b->index);
        assert_int_equal(a->layer_first, b->layer_first);
        assert_int_equal(a->layer_last, b->layer_last);
        assert_true(a->z_min_mm == b->z_min_mm && a->z_max_mm == b->z_max_mm);
        assert_int_equal(a->has_angles, b->has_angles);
        if (b->has_angles)
            assert_true(a->angle_from_deg == b->angle_from_deg &&
                        a->angle_to_deg == b->angle_to_deg);
        assert_int_equal(a->side, b->side);
        assert_true(a->volume_mm3 == b->volume_mm3 && a->area_mm2 == b->area_mm2);
        assert_true(a->depth_max_mm == b->depth_max_mm && a->depth_mean_mm == b->depth_mean_mm);
        assert_string_equal(a->damage_class, b->damage_class);
        if (b->features_json)
            assert_string_equal(a->features_json, b->features_json);
        else
            assert_null(a->features_json);
        assert_mesh_equal(&a->patch, &b->patch);
    }
    assert_int_equal(r.advice_count, 3);
    for (size_t i = 0; i < 3; i++) {
        const sr_run_advice *a = &r.advice[i], *b = &s.adv[i];
        assert_int_equal(a->section_index, b->section_index);
        assert_int_equal(a->rule_id, b->rule_id);
        assert_string_equal(a->rule_name, i == 0 ? "spray-small-chip" : "");
        assert_string_equal(a->process, b->process);
        assert_string_equal(a->reason, b->reason);
        assert_string_equal(a->details_json, b->details_json ? b->details_json : "{}");
    }
    assert_mesh_equal(&r.restored, &w->restored);
    /* the advice rows point at the right section rows */
    char sql[256];
    snprintf(sql, sizeof sql,
             "SELECT s.section_index FROM advice a JOIN sections s ON s.id = a.section_id"
             " WHERE a.run_id = %lld AND a.process = 'weld_buildup'",
             (long long)id);
    assert_int_equal(raw_int(fx->db, sql), 1);
    /* the alignment blob is 96 bytes, first double little-endian */
    snprintf(sql, sizeof sql, "SELECT length(alignment) FROM runs WHERE id = %lld", (long long)id);
    assert_int_equal(raw_int(fx->db, sql), 96);
    double first = w->alignment[0];
    uint64_t bits;
    memcpy(&bits, &first, 8);
    char hex[17];
    for (int i = 0; i < 8; i++)
        snprintf(hex + 2 * i, 3, "%02X", (unsigned)((bits >> (8 * i)) & 0xff));
    snprintf(sql, sizeof sql, "SELECT hex(substr(alignment, 1, 8)) = '%s' FROM runs WHERE id = %lld",
             hex, (long long)id);
    assert_int_equal(raw_int(fx->db, sql), 1);
    sr_run_release(&r);
    sample_release(&s);
}

/* An open scan's gaps recorded apart from the sections: a 10 x 20 x 30 box without its
 * top (one gap: 4 edges, 60 mm of rim, 200 mm², centred at (5, 10, 30), closed in its
 * plane) and a stray triangle 20 mm above it, recorded with the sample's two sections
 * and 7 triangles sealed (sql/012) and 2 gap sags of 3.25 mm³ (sql/015) and read back;
 * the sample without a scan record reads back none. */
static void run_scan_gaps_round_trip_apart_from_the_sections(void **state)
{
    fixture *fx = *state;
    sample s;
    sample_init(&s, fx);
    sr_mesh box;
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    size_t kept = 0;
    for (size_t t = 0; t < box.tri_count; t++) {
        bool top = true;
        for (int k = 0; k < 3; k++)
            top = top && box.xyz[3 * box.tri[3 * t + k] + 2] == 30;
        if (!top) {
            memmove(box.tri + 3 * kept, box.tri + 3 * t, 3 * sizeof *box.tri);
            kept++;
        }
    }
    box.tri_count = kept;
    sr_mesh stray;
    assert_int_equal(sr_mesh_alloc(&stray, 3, 1), SR_OK);
    const double sv[9] = {0, 0, 50, 0.5, 0, 50, 0, 0.5, 50};
    memcpy(stray.xyz, sv, sizeof sv);
    stray.tri[0] = 0, stray.tri[1] = 1, stray.tri[2] = 2;
    assert_int_equal(sr_mesh_append(&box, &stray), SR_OK);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&box, NULL, &d, NULL), SR_OK);
    sr_scan_closing how[1];
    assert_int_equal(d.loop_count, 1);
    assert_int_equal(sr_scan_close_openings_how(&box, &d, 0, NULL, how, NULL), SR_OK);
    d.sealed_triangles = 7; /* as if the closing had been sealed round a defect */
    d.uncurled_vertices = 3; /* and a rim untwisted */
    assert_int_equal(sr_run_scan_from_desc(&d, how, &s.run.scan, NULL), SR_OK);
    assert_int_equal(s.run.scan->sags, 0);
    s.run.scan->sags = 2; /* as if two lenses were restored behind gap fills (sql/015) */
    s.run.scan->sag_mm3 = 3.25;
    int64_t id = add_ok(fx, &s.run);
    sr_run r;
    assert_int_equal(sr_catalog_run_get(fx->cat, id, 0, &r, NULL), SR_OK);
    assert_int_equal(r.section_count, 2);
    assert_non_null(r.scan);
    assert_int_equal(r.scan->gap_count, 1);
    assert_int_equal(r.scan->gaps[0].edges, 4);
    assert_true(r.scan->gaps[0].length_mm == 60 && r.scan->gaps[0].area_mm2 == 200);
    assert_true(r.scan->gaps[0].centre[0] == 5 && r.scan->gaps[0].centre[1] == 10 &&
                r.scan->gaps[0].centre[2] == 30);
    assert_string_equal(r.scan->gaps[0].closed_by, "plane");
    assert_int_equal(r.scan->triangles, 11);
    assert_int_equal(r.scan->boundary_edges, 4);
    assert_int_equal(r.scan->components, 2);
    assert_int_equal(r.scan->strays, 1);
    assert_int_equal(r.scan->stray_triangles, 1);
    assert_true(r.scan->open_area_mm2 == 200);
    assert_int_equal(r.scan->sealed_triangles, 7);
    assert_int_equal(r.scan->uncurled_vertices, 3);
    assert_int_equal(r.scan->sags, 2);
    assert_true(r.scan->sag_mm3 == 3.25);
    sr_run_release(&r);
    sr_run_scan_free(s.run.scan);
    s.run.scan = NULL;
    id = add_ok(fx, &s.run);
    assert_int_equal(sr_catalog_run_get(fx->cat, id, 0, &r, NULL), SR_OK);
    assert_null(r.scan);
    sr_run_release(&r);
    sr_scan_desc_release(&d);
    sr_mesh_release(&stray);
    sr_mesh_release(&box);
    sample_release(&s);
}

static void run_get_without_flags_reads_no_layers_or_meshes(void **state)
{
    fixture *fx = *state;
    sample s;
    sample_init(&s, fx);
    int64_t id = add_ok(fx, &s.run);
    sr_run r;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_get(fx->cat, id, 0, &r, &err), SR_OK);
    assert_int_equal(r.layer_count, 0);
    assert_null(r.layer_z);
    assert_null(r.damaged_xy);
    assert_int_equal(r.restored.tri_count, 0);
    assert_int_equal(r.section_count, 2);
    assert_int_equal(r.sections[0].patch.tri_count, 0);
    assert_true(r.sections[0].volume_mm3 == 1000);
    assert_int_equal(r.advice_count, 3);
    sr_run_release(&r);
    sample_release(&s);
}

static void run_failed_record_round_trips_with_nulls(void **state)
{
    fixture *fx = *state;
    sr_run w;
    memset(&w, 0, sizeof w);
    w.instance_id = fx->inst[2];
    w.symmetry = (sr_symmetry){SR_SYM_GLIDE, 0, 12.5};
    w.params = (sr_params){"default", 320, 240, 0.95, 0.95, 0.05, 0.1, 1.0, ""};
    snprintf(w.method, sizeof w.method, "robust");
    w.fit_quality = -1;
    w.ok = 0;
    snprintf(w.error, sizeof w.error, "cannot align 'scan': no triangle with an area");
    int64_t id = add_ok(fx, &w);
    sr_run r;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_get(fx->cat, id, SR_RUN_WITH_LAYERS | SR_RUN_WITH_MESHES, &r,
                                        &err),
                     SR_OK);
    assert_int_equal(r.ok, 0);
    assert_string_equal(r.error, w.error);
    assert_int_equal(r.has_alignment, 0);
    assert_int_equal(r.unbuilt_sections, 0);
    assert_true(r.unbuilt_mm3 == 0);
    assert_true(r.fit_quality < 0);
    assert_int_equal(r.symmetry.kind, SR_SYM_GLIDE);
    assert_true(r.symmetry.shift_mm == 12.5);
    assert_string_equal(r.software_version, SR_VERSION);   /* "" stored as this build's */
    assert_int_equal(strlen(r.started_at), 20);             /* "" stored as now */
    assert_string_equal(r.finished_at, "");
    assert_null(r.timings_json);
    assert_int_equal(r.layer_count, 0);
    assert_int_equal(r.section_count, 0);
    assert_null(r.sections);
    assert_int_equal(r.advice_count, 0);
    assert_int_equal(r.restored.tri_count, 0);
    sr_run_release(&r);
}

/* ---- refused input: nothing written ---- */

/* One mutation of the sample and the message it must give. */
typedef struct bad_case {
    const char *name;
    void (*mutate)(sample *s);
    sr_status status;
    const char *msg;
} bad_case;

static void m_instance0(sample *s) { s->run.instance_id = 0; }
static void m_symnone(sample *s) { s->run.symmetry.kind = SR_SYM_NONE; }
static void m_order(sample *s) { s->run.symmetry.order = 1; }
static void m_layers0(sample *s) { s->run.params.layers = 0; }
static void m_gamma(sample *s) { s->run.params.gamma_axis = 1.5; }
static void m_method(sample *s) { s->run.method[0] = '\0'; }
static void m_align(sample *s) { s->run.alignment[4] = INFINITY; }
static void m_fit(sample *s) { s->run.fit_quality = 1.5; }
static void m_failed(sample *s) { s->run.ok = 0; }
static void m_times(sample *s) { snprintf(s->run.finished_at, 32, "2024-02-01T00:00:00Z"); }
static void m_timings(sample *s) { s->run.timings_json = "{\"align\":"; }
static void m_unbuilt(sample *s)
{
    s->run.unbuilt_sections = 1;
    s->run.unbuilt_mm3 = NAN;
}
static void m_layer_arrays(sample *s) { s->run.damaged_xy = NULL; }
static void m_layer_z(sample *s) { s->z[1] = NAN; }
static void m_sec_layers(sample *s) { s->sec[1].layer_first = 5; }
static void m_sec_z(sample *s) { s->sec[0].z_max_mm = 0; }
static void m_sec_angle(sample *s) { s->sec[0].angle_from_deg = 360; }
static void m_sec_arc(sample *s) { s->sec[0].angle_to_deg = 700; }
static void m_sec_side(sample *s) { s->sec[1].side = 2; }
static void m_sec_volume(sample *s) { s->sec[1].volume_mm3 = -1; }
static void m_sec_depth(sample *s) { s->sec[0].depth_mean_mm = NAN; }
static void m_sec_class(sample *s) { s->sec[1].damage_class[0] = '\0'; }
static void m_sec_features(sample *s) { s->sec[0].features_json = "not json"; }
static void m_sec_dup(sample *s) { s->sec[1].index = 0; }
static void m_patch_nan(sample *s) { s->sec[0].patch.xyz[4] = NAN; }
static void m_patch_index(sample *s) { s->sec[0].patch.tri[7] = 999; }
static void m_restored_nan(sample *s) { s->run.restored.xyz[0] = NAN; }
static void m_adv_section(sample *s) { s->adv[1].section_index = 7; }
static void m_adv_process(sample *s) { s->adv[2].process[0] = '\0'; }
static void m_adv_details(sample *s) { s->adv[0].details_json = "[1,"; }

static const bad_case bad_cases[] = {
    {"instance 0", m_instance0, SR_E_RANGE, "bad instance_id 0"},
    {"no symmetry", m_symnone, SR_E_RANGE, "bad symmetry"},
    {"order 1", m_order, SR_E_RANGE, "order"},
    {"0 layers", m_layers0, SR_E_RANGE, "bad params: bad layers 0"},
    {"gamma 1.5", m_gamma, SR_E_RANGE, "bad params: bad gamma_axis 1.5"},
    {"empty method", m_method, SR_E_RANGE, "bad method"},
    {"inf alignment", m_align, SR_E_RANGE, "bad alignment: element 4"},
    {"fit 1.5", m_fit, SR_E_RANGE, "bad fit_quality 1.5"},
    {"failed, no error", m_failed, SR_E_RANGE, "bad error"},
    {"finished first", m_times, SR_E_RANGE, "bad finished_at"},
    {"bad timings", m_timings, SR_E_RANGE, "bad timings_json: not valid JSON"},
    {"unbuilt volume", m_unbuilt, SR_E_RANGE, "bad unbuilt_mm3"},
    {"layer array", m_layer_arrays, SR_E_RANGE, "bad layers"},
    {"layer z NaN", m_layer_z, SR_E_RANGE, "bad layer_z of layer 1"},
    {"section layers", m_sec_layers, SR_E_RANGE, "bad section 1: layer_last 1 < layer_first 5"},
    {"section z", m_sec_z, SR_E_RANGE, "bad section 0: z range"},
    {"section angle", m_sec_angle, SR_E_RANGE, "bad section 0: angles 360"},
    {"section arc", m_sec_arc, SR_E_RANGE, "bad section 0: angles 270..700"},
    {"section side", m_sec_side, SR_E_RANGE, "bad section 1: side 2"},
    {"section volume", m_sec_volume, SR_E_RANGE, "bad section 1: volume_mm3 -1"},
    {"section depth", m_sec_depth, SR_E_RANGE, "bad section 0: depth_mean_mm"},
    {"section class", m_sec_class, SR_E_RANGE, "bad section 1: damage_class"},
    {"section features", m_sec_features, SR_E_RANGE, "bad features_json of section 0"},
    {"duplicate index", m_sec_dup, SR_E_RANGE, "index 0 is used by section 0 too"},
    {"patch NaN", m_patch_nan, SR_E_INVALID, "patch of section 0"},
    {"patch index", m_patch_index, SR_E_INVALID, "patch of section 0"},
    {"restored NaN", m_restored_nan, SR_E_INVALID, "restored mesh"},
    {"advice section", m_adv_section, SR_E_RANGE, "bad advice 1: no section with index 7"},
    {"advice process", m_adv_process, SR_E_RANGE, "bad advice 2: process"},
    {"advice details", m_adv_details, SR_E_RANGE, "bad details_json of advice 0"},
};

static void run_add_refuses_each_bad_field_and_writes_nothing(void **state)
{
    fixture *fx = *state;
    counts before = count_all(fx);
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
        const bad_case *c = &bad_cases[i];
        sample s;
        sample_init(&s, fx);
        c->mutate(&s);
        sr_err err = {{0}};
        int64_t id = -7;
        sr_status st = sr_catalog_run_add(fx->cat, &s.run, &id, &err);
        if (st != c->status || !strstr(err.msg, c->msg))
            fail_msg("case '%s': status %d, message '%s'; expected %d with '%s'", c->name, st,
                     err.msg, c->status, c->msg);
        assert_int_equal(id, -7);
        sample_release(&s);
        assert_counts_equal(count_all(fx), before);
    }
}

static void run_add_unknown_instance_is_not_found_and_writes_nothing(void **state)
{
    fixture *fx = *state;
    counts before = count_all(fx);
    sample s;
    sample_init(&s, fx);
    s.run.instance_id = 99;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_add(fx->cat, &s.run, NULL, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "no instance 99 in the catalogue");
    assert_counts_equal(count_all(fx), before);
    sample_release(&s);
}

/* The rule is checked after the run row, its layers, both sections and both patch
 * meshes and the first advice are written: the rollback must take all of them back. */
static void run_add_rolls_back_every_row_when_a_late_step_fails(void **state)
{
    fixture *fx = *state;
    sample ok;
    sample_init(&ok, fx);
    add_ok(fx, &ok.run);        /* a run already there stays */
    sample_release(&ok);
    counts before = count_all(fx);
    sample s;
    sample_init(&s, fx);
    s.adv[2].rule_id = 4242;    /* the last advice names a rule that does not exist */
    sr_err err = {{0}};
    int64_t id = -7;
    assert_int_equal(sr_catalog_run_add(fx->cat, &s.run, &id, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "no repair rule 4242 in the catalogue");
    assert_int_equal(id, -7);
    assert_counts_equal(count_all(fx), before);
    sample_release(&s);
    /* and the handle still writes */
    sample_init(&s, fx);
    add_ok(fx, &s.run);
    sample_release(&s);
}

static void run_add_on_a_read_only_catalogue_fails_cleanly(void **state)
{
    fixture *fx = *state;
    sr_catalog *ro = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, SR_CATALOG_READONLY, &ro, &err), SR_OK);
    counts before = count_all(fx);
    sample s;
    sample_init(&s, fx);
    assert_int_equal(sr_catalog_run_add(ro, &s.run, NULL, &err), SR_E_DB);
    assert_msg_has(err, "read-only");
    assert_counts_equal(count_all(fx), before);
    sample_release(&s);
    sr_catalog_close(ro);
}

/* ---- listing, count ---- */

typedef struct collected {
    sr_run_summary v[16];
    size_t count;
    size_t stop_after;      /* 0 = never stop */
} collected;

static int collect(const sr_run_summary *s, void *user)
{
    collected *c = user;
    assert_true(c->count < 16);
    c->v[c->count++] = *s;
    return c->stop_after && c->count >= c->stop_after;
}

/* Adds a run of instance `inst` started at `when`; with_sections adds the sample's
 * sections and advice. */
static int64_t add_at(fixture *fx, int64_t inst, const char *when, bool with_sections)
{
    sample s;
    sample_init(&s, fx);
    s.run.instance_id = inst;
    snprintf(s.run.started_at, sizeof s.run.started_at, "%s", when);
    s.run.finished_at[0] = '\0';
    if (!with_sections) {
        s.run.section_count = 0;
        s.run.advice_count = 0;
    }
    int64_t id = add_ok(fx, &s.run);
    sample_release(&s);
    return id;
}

static void run_list_is_newest_first_with_summaries(void **state)
{
    fixture *fx = *state;
    int64_t a = add_at(fx, fx->inst[0], "2024-01-02T00:00:00Z", true);
    int64_t b = add_at(fx, fx->inst[1], "2024-03-01T00:00:00Z", false);
    int64_t c = add_at(fx, fx->inst[2], "2024-02-01T00:00:00Z", false);
    int64_t d = add_at(fx, fx->inst[0], "2024-03-01T00:00:00Z", false); /* same time as b */
    collected got = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_list(fx->cat, NULL, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 4);
    assert_int_equal(got.v[0].id, d);   /* equal times: the later id first */
    assert_int_equal(got.v[1].id, b);
    assert_int_equal(got.v[2].id, c);
    assert_int_equal(got.v[3].id, a);
    const sr_run_summary *s = &got.v[3];
    assert_int_equal(s->instance_id, fx->inst[0]);
    assert_string_equal(s->part_number, "P-1");
    assert_string_equal(s->serial, "S-A");
    assert_string_equal(s->material, "S355");
    assert_int_equal(s->symmetry.kind, SR_SYM_AXIAL);
    assert_int_equal(s->symmetry.order, 6);
    assert_string_equal(s->method, "paper");
    assert_int_equal(s->ok, 1);
    assert_string_equal(s->started_at, "2024-01-02T00:00:00Z");
    assert_int_equal(s->section_count, 2);
    assert_near(s->missing_volume_mm3, 1002.5, 1e-9);
    assert_string_equal(s->process, "spray_forming");   /* advice of section 0 */
    assert_int_equal(got.v[0].section_count, 0);
    assert_near(got.v[0].missing_volume_mm3, 0, 0);
    assert_string_equal(got.v[0].process, "");
}

static void run_list_counts_the_sections_not_built(void **state)
{
    fixture *fx = *state;
    sample s;
    sample_init(&s, fx);
    s.run.unbuilt_sections = 3; /* sql/013: found missing, no closed patch */
    s.run.unbuilt_mm3 = 40;
    int64_t with = add_ok(fx, &s.run);
    sample_release(&s);
    int64_t without = add_at(fx, fx->inst[1], "2023-01-01T00:00:00Z", false);
    collected got = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_list(fx->cat, NULL, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 2);
    for (size_t i = 0; i < got.count; i++) {
        assert_true(got.v[i].id == with || got.v[i].id == without);
        assert_int_equal(got.v[i].unbuilt_sections, got.v[i].id == with ? 3 : 0);
    }
}

static void run_list_filters_by_instance_and_part(void **state)
{
    fixture *fx = *state;
    int64_t a = add_at(fx, fx->inst[0], "2024-01-01T00:00:00Z", false);
    int64_t b = add_at(fx, fx->inst[1], "2024-01-02T00:00:00Z", false);
    int64_t c = add_at(fx, fx->inst[2], "2024-01-03T00:00:00Z", false);
    sr_err err = {{0}};
    collected got = {0};
    sr_run_filter f = {fx->inst[1], NULL};
    assert_int_equal(sr_catalog_run_list(fx->cat, &f, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 1);
    assert_int_equal(got.v[0].id, b);

    memset(&got, 0, sizeof got);
    f = (sr_run_filter){0, "P-1"};
    assert_int_equal(sr_catalog_run_list(fx->cat, &f, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 2);
    assert_int_equal(got.v[0].id, b);
    assert_int_equal(got.v[1].id, a);

    char key[32];   /* a part id works where a number does */
    snprintf(key, sizeof key, "%lld", (long long)fx->part[1]);
    memset(&got, 0, sizeof got);
    f = (sr_run_filter){0, key};
    assert_int_equal(sr_catalog_run_list(fx->cat, &f, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 1);
    assert_int_equal(got.v[0].id, c);

    memset(&got, 0, sizeof got);    /* both filters: instance 3 is not of P-1 */
    f = (sr_run_filter){fx->inst[2], "P-1"};
    assert_int_equal(sr_catalog_run_list(fx->cat, &f, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 0);

    memset(&got, 0, sizeof got);    /* the callback stops the listing */
    got.stop_after = 2;
    assert_int_equal(sr_catalog_run_list(fx->cat, NULL, collect, &got, &err), SR_OK);
    assert_int_equal(got.count, 2);
}

static void run_list_of_an_unknown_part_is_not_found(void **state)
{
    fixture *fx = *state;
    sr_err err = {{0}};
    collected got = {0};
    sr_run_filter f = {0, "NOPE"};
    assert_int_equal(sr_catalog_run_list(fx->cat, &f, collect, &got, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "no part 'NOPE' in the catalogue");
    assert_int_equal(got.count, 0);
}

static void run_count_counts_runs(void **state)
{
    fixture *fx = *state;
    int64_t n = -1;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_count(fx->cat, &n, &err), SR_OK);
    assert_int_equal(n, 0);
    add_at(fx, fx->inst[0], "2024-01-01T00:00:00Z", true);
    add_at(fx, fx->inst[2], "2024-01-01T00:00:00Z", false);
    assert_int_equal(sr_catalog_run_count(fx->cat, &n, &err), SR_OK);
    assert_int_equal(n, 2);
}

/* ---- not found, release ---- */

static void run_get_of_an_unknown_id_is_not_found(void **state)
{
    fixture *fx = *state;
    sr_run r;
    memset(&r, 0x5a, sizeof r);
    sr_run before = r;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_get(fx->cat, 42, SR_RUN_WITH_MESHES, &r, &err),
                     SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no run 42 in the catalogue");
    assert_memory_equal(&r, &before, sizeof r);     /* out untouched */
    /* and the handle is usable (the read transaction ended) */
    sample s;
    sample_init(&s, fx);
    add_ok(fx, &s.run);
    sample_release(&s);
}

static void run_restored_mesh_loads_or_says_why_not(void **state)
{
    fixture *fx = *state;
    sample s;
    sample_init(&s, fx);
    int64_t with = add_ok(fx, &s.run);
    sr_mesh_release(&s.run.restored);
    int64_t without = add_ok(fx, &s.run);
    box_mesh(20, 5, &s.run.restored);
    sr_mesh m;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_run_restored_mesh(fx->cat, with, &m, &err), SR_OK);
    assert_mesh_equal(&m, &s.run.restored);
    sr_mesh_release(&m);
    assert_int_equal(sr_catalog_run_restored_mesh(fx->cat, without, &m, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "has no restored mesh");
    assert_int_equal(sr_catalog_run_restored_mesh(fx->cat, 777, &m, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "no run 777 in the catalogue");
    sample_release(&s);
}

static void run_release_accepts_null_and_zeroed(void **state)
{
    (void)state;
    sr_run_release(NULL);
    sr_run r;
    memset(&r, 0, sizeof r);
    sr_run_release(&r);
    sr_run_release(&r);     /* twice: release zeroes */
    sr_run zero;
    memset(&zero, 0, sizeof zero);
    assert_memory_equal(&r, &zero, sizeof r);
}

/* ---- sr_run_from_result ---- */

/* A hand-made result: 2 layers x 4 sectors, one damaged cell, one section. */
static void fake_result(sr_recon_result *res)
{
    memset(res, 0, sizeof *res);
    assert_int_equal(sr_layer_grid_alloc(&res->grid, 2, 4, 10.0, 2.0), SR_OK);
    res->analysis.layers = 2;
    res->analysis.sectors = 4;
    res->analysis.restored_r = calloc(8, sizeof(double));
    res->analysis.damaged = calloc(8, 1);
    assert_non_null(res->analysis.restored_r);
    assert_non_null(res->analysis.damaged);
    res->analysis.plane_angle = M_PI / 2;
    for (size_t c = 0; c < 8; c++) {
        double th = sr_sector_angle(c % 4, 4);
        res->grid.r[c] = 5;
        res->grid.pt[3 * c] = 5 * cos(th + 0.1);
        res->grid.pt[3 * c + 1] = 5 * sin(th + 0.1);
        res->grid.pt[3 * c + 2] = sr_layer_z(&res->grid, c / 4);
        res->analysis.restored_r[c] = 5;
    }
    res->grid.r[1] = 0;                 /* layer 0, sector 1: no point */
    res->analysis.restored_r[1] = 0;
    res->grid.r[6] = 3;                 /* layer 1, sector 2: damaged, restored to 5 */
    res->analysis.damaged[6] = 1;
    res->analysis.damaged_cells = 1;
    for (int i = 0; i < 12; i++)
        res->alignment.xform[i] = i % 5 == 0 ? 1 : 0;
    res->alignment.fit_score = 0.75;
    res->sections = calloc(1, sizeof *res->sections);
    assert_non_null(res->sections);
    res->section_count = 1;
    sr_section *s = &res->sections[0];
    s->layer_first = s->layer_last = 1;
    s->z_min = 12;
    s->z_max = 14;
    s->cell_count = 1;
    s->sector_first = 3;                /* wraps: sectors 3 and 0 */
    s->angle_min_deg = 270;             /* the arc the run record keeps */
    s->angle_max_deg = 90;
    s->sector_count = 2;
    s->depth_max_mm = s->depth_mean_mm = 2;
    s->volume_mm3 = 33;
    s->area_mm2 = 44;
    box_mesh(0, 1, &s->patch);
    box_mesh(0, 3, &res->restored);
    res->timings = (sr_recon_timings){.align_s = 0.5,
                                      .slice_s = 0.25,
                                      .analyse_s = 0.125,
                                      .patch_s = 0.0625,
                                      .union_s = 1,
                                      .total_s = 2,
                                      .vote_s = 0.03125};
}

static void run_from_result_lays_out_outlines_sections_and_timings(void **state)
{
    fixture *fx = *state;
    sr_recon_result res;
    fake_result(&res);
    res.method = SR_METHOD_IMAGE; /* its vote found a section it could not build */
    res.image.unbuilt = 3;
    res.image.unbuilt_mm3 = 40;
    sr_params p = {"coarse", 80, 60, 0.9, 0.85, 0.05, 0.1, 1.0, ""};
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_run run;
    sr_err err = {{0}};
    assert_int_equal(sr_run_from_result(&res, fx->inst[1], &sym, &p, "paper", &run, &err), SR_OK);
    assert_int_equal(run.unbuilt_sections, 3);
    assert_true(run.unbuilt_mm3 == 40);
    assert_int_equal(run.instance_id, fx->inst[1]);
    assert_int_equal(run.params.layers, 2);     /* as run: the grid's */
    assert_int_equal(run.params.sectors, 4);
    assert_string_equal(run.params.name, "coarse");
    assert_true(run.params.gamma_plane == 0.85);
    assert_string_equal(run.method, "paper");
    assert_int_equal(run.has_alignment, 1);
    assert_memory_equal(run.alignment, res.alignment.xform, sizeof run.alignment);
    assert_true(run.fit_quality == 0.75);
    assert_int_equal(run.ok, 1);
    assert_string_equal(run.software_version, SR_VERSION);
    assert_true(strcmp(run.started_at, run.finished_at) <= 0);
    assert_string_equal(run.timings_json,
                        "{\"align\":0.5,\"slice\":0.25,\"unfold\":0,\"vote\":0.03125,"
                        "\"clip\":0,\"continue\":0,\"analyse\":0.125,\"patch\":0.0625,"
                        "\"union\":1,\"finish\":0,\"total\":2}");
    assert_int_equal(run.layer_count, 2);
    assert_int_equal(run.sectors, 4);
    assert_near(run.layer_z[0], 11, 1e-12);
    assert_near(run.layer_z[1], 13, 1e-12);
    /* damaged points: the grid's; no point = NaN */
    assert_true(run.damaged_xy[0] == res.grid.pt[0] && run.damaged_xy[1] == res.grid.pt[1]);
    assert_true(isnan(run.damaged_xy[2]) && isnan(run.damaged_xy[3]));
    assert_true(isnan(run.restored_xy[2]) && isnan(run.restored_xy[3]));
    /* an undamaged cell keeps its point; the damaged one moves to r 5 at the centre */
    assert_true(run.restored_xy[0] == run.damaged_xy[0]);
    double th = sr_sector_angle(2, 4);
    assert_near(run.restored_xy[2 * 6], 5 * cos(th), 1e-12);
    assert_near(run.restored_xy[2 * 6 + 1], 5 * sin(th), 1e-12);
    assert_near(run.damaged_xy[2 * 6], res.grid.pt[3 * 6], 0);
    /* the section: arc from sector 3 over 2 sectors = 270..450 deg */
    assert_int_equal(run.section_count, 1);
    const sr_run_section *s = &run.sections[0];
    assert_int_equal(s->index, 0);
    assert_int_equal(s->has_angles, 1);
    assert_near(s->angle_from_deg, 270, 1e-12);
    assert_near(s->angle_to_deg, 450, 1e-12);
    assert_int_equal(s->side, 0);
    assert_string_equal(s->damage_class, "unclassified");
    assert_null(s->features_json);
    assert_true(s->volume_mm3 == 33 && s->area_mm2 == 44);
    assert_mesh_equal(&s->patch, &res.sections[0].patch);
    assert_mesh_equal(&run.restored, &res.restored);
    assert_int_equal(run.advice_count, 0);
    /* and it is storable as it is */
    int64_t id = add_ok(fx, &run);
    sr_run back;
    assert_int_equal(sr_catalog_run_get(fx->cat, id, SR_RUN_WITH_LAYERS, &back, &err), SR_OK);
    assert_doubles_same(back.damaged_xy, run.damaged_xy, 16);
    assert_doubles_same(back.restored_xy, run.restored_xy, 16);
    sr_run_release(&back);
    sr_run_release(&run);

    /* planar: the side of the plane from the arc's middle (sectors 3, 0: about 0 deg,
     * +x, the side the canonical normal points to) */
    sym = (sr_symmetry){SR_SYM_MIRROR, 0, 0};
    assert_int_equal(sr_run_from_result(&res, fx->inst[1], &sym, &p, "paper", &run, &err), SR_OK);
    assert_int_equal(run.sections[0].has_angles, 0);
    assert_int_equal(run.sections[0].side, 1);
    sr_run_release(&run);
    res.sections[0].sector_first = 1;   /* sectors 1, 2: about 180 deg, -x */
    assert_int_equal(sr_run_from_result(&res, fx->inst[1], &sym, &p, "paper", &run, &err), SR_OK);
    assert_int_equal(run.sections[0].side, -1);
    sr_run_release(&run);
    sr_recon_result_release(&res);
}

static void run_from_result_refuses_a_bad_method_and_mismatched_grids(void **state)
{
    fixture *fx = *state;
    sr_recon_result res;
    fake_result(&res);
    sr_params p = {"default", 1, 3, 0.9, 0.9, 0.05, 0.1, 1.0, ""};
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_run run;
    memset(&run, 0x33, sizeof run);
    sr_run before = run;
    sr_err err = {{0}};
    assert_int_equal(sr_run_from_result(&res, fx->inst[0], &sym, &p, "", &run, &err), SR_E_RANGE);
    assert_msg_has(err, "bad method");
    assert_int_equal(sr_run_from_result(&res, fx->inst[0], &sym, &p, "a-method-far-too-long",
                                        &run, &err),
                     SR_E_RANGE);
    res.analysis.sectors = 5;
    assert_int_equal(sr_run_from_result(&res, fx->inst[0], &sym, &p, "paper", &run, &err),
                     SR_E_RANGE);
    assert_msg_has(err, "disagree");
    assert_memory_equal(&run, &before, sizeof run);
    sr_recon_result_release(&res);
}

/* A real reconstruction of the demo shaft, recorded and read back. */
static void reconstruction_of_the_demo_shaft_is_recorded_whole(void **state)
{
    fixture *fx = *state;
    sr_mesh intact, damaged;
    sr_err err = {{0}};
    assert_int_equal(sr_demo_part_build(0, &intact, &damaged, &err), SR_OK);
    sr_instance_new in = {.part = "P-2", .mesh = &damaged, .serial = "SHAFT"};
    int64_t inst;
    assert_int_equal(sr_catalog_instance_add(fx->cat, &in, &inst, &err), SR_OK);
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry = (sr_symmetry){SR_SYM_AXIAL, 0, 0};
    o.layers = 40;
    o.sectors = 60;
    o.min_depth_mm = 0.1;
    o.skip_union = 1;
    sr_recon_result res;
    if (sr_reconstruct(&damaged, &o, &res, &err) != SR_OK)
        fail_msg("reconstruct: %s", err.msg);
    assert_true(res.section_count >= 1);
    sr_params p = {"test", 40, 60, 0.95, 0.95, 0.05, 0.1, 1.0, ""};
    sr_run run;
    assert_int_equal(sr_run_from_result(&res, inst, &o.symmetry, &p, "paper", &run, &err), SR_OK);
    int64_t id = add_ok(fx, &run);
    sr_run back;
    assert_int_equal(sr_catalog_run_get(fx->cat, id, SR_RUN_WITH_LAYERS | SR_RUN_WITH_MESHES,
                                        &back, &err),
                     SR_OK);
    assert_int_equal(back.section_count, res.section_count);
    for (size_t i = 0; i < res.section_count; i++) {
        assert_true(back.sections[i].volume_mm3 == res.sections[i].volume_mm3);
        assert_mesh_equal(&back.sections[i].patch, &res.sections[i].patch);
        /* the stored patch encloses at least the section's missing volume (the robust
         * method's patch also overlaps the damaged part a little, see patch.h) */
        assert_true(sr_mesh_volume(&back.sections[i].patch) >=
                    res.sections[i].volume_mm3 * (1 - 1e-6));
    }
    assert_mesh_equal(&back.restored, &res.restored);
    assert_int_equal(back.layer_count, 40);
    assert_int_equal(back.sectors, 60);
    /* the chip is at the shoulder's lower edge: somewhere a restored point lies
     * outside its damaged one, by no more than the chip's 6 mm depth */
    double most = 0;
    for (size_t c = 0; c < 40 * 60; c++) {
        const double *d = back.damaged_xy + 2 * c, *r = back.restored_xy + 2 * c;
        if (isnan(d[0]))
            continue;
        most = fmax(most, hypot(r[0], r[1]) - hypot(d[0], d[1]));
    }
    assert_true(most > 1 && most < 6.5);
    sr_run_release(&back);
    sr_run_release(&run);
    sr_recon_result_release(&res);
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);
}

#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)

int main(void)
{
    const struct CMUnitTest tests[] = {
        T(run_round_trip_reads_back_every_field),
        T(run_get_without_flags_reads_no_layers_or_meshes),
        T(run_scan_gaps_round_trip_apart_from_the_sections),
        T(run_failed_record_round_trips_with_nulls),
        T(run_add_refuses_each_bad_field_and_writes_nothing),
        T(run_add_unknown_instance_is_not_found_and_writes_nothing),
        T(run_add_rolls_back_every_row_when_a_late_step_fails),
        T(run_add_on_a_read_only_catalogue_fails_cleanly),
        T(run_list_is_newest_first_with_summaries),
        T(run_list_counts_the_sections_not_built),
        T(run_list_filters_by_instance_and_part),
        T(run_list_of_an_unknown_part_is_not_found),
        T(run_count_counts_runs),
        T(run_get_of_an_unknown_id_is_not_found),
        T(run_restored_mesh_loads_or_says_why_not),
        T(run_release_accepts_null_and_zeroed),
        T(run_from_result_lays_out_outlines_sections_and_timings),
        T(run_from_result_refuses_a_bad_method_and_mismatched_grids),
        T(reconstruction_of_the_demo_shaft_is_recorded_whole),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
