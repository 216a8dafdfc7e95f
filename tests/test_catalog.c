/*
 * test_catalog.c: the SQLite catalogue (src/catalog*.c, sql/): creating, reopening and
 * refusing files (not SQLite, another program's, a newer schema), migrations that
 * fail and roll back, parts, instances, symmetries and parameter sets round-tripping,
 * every refused input leaving the catalogue unchanged (rows counted before and after),
 * and two handles sharing one file. White-box where it must be: catalog_int.h gives
 * the migration hook and the handle's sqlite3* (for a short busy timeout), and raw
 * sqlite3 calls build the foreign files and count rows.
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
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "catalog/catalog.h"
#include "catalog/catalog_int.h"
#include "catalog/catalog_runs.h"
#include "catalog/catalog_rules.h"
#include "run/params_default.h"
#include "support/assert_near.h"

/* ---- fixture: a fresh temporary directory per test ---- */

typedef struct fixture {
    char dir[64];
    char db[128];       /* <dir>/cat.db, not created */
} fixture;

static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    if (!fx)
        return -1;
    strcpy(fx->dir, "/tmp/symrec-test-XXXXXX");
    if (!mkdtemp(fx->dir)) {
        free(fx);
        return -1;
    }
    snprintf(fx->db, sizeof fx->db, "%s/cat.db", fx->dir);
    *state = fx;
    return 0;
}

static int teardown(void **state)
{
    fixture *fx = *state;
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

/* ---- helpers ---- */

static sr_catalog *open_new(const fixture *fx)
{
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    sr_status st = sr_catalog_open(fx->db, SR_CATALOG_CREATE, &cat, &err);
    if (st != SR_OK)
        fail_msg("open: %s", err.msg);
    return cat;
}

/* One integer from `sql` on a raw connection to `path` (no symrec code involved). */
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

/* Runs statements on a raw read-write connection; asserts success. */
static void raw_exec(const char *path, const char *sql)
{
    sqlite3 *db = NULL;
    assert_int_equal(sqlite3_open_v2(path, &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, NULL),
                     SQLITE_OK);
    char *msg = NULL;
    if (sqlite3_exec(db, sql, NULL, NULL, &msg) != SQLITE_OK)
        fail_msg("%s: %s", sql, msg);
    assert_int_equal(sqlite3_close(db), SQLITE_OK);
}

/* Result code of one statement run on the handle's own connection (foreign keys on). */
static int cat_exec_rc(sr_catalog *cat, const char *sql)
{
    return sqlite3_exec(cat->db, sql, NULL, NULL, NULL) & 0xff;
}

/* Row counts of every table that a part or instance add touches. */
typedef struct counts {
    int64_t parts, instances, meshes, materials, symmetries, params;
} counts;

static counts count_all(const char *path)
{
    counts c;
    c.parts = raw_int(path, "SELECT count(*) FROM parts");
    c.instances = raw_int(path, "SELECT count(*) FROM instances");
    c.meshes = raw_int(path, "SELECT count(*) FROM meshes");
    c.materials = raw_int(path, "SELECT count(*) FROM materials");
    c.symmetries = raw_int(path, "SELECT count(*) FROM symmetries");
    c.params = raw_int(path, "SELECT count(*) FROM parameter_sets");
    return c;
}

static void assert_counts_equal(counts a, counts b)
{
    assert_int_equal(a.parts, b.parts);
    assert_int_equal(a.instances, b.instances);
    assert_int_equal(a.meshes, b.meshes);
    assert_int_equal(a.materials, b.materials);
    assert_int_equal(a.symmetries, b.symmetries);
    assert_int_equal(a.params, b.params);
}

/* Whole file contents (the caller frees). */
static unsigned char *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    long n = ftell(f);
    assert_true(n >= 0);
    rewind(f);
    unsigned char *buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *size = (size_t)n;
    return buf;
}

static void assert_file_unchanged(const char *path, const unsigned char *before, size_t size)
{
    size_t n;
    unsigned char *after = read_file(path, &n);
    assert_int_equal(n, size);
    assert_memory_equal(after, before, size);
    free(after);
}

static void assert_msg(const sr_err *err, const char *words)
{
    if (!strstr(err->msg, words))
        fail_msg("message '%s' does not contain '%s'", err->msg, words);
}

/* A closed box of side 2 at (x0, 0.5, -1), 8 vertices, 12 outward triangles;
 * volume 8, area 24. Coordinates chosen so a text round trip would not be exact. */
static void make_box(sr_mesh *m, double x0)
{
    double lo[3] = {x0, 0.5, -1.0}, hi[3] = {x0 + 2.0, 2.5, 1.0};
    static const uint32_t f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                      {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                      {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    assert_int_equal(sr_mesh_alloc(m, 8, 12), SR_OK);
    for (int i = 0; i < 8; i++) {
        m->xyz[3 * i + 0] = ((i & 1) ^ ((i >> 1) & 1)) ? hi[0] : lo[0];
        m->xyz[3 * i + 1] = (i & 2) ? hi[1] : lo[1];
        m->xyz[3 * i + 2] = (i & 4) ? hi[2] : lo[2];
    }
    memcpy(m->tri, f, sizeof f);
}

static void assert_same_mesh(const sr_mesh *a, const sr_mesh *b)
{
    assert_int_equal(a->vertex_count, b->vertex_count);
    assert_int_equal(a->tri_count, b->tri_count);
    assert_memory_equal(a->xyz, b->xyz, a->vertex_count * 3 * sizeof(double));
    assert_memory_equal(a->tri, b->tri, a->tri_count * 3 * sizeof(uint32_t));
}

/* Adds material `name` (7.85 g/cm³): a part may name only a material the catalogue
 * holds, and these tests' materials are not all seeded. */
static void add_material(sr_catalog *cat, const char *name)
{
    sr_material_new m = {.name = name, .density_g_cm3 = 7.85};
    sr_err err = {{0}};
    if (sr_catalog_material_add(cat, &m, NULL, &err) != SR_OK)
        fail_msg("material add: %s", err.msg);
}

static int64_t add_part(sr_catalog *cat, const char *number, const char *name,
                        const char *material, const sr_mesh *mesh)
{
    sr_part_new p = {0};
    p.number = number;
    p.name = name;
    p.material = material;
    p.mesh = mesh;
    int64_t id = 0;
    sr_err err = {{0}};
    if (sr_catalog_part_add(cat, &p, &id, &err) != SR_OK)
        fail_msg("part add: %s", err.msg);
    return id;
}

static int64_t add_instance(sr_catalog *cat, const char *part, const sr_symmetry *sym)
{
    sr_mesh m;
    make_box(&m, 3.0);
    sr_instance_new in = {0};
    in.part = part;
    in.mesh = &m;
    if (sym)
        in.symmetry = *sym;
    int64_t id = 0;
    sr_err err = {{0}};
    if (sr_catalog_instance_add(cat, &in, &id, &err) != SR_OK)
        fail_msg("instance add: %s", err.msg);
    sr_mesh_release(&m);
    return id;
}

/* ---- opening, schema, migrations ---- */

static void create_sets_version_app_id_and_all_tables(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    assert_true(sr_catalog_schema_latest() >= 1);
    assert_int_equal(sr_catalog_schema_version(cat), sr_catalog_schema_latest());
    assert_string_equal(sr_catalog_path(cat), fx->db);
    /* per-connection settings */
    sqlite3_stmt *stmt;
    assert_int_equal(sqlite3_prepare_v2(cat->db, "PRAGMA foreign_keys", -1, &stmt, NULL), SQLITE_OK);
    assert_int_equal(sqlite3_step(stmt), SQLITE_ROW);
    assert_int_equal(sqlite3_column_int(stmt, 0), 1);
    sqlite3_finalize(stmt);
    assert_int_equal(sqlite3_prepare_v2(cat->db, "PRAGMA journal_mode", -1, &stmt, NULL), SQLITE_OK);
    assert_int_equal(sqlite3_step(stmt), SQLITE_ROW);
    assert_string_equal((const char *)sqlite3_column_text(stmt, 0), "wal");
    sqlite3_finalize(stmt);
    sr_catalog_close(cat);

    assert_int_equal(raw_int(fx->db, "PRAGMA application_id"), SR_CATALOG_APP_ID);
    assert_int_equal(raw_int(fx->db, "PRAGMA application_id"), 0x53594d52);
    assert_int_equal(raw_int(fx->db, "PRAGMA user_version"), sr_catalog_schema_latest());
    assert_int_equal(raw_int(fx->db,
                             "SELECT count(*) FROM sqlite_schema WHERE type = 'table' AND name IN"
                             " ('materials', 'meshes', 'parts', 'instances', 'symmetries',"
                             " 'parameter_sets', 'runs', 'run_layers', 'sections',"
                             " 'repair_rules', 'advice')"),
                     11);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM parameter_sets"), 3);
}

static void reopen_is_idempotent(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_material(cat, "steel");
    add_part(cat, "P-1", "plate", "steel", NULL);
    sr_catalog_close(cat);
    int64_t objects = raw_int(fx->db, "SELECT count(*) FROM sqlite_schema");
    counts before = count_all(fx->db);

    for (int i = 0; i < 2; i++) {
        sr_err err = {{0}};
        unsigned flags = i == 0 ? 0 : SR_CATALOG_CREATE;
        assert_int_equal(sr_catalog_open(fx->db, flags, &cat, &err), SR_OK);
        assert_int_equal(sr_catalog_schema_version(cat), sr_catalog_schema_latest());
        sr_part_info info;
        assert_int_equal(sr_catalog_part_find(cat, "P-1", &info, NULL), SR_OK);
        sr_catalog_close(cat);
    }
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM sqlite_schema"), objects);
    assert_counts_equal(count_all(fx->db), before);
    assert_int_equal(raw_int(fx->db, "PRAGMA user_version"), sr_catalog_schema_latest());
}

static void missing_file_without_create_is_refused(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = (sr_catalog *)0x1;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, 0, &cat, &err), SR_E_IO);
    assert_ptr_equal(cat, (sr_catalog *)0x1);
    assert_msg(&err, "no such file");
    assert_int_equal(access(fx->db, F_OK), -1);  /* not created */
    assert_int_equal(sr_catalog_open(fx->db, SR_CATALOG_READONLY | SR_CATALOG_CREATE, &cat, &err),
                     SR_E_IO);
    assert_int_equal(access(fx->db, F_OK), -1);
}

static void every_table_and_column_has_a_comment(void **state)
{
    /* In every sql/ file: each CREATE TABLE is preceded by a comment line, and each
     * column line inside it (indented 4 spaces; deeper lines continue a column) carries
     * a "--" comment, table constraints (CHECK, UNIQUE, FOREIGN) excepted. */
    int tables = 0, columns = 0;
    for (const sr_sql_file *f = sr_sql_files; f->name; f++) {
        const char *p = f->text, *prev = "";
        size_t prev_len = 0;
        bool in_table = false;
        while (*p) {
            const char *end = strchr(p, '\n');
            size_t len = end ? (size_t)(end - p) : strlen(p);
            char line[512];
            snprintf(line, sizeof line, "%.*s", (int)(len < 511 ? len : 511), p);
            const char *t = line + strspn(line, " ");
            if (strncmp(t, "CREATE TABLE", 12) == 0) {
                if (!(prev_len >= 2 && strncmp(prev, "--", 2) == 0))
                    fail_msg("%s: no comment above '%s'", f->name, line);
                in_table = true;
                tables++;
            } else if (in_table) {
                if (*t == ')') {
                    in_table = false;
                } else if (t - line == 4 && strncmp(t, "--", 2) != 0 && strncmp(t, "CHECK", 5) != 0 &&
                           strncmp(t, "UNIQUE", 6) != 0 && strncmp(t, "FOREIGN", 7) != 0) {
                    if (!strstr(line, "--"))
                        fail_msg("%s: column without a comment: '%s'", f->name, line);
                    columns++;
                }
            }
            prev = p;
            prev_len = len;
            p = end ? end + 1 : p + len;
        }
    }
    assert_true(tables >= 11);
    assert_true(columns >= 100);
}

static void garbage_file_is_refused_untouched(void **state)
{
    fixture *fx = *state;
    unsigned char junk[4096];
    for (size_t i = 0; i < sizeof junk; i++)
        junk[i] = (unsigned char)(i * 7919u >> 3);
    FILE *f = fopen(fx->db, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(junk, 1, sizeof junk, f), sizeof junk);
    fclose(f);
    for (int i = 0; i < 3; i++) {
        static const unsigned flags[3] = {0, SR_CATALOG_CREATE, SR_CATALOG_READONLY};
        sr_catalog *cat = NULL;
        sr_err err = {{0}};
        assert_int_equal(sr_catalog_open(fx->db, flags[i], &cat, &err), SR_E_VERSION);
        assert_null(cat);
        char want[256];
        snprintf(want, sizeof want, "'%s' is not a symrec catalogue (file is not a database)",
                 fx->db);
        assert_string_equal(err.msg, want);
        assert_file_unchanged(fx->db, junk, sizeof junk);
    }
}

static void other_application_id_is_refused_untouched(void **state)
{
    fixture *fx = *state;
    raw_exec(fx->db, "PRAGMA application_id = 0x12345678; CREATE TABLE t (x INTEGER);");
    size_t size;
    unsigned char *before = read_file(fx->db, &size);
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, SR_CATALOG_CREATE, &cat, &err), SR_E_VERSION);
    assert_null(cat);
    assert_msg(&err, "is not a symrec catalogue (application_id 0x12345678)");
    assert_file_unchanged(fx->db, before, size);
    free(before);
}

static void other_program_database_without_app_id_is_refused(void **state)
{
    fixture *fx = *state;
    raw_exec(fx->db, "CREATE TABLE customers (name TEXT);");
    size_t size;
    unsigned char *before = read_file(fx->db, &size);
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, SR_CATALOG_CREATE, &cat, &err), SR_E_VERSION);
    assert_msg(&err, "is not a symrec catalogue (an SQLite database of another program)");
    assert_file_unchanged(fx->db, before, size);
    free(before);
}

static void empty_file_needs_create(void **state)
{
    fixture *fx = *state;
    FILE *f = fopen(fx->db, "wb");
    assert_non_null(f);
    fclose(f);
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, 0, &cat, &err), SR_E_VERSION);
    assert_msg(&err, "is not a symrec catalogue (empty database");
    assert_int_equal(sr_catalog_open(fx->db, SR_CATALOG_CREATE, &cat, &err), SR_OK);
    assert_int_equal(sr_catalog_schema_version(cat), sr_catalog_schema_latest());
    sr_catalog_close(cat);
}

static void newer_schema_is_refused_untouched(void **state)
{
    fixture *fx = *state;
    sr_catalog_close(open_new(fx));
    /* one past the latest migration this build has */
    int newer = sr_catalog_schema_latest() + 1;
    char pragma[64];
    snprintf(pragma, sizeof pragma, "PRAGMA user_version = %d;", newer);
    raw_exec(fx->db, pragma);
    size_t size;
    unsigned char *before = read_file(fx->db, &size);
    char want[256];
    snprintf(want, sizeof want,
             "'%s' has schema version %d, this symrec knows up to %d: upgrade symrec", fx->db,
             newer, sr_catalog_schema_latest());
    static const unsigned flags[3] = {0, SR_CATALOG_CREATE, SR_CATALOG_READONLY};
    for (int i = 0; i < 3; i++) {
        sr_catalog *cat = NULL;
        sr_err err = {{0}};
        assert_int_equal(sr_catalog_open(fx->db, flags[i], &cat, &err), SR_E_VERSION);
        assert_null(cat);
        assert_string_equal(err.msg, want);
        assert_file_unchanged(fx->db, before, size);
    }
    free(before);

    raw_exec(fx->db, "PRAGMA user_version = -1;");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, 0, &cat, &err), SR_E_VERSION);
    assert_msg(&err, "is not a symrec catalogue (schema version -1)");
}

/* A catalogue at schema version 1 (the real 001 only), for the tests of migrating it
 * with a test's own 002, whatever migrations the build has after 001. */
static sr_catalog *open_v1(const fixture *fx)
{
    sr_sql_file files[2] = {sr_sql_files[0], {NULL, NULL}};
    assert_string_equal(files[0].name, "001_init.sql");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_cat_open_with(fx->db, SR_CATALOG_CREATE, files, &cat, &err) != SR_OK)
        fail_msg("open: %s", err.msg);
    return cat;
}

/* The real 001 followed by a test's 002. */
static void migrations_with(sr_sql_file files[3], const char *text2, const char *name2)
{
    files[0] = sr_sql_files[0];
    assert_string_equal(files[0].name, "001_init.sql");
    files[1].name = name2;
    files[1].text = text2;
    files[2].name = NULL;
    files[2].text = NULL;
}

static void failing_migration_rolls_back(void **state)
{
    fixture *fx = *state;
    sr_catalog_close(open_v1(fx));
    counts before = count_all(fx->db);
    sr_sql_file files[3];
    migrations_with(files,
                    "CREATE TABLE extra (x INTEGER);\n"
                    "INSERT INTO parameter_sets (name, layers, sectors, gamma_axis, gamma_plane,"
                    " delta_d, min_depth_mm, min_volume_mm3) VALUES ('x', 1, 3, 1, 1, 1, 0, 0);\n"
                    "INSERT INTO no_such_table VALUES (1);\n"
                    "PRAGMA user_version = 2;\n",
                    "002_broken.sql");
    assert_int_equal(sr_cat_schema_latest_of(files), 2);
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_cat_open_with(fx->db, 0, files, &cat, &err), SR_E_DB);
    assert_null(cat);
    assert_msg(&err, "cannot apply migration 002_broken.sql");
    assert_msg(&err, "no_such_table");
    assert_int_equal(raw_int(fx->db, "PRAGMA user_version"), 1);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM sqlite_schema WHERE name = 'extra'"), 0);
    assert_counts_equal(count_all(fx->db), before);
    /* the catalogue still opens with the real migrations */
    assert_int_equal(sr_catalog_open(fx->db, 0, &cat, &err), SR_OK);
    sr_catalog_close(cat);
}

static void migration_must_set_its_version(void **state)
{
    fixture *fx = *state;
    sr_catalog_close(open_v1(fx));
    sr_sql_file files[3];
    migrations_with(files, "CREATE TABLE extra (x INTEGER);\n", "002_forgetful.sql");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_cat_open_with(fx->db, 0, files, &cat, &err), SR_E_INTERNAL);
    assert_msg(&err, "it left user_version 1, not 2");
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM sqlite_schema WHERE name = 'extra'"), 0);
}

static void migration_leaving_broken_foreign_key_rolls_back(void **state)
{
    /* Migrations run with foreign keys off (so a table can be rebuilt); the check
     * before COMMIT must catch what they would have refused. */
    fixture *fx = *state;
    sr_catalog_close(open_v1(fx));
    sr_sql_file files[3];
    migrations_with(files,
                    "INSERT INTO parts (number, name, material_id) VALUES ('X', 'x', 999);\n"
                    "PRAGMA user_version = 2;\n",
                    "002_dangling.sql");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_cat_open_with(fx->db, 0, files, &cat, &err), SR_E_INTERNAL);
    assert_msg(&err, "cannot apply migration 002_dangling.sql");
    assert_msg(&err, "leaves a row of table 'parts' with a broken foreign key");
    assert_int_equal(raw_int(fx->db, "PRAGMA user_version"), 1);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM parts"), 0);
}

/* Schema 4 to 5 (sql/005_mesh_units.sql): every mesh stored before takes 'mm', the rows
 * stay, and a mesh read in another unit keeps it from then on. */
static void migration_005_gives_older_meshes_mm(void **state)
{
    fixture *fx = *state;
    sr_sql_file v4[5];
    for (int i = 0; i < 4; i++)
        v4[i] = sr_sql_files[i];
    v4[4] = (sr_sql_file){NULL, NULL};
    assert_string_equal(v4[3].name, "004_history_summary.sql");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_cat_open_with(fx->db, SR_CATALOG_CREATE, v4, &cat, &err) != SR_OK)
        fail_msg("open: %s", err.msg);
    assert_int_equal(sr_catalog_schema_version(cat), 4);
    sr_mesh m;
    make_box(&m, 0.0);
    add_part(cat, "P-1", "plate", NULL, &m);
    sr_mesh_release(&m);
    add_instance(cat, "P-1", NULL);
    sr_catalog_close(cat);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM pragma_table_info('meshes')"
                                     " WHERE name = 'source_unit'"),
                     0);

    assert_int_equal(sr_catalog_open(fx->db, 0, &cat, &err), SR_OK);
    assert_int_equal(sr_catalog_schema_opened(cat), 4);
    assert_int_equal(sr_catalog_schema_version(cat), sr_catalog_schema_latest());
    sr_part_info p;
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &p, &err), SR_OK);
    assert_string_equal(p.source_unit, "mm");
    assert_int_equal(p.instance_count, 1);
    sr_instance_info in;
    assert_int_equal(sr_catalog_instance_get(cat, 1, &in, &err), SR_OK);
    assert_string_equal(in.source_unit, "mm");
    /* a scan read in inches keeps its unit */
    make_box(&m, 5.0);
    sr_instance_new inch = {.part = "P-1", .mesh = &m, .source_unit = SR_UNIT_IN};
    int64_t id;
    assert_int_equal(sr_catalog_instance_add(cat, &inch, &id, &err), SR_OK);
    sr_mesh_release(&m);
    assert_int_equal(sr_catalog_instance_get(cat, id, &in, &err), SR_OK);
    assert_string_equal(in.source_unit, "in");
    sr_catalog_close(cat);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM meshes"), 3);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM meshes WHERE source_unit = 'mm'"), 2);
    assert_int_equal(raw_int(fx->db, "PRAGMA user_version"), sr_catalog_schema_latest());
}

/* A run on instance inst with a nominal record measured by `method` (NULL: no
 * nominal record); returns its id. */
static int64_t add_run_with_nominal(sr_catalog *cat, int64_t inst, const char *method,
                                    double cell_mm, const char *note)
{
    sr_run r;
    memset(&r, 0, sizeof r);
    r.instance_id = inst;
    r.symmetry = (sr_symmetry){SR_SYM_AXIAL, 0, 0};
    r.params = (sr_params){"default", 10, 12, 0.9, 0.8, 0.07, 0.2, 1.5, ""};
    snprintf(r.method, sizeof r.method, "image");
    r.fit_quality = -1;
    r.ok = 1;
    snprintf(r.started_at, sizeof r.started_at, "2026-12-05T06:00:00Z");
    sr_run_nominal n;
    memset(&n, 0, sizeof n);
    snprintf(n.reference, sizeof n.reference, "symmetry");
    n.transform[0] = n.transform[5] = n.transform[10] = 1;
    n.coverage = 0.97;
    n.nominal_mm3 = 120;
    snprintf(n.method, sizeof n.method, "%s", method ? method : "");
    n.cell_mm = cell_mm;
    snprintf(n.exact_note, sizeof n.exact_note, "%s", note);
    r.nominal = method ? &n : NULL;
    int64_t id = 0;
    sr_err err = {{0}};
    if (sr_catalog_run_add(cat, &r, &id, &err) != SR_OK)
        fail_msg("run add: %s", err.msg);
    return id;
}

/* Schema 9 to 10 (sql/010_nominal_method.sql): a nominal recorded before keeps its
 * figures and reads back with its method unknown; one recorded after keeps how it was
 * measured (cells with their size and why the exact difference was refused, or
 * exact), and the catalogue refuses a method it does not know. */
static void migration_010_records_how_the_nominal_was_measured(void **state)
{
    fixture *fx = *state;
    sr_sql_file v9[10];
    for (int i = 0; i < 9; i++)
        v9[i] = sr_sql_files[i];
    v9[9] = (sr_sql_file){NULL, NULL};
    assert_string_equal(v9[8].name, "009_inspection.sql");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_cat_open_with(fx->db, SR_CATALOG_CREATE, v9, &cat, &err) != SR_OK)
        fail_msg("open: %s", err.msg);
    assert_int_equal(sr_catalog_schema_version(cat), 9);
    sr_mesh m;
    make_box(&m, 0.0);
    add_part(cat, "P-1", "plate", NULL, &m);
    sr_mesh_release(&m);
    int64_t inst = add_instance(cat, "P-1", NULL);
    add_run_with_nominal(cat, inst, NULL, 0, ""); /* the run; its nominal below */
    sr_catalog_close(cat);
    /* a version-9 nominal, written as version 9 wrote it */
    raw_exec(fx->db,
             "INSERT INTO run_nominal (run_id, reference, transform, coverage, rms_mm, tol_mm,"
             " nominal_mm3, symmetry_mm3, diff_mm3, diff_pct, sliver_mm, slivers, sliver_mm3,"
             " min_volume_mm3, scan_outside_mm3, scan_outside_limit_mm3, poor, note, seconds)"
             " SELECT id, 'symmetry', zeroblob(96), 0.9, 0.01, 0.1, 100, 99, 1, 1, 0.05, 0, 0,"
             " 1, 0, 5, 0, '', 0.5 FROM runs;");

    assert_int_equal(sr_catalog_open(fx->db, 0, &cat, &err), SR_OK);
    assert_int_equal(sr_catalog_schema_opened(cat), 9);
    assert_int_equal(sr_catalog_schema_version(cat), sr_catalog_schema_latest());
    sr_run old;
    assert_int_equal(sr_catalog_run_get(cat, 1, 0, &old, &err), SR_OK);
    assert_non_null(old.nominal);
    assert_near(old.nominal->nominal_mm3, 100, 0);
    assert_string_equal(old.nominal->method, "");
    assert_int_equal(old.unbuilt_sections, 0); /* sql/013: none recorded before */
    assert_true(old.unbuilt_mm3 == 0);
    char how[320];
    sr_run_nominal_method_text(old.nominal, how, sizeof how);
    assert_non_null(strstr(how, "not recorded"));
    sr_run_release(&old);

    int64_t cells = add_run_with_nominal(cat, inst, "cells", 0.25, "'scan' intersects itself");
    int64_t exact = add_run_with_nominal(cat, inst, "exact", 0, "");
    sr_run back;
    assert_int_equal(sr_catalog_run_get(cat, cells, 0, &back, &err), SR_OK);
    assert_string_equal(back.nominal->method, "cells");
    assert_near(back.nominal->cell_mm, 0.25, 0);
    assert_string_equal(back.nominal->exact_note, "'scan' intersects itself");
    sr_run_nominal_method_text(back.nominal, how, sizeof how);
    assert_non_null(strstr(how, "by cells of 0.250 mm"));
    assert_non_null(strstr(how, "refused the scan: 'scan' intersects itself"));
    sr_run_release(&back);
    assert_int_equal(sr_catalog_run_get(cat, exact, 0, &back, &err), SR_OK);
    assert_string_equal(back.nominal->method, "exact");
    sr_run_release(&back);
    assert_int_equal(cat_exec_rc(cat, "UPDATE run_nominal SET method = 'fast'"), SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "UPDATE run_nominal SET cell_mm = 0"), SQLITE_CONSTRAINT);
    sr_catalog_close(cat);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM run_nominal WHERE method IS NULL"), 1);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM run_nominal WHERE cell_mm IS NULL"), 2);
}

static void migration_upgrades_older_catalogue(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_v1(fx);
    add_part(cat, "P-1", "plate", NULL, NULL);
    sr_catalog_close(cat);
    sr_sql_file files[3];
    migrations_with(files,
                    "-- a later migration\n"
                    "ALTER TABLE materials ADD COLUMN max_temp_c REAL; -- a new column\n"
                    "PRAGMA user_version = 2;\n",
                    "002_material_limits.sql");
    sr_err err = {{0}};
    /* read-only never migrates: refused */
    assert_int_equal(sr_cat_open_with(fx->db, SR_CATALOG_READONLY, files, &cat, &err), SR_E_VERSION);
    assert_msg(&err, "has schema version 1, this symrec needs 2");
    assert_int_equal(sr_cat_open_with(fx->db, 0, files, &cat, &err), SR_OK);
    assert_int_equal(sr_catalog_schema_version(cat), 2);
    sr_catalog_close(cat);
    /* the part kept (by SQL: the API's queries are those of the built-in schema) */
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM parts WHERE number = 'P-1'"), 1);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM pragma_table_info('materials')"
                                     " WHERE name = 'max_temp_c'"),
                     1);
    /* (a file newer than the built-in migrations: newer_schema_is_refused_untouched) */
}

static void gap_in_migrations_is_refused(void **state)
{
    fixture *fx = *state;
    sr_sql_file files[3];
    migrations_with(files, "PRAGMA user_version = 3;\n", "003_skips_two.sql");
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_cat_open_with(fx->db, SR_CATALOG_CREATE, files, &cat, &err),
                     SR_E_INTERNAL);
    assert_msg(&err, "migration 002 missing");
    assert_int_equal(access(fx->db, F_OK), -1);
}

static void schema_refuses_inconsistent_rows(void **state)
{
    /* The constraints are the safety net under the C checks: rows the C code never
     * writes are refused by the file itself. */
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_mesh m;
    make_box(&m, 0);
    int64_t part = add_part(cat, "P-1", "plate", NULL, &m);
    assert_true(part > 0);
    sr_mesh_release(&m);
    /* symmetry on neither or both of part and instance, unknown kind */
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO symmetries (kind) VALUES ('axial')"),
                     SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO symmetries (part_id, kind) VALUES (1, 'spiral')"),
                     SQLITE_CONSTRAINT);
    /* foreign keys are enforced on the handle's connection */
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO instances (part_id, mesh_id) VALUES (99, 1)"),
                     SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "DELETE FROM meshes"), SQLITE_CONSTRAINT);
    /* a blob whose length disagrees with the counts */
    assert_int_equal(cat_exec_rc(cat, "UPDATE meshes SET data = X'00'"), SQLITE_CONSTRAINT);
    /* STRICT: wrong type */
    assert_int_equal(cat_exec_rc(cat, "UPDATE parts SET mesh_id = 'one'"), SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "UPDATE parameter_sets SET layers = 0"), SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO instances (part_id, mesh_id, received)"
                                      " VALUES (1, 1, '2024-13-01')"),
                     SQLITE_CONSTRAINT);
    /* a run, a section of it, and advice naming a section of another run */
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO instances (part_id, mesh_id) VALUES (1, 1)"),
                     SQLITE_OK);
    const char *run =
        "INSERT INTO runs (instance_id, symmetry_kind, params_name, layers, sectors, gamma_axis,"
        " gamma_plane, delta_d, min_depth_mm, min_volume_mm3, method, status, software_version,"
        " started_at) VALUES (1, 'axial', 'default', 320, 240, 0.95, 0.95, 0.05, 0.1, 1, 'paper',"
        " 'ok', '0.1.0', '2024-01-01T00:00:00Z')";
    assert_int_equal(cat_exec_rc(cat, run), SQLITE_OK);
    assert_int_equal(cat_exec_rc(cat, run), SQLITE_OK);
    assert_int_equal(cat_exec_rc(cat, "UPDATE runs SET status = 'maybe' WHERE id = 1"),
                     SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "UPDATE runs SET status = 'failed' WHERE id = 1"),
                     SQLITE_CONSTRAINT);  /* a failed run needs its error */
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO sections (run_id, section_index, layer_first,"
                                      " layer_last, z_min_mm, z_max_mm, volume_mm3, area_mm2,"
                                      " depth_max_mm, depth_mean_mm, class)"
                                      " VALUES (1, 0, 3, 5, 1.0, 2.0, 10, 5, 1, 0.5, 'chip')"),
                     SQLITE_OK);
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO advice (run_id, section_id, process, reason)"
                                      " VALUES (2, 1, 'spray_forming', 'x')"),
                     SQLITE_CONSTRAINT);
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO advice (run_id, section_id, process, reason)"
                                      " VALUES (1, 1, 'spray_forming', 'x')"),
                     SQLITE_OK);
    assert_int_equal(cat_exec_rc(cat, "INSERT INTO run_layers (run_id, layer_index, z_mm, damaged,"
                                      " restored) VALUES (1, 0, 0.5, zeroblob(32), zeroblob(16))"),
                     SQLITE_CONSTRAINT);
    /* deleting a run takes its sections and advice with it */
    assert_int_equal(cat_exec_rc(cat, "DELETE FROM runs WHERE id = 1"), SQLITE_OK);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM sections"), 0);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM advice"), 0);
    /* a part with instances cannot be deleted */
    assert_int_equal(cat_exec_rc(cat, "DELETE FROM parts"), SQLITE_CONSTRAINT);
    sr_catalog_close(cat);
}

/* ---- parts ---- */

static void part_with_mesh_round_trips_bit_identical(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_mesh m;
    make_box(&m, 0.1);
    sr_part_new p = {0};
    p.number = "SH-100";
    p.name = "drive shaft";
    p.material = "42CrMo4";
    p.notes = "hardened";
    p.mesh = &m;
    p.source_file = "shaft.stl";
    p.symmetry.kind = SR_SYM_AXIAL;
    p.symmetry.order = 4;
    int64_t id = 0;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_add(cat, &p, &id, &err), SR_OK);
    assert_true(id > 0);

    sr_part_info info;
    assert_int_equal(sr_catalog_part_find(cat, "SH-100", &info, &err), SR_OK);
    assert_int_equal(info.id, id);
    assert_string_equal(info.number, "SH-100");
    assert_string_equal(info.name, "drive shaft");
    assert_string_equal(info.material, "42CrMo4");
    assert_string_equal(info.notes, "hardened");
    assert_true(info.mesh_id > 0);
    assert_int_equal(info.vertex_count, 8);
    assert_int_equal(info.tri_count, 12);
    assert_near(info.volume_mm3, 8.0, 1e-12);
    assert_near(info.area_mm2, 24.0, 1e-12);
    assert_near(info.bbox_min[0], 0.1, 0);
    assert_near(info.bbox_max[1], 2.5, 0);
    assert_near(info.bbox_min[2], -1.0, 0);
    assert_int_equal(info.instance_count, 0);
    assert_int_equal(info.symmetry.kind, SR_SYM_AXIAL);
    assert_int_equal(info.symmetry.order, 4);
    assert_int_equal(strlen(info.created_at), 20);
    assert_int_equal(info.created_at[19], 'Z');

    sr_mesh back;
    assert_int_equal(sr_catalog_part_mesh(cat, id, &back, &err), SR_OK);
    assert_same_mesh(&back, &m);
    sr_mesh_release(&back);
    assert_int_equal(sr_catalog_mesh_load(cat, info.mesh_id, &back, &err), SR_OK);
    assert_same_mesh(&back, &m);
    sr_mesh_release(&back);
    sr_catalog_close(cat);

    assert_int_equal(raw_int(fx->db, "SELECT closed FROM meshes"), 1);
    assert_int_equal(raw_int(fx->db, "SELECT source_file = 'shaft.stl' FROM meshes"), 1);
    assert_int_equal(raw_int(fx->db, "SELECT length(data) FROM meshes"), 24 + 24 * 8 + 12 * 12);
    sr_mesh_release(&m);
}

static void part_without_mesh_has_no_mesh(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    int64_t id = add_part(cat, "P-1", "plate", NULL, NULL);
    sr_part_info info;
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &info, NULL), SR_OK);
    assert_int_equal(info.mesh_id, 0);
    assert_int_equal(info.tri_count, 0);
    assert_string_equal(info.material, "");
    assert_int_equal(info.symmetry.kind, SR_SYM_NONE);
    sr_mesh back = {0};
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_mesh(cat, id, &back, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "part 'P-1' has no mesh in the catalogue");
    assert_null(back.xyz);
    assert_int_equal(sr_catalog_part_mesh(cat, 99, &back, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no part 99 in the catalogue");
    assert_int_equal(sr_catalog_mesh_load(cat, 99, &back, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no mesh 99 in the catalogue");
    sr_catalog_close(cat);
}

static void part_find_by_number_then_id(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    int64_t a = add_part(cat, "X-1", "first", NULL, NULL);   /* id 1 */
    int64_t b = add_part(cat, "1", "second", NULL, NULL);    /* id 2, number "1" */
    assert_int_equal(a, 1);
    assert_int_equal(b, 2);
    sr_part_info info;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_find(cat, "1", &info, &err), SR_OK);
    assert_int_equal(info.id, b);   /* the number wins over id 1 */
    assert_int_equal(sr_catalog_part_find(cat, "2", &info, &err), SR_OK);
    assert_string_equal(info.number, "1");   /* no number "2": id 2 */
    assert_int_equal(sr_catalog_part_find(cat, "x-1", &info, &err), SR_OK);
    assert_string_equal(info.number, "X-1");   /* numbers ignore ASCII case */
    memset(&info, 0x5a, sizeof info);
    assert_int_equal(sr_catalog_part_find(cat, "99", &info, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no part '99' in the catalogue");
    assert_int_equal(info.id, 0x5a5a5a5a5a5a5a5a);   /* untouched */
    assert_int_equal(sr_catalog_part_find(cat, "02", &info, &err), SR_E_NOTFOUND);
    assert_int_equal(sr_catalog_part_find(cat, "", &info, &err), SR_E_NOTFOUND);
    assert_int_equal(sr_catalog_part_find(cat, "99999999999999999999", &info, &err),
                     SR_E_NOTFOUND);
    sr_catalog_close(cat);
}

typedef struct collected {
    int count;
    int stop_after;     /* 0 = never stop */
    char numbers[8][64];
} collected;

static int collect_part(const sr_part_info *p, void *user)
{
    collected *c = user;
    if (c->count < 8)
        strcpy(c->numbers[c->count], p->number);
    c->count++;
    return c->stop_after && c->count >= c->stop_after;
}

static collected list_parts(sr_catalog *cat, const char *name, const char *number,
                            const char *material)
{
    sr_part_filter f = {name, number, material};
    collected c = {0};
    sr_err err = {{0}};
    if (sr_catalog_part_list(cat, &f, collect_part, &c, &err) != SR_OK)
        fail_msg("list: %s", err.msg);
    return c;
}

static void part_list_filters_by_name_number_material(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_material(cat, "steel");
    add_part(cat, "SH-200", "pump shaft", "steel", NULL);
    add_part(cat, "SH-100", "drive shaft", "42CrMo4", NULL);
    add_part(cat, "GR-7", "spur gear", "Steel", NULL);   /* same material as "steel" */
    /* "steel" once (names ignore case) and 42CrMo4 (seeded by 002_rules.sql, or added) */
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM materials"
                                     " WHERE name IN ('steel', '42CrMo4')"), 2);

    collected c = {0};
    assert_int_equal(sr_catalog_part_list(cat, NULL, collect_part, &c, NULL), SR_OK);
    assert_int_equal(c.count, 3);
    assert_string_equal(c.numbers[0], "GR-7");
    assert_string_equal(c.numbers[1], "SH-100");
    assert_string_equal(c.numbers[2], "SH-200");

    c = list_parts(cat, "SHAFT", NULL, NULL);
    assert_int_equal(c.count, 2);
    c = list_parts(cat, NULL, "sh-2", NULL);
    assert_int_equal(c.count, 1);
    assert_string_equal(c.numbers[0], "SH-200");
    c = list_parts(cat, NULL, NULL, "STEEL");
    assert_int_equal(c.count, 2);
    assert_string_equal(c.numbers[0], "GR-7");
    assert_string_equal(c.numbers[1], "SH-200");
    c = list_parts(cat, "gear", NULL, "steel");
    assert_int_equal(c.count, 1);
    c = list_parts(cat, NULL, NULL, "stee");   /* material matches exactly */
    assert_int_equal(c.count, 0);
    c = list_parts(cat, "", "", "");            /* empty = everything */
    assert_int_equal(c.count, 3);
    c = list_parts(cat, "%", NULL, NULL);        /* no wildcard meaning */
    assert_int_equal(c.count, 0);

    collected stop = {.stop_after = 1};
    assert_int_equal(sr_catalog_part_list(cat, NULL, collect_part, &stop, NULL), SR_OK);
    assert_int_equal(stop.count, 1);
    sr_catalog_close(cat);
}

static void duplicate_part_number_changes_nothing(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_mesh m;
    make_box(&m, 0);
    add_material(cat, "steel");
    add_part(cat, "P-1", "plate", "steel", &m);
    counts before = count_all(fx->db);

    sr_part_new p = {0};
    p.number = "p-1";   /* same number ignoring case */
    p.name = "another plate";
    p.material = "bronze";
    p.mesh = &m;
    p.symmetry.kind = SR_SYM_MIRROR;
    int64_t id = -5;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_add(cat, &p, &id, &err), SR_E_EXISTS);
    assert_string_equal(err.msg, "part 'p-1' is already in the catalogue");
    assert_int_equal(id, -5);
    assert_counts_equal(count_all(fx->db), before);
    sr_catalog_close(cat);
    sr_mesh_release(&m);
}

static void part_add_refuses_bad_fields(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    counts before = count_all(fx->db);
    char long_number[65];
    memset(long_number, 'n', 64);
    long_number[64] = '\0';
    sr_mesh nan_mesh;
    make_box(&nan_mesh, 0);
    nan_mesh.xyz[4] = NAN;

    struct {
        sr_part_new p;
        sr_status want;
        const char *words;
    } cases[] = {
        {{.number = NULL, .name = "x"}, SR_E_RANGE, "a part needs a number"},
        {{.number = "", .name = "x"}, SR_E_RANGE, "a part needs a number"},
        {{.number = long_number, .name = "x"}, SR_E_RANGE, "longer than 63 bytes"},
        {{.number = "P-9", .name = ""}, SR_E_RANGE, "part 'P-9' needs a name"},
        {{.number = "P-9", .name = "x", .material = long_number}, SR_E_RANGE, "bad material"},
        {{.number = "P-9", .name = "x", .symmetry = {SR_SYM_AXIAL, 1, 0}}, SR_E_RANGE,
         "bad order 1"},
        {{.number = "P-9", .name = "x", .symmetry = {SR_SYM_GLIDE, 0, -1}}, SR_E_RANGE,
         "bad shift"},
        {{.number = "P-9", .name = "x", .mesh = &nan_mesh, .source_file = "bad.stl"},
         SR_E_INVALID, "'bad.stl' has 1 vertices with NaN"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sr_err err = {{0}};
        int64_t id = -5;
        assert_int_equal(sr_catalog_part_add(cat, &cases[i].p, &id, &err), cases[i].want);
        assert_msg(&err, cases[i].words);
        assert_int_equal(id, -5);
    }
    assert_counts_equal(count_all(fx->db), before);
    sr_mesh_release(&nan_mesh);
    sr_catalog_close(cat);
}

static void late_failure_rolls_back_the_whole_add(void **state)
{
    /* A failure after the mesh row is written must take it back: a temporary trigger
     * on the handle's connection makes the last insert fail. */
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_material(cat, "bronze");
    add_part(cat, "A", "a", NULL, NULL);
    counts before = count_all(fx->db);
    sr_mesh m;
    make_box(&m, 0);
    sr_err err = {{0}};

    assert_int_equal(cat_exec_rc(cat, "CREATE TEMP TRIGGER boom BEFORE INSERT ON main.symmetries"
                                      " BEGIN SELECT RAISE(ABORT, 'boom'); END"),
                     SQLITE_OK);
    sr_part_new p = {.number = "B", .name = "b", .material = "bronze", .mesh = &m,
                     .symmetry = {SR_SYM_MIRROR, 0, 0}};
    assert_int_equal(sr_catalog_part_add(cat, &p, NULL, &err), SR_E_DB);
    assert_msg(&err, "boom");
    sr_instance_new in = {.part = "A", .mesh = &m, .symmetry = {SR_SYM_AXIAL, 0, 0}};
    assert_int_equal(sr_catalog_instance_add(cat, &in, NULL, &err), SR_E_DB);
    assert_msg(&err, "boom");
    assert_counts_equal(count_all(fx->db), before);

    /* the handle is usable afterwards: no transaction was left open */
    assert_int_equal(cat_exec_rc(cat, "DROP TRIGGER temp.boom"), SQLITE_OK);
    assert_int_equal(sr_catalog_part_add(cat, &p, NULL, &err), SR_OK);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM parts"), before.parts + 1);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM meshes"), before.meshes + 1);
    sr_mesh_release(&m);
    sr_catalog_close(cat);
}

/* ---- instances ---- */

static void instance_round_trips(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    int64_t part = add_part(cat, "SH-100", "drive shaft", NULL, NULL);
    sr_mesh scan;
    make_box(&scan, -7.25);
    sr_instance_new in = {0};
    in.part = "SH-100";
    in.mesh = &scan;
    in.serial = "SN-0042";
    in.received = "2024-02-29";
    in.notes = "chipped shoulder";
    in.source_file = "scan-42.stl";
    int64_t id = 0;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_instance_add(cat, &in, &id, &err), SR_OK);

    sr_instance_info info;
    assert_int_equal(sr_catalog_instance_get(cat, id, &info, &err), SR_OK);
    assert_int_equal(info.id, id);
    assert_int_equal(info.part_id, part);
    assert_string_equal(info.part_number, "SH-100");
    assert_string_equal(info.serial, "SN-0042");
    assert_string_equal(info.received, "2024-02-29");
    assert_string_equal(info.notes, "chipped shoulder");
    assert_int_equal(info.vertex_count, 8);
    assert_int_equal(info.tri_count, 12);
    assert_near(info.volume_mm3, 8.0, 1e-12);
    assert_near(info.bbox_min[0], -7.25, 0);
    assert_int_equal(info.symmetry.kind, SR_SYM_NONE);
    sr_mesh back;
    assert_int_equal(sr_catalog_instance_mesh(cat, id, &back, &err), SR_OK);
    assert_same_mesh(&back, &scan);
    sr_mesh_release(&back);

    sr_part_info pinfo;
    assert_int_equal(sr_catalog_part_find(cat, "SH-100", &pinfo, &err), SR_OK);
    assert_int_equal(pinfo.instance_count, 1);

    /* received defaults to today (UTC); by id as the part key */
    time_t t0 = time(NULL);
    in.part = "1";
    in.received = NULL;
    in.serial = NULL;
    int64_t id2 = 0;
    assert_int_equal(sr_catalog_instance_add(cat, &in, &id2, &err), SR_OK);
    time_t t1 = time(NULL);
    assert_int_equal(sr_catalog_instance_get(cat, id2, &info, &err), SR_OK);
    char d0[16], d1[16];
    strftime(d0, sizeof d0, "%Y-%m-%d", gmtime(&t0));
    strftime(d1, sizeof d1, "%Y-%m-%d", gmtime(&t1));
    assert_true(strcmp(info.received, d0) == 0 || strcmp(info.received, d1) == 0);
    assert_string_equal(info.serial, "");
    assert_int_equal(sr_catalog_instance_get(cat, 99, &info, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no instance 99 in the catalogue");
    assert_int_equal(sr_catalog_instance_mesh(cat, 99, &back, &err), SR_E_NOTFOUND);
    sr_mesh_release(&scan);
    sr_catalog_close(cat);
}

static int count_instance(const sr_instance_info *inst, void *user)
{
    (void)inst;
    (*(int *)user)++;
    return 0;
}

static void instance_list_by_part(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "A", "a", NULL, NULL);
    add_part(cat, "B", "b", NULL, NULL);
    add_instance(cat, "A", NULL);
    add_instance(cat, "B", NULL);
    add_instance(cat, "A", NULL);
    int n = 0;
    assert_int_equal(sr_catalog_instance_list(cat, NULL, count_instance, &n, NULL), SR_OK);
    assert_int_equal(n, 3);
    n = 0;
    assert_int_equal(sr_catalog_instance_list(cat, "a", count_instance, &n, NULL), SR_OK);
    assert_int_equal(n, 2);
    n = 0;
    assert_int_equal(sr_catalog_instance_list(cat, "2", count_instance, &n, NULL), SR_OK);
    assert_int_equal(n, 1);
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_instance_list(cat, "C", count_instance, &n, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no part 'C' in the catalogue");
    sr_catalog_close(cat);
}

static void instance_of_unknown_part_writes_nothing(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "A", "a", NULL, NULL);
    counts before = count_all(fx->db);
    sr_mesh scan;
    make_box(&scan, 0);
    sr_instance_new in = {0};
    in.part = "NOPE";
    in.mesh = &scan;
    in.symmetry.kind = SR_SYM_MIRROR;
    int64_t id = -5;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_instance_add(cat, &in, &id, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no part 'NOPE' in the catalogue");
    assert_int_equal(id, -5);
    assert_counts_equal(count_all(fx->db), before);   /* no orphan mesh either */
    sr_mesh_release(&scan);
    sr_catalog_close(cat);
}

static void instance_with_invalid_mesh_writes_nothing(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "A", "a", NULL, NULL);
    counts before = count_all(fx->db);
    sr_mesh nan_mesh, bad_index, empty = {0};
    make_box(&nan_mesh, 0);
    nan_mesh.xyz[7] = NAN;
    make_box(&bad_index, 0);
    bad_index.tri[5] = 8;
    struct {
        const sr_mesh *mesh;
        const char *source;
        const char *words;
    } cases[] = {
        {&nan_mesh, "scan.stl", "'scan.stl' has 1 vertices with NaN or infinite coordinates"},
        {&empty, NULL, "'scan of part A' contains no triangles"},
        {&bad_index, "idx.stl", "'idx.stl' has 1 triangles with a vertex index out of range"},
        {NULL, NULL, "needs a mesh"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sr_instance_new in = {0};
        in.part = "A";
        in.mesh = cases[i].mesh;
        in.source_file = cases[i].source;
        sr_err err = {{0}};
        int64_t id = -5;
        assert_int_equal(sr_catalog_instance_add(cat, &in, &id, &err), SR_E_INVALID);
        assert_msg(&err, cases[i].words);
        assert_int_equal(id, -5);
    }
    assert_counts_equal(count_all(fx->db), before);
    sr_mesh_release(&nan_mesh);
    sr_mesh_release(&bad_index);
    sr_catalog_close(cat);
}

static void instance_refuses_bad_received_date(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "A", "a", NULL, NULL);
    counts before = count_all(fx->db);
    sr_mesh scan;
    make_box(&scan, 0);
    static const char *bad[] = {"2023-02-29", "2024-13-01", "2024-04-31", "24-01-01",
                                "2024-1-01",  "2024/01/01", "0000-01-01", "today"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sr_instance_new in = {0};
        in.part = "A";
        in.mesh = &scan;
        in.received = bad[i];
        sr_err err = {{0}};
        assert_int_equal(sr_catalog_instance_add(cat, &in, NULL, &err), SR_E_RANGE);
        char want[128];
        snprintf(want, sizeof want, "bad received date '%s': expected YYYY-MM-DD", bad[i]);
        assert_string_equal(err.msg, want);
    }
    assert_counts_equal(count_all(fx->db), before);
    sr_mesh_release(&scan);
    sr_catalog_close(cat);
}

static void instance_symmetry_overrides_part(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    int64_t part = add_part(cat, "A", "a", NULL, NULL);
    sr_symmetry axial = {SR_SYM_AXIAL, 0, 0};
    sr_symmetry mirror = {SR_SYM_MIRROR, 0, 0};
    sr_symmetry glide = {SR_SYM_GLIDE, 0, 2.5};
    sr_symmetry none = {SR_SYM_NONE, 0, 0};
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_set_symmetry(cat, part, &axial, &err), SR_OK);
    int64_t plain = add_instance(cat, "A", NULL);
    int64_t over = add_instance(cat, "A", &mirror);
    sr_instance_info info;
    assert_int_equal(sr_catalog_instance_get(cat, plain, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_AXIAL);
    assert_int_equal(sr_catalog_instance_get(cat, over, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_MIRROR);

    /* the part's symmetry replaced: seen by the instance without override */
    assert_int_equal(sr_catalog_part_set_symmetry(cat, part, &glide, &err), SR_OK);
    assert_int_equal(sr_catalog_instance_get(cat, plain, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_GLIDE);
    assert_near(info.symmetry.shift_mm, 2.5, 0);
    assert_int_equal(sr_catalog_instance_get(cat, over, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_MIRROR);
    sr_part_info pinfo;
    assert_int_equal(sr_catalog_part_find(cat, "A", &pinfo, NULL), SR_OK);
    assert_int_equal(pinfo.symmetry.kind, SR_SYM_GLIDE);
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM symmetries"), 2);

    /* override removed: falls back to the part's */
    assert_int_equal(sr_catalog_instance_set_symmetry(cat, over, &none, &err), SR_OK);
    assert_int_equal(sr_catalog_instance_get(cat, over, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_GLIDE);
    /* override set again on an existing instance: axial 6-fold */
    sr_symmetry six = {SR_SYM_AXIAL, 6, 0};
    assert_int_equal(sr_catalog_instance_set_symmetry(cat, over, &six, &err), SR_OK);
    assert_int_equal(sr_catalog_instance_get(cat, over, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_AXIAL);
    assert_int_equal(info.symmetry.order, 6);

    /* errors change nothing */
    counts before = count_all(fx->db);
    assert_int_equal(sr_catalog_part_set_symmetry(cat, 99, &axial, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no part 99 in the catalogue");
    assert_int_equal(sr_catalog_instance_set_symmetry(cat, 99, &axial, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no instance 99 in the catalogue");
    sr_symmetry bad = {SR_SYM_AXIAL, 361, 0};
    assert_int_equal(sr_catalog_part_set_symmetry(cat, part, &bad, &err), SR_E_RANGE);
    assert_int_equal(sr_catalog_instance_set_symmetry(cat, over, &bad, &err), SR_E_RANGE);
    assert_counts_equal(count_all(fx->db), before);
    assert_int_equal(sr_catalog_instance_get(cat, over, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.order, 6);

    /* part symmetry cleared: the plain instance has none */
    assert_int_equal(sr_catalog_part_set_symmetry(cat, part, &none, &err), SR_OK);
    assert_int_equal(sr_catalog_instance_get(cat, plain, &info, NULL), SR_OK);
    assert_int_equal(info.symmetry.kind, SR_SYM_NONE);
    sr_catalog_close(cat);
}

/* ---- parameter sets ---- */

static void params_are_seeded_from_the_paper(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_params p;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_params_get(cat, "default", &p, &err), SR_OK);
    assert_string_equal(p.name, "default");
    assert_int_equal(p.layers, 320);
    assert_int_equal(p.sectors, 240);
    assert_near(p.gamma_axis, 0.95, 0);
    assert_near(p.gamma_plane, 0.95, 0);
    assert_near(p.delta_d, 0.05, 0);
    assert_near(p.min_depth_mm, 0.1, 0);
    assert_near(p.min_volume_mm3, 1.0, 0);
    assert_non_null(strstr(p.notes, "Table 2"));
    assert_int_equal(sr_params_check(&p, NULL), SR_OK);
    assert_int_equal(sr_catalog_params_get(cat, "coarse", &p, &err), SR_OK);
    assert_int_equal(p.layers, 80);
    assert_int_equal(p.sectors, 60);
    assert_int_equal(sr_catalog_params_get(cat, "MEDIUM", &p, &err), SR_OK);
    assert_int_equal(p.layers, 160);
    assert_int_equal(p.sectors, 120);
    assert_int_equal(sr_catalog_params_get(cat, "fine", &p, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no parameter set 'fine' in the catalogue");
    sr_catalog_close(cat);
}

/* The seeded 'default' row (sql/001_init.sql) and the core's table (params_default.h)
 * are two copies of one set: field by field equal, so neither can drift alone. */
static void seeded_default_set_equals_the_core_table(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_params seeded, core;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_params_get(cat, "default", &seeded, &err), SR_OK);
    sr_params_default(&core);
    assert_string_equal(seeded.name, core.name);
    assert_int_equal(seeded.layers, core.layers);
    assert_int_equal(seeded.sectors, core.sectors);
    assert_true(seeded.gamma_axis == core.gamma_axis);
    assert_true(seeded.gamma_plane == core.gamma_plane);
    assert_true(seeded.delta_d == core.delta_d);
    assert_true(seeded.min_depth_mm == core.min_depth_mm);
    assert_true(seeded.min_volume_mm3 == core.min_volume_mm3);
    /* notes differ on purpose: the row says where the values come from */
    assert_int_equal(sr_params_check(&core, NULL), SR_OK);
    sr_catalog_close(cat);
}

typedef struct names {
    int count;
    char name[8][64];
} names;

static int collect_params(const sr_params *p, void *user)
{
    names *n = user;
    if (n->count < 8)
        strcpy(n->name[n->count], p->name);
    n->count++;
    return 0;
}

static void params_put_inserts_and_replaces(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_params p;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_params_get(cat, "default", &p, &err), SR_OK);
    strcpy(p.name, "fine");
    p.layers = 640;
    p.sectors = 480;
    p.gamma_axis = 0.9;
    strcpy(p.notes, "twice the paper's finest");
    assert_int_equal(sr_catalog_params_put(cat, &p, &err), SR_OK);
    sr_params back;
    assert_int_equal(sr_catalog_params_get(cat, "fine", &back, &err), SR_OK);
    assert_string_equal(back.name, "fine");
    assert_int_equal(back.layers, 640);
    assert_int_equal(back.sectors, 480);
    assert_near(back.gamma_axis, 0.9, 0);
    assert_near(back.gamma_plane, p.gamma_plane, 0);
    assert_near(back.delta_d, p.delta_d, 0);
    assert_near(back.min_depth_mm, p.min_depth_mm, 0);
    assert_near(back.min_volume_mm3, p.min_volume_mm3, 0);
    assert_string_equal(back.notes, "twice the paper's finest");

    p.layers = 1000;
    strcpy(p.name, "FINE");
    assert_int_equal(sr_catalog_params_put(cat, &p, &err), SR_OK);
    assert_int_equal(sr_catalog_params_get(cat, "fine", &back, &err), SR_OK);
    assert_int_equal(back.layers, 1000);
    assert_string_equal(back.name, "FINE");

    names n = {0};
    assert_int_equal(sr_catalog_params_list(cat, collect_params, &n, &err), SR_OK);
    assert_int_equal(n.count, 4);
    assert_string_equal(n.name[0], "coarse");
    assert_string_equal(n.name[1], "default");
    assert_string_equal(n.name[2], "FINE");
    assert_string_equal(n.name[3], "medium");
    sr_catalog_close(cat);
}

static void params_check_names_every_bad_field(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_params good;
    assert_int_equal(sr_catalog_params_get(cat, "default", &good, NULL), SR_OK);
    int64_t rows = raw_int(fx->db, "SELECT count(*) FROM parameter_sets");
    struct {
        const char *field;
        double value;
        const char *want;
    } cases[] = {
        {"layers", 0, "bad layers 0: expected 1..100000"},
        {"layers", 100001, "bad layers 100001: expected 1..100000"},
        {"layers", -3, "bad layers -3: expected 1..100000"},
        {"sectors", 2, "bad sectors 2: expected 3..100000"},
        {"sectors", 100001, "bad sectors 100001: expected 3..100000"},
        {"gamma_axis", 0, "bad gamma_axis 0: expected a value in (0, 1]"},
        {"gamma_axis", 1.5, "bad gamma_axis 1.5: expected a value in (0, 1]"},
        {"gamma_axis", NAN, "bad gamma_axis nan: expected a value in (0, 1]"},
        {"gamma_plane", -0.5, "bad gamma_plane -0.5: expected a value in (0, 1]"},
        {"gamma_plane", 1.0000001, "bad gamma_plane 1: expected a value in (0, 1]"},
        {"delta_d", 0, "bad delta_d 0: expected a value in (0, 1]"},
        {"delta_d", INFINITY, "bad delta_d inf: expected a value in (0, 1]"},
        {"min_depth_mm", -0.1, "bad min_depth_mm -0.1: expected a finite value >= 0"},
        {"min_depth_mm", INFINITY, "bad min_depth_mm inf: expected a finite value >= 0"},
        {"min_volume_mm3", -1, "bad min_volume_mm3 -1: expected a finite value >= 0"},
        {"min_volume_mm3", NAN, "bad min_volume_mm3 nan: expected a finite value >= 0"},
        {"name", 0, "bad name: expected 1..63 bytes"},
        {"name", 1, "bad name: expected 1..63 bytes"},
        {"notes", 1, "bad notes: expected at most 255 bytes"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sr_params p = good;
        const char *f = cases[i].field;
        double v = cases[i].value;
        if (strcmp(f, "layers") == 0)
            p.layers = (int)v;
        else if (strcmp(f, "sectors") == 0)
            p.sectors = (int)v;
        else if (strcmp(f, "gamma_axis") == 0)
            p.gamma_axis = v;
        else if (strcmp(f, "gamma_plane") == 0)
            p.gamma_plane = v;
        else if (strcmp(f, "delta_d") == 0)
            p.delta_d = v;
        else if (strcmp(f, "min_depth_mm") == 0)
            p.min_depth_mm = v;
        else if (strcmp(f, "min_volume_mm3") == 0)
            p.min_volume_mm3 = v;
        else if (strcmp(f, "name") == 0 && v == 0)
            p.name[0] = '\0';
        else if (strcmp(f, "name") == 0)
            memset(p.name, 'a', sizeof p.name);      /* no terminating NUL */
        else
            memset(p.notes, 'a', sizeof p.notes);
        sr_err err = {{0}};
        assert_int_equal(sr_params_check(&p, &err), SR_E_RANGE);
        assert_string_equal(err.msg, cases[i].want);
        /* put checks first and writes nothing */
        assert_int_equal(sr_catalog_params_put(cat, &p, &err), SR_E_RANGE);
        assert_string_equal(err.msg, cases[i].want);
    }
    /* edges that are allowed */
    sr_params edge = good;
    edge.layers = 1;
    edge.sectors = 3;
    edge.gamma_axis = edge.gamma_plane = edge.delta_d = 1.0;
    edge.min_depth_mm = edge.min_volume_mm3 = 0;
    assert_int_equal(sr_params_check(&edge, NULL), SR_OK);
    edge.layers = edge.sectors = 100000;
    assert_int_equal(sr_params_check(&edge, NULL), SR_OK);

    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM parameter_sets"), rows);
    sr_params back;
    assert_int_equal(sr_catalog_params_get(cat, "default", &back, NULL), SR_OK);
    assert_memory_equal(&back, &good, sizeof good);
    sr_catalog_close(cat);
}

/* ---- sharing, locking, read-only, corruption ---- */

typedef struct writer_ctx {
    sr_catalog *writer;
    int rows;
    sr_status add_status;
} writer_ctx;

static int write_during_read(const sr_part_info *p, void *user)
{
    writer_ctx *w = user;
    (void)p;
    if (w->rows++ == 0) {
        sr_part_new np = {0};
        np.number = "NEW";
        np.name = "added while the other handle reads";
        w->add_status = sr_catalog_part_add(w->writer, &np, NULL, NULL);
    }
    return 0;
}

static void two_handles_write_while_reading(void **state)
{
    fixture *fx = *state;
    sr_catalog *a = open_new(fx), *b = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, 0, &b, &err), SR_OK);
    add_part(a, "P-1", "one", NULL, NULL);
    add_part(a, "P-2", "two", NULL, NULL);

    /* b reads (a snapshot); a writes in the middle of b's read */
    writer_ctx w = {a, 0, SR_E_INTERNAL};
    assert_int_equal(sr_catalog_part_list(b, NULL, write_during_read, &w, &err), SR_OK);
    assert_int_equal(w.add_status, SR_OK);
    assert_int_equal(w.rows, 2);   /* b's read did not see the new part */
    sr_part_info info;
    assert_int_equal(sr_catalog_part_find(b, "NEW", &info, &err), SR_OK);   /* now it does */

    /* and the other way round */
    add_part(b, "P-3", "three", NULL, NULL);
    assert_int_equal(sr_catalog_part_find(a, "P-3", &info, &err), SR_OK);
    sr_catalog_close(a);
    sr_catalog_close(b);
}

static void busy_writer_fails_cleanly(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_material(cat, "steel");
    sqlite3_busy_timeout(cat->db, 50);   /* the real 5 s is too long for a unit test */
    sqlite3 *other = NULL;
    assert_int_equal(sqlite3_open(fx->db, &other), SQLITE_OK);
    assert_int_equal(sqlite3_exec(other, "BEGIN IMMEDIATE", NULL, NULL, NULL), SQLITE_OK);

    counts before = count_all(fx->db);
    sr_err err = {{0}};
    sr_part_new p = {.number = "P-1", .name = "plate", .material = "steel"};
    assert_int_equal(sr_catalog_part_add(cat, &p, NULL, &err), SR_E_DB);
    assert_msg(&err, "the catalogue is busy");
    sr_part_info info;
    assert_int_equal(sr_catalog_params_get(cat, "default", &(sr_params){0}, NULL), SR_OK);  /* reads go on */

    assert_int_equal(sqlite3_exec(other, "ROLLBACK", NULL, NULL, NULL), SQLITE_OK);
    assert_int_equal(sqlite3_close(other), SQLITE_OK);
    assert_counts_equal(count_all(fx->db), before);
    assert_int_equal(sr_catalog_part_add(cat, &p, NULL, &err), SR_OK);
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &info, &err), SR_OK);
    sr_catalog_close(cat);
}

static void readonly_handle_reads_but_never_writes(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "P-1", "plate", NULL, NULL);
    sr_catalog_close(cat);
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(fx->db, SR_CATALOG_READONLY, &cat, &err), SR_OK);
    sr_part_info info;
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &info, &err), SR_OK);
    counts before = count_all(fx->db);
    sr_part_new p = {.number = "P-2", .name = "x"};
    assert_int_equal(sr_catalog_part_add(cat, &p, NULL, &err), SR_E_DB);
    char want[256];
    snprintf(want, sizeof want, "cannot write to '%s': the catalogue is open read-only", fx->db);
    assert_string_equal(err.msg, want);
    sr_params params;
    assert_int_equal(sr_catalog_params_get(cat, "default", &params, NULL), SR_OK);
    assert_int_equal(sr_catalog_params_put(cat, &params, &err), SR_E_DB);
    assert_counts_equal(count_all(fx->db), before);
    sr_catalog_close(cat);
}

static void corrupt_mesh_blob_is_reported_on_load(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_mesh m;
    make_box(&m, 0);
    int64_t part = add_part(cat, "P-1", "plate", NULL, &m);
    sr_mesh_release(&m);
    sr_mesh back = {0};
    sr_err err = {{0}};
    char want[256];

    /* same length (the schema's CHECK holds), zeroed bytes: bad magic */
    assert_int_equal(cat_exec_rc(cat, "UPDATE meshes SET data = zeroblob(length(data))"), SQLITE_OK);
    assert_int_equal(sr_catalog_part_mesh(cat, part, &back, &err), SR_E_FORMAT);
    snprintf(want, sizeof want, "cannot load mesh 1 from '%s': mesh blob has a bad magic (expected 'SRM1')",
             fx->db);
    assert_string_equal(err.msg, want);
    assert_null(back.xyz);

    /* a row whose counts disagree with its (valid) blob: only possible by hand */
    make_box(&m, 0);
    int64_t part2 = add_part(cat, "P-2", "plate", NULL, &m);
    sr_mesh_release(&m);
    assert_int_equal(cat_exec_rc(cat, "PRAGMA ignore_check_constraints = ON;"
                                      " UPDATE meshes SET vertex_count = 9 WHERE id = 2;"
                                      " PRAGMA ignore_check_constraints = OFF"),
                     SQLITE_OK);
    assert_int_equal(sr_catalog_part_mesh(cat, part2, &back, &err), SR_E_FORMAT);
    assert_msg(&err, "the row says 9 vertices and 12 triangles, its blob holds 8 and 12");
    assert_int_equal(cat_exec_rc(cat, "UPDATE meshes SET format_version = 2, vertex_count = 8"
                                      " WHERE id = 2"),
                     SQLITE_OK);
    assert_int_equal(sr_catalog_mesh_load(cat, 2, &back, &err), SR_E_UNSUPPORTED);
    assert_msg(&err, "blob format version 2, this symrec reads 1: upgrade symrec");
    sr_catalog_close(cat);
}

/* ---- corrections: materials, part and instance set/remove, backup, check ---- */

static void part_add_refuses_an_unknown_material_and_writes_nothing(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    counts before = count_all(fx->db);
    sr_mesh m;
    make_box(&m, 0);
    sr_part_new p = {.number = "P-1", .name = "plate", .material = "unobtainium", .mesh = &m};
    int64_t id = -5;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_add(cat, &p, &id, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no material 'unobtainium' in the catalogue");
    assert_int_equal(id, -5);
    assert_counts_equal(count_all(fx->db), before); /* no material row, no mesh */
    p.material = "c45";                             /* seeded, any case */
    assert_int_equal(sr_catalog_part_add(cat, &p, &id, &err), SR_OK);
    sr_part_info info;
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &info, &err), SR_OK);
    assert_string_equal(info.material, "C45");
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM materials"), before.materials);
    sr_mesh_release(&m);
    sr_catalog_close(cat);
}

static void materials_are_added_with_a_density_and_corrected(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_err err = {{0}};
    sr_material_new steel = {
        .name = "S235", .density_g_cm3 = 7.85, .family = "steel", .notes = "EN 10025-2"};
    int64_t id = 0;
    assert_int_equal(sr_catalog_material_add(cat, &steel, &id, &err), SR_OK);
    assert_true(id > 0);
    sr_material m;
    assert_int_equal(sr_catalog_material_get(cat, "s235", &m, &err), SR_OK);
    assert_string_equal(m.name, "S235");
    assert_true(m.density_g_cm3 == 7.85);
    assert_string_equal(m.family, "steel");
    assert_string_equal(m.notes, "EN 10025-2");

    /* refusals, each naming the field; nothing written */
    int64_t materials = raw_int(fx->db, "SELECT count(*) FROM materials");
    sr_material_new again = {.name = "s235", .density_g_cm3 = 7.8};
    assert_int_equal(sr_catalog_material_add(cat, &again, NULL, &err), SR_E_EXISTS);
    assert_string_equal(err.msg, "material 's235' is already in the catalogue");
    sr_material_new no_density = {.name = "X", .density_g_cm3 = NAN};
    assert_int_equal(sr_catalog_material_add(cat, &no_density, NULL, &err), SR_E_RANGE);
    assert_msg(&err, "bad density of material 'X'");
    sr_material_new zero = {.name = "X", .density_g_cm3 = 0};
    assert_int_equal(sr_catalog_material_add(cat, &zero, NULL, &err), SR_E_RANGE);
    sr_material_new wood = {.name = "X", .density_g_cm3 = 0.7, .family = "wood"};
    assert_int_equal(sr_catalog_material_add(cat, &wood, NULL, &err), SR_E_RANGE);
    assert_msg(&err, "bad family 'wood'");
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM materials"), materials);

    /* a material an older symrec created without a density gets one */
    raw_exec(fx->db, "INSERT INTO materials (name) VALUES ('steel')");
    assert_int_equal(sr_catalog_material_get(cat, "steel", &m, &err), SR_OK);
    assert_true(isnan(m.density_g_cm3));
    sr_material_new fix = {.density_g_cm3 = 7.8, .family = "steel"};
    assert_int_equal(sr_catalog_material_set(cat, "STEEL", &fix, &err), SR_OK);
    assert_int_equal(sr_catalog_material_get(cat, "steel", &m, &err), SR_OK);
    assert_true(m.density_g_cm3 == 7.8);
    assert_string_equal(m.family, "steel");
    sr_material_new clear = {.density_g_cm3 = NAN, .family = "", .notes = "plain"};
    assert_int_equal(sr_catalog_material_set(cat, "steel", &clear, &err), SR_OK);
    assert_int_equal(sr_catalog_material_get(cat, "steel", &m, &err), SR_OK);
    assert_true(m.density_g_cm3 == 7.8); /* kept */
    assert_string_equal(m.family, "");
    assert_string_equal(m.notes, "plain");
    sr_material_new nothing = {.density_g_cm3 = NAN};
    assert_int_equal(sr_catalog_material_set(cat, "steel", &nothing, &err), SR_E_INVALID);
    assert_int_equal(sr_catalog_material_set(cat, "nope", &fix, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no material 'nope' in the catalogue");
    sr_catalog_close(cat);
}

static void part_set_changes_only_what_it_is_given(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_mesh m;
    make_box(&m, 0);
    int64_t id = add_part(cat, "P-1", "plate", "C45", &m);
    add_part(cat, "P-2", "other", NULL, NULL);
    sr_err err = {{0}};
    sr_part_change ch = {.name = "base plate",
                         .material = "42CrMo4",
                         .notes = "fixed",
                         .set_symmetry = true,
                         .symmetry = {SR_SYM_AXIAL, 6, 0}};
    char key[32];
    snprintf(key, sizeof key, "%lld", (long long)id); /* by id */
    assert_int_equal(sr_catalog_part_set(cat, key, &ch, &err), SR_OK);
    sr_part_info p;
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &p, &err), SR_OK);
    assert_string_equal(p.name, "base plate");
    assert_string_equal(p.material, "42CrMo4");
    assert_string_equal(p.notes, "fixed");
    assert_int_equal(p.symmetry.kind, SR_SYM_AXIAL);
    assert_int_equal(p.symmetry.order, 6);
    assert_true(p.mesh_id > 0);

    sr_part_change renumber = {.number = "P-1A", .set_symmetry = true}; /* kind NONE clears */
    assert_int_equal(sr_catalog_part_set(cat, "P-1", &renumber, &err), SR_OK);
    assert_int_equal(sr_catalog_part_find(cat, "P-1A", &p, &err), SR_OK);
    assert_int_equal(p.id, id);
    assert_string_equal(p.name, "base plate"); /* kept */
    assert_int_equal(p.symmetry.kind, SR_SYM_NONE);
    sr_part_change recase = {.number = "p-1a"}; /* its own number in another case */
    assert_int_equal(sr_catalog_part_set(cat, "P-1A", &recase, &err), SR_OK);

    /* refusals change nothing */
    counts before = count_all(fx->db);
    sr_part_change taken = {.number = "p-2"};
    assert_int_equal(sr_catalog_part_set(cat, "p-1a", &taken, &err), SR_E_EXISTS);
    assert_string_equal(err.msg, "part 'p-2' is already in the catalogue");
    sr_part_change unknown = {.material = "unobtainium", .name = "x"};
    assert_int_equal(sr_catalog_part_set(cat, "p-1a", &unknown, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no material 'unobtainium' in the catalogue");
    assert_int_equal(sr_catalog_part_set(cat, "nope", &ch, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no part 'nope' in the catalogue");
    sr_part_change nothing = {0};
    assert_int_equal(sr_catalog_part_set(cat, "p-1a", &nothing, &err), SR_E_INVALID);
    sr_part_change empty_name = {.name = ""};
    assert_int_equal(sr_catalog_part_set(cat, "p-1a", &empty_name, &err), SR_E_RANGE);
    sr_part_change bad_sym = {.set_symmetry = true, .symmetry = {SR_SYM_AXIAL, 1, 0}};
    assert_int_equal(sr_catalog_part_set(cat, "p-1a", &bad_sym, &err), SR_E_RANGE);
    assert_counts_equal(count_all(fx->db), before);
    assert_int_equal(sr_catalog_part_find(cat, "p-1a", &p, &err), SR_OK);
    assert_string_equal(p.name, "base plate");
    assert_string_equal(p.material, "42CrMo4");
    sr_mesh_release(&m);
    sr_catalog_close(cat);
}

static void instance_set_changes_serial_date_and_notes(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "P-1", "plate", NULL, NULL);
    int64_t id = add_instance(cat, "P-1", NULL);
    sr_err err = {{0}};
    sr_instance_change ch = {.serial = "SN-9", .received = "2024-02-29", .notes = "dent"};
    assert_int_equal(sr_catalog_instance_set(cat, id, &ch, &err), SR_OK);
    sr_instance_info in;
    assert_int_equal(sr_catalog_instance_get(cat, id, &in, &err), SR_OK);
    assert_string_equal(in.serial, "SN-9");
    assert_string_equal(in.received, "2024-02-29");
    assert_string_equal(in.notes, "dent");
    sr_instance_change clear = {.serial = "", .received = ""};
    assert_int_equal(sr_catalog_instance_set(cat, id, &clear, &err), SR_OK);
    assert_int_equal(sr_catalog_instance_get(cat, id, &in, &err), SR_OK);
    assert_string_equal(in.serial, "");
    assert_string_equal(in.received, "");
    assert_string_equal(in.notes, "dent"); /* kept */
    assert_int_equal(raw_int(fx->db, "SELECT count(*) FROM instances WHERE serial IS NULL"
                                     " AND received IS NULL"),
                     1);

    sr_instance_change bad_date = {.received = "2023-02-29"};
    assert_int_equal(sr_catalog_instance_set(cat, id, &bad_date, &err), SR_E_RANGE);
    assert_string_equal(err.msg, "bad received date '2023-02-29': expected YYYY-MM-DD");
    assert_int_equal(sr_catalog_instance_set(cat, id + 1, &ch, &err), SR_E_NOTFOUND);
    assert_string_equal(err.msg, "no instance 2 in the catalogue");
    sr_instance_change nothing = {0};
    assert_int_equal(sr_catalog_instance_set(cat, id, &nothing, &err), SR_E_INVALID);
    assert_int_equal(sr_catalog_instance_get(cat, id, &in, &err), SR_OK);
    assert_string_equal(in.received, "");
    sr_catalog_close(cat);
}

static void part_remove_takes_its_mesh_and_symmetry_and_refuses_with_instances(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    sr_mesh m;
    make_box(&m, 0);
    add_part(cat, "P-1", "plate", "C45", &m);
    add_part(cat, "P-2", "plate", NULL, &m);
    sr_symmetry axial = {SR_SYM_AXIAL, 0, 0};
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_part_set_symmetry(cat, 1, &axial, &err), SR_OK);
    int64_t inst = add_instance(cat, "P-2", &axial);
    counts before = count_all(fx->db);

    sr_removal r = {-1, -1, -1};
    assert_int_equal(sr_catalog_part_remove(cat, "P-2", 0, &r, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "part 'P-2' has 1 instance and 0 runs; nothing removed "
                                 "(--with-runs removes them too)");
    assert_int_equal(sr_catalog_instance_remove(cat, inst + 1, 0, &r, &err), SR_E_NOTFOUND);
    assert_int_equal(sr_catalog_part_remove(cat, "nope", 0, &r, &err), SR_E_NOTFOUND);
    assert_counts_equal(count_all(fx->db), before);
    assert_int_equal(r.runs, -1);

    assert_int_equal(sr_catalog_part_remove(cat, "P-1", 0, &r, &err), SR_OK);
    assert_int_equal(r.instances, 0);
    assert_int_equal(r.runs, 0);
    assert_int_equal(r.meshes, 1);
    /* an instance without runs goes without the flag, with its scan and override */
    assert_int_equal(sr_catalog_instance_remove(cat, inst, 0, &r, &err), SR_OK);
    assert_int_equal(r.meshes, 1);
    counts after = count_all(fx->db);
    assert_int_equal(after.parts, before.parts - 1);
    assert_int_equal(after.instances, before.instances - 1);
    assert_int_equal(after.meshes, before.meshes - 2);
    assert_int_equal(after.symmetries, before.symmetries - 2);
    assert_int_equal(after.materials, before.materials); /* a material stays */
    sr_part_info p;
    assert_int_equal(sr_catalog_part_find(cat, "P-1", &p, &err), SR_E_NOTFOUND);
    sr_mesh_release(&m);
    sr_catalog_close(cat);
}

static void backup_copies_the_catalogue_and_refuses_an_existing_file(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "P-1", "plate", "C45", NULL);
    char copy[160];
    snprintf(copy, sizeof copy, "%s/copy.db", fx->dir);
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_backup(cat, copy, false, &err), SR_OK);
    assert_int_equal(raw_int(copy, "SELECT count(*) FROM parts WHERE number = 'P-1'"), 1);
    assert_int_equal(raw_int(copy, "PRAGMA application_id"), SR_CATALOG_APP_ID);

    /* an existing file is refused and left alone; --force replaces it */
    add_part(cat, "P-2", "plate", NULL, NULL);
    size_t size;
    unsigned char *before = read_file(copy, &size);
    assert_int_equal(sr_catalog_backup(cat, copy, false, &err), SR_E_EXISTS);
    char want[256];
    snprintf(want, sizeof want, "'%s' already exists (replace it with --force)", copy);
    assert_string_equal(err.msg, want);
    assert_file_unchanged(copy, before, size);
    free(before);
    assert_int_equal(sr_catalog_backup(cat, copy, true, &err), SR_OK);
    assert_int_equal(raw_int(copy, "SELECT count(*) FROM parts"), 2);
    assert_int_equal(sr_catalog_backup(cat, fx->db, true, &err), SR_E_INVALID);
    assert_msg(&err, "is the catalogue itself");
    sr_catalog_close(cat);

    /* the copy opens as a catalogue, and a read-only handle can be backed up */
    sr_catalog *ro = NULL;
    assert_int_equal(sr_catalog_open(copy, SR_CATALOG_READONLY, &ro, &err), SR_OK);
    sr_part_info p;
    assert_int_equal(sr_catalog_part_find(ro, "P-2", &p, &err), SR_OK);
    char second[160];
    snprintf(second, sizeof second, "%s/second.db", fx->dir);
    assert_int_equal(sr_catalog_backup(ro, second, false, &err), SR_OK);
    sr_catalog_close(ro);
    assert_int_equal(raw_int(second, "SELECT count(*) FROM parts"), 2);
}

static int count_problem(const char *what, void *user)
{
    (void)what;
    (*(int *)user)++;
    return 0;
}

static void check_reports_a_broken_foreign_key(void **state)
{
    fixture *fx = *state;
    sr_catalog *cat = open_new(fx);
    add_part(cat, "P-1", "plate", "C45", NULL);
    sr_err err = {{0}};
    int problems = 0;
    sr_check_info info;
    assert_int_equal(sr_catalog_check(cat, count_problem, &problems, &info, &err), SR_OK);
    assert_int_equal(problems, 0);
    assert_int_equal(info.application_id, SR_CATALOG_APP_ID);
    assert_int_equal(info.schema_version, sr_catalog_schema_latest());
    assert_int_equal(info.no_density, 0);
    /* raw_exec's connection has foreign keys off, as a plain sqlite3 shell */
    raw_exec(fx->db, "UPDATE parts SET material_id = 999");
    raw_exec(fx->db, "INSERT INTO materials (name) VALUES ('steel')"); /* noted, no problem */
    assert_int_equal(sr_catalog_check(cat, count_problem, &problems, &info, &err), SR_OK);
    assert_int_equal(problems, 1);
    assert_int_equal(info.problems, 1);
    assert_int_equal(info.no_density, 1);
    sr_catalog_close(cat);
}

int main(void)
{
#define T(name) cmocka_unit_test_setup_teardown(name, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(create_sets_version_app_id_and_all_tables),
        T(reopen_is_idempotent),
        T(missing_file_without_create_is_refused),
        T(every_table_and_column_has_a_comment),
        T(garbage_file_is_refused_untouched),
        T(other_application_id_is_refused_untouched),
        T(other_program_database_without_app_id_is_refused),
        T(empty_file_needs_create),
        T(newer_schema_is_refused_untouched),
        T(failing_migration_rolls_back),
        T(migration_must_set_its_version),
        T(migration_leaving_broken_foreign_key_rolls_back),
        T(migration_upgrades_older_catalogue),
        T(migration_005_gives_older_meshes_mm),
        T(migration_010_records_how_the_nominal_was_measured),
        T(gap_in_migrations_is_refused),
        T(schema_refuses_inconsistent_rows),
        T(part_with_mesh_round_trips_bit_identical),
        T(part_without_mesh_has_no_mesh),
        T(part_find_by_number_then_id),
        T(part_list_filters_by_name_number_material),
        T(duplicate_part_number_changes_nothing),
        T(part_add_refuses_bad_fields),
        T(late_failure_rolls_back_the_whole_add),
        T(instance_round_trips),
        T(instance_list_by_part),
        T(instance_of_unknown_part_writes_nothing),
        T(instance_with_invalid_mesh_writes_nothing),
        T(instance_refuses_bad_received_date),
        T(instance_symmetry_overrides_part),
        T(params_are_seeded_from_the_paper),
        T(seeded_default_set_equals_the_core_table),
        T(params_put_inserts_and_replaces),
        T(params_check_names_every_bad_field),
        T(two_handles_write_while_reading),
        T(busy_writer_fails_cleanly),
        T(part_add_refuses_an_unknown_material_and_writes_nothing),
        T(materials_are_added_with_a_density_and_corrected),
        T(part_set_changes_only_what_it_is_given),
        T(instance_set_changes_serial_date_and_notes),
        T(part_remove_takes_its_mesh_and_symmetry_and_refuses_with_instances),
        T(backup_copies_the_catalogue_and_refuses_an_existing_file),
        T(check_reports_a_broken_foreign_key),
        T(readonly_handle_reads_but_never_writes),
        T(corrupt_mesh_blob_is_reported_on_load),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
