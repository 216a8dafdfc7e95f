/*
 * cmd_instance.c: `symrec instance add|list|show|set|remove`: an instance is one
 * damaged copy of a part as it came into the shop, with its scan (the damaged mesh),
 * serial, date received and, if it differs from the part's, its own symmetry; `set`
 * corrects serial, date and notes, `remove` takes it out (with its runs only when
 * asked). Also the instance
 * table that `part show` and `demo` print. The "missing" volume shown is the part's
 * intact volume minus the instance's: what a repair has to put back.
 */
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_identify.h"
#include "cli.h"
#include "json_out.h"

static const char usage_instance[] =
    "usage: symrec [--db FILE] instance add --part P|auto --mesh FILE [--serial S]\n"
    "                               [--received YYYY-MM-DD] [--notes T]\n"
    "                               [--symmetry K [--order N] [--shift MM]] [--json]\n"
    "       symrec [--db FILE] instance list [--part P] [--json]\n"
    "       symrec [--db FILE] instance show ID [--json]\n"
    "       symrec [--db FILE] instance set ID [--serial S] [--received YYYY-MM-DD]\n"
    "                               [--notes T] [--json]\n"
    "       symrec [--db FILE] instance remove ID [--with-runs] [--json]\n"
    "\n"
    "  add     add a damaged instance of part P with its scan; prints the new id\n"
    "  list    a table of instances, of one part or all\n"
    "  show    one instance in full\n"
    "  set     correct an instance's serial, date received or notes\n"
    "  remove  remove an instance (with its runs only with --with-runs)\n";

static const char usage_set[] =
    "usage: symrec [--db FILE] instance set ID [--serial S] [--received YYYY-MM-DD]\n"
    "                               [--notes T] [--json]\n"
    "\n"
    "Corrects instance ID and prints it as changed. At least one option; \"\" makes the\n"
    "serial or the date unknown, or clears the notes.\n"
    "\n"
    "  --serial S     the serial number (up to 63 characters)\n"
    "  --received D   the date it was received, YYYY-MM-DD\n"
    "  --notes T      free text: what is broken\n"
    "  --json         print the instance as a JSON object\n";

static const char usage_remove[] =
    "usage: symrec [--db FILE] instance remove ID [--with-runs] [--json]\n"
    "\n"
    "Removes instance ID with its scan and symmetry override, and says what went. While\n"
    "runs of it are recorded it is refused, naming how many, and nothing changes.\n"
    "\n"
    "  --with-runs   remove its runs (with their sections, advice and meshes) too, in\n"
    "                one transaction; the history summary loses exactly those runs\n"
    "  --json        print what went as a JSON object: {\"instance\", \"part\", \"runs\",\n"
    "                \"meshes\"}\n";

static const char usage_add[] =
    "usage: symrec [--db FILE] instance add --part P|auto --mesh FILE [--units U]\n"
    "                               [--serial S] [--received YYYY-MM-DD] [--notes T]\n"
    "                               [--symmetry K [--order N] [--shift MM]] [--json]\n"
    "\n"
    "Adds a damaged instance of a part with its scanned mesh and prints the new id.\n"
    "\n"
    "  --part P       the part: its number or id, or `auto`: the part `symrec identify`\n"
    "                 finds for the scan; refused (exit 1, the candidates listed) when\n"
    "                 no part explains it or the first two are too close to call (a part\n"
    "                 numbered \"auto\" is then given by its id)\n"
    "  --mesh FILE    the damaged mesh: .stl .obj .ply .off .gltf .glb, read in --units\n"
    "                 and stored in mm with the unit noted; at most 2 GiB,\n"
    "                 |coordinate| <= 1e6 mm, largest extent >= 1e-3 mm once in mm\n"
    "  --serial S     the instance's serial number\n"
    "  --received D   the date it was received, YYYY-MM-DD (default today, UTC)\n"
    "  --notes T      free text: what is broken\n"
    "  --symmetry K   override the part's symmetry: axial, mirror or glide\n"
    "  --order N      axial only: n-fold order 2..360, or 0 for continuous\n"
    "  --shift MM     glide only: the shift along the plane in mm (0 = search)\n"
    "  --json         print the new instance as a JSON object instead of its id\n" CLI_UNITS_HELP;

static const char usage_list[] =
    "usage: symrec [--db FILE] instance list [--part P] [--json]\n"
    "\n"
    "Lists damaged instances by id: id, part, serial, date received, triangles, volume\n"
    "(mm³), the volume missing against the part's intact mesh (mm³ and %) and symmetry.\n"
    "\n"
    "  --part P   only the instances of part P (number or id)\n"
    "  --json     one JSON array of instance objects\n";

static const char usage_show[] =
    "usage: symrec [--db FILE] instance show ID [--json]\n"
    "\n"
    "Shows instance ID in full: part, serial, date received, notes, symmetry, mesh\n"
    "size, bounding box (mm), area (mm²), volume (mm³) and the volume missing against\n"
    "the part's intact mesh.\n"
    "\n"
    "  --json   one JSON object\n";

/* The part's intact volume for an instance's missing volume; false if the part has
 * no mesh (or cannot be found). */
static bool intact_volume(sr_catalog *cat, const sr_instance_info *in, sr_part_info *cache,
                          double *out)
{
    if (cache->id != in->part_id) {
        sr_part_info p;
        if (sr_catalog_part_find(cat, in->part_number, &p, NULL) != SR_OK || p.id != in->part_id)
            return false;
        *cache = p;
    }
    if (!cache->mesh_id || !in->mesh_id)
        return false;
    *out = cache->volume_mm3;
    return true;
}

bool cli_instance_table(sr_catalog *cat, const cli_instances *list, bool with_part, int indent)
{
    static const char *const headers[] = {"id",          "part",      "serial",
                                          "received",    "triangles", "volume mm³",
                                          "missing mm³", "missing",   "symmetry"};
    static const bool right[] = {true, false, false, false, true, true, true, true, false};
    /* Without the part column, every column shifts left by one. */
    size_t skip = with_part ? 0 : 1;
    const char *hdr[9];
    bool rt[9];
    size_t cols = 0;
    for (size_t c = 0; c < 9; c++) {
        if (c == 1 && skip)
            continue;
        hdr[cols] = headers[c];
        rt[cols++] = right[c];
    }
    cli_table t;
    cli_table_init(&t, cols, hdr, rt);
    sr_part_info part = {0};
    for (size_t i = 0; i < list->count; i++) {
        const sr_instance_info *in = &list->v[i];
        char sym[64];
        double intact;
        cli_table_cell(&t, "%lld", (long long)in->id);
        if (with_part)
            cli_table_cell(&t, "%s", in->part_number);
        cli_table_cell(&t, "%s", in->serial[0] ? in->serial : "-");
        cli_table_cell(&t, "%s", in->received[0] ? in->received : "-");
        cli_table_cell(&t, "%zu", in->tri_count);
        cli_table_cell(&t, "%.1f", in->volume_mm3);
        if (intact_volume(cat, in, &part, &intact) && intact > 0) {
            cli_table_cell(&t, "%.1f", intact - in->volume_mm3);
            cli_table_cell(&t, "%.2f %%", 100.0 * (intact - in->volume_mm3) / intact);
        } else {
            cli_table_cell(&t, "-");
            cli_table_cell(&t, "-");
        }
        cli_table_cell(&t, "%s", cli_sym_str(&in->symmetry, sym, sizeof sym));
    }
    bool ok = cli_table_print(&t, stdout, indent);
    cli_table_release(&t);
    return ok;
}

/* --part auto: the part the scan is identified as. CLI_OK with *out when one part
 * clearly explains it; otherwise the candidates printed (as `identify` does) and the
 * refusal on stderr, CLI_FAIL; a failed identification sets *st and err (CLI_OK). */
static int pick_part(sr_catalog *cat, const sr_mesh *mesh, const char *path, bool json,
                     sr_part_info *out, sr_err *err, sr_status *st)
{
    sr_identify_result res;
    *st = sr_catalog_identify(cat, mesh, NULL, &res, err);
    if (*st != SR_OK)
        return CLI_OK;
    if (res.verdict == SR_IDENTIFY_MATCH && res.same_design == 1) {
        *st = sr_catalog_part_find(cat, res.cand[0].number, out, err);
        if (*st == SR_OK)
            cli_note("'%s' identified as part '%s' (score %.3f, next %.3f)", cli_tx(path),
                     cli_tx(res.cand[0].number), res.cand[0].fit.score,
                     res.registered > 1 ? res.cand[1].fit.score : 0.0);
        sr_identify_result_release(&res);
        return CLI_OK;
    }
    cli_identify_print(&res, path, json);
    if (res.verdict == SR_IDENTIFY_MATCH)
        cli_error("cannot pick the part of '%s': it is one design filed under %zu part "
                  "numbers ('%s', '%s'%s); give --part",
                  cli_tx(path), res.same_design, cli_tx(res.cand[0].number),
                  cli_tx(res.cand[1].number), res.same_design > 2 ? ", ..." : "");
    else if (res.verdict == SR_IDENTIFY_TOO_CLOSE)
        cli_error("cannot pick the part of '%s': '%s' and '%s' are too close to call "
                  "(scores %.3f and %.3f); give --part",
                  cli_tx(path), cli_tx(res.cand[0].number),
                  cli_tx(res.cand[res.same_design].number), res.cand[0].fit.score,
                  res.cand[res.same_design].fit.score);
    else
        cli_error("cannot pick the part of '%s': no part in the catalogue explains it; add "
                  "the part first, or give --part",
                  cli_tx(path));
    sr_identify_result_release(&res);
    return CLI_FAIL;
}

static int instance_add(const cli_ctx *ctx, int argc, char **argv)
{
    const char *part = NULL, *mesh_path = NULL, *serial = NULL, *received = NULL;
    const char *notes = NULL, *sym_kind = NULL, *order = NULL, *shift = NULL, *units = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--part", &part, NULL},
        {"--mesh", &mesh_path, NULL},
        {"--units", &units, NULL},
        {"--serial", &serial, NULL},
        {"--received", &received, NULL},
        {"--notes", &notes, NULL},
        {"--symmetry", &sym_kind, NULL},
        {"--order", &order, NULL},
        {"--shift", &shift, NULL},
        {"--json", NULL, &json},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"instance add", usage_add, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    const char *missing = !part ? "--part" : !mesh_path ? "--mesh" : NULL;
    if (missing)
        return cli_usage_error("'instance add' needs %s (see 'symrec instance add --help')",
                               missing);
    if (received && !cli_date_valid(received))
        return cli_usage_error("bad --received '%s': expected a date YYYY-MM-DD", received);
    sr_symmetry sym;
    if (!cli_parse_symmetry(sym_kind, order, shift, 0, &sym))
        return CLI_USAGE;
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "add the instance", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_part_info p;
    sr_instance_info info;
    sr_mesh mesh;
    sr_mesh_init(&mesh);
    int64_t id = 0;
    /* The part first: a wrong part number is reported before a large scan is read. */
    bool aut = strcmp(part, "auto") == 0;
    sr_status st = aut ? cli_mesh_read(mesh_path, unit, &mesh, &unit, &err)
                       : sr_catalog_part_find(cat, part, &p, &err);
    if (st == SR_OK && aut) {
        rc = pick_part(cat, &mesh, mesh_path, json, &p, &err, &st);
        if (rc != CLI_OK) {
            sr_mesh_release(&mesh);
            sr_catalog_close(cat);
            return rc;
        }
        part = p.number;
    } else if (st == SR_OK) {
        st = cli_mesh_read(mesh_path, unit, &mesh, &unit, &err);
    }
    if (st == SR_OK) {
        sr_instance_new inst = {
            .part = part,
            .mesh = &mesh,
            .serial = serial,
            .received = received,
            .notes = notes,
            .source_file = mesh_path,
            .source_unit = unit,
            .symmetry = sym,
        };
        st = sr_catalog_instance_add(cat, &inst, &id, &err);
    }
    if (st == SR_OK)
        st = sr_catalog_instance_get(cat, id, &info, &err);
    sr_mesh_release(&mesh);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    cli_note("added instance %lld of part '%s': %zu triangles, %.1f mm³", (long long)id,
             cli_tx(info.part_number), info.tri_count, info.volume_mm3);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_instance(&j, &info);
        rc = json_finish(&j);
    } else {
        printf("%lld\n", (long long)id);
        rc = CLI_OK;
    }
    sr_catalog_close(cat);
    return rc;
}

static int instance_list(const cli_ctx *ctx, int argc, char **argv)
{
    const char *part = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--part", &part, NULL}, {"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"instance list", usage_list, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_part_info p;
    cli_instances list = {0};
    /* An unknown --part is an error, not an empty list. */
    sr_status st = part ? sr_catalog_part_find(cat, part, &p, &err) : SR_OK;
    if (st == SR_OK)
        st = cli_instances_load(cat, part, &list, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    rc = CLI_OK;
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_array_begin(&j);
        for (size_t i = 0; i < list.count; i++)
            json_instance(&j, &list.v[i]);
        json_array_end(&j);
        rc = json_finish(&j);
    } else if (list.count == 0) {
        printf("no instances\n");
    } else if (!cli_instance_table(cat, &list, true, 0)) {
        rc = CLI_FAIL;
    }
    cli_instances_release(&list);
    sr_catalog_close(cat);
    return rc;
}

static void print_instance_text(const sr_instance_info *in, const sr_part_info *p)
{
    char sym[64];
    printf("instance %lld of part %s (%s)\n", (long long)in->id, cli_tx(p->number),
           cli_tx(p->name));
    printf("  serial:     %s\n", in->serial[0] ? cli_tx(in->serial) : "-");
    printf("  received:   %s\n", in->received[0] ? cli_tx(in->received) : "-");
    if (in->notes[0])
        cli_print_field(stdout, "  notes:      ", in->notes);
    printf("  symmetry:   %s\n", cli_sym_str(&in->symmetry, sym, sizeof sym));
    printf("  mesh:       %zu vertices, %zu triangles, read in %s\n", in->vertex_count,
           in->tri_count, in->source_unit);
    cli_print_bbox(stdout, "  bbox:       ", in->bbox_min, in->bbox_max);
    printf("  area:       %.1f mm²\n", in->area_mm2);
    printf("  volume:     %.1f mm³\n", in->volume_mm3);
    if (p->mesh_id && p->volume_mm3 > 0) {
        double missing = p->volume_mm3 - in->volume_mm3;
        printf("  intact:     %.1f mm³ (part %s)\n", p->volume_mm3, cli_tx(p->number));
        printf("  missing:    %.1f mm³ (%.2f %% of intact)\n", missing,
               100.0 * missing / p->volume_mm3);
    }
    printf("  created:    %s\n", in->created_at);
}

/* An instance with its part's figures, as `instance show` and `instance set` print it:
 * the text view, or one JSON object with the part's name and the volumes. */
static int print_instance(const sr_instance_info *in, const sr_part_info *p, bool json)
{
    if (!json) {
        print_instance_text(in, p);
        return CLI_OK;
    }
    bool has = p->mesh_id && in->mesh_id;
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_instance_members(&j, in);
    json_key(&j, "part_name");
    json_string(&j, p->name);
    json_key(&j, "intact_volume_mm3");
    has ? json_number(&j, p->volume_mm3) : json_null(&j);
    json_key(&j, "missing_volume_mm3");
    has ? json_number(&j, p->volume_mm3 - in->volume_mm3) : json_null(&j);
    json_object_end(&j);
    return json_finish(&j);
}

static int instance_show(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"instance show", usage_show, opts, 1, 1, "an instance id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    int64_t id;
    if (!cli_parse_id("ID", key, &id))
        return CLI_USAGE;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_instance_info in;
    sr_part_info p;
    sr_status st = sr_catalog_instance_get(cat, id, &in, &err);
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, in.part_number, &p, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    rc = print_instance(&in, &p, json);
    sr_catalog_close(cat);
    return rc;
}

static int instance_set(const cli_ctx *ctx, int argc, char **argv)
{
    sr_instance_change ch = {NULL, NULL, NULL};
    bool json = false;
    const cli_opt opts[] = {
        {"--serial", &ch.serial, NULL},
        {"--received", &ch.received, NULL},
        {"--notes", &ch.notes, NULL},
        {"--json", NULL, &json},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"instance set", usage_set, opts, 1, 1, "an instance id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    int64_t id;
    if (!cli_parse_id("ID", key, &id))
        return CLI_USAGE;
    if (!ch.serial && !ch.received && !ch.notes)
        return cli_usage_error("'instance set' needs --serial, --received or --notes (see "
                               "'symrec instance set --help')");
    if (ch.received && *ch.received && !cli_date_valid(ch.received))
        return cli_usage_error("bad --received '%s': expected a date YYYY-MM-DD",
                               cli_tx(ch.received));
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "change the instance", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_instance_info in;
    sr_part_info p;
    sr_status st = sr_catalog_instance_set(cat, id, &ch, &err);
    if (st == SR_OK)
        st = sr_catalog_instance_get(cat, id, &in, &err);
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, in.part_number, &p, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    cli_note("changed instance %lld of part '%s'", (long long)id, cli_tx(in.part_number));
    rc = print_instance(&in, &p, json);
    sr_catalog_close(cat);
    return rc;
}

static int instance_remove(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false, with_runs = false;
    const cli_opt opts[] = {
        {"--with-runs", NULL, &with_runs}, {"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"instance remove", usage_remove, opts, 1, 1, "an instance id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    int64_t id;
    if (!cli_parse_id("ID", key, &id))
        return CLI_USAGE;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "remove the instance", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_instance_info in;
    sr_removal r;
    sr_status st = sr_catalog_instance_get(cat, id, &in, &err);
    if (st == SR_OK)
        st = sr_catalog_instance_remove(cat, id, with_runs ? SR_CATALOG_WITH_RUNS : 0, &r, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "instance");
        json_int(&j, id);
        json_key(&j, "part");
        json_string(&j, in.part_number);
        json_key(&j, "runs");
        json_int(&j, r.runs);
        json_key(&j, "meshes");
        json_int(&j, r.meshes);
        json_object_end(&j);
        return json_finish(&j);
    }
    char what[96] = "";
    if (r.runs) {
        memcpy(what, " with ", 7);
        cli_removal_str(&r, false, what + 6, sizeof what - 6);
    }
    printf("removed instance %lld of part %s%s\n", (long long)id, cli_tx(in.part_number), what);
    return CLI_OK;
}

int cmd_instance(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"add", instance_add},       {"list", instance_list},
                                          {"show", instance_show},     {"set", instance_set},
                                          {"remove", instance_remove}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "instance", usage_instance, subs, argc, argv);
}
