/*
 * cmd_fixtures.c: `symrec fixtures --out DIR`: writes each demo part's intact and
 * damaged mesh as binary STL (<number>_intact.stl, <number>_damaged.stl) and
 * volumes.json with their volumes: the project's own small test meshes with known
 * answers, made by its own code (`make fixtures`).
 *
 * The volumes are measured on the files as written (read back), not on the meshes in
 * memory: binary STL stores float32 coordinates, and the numbers in volumes.json must
 * be the ones a reader of the files gets.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"
#include "mesh/shapes.h"

static const char usage[] =
    "usage: symrec fixtures --out DIR [--json]\n"
    "\n"
    "Writes each built-in demo part's intact and damaged mesh as binary STL into DIR\n"
    "(created if missing): <number>_intact.stl and <number>_damaged.stl, and\n"
    "volumes.json with each part's intact, damaged and missing volume in mm³, measured\n"
    "on the files as written. Prints the same volumes as a table.\n"
    "\n"
    "  --out DIR   the folder to write into\n"
    "  --json      print volumes.json's object instead of the table\n";

/* mkdir -p: creates dir and its missing parents. */
static bool make_dirs(const char *dir, sr_err *err)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path) {
        sr_err_set(err, SR_E_RANGE, "cannot create '%s': path too long", dir);
        return false;
    }
    for (char *p = path + 1;; p++) {
        if (*p != '/' && *p != '\0')
            continue;
        char c = *p;
        *p = '\0';
        struct stat st;
        if (mkdir(path, 0777) != 0 && errno != EEXIST) {
            sr_err_set(err, SR_E_IO, "cannot create '%s': %s", path, strerror(errno));
            return false;
        }
        if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
            sr_err_set(err, SR_E_IO, "cannot create '%s': not a directory", path);
            return false;
        }
        *p = c;
        if (c == '\0')
            return true;
    }
}

/* A part number as a file name: anything but [A-Za-z0-9._-] becomes '_'. */
static void file_stem(const char *number, char *out, size_t size)
{
    size_t n = 0;
    for (const char *p = number; *p && n + 1 < size; p++) {
        char c = *p;
        bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  c == '.' || c == '-' || c == '_';
        out[n++] = ok ? c : '_';
    }
    out[n] = '\0';
}

typedef struct fixture {
    const sr_demo_part *part;
    char intact_file[160], damaged_file[160];
    double intact_mm3, damaged_mm3;
    size_t intact_tris, damaged_tris;
} fixture;

/* Writes `mesh` to dir/name and measures the volume of what landed in the file. */
static sr_status write_measured(const char *dir, const char *name, const sr_mesh *mesh,
                                double *volume, size_t *tris, sr_err *err)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path)
        return sr_err_set(err, SR_E_RANGE, "cannot write '%s/%s': path too long", dir, name);
    sr_status st = sr_mesh_write(path, mesh, NULL, err);
    if (st != SR_OK)
        return st;
    sr_mesh back;
    sr_mesh_init(&back);
    st = sr_mesh_read(path, &back, err);
    if (st != SR_OK)
        return st;
    *volume = sr_mesh_volume(&back);
    *tris = back.tri_count;
    sr_mesh_release(&back);
    return SR_OK;
}

static sr_status make_fixture(const char *dir, size_t i, fixture *fx, sr_err *err)
{
    fx->part = sr_demo_part_get(i);
    char stem[128];
    file_stem(fx->part->number, stem, sizeof stem);
    snprintf(fx->intact_file, sizeof fx->intact_file, "%s_intact.stl", stem);
    snprintf(fx->damaged_file, sizeof fx->damaged_file, "%s_damaged.stl", stem);
    sr_mesh intact, damaged;
    sr_mesh_init(&intact);
    sr_mesh_init(&damaged);
    sr_status st = sr_demo_part_build(i, &intact, &damaged, err);
    if (st == SR_OK)
        st = write_measured(dir, fx->intact_file, &intact, &fx->intact_mm3, &fx->intact_tris,
                            err);
    if (st == SR_OK)
        st = write_measured(dir, fx->damaged_file, &damaged, &fx->damaged_mm3,
                            &fx->damaged_tris, err);
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);
    return st;
}

/* The volumes as one JSON object: volumes.json and `fixtures --json`. */
static void json_fixtures(json_out *jp, const fixture *fx, size_t count)
{
    json_object_begin(jp);
    json_key(jp, "units");
    json_string(jp, "mm3");
    json_key(jp, "note");
    json_string(jp, "volumes of the binary STL files as written; missing = intact - damaged");
    json_key(jp, "parts");
    json_array_begin(jp);
    for (size_t i = 0; i < count; i++) {
        json_object_begin(jp);
        json_key(jp, "number");
        json_string(jp, fx[i].part->number);
        json_key(jp, "name");
        json_string(jp, fx[i].part->name);
        json_key(jp, "intact_file");
        json_string(jp, fx[i].intact_file);
        json_key(jp, "damaged_file");
        json_string(jp, fx[i].damaged_file);
        json_key(jp, "intact_triangles");
        json_int(jp, (int64_t)fx[i].intact_tris);
        json_key(jp, "damaged_triangles");
        json_int(jp, (int64_t)fx[i].damaged_tris);
        json_key(jp, "intact_mm3");
        json_number(jp, fx[i].intact_mm3);
        json_key(jp, "damaged_mm3");
        json_number(jp, fx[i].damaged_mm3);
        json_key(jp, "missing_mm3");
        json_number(jp, fx[i].intact_mm3 - fx[i].damaged_mm3);
        json_object_end(jp);
    }
    json_array_end(jp);
    json_object_end(jp);
}

/* Writes volumes.json through a temporary file renamed into place. */
static sr_status write_volumes(const char *dir, const fixture *fx, size_t count, sr_err *err)
{
    char path[4096], tmp[4200];
    if (snprintf(path, sizeof path, "%s/volumes.json", dir) >= (int)sizeof path)
        return sr_err_set(err, SR_E_RANGE, "cannot write '%s/volumes.json': path too long", dir);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return sr_err_set(err, SR_E_IO, "cannot write '%s': %s", tmp, strerror(errno));
    json_out j;
    json_init(&j, f);
    json_fixtures(&j, fx, count);
    sr_status st = json_end(&j, err);
    if (st != SR_OK) {
        fclose(f);
        remove(tmp);
        return st;
    }
    bool ok = fflush(f) == 0 && !ferror(f) && fsync(fileno(f)) == 0;
    int saved = errno;
    if (fclose(f) != 0 && ok) {
        ok = false;
        saved = errno;
    }
    if (ok && rename(tmp, path) != 0) {
        ok = false;
        saved = errno;
    }
    if (!ok) {
        remove(tmp);
        return sr_err_set(err, SR_E_IO, "cannot write '%s': %s", path, strerror(saved));
    }
    return SR_OK;
}

int cmd_fixtures(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--out", &out, NULL}, {"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"fixtures", usage, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, NULL, NULL, &rc))
        return rc;
    if (!out || !out[0])
        return cli_usage_error("'fixtures' needs --out DIR (see 'symrec fixtures --help')");

    sr_err err;
    sr_err_clear(&err);
    if (!make_dirs(out, &err))
        return cli_fail(SR_E_IO, &err);
    size_t count = sr_demo_part_count();
    fixture *fx = calloc(count ? count : 1, sizeof *fx);
    if (!fx)
        return cli_error("out of memory");
    sr_status st = SR_OK;
    for (size_t i = 0; i < count && st == SR_OK; i++) {
        st = make_fixture(out, i, &fx[i], &err);
        if (st == SR_OK)
            cli_note("fixtures: wrote %s/%s and %s", out, fx[i].intact_file,
                     fx[i].damaged_file);
    }
    if (st == SR_OK)
        st = write_volumes(out, fx, count, &err);
    if (st != SR_OK) {
        free(fx);
        return cli_fail(st, &err);
    }
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_fixtures(&j, fx, count);
        free(fx);
        return json_finish(&j);
    }
    static const char *const headers[] = {"number", "intact mm³", "damaged mm³",
                                          "missing mm³", "missing"};
    static const bool right[] = {false, true, true, true, true};
    cli_table t;
    cli_table_init(&t, 5, headers, right);
    for (size_t i = 0; i < count; i++) {
        double missing = fx[i].intact_mm3 - fx[i].damaged_mm3;
        cli_table_cell(&t, "%s", fx[i].part->number);
        cli_table_cell(&t, "%.3f", fx[i].intact_mm3);
        cli_table_cell(&t, "%.3f", fx[i].damaged_mm3);
        cli_table_cell(&t, "%.3f", missing);
        cli_table_cell(&t, "%.2f %%", fx[i].intact_mm3 > 0 ? 100 * missing / fx[i].intact_mm3 : 0);
    }
    bool ok = cli_table_print(&t, stdout, 0);
    if (ok)
        printf("wrote %zu meshes and volumes.json to '%s'\n", 2 * count, out);
    cli_table_release(&t);
    free(fx);
    return ok ? CLI_OK : CLI_FAIL;
}
