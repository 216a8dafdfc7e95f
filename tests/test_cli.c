/*
 * test_cli.c: golden tests of the symrec command line. Each case runs the binary
 * ($SYMREC_BIN, optionally under $SYMREC_WRAP such as valgrind) on a catalogue in a
 * fresh temporary folder and checks the exact exit code and what it printed: results
 * on stdout (--json parsed by a small strict JSON reader below), each diagnostic one
 * line on stderr ("symrec: error: ..." exit 1, "symrec: usage: ..." exit 2), and that
 * a failed command leaves the catalogue as it was. Mesh files are made inside the
 * tests with the library (sr_shape_cylinder + sr_mesh_write) and exports are read back
 * with sr_mesh_read and compared with what the catalogue stored.
 *
 * Run from the repository root (the default binary is build/debug/symrec).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sqlite3.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog.h"
#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/json_query.h"
#include "support/run_cmd.h"
#include "support/test_select.h"
#include "base/version.h"

#define PI 3.14159265358979323846

/* ------------------------------------------------------------------------------------
 * Temporary folder per test
 * ---------------------------------------------------------------------------------- */

typedef struct env {
    char dir[64];           /* /tmp/symrec-test-XXXXXX */
    char db[128];           /* dir/cat.db */
    char cyl[128];          /* dir/cyl.stl: cylinder r 10, z 0..20, 16 sides */
    char box[128];          /* dir/box.stl: box 0..10 x 0..20 x 0..30 */
} env;

static void rm_rf(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        if (d) {
            struct dirent *e;
            while ((e = readdir(d)) != NULL) {
                if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                    continue;
                char sub[1024];
                snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
                rm_rf(sub);
            }
            closedir(d);
        }
        rmdir(path);
    } else {
        unlink(path);
    }
}

static void path_in(const env *e, const char *name, char *out, size_t size)
{
    int n = snprintf(out, size, "%s/%s", e->dir, name);
    assert_true(n > 0 && (size_t)n < size);
}

static void write_bytes(const char *path, const void *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    if (len)
        assert_int_equal(fwrite(data, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *data = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 4096 + 1 > cap) {
            cap = cap ? 2 * cap : 8192;
            char *d = realloc(data, cap);
            assert_non_null(d);
            data = d;
        }
        size_t n = fread(data + len, 1, 4096, f);
        len += n;
        if (n == 0)
            break;
    }
    fclose(f);
    data[len] = '\0';
    return data;
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

static void write_mesh_file(const char *path, const sr_mesh *mesh)
{
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_mesh_write(path, mesh, NULL, &err);
    if (st != SR_OK)
        fail_msg("cannot write %s: %s", path, err.msg);
}

static int setup(void **state)
{
    env *e = calloc(1, sizeof *e);
    assert_non_null(e);
    strcpy(e->dir, "/tmp/symrec-test-XXXXXX");
    assert_non_null(mkdtemp(e->dir));
    path_in(e, "cat.db", e->db, sizeof e->db);
    path_in(e, "cyl.stl", e->cyl, sizeof e->cyl);
    path_in(e, "box.stl", e->box, sizeof e->box);
    sr_mesh m;
    sr_mesh_init(&m);
    assert_int_equal(sr_shape_cylinder(10.0, 0.0, 20.0, 16, &m, NULL), SR_OK);
    write_mesh_file(e->cyl, &m);
    sr_mesh_release(&m);
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    write_mesh_file(e->box, &m);
    sr_mesh_release(&m);
    *state = e;
    return 0;
}

static int teardown(void **state)
{
    env *e = *state;
    rm_rf(e->dir);
    free(e);
    return 0;
}

/* Volume of the 16-sided cylinder r 10 x 20 (a regular prism). */
static double cyl_volume(void)
{
    return 16 / 2.0 * 100.0 * sin(2 * PI / 16) * 20.0;
}

/* ------------------------------------------------------------------------------------
 * Running symrec
 * ---------------------------------------------------------------------------------- */

typedef struct result {
    int code;
    char *out;
    char *err;
} result;

static void result_free(result *r)
{
    free(r->out);
    free(r->err);
    r->out = r->err = NULL;
}

/* Runs symrec with the NULL-terminated words after the binary; under $SYMREC_WRAP
 * unless `native`. */
static void run_words_how(result *r, const char *const *words, int native)
{
    const char *argv[64];
    size_t n = 0;
    argv[n++] = sr_test_bin();
    for (size_t i = 0; words[i]; i++) {
        assert_true(n < 63);
        argv[n++] = words[i];
    }
    argv[n] = NULL;
    r->code = native ? sr_test_run_native(argv, NULL, &r->out, &r->err)
                     : sr_test_run(argv, NULL, &r->out, &r->err);
    if (r->code < 0)
        fail_msg("cannot run %s (set SYMREC_BIN)", argv[0]);
}

static void run_words(result *r, const char *const *words)
{
    run_words_how(r, words, 0);
}

#define RUN(r, ...)                                                                       \
    do {                                                                                  \
        const char *const words_[] = {__VA_ARGS__, NULL};                                 \
        run_words((r), words_);                                                           \
    } while (0)

/* RUN outside $SYMREC_WRAP: set-up only (filling a catalogue with runs), never the
 * command a test is about. */
#define RUN_NATIVE(r, ...)                                                                \
    do {                                                                                  \
        const char *const words_[] = {__VA_ARGS__, NULL};                                 \
        run_words_how((r), words_, 1);                                                    \
    } while (0)

/* The run succeeded with nothing on stderr. */
static void expect_ok(const result *r)
{
    if (r->code != 0)
        fail_msg("exit %d, stderr: %s", r->code, r->err);
}

/* stderr is exactly one line "symrec: <kind>: ...", containing `needle` if given. */
static void expect_one_line(const char *err, const char *kind, const char *needle)
{
    char prefix[32];
    snprintf(prefix, sizeof prefix, "symrec: %s: ", kind);
    if (strncmp(err, prefix, strlen(prefix)) != 0)
        fail_msg("stderr does not start with '%s': %s", prefix, err);
    const char *nl = strchr(err, '\n');
    if (!nl || nl[1] != '\0')
        fail_msg("stderr is not exactly one line: %s", err);
    if (needle && !strstr(err, needle))
        fail_msg("stderr lacks '%s': %s", needle, err);
}

/* Failed with exit 1, one error line, nothing on stdout. */
static void expect_error(const result *r, const char *needle)
{
    if (r->code != 1)
        fail_msg("expected exit 1, got %d; stderr: %s", r->code, r->err);
    expect_one_line(r->err, "error", needle);
    assert_string_equal(r->out, "");
}

/* Failed with exit 2, one usage line, nothing on stdout. */
static void expect_usage(const result *r, const char *needle)
{
    if (r->code != 2)
        fail_msg("expected exit 2, got %d; stderr: %s", r->code, r->err);
    expect_one_line(r->err, "usage", needle);
    assert_string_equal(r->out, "");
}

static bool contains(const char *haystack, const char *needle)
{
    return strstr(haystack, needle) != NULL;
}

static void expect_contains(const char *haystack, const char *needle)
{
    if (!contains(haystack, needle))
        fail_msg("'%s' not found in: %s", needle, haystack);
}

/* ------------------------------------------------------------------------------------
 * A strict JSON reader (RFC 8259), enough to check --json output
 * ---------------------------------------------------------------------------------- */

typedef enum jtype { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ } jtype;

typedef struct jv {
    jtype type;
    bool b;
    double num;
    char *str;
    size_t count;
    struct jv *items;   /* array elements or object values */
    char **keys;        /* object keys */
} jv;

typedef struct jparser {
    const char *p;
    int depth;
} jparser;

static void jv_release(jv *v)
{
    free(v->str);
    for (size_t i = 0; i < v->count; i++) {
        jv_release(&v->items[i]);
        if (v->keys)
            free(v->keys[i]);
    }
    free(v->items);
    free(v->keys);
    memset(v, 0, sizeof *v);
}

static void skip_ws(jparser *ps)
{
    while (*ps->p == ' ' || *ps->p == '\t' || *ps->p == '\n' || *ps->p == '\r')
        ps->p++;
}

static void put_utf8(char **out, unsigned cp)
{
    char *o = *out;
    if (cp < 0x80) {
        *o++ = (char)cp;
    } else if (cp < 0x800) {
        *o++ = (char)(0xc0 | (cp >> 6));
        *o++ = (char)(0x80 | (cp & 0x3f));
    } else if (cp < 0x10000) {
        *o++ = (char)(0xe0 | (cp >> 12));
        *o++ = (char)(0x80 | ((cp >> 6) & 0x3f));
        *o++ = (char)(0x80 | (cp & 0x3f));
    } else {
        *o++ = (char)(0xf0 | (cp >> 18));
        *o++ = (char)(0x80 | ((cp >> 12) & 0x3f));
        *o++ = (char)(0x80 | ((cp >> 6) & 0x3f));
        *o++ = (char)(0x80 | (cp & 0x3f));
    }
    *out = o;
}

static bool hex4(const char *p, unsigned *out)
{
    unsigned v = 0;
    for (int i = 0; i < 4; i++) {
        char c = p[i];
        v <<= 4;
        if (c >= '0' && c <= '9')
            v |= (unsigned)(c - '0');
        else if (c >= 'a' && c <= 'f')
            v |= (unsigned)(c - 'a' + 10);
        else if (c >= 'A' && c <= 'F')
            v |= (unsigned)(c - 'A' + 10);
        else
            return false;
    }
    *out = v;
    return true;
}

static bool parse_string(jparser *ps, char **out)
{
    if (*ps->p != '"')
        return false;
    ps->p++;
    char *s = malloc(strlen(ps->p) * 4 + 1);   /* \uXXXX is 6 bytes in, at most 4 out */
    char *o = s;
    for (;;) {
        unsigned char c = (unsigned char)*ps->p;
        if (c == '"') {
            ps->p++;
            break;
        }
        if (c < 0x20) {     /* raw control characters (and the NUL end) are invalid */
            free(s);
            return false;
        }
        if (c != '\\') {
            *o++ = (char)c;
            ps->p++;
            continue;
        }
        char e = ps->p[1];
        ps->p += 2;
        switch (e) {
        case '"': *o++ = '"'; break;
        case '\\': *o++ = '\\'; break;
        case '/': *o++ = '/'; break;
        case 'b': *o++ = '\b'; break;
        case 'f': *o++ = '\f'; break;
        case 'n': *o++ = '\n'; break;
        case 'r': *o++ = '\r'; break;
        case 't': *o++ = '\t'; break;
        case 'u': {
            unsigned cp, lo;
            if (!hex4(ps->p, &cp)) {
                free(s);
                return false;
            }
            ps->p += 4;
            if (cp >= 0xd800 && cp <= 0xdbff && ps->p[0] == '\\' && ps->p[1] == 'u' &&
                hex4(ps->p + 2, &lo) && lo >= 0xdc00 && lo <= 0xdfff) {
                cp = 0x10000 + ((cp - 0xd800) << 10) + (lo - 0xdc00);
                ps->p += 6;
            }
            put_utf8(&o, cp);
            break;
        }
        default:
            free(s);
            return false;
        }
    }
    *o = '\0';
    *out = s;
    return true;
}

static bool parse_value(jparser *ps, jv *v);

static bool parse_items(jparser *ps, jv *v, bool object)
{
    char close = object ? '}' : ']';
    ps->p++;
    skip_ws(ps);
    if (*ps->p == close) {
        ps->p++;
        return true;
    }
    for (;;) {
        jv item = {0};
        char *key = NULL;
        if (object) {
            skip_ws(ps);
            if (!parse_string(ps, &key))
                return false;
            skip_ws(ps);
            if (*ps->p != ':') {
                free(key);
                return false;
            }
            ps->p++;
        }
        if (!parse_value(ps, &item)) {
            free(key);
            jv_release(&item);
            return false;
        }
        v->items = realloc(v->items, (v->count + 1) * sizeof *v->items);
        if (object)
            v->keys = realloc(v->keys, (v->count + 1) * sizeof *v->keys);
        assert_non_null(v->items);
        v->items[v->count] = item;
        if (object)
            v->keys[v->count] = key;
        v->count++;
        skip_ws(ps);
        if (*ps->p == ',') {
            ps->p++;
            continue;
        }
        if (*ps->p == close) {
            ps->p++;
            return true;
        }
        return false;
    }
}

static bool parse_value(jparser *ps, jv *v)
{
    skip_ws(ps);
    if (++ps->depth > 64)
        return false;
    bool ok;
    const char *p = ps->p;
    if (*p == '{') {
        v->type = J_OBJ;
        ok = parse_items(ps, v, true);
    } else if (*p == '[') {
        v->type = J_ARR;
        ok = parse_items(ps, v, false);
    } else if (*p == '"') {
        v->type = J_STR;
        ok = parse_string(ps, &v->str);
    } else if (strncmp(p, "null", 4) == 0) {
        v->type = J_NULL;
        ps->p += 4;
        ok = true;
    } else if (strncmp(p, "true", 4) == 0 || strncmp(p, "false", 5) == 0) {
        v->type = J_BOOL;
        v->b = p[0] == 't';
        ps->p += v->b ? 4 : 5;
        ok = true;
    } else {
        /* -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)? */
        const char *q = p;
        if (*q == '-')
            q++;
        if (*q == '0')
            q++;
        else if (*q >= '1' && *q <= '9')
            while (*q >= '0' && *q <= '9')
                q++;
        else
            return false;
        if (*q == '.') {
            q++;
            if (!(*q >= '0' && *q <= '9'))
                return false;
            while (*q >= '0' && *q <= '9')
                q++;
        }
        if (*q == 'e' || *q == 'E') {
            q++;
            if (*q == '+' || *q == '-')
                q++;
            if (!(*q >= '0' && *q <= '9'))
                return false;
            while (*q >= '0' && *q <= '9')
                q++;
        }
        v->type = J_NUM;
        v->num = strtod(p, NULL);
        ps->p = q;
        ok = true;
    }
    ps->depth--;
    return ok;
}

/* Parses text that must be exactly one JSON value followed by one newline. */
static jv parse_json(const char *text)
{
    jparser ps = {text, 0};
    jv v = {0};
    if (!parse_value(&ps, &v))
        fail_msg("invalid JSON near '%.40s' in: %s", ps.p, text);
    if (strcmp(ps.p, "\n") != 0)
        fail_msg("JSON not followed by exactly one newline: '%s'", ps.p);
    return v;
}

static const jv *jget(const jv *obj, const char *key)
{
    assert_int_equal(obj->type, J_OBJ);
    for (size_t i = 0; i < obj->count; i++)
        if (strcmp(obj->keys[i], key) == 0)
            return &obj->items[i];
    fail_msg("no key '%s' in JSON object", key);
    return NULL;
}

static const char *jstr(const jv *obj, const char *key)
{
    const jv *v = jget(obj, key);
    assert_int_equal(v->type, J_STR);
    return v->str;
}

static double jnum(const jv *obj, const char *key)
{
    const jv *v = jget(obj, key);
    assert_int_equal(v->type, J_NUM);
    return v->num;
}

/* ------------------------------------------------------------------------------------
 * Shorthands for the common set-up steps
 * ---------------------------------------------------------------------------------- */

/* Adds the materials these tests name that sql/ does not seed (a part may name only a
 * material the catalogue holds): steel, 16MnCr5 and AlSi10Mg, with their densities. */
static void add_test_materials(sr_catalog *cat)
{
    static const sr_material_new mats[] = {
        {"steel", 7.85, "steel", "plain steel, for the tests"},
        {"16MnCr5", 7.85, "steel", "EN 10084 case-hardening steel"},
        {"AlSi10Mg", 2.67, "aluminium", "EN AC-43000 cast aluminium alloy"},
    };
    for (size_t i = 0; i < sizeof mats / sizeof mats[0]; i++) {
        sr_err err;
        sr_err_clear(&err);
        if (sr_catalog_material_add(cat, &mats[i], NULL, &err) != SR_OK)
            fail_msg("cannot add material %s: %s", mats[i].name, err.msg);
    }
}

/* Creates the test's catalogue through the library (`catalog init` itself is tested on
 * its own, and a process fewer per test matters under valgrind, about a second each);
 * with_materials: add_test_materials too. */
static void create_catalog(const env *e, bool with_materials)
{
    sr_catalog *cat = NULL;
    sr_err err;
    sr_err_clear(&err);
    if (sr_catalog_open(e->db, SR_CATALOG_CREATE, &cat, &err) != SR_OK)
        fail_msg("cannot create %s: %s", e->db, err.msg);
    if (with_materials)
        add_test_materials(cat);
    sr_catalog_close(cat);
}

/* The usual catalogue of a test: created, with the test materials. */
static void init_catalog(const env *e)
{
    create_catalog(e, true);
}

/* Adds a part from `mesh` and returns the id it printed. Set-up: it runs outside
 * $SYMREC_WRAP (a `part add` under Valgrind costs seconds); the cases about `part add`
 * run it themselves. */
static long add_part(const env *e, const char *number, const char *name, const char *material,
                     const char *mesh)
{
    result r;
    RUN_NATIVE(&r, "--db", e->db, "part", "add", "--number", number, "--name", name, "--material",
        material, "--mesh", mesh);
    expect_ok(&r);
    char *end;
    long id = strtol(r.out, &end, 10);
    if (id < 1 || strcmp(end, "\n") != 0)
        fail_msg("part add printed '%s', expected an id", r.out);
    result_free(&r);
    return id;
}

/* Adds an instance of `part` and returns its id; set-up, outside $SYMREC_WRAP as
 * add_part. */
static long add_instance(const env *e, const char *part, const char *mesh, const char *serial)
{
    result r;
    RUN_NATIVE(&r, "--db", e->db, "instance", "add", "--part", part, "--mesh", mesh, "--serial",
        serial, "--received", "2024-02-29", "--notes", "dent on the rim");
    expect_ok(&r);
    char *end;
    long id = strtol(r.out, &end, 10);
    if (id < 1 || strcmp(end, "\n") != 0)
        fail_msg("instance add printed '%s', expected an id", r.out);
    result_free(&r);
    return id;
}

/* `part list --json` output (caller frees). */
static char *part_list_json(const env *e)
{
    result r;
    RUN(&r, "--db", e->db, "part", "list", "--json");
    expect_ok(&r);
    free(r.err);
    return r.out;
}

/* Under $SYMREC_WRAP (valgrind: about a second per run) a table of cases that all take
 * the same early-exit path runs only its first and last case; natively every case runs. */
static bool sampled_out(size_t i, size_t n)
{
    const char *wrap = getenv("SYMREC_WRAP");
    return wrap && wrap[0] && i != 0 && i + 1 != n;
}

/* ------------------------------------------------------------------------------------
 * Help, version, usage errors
 * ---------------------------------------------------------------------------------- */

static void top_level_help_lists_commands_and_db_default(void **state)
{
    result r;
    RUN(&r, "--help");
    expect_ok(&r);
    assert_string_equal(r.err, "");
    expect_contains(r.out, "usage: symrec");
    const char *cmds[] = {"catalog", "part",   "instance", "export",    "reconstruct", "run",
                          "compare", "params", "demo",     "fixtures",  "help",        "history",
                          "report",  "plan",   "rules",    "materials", "check",       "convert"};
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        char line[32];
        snprintf(line, sizeof line, "\n  %s ", cmds[i]);
        expect_contains(r.out, line);
    }
    expect_contains(r.out, "--db FILE");
    expect_contains(r.out, "$SYMREC_DB");
    expect_contains(r.out, "./symrec.db");
    result_free(&r);

    /* `symrec help` alone is the same text. */
    result h;
    RUN(&h, "help");
    expect_ok(&h);
    RUN(&r, "--help");
    assert_string_equal(h.out, r.out);
    result_free(&h);
    result_free(&r);
}

static void every_command_and_subcommand_has_help(void **state)
{
    const env *e = *state;
    static const char *const cmds[][3] = {
        {"catalog", "--help"},
        {"catalog", "init", "--help"},
        {"catalog", "info", "--help"},
        {"part", "--help"},
        {"part", "add", "--help"},
        {"part", "list", "--help"},
        {"part", "show", "--help"},
        {"instance", "--help"},
        {"instance", "add", "--help"},
        {"instance", "list", "--help"},
        {"instance", "show", "--help"},
        {"export", "--help"},
        {"reconstruct", "--help"},
        {"run", "--help"},
        {"run", "list", "--help"},
        {"run", "show", "--help"},
        {"compare", "--help"},
        {"plan", "--help"},
        {"params", "--help"},
        {"params", "list", "--help"},
        {"params", "show", "--help"},
        {"params", "set", "--help"},
        {"rules", "--help"},
        {"rules", "list", "--help"},
        {"rules", "show", "--help"},
        {"rules", "set", "--help"},
        {"rules", "add", "--help"},
        {"rules", "enable", "--help"},
        {"rules", "disable", "--help"},
        {"materials", "--help"},
        {"materials", "list", "--help"},
        {"demo", "--help"},
        {"fixtures", "--help"},
        {"help", "--help"},
        {"history", "--help"},
        {"report", "--help"},
        {"check", "--help"},
        {"convert", "--help"},
    };
    const size_t n = sizeof cmds / sizeof cmds[0];
    for (size_t i = 0; i < n; i++) {
        if (sampled_out(i, n))
            continue;
        const char *words[6] = {"--db", e->db, cmds[i][0], cmds[i][1], cmds[i][2], NULL};
        result r;
        run_words(&r, words);
        if (r.code != 0)
            fail_msg("'%s %s --help' exited %d: %s", cmds[i][0], cmds[i][1], r.code, r.err);
        assert_string_equal(r.err, "");
        if (strncmp(r.out, "usage: symrec", 13) != 0)
            fail_msg("'%s %s' help does not start with usage: %s", cmds[i][0], cmds[i][1],
                     r.out);
        /* A subcommand's help names the subcommand. */
        if (cmds[i][2]) {
            char want[64];
            snprintf(want, sizeof want, "%s %s", cmds[i][0], cmds[i][1]);
            expect_contains(r.out, want);
        }
        result_free(&r);
    }
    /* Asking for help never creates the catalogue. */
    assert_false(file_exists(e->db));
}

static void help_command_shows_a_commands_help(void **state)
{
    result a, b;
    RUN(&a, "help", "part", "add");
    RUN(&b, "part", "add", "--help");
    expect_ok(&a);
    expect_ok(&b);
    assert_string_equal(a.out, b.out);
    expect_contains(a.out, "--number P");
    result_free(&a);
    result_free(&b);

    RUN(&a, "help", "export");
    expect_ok(&a);
    expect_contains(a.out, "export part P --out FILE");
    result_free(&a);

    RUN(&a, "help", "frobnicate");
    expect_usage(&a, "unknown command 'frobnicate'");
    result_free(&a);
}

static void version_prints_the_version(void **state)
{
    result r;
    RUN(&r, "--version");
    expect_ok(&r);
    assert_string_equal(r.out, "symrec " SR_VERSION "\n");
    assert_string_equal(r.out, "symrec 0.1.0\n");
    assert_string_equal(r.err, "");
    result_free(&r);
}

static void unknown_command_is_a_usage_error(void **state)
{
    result r;
    RUN(&r, "frobnicate");
    expect_usage(&r, NULL);
    assert_string_equal(r.err,
                        "symrec: usage: unknown command 'frobnicate' (see 'symrec --help')\n");
    result_free(&r);
}

static void missing_command_is_a_usage_error(void **state)
{
    const env *e = *state;
    result r;
    RUN(&r, "--db", e->db);
    expect_usage(&r, "missing command");
    result_free(&r);
    const char *none[] = {NULL};
    run_words(&r, none);
    expect_usage(&r, "missing command");
    result_free(&r);
}

static void unknown_options_are_usage_errors(void **state)
{
    const env *e = *state;
    result r;
    RUN(&r, "--bogus", "part", "list");
    expect_usage(&r, "unknown option '--bogus'");
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "list", "--bogus");
    expect_usage(&r, "unknown option '--bogus' for 'part list'");
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "list", "--json=yes");
    expect_usage(&r, "option '--json' takes no value");
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "show", "A", "B");
    expect_usage(&r, "unexpected argument 'B'");
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "show");
    expect_usage(&r, "'part show' needs a part number or id");
    result_free(&r);

    RUN(&r, "--db", e->db, "part");
    expect_usage(&r, "'part' needs a subcommand");
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "frob");
    expect_usage(&r, "unknown subcommand 'instance frob'");
    result_free(&r);

    /* None of that touched the catalogue path. */
    assert_false(file_exists(e->db));
}

static void missing_option_values_are_usage_errors(void **state)
{
    const env *e = *state;
    result r;
    RUN(&r, "--db");
    expect_usage(&r, "option '--db' needs a file name");
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "add", "--number");
    expect_usage(&r, "option '--number' needs a value");
    result_free(&r);

    /* The next option is not taken as the value. */
    RUN(&r, "--db", e->db, "part", "add", "--number", "--name", "x");
    expect_usage(&r, "option '--number' needs a value");
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "add", "--number", "P1", "--name", "n", "--material", "m");
    expect_usage(&r, "'part add' needs --mesh");
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "add", "--mesh", e->cyl);
    expect_usage(&r, "'instance add' needs --part");
    result_free(&r);

    RUN(&r, "--db", e->db, "export", "part", "P1");
    expect_usage(&r, "'export' needs --out FILE");
    result_free(&r);

    RUN(&r, "fixtures");
    expect_usage(&r, "'fixtures' needs --out DIR");
    result_free(&r);
}

/* Runs `part add` with one bad symmetry option and expects the exact usage line. */
static void expect_bad_symmetry(const env *e, const char *kind, const char *opt,
                                const char *value, const char *want)
{
    result r;
    if (opt) {
        RUN(&r, "--db", e->db, "part", "add", "--number", "P1", "--name", "n", "--material",
            "m", "--mesh", e->cyl, "--symmetry", kind, opt, value);
    } else {
        RUN(&r, "--db", e->db, "part", "add", "--number", "P1", "--name", "n", "--material",
            "m", "--mesh", e->cyl, "--symmetry", kind);
    }
    expect_usage(&r, NULL);
    char line[256];
    snprintf(line, sizeof line, "symrec: usage: %s\n", want);
    assert_string_equal(r.err, line);
    result_free(&r);
}

static void bad_numbers_are_usage_errors_naming_the_option(void **state)
{
    const env *e = *state;
    const char *order_want = "expected an integer 2..360 (or 0 for continuous)";
    const char *bad_orders[] = {"x", "1", "361", "-2", "5abc", "", " 6", "6.0", "99999999999"};
    const size_t n_orders = sizeof bad_orders / sizeof bad_orders[0];
    for (size_t i = 0; i < n_orders; i++) {
        if (sampled_out(i, n_orders))
            continue;
        char want[160];
        snprintf(want, sizeof want, "bad --order '%s': %s", bad_orders[i], order_want);
        expect_bad_symmetry(e, "axial", "--order", bad_orders[i], want);
    }
    const char *shift_want = "expected a shift in mm, 0..1000000 (0 = find by search)";
    const char *bad_shifts[] = {"nan", "inf", "-1", "0x10", "1e400", "abc", "2mm"};
    const size_t n_shifts = sizeof bad_shifts / sizeof bad_shifts[0];
    for (size_t i = 0; i < n_shifts; i++) {
        if (sampled_out(i, n_shifts))
            continue;
        char want[160];
        snprintf(want, sizeof want, "bad --shift '%s': %s", bad_shifts[i], shift_want);
        expect_bad_symmetry(e, "glide", "--shift", bad_shifts[i], want);
    }
    expect_bad_symmetry(e, "mirror", "--order", "6", "--order applies to --symmetry axial only");
    expect_bad_symmetry(e, "axial", "--shift", "6", "--shift applies to --symmetry glide only");
    expect_bad_symmetry(e, "spiral", NULL, NULL,
                        "bad --symmetry 'spiral': expected axial, mirror or glide");

    result r;
    RUN(&r, "--db", e->db, "params", "set", "fine", "--layers", "abc");
    expect_usage(&r, NULL);
    assert_string_equal(r.err,
                        "symrec: usage: bad --layers 'abc': expected an integer 1..100000\n");
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "show", "abc");
    expect_usage(&r, "bad ID 'abc': expected a positive integer id");
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "show", "0");
    expect_usage(&r, "bad ID '0'");
    result_free(&r);

    /* Usage errors are found before the catalogue is opened (it does not exist). */
    assert_false(file_exists(e->db));
}

/* ------------------------------------------------------------------------------------
 * Catalogue
 * ---------------------------------------------------------------------------------- */

static void catalog_init_creates_then_is_idempotent(void **state)
{
    const env *e = *state;
    char want[256];
    result r;
    RUN(&r, "--db", e->db, "catalog", "init");
    expect_ok(&r);
    snprintf(want, sizeof want, "created catalogue '%s' (schema version %d)\n", e->db,
             sr_catalog_schema_latest());
    assert_string_equal(r.out, want);
    assert_string_equal(r.err, "");
    result_free(&r);

    RUN(&r, "--db", e->db, "catalog", "init");
    expect_ok(&r);
    snprintf(want, sizeof want, "catalogue '%s' already exists (schema version %d)\n", e->db,
             sr_catalog_schema_latest());
    assert_string_equal(r.out, want);
    result_free(&r);

    RUN(&r, "--db", e->db, "catalog", "info", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_string_equal(jstr(&v, "path"), e->db);
    assert_int_equal((int)jnum(&v, "schema_version"), sr_catalog_schema_latest());
    assert_int_equal((int)jnum(&v, "parts"), 0);
    assert_int_equal((int)jnum(&v, "instances"), 0);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "catalog", "info");
    expect_ok(&r);
    snprintf(want, sizeof want, "schema version:  %d\n", sr_catalog_schema_latest());
    expect_contains(r.out, want);
    expect_contains(r.out, "parts:           0\n");
    result_free(&r);
}

static void catalog_info_counts_parts_and_instances(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    add_part(e, "P2", "block", "steel", e->box);
    add_instance(e, "P1", e->cyl, "S1");
    result r;
    RUN(&r, "--db", e->db, "catalog", "info", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal((int)jnum(&v, "parts"), 2);
    assert_int_equal((int)jnum(&v, "instances"), 1);
    assert_int_equal((int)jnum(&v, "runs"), 0);
    jv_release(&v);
    result_free(&r);
}

static void commands_on_a_missing_catalogue_fail_without_creating_it(void **state)
{
    const env *e = *state;
    result r;
    RUN(&r, "--db", e->db, "part", "list");
    expect_error(&r, "no catalogue '");
    expect_contains(r.err, e->db);
    expect_contains(r.err, "catalog init");
    result_free(&r);
    RUN(&r, "--db", e->db, "part", "add", "--number", "P1", "--name", "n", "--material", "m",
        "--mesh", e->cyl);
    expect_error(&r, "no catalogue '");
    result_free(&r);
    assert_false(file_exists(e->db));
}

static void garbage_catalogue_file_is_refused(void **state)
{
    const env *e = *state;
    char junk[4096];
    for (size_t i = 0; i < sizeof junk; i++)
        junk[i] = (char)(i * 7 + 3);
    write_bytes(e->db, junk, sizeof junk);
    result r;
    RUN(&r, "--db", e->db, "part", "list");
    expect_error(&r, "not a symrec catalogue");
    expect_contains(r.err, e->db);
    result_free(&r);
    RUN(&r, "--db", e->db, "catalog", "init");
    expect_error(&r, "not a symrec catalogue");
    result_free(&r);
    /* The file is left as it was. */
    char *back = read_text(e->db);
    assert_non_null(back);
    assert_memory_equal(back, junk, sizeof junk);
    free(back);
}

static void symrec_db_environment_variable_is_used(void **state)
{
    const env *e = *state;
    char env_db[128], other_db[128];
    path_in(e, "env.db", env_db, sizeof env_db);
    path_in(e, "other.db", other_db, sizeof other_db);
    assert_int_equal(setenv("SYMREC_DB", env_db, 1), 0);
    result r;
    RUN(&r, "catalog", "init");
    expect_ok(&r);
    expect_contains(r.out, env_db);
    result_free(&r);
    assert_true(file_exists(env_db));
    /* --db wins over the environment. */
    RUN(&r, "--db", other_db, "catalog", "init");
    expect_ok(&r);
    expect_contains(r.out, other_db);
    result_free(&r);
    RUN(&r, "catalog", "info", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_string_equal(jstr(&v, "path"), env_db);
    jv_release(&v);
    result_free(&r);
    unsetenv("SYMREC_DB");
    assert_true(file_exists(other_db));
}

/* ------------------------------------------------------------------------------------
 * Parts
 * ---------------------------------------------------------------------------------- */

static void part_add_prints_the_id_and_part_list_shows_it(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "SH-1", "--name", "drive shaft",
        "--material", "42CrMo4", "--mesh", e->cyl, "--notes", "a note");
    expect_ok(&r);
    assert_string_equal(r.out, "1\n");
    expect_contains(r.err, "added part 'SH-1' (id 1): 64 triangles");
    expect_contains(r.err, "mm³");
    result_free(&r);

    char *list = part_list_json(e);
    jv v = parse_json(list);
    assert_int_equal(v.type, J_ARR);
    assert_int_equal(v.count, 1);
    const jv *p = &v.items[0];
    assert_int_equal((int)jnum(p, "id"), 1);
    assert_string_equal(jstr(p, "number"), "SH-1");
    assert_string_equal(jstr(p, "name"), "drive shaft");
    assert_string_equal(jstr(p, "material"), "42CrMo4");
    assert_string_equal(jstr(p, "notes"), "a note");
    assert_int_equal((int)jnum(p, "triangles"), 64);    /* 16 sides + 2 fans of 16 */
    assert_int_equal((int)jnum(p, "vertices"), 34);
    assert_true(fabs(jnum(p, "volume_mm3") - cyl_volume()) < 1e-3);
    assert_int_equal(jget(p, "symmetry")->type, J_NULL);
    assert_int_equal((int)jnum(p, "instance_count"), 0);
    jv_release(&v);
    free(list);

    RUN(&r, "--db", e->db, "part", "list");
    expect_ok(&r);
    assert_string_equal(r.err, "");
    expect_contains(r.out, "volume mm³");
    expect_contains(r.out, "SH-1");
    expect_contains(r.out, "drive shaft");
    expect_contains(r.out, "42CrMo4");
    char vol[32];
    snprintf(vol, sizeof vol, "%.1f", cyl_volume());
    expect_contains(r.out, vol);
    result_free(&r);
}

static void part_add_json_prints_the_part(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "GEAR-20", "--name", "spur gear",
        "--material", "16MnCr5", "--mesh", e->cyl, "--symmetry", "axial", "--order", "20",
        "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal((int)jnum(&v, "id"), 1);
    assert_string_equal(jstr(&v, "number"), "GEAR-20");
    const jv *sym = jget(&v, "symmetry");
    assert_string_equal(jstr(sym, "kind"), "axial");
    assert_int_equal((int)jnum(sym, "order"), 20);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "add", "--number", "RAIL", "--name", "rail", "--material",
        "steel", "--mesh", e->box, "--symmetry", "glide", "--shift", "10", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    sym = jget(&v, "symmetry");
    assert_string_equal(jstr(sym, "kind"), "glide");
    assert_true(jnum(sym, "shift_mm") == 10.0);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "part", "show", "RAIL");
    expect_ok(&r);
    expect_contains(r.out, "  symmetry:   glide, shift 10 mm\n");
    result_free(&r);
    RUN(&r, "--db", e->db, "part", "show", "GEAR-20");
    expect_ok(&r);
    expect_contains(r.out, "  symmetry:   axial, 20-fold\n");
    result_free(&r);
}

static void part_add_duplicate_number_fails_and_changes_nothing(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    char *before = part_list_json(e);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "P1", "--name", "other", "--material", "C45",
        "--mesh", e->box);
    expect_error(&r, "P1");
    result_free(&r);
    /* Part numbers are unique ignoring case. */
    RUN(&r, "--db", e->db, "part", "add", "--number", "p1", "--name", "other", "--material", "C45",
        "--mesh", e->box);
    expect_error(&r, NULL);
    result_free(&r);
    char *after = part_list_json(e);
    assert_string_equal(before, after);
    free(before);
    free(after);
}

static void part_list_filters_by_name_number_and_material(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "SH-100", "Drive Shaft", "42CrMo4", e->cyl);
    add_part(e, "SH-200", "idler shaft", "C45", e->cyl);
    add_part(e, "BR-300", "bracket", "C45", e->box);

    struct {
        const char *opt, *value;
        size_t count;
        const char *first;
    } cases[] = {
        {"--name", "SHAFT", 2, "SH-100"},   /* case-insensitive substring */
        {"--name", "brack", 1, "BR-300"},
        {"--number", "sh-", 2, "SH-100"},
        {"--number", "300", 1, "BR-300"},
        {"--material", "c45", 2, "BR-300"}, /* ordered by number */
        {"--material", "C4", 0, NULL},      /* material matches exactly */
        {"--name", "nothing", 0, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        result r;
        RUN(&r, "--db", e->db, "part", "list", cases[i].opt, cases[i].value, "--json");
        expect_ok(&r);
        jv v = parse_json(r.out);
        assert_int_equal(v.type, J_ARR);
        if (v.count != cases[i].count)
            fail_msg("part list %s %s: %zu parts, expected %zu", cases[i].opt, cases[i].value,
                     v.count, cases[i].count);
        if (cases[i].first)
            assert_string_equal(jstr(&v.items[0], "number"), cases[i].first);
        jv_release(&v);
        result_free(&r);
    }
    result r;
    RUN(&r, "--db", e->db, "part", "list", "--name", "nothing");
    expect_ok(&r);
    assert_string_equal(r.out, "no parts\n");
    result_free(&r);
}

static void part_show_by_number_and_by_id(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    long id = add_part(e, "BLK-7", "block", "AlSi10Mg", e->box);
    char id_text[16];
    snprintf(id_text, sizeof id_text, "%ld", id);

    result a, b;
    RUN(&a, "--db", e->db, "part", "show", "BLK-7", "--json");
    RUN(&b, "--db", e->db, "part", "show", id_text, "--json");
    expect_ok(&a);
    expect_ok(&b);
    assert_string_equal(a.out, b.out);
    jv v = parse_json(a.out);
    assert_string_equal(jstr(&v, "number"), "BLK-7");
    assert_true(jnum(&v, "volume_mm3") == 6000.0);
    assert_true(jnum(&v, "area_mm2") == 2200.0);
    const jv *hi = jget(&v, "bbox_max_mm");
    assert_int_equal(hi->type, J_ARR);
    assert_int_equal(hi->count, 3);
    assert_true(hi->items[0].num == 10 && hi->items[1].num == 20 && hi->items[2].num == 30);
    assert_int_equal(jget(&v, "instances")->type, J_ARR);
    assert_int_equal(jget(&v, "instances")->count, 0);
    jv_release(&v);
    result_free(&a);
    result_free(&b);

    RUN(&a, "--db", e->db, "part", "show", "BLK-7");
    expect_ok(&a);
    assert_string_equal(a.err, "");
    char head[64];
    snprintf(head, sizeof head, "part BLK-7 (id %ld)\n", id);
    assert_true(strncmp(a.out, head, strlen(head)) == 0);
    expect_contains(a.out, "  name:       block\n");
    expect_contains(a.out, "  material:   AlSi10Mg\n");
    expect_contains(a.out, "  symmetry:   -\n");
    expect_contains(a.out, "  mesh:       8 vertices, 12 triangles, read in mm\n");
    expect_contains(a.out, "x 0.000 .. 10.000, y 0.000 .. 20.000, z 0.000 .. 30.000 mm\n");
    expect_contains(a.out, "  area:       2200.0 mm²\n");
    expect_contains(a.out, "  volume:     6000.0 mm³\n");
    expect_contains(a.out, "  instances:  0\n");
    result_free(&a);

    RUN(&a, "--db", e->db, "part", "show", "NOPE");
    expect_error(&a, "no part 'NOPE'");
    result_free(&a);
}

static void strings_are_escaped_in_json(void **state)
{
    const env *e = *state;
    init_catalog(e);
    const char *notes = "quote \" backslash \\ tab\t newline\n bell\a del\x7f \xc3\xa9t\xc3\xa9";
    const char *name = "\"quoted\" name";
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "Q/1", "--name", name, "--material",
        "steel", "--mesh", e->cyl, "--notes", notes);
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "part", "show", "Q/1", "--json");
    expect_ok(&r);
    /* Raw control characters never appear inside JSON text. */
    for (const char *p = r.out; *p; p++)
        if ((unsigned char)*p < 0x20 && !(p[0] == '\n' && p[1] == '\0'))
            fail_msg("raw control character 0x%02x in JSON output", *p);
    jv v = parse_json(r.out);
    assert_string_equal(jstr(&v, "notes"), notes);
    assert_string_equal(jstr(&v, "name"), name);
    assert_string_equal(jstr(&v, "number"), "Q/1");
    jv_release(&v);
    result_free(&r);

    /* The table keeps one row per part even with a newline in a field. */
    RUN(&r, "--db", e->db, "part", "list");
    expect_ok(&r);
    size_t lines = 0;
    for (const char *p = r.out; *p; p++)
        lines += *p == '\n';
    assert_int_equal(lines, 2);
    result_free(&r);

    /* Bytes that are not UTF-8 come out as U+FFFD, so the JSON stays valid UTF-8. */
    RUN(&r, "--db", e->db, "part", "add", "--number", "U1", "--name", "bad\xffutf\xc3",
        "--material", "steel", "--mesh", e->cyl, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_string_equal(jstr(&v, "name"), "bad\xef\xbf\xbdutf\xef\xbf\xbd");
    jv_release(&v);
    result_free(&r);
}

/* ------------------------------------------------------------------------------------
 * Bad mesh files
 * ---------------------------------------------------------------------------------- */

/* part add with `mesh` must fail with one error line naming the file, leaving the
 * catalogue as it was. */
static void expect_part_add_refuses(const env *e, const char *mesh, const char *needle)
{
    char *before = part_list_json(e);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "BAD", "--name", "bad", "--material",
        "steel", "--mesh", mesh);
    expect_error(&r, needle);
    /* The file is named by its base name at least. */
    const char *base = strrchr(mesh, '/');
    expect_contains(r.err, base ? base + 1 : mesh);
    result_free(&r);
    char *after = part_list_json(e);
    assert_string_equal(before, after);
    free(before);
    free(after);
}

static void part_add_refuses_a_missing_mesh_file(void **state)
{
    const env *e = *state;
    init_catalog(e);
    char path[128];
    path_in(e, "missing.stl", path, sizeof path);
    expect_part_add_refuses(e, path, NULL);
}

static void part_add_refuses_an_empty_mesh_file(void **state)
{
    const env *e = *state;
    init_catalog(e);
    char path[128];
    path_in(e, "empty.stl", path, sizeof path);
    write_bytes(path, "", 0);
    expect_part_add_refuses(e, path, NULL);
}

static void part_add_refuses_a_garbage_mesh_file(void **state)
{
    const env *e = *state;
    init_catalog(e);
    char path[128];
    path_in(e, "garbage.stl", path, sizeof path);
    const char junk[] = "this is not a mesh at all\n\x01\x02\x03 just words\n";
    write_bytes(path, junk, sizeof junk - 1);
    expect_part_add_refuses(e, path, NULL);
    path_in(e, "garbage.obj", path, sizeof path);
    write_bytes(path, "f 1 2 3\nv nonsense\n", 19);
    expect_part_add_refuses(e, path, NULL);
}

static void part_add_refuses_a_truncated_binary_stl(void **state)
{
    const env *e = *state;
    init_catalog(e);
    /* The cylinder's binary STL is 84 + 50 * 64 bytes; keep the header and 3 triangles. */
    char path[128];
    path_in(e, "truncated.stl", path, sizeof path);
    char *full = read_text(e->cyl);
    assert_non_null(full);
    write_bytes(path, full, 84 + 50 * 3);
    free(full);
    expect_part_add_refuses(e, path, "truncated");
}

/* A catalogue part is its intact model: an open box (one face left off), one triangle,
 * and a box whose triangles face inward are refused, each saying why; --allow-open
 * stores the open box with a warning. */
static void part_add_refuses_a_mesh_that_is_not_a_closed_solid(void **state)
{
    const env *e = *state;
    init_catalog(e);
    /* a 10 mm cube's 12 triangles, outward */
    static const char *cube =
        "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\n";
    static const char *faces[] = {"f 1 3 2\nf 1 4 3\n", "f 5 6 7\nf 5 7 8\n", "f 1 2 6\nf 1 6 5\n",
                                  "f 2 3 7\nf 2 7 6\n", "f 3 4 8\nf 3 8 7\n", "f 4 1 5\nf 4 5 8\n"};
    char open_box[1024], inward[1024], path[128];
    snprintf(open_box, sizeof open_box, "%s", cube);
    for (int i = 1; i < 6; i++) /* no bottom */
        strncat(open_box, faces[i], sizeof open_box - strlen(open_box) - 1);
    path_in(e, "open_box.obj", path, sizeof path);
    write_bytes(path, open_box, strlen(open_box));
    expect_part_add_refuses(e, path, "not a closed solid (4 boundary, 0 non-manifold");

    path_in(e, "one_triangle.obj", path, sizeof path);
    const char tri[] = "v 0 0 0\nv 10 0 0\nv 0 10 0\nf 1 2 3\n";
    write_bytes(path, tri, sizeof tri - 1);
    expect_part_add_refuses(e, path, "not a closed solid (3 boundary");

    /* every face reversed: closed and consistent, but inside out */
    snprintf(inward, sizeof inward, "%s", cube);
    static const char *reversed[] = {"f 1 2 3\nf 1 3 4\n", "f 5 7 6\nf 5 8 7\n",
                                     "f 1 6 2\nf 1 5 6\n", "f 2 7 3\nf 2 6 7\n",
                                     "f 3 8 4\nf 3 7 8\n", "f 4 5 1\nf 4 8 5\n"};
    for (int i = 0; i < 6; i++)
        strncat(inward, reversed[i], sizeof inward - strlen(inward) - 1);
    path_in(e, "inward.obj", path, sizeof path);
    write_bytes(path, inward, strlen(inward));
    expect_part_add_refuses(e, path, "encloses no volume (-1000 mm³: its triangles face inward)");

    /* the same open box, stored as asked */
    path_in(e, "open_box.obj", path, sizeof path);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "OPEN-1", "--name", "open box", "--material",
        "steel", "--mesh", path, "--allow-open");
    expect_ok(&r);
    expect_contains(r.err, "warning: part 'OPEN-1'");
    expect_contains(r.err, "not a closed solid");
    result_free(&r);
    char *list = part_list_json(e);
    expect_contains(list, "\"OPEN-1\"");
    free(list);
}

static void part_add_refuses_an_unknown_extension(void **state)
{
    const env *e = *state;
    init_catalog(e);
    char path[128];
    path_in(e, "mesh.xyz", path, sizeof path);
    write_bytes(path, "1 2 3\n", 6);
    expect_part_add_refuses(e, path, NULL);
}

/* ------------------------------------------------------------------------------------
 * Instances
 * ---------------------------------------------------------------------------------- */

static void instance_add_list_and_show(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "BLK-1", "block", "steel", e->box);
    add_part(e, "SH-1", "shaft", "steel", e->cyl);
    /* A "damaged" block: 10 x 20 x 24 instead of 30 high, 1200 mm³ missing. */
    char dmg[128];
    path_in(e, "damaged.stl", dmg, sizeof dmg);
    sr_mesh m;
    sr_mesh_init(&m);
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 24};
    assert_int_equal(sr_shape_box(lo, hi, &m, NULL), SR_OK);
    write_mesh_file(dmg, &m);
    sr_mesh_release(&m);

    result r;
    RUN(&r, "--db", e->db, "instance", "add", "--part", "BLK-1", "--mesh", dmg, "--serial",
        "SN-1", "--received", "2024-02-29", "--notes", "top sheared off");
    expect_ok(&r);
    assert_string_equal(r.out, "1\n");
    expect_contains(r.err, "added instance 1 of part 'BLK-1'");
    result_free(&r);
    long second = add_instance(e, "SH-1", e->cyl, "SN-2");
    assert_int_equal(second, 2);

    RUN(&r, "--db", e->db, "instance", "list", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(v.count, 2);
    assert_string_equal(jstr(&v.items[0], "part_number"), "BLK-1");
    assert_string_equal(jstr(&v.items[0], "serial"), "SN-1");
    assert_string_equal(jstr(&v.items[0], "received"), "2024-02-29");
    assert_string_equal(jstr(&v.items[0], "notes"), "top sheared off");
    assert_true(jnum(&v.items[0], "volume_mm3") == 4800.0);
    assert_string_equal(jstr(&v.items[1], "part_number"), "SH-1");
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "list", "--part", "SH-1", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(v.count, 1);
    assert_int_equal((int)jnum(&v.items[0], "id"), 2);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "list");
    expect_ok(&r);
    expect_contains(r.out, "missing mm³");
    expect_contains(r.out, "1200.0");
    expect_contains(r.out, "20.00 %");
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "show", "1", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal((int)jnum(&v, "id"), 1);
    assert_string_equal(jstr(&v, "part_number"), "BLK-1");
    assert_true(jnum(&v, "intact_volume_mm3") == 6000.0);
    assert_true(jnum(&v, "missing_volume_mm3") == 1200.0);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "instance", "show", "1");
    expect_ok(&r);
    expect_contains(r.out, "instance 1 of part BLK-1 (block)\n");
    expect_contains(r.out, "  serial:     SN-1\n");
    expect_contains(r.out, "  received:   2024-02-29\n");
    expect_contains(r.out, "  volume:     4800.0 mm³\n");
    expect_contains(r.out, "  missing:    1200.0 mm³ (20.00 % of intact)\n");
    result_free(&r);

    /* The part shows its instances. */
    RUN(&r, "--db", e->db, "part", "show", "BLK-1", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal((int)jnum(&v, "instance_count"), 1);
    const jv *list = jget(&v, "instances");
    assert_int_equal(list->count, 1);
    assert_string_equal(jstr(&list->items[0], "serial"), "SN-1");
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "part", "show", "BLK-1");
    expect_ok(&r);
    expect_contains(r.out, "SN-1");
    expect_contains(r.out, "2024-02-29");
    result_free(&r);
}

static void instance_add_for_an_unknown_part_fails(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    result r;
    RUN(&r, "--db", e->db, "instance", "add", "--part", "NOPE", "--mesh", e->cyl);
    expect_error(&r, "no part 'NOPE'");
    result_free(&r);
    RUN(&r, "--db", e->db, "instance", "list", "--part", "NOPE");
    expect_error(&r, "no part 'NOPE'");
    result_free(&r);
    RUN(&r, "--db", e->db, "instance", "list", "--json");
    expect_ok(&r);
    assert_string_equal(r.out, "[]\n");
    result_free(&r);
}

static void instance_add_validates_the_date(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    const char *bad[] = {"2024-02-30", "2023-02-29", "1900-02-29", "2024-04-31",
                         "2024-13-01", "2024-00-10", "24-01-01",   "2024-1-01",
                         "2024/01/01", "2024-01-01x", ""};
    const size_t n = sizeof bad / sizeof bad[0];
    for (size_t i = 0; i < n; i++) {
        if (sampled_out(i, n))
            continue;
        result r;
        RUN(&r, "--db", e->db, "instance", "add", "--part", "P1", "--mesh", e->cyl,
            "--received", bad[i]);
        char want[128];
        snprintf(want, sizeof want,
                 "symrec: usage: bad --received '%s': expected a date YYYY-MM-DD\n", bad[i]);
        expect_usage(&r, NULL);
        assert_string_equal(r.err, want);
        result_free(&r);
    }
    result r;
    RUN(&r, "--db", e->db, "instance", "add", "--part", "P1", "--mesh", e->cyl, "--received",
        "2000-02-29");
    expect_ok(&r);
    result_free(&r);
}

static void instance_show_of_an_unknown_id_fails(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "instance", "show", "42");
    expect_error(&r, "no instance 42");
    result_free(&r);
}

static void instance_symmetry_override_is_shown(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "part", "add", "--number", "P1", "--name", "shaft", "--material",
        "steel", "--mesh", e->cyl, "--symmetry", "axial");
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "instance", "add", "--part", "P1", "--mesh", e->cyl, "--symmetry",
        "mirror", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_string_equal(jstr(jget(&v, "symmetry"), "kind"), "mirror");
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "instance", "add", "--part", "P1", "--mesh", e->cyl, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    const jv *sym = jget(&v, "symmetry");
    assert_string_equal(jstr(sym, "kind"), "axial");    /* the part's */
    assert_int_equal((int)jnum(sym, "order"), 0);
    jv_release(&v);
    result_free(&r);
}

/* ------------------------------------------------------------------------------------
 * Export
 * ---------------------------------------------------------------------------------- */

/* Triangles as 9 coordinates, rotated so the smallest vertex comes first (keeps the
 * orientation), then sorted: a form that ignores vertex and triangle order. */
static int cmp_tri(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int i = 0; i < 9; i++)
        if (x[i] != y[i])
            return x[i] < y[i] ? -1 : 1;
    return 0;
}

static int cmp_vertex(const double *a, const double *b)
{
    for (int i = 0; i < 3; i++)
        if (a[i] != b[i])
            return a[i] < b[i] ? -1 : 1;
    return 0;
}

static double *canonical_tris(const sr_mesh *m)
{
    double *t = malloc(m->tri_count * 9 * sizeof *t);
    assert_non_null(t);
    for (size_t i = 0; i < m->tri_count; i++) {
        const double *v[3];
        for (int k = 0; k < 3; k++)
            v[k] = &m->xyz[3 * m->tri[3 * i + k]];
        int first = 0;
        for (int k = 1; k < 3; k++)
            if (cmp_vertex(v[k], v[first]) < 0)
                first = k;
        for (int k = 0; k < 3; k++)
            memcpy(&t[9 * i + 3 * k], v[(first + k) % 3], 3 * sizeof(double));
    }
    qsort(t, m->tri_count, 9 * sizeof *t, cmp_tri);
    return t;
}

static void assert_same_geometry(const sr_mesh *a, const sr_mesh *b, const char *what)
{
    if (a->tri_count != b->tri_count || a->vertex_count != b->vertex_count)
        fail_msg("%s: %zu vertices %zu triangles, stored %zu and %zu", what, a->vertex_count,
                 a->tri_count, b->vertex_count, b->tri_count);
    double *ta = canonical_tris(a), *tb = canonical_tris(b);
    if (memcmp(ta, tb, a->tri_count * 9 * sizeof *ta) != 0)
        fail_msg("%s: triangles differ from the stored mesh", what);
    free(ta);
    free(tb);
}

static void export_round_trips_through_every_format(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    add_instance(e, "P1", e->box, "SN-1");

    sr_catalog *cat;
    sr_err err;
    sr_err_clear(&err);
    assert_int_equal(sr_catalog_open(e->db, 0, &cat, &err), SR_OK);
    sr_mesh part_mesh, inst_mesh;
    sr_mesh_init(&part_mesh);
    sr_mesh_init(&inst_mesh);
    sr_part_info info;
    assert_int_equal(sr_catalog_part_find(cat, "P1", &info, &err), SR_OK);
    assert_int_equal(sr_catalog_part_mesh(cat, info.id, &part_mesh, &err), SR_OK);
    assert_int_equal(sr_catalog_instance_mesh(cat, 1, &inst_mesh, &err), SR_OK);
    sr_catalog_close(cat);

    const char *exts[] = {"stl", "obj", "ply", "off", "gltf", "glb"};
    for (size_t i = 0; i < sizeof exts / sizeof exts[0]; i++) {
        for (int inst = 0; inst < 2; inst++) {
            char name[32], path[160];
            snprintf(name, sizeof name, "out_%s.%s", inst ? "inst" : "part", exts[i]);
            path_in(e, name, path, sizeof path);
            result r;
            if (inst)
                RUN(&r, "--db", e->db, "export", "instance", "1", "--out", path, "--json");
            else
                RUN(&r, "--db", e->db, "export", "part", "P1", "--out", path, "--json");
            expect_ok(&r);
            jv v = parse_json(r.out);
            assert_string_equal(jstr(&v, "format"), exts[i]);
            assert_string_equal(jstr(&v, "path"), path);
            const sr_mesh *stored = inst ? &inst_mesh : &part_mesh;
            assert_int_equal((size_t)jnum(&v, "triangles"), stored->tri_count);
            jv_release(&v);
            result_free(&r);

            sr_mesh back;
            sr_mesh_init(&back);
            sr_status st = sr_mesh_read(path, &back, &err);
            if (st != SR_OK)
                fail_msg("cannot read back %s: %s", path, err.msg);
            assert_same_geometry(&back, stored, path);
            sr_mesh_release(&back);
        }
    }
    sr_mesh_release(&part_mesh);
    sr_mesh_release(&inst_mesh);

    /* The human form says what went where. */
    char path[160];
    path_in(e, "p.stl", path, sizeof path);
    result r;
    RUN(&r, "--db", e->db, "export", "part", "P1", "--out", path);
    expect_ok(&r);
    char want[256];
    snprintf(want, sizeof want, "wrote part P1 to '%s' (stl, 34 vertices, 64 triangles)\n",
             path);
    assert_string_equal(r.out, want);
    result_free(&r);
}

/* check says what a file holds (a closed box: its volume; an open one: its boundary);
 * convert rewrites it in another format with the same geometry. */
static void check_and_convert_a_mesh_file(void **state)
{
    const env *e = *state;
    result r;
    RUN(&r, "check", e->box, "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_true(fabs(jnum(&v, "volume") - 6000) < 1e-6);
    assert_true(jget(&v, "closed")->b && jget(&v, "outward")->b);
    assert_int_equal((int)jnum(&v, "components"), 1);
    assert_string_equal(jstr(&v, "likely_unit"), "mm");
    jv_release(&v);
    result_free(&r);
    RUN(&r, "check", e->box);
    expect_ok(&r);
    expect_contains(r.out, "a closed solid, facing outward");
    result_free(&r);

    char open_box[160];
    path_in(e, "open.obj", open_box, sizeof open_box);
    const char text[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
                        "f 1 2 3\nf 1 3 4\nf 1 2 6\nf 1 6 5\n";
    write_bytes(open_box, text, sizeof text - 1);
    RUN(&r, "check", open_box);
    expect_ok(&r);
    expect_contains(r.out, "not a closed solid: ");
    expect_contains(r.out, "likely unit         in (largest side 1 as read)");
    result_free(&r);

    char converted[160];
    path_in(e, "box.ply", converted, sizeof converted);
    RUN(&r, "convert", e->box, converted, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_string_equal(jstr(&v, "format"), "ply");
    assert_int_equal((int)jnum(&v, "triangles"), 12);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "compare", e->box, converted, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_true(jnum(&v, "hausdorff_mm") == 0);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "convert", e->box, "x.xyz");
    expect_usage(&r, "bad OUT 'x.xyz'");
    result_free(&r);
    path_in(e, "missing.stl", converted, sizeof converted);
    RUN(&r, "check", converted);
    expect_error(&r, "missing.stl");
    result_free(&r);
}

/* check reads an open mesh as a scan: a 10 mm cube without its top and a stray triangle
 * 30 mm above it has one opening (4 edges, 40 mm, 100 of 600 mm² open) and two
 * components, the triangle (0.5 mm²) a stray. */
static void check_describes_an_open_scan(void **state)
{
    const env *e = *state;
    char path[160];
    path_in(e, "scan.obj", path, sizeof path);
    const char text[] = "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\n"
                        "v 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\n"
                        "v 5 5 40\nv 6 5 40\nv 5 6 40\n"
                        "f 1 3 2\nf 1 4 3\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
                        "f 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\nf 9 10 11\n";
    write_bytes(path, text, sizeof text - 1);
    result r;
    RUN(&r, "check", path);
    expect_ok(&r);
    expect_contains(r.out, "  openings            1 boundary loop, 4 edges (4 edges 40.0 mm)\n");
    expect_contains(r.out, "  open share          16.67 % (100 mm² of openings)\n");
    expect_contains(r.out, "  strays              1 (1 triangles, 0.5 mm²)");
    expect_contains(r.out, "read as a scan\n");
    result_free(&r);
    RUN(&r, "check", path, "--json");
    expect_ok(&r);
    assert_true(jq_num(r.out, "$.scan.loops[0].length_mm") == 40);
    assert_true(jq_num(r.out, "$.scan.loops[0].span_mm2") == 100);
    assert_int_equal(jq_len(r.out, "$.scan.components"), 2);
    /* (5, 6, 40) to the rim of the wall y = 10: sqrt(4² + 30²) */
    assert_true(fabs(jq_num(r.out, "$.scan.components[1].distance_mm") - sqrt(916)) < 1e-9);
    assert_true(jq_num(r.out, "$.scan.strays.count") == 1);
    result_free(&r);
}

static void export_of_an_unknown_id_fails(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "P1", "shaft", "steel", e->cyl);
    char path[160];
    path_in(e, "x.stl", path, sizeof path);
    result r;
    RUN(&r, "--db", e->db, "export", "part", "NOPE", "--out", path);
    expect_error(&r, "no part 'NOPE'");
    result_free(&r);
    RUN(&r, "--db", e->db, "export", "instance", "99", "--out", path);
    expect_error(&r, "no instance 99");
    result_free(&r);
    assert_false(file_exists(path));

    path_in(e, "x.xyz", path, sizeof path);
    RUN(&r, "--db", e->db, "export", "part", "P1", "--out", path);
    expect_usage(&r, "expected a file ending in .stl, .obj, .ply, .off, .gltf or .glb");
    result_free(&r);
    RUN(&r, "--db", e->db, "export", "model", "P1", "--out", path);
    expect_usage(&r, "bad 'export model'");
    result_free(&r);
}

/* ------------------------------------------------------------------------------------
 * Parameter sets
 * ---------------------------------------------------------------------------------- */

static void params_list_show_and_set(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "params", "list", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(v.type, J_ARR);
    bool has_default = false;
    for (size_t i = 0; i < v.count; i++)
        has_default |= strcmp(jstr(&v.items[i], "name"), "default") == 0;
    assert_true(has_default);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "params", "show", "default", "--json");
    expect_ok(&r);
    jv def = parse_json(r.out);
    result_free(&r);

    RUN(&r, "--db", e->db, "params", "set", "fine", "--layers", "240", "--sectors", "320",
        "--json");
    expect_ok(&r);
    expect_contains(r.err, "created parameter set 'fine'");
    v = parse_json(r.out);
    assert_int_equal((int)jnum(&v, "layers"), 240);
    assert_int_equal((int)jnum(&v, "sectors"), 320);
    /* Fields not given come from "default". */
    assert_true(jnum(&v, "gamma_axis") == jnum(&def, "gamma_axis"));
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "params", "set", "fine", "--gamma-axis", "0.5");
    expect_ok(&r);
    expect_contains(r.err, "updated parameter set 'fine'");
    result_free(&r);
    RUN(&r, "--db", e->db, "params", "show", "fine", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal((int)jnum(&v, "layers"), 240);     /* kept */
    assert_true(jnum(&v, "gamma_axis") == 0.5);
    jv_release(&v);
    result_free(&r);
    jv_release(&def);

    RUN(&r, "--db", e->db, "params", "set", "fine", "--gamma-axis", "0");
    expect_usage(&r, "bad --gamma-axis '0'");
    result_free(&r);
    /* --gamma sets both, as reconstruct's --gamma does */
    RUN(&r, "--db", e->db, "params", "set", "fine", "--gamma", "0.7", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_true(jnum(&v, "gamma_axis") == 0.7 && jnum(&v, "gamma_plane") == 0.7);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "params", "show", "nonesuch");
    expect_error(&r, "no parameter set 'nonesuch'");
    result_free(&r);
}

/* ------------------------------------------------------------------------------------
 * Repair rules and materials (branch rules)
 * ---------------------------------------------------------------------------------- */

/* `rules show RULE --json`, parsed (the caller releases). */
static jv rule_json(const env *e, const char *rule)
{
    result r;
    RUN(&r, "--db", e->db, "rules", "show", rule, "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    result_free(&r);
    return v;
}

static void rules_list_show_and_set(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "rules", "list", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(v.type, J_ARR);
    assert_int_equal(v.count, 9);
    assert_string_equal(jstr(&v.items[0], "name"), "replace-beyond-25pct");
    assert_true(jnum(&v.items[0], "min_lost_fraction") == 0.25);
    assert_string_equal(jstr(&v.items[8], "process"), "manual_review");
    assert_int_equal(jget(&v.items[8], "class")->type, J_NULL);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "rules", "list");
    expect_ok(&r);
    assert_string_equal(r.err, "");
    expect_contains(r.out, "spray-small-loss");
    expect_contains(r.out, "max_depth_mm=3 max_section_fraction=0.05");
    result_free(&r);

    v = rule_json(e, "spray-small-loss");
    assert_true(jnum(&v, "max_depth_mm") == 3);
    assert_int_equal(jget(&v, "updated_at")->type, J_NULL);
    char id[32];
    snprintf(id, sizeof id, "%d", (int)jnum(&v, "id"));
    jv_release(&v);

    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "max_depth_mm", "2.5");
    expect_ok(&r);
    assert_string_equal(r.err, "symrec: updated rule 'spray-small-loss': max_depth_mm = 2.5\n");
    expect_contains(r.out, "max_depth_mm:         2.5");
    result_free(&r);
    v = rule_json(e, id);   /* by id */
    assert_string_equal(jstr(&v, "name"), "spray-small-loss");
    assert_true(jnum(&v, "max_depth_mm") == 2.5);
    assert_int_equal(jget(&v, "updated_at")->type, J_STR);
    jv_release(&v);

    RUN(&r, "--db", e->db, "rules", "set", id, "max_depth_mm", "null", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(jget(&v, "max_depth_mm")->type, J_NULL);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "rules", "set", "wear-band-spray", "parameters_json",
        "{\"layer_mm\":0.2}", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_string_equal(jstr(&v, "parameters_json"), "{\"layer_mm\":0.2}");
    jv_release(&v);
    result_free(&r);
}

static void rules_set_errors_change_nothing(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result before, r, after;
    RUN(&before, "--db", e->db, "rules", "show", "spray-small-loss", "--json");
    expect_ok(&before);

    RUN(&r, "--db", e->db, "rules", "set", "nonesuch", "priority", "1");
    expect_error(&r, "no rule 'nonesuch' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "show", "nonesuch");
    expect_error(&r, "no rule 'nonesuch' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "depth", "1");
    expect_usage(&r, "unknown rule field 'depth'");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "max_depth_mm", "deep");
    expect_error(&r, "bad max_depth_mm 'deep': expected a number or null");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "max_depth_mm", "--", "-1");
    expect_error(&r, "bad max_depth_mm -1: expected a number >= 0");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "min_depth_mm", "4");
    expect_error(&r, "bad min_depth_mm 4: greater than max_depth_mm 3");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "process", "null");
    expect_error(&r, "field 'process' cannot be null");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "class", "dent");
    expect_error(&r, "bad class 'dent': expected one of chip, gouge, wear_band");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "set", "spray-small-loss", "max_depth_mm");
    expect_usage(&r, NULL);
    result_free(&r);

    RUN(&after, "--db", e->db, "rules", "show", "spray-small-loss", "--json");
    expect_ok(&after);
    assert_string_equal(before.out, after.out);
    result_free(&before);
    result_free(&after);
}

static void rules_add_enable_and_disable(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "rules", "add", "shop-weld", "--process", "weld_buildup", "--reason",
        "our welder", "--source", "shop practice", "--priority", "5", "--json");
    expect_ok(&r);
    expect_contains(r.err, "added rule 'shop-weld'");
    jv v = parse_json(r.out);
    assert_true(jnum(&v, "priority") == 5);
    assert_true(jnum(&v, "enabled") == 1);
    assert_string_equal(jstr(&v, "scope"), "section");
    jv_release(&v);
    result_free(&r);

    RUN(&r, "--db", e->db, "rules", "add", "SHOP-WELD", "--process", "ded", "--reason", "x",
        "--source", "y");
    expect_error(&r, "rule 'SHOP-WELD' already exists");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "add", "other", "--process", "glue", "--reason", "x",
        "--source", "y");
    expect_error(&r, "bad process 'glue'");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "add", "other", "--reason", "x");
    expect_usage(&r, "needs --process, --reason and --source");
    result_free(&r);

    RUN(&r, "--db", e->db, "rules", "disable", "shop-weld");
    expect_ok(&r);
    assert_string_equal(r.err, "symrec: disabled rule 'shop-weld'\n");
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "list", "--enabled", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(v.count, 9);
    for (size_t i = 0; i < v.count; i++)
        assert_string_not_equal(jstr(&v.items[i], "name"), "shop-weld");
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "enable", "shop-weld", "--json");
    expect_ok(&r);
    v = parse_json(r.out); /* the rule as stored, enabled */
    assert_string_equal(jstr(&v, "name"), "shop-weld");
    assert_true(jnum(&v, "enabled") == 1);
    jv_release(&v);
    result_free(&r);
    v = rule_json(e, "shop-weld");
    assert_true(jnum(&v, "enabled") == 1);
    jv_release(&v);
    RUN(&r, "--db", e->db, "rules", "enable", "nonesuch");
    expect_error(&r, "no rule 'nonesuch'");
    result_free(&r);
}

static void materials_list_shows_the_seeded_materials(void **state)
{
    const env *e = *state;
    create_catalog(e, false); /* the seeded materials only */
    result r;
    RUN(&r, "--db", e->db, "materials", "list", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(v.count, 9);
    assert_string_equal(jstr(&v.items[0], "name"), "42CrMo4");
    assert_true(jnum(&v.items[0], "density_g_cm3") == 7.85);
    assert_string_equal(jstr(&v.items[0], "family"), "steel");
    assert_int_equal(jget(&v.items[0], "limits")->count, 3);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "materials", "list");
    expect_ok(&r);
    expect_contains(r.out, "EN-GJL-250");
    expect_contains(r.out, "ded <= 3 mm, spray_forming, -weld_buildup");
    result_free(&r);
    RUN(&r, "--db", e->db, "materials", "show");
    expect_usage(&r, "unknown subcommand 'materials show'");
    result_free(&r);
}

/* ------------------------------------------------------------------------------------
 * Demo and fixtures
 * ---------------------------------------------------------------------------------- */

static size_t json_array_count(const char *text)
{
    jv v = parse_json(text);
    assert_int_equal(v.type, J_ARR);
    size_t n = v.count;
    jv_release(&v);
    return n;
}

/* The README's main job: look-up, reconstruction recorded with features and advice, the
 * build plan, the report and the history, all from one `symrec demo`. */
static void demo_runs_the_whole_job(void **state)
{
    const env *e = *state;
    char out[600], path[700];
    snprintf(out, sizeof out, "%s/demo-out", e->dir);
    result r;
    RUN(&r, "--db", e->db, "demo", "--out", out, "--part", "SR-RAIL-04");
    expect_ok(&r);
    expect_contains(r.out, "== The whole job on SR-RAIL-04");
    expect_contains(r.out, "run 1 recorded");
    expect_contains(r.out, "advice:");
    expect_contains(r.out, "build plan of run 1");
    expect_contains(r.out, "report of run 1 written");
    expect_contains(r.out, "SR-RAIL-04  SN-24-0901");   /* the history row */
    result_free(&r);
    const char *files[] = {"run/restored.stl", "run/patches.stl", "run/result.glb",
                           "plan/plan.json", "plan/plan.gcode", "plan/layer_001.svg",
                           "report.html"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", out, files[i]);
        assert_true(file_exists(path));
    }
    RUN(&r, "--db", e->db, "demo", "--part", "NO-SUCH-PART", "--out", out);
    expect_usage(&r, "bad --part 'NO-SUCH-PART'");
    result_free(&r);
}

static void demo_builds_the_catalogue_and_is_idempotent(void **state)
{
    const env *e = *state;
    size_t count = sr_demo_part_count();
    assert_true(count > 0);
    result r;
    RUN(&r, "--db", e->db, "demo", "--catalog-only");
    expect_ok(&r);
    for (size_t i = 0; i < count; i++) {
        const sr_demo_part *dp = sr_demo_part_get(i);
        char head[96];
        snprintf(head, sizeof head, "\npart %s (id ", dp->number);
        expect_contains(r.out, head);
        expect_contains(r.out, dp->serial);
        expect_contains(r.out, dp->material);
    }
    expect_contains(r.out, "volume mm³");
    expect_contains(r.out, "missing mm³");
    char added[128];
    snprintf(added, sizeof added, "added %zu parts and %zu damaged instances", count, count);
    expect_contains(r.err, added);
    char *first_out = r.out;
    free(r.err);

    char *parts1 = part_list_json(e);
    assert_int_equal(json_array_count(parts1), count);
    RUN(&r, "--db", e->db, "instance", "list", "--json");
    expect_ok(&r);
    assert_int_equal(json_array_count(r.out), count);
    result_free(&r);

    /* Again: nothing added, the same catalogue shown. */
    RUN(&r, "--db", e->db, "demo", "--catalog-only");
    expect_ok(&r);
    expect_contains(r.err, "added 0 parts and 0 damaged instances");
    assert_string_equal(r.out, first_out);
    result_free(&r);
    free(first_out);
    char *parts2 = part_list_json(e);
    assert_string_equal(parts1, parts2);
    free(parts1);
    free(parts2);

    /* Each demo part carries its symmetry and its missing volume is positive. */
    for (size_t i = 0; i < count; i++) {
        const sr_demo_part *dp = sr_demo_part_get(i);
        RUN(&r, "--db", e->db, "part", "show", dp->number, "--json");
        expect_ok(&r);
        jv v = parse_json(r.out);
        const jv *sym = jget(&v, "symmetry");
        assert_string_equal(jstr(sym, "kind"), sr_sym_kind_name((sr_sym_kind)dp->sym_kind));
        const jv *insts = jget(&v, "instances");
        assert_int_equal(insts->count, 1);
        assert_string_equal(jstr(&insts->items[0], "serial"), dp->serial);
        assert_true(jnum(&v, "volume_mm3") > jnum(&insts->items[0], "volume_mm3"));
        jv_release(&v);
        result_free(&r);
    }
}

static void fixtures_write_meshes_whose_volumes_match_volumes_json(void **state)
{
    const env *e = *state;
    char dir[160], path[512];
    path_in(e, "fx/nested", dir, sizeof dir);
    result r;
    RUN(&r, "fixtures", "--out", dir);
    expect_ok(&r);
    expect_contains(r.out, "missing mm³");
    result_free(&r);

    snprintf(path, sizeof path, "%s/volumes.json", dir);
    char *text = read_text(path);
    assert_non_null(text);
    /* --json prints the same object */
    RUN(&r, "fixtures", "--out", dir, "--json");
    expect_ok(&r);
    assert_string_equal(r.out, text);
    result_free(&r);
    jv v = parse_json(text);
    free(text);
    assert_string_equal(jstr(&v, "units"), "mm3");
    const jv *parts = jget(&v, "parts");
    size_t count = sr_demo_part_count();
    assert_int_equal(parts->count, count);
    for (size_t i = 0; i < count; i++) {
        const sr_demo_part *dp = sr_demo_part_get(i);
        const jv *p = &parts->items[i];
        assert_string_equal(jstr(p, "number"), dp->number);
        sr_mesh mi, md, bi, bd;
        sr_mesh_init(&mi);
        sr_mesh_init(&md);
        sr_mesh_init(&bi);
        sr_mesh_init(&bd);
        char want[160];
        snprintf(want, sizeof want, "%s_intact.stl", dp->number);
        assert_string_equal(jstr(p, "intact_file"), want);
        snprintf(path, sizeof path, "%s/%s", dir, want);
        assert_int_equal(sr_mesh_read(path, &mi, NULL), SR_OK);
        snprintf(want, sizeof want, "%s_damaged.stl", dp->number);
        assert_string_equal(jstr(p, "damaged_file"), want);
        snprintf(path, sizeof path, "%s/%s", dir, want);
        assert_int_equal(sr_mesh_read(path, &md, NULL), SR_OK);

        /* The numbers are those of the files, to the last bit. */
        double vi = sr_mesh_volume(&mi), vd = sr_mesh_volume(&md);
        assert_true(jnum(p, "intact_mm3") == vi);
        assert_true(jnum(p, "damaged_mm3") == vd);
        assert_true(jnum(p, "missing_mm3") == vi - vd);
        assert_true(vi - vd > 0);
        assert_int_equal((size_t)jnum(p, "intact_triangles"), mi.tri_count);

        /* And they are the demo part's volumes up to float32 rounding of the STL. */
        assert_int_equal(sr_demo_part_build(i, &bi, &bd, NULL), SR_OK);
        assert_true(fabs(vi - sr_mesh_volume(&bi)) <= 1e-5 * vi);
        assert_true(fabs(vd - sr_mesh_volume(&bd)) <= 1e-5 * vd);
        sr_mesh_release(&mi);
        sr_mesh_release(&md);
        sr_mesh_release(&bi);
        sr_mesh_release(&bd);
    }
    jv_release(&v);
}

/* ------------------------------------------------------------------------------------
 * Reconstruction runs: recording (reconstruct), run list/show, compare, bad input
 * ---------------------------------------------------------------------------------- */

/* Rows of one table, counted on a raw connection. */
static int64_t table_rows(const env *e, const char *table)
{
    sqlite3 *db = NULL;
    assert_int_equal(sqlite3_open_v2(e->db, &db, SQLITE_OPEN_READONLY, NULL), SQLITE_OK);
    char sql[128];
    snprintf(sql, sizeof sql, "SELECT count(*) FROM %s", table);
    sqlite3_stmt *stmt = NULL;
    if (sqlite3_prepare_v2(db, sql, -1, &stmt, NULL) != SQLITE_OK)
        fail_msg("%s: %s", sql, sqlite3_errmsg(db));
    assert_int_equal(sqlite3_step(stmt), SQLITE_ROW);
    int64_t n = sqlite3_column_int64(stmt, 0);
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return n;
}

/* Rows in every table a run writes, as one comparable string. */
static void run_rows(const env *e, char *out, size_t size)
{
    snprintf(out, size, "runs %lld layers %lld sections %lld advice %lld meshes %lld",
             (long long)table_rows(e, "runs"), (long long)table_rows(e, "run_layers"),
             (long long)table_rows(e, "sections"), (long long)table_rows(e, "advice"),
             (long long)table_rows(e, "meshes"));
}

/* Failed with exit 1 and nothing on stdout after the progress note: stderr is the
 * "reconstructing ..." line, then one error line containing `needle`. */
static void expect_failure_after_progress(const result *r, const char *needle)
{
    if (r->code != 1)
        fail_msg("expected exit 1, got %d; stderr: %s", r->code, r->err);
    assert_string_equal(r->out, "");
    const char *nl = strchr(r->err, '\n');
    if (strncmp(r->err, "symrec: reconstructing ", 23) != 0 || !nl)
        fail_msg("stderr does not start with the progress note: %s", r->err);
    expect_one_line(nl + 1, "error", needle);
}

/* The demo catalogue's first three parts, built in-process (a process fewer per test):
 * instance 1 the chipped shaft, 2 the gouged bushing, 3 the broken bracket (mirror). */
static void make_demo(const env *e)
{
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    if (sr_catalog_open(e->db, SR_CATALOG_CREATE, &cat, &err) != SR_OK)
        fail_msg("cannot create %s: %s", e->db, err.msg);
    add_test_materials(cat);
    for (size_t i = 0; i < 3; i++) {
        const sr_demo_part *dp = sr_demo_part_get(i);
        sr_mesh intact, damaged;
        assert_int_equal(sr_demo_part_build(i, &intact, &damaged, &err), SR_OK);
        sr_part_new part = {.number = dp->number, .name = dp->name, .material = dp->material,
                            .mesh = &intact,
                            .symmetry = {(sr_sym_kind)dp->sym_kind, dp->sym_order,
                                         dp->sym_shift_mm}};
        int64_t id;
        assert_int_equal(sr_catalog_part_add(cat, &part, &id, &err), SR_OK);
        sr_instance_new inst = {.part = dp->number, .mesh = &damaged, .serial = dp->serial};
        assert_int_equal(sr_catalog_instance_add(cat, &inst, &id, &err), SR_OK);
        assert_int_equal(id, (int64_t)i + 1);
        sr_mesh_release(&intact);
        sr_mesh_release(&damaged);
    }
    sr_catalog_close(cat);
}

static void reconstruct_of_an_instance_records_a_run_that_run_list_and_show_return(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    /* --no-union: the boolean is the reconstruction's business (and slow under
     * valgrind); the record is the same either way */
    RUN(&r, "--db", e->db, "reconstruct", "1", "--params", "coarse", "--no-union", "--json");
    expect_ok(&r);
    jv rec = parse_json(r.out);
    result_free(&r);
    const jv *run_id = jget(&rec, "run_id");
    assert_int_equal(run_id->type, J_NUM);
    long id = (long)run_id->num;
    assert_true(id >= 1);
    assert_string_equal(jstr(jget(&rec, "params"), "name"), "coarse");
    assert_int_equal((int)jnum(&rec, "layers"), 80);
    /* the demo scan is clean: nothing crossed, nothing moved */
    assert_int_equal((int)jnum(jget(&rec, "scan_folds"), "crossing_pairs"), 0);
    assert_int_equal((int)jnum(jget(&rec, "scan_folds"), "vertices_moved"), 0);
    /* every section the vote found was built */
    assert_int_equal((int)jnum(jget(&rec, "image"), "unbuilt_sections"), 0);
    const jv *secs = jget(&rec, "sections");
    assert_true(secs->count >= 1);
    /* the image method's phases: its vote and clipping inside the analysis, every
     * phase inside the total */
    const jv *tm = jget(&rec, "timings");
    assert_true(jnum(tm, "vote_s") > 0);
    assert_true(jnum(tm, "clip_s") > 0);
    assert_true(jnum(tm, "vote_s") + jnum(tm, "clip_s") + jnum(tm, "continue_s") <=
                jnum(tm, "analyse_s") + 1e-6);
    assert_true(jnum(tm, "align_s") + jnum(tm, "unfold_s") + jnum(tm, "analyse_s") +
                    jnum(tm, "union_s") + jnum(tm, "finish_s") <=
                jnum(tm, "total_s") + 1e-6);
    /* the input's own steps, timed apart from the method's: the catalogue's mesh read,
     * then described as a scan */
    assert_true(jnum(tm, "read_s") > 0);
    assert_true(jnum(tm, "scan_s") > 0);
    char ids[32];
    snprintf(ids, sizeof ids, "%ld", id);

    RUN(&r, "--db", e->db, "run", "list", "--json");
    expect_ok(&r);
    jv list = parse_json(r.out);
    result_free(&r);
    assert_int_equal(list.type, J_ARR);
    assert_int_equal(list.count, 1);
    const jv *row = &list.items[0];
    assert_int_equal((long)jnum(row, "id"), id);
    assert_int_equal((long)jnum(row, "instance_id"), 1);
    assert_string_equal(jstr(row, "part_number"), "SR-SHAFT-01");
    assert_string_equal(jstr(row, "status"), "ok");
    assert_int_equal((size_t)jnum(row, "sections"), secs->count);
    assert_int_equal((int)jnum(row, "unbuilt_sections"), 0); /* every section found built */
    double total = 0;
    for (size_t i = 0; i < secs->count; i++)
        total += jnum(&secs->items[i], "volume_mm3");
    assert_near(jnum(row, "missing_volume_mm3"), total, 1e-9 * total);
    jv_release(&list);

    RUN(&r, "--db", e->db, "run", "show", ids, "--json");
    expect_ok(&r);
    jv show = parse_json(r.out);
    result_free(&r);
    assert_int_equal((long)jnum(&show, "id"), id);
    assert_string_equal(jstr(&show, "status"), "ok");
    assert_string_equal(jstr(&show, "method"), "image");  /* the default method */
    assert_string_equal(jstr(&show, "software_version"), SR_VERSION);
    assert_string_equal(jstr(jget(&show, "symmetry"), "kind"), "axial");
    assert_int_equal((int)jnum(jget(&show, "params"), "sectors"), 60);
    const jv *align = jget(&show, "alignment");
    assert_int_equal(jget(align, "transform")->count, 12);
    assert_near(jnum(align, "fit_quality"), jnum(jget(&rec, "alignment"), "fit_score"), 0);
    const jv *rec_xf = jget(jget(&rec, "alignment"), "transform");
    for (size_t i = 0; i < 12; i++)
        assert_true(jget(align, "transform")->items[i].num == rec_xf->items[i].num);
    assert_int_equal(jget(&show, "timings")->type, J_OBJ);
    assert_true(jnum(jget(&show, "timings"), "total") >= jnum(jget(&show, "timings"), "vote"));
    /* stored to six significant digits (run_build.c): 20 s of vote under a loaded
     * Memcheck read back 1.5e-5 off */
    assert_near(jnum(jget(&show, "timings"), "vote"), jnum(tm, "vote_s"),
                5e-6 * fabs(jnum(tm, "vote_s")) + 1e-9);
    assert_true(jnum(jget(&show, "restored_mesh"), "triangles") > 0);
    const jv *ssecs = jget(&show, "sections");
    assert_int_equal(ssecs->count, secs->count);
    for (size_t i = 0; i < secs->count; i++) {
        const jv *f = jget(&ssecs->items[i], "features");
        const jv *want = &secs->items[i];
        /* the same doubles, printed the same shortest way */
        assert_true(jnum(f, "volume_mm3") == jnum(want, "volume_mm3"));
        assert_true(jnum(f, "area_mm2") == jnum(want, "area_mm2"));
        assert_true(jnum(f, "depth_max_mm") == jnum(want, "depth_max_mm"));
        assert_true(jnum(f, "depth_mean_mm") == jnum(want, "depth_mean_mm"));
        assert_true(jnum(f, "z_min_mm") == jnum(want, "z_min_mm"));
        assert_true(jnum(f, "z_max_mm") == jnum(want, "z_max_mm"));
        assert_true(jnum(f, "angle_min_deg") == jnum(want, "angle_min_deg"));
        assert_true(jnum(f, "angle_max_deg") == jnum(want, "angle_max_deg"));
        /* classified by the features engine (section_features.h), one of its classes */
        const char *cls = jstr(f, "class");
        assert_true(strcmp(cls, "chip") == 0 || strcmp(cls, "gouge") == 0 ||
                    strcmp(cls, "wear_band") == 0 || strcmp(cls, "broken_feature") == 0 ||
                    strcmp(cls, "crack") == 0);
        assert_int_equal((long)jnum(&ssecs->items[i], "index"), (long)jnum(want, "index"));
        assert_int_equal((long)jnum(&ssecs->items[i], "patch_triangles"),
                         (long)jnum(want, "patch_triangles"));
    }
    assert_int_equal(jget(&show, "advice")->type, J_ARR);
    jv_release(&show);
    jv_release(&rec);

    /* --layers adds every layer's outline pair */
    RUN(&r, "--db", e->db, "run", "show", ids, "--json", "--layers");
    expect_ok(&r);
    show = parse_json(r.out);
    result_free(&r);
    const jv *layers = jget(&show, "layers");
    assert_int_equal(layers->count, 80);
    assert_int_equal(jget(&layers->items[0], "damaged")->count, 60);
    assert_int_equal(jget(&layers->items[79], "restored")->count, 60);
    jv_release(&show);

    /* the human forms */
    RUN(&r, "--db", e->db, "run", "show", ids);
    expect_ok(&r);
    expect_contains(r.out, "instance 1 of part SR-SHAFT-01, ok");
    expect_contains(r.out, "set 'coarse': 80 layers, 60 sectors");
    expect_contains(r.out, "advice:");
    expect_contains(r.out, "reasons");
    expect_contains(r.out, "timings:     align ");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list");
    expect_ok(&r);
    expect_contains(r.out, "missing mm³");
    expect_contains(r.out, "SR-SHAFT-01");
    expect_contains(r.out, "SN-24-0117");
    result_free(&r);
    RUN(&r, "--db", e->db, "catalog", "info", "--json");
    expect_ok(&r);
    jv info = parse_json(r.out);
    assert_int_equal((int)jnum(&info, "runs"), 1);
    jv_release(&info);
    result_free(&r);
}

static void reconstruct_prints_run_recorded_and_no_record_records_none(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--params", "coarse", "--no-union");
    expect_ok(&r);
    expect_contains(r.out, "\nrun 1 recorded\n");
    result_free(&r);
    char before[256], after[256];
    run_rows(e, before, sizeof before);
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--params", "coarse", "--no-union",
        "--no-record", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(jget(&v, "run_id")->type, J_NULL);
    jv_release(&v);
    result_free(&r);
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);
    /* --mesh runs are never recorded */
    char mesh[160];
    path_in(e, "shaft.stl", mesh, sizeof mesh);
    RUN(&r, "--db", e->db, "export", "instance", "1", "--out", mesh);
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", mesh, "--symmetry", "axial", "--layers", "40",
        "--sectors", "60", "--no-union", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(jget(&v, "run_id")->type, J_NULL);
    assert_string_equal(jstr(jget(&v, "params"), "name"), "default");
    assert_int_equal((int)jnum(jget(&v, "params"), "layers"), 40);
    jv_release(&v);
    result_free(&r);
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);
}

/* A --mesh run (no instance, never recorded) gets the features and advice an instance
 * run gets, in the lines `run show` prints and in --json: from the --db catalogue's
 * rules, read only, when the file exists, else from the built-in seeded rules (and no
 * catalogue file is created). */
static void reconstruct_of_a_mesh_file_prints_features_and_advice(void **state)
{
    const env *e = *state;
    make_demo(e);
    char mesh[160], before[256], after[256], none[200];
    path_in(e, "shaft.stl", mesh, sizeof mesh);
    path_in(e, "no-such.db", none, sizeof none);
    result r;
    RUN(&r, "--db", e->db, "export", "instance", "1", "--out", mesh);
    expect_ok(&r);
    result_free(&r);
    run_rows(e, before, sizeof before);
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", mesh, "--symmetry", "axial", "--layers", "40",
        "--sectors", "60", "--no-union");
    expect_ok(&r);
    expect_contains(r.out, "\n    features of 1: {\"class\":\"");
    expect_contains(r.out, "\n  advice:\n    section 1: ");
    assert_null(strstr(r.out, "recorded"));
    result_free(&r);
    RUN(&r, "--db", none, "reconstruct", "--mesh", mesh, "--symmetry", "axial", "--layers", "40",
        "--sectors", "60", "--no-union", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(jget(&v, "run_id")->type, J_NULL);
    const jv *secs = jget(&v, "sections");
    assert_true(secs->count >= 1);
    const jv *feat = jget(&secs->items[0], "features");
    assert_int_equal(feat->type, J_OBJ);
    assert_string_equal(jstr(feat, "class"), jstr(&secs->items[0], "class"));
    const jv *adv = jget(&v, "advice");
    assert_int_equal(adv->type, J_ARR);
    assert_true(adv->count >= 1);
    assert_int_equal((int)jnum(&adv->items[adv->count - 1], "section"), (int)secs->count);
    assert_true(strlen(jstr(&adv->items[0], "process")) > 0);
    jv_release(&v);
    result_free(&r);
    assert_false(file_exists(none));
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);
}

/* --order auto (issue 6 item 4): a hexagonal prism is found 6-fold and restored with
 * that order; a round demo shaft is found continuous and its run records order 0 (not
 * "auto"); a catalogue part keeps only orders, so 'part add --order auto' is refused. */
static void reconstruct_order_auto_finds_and_records_the_order(void **state)
{
    const env *e = *state;
    make_demo(e);
    double hex[12];
    for (int k = 0; k < 6; k++) {
        hex[2 * k] = 12 * cos(M_PI / 3 * k + 0.2);
        hex[2 * k + 1] = 12 * sin(M_PI / 3 * k + 0.2);
    }
    sr_mesh m = {0};
    assert_int_equal(sr_shape_prism(hex, 6, 0, 10, &m, NULL), SR_OK);
    char path[160];
    path_in(e, "hex.stl", path, sizeof path);
    write_mesh_file(path, &m);
    sr_mesh_release(&m);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", path, "--symmetry", "axial", "--order",
        "auto", "--layers", "20", "--sectors", "120", "--no-union", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal((int)jnum(jget(&v, "symmetry"), "order"), 6);
    const jv *od = jget(&v, "order_detection");
    assert_int_equal((int)jnum(od, "order"), 6);
    assert_int_equal(jget(od, "round")->type, J_BOOL);
    assert_false(jget(od, "round")->b);
    assert_true(jnum(od, "mismatch_mm") < 0.05 && jnum(od, "base_mismatch_mm") > 0.5);
    assert_int_equal((int)jget(&v, "sections")->count, 0);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", path, "--symmetry", "axial", "--order",
        "auto", "--layers", "20", "--sectors", "120", "--no-union");
    expect_ok(&r);
    expect_contains(r.out, "  order:      6-fold, found (mismatch turned by 60.00 deg: ");
    result_free(&r);

    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--symmetry", "axial", "--order",
        "auto", "--params", "coarse", "--no-union", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal((int)jnum(jget(&v, "symmetry"), "order"), 0);
    assert_true(jget(jget(&v, "order_detection"), "round")->b);
    char ids[32];
    snprintf(ids, sizeof ids, "%ld", (long)jnum(&v, "run_id"));
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show", ids, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_string_equal(jstr(jget(&v, "symmetry"), "kind"), "axial");
    assert_int_equal((int)jnum(jget(&v, "symmetry"), "order"), 0);
    jv_release(&v);
    result_free(&r);
    expect_bad_symmetry(e, "axial", "--order", "auto",
                        "bad --order 'auto': expected an integer 2..360 (or 0 for continuous)");
}

static void reconstruct_params_and_overrides_are_recorded(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--params", "coarse", "--layers",
        "50", "--gamma", "0.9", "--min-depth", "0.25", "--no-union", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    char ids[32];
    snprintf(ids, sizeof ids, "%ld", (long)jnum(&v, "run_id"));
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show", ids, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    const jv *p = jget(&v, "params");
    assert_string_equal(jstr(p, "name"), "coarse");
    assert_int_equal((int)jnum(p, "layers"), 50);
    assert_int_equal((int)jnum(p, "sectors"), 60);
    assert_near(jnum(p, "gamma_axis"), 0.9, 0);
    assert_near(jnum(p, "gamma_plane"), 0.9, 0);
    assert_near(jnum(p, "min_depth_mm"), 0.25, 0);
    assert_near(jnum(p, "delta_d"), 0.05, 0);
    jv_release(&v);
    result_free(&r);
}

/* Sections of `reconstruct 1 --params NAME --no-union --no-record --json`. */
static size_t sections_with(const env *e, const char *params)
{
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--params", params, "--no-union",
        "--no-record", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    size_t n = jget(&v, "sections")->count;
    jv_release(&v);
    result_free(&r);
    return n;
}

/* The set's min_volume_mm3 and min_depth_mm reach the reconstruction: the chipped
 * shaft's sections, found with 'coarse', are all dropped by a set otherwise alike whose
 * smallest section is larger than the part (or deeper than its radius). */
static void reconstruct_applies_the_sets_min_volume_and_min_depth(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "params", "set", "huge", "--layers", "80", "--sectors", "60",
        "--min-volume", "1e9");
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "params", "set", "deep", "--layers", "80", "--sectors", "60",
        "--min-depth", "1e5");
    expect_ok(&r);
    result_free(&r);
    assert_true(sections_with(e, "coarse") >= 1);
    assert_int_equal(sections_with(e, "huge"), 0);
    assert_int_equal(sections_with(e, "deep"), 0);
}

static void a_failed_reconstruct_records_nothing(void **state)
{
    const env *e = *state;
    make_demo(e);
    char before[256], after[256];
    run_rows(e, before, sizeof before);
    /* the output folder cannot be made (a file is in the way): refused before the
     * reconstruction */
    char blocker[160], out[200];
    path_in(e, "blocker", blocker, sizeof blocker);
    write_bytes(blocker, "x", 1);
    snprintf(out, sizeof out, "%s/sub", blocker);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--params", "coarse", "--no-union", "--out", out);
    expect_error(&r, "cannot write the output folder '");
    result_free(&r);
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);
    /* writing the output set fails after the reconstruction (the test hook of
     * cli/outset.h, as a full disk would): nothing is recorded */
    path_in(e, "out", out, sizeof out);
    setenv("SYMREC_TEST_OUTSET_FAIL", "1", 1);
    RUN(&r, "--db", e->db, "reconstruct", "1", "--params", "coarse", "--no-union", "--out", out);
    unsetenv("SYMREC_TEST_OUTSET_FAIL");
    expect_failure_after_progress(&r, "cannot write the output folder '");
    result_free(&r);
    assert_false(file_exists(out));
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);

    /* a scan whose triangles have no area: the reconstruction itself fails */
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(e->db, 0, &cat, &err), SR_OK);
    double xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
    uint32_t tri[] = {0, 1, 2, 1, 2, 3};
    sr_mesh flat = {xyz, tri, 4, 2};
    sr_instance_new in = {.part = "SR-SHAFT-01", .mesh = &flat, .serial = "FLAT"};
    int64_t id;
    assert_int_equal(sr_catalog_instance_add(cat, &in, &id, &err), SR_OK);
    sr_catalog_close(cat);
    run_rows(e, before, sizeof before);
    char ids[32];
    snprintf(ids, sizeof ids, "%lld", (long long)id);
    RUN(&r, "--db", e->db, "reconstruct", ids, "--params", "coarse");
    expect_failure_after_progress(&r, "no triangle with an area");
    result_free(&r);
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);
}

static void reconstruct_refuses_bad_input(void **state)
{
    const env *e = *state;
    make_demo(e);
    char before[256], after[256];
    run_rows(e, before, sizeof before);
    static const struct {
        const char *a, *b;
        int code;
        const char *msg;
    } cases[] = {
        {"--layers", "0", 2, "bad --layers '0'"},
        {"--sectors", "0", 2, "bad --sectors '0'"},
        {"--sectors", "2", 2, "bad --sectors '2'"},
        {"--gamma", "0", 2, "bad --gamma '0'"},
        {"--gamma", "1.5", 2, "bad --gamma '1.5'"},
        {"--min-depth", "-0.5", 2, "bad --min-depth '-0.5'"},
        {"--params", "", 2, "bad --params ''"},
        {"--params", "nope", 1, "no parameter set 'nope' in the catalogue"},
        {"--format", "xyz", 2, "bad --format 'xyz'"},
    };
    const size_t n = sizeof cases / sizeof cases[0];
    for (size_t i = 0; i < n; i++) {
        if (sampled_out(i, n))
            continue;
        result r;
        RUN(&r, "--db", e->db, "reconstruct", "1", cases[i].a, cases[i].b);
        if (cases[i].code == 2)
            expect_usage(&r, cases[i].msg);
        else
            expect_error(&r, cases[i].msg);
        result_free(&r);
    }
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "99");
    expect_error(&r, "no instance 99 in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", "x1");
    expect_usage(&r, "INSTANCE");
    result_free(&r);
    run_rows(e, after, sizeof after);
    assert_string_equal(after, before);
}

/* Long work tells where it is on stderr: one plain line per phase when stderr is not a
 * terminal (the delay of a second set to 0 here), a bar redrawn in place on a terminal
 * (a pty through script(1)), nothing with --quiet; the result on stdout is the same. */
static void reconstruct_shows_progress_by_phase_unless_quiet(void **state)
{
    const env *e = *state;
    setenv("SYMREC_PROGRESS_AFTER", "0", 1);
    result r;
    RUN(&r, "reconstruct", "--mesh", e->cyl, "--symmetry", "axial", "--no-record", "--json");
    expect_ok(&r);
    const char *phases[] = {"unfold (1/7)",   "align (2/7)", "slice (3/7)", "sections (4/7)",
                            "continue (5/7)", "union (6/7)", "finish (7/7)"};
    const char *at = r.err;
    for (size_t i = 0; i < sizeof phases / sizeof phases[0]; i++) {
        char want[64];
        snprintf(want, sizeof want, "symrec: reconstruct: %s at ", phases[i]);
        const char *hit = strstr(at, want);
        if (!hit)
            fail_msg("no '%s' after the earlier phases in:\n%s", want, r.err);
        at = hit;
    }
    expect_contains(r.err, "symrec: reconstruct: done in ");
    char *loud = r.out;
    r.out = NULL;
    result_free(&r);

    /* --quiet, after the command like any global option: no progress, no notes */
    RUN(&r, "reconstruct", "--mesh", e->cyl, "--symmetry", "axial", "--no-record", "--json",
        "--quiet");
    expect_ok(&r);
    assert_string_equal(r.err, "");
    /* the same answer (the times may differ) */
    jv quiet = parse_json(r.out), was = parse_json(loud);
    assert_true(jnum(&quiet, "patch_volume_mm3") == jnum(&was, "patch_volume_mm3"));
    assert_int_equal(jget(&quiet, "sections")->count, jget(&was, "sections")->count);
    jv_release(&quiet);
    jv_release(&was);
    result_free(&r);
    free(loud);

    /* on a terminal: the bar, redrawn in place, and cleared at the end */
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s reconstruct --mesh %s --symmetry axial --no-record >/dev/null",
             sr_test_bin(), e->cyl);
    const char *argv[] = {"script", "-qfec", cmd, "/dev/null", NULL};
    char *out = NULL, *err = NULL;
    int rc = sr_test_run_native(argv, NULL, &out, &err);
    if (rc == -1 || (out && strstr(out, "not found"))) {
        free(out);
        free(err);
        unsetenv("SYMREC_PROGRESS_AFTER");
        skip(); /* no script(1): util-linux's bsdutils is essential on Debian */
    }
    assert_int_equal(rc, 0);
    expect_contains(out, "\r\033[Ksymrec: reconstruct [");
    expect_contains(out, "] 6/7 union ");
    assert_null(strstr(out, "symrec: reconstruct: union (")); /* no plain lines */
    free(out);
    free(err);
    unsetenv("SYMREC_PROGRESS_AFTER");
}

/* Global options may follow the command. */
static void global_options_may_follow_the_command(void **state)
{
    const env *e = *state;
    init_catalog(e);
    add_part(e, "SH-1", "shaft", "steel", e->cyl);
    result r;
    RUN(&r, "part", "list", "--db", e->db, "--json");
    expect_ok(&r);
    expect_contains(r.out, "\"SH-1\"");
    result_free(&r);
    char eq[160];
    snprintf(eq, sizeof eq, "--db=%s", e->db);
    RUN(&r, "part", "show", "SH-1", eq, "-q");
    expect_ok(&r);
    expect_contains(r.out, "SH-1");
    result_free(&r);
    RUN(&r, "part", "list", "--db");
    expect_usage(&r, "option '--db' needs a file name");
    result_free(&r);
}

static long add_chipped_run(const env *e);

/* The JSON names agree across commands: a run's id is "run_id" in run show and list as in
 * reconstruct; "source" of a mesh file is its path (no quotes), with mesh_file and
 * instance_id beside it; a rule's parameters are an object; reconstruct takes the
 * thresholds by the names params set uses. */
static void json_names_agree_across_commands(void **state)
{
    const env *e = *state;
    long id = add_chipped_run(e); /* a catalogue with one run */
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "--mesh", e->cyl, "--symmetry", "axial", "--no-record",
        "--params", "default", "--gamma-axis", "0.8", "--gamma-plane", "0.6", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_string_equal(jstr(&v, "source"), e->cyl);
    assert_string_equal(jstr(&v, "mesh_file"), e->cyl);
    assert_int_equal(jget(&v, "instance_id")->type, J_NULL);
    assert_true(jnum(jget(&v, "params"), "gamma_axis") == 0.8);
    assert_true(jnum(jget(&v, "params"), "gamma_plane") == 0.6);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "rules", "show", "shoulder-ded", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    const jv *params = jget(&v, "parameters");
    assert_int_equal(params->type, J_OBJ);
    assert_true(jnum(params, "layer_mm") > 0);
    jv_release(&v);
    result_free(&r);
    char ids[32];
    snprintf(ids, sizeof ids, "%ld", id);
    RUN(&r, "--db", e->db, "run", "show", ids, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal((long)jnum(&v, "run_id"), id);
    assert_int_equal((long)jnum(&v, "id"), id);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--json");
    expect_ok(&r);
    expect_contains(r.out, "\"run_id\":");
    result_free(&r);
}

static void reconstruct_of_an_intact_scan_says_nothing_to_repair(void **state)
{
    const env *e = *state;
    make_demo(e);
    char mesh[160];
    path_in(e, "intact.ply", mesh, sizeof mesh);
    result r;
    RUN(&r, "--db", e->db, "export", "part", "SR-SHAFT-01", "--out", mesh);
    expect_ok(&r);
    result_free(&r);
    long id = add_instance(e, "SR-SHAFT-01", mesh, "INTACT");
    char ids[32];
    snprintf(ids, sizeof ids, "%ld", id);
    /* --no-nominal: this case stays under Memcheck for the vote's sake; the nominal's
     * registration would take minutes there (test_cli_nominal.c covers it) */
    RUN(&r, "--db", e->db, "reconstruct", ids, "--params", "coarse", "--no-nominal");
    expect_ok(&r);
    expect_contains(r.out, "nothing to repair: no missing section found");
    expect_contains(r.out, "recorded\n");
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", ids, "--params", "coarse", "--json", "--no-nominal");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(jget(&v, "sections")->type, J_ARR);
    assert_int_equal(jget(&v, "sections")->count, 0);
    assert_near(jnum(&v, "patch_volume_mm3"), 0, 0);
    char rid[32];
    snprintf(rid, sizeof rid, "%ld", (long)jnum(&v, "run_id"));
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show", rid, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(jget(&v, "sections")->count, 0);
    assert_near(jnum(&v, "missing_volume_mm3"), 0, 0);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show", rid);
    expect_ok(&r);
    expect_contains(r.out, "sections:    none (nothing to repair)");
    result_free(&r);
}

static void a_symmetry_that_does_not_fit_finishes_and_reports_the_fit(void **state)
{
    const env *e = *state;
    make_demo(e);
    /* mirror on the axial shaft: it finishes (a shaft is mirror-symmetric too) and the
     * fit is reported */
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--symmetry", "mirror", "--params",
        "coarse", "--no-union", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    const jv *a = jget(&v, "alignment");
    double score = jnum(a, "fit_score");
    assert_true(score >= 0 && score <= 1);
    assert_int_equal(jget(a, "fit_poor")->type, J_BOOL);
    assert_string_equal(jstr(jget(&v, "symmetry"), "kind"), "mirror");
    jv_release(&v);
    result_free(&r);
    /* axial on the flat bracket: a poor fit, said so, and still a recorded run */
    RUN(&r, "--db", e->db, "reconstruct", "3", "--no-nominal", "--symmetry", "axial", "--params",
        "coarse", "--no-union", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    a = jget(&v, "alignment");
    assert_true(jnum(a, "fit_score") < 0.5);
    assert_true(jget(a, "fit_poor")->b);
    assert_int_equal(jget(&v, "run_id")->type, J_NUM);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", "3", "--no-nominal", "--symmetry", "axial", "--params",
        "coarse", "--no-union", "--no-record");
    expect_ok(&r);
    expect_contains(r.out, "poor fit: score ");
    result_free(&r);
}

static void run_commands_refuse_wrong_ids_and_filters(void **state)
{
    const env *e = *state;
    init_catalog(e);
    result r;
    RUN(&r, "--db", e->db, "run", "list");
    expect_ok(&r);
    assert_string_equal(r.out, "no runs\n");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--json");
    expect_ok(&r);
    assert_string_equal(r.out, "[]\n");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show", "99");
    expect_error(&r, "no run 99 in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show", "0");
    expect_usage(&r, "bad N '0'");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "show");
    expect_usage(&r, NULL);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--instance", "5");
    expect_error(&r, "no instance 5 in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--part", "NOPE", "--json");
    expect_error(&r, "no part 'NOPE' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "frob");
    expect_usage(&r, "run");
    result_free(&r);
}

static void run_list_filters_by_instance_and_part(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--params", "coarse", "--no-union");
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "reconstruct", "2", "--no-nominal", "--params", "coarse", "--no-union");
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal(v.count, 2);
    assert_int_equal((int)jnum(&v.items[0], "id"), 2);     /* newest first */
    assert_int_equal((int)jnum(&v.items[1], "id"), 1);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--instance", "1", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(v.count, 1);
    assert_int_equal((int)jnum(&v.items[0], "instance_id"), 1);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "run", "list", "--part", "SR-BUSH-02", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_int_equal(v.count, 1);
    assert_string_equal(jstr(&v.items[0], "part_number"), "SR-BUSH-02");
    jv_release(&v);
    result_free(&r);
}

static void compare_gives_volumes_and_deviations(void **state)
{
    const env *e = *state;
    /* the cylinder against itself, then the box against the cylinder */
    result r;
    RUN(&r, "compare", e->cyl, e->cyl, "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_near(jnum(&v, "volume_diff_mm3"), 0, 0);
    assert_near(jnum(&v, "hausdorff_mm"), 0, 1e-9);
    assert_near(jnum(jget(&v, "a"), "volume_mm3"), cyl_volume(), 1e-3);
    assert_true(jget(jget(&v, "a"), "closed")->b);
    jv_release(&v);
    result_free(&r);
    /* as placed: the registration has a test of its own */
    RUN(&r, "compare", e->cyl, e->box, "--json", "--samples", "5000", "--no-align");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_near(jnum(&v, "volume_diff_mm3"), 6000 - cyl_volume(), 1e-3);
    assert_true(jnum(jget(&v, "b_to_a"), "samples") >= 5000);
    assert_true(jnum(&v, "hausdorff_mm") >= jnum(jget(&v, "a_to_b"), "max_mm"));
    jv_release(&v);
    result_free(&r);
    RUN(&r, "compare", e->cyl, e->box, "--no-align");
    expect_ok(&r);
    expect_contains(r.out, "volume difference B - A: ");
    expect_contains(r.out, "Hausdorff distance: ");
    result_free(&r);
}

/* A damaged part turned and moved away is registered to its intact mesh before the
 * deviations (the default when the two are not in the same frame): what is left is the
 * damage alone. --no-align compares it where it lies; a mesh in place is not moved. */
static void compare_registers_a_moved_scan_to_its_part(void **state)
{
    const env *e = *state;
    sr_mesh intact, damaged;
    sr_err err;
    sr_err_clear(&err);
    assert_int_equal(sr_demo_part_build(0, &intact, &damaged, &err), SR_OK); /* the shaft */
    double missing = sr_mesh_volume(&intact) - sr_mesh_volume(&damaged);
    char in_place[128];
    path_in(e, "in_place.stl", in_place, sizeof in_place);
    write_mesh_file(in_place, &damaged);
    const double m[12] = {0, -1, 0, 150, 0, 0, -1, -40, 1, 0, 0, 25}; /* a proper turn */
    sr_mesh_transform(&damaged, m);
    char a[128], b[128];
    path_in(e, "intact.stl", a, sizeof a);
    path_in(e, "moved.stl", b, sizeof b);
    write_mesh_file(a, &intact);
    write_mesh_file(b, &damaged);
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);

    /* the answer: the damaged mesh where it belongs, not registered */
    result r;
    RUN(&r, "compare", a, in_place, "--no-align", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    double want_hausdorff = jnum(&v, "hausdorff_mm");
    double want_mean = jnum(jget(&v, "b_to_a"), "mean_mm");
    assert_true(want_hausdorff > 2); /* the chip */
    jv_release(&v);
    result_free(&r);

    RUN(&r, "compare", a, b, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    const jv *g = jget(&v, "registration");
    assert_true(jget(g, "applied")->b);
    assert_string_equal(jstr(g, "why"), "not in the same frame");
    assert_true(jnum(g, "in_place_coverage") < 0.2);
    assert_true(jnum(g, "coverage") > 0.9);
    assert_true(jnum(g, "rms_mm") < 0.05);
    /* the shaft turns freely about its axis: what must come back is the axis, z of A.
     * Its points (0, 0, z) went to m's (150, -40 - z, 25); the registration puts them
     * back on A's z axis at the same z */
    double reg[12];
    for (int i = 0; i < 12; i++) {
        char path[48];
        snprintf(path, sizeof path, "$.registration.matrix[%d]", i);
        reg[i] = jq_num(r.out, path);
    }
    for (double z = 0; z <= 100; z += 50) {
        const double p[3] = {150, -40 - z, 25};
        double q[3];
        sr_xform_apply(reg, p, q);
        if (!(hypot(q[0], q[1]) < 0.05 && fabs(q[2] - z) < 0.05))
            fail_msg("the axis point z = %g came back at (%g, %g, %g)", z, q[0], q[1], q[2]);
    }
    /* the volumes do not move; A's samples that miss B are the chipped shoulder's */
    assert_near(jnum(&v, "volume_diff_mm3"), -missing, 1e-3 * missing);
    double aligned = jnum(&v, "hausdorff_mm");
    assert_near(aligned, want_hausdorff, 0.05);
    assert_near(jnum(jget(&v, "b_to_a"), "mean_mm"), want_mean, 0.01);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "compare", a, b, "--no-align", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_false(jget(jget(&v, "registration"), "applied")->b);
    assert_true(jnum(&v, "hausdorff_mm") > 10 * aligned);
    jv_release(&v);
    result_free(&r);

    RUN(&r, "compare", a, b);
    expect_ok(&r);
    expect_contains(r.out, "note: the bounding boxes of A and B overlap by ");
    expect_contains(r.out, "B registered to A (not in the same frame): rotated ");
    result_free(&r);

    RUN(&r, "compare", a, a);
    expect_ok(&r);
    expect_contains(r.out, "B is in A's frame (100.0 % of B within ");
    result_free(&r);

    RUN(&r, "compare", a, b, "--align", "--no-align");
    expect_usage(&r, "--align or --no-align, not both");
    result_free(&r);
}

static void compare_takes_stored_meshes(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--no-nominal", "--params", "coarse", "--no-union");
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "--db", e->db, "compare", "part:SR-SHAFT-01", "instance:1", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    double lost = -jnum(&v, "volume_diff_mm3");
    assert_true(lost > 1000 && lost < 1500);    /* the chip: 1239 mm³ */
    assert_string_equal(jstr(jget(&v, "b"), "source"), "instance 1");
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "compare", "part:SR-SHAFT-01", "run:1", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_string_equal(jstr(jget(&v, "b"), "source"), "run 1");
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "compare", "part:SR-SHAFT-01", "run:9");
    expect_error(&r, "no run 9 in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "compare", "part:NOPE", "run:1");
    expect_error(&r, "no part 'NOPE' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "compare", "instance:x", "run:1");
    expect_usage(&r, "instance:N");
    result_free(&r);
}

static void compare_refuses_missing_and_garbage_files(void **state)
{
    const env *e = *state;
    char missing[160], garbage[160];
    path_in(e, "missing.stl", missing, sizeof missing);
    path_in(e, "garbage.stl", garbage, sizeof garbage);
    write_bytes(garbage, "this is not a mesh at all, not even close to one\n", 49);
    result r;
    RUN(&r, "compare", missing, e->cyl);
    expect_error(&r, "missing.stl");
    result_free(&r);
    RUN(&r, "compare", e->cyl, garbage, "--json");
    expect_error(&r, "garbage.stl");
    result_free(&r);
    RUN(&r, "compare", e->cyl);
    expect_usage(&r, NULL);
    result_free(&r);
    RUN(&r, "compare", e->cyl, e->cyl, "--samples", "0");
    expect_usage(&r, "bad --samples '0'");
    result_free(&r);
    /* a catalogue reference without a catalogue: the usual message, no file made */
    RUN(&r, "--db", e->db, "compare", e->cyl, "run:1");
    expect_error(&r, "no catalogue '");
    result_free(&r);
    assert_false(file_exists(e->db));
}

/* ------------------------------------------------------------------------------------
 * Build plans
 * ---------------------------------------------------------------------------------- */

/* Stores a run of the cylinder part through the library: 10 layers of 1 mm, 72 sectors
 * (5 degrees), restored radius 10, a 2 mm deep chip over 10..50 degrees in layers 2..7
 * (section 1). Returns the run id. */
/* add_chipped_run with one advice for its section (process, details JSON) when process
 * is not NULL; into a new catalogue when first, else beside the runs already there. */
static long add_chipped_run_advised(const env *e, const char *process, const char *details,
                                    bool first);

static long add_chipped_run(const env *e)
{
    return add_chipped_run_advised(e, NULL, NULL, true);
}

static long add_chipped_run_advised(const env *e, const char *process, const char *details,
                                    bool first)
{
    static long inst;
    if (first) {
        init_catalog(e);
        add_part(e, "SH-1", "shaft", "steel", e->cyl);
        inst = add_instance(e, "SH-1", e->cyl, "S-1");
    }
    enum { L = 10, S = 72 };
    static double z[L], dmg[L * S * 2], rst[L * S * 2];
    for (size_t l = 0; l < L; l++) {
        z[l] = (double)l + 0.5;
        for (size_t j = 0; j < S; j++) {
            double a = ((double)j + 0.5) * 5.0 * PI / 180.0;
            double rd = (l >= 2 && l <= 7 && j >= 2 && j <= 9) ? 8.0 : 10.0;
            rst[2 * (l * S + j)] = 10.0 * cos(a);
            rst[2 * (l * S + j) + 1] = 10.0 * sin(a);
            dmg[2 * (l * S + j)] = rd * cos(a);
            dmg[2 * (l * S + j) + 1] = rd * sin(a);
        }
    }
    sr_run_section sec;
    memset(&sec, 0, sizeof sec);
    sec.layer_first = 2;
    sec.layer_last = 7;
    sec.z_min_mm = 2;
    sec.z_max_mm = 8;
    sec.has_angles = 1;
    sec.angle_from_deg = 10;
    sec.angle_to_deg = 50;
    sec.volume_mm3 = 6 * 0.5 * (100 - 64) * sin(5 * PI / 180) * 8;
    sec.depth_max_mm = sec.depth_mean_mm = 2;
    strcpy(sec.damage_class, "chip");
    sr_run run;
    memset(&run, 0, sizeof run);
    run.instance_id = inst;
    run.symmetry.kind = SR_SYM_AXIAL;
    strcpy(run.method, "paper");
    run.has_alignment = 1;
    run.alignment[0] = run.alignment[5] = run.alignment[10] = 1;
    run.fit_quality = 0.9;
    run.ok = 1;
    run.layer_count = L;
    run.sectors = S;
    run.layer_z = z;
    run.damaged_xy = dmg;
    run.restored_xy = rst;
    run.sections = &sec;
    run.section_count = 1;
    sr_run_advice adv;
    memset(&adv, 0, sizeof adv);
    if (process) {
        snprintf(adv.process, sizeof adv.process, "%s", process);
        snprintf(adv.reason, sizeof adv.reason, "test advice");
        adv.details_json = (char *)details;
        run.advice = &adv;
        run.advice_count = 1;
    }
    sr_catalog *cat = NULL;
    sr_err err;
    sr_err_clear(&err);
    int64_t id = 0;
    assert_int_equal(sr_catalog_open(e->db, 0, &cat, &err), SR_OK);
    assert_int_equal(sr_catalog_params_get(cat, "default", &run.params, &err), SR_OK);
    run.params.layers = L;
    run.params.sectors = S;
    if (sr_catalog_run_add(cat, &run, &id, &err) != SR_OK)
        fail_msg("cannot add the run: %s", err.msg);
    sr_catalog_close(cat);
    return (long)id;
}

static void plan_writes_json_svg_per_layer_and_gcode(void **state)
{
    const env *e = *state;
    long id = add_chipped_run(e);
    char idtext[32], out[128], path[192];
    snprintf(idtext, sizeof idtext, "%ld", id);
    path_in(e, "plan", out, sizeof out);
    result r;
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out, "--feed", "450", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_int_equal((long)jnum(&v, "run"), id);
    assert_int_equal((int)jnum(&v, "section"), 1);
    assert_int_equal((int)jnum(&v, "layer_count"), 6);
    assert_true(jnum(&v, "layer_mm") == 1.0);
    assert_true(jnum(&v, "feed_mm_min") == 450.0);
    double missing = 6 * 0.5 * sin(5 * PI / 180) * (2 * 10 * 2 + 7 * (100 - 64));
    assert_true(fabs(jnum(&v, "missing_volume_mm3") - missing) < 0.01);
    assert_true(jnum(&v, "deposit_volume_mm3") > missing);
    assert_string_equal(jstr(&v, "symmetry"), "axial");
    jv_release(&v);
    result_free(&r);
    for (int k = 1; k <= 6; k++) {
        snprintf(path, sizeof path, "%s/layer_%03d.svg", out, k);
        assert_true(file_exists(path));
    }
    snprintf(path, sizeof path, "%s/layer_007.svg", out);
    assert_false(file_exists(path));
    snprintf(path, sizeof path, "%s/plan.gcode", out);
    char *gcode = read_text(path);
    assert_non_null(gcode);
    expect_contains(gcode, "G21\nG90\n");
    expect_contains(gcode, "; layer 6 z=8.00000\n");
    expect_contains(gcode, " Z3.00000 F450.0\n");
    free(gcode);
    snprintf(path, sizeof path, "%s/plan.json", out);
    char *json = read_text(path);
    assert_non_null(json);
    v = parse_json(json); /* the file is strict JSON */
    assert_int_equal((int)jnum(&v, "layer_count"), 6);
    jv_release(&v);
    free(json);

    /* the human summary */
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out, "--pattern", "contour");
    expect_ok(&r);
    expect_contains(r.out, "6 layers of 1.000 mm");
    expect_contains(r.out, "pattern contour,");
    result_free(&r);
}

/* The plan takes its settings from the section's advice (the rule's layer, step-over,
 * allowance and rate), an option given overrides one of them, a 'replace' advice has
 * no plan unless --ignore-advice, and the build time is the path's, moves included. */
static void plan_follows_the_advice_of_its_section(void **state)
{
    const env *e = *state;
    long id = add_chipped_run_advised(
        e, "ded",
        "{\"parameters\":{\"layer_mm\":0.8,\"step_over_mm\":1.2,\"allowance_mm\":0.8,"
        "\"deposition_rate_g_min\":10,\"efficiency\":0.8},\"preheat_c\":250}",
        true);
    char idtext[32], out[128];
    snprintf(idtext, sizeof idtext, "%ld", id);
    path_in(e, "plan", out, sizeof out);
    result r;
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out, "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_true(jnum(&v, "layer_mm") == 0.8);
    assert_int_equal((int)jnum(&v, "layer_count"), 8); /* 6 mm of section in 0.8 mm */
    assert_true(jnum(&v, "step_over_mm") == 1.2);
    assert_true(jnum(&v, "allowance_mm") == 0.8);
    double rate = 10 * 0.8 / 7.85; /* 'steel' is added with 7.85 g/cm³ */
    assert_true(fabs(jnum(&v, "rate_cm3_min") - rate) < 1e-12);
    assert_true(fabs(jnum(&v, "feed_mm_min") - rate * 1000 / (1.2 * 0.8)) < 1e-9);
    assert_string_equal(jstr(&v, "process"), "ded");
    double build = jnum(&v, "build_time_min"), dep = jnum(&v, "deposit_time_min"),
           travel = jnum(&v, "travel_time_min");
    assert_true(travel > 0 && dep > 0);
    assert_true(fabs(build - (dep + travel)) < 1e-12);
    assert_true(fabs(dep - jnum(&v, "path_length_mm") / jnum(&v, "feed_mm_min")) < 1e-12);
    jv_release(&v);
    expect_contains(r.out, "\"from_advice\":[\"layer_mm\",\"step_over_mm\",\"allowance_mm\","
                           "\"rate_cm3_min\"]");
    result_free(&r);
    char path[192];
    snprintf(path, sizeof path, "%s/plan.gcode", out);
    char *gcode = read_text(path);
    assert_non_null(gcode);
    expect_contains(gcode, "; process ded");
    expect_contains(gcode, "; preheat the part to 250 C");
    free(gcode);

    /* an option given wins over the advice's */
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out, "--layer-mm", "0.5");
    expect_ok(&r);
    expect_contains(r.out, "12 layers of 0.500 mm");
    expect_contains(r.out, "step-over 1.200 mm, machining allowance 0.800 mm");
    expect_contains(r.out, "process ded, as advised by rule");
    expect_contains(r.out, "(options given override part of it)");
    result_free(&r);

    /* a section advised 'replace' */
    long rid = add_chipped_run_advised(e, "replace", "{}", false);
    snprintf(idtext, sizeof idtext, "%ld", rid);
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out);
    expect_error(&r, "was advised 'replace'");
    expect_contains(r.err, "--ignore-advice");
    result_free(&r);
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out, "--ignore-advice", "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_true(jnum(&v, "layer_mm") == 1.0); /* the run's spacing */
    jv_release(&v);
    result_free(&r);
}

static void plan_of_an_unknown_run_or_section_fails(void **state)
{
    const env *e = *state;
    long id = add_chipped_run(e);
    char idtext[32], out[128];
    snprintf(idtext, sizeof idtext, "%ld", id);
    path_in(e, "plan", out, sizeof out);
    result r;
    RUN(&r, "--db", e->db, "plan", "99", "--out", out);
    expect_error(&r, "no run 99");
    result_free(&r);
    RUN(&r, "--db", e->db, "plan", idtext, "--out", out, "--section", "2");
    expect_error(&r, "has no section 2");
    result_free(&r);
    assert_false(file_exists(out));
}

static void plan_bad_options_are_usage_errors(void **state)
{
    const env *e = *state;
    result r;
    RUN(&r, "--db", e->db, "plan", "1");
    expect_usage(&r, "needs --out DIR");
    result_free(&r);
    RUN(&r, "--db", e->db, "plan", "1", "--out", "x", "--step-over", "0");
    expect_usage(&r, "--step-over");
    result_free(&r);
    RUN(&r, "--db", e->db, "plan", "1", "--out", "x", "--allowance", "-1");
    expect_usage(&r, "--allowance");
    result_free(&r);
    RUN(&r, "--db", e->db, "plan", "1", "--out", "x", "--pattern", "spiral");
    expect_usage(&r, "--pattern 'spiral'");
    result_free(&r);
    RUN(&r, "--db", e->db, "plan", "1", "--out", "x", "--off-code", "M5;M2");
    expect_usage(&r, "off_code");
    result_free(&r);
    assert_false(file_exists(e->db));
}

/* ------------------------------------------------------------------------------------
 * History and report
 * ---------------------------------------------------------------------------------- */

/* The demo's shaft and bushing, plus a second shaft instance (4), and four runs:
 * instance 1 twice, 4 once, 2 once (runs 1..4 in that order). */
static void make_history(const env *e)
{
    make_demo(e);
    sr_catalog *cat = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(e->db, 0, &cat, &err), SR_OK);
    sr_mesh intact, damaged;
    assert_int_equal(sr_demo_part_build(0, &intact, &damaged, &err), SR_OK);
    sr_instance_new inst = {.part = sr_demo_part_get(0)->number, .mesh = &damaged,
                            .serial = "SN-SECOND"};
    int64_t id;
    assert_int_equal(sr_catalog_instance_add(cat, &inst, &id, &err), SR_OK);
    assert_int_equal(id, 4);
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);
    sr_catalog_close(cat);
    /* the first under the wrap (Valgrind: a recorded run with its sections), the other
     * three natively: they only give the filters runs to tell apart; no nominal (the
     * history is what is tested, and the registration is slow under Valgrind) */
    static const char *const order[] = {"1", "1", "4", "2"};
    for (size_t i = 0; i < 4; i++) {
        result r;
        if (i == 0)
            RUN(&r, "--db", e->db, "reconstruct", order[i], "--params", "coarse", "--no-union",
                "--no-nominal");
        else
            RUN_NATIVE(&r, "--db", e->db, "reconstruct", order[i], "--params", "coarse",
                       "--no-union", "--no-nominal");
        expect_ok(&r);
        result_free(&r);
    }
}

/* Number of runs in `history --json` output, checking each has the keys. */
static size_t history_json_runs(const char *out, const char *part)
{
    jv v = parse_json(out);
    const jv *runs = jget(&v, "runs");
    assert_int_equal(runs->type, J_ARR);
    assert_int_equal(jget(&v, "summary")->type, J_OBJ);
    size_t n = runs->count;
    for (size_t i = 0; i < n; i++) {
        const jv *r = &runs->items[i];
        if (part)
            assert_string_equal(jstr(r, "part_number"), part);
        assert_int_equal(jget(r, "damage_classes")->type, J_ARR);
        assert_int_equal(jget(r, "advice")->type, J_ARR);
        assert_non_null(jstr(r, "outcome"));
        assert_true(jnum(r, "missing_volume_mm3") > 0);
    }
    assert_int_equal((size_t)jnum(jget(&v, "summary"), "runs"), n);
    jv_release(&v);
    return n;
}

static size_t count_lines(const char *s)
{
    size_t n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

static void history_filters_return_exactly_the_runs_made(void **state)
{
    const env *e = *state;
    make_history(e);
    const char *shaft = sr_demo_part_get(0)->number, *bush = sr_demo_part_get(1)->number;
    result r;
    RUN(&r, "--db", e->db, "history", "--json");
    expect_ok(&r);
    assert_int_equal(history_json_runs(r.out, NULL), 4);
    jv v = parse_json(r.out);
    const jv *runs = jget(&v, "runs");
    assert_int_equal((int)jnum(&runs->items[0], "run_id"), 4); /* newest first */
    assert_int_equal((int)jnum(&runs->items[3], "run_id"), 1);
    jv_release(&v);
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--part", shaft, "--json");
    expect_ok(&r);
    assert_int_equal(history_json_runs(r.out, shaft), 3);
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--instance", "1", "--json");
    expect_ok(&r);
    assert_int_equal(history_json_runs(r.out, shaft), 2);
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--material", sr_demo_part_get(1)->material, "--json");
    expect_ok(&r);
    assert_int_equal(history_json_runs(r.out, bush), 1);
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--since", "2000-01-01", "--until", "2999-12-31",
        "--json");
    expect_ok(&r);
    assert_int_equal(history_json_runs(r.out, NULL), 4);
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--until", "2000-01-01", "--json");
    expect_ok(&r);
    assert_int_equal(history_json_runs(r.out, NULL), 0);
    result_free(&r);

    /* CSV: a header and one CRLF line per run; the symmetry "axial, continuous" quoted */
    RUN(&r, "--db", e->db, "history", "--part", shaft, "--csv");
    expect_ok(&r);
    assert_int_equal(count_lines(r.out), 1 + 3);
    assert_int_equal(strncmp(r.out, "run_id,date,started_at,instance_id,part,", 40), 0);
    expect_contains(r.out, "outcome\r\n");
    expect_contains(r.out, ",\"axial, continuous\",");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--instance", "2", "--csv");
    expect_ok(&r);
    assert_int_equal(count_lines(r.out), 1 + 1);
    result_free(&r);

    /* table and summary */
    RUN(&r, "--db", e->db, "history");
    expect_ok(&r);
    assert_int_equal(count_lines(r.out), 1 + 4);
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--summary");
    expect_ok(&r);
    expect_contains(r.out, "runs: 4 (0 failed)");
    expect_contains(r.out, "per part:");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--summary", "--csv");
    expect_ok(&r);
    assert_int_equal(count_lines(r.out), 1 + 2); /* header, shaft, bushing */
    result_free(&r);
}

static void history_refuses_bad_filters(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "history", "--since", "2024-02-30");
    expect_usage(&r, "bad --since '2024-02-30'");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--until", "yesterday", "--json");
    expect_usage(&r, "bad --until 'yesterday'");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--since", "2024-03-02", "--until", "2024-03-01");
    expect_usage(&r, "after --until");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--part", "NOPE", "--json");
    expect_error(&r, "no part 'NOPE' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--part", "NOPE", "--csv");
    expect_error(&r, "no part 'NOPE' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--material", "Unobtainium");
    expect_error(&r, "no material 'Unobtainium' in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--instance", "9");
    expect_error(&r, "no instance 9 in the catalogue");
    result_free(&r);
    RUN(&r, "--db", e->db, "history", "--json", "--csv");
    expect_usage(&r, "not both");
    result_free(&r);
    RUN(&r, "--db", e->db, "history");
    expect_ok(&r);
    assert_string_equal(r.out, "no runs\n");
    result_free(&r);
}

/* export run N: the restored part, the patches (their volume is the run's), one
 * section's patch, or both as a glTF scene; refusals say why. */
static void export_run_writes_its_restored_part_and_patches(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN_NATIVE(&r, "--db", e->db, "reconstruct", "1", "--params", "coarse", "--json");
    expect_ok(&r);
    jv rec = parse_json(r.out);
    result_free(&r);
    double patch_volume = jnum(&rec, "patch_volume_mm3");
    double restored_volume = jnum(&rec, "restored_volume_mm3");
    char rid[32];
    snprintf(rid, sizeof rid, "%ld", (long)jnum(&rec, "run_id"));
    jv_release(&rec);
    assert_true(patch_volume > 0);

    char path[160];
    path_in(e, "patches.stl", path, sizeof path);
    RUN(&r, "--db", e->db, "export", "run", rid, "--out", path, "--what", "patches");
    expect_ok(&r);
    result_free(&r);
    RUN(&r, "check", path, "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_true(fabs(jnum(&v, "volume") - patch_volume) < 1e-3 * patch_volume);
    jv_release(&v);
    result_free(&r);

    path_in(e, "restored.obj", path, sizeof path);
    RUN(&r, "--db", e->db, "export", "run", rid, "--out", path);
    expect_ok(&r);
    expect_contains(r.out, "restored");
    result_free(&r);
    RUN(&r, "check", path, "--json");
    expect_ok(&r);
    v = parse_json(r.out);
    assert_true(fabs(jnum(&v, "volume") - restored_volume) < 1e-6 * restored_volume);
    jv_release(&v);
    result_free(&r);

    path_in(e, "section1.ply", path, sizeof path);
    RUN(&r, "--db", e->db, "export", "run", rid, "--out", path, "--section", "1");
    expect_ok(&r);
    result_free(&r);
    assert_true(file_exists(path));

    path_in(e, "both.glb", path, sizeof path);
    RUN(&r, "--db", e->db, "export", "run", rid, "--out", path, "--what", "both");
    expect_ok(&r);
    result_free(&r);
    sr_scene scene;
    memset(&scene, 0, sizeof scene);
    assert_int_equal(sr_scene_read(path, &scene, NULL), SR_OK);
    assert_true(scene.count >= 2);
    assert_string_equal(scene.names[0], "restored");
    assert_string_equal(scene.names[1], "section 1");
    sr_scene_release(&scene);

    path_in(e, "both.stl", path, sizeof path);
    RUN(&r, "--db", e->db, "export", "run", rid, "--out", path, "--what", "both");
    expect_usage(&r, "--what both needs a .gltf or .glb file");
    result_free(&r);
    RUN(&r, "--db", e->db, "export", "run", rid, "--out", path, "--section", "9");
    expect_error(&r, "has no section 9");
    result_free(&r);
    RUN(&r, "--db", e->db, "export", "part", "SR-SHAFT-01", "--out", path, "--what", "patches");
    expect_usage(&r, "--what and --section are for 'export run N'");
    result_free(&r);
    RUN(&r, "--db", e->db, "export", "run", "99", "--out", path);
    expect_error(&r, "no run 99");
    result_free(&r);
}

static void report_writes_a_self_contained_page_of_the_run(void **state)
{
    const env *e = *state;
    make_demo(e);
    result r;
    RUN(&r, "--db", e->db, "reconstruct", "1", "--params", "coarse", "--no-union");
    expect_ok(&r);
    result_free(&r);
    char out[160];
    path_in(e, "run1.html", out, sizeof out);
    RUN(&r, "--db", e->db, "report", "1", "--out", out);
    expect_ok(&r);
    expect_contains(r.out, "report of run 1 written to");
    result_free(&r);
    char *html = read_text(out);
    assert_non_null(html);
    expect_contains(html, "<title>symrec report: run 1, part ");
    expect_contains(html, "<table id=\"feature-table\">");
    expect_contains(html, sr_demo_part_get(0)->serial);
    /* the scan, read from the catalogue, offered in the 3D view */
    expect_contains(html, "id=\"show-scan\"");
    assert_string_equal(html + strlen(html) - 8, "</html>\n");
    /* no address outside the embedded three.js (whose text names XML namespaces) */
    char *lib = strstr(html, "<script id=\"three-js\">");
    assert_non_null(lib);
    char *lib_end = strstr(lib, "</script>");
    assert_non_null(lib_end);
    memmove(lib, lib_end, strlen(lib_end) + 1);
    assert_null(strstr(html, "http://"));
    assert_null(strstr(html, "https://"));
    free(html);
    /* no temporary file left beside it */
    DIR *d = opendir(e->dir);
    assert_non_null(d);
    struct dirent *de;
    while ((de = readdir(d)) != NULL)
        if (strstr(de->d_name, ".tmp-"))
            fail_msg("temporary file left: %s", de->d_name);
    closedir(d);
    RUN(&r, "--db", e->db, "report", "1", "--out", out, "--max-triangles", "200", "--json");
    expect_ok(&r);
    jv v = parse_json(r.out);
    assert_true(jget(&v, "decimated")->b);
    assert_true(jnum(&v, "triangles_shown") <= 200);
    /* every section has a build plan (with its layers) or is advised replace */
    double planned = jnum(&v, "plan_sections"), replaced = jnum(&v, "replace_sections");
    assert_true(planned + replaced >= 1);
    assert_true(planned == 0 || jnum(&v, "plan_layers") >= planned);
    jv_release(&v);
    result_free(&r);
    html = read_text(out);
    assert_non_null(html);
    if (planned > 0)
        expect_contains(html, "<table id=\"plan-table\">");
    else
        expect_contains(html, "No build plan: the advice is to replace the part");
    free(html);
}

static void report_refuses_a_wrong_run_and_bad_arguments(void **state)
{
    const env *e = *state;
    make_demo(e);
    char out[160];
    path_in(e, "x.html", out, sizeof out);
    result r;
    RUN(&r, "--db", e->db, "report", "99", "--out", out);
    expect_error(&r, "no run 99 in the catalogue");
    result_free(&r);
    assert_false(file_exists(out));
    RUN(&r, "--db", e->db, "report", "1");
    expect_usage(&r, "--out");
    result_free(&r);
    RUN(&r, "--db", e->db, "report", "x", "--out", out);
    expect_usage(&r, "bad RUN 'x'");
    result_free(&r);
    RUN(&r, "--db", e->db, "report", "1", "--out", out, "--max-triangles", "5");
    expect_usage(&r, "bad --max-triangles '5'");
    result_free(&r);
    /* HTML is not written into a file named as something else */
    char pdf[160];
    path_in(e, "x.pdf", pdf, sizeof pdf);
    RUN(&r, "--db", e->db, "report", "1", "--out", pdf);
    expect_usage(&r, "the report is an HTML page, name it .html");
    result_free(&r);
    assert_false(file_exists(pdf));
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    struct CMUnitTest tests[] = {
        T(top_level_help_lists_commands_and_db_default),
        T(every_command_and_subcommand_has_help),
        T(help_command_shows_a_commands_help),
        T(version_prints_the_version),
        T(unknown_command_is_a_usage_error),
        T(missing_command_is_a_usage_error),
        T(unknown_options_are_usage_errors),
        T(missing_option_values_are_usage_errors),
        T(bad_numbers_are_usage_errors_naming_the_option),
        T(catalog_init_creates_then_is_idempotent),
        T(catalog_info_counts_parts_and_instances),
        T(commands_on_a_missing_catalogue_fail_without_creating_it),
        T(garbage_catalogue_file_is_refused),
        T(symrec_db_environment_variable_is_used),
        T(part_add_prints_the_id_and_part_list_shows_it),
        T(part_add_json_prints_the_part),
        T(part_add_duplicate_number_fails_and_changes_nothing),
        T(part_list_filters_by_name_number_and_material),
        T(part_show_by_number_and_by_id),
        T(strings_are_escaped_in_json),
        T(part_add_refuses_a_missing_mesh_file),
        T(part_add_refuses_an_empty_mesh_file),
        T(part_add_refuses_a_garbage_mesh_file),
        T(part_add_refuses_a_truncated_binary_stl),
        T(part_add_refuses_a_mesh_that_is_not_a_closed_solid),
        T(part_add_refuses_an_unknown_extension),
        T(instance_add_list_and_show),
        T(instance_add_for_an_unknown_part_fails),
        T(instance_add_validates_the_date),
        T(instance_show_of_an_unknown_id_fails),
        T(instance_symmetry_override_is_shown),
        T(export_round_trips_through_every_format),
        T(export_of_an_unknown_id_fails),
        T(check_and_convert_a_mesh_file),
        T(check_describes_an_open_scan),
        T(export_run_writes_its_restored_part_and_patches),
        T(params_list_show_and_set),
        T(rules_list_show_and_set),
        T(rules_set_errors_change_nothing),
        T(rules_add_enable_and_disable),
        T(materials_list_shows_the_seeded_materials),
        T(demo_builds_the_catalogue_and_is_idempotent),
        T(demo_runs_the_whole_job),
        T(fixtures_write_meshes_whose_volumes_match_volumes_json),
        T(reconstruct_of_an_instance_records_a_run_that_run_list_and_show_return),
        T(reconstruct_prints_run_recorded_and_no_record_records_none),
        T(reconstruct_of_a_mesh_file_prints_features_and_advice),
        T(reconstruct_params_and_overrides_are_recorded),
        T(reconstruct_applies_the_sets_min_volume_and_min_depth),
        T(reconstruct_order_auto_finds_and_records_the_order),
        T(a_failed_reconstruct_records_nothing),
        T(reconstruct_refuses_bad_input),
        T(reconstruct_of_an_intact_scan_says_nothing_to_repair),
        T(reconstruct_shows_progress_by_phase_unless_quiet),
        T(global_options_may_follow_the_command),
        T(json_names_agree_across_commands),
        T(a_symmetry_that_does_not_fit_finishes_and_reports_the_fit),
        T(run_commands_refuse_wrong_ids_and_filters),
        T(run_list_filters_by_instance_and_part),
        T(compare_gives_volumes_and_deviations),
        T(compare_registers_a_moved_scan_to_its_part),
        T(compare_takes_stored_meshes),
        T(compare_refuses_missing_and_garbage_files),
        T(history_filters_return_exactly_the_runs_made),
        T(history_refuses_bad_filters),
        T(report_writes_a_self_contained_page_of_the_run),
        T(report_refuses_a_wrong_run_and_bad_arguments),
        T(plan_writes_json_svg_per_layer_and_gcode),
        T(plan_follows_the_advice_of_its_section),
        T(plan_of_an_unknown_run_or_section_fails),
        T(plan_bad_options_are_usage_errors),
    };
#undef T
    /* SYMREC_TEST_SHARD=K/N (and _FILTER, _SKIP): tests/run_tests.sh runs this binary
     * as shards side by side, which matters under Valgrind */
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
