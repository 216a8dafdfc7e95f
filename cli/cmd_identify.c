/*
 * cmd_identify.c: `symrec identify SCAN`: which catalogue part a scan is of. The
 * work is src/catalog/catalog_identify.c (descriptor pre-filter, trimmed registration
 * of the closest parts); this file parses, prints the ranking and the verdict, and
 * owns the printing `instance add --part auto` shares (cli_identify_print).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_identify.h"
#include "cli.h"
#include "json_out.h"

static const char usage_identify[] =
    "usage: symrec [--db FILE] identify SCAN [--top K] [--tol MM] [--units U] [--json]\n"
    "\n"
    "Finds which catalogue part a scan (a damaged or intact piece, in any pose) is of:\n"
    "the parts with an intact mesh ranked by how well they explain the scan. The parts\n"
    "whose shape descriptor (pose-invariant: D2 distances, principal spreads; size\n"
    "kept) is closest to the scan's are registered to it (rigid, trimmed: up to a\n"
    "quarter of the part may be missing) and ranked by score. For each: the part\n"
    "number and name, the score (0..1: coverage x (1 - lacking), less for a large RMS),\n"
    "the coverage (% of the scan's surface within the tolerance of the part; in\n"
    "--json also \"inside\": % farther, inside the part's solid: fracture faces), the RMS\n"
    "distance of that surface (mm), how much of the part the scan lacks (% of the\n"
    "part's surface farther than the tolerance from the scan) and the rigid transform\n"
    "from the scan to the part's frame (rotation in degrees, move in mm).\n"
    "\n"
    "Then the verdict: `match` (the first explains the scan: coverage >= 50 % and with\n"
    "the fracture faces inside the part >= 80 %, lacking <= 30 %, RMS <= a quarter of\n"
    "the tolerance, and the next other design scores at\n"
    "least 0.05 less), `too close to call` (two designs within 0.05), or `no match`\n"
    "(no part explains the scan: it is of a part not in the catalogue). Parts within\n"
    "0.05 of the first whose intact meshes are the first's (each within the tolerance\n"
    "of the other) are one design under several numbers: the match names them all.\n"
    "Parts added before\n"
    "descriptors were kept get theirs computed on the first run, and stored when the\n"
    "catalogue can be written.\n"
    "\n"
    "  SCAN       a mesh file (.stl .obj .ply .off .gltf .glb)\n"
    "  --units U  the unit SCAN is drawn in: mm, cm, m or in (default: mm for .stl\n"
    "             .obj .ply .off, m for .gltf .glb)\n"
    "  --top K    how many candidates to show, 1..20 (default 3; at least 4 are\n"
    "             registered, and up to 10 about as close by descriptor)\n"
    "  --tol MM   the tolerance for coverage and lacking, mm (default 0.5 % of the\n"
    "             scan's bounding-box diagonal)\n"
    "  --json     one JSON object: {\"scan\", \"tol_mm\", \"parts\", \"registered\",\n"
    "             \"descriptors_computed\", \"descriptors_stored\", \"verdict\" (\"match\",\n"
    "             \"too_close\", \"no_match\"), \"match\" (the part number, or null),\n"
    "             \"same_design\" (the other numbers of the matched design),\n"
    "             \"candidates\": [{\"rank\", \"part\", \"name\", \"score\", \"coverage\",\n"
    "             \"inside\", \"rms_mm\", \"lacking\", \"descriptor_distance\",\n"
    "             \"rotation_deg\", \"translation_mm\", \"matrix\" (3 x 4 rows, scan -> part)}]}\n"
    "\n"
    "Exit 0 with an answer, `no match` included; 1 when the scan cannot be read or the\n"
    "catalogue holds no part with a mesh; 2 for a usage error.\n";

static double rotation_deg(const double m[12])
{
    double tr = (m[0] + m[5] + m[10] - 1) / 2;
    return acos(fmax(-1.0, fmin(1.0, tr))) * 180 / M_PI;
}

static double translation_mm(const double m[12])
{
    return sqrt(m[3] * m[3] + m[7] * m[7] + m[11] * m[11]);
}

static const char *verdict_key(sr_identify_verdict v)
{
    return v == SR_IDENTIFY_MATCH ? "match" : v == SR_IDENTIFY_TOO_CLOSE ? "too_close" : "no_match";
}

static int print_json(const sr_identify_result *res, const char *scan)
{
    json_out j;
    json_init(&j, stdout);
    json_object_begin(&j);
    json_key(&j, "scan");
    json_string(&j, scan);
    json_key(&j, "tol_mm");
    json_number(&j, res->tol_mm);
    json_key(&j, "parts");
    json_int(&j, (int64_t)res->parts);
    json_key(&j, "registered");
    json_int(&j, (int64_t)res->registered);
    json_key(&j, "descriptors_computed");
    json_int(&j, (int64_t)res->described);
    json_key(&j, "descriptors_stored");
    json_int(&j, (int64_t)res->stored);
    json_key(&j, "verdict");
    json_string(&j, verdict_key(res->verdict));
    json_key(&j, "match");
    json_string(&j, res->verdict == SR_IDENTIFY_MATCH ? res->cand[0].number : NULL);
    json_key(&j, "same_design");
    json_array_begin(&j);
    for (size_t i = 1; res->verdict == SR_IDENTIFY_MATCH && i < res->same_design; i++)
        json_string(&j, res->cand[i].number);
    json_array_end(&j);
    json_key(&j, "candidates");
    json_array_begin(&j);
    for (size_t i = 0; i < res->count; i++) {
        const sr_identify_candidate *c = &res->cand[i];
        json_object_begin(&j);
        json_key(&j, "rank");
        json_int(&j, (int64_t)i + 1);
        json_key(&j, "part");
        json_string(&j, c->number);
        json_key(&j, "name");
        json_string(&j, c->name);
        json_key(&j, "score");
        json_number(&j, c->fit.score);
        json_key(&j, "coverage");
        json_number(&j, c->fit.coverage);
        json_key(&j, "inside");
        json_number(&j, c->fit.inside);
        json_key(&j, "rms_mm");
        json_number(&j, c->fit.rms_mm);
        json_key(&j, "lacking");
        json_number(&j, c->fit.lacking);
        json_key(&j, "descriptor_distance");
        json_number(&j, c->descriptor_distance);
        json_key(&j, "rotation_deg");
        json_number(&j, rotation_deg(c->fit.mat));
        json_key(&j, "translation_mm");
        json_number(&j, translation_mm(c->fit.mat));
        json_key(&j, "matrix");
        json_array_begin(&j);
        for (int r = 0; r < 3; r++) {
            json_array_begin(&j);
            for (int k = 0; k < 4; k++)
                json_number(&j, c->fit.mat[4 * r + k]);
            json_array_end(&j);
        }
        json_array_end(&j);
        json_object_end(&j);
    }
    json_array_end(&j);
    json_object_end(&j);
    return json_finish(&j);
}

int cli_identify_print(const sr_identify_result *res, const char *scan, bool json)
{
    if (json)
        return print_json(res, scan);
    static const char *const headers[] = {"rank",   "part",    "name",         "score",  "covers",
                                          "RMS mm", "lacking", "rotation deg", "move mm"};
    static const bool right[] = {true, false, false, true, true, true, true, true, true};
    cli_table t;
    cli_table_init(&t, 9, headers, right);
    for (size_t i = 0; i < res->count; i++) {
        const sr_identify_candidate *c = &res->cand[i];
        cli_table_cell(&t, "%zu", i + 1);
        cli_table_cell(&t, "%s", c->number);
        cli_table_cell(&t, "%s", c->name);
        cli_table_cell(&t, "%.3f", c->fit.score);
        cli_table_cell(&t, "%.1f %%", 100 * c->fit.coverage);
        cli_table_cell(&t, "%.3f", c->fit.rms_mm);
        cli_table_cell(&t, "%.1f %%", 100 * c->fit.lacking);
        cli_table_cell(&t, "%.1f", rotation_deg(c->fit.mat));
        cli_table_cell(&t, "%.2f", translation_mm(c->fit.mat));
    }
    printf("scan %s against %zu parts, %zu registered (tolerance %.3f mm):\n", cli_tx(scan),
           res->parts, res->registered, res->tol_mm);
    bool ok = cli_table_print(&t, stdout, 2);
    cli_table_release(&t);
    const sr_identify_candidate *a = &res->cand[0];
    size_t k = res->same_design;
    if (res->verdict == SR_IDENTIFY_MATCH) {
        printf("match: part '%s' (%s), score %.3f, next %.3f\n", cli_tx(a->number), cli_tx(a->name),
               a->fit.score, k < res->registered ? res->cand[k].fit.score : 0.0);
        for (size_t i = 1; i < k; i++)
            printf("  the same design as part '%s' (%s, score %.3f): its intact mesh is this "
                   "part's within the tolerance\n",
                   cli_tx(res->cand[i].number), cli_tx(res->cand[i].name), res->cand[i].fit.score);
    } else if (res->verdict == SR_IDENTIFY_TOO_CLOSE) {
        printf("too close to call: parts '%s' and '%s' score %.3f and %.3f\n", cli_tx(a->number),
               cli_tx(res->cand[k].number), a->fit.score, res->cand[k].fit.score);
    } else
        printf("no match: no part explains the scan (best: '%s', %.1f %% of the scan on it "
               "and %.1f %% inside it, %.1f %% of it lacking)\n",
               cli_tx(a->number), 100 * a->fit.coverage, 100 * a->fit.inside, 100 * a->fit.lacking);
    return ok ? CLI_OK : CLI_FAIL;
}

int cmd_identify(const cli_ctx *ctx, int argc, char **argv)
{
    const char *top_text = NULL, *tol_text = NULL, *scan_path = NULL, *units = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--top", &top_text, NULL}, {"--tol", &tol_text, NULL}, {"--units", &units, NULL},
        {"--json", NULL, &json},    {NULL, NULL, NULL},
    };
    const cli_spec spec = {"identify", usage_identify, opts, 1, 1, "SCAN"};
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, &scan_path, NULL, &rc))
        return rc;
    sr_identify_opts o = {0, 0};
    int top = 0;
    if (top_text) {
        if (!cli_parse_int("--top", top_text, 1, SR_IDENTIFY_TOP_MAX, "a count 1..20", &top))
            return CLI_USAGE;
        o.top = (size_t)top;
    }
    if (tol_text &&
        !cli_parse_double("--tol", tol_text, 1e-6, 1e6, "a distance in mm > 0", &o.tol_mm))
        return CLI_USAGE;
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ_CACHE, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_mesh scan;
    sr_mesh_init(&scan);
    sr_identify_result res;
    memset(&res, 0, sizeof res);
    sr_status st = cli_mesh_read(scan_path, unit, &scan, NULL, &err);
    if (st == SR_OK)
        st = sr_catalog_identify(cat, &scan, &o, &res, &err);
    sr_mesh_release(&scan);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    rc = cli_identify_print(&res, scan_path, json);
    sr_identify_result_release(&res);
    return rc;
}
