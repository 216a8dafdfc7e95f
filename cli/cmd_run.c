/*
 * cmd_run.c: `symrec run list` and `symrec run show N`: the record of reconstruction
 * runs that `symrec reconstruct INSTANCE` writes (src/catalog/catalog_runs.h), read back as a
 * table or in full: parameters, alignment and fit, timings, the missing sections with
 * their figures, class and features, the advice given, and on request the per-layer
 * outlines.
 *
 * `run show --json` is a contract for scripts and for the report/advice commands:
 * each section has a "features" object holding at least z_min_mm, z_max_mm,
 * angle_min_deg/angle_max_deg (axial) or side (planar), depth_max_mm, depth_mean_mm,
 * volume_mm3, area_mm2 and class, followed by the members of the section's stored
 * features_json that do not repeat those; each advice entry has process, rules
 * (names) and reason. The stored JSON texts (timings, features, details) go into the
 * document compacted, as raw values of the one JSON writer (json_out.h).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_scan.h"
#include "catalog/catalog_inspect.h"
#include "catalog/catalog_runs.h"
#include "cli.h"
#include "json_out.h"

static const char usage_run[] =
    "usage: symrec [--db FILE] run list [--instance N] [--part P] [--json]\n"
    "       symrec [--db FILE] run show N [--layers] [--json]\n"
    "\n"
    "  list    the recorded reconstruction runs, newest first\n"
    "  show    one run in full\n";

static const char usage_list[] =
    "usage: symrec [--db FILE] run list [--instance N] [--part P] [--json]\n"
    "\n"
    "Lists the reconstruction runs recorded by 'symrec reconstruct INSTANCE', newest\n"
    "first: id, start date (UTC), part, serial, symmetry, method, number of missing\n"
    "sections, missing volume (mm³, the sum of the sections'), status and the process\n"
    "advised for the largest section.\n"
    "\n"
    "  --instance N   only runs of instance N\n"
    "  --part P       only runs of instances of part P (number or id)\n"
    "  --json         one JSON array of run summaries\n";

static const char usage_show[] =
    "usage: symrec [--db FILE] run show N [--layers] [--json]\n"
    "\n"
    "Shows run N in full: instance and part, status, software version and times, the\n"
    "symmetry and every parameter as used (with the proposal of --symmetry auto:\n"
    "kind, confidence, consistency per kind), the alignment (the 3x4 scan-to-aligned\n"
    "transform) and its fit quality, the timings per phase (s), the restored mesh, the\n"
    "missing sections (layers, z range in mm, angular range in degrees for axial parts\n"
    "or the side of the plane for planar ones, depth max/mean in mm, volume mm³, area\n"
    "mm², damage class and features) and the advice given. Sections are numbered from\n"
    "1, largest first.\n"
    "\n"
    "  --layers   add the per-layer outlines: for every layer its height (mm) and, for\n"
    "             every sector, the damaged and the restored outline point (x, y) in\n"
    "             the aligned frame (mm; '-' / null where a sector has no point)\n"
    "  --json     one JSON object; sections[] each with a \"features\" object,\n"
    "             advice[] with \"section\" (its number, null = whole part),\n"
    "             \"process\", \"rules\" (names), \"reason\" and \"details\", and\n"
    "             \"nominal\": the part's intact mesh as a second opinion (see\n"
    "             'symrec reconstruct --help'; null when the run had none), and\n"
    "             \"scan_gaps\": the openings of an open scan, closed before the\n"
    "             reconstruction and kept apart from the sections, with \"sags\" and\n"
    "             \"sag_mm3\": what was restored behind their fills, not damage (null\n"
    "             for a closed input)\n";

/* ---- JSON text stored by other modules (timings, features, details) ----
 * Read with base/json_scan.h: bounded by the terminating NUL, so a damaged text gives
 * a short or null value, never a crash; written through json_raw and json_key_raw, so
 * the builder places the commas. */

/* The JSON text [p, end) without the whitespace outside strings, as a heap string
 * (free() it); NULL when out of memory. */
static char *compact(const char *p, const char *end)
{
    char *out = malloc((size_t)(end - p) + 1), *o = out;
    if (!out)
        return NULL;
    bool in_str = false;
    for (; p < end; p++) {
        char c = *p;
        if (in_str) {
            *o++ = c;
            if (c == '\\' && p + 1 < end)
                *o++ = *++p;
            else if (c == '"')
                in_str = false;
        } else if (c == '"') {
            in_str = true;
            *o++ = c;
        } else if (c != ' ' && c != '\t' && c != '\n' && c != '\r') {
            *o++ = c;
        }
    }
    *o = '\0';
    return out;
}

/* Prints the JSON text [p, end) compacted (as stored when out of memory). */
static void print_compact(const char *p, const char *end)
{
    char *text = compact(p, end);
    if (text)
        fputs(text, stdout);
    else
        fwrite(p, 1, (size_t)(end - p), stdout);
    free(text);
}

/* Writes the stored JSON value [p, end) as the next value, compacted. */
static void json_stored_span(json_out *j, const char *p, const char *end)
{
    char *text = compact(p, end);
    if (text)
        json_raw(j, text);
    else
        json_nomem(j);
    free(text);
}

/* Writes a stored JSON text as the next value (null when NULL or unreadable). */
static void json_stored(json_out *j, const char *text)
{
    const char *p = text ? sr_json_skip_space(text) : NULL;
    const char *end = p ? sr_json_value_end(p) : NULL;
    if (end)
        json_stored_span(j, p, end);
    else
        json_null(j);
}

/* ---- run list ---- */

typedef struct list_ctx {
    bool json;
    json_out j;
    cli_table t;
    size_t count;
} list_ctx;

static int list_row(const sr_run_summary *s, void *user)
{
    list_ctx *c = user;
    c->count++;
    char sym[64];
    if (c->json) {
        json_out *j = &c->j;
        json_object_begin(j);
        json_key(j, "id");
        json_int(j, s->id);
        json_key(j, "run_id"); /* the name reconstruct --json gives it */
        json_int(j, s->id);
        json_key(j, "instance_id");
        json_int(j, s->instance_id);
        json_key(j, "part_number");
        json_string(j, s->part_number);
        json_key(j, "serial");
        json_string(j, s->serial[0] ? s->serial : NULL);
        json_key(j, "material");
        json_string(j, s->material[0] ? s->material : NULL);
        json_key(j, "symmetry");
        json_symmetry(j, &s->symmetry);
        json_key(j, "method");
        json_string(j, s->method);
        json_key(j, "status");
        json_string(j, s->ok ? "ok" : "failed");
        json_key(j, "started_at");
        json_string(j, s->started_at);
        json_key(j, "sections");
        json_int(j, (int64_t)s->section_count);
        json_key(j, "missing_volume_mm3");
        json_number(j, s->missing_volume_mm3);
        json_key(j, "process");
        json_string(j, s->process[0] ? s->process : NULL);
        json_key(j, "unbuilt_sections"); /* found missing, no closed patch: not restored */
        json_int(j, (int64_t)s->unbuilt_sections);
        json_object_end(j);
        return 0;
    }
    cli_table *t = &c->t;
    cli_table_cell(t, "%lld", (long long)s->id);
    cli_table_cell(t, "%.10s", s->started_at);
    cli_table_cell(t, "%s", s->part_number);
    cli_table_cell(t, "%s", s->serial[0] ? s->serial : "-");
    cli_table_cell(t, "%s", cli_sym_str(&s->symmetry, sym, sizeof sym));
    cli_table_cell(t, "%s", s->method);
    cli_table_cell(t, "%zu", s->section_count);
    cli_table_cell(t, "%.1f", s->missing_volume_mm3);
    if (s->ok && s->unbuilt_sections) /* a loss found and not restored: said where listed */
        cli_table_cell(t, "ok, %zu not built", s->unbuilt_sections);
    else
        cli_table_cell(t, "%s", s->ok ? "ok" : "failed");
    cli_table_cell(t, "%s", s->process[0] ? s->process : "-");
    return 0;
}

static int run_list(const cli_ctx *ctx, int argc, char **argv)
{
    const char *instance = NULL, *part = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--instance", &instance, NULL},
                            {"--part", &part, NULL},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"run list", usage_list, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_run_filter filter = {0, part};
    if (instance && !cli_parse_id("--instance", instance, &filter.instance_id))
        return CLI_USAGE;
    if (part && !*part)
        return cli_usage_error("bad --part '': expected a part number or id");
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = SR_OK;
    if (filter.instance_id) {
        sr_instance_info inst;
        st = sr_catalog_instance_get(cat, filter.instance_id, &inst, &err);
    }
    list_ctx c;
    memset(&c, 0, sizeof c);
    c.json = json;
    static const char *const headers[] = {"id",       "date",     "part",        "serial",
                                          "symmetry", "method",   "sections",
                                          "missing mm³", "status", "process"};
    static const bool right[] = {true, false, false, false, false,
                                 false, true, true, false, false};
    cli_table_init(&c.t, 10, headers, right);
    /* The JSON document is started only when the query can run (the look-ups above
     * and the part filter are checked first), and discarded if the query fails. */
    if (st == SR_OK && part) {
        sr_part_info p;
        st = sr_catalog_part_find(cat, part, &p, &err);
    }
    if (st == SR_OK && json) {
        json_init(&c.j, stdout);
        json_array_begin(&c.j);
    }
    if (st == SR_OK)
        st = sr_catalog_run_list(cat, &filter, list_row, &c, &err);
    sr_catalog_close(cat);
    if (st != SR_OK) {
        if (json)
            json_discard(&c.j); /* c is zeroed: also when never started */
        cli_table_release(&c.t);
        return cli_fail(st, &err);
    }
    rc = CLI_OK;
    if (json) {
        json_array_end(&c.j);
        rc = json_finish(&c.j);
    } else if (c.count == 0) {
        printf("no runs\n");
    } else if (!cli_table_print(&c.t, stdout, 0)) {
        rc = CLI_FAIL;
    }
    cli_table_release(&c.t);
    return rc;
}

/* ---- run show ---- */

static const char *const fixed_features[] = {
    "z_min_mm", "z_max_mm", "angle_min_deg", "angle_max_deg", "arc_deg", "side",
    "depth_max_mm", "depth_mean_mm", "volume_mm3", "area_mm2", "class", "layer_first",
    "layer_last", NULL};

static void feature_member(const char *key, size_t len, const char *val, const char *end,
                           void *user)
{
    json_out *j = user;
    for (size_t i = 0; fixed_features[i]; i++)
        if (strlen(fixed_features[i]) == len && memcmp(fixed_features[i], key, len) == 0)
            return;
    /* the key as written (escapes included), then the value */
    json_key_raw(j, key, len);
    json_stored_span(j, val, end);
}

/* Counter-clockwise end of an axial arc as reconstruct prints it: in [0, 360], a
 * wrapping arc ending below its start. */
static double arc_end(const sr_run_section *s)
{
    if (s->angle_to_deg - s->angle_from_deg >= 360)
        return s->angle_from_deg + 360;
    return s->angle_to_deg > 360 ? s->angle_to_deg - 360 : s->angle_to_deg;
}

void json_run_features(json_out *j, const sr_run_section *s)
{
    json_object_begin(j);
    json_key(j, "z_min_mm");
    json_number(j, s->z_min_mm);
    json_key(j, "z_max_mm");
    json_number(j, s->z_max_mm);
    if (s->has_angles) {
        json_key(j, "angle_min_deg");
        json_number(j, s->angle_from_deg);
        json_key(j, "angle_max_deg");
        json_number(j, arc_end(s));
        json_key(j, "arc_deg");
        json_number(j, s->angle_to_deg - s->angle_from_deg);
    } else {
        json_key(j, "side");
        if (s->side)
            json_int(j, s->side);
        else
            json_null(j);
    }
    json_key(j, "depth_max_mm");
    json_number(j, s->depth_max_mm);
    json_key(j, "depth_mean_mm");
    json_number(j, s->depth_mean_mm);
    json_key(j, "volume_mm3");
    json_number(j, s->volume_mm3);
    json_key(j, "area_mm2");
    json_number(j, s->area_mm2);
    json_key(j, "class");
    json_string(j, s->damage_class);
    sr_json_for_members(s->features_json, feature_member, j);
    json_object_end(j);
}

static void json_section(json_out *j, const sr_run_section *s)
{
    json_object_begin(j);
    json_key(j, "index");
    json_int(j, (int64_t)s->index + 1);
    json_key(j, "id");
    json_int(j, s->id);
    json_key(j, "layer_first");
    json_int(j, (int64_t)s->layer_first);
    json_key(j, "layer_last");
    json_int(j, (int64_t)s->layer_last);
    json_key(j, "patch_triangles");
    json_int(j, (int64_t)s->patch.tri_count);
    json_key(j, "features");
    json_run_features(j, s);
    json_object_end(j);
}

static void json_point(json_out *j, const double *xy)
{
    json_array_begin(j);
    json_number(j, xy[0]);
    json_number(j, xy[1]);
    json_array_end(j);
}

void json_run_advice(json_out *j, const sr_run *r)
{
    json_array_begin(j);
    for (size_t i = 0; i < r->advice_count; i++) {
        const sr_run_advice *a = &r->advice[i];
        json_object_begin(j);
        json_key(j, "section");
        if (a->section_index >= 0)
            json_int(j, (int64_t)a->section_index + 1);
        else
            json_null(j);
        json_key(j, "process");
        json_string(j, a->process);
        json_key(j, "rules");
        json_array_begin(j);
        if (a->rule_name[0])
            json_string(j, a->rule_name);
        json_array_end(j);
        json_key(j, "rule_id");
        if (a->rule_id)
            json_int(j, a->rule_id);
        else
            json_null(j);
        json_key(j, "reason");
        json_string(j, a->reason);
        json_key(j, "details");
        json_stored(j, a->details_json ? a->details_json : "{}");
        json_object_end(j);
    }
    json_array_end(j);
}

/* The latest inspection as run show gives it (NULL = none). */
static void json_inspection(json_out *j, const sr_inspection_info *v)
{
    if (!v) {
        json_null(j);
        return;
    }
    json_object_begin(j);
    json_key(j, "id");
    json_int(j, v->id);
    json_key(j, "verdict");
    json_string(j, v->verdict);
    json_key(j, "reasons");
    json_string(j, v->reasons);
    json_key(j, "allowance_mm");
    json_number(j, v->allowance_mm);
    json_key(j, "tolerance_mm");
    json_number(j, v->tolerance_mm);
    json_key(j, "registered");
    json_bool(j, v->registered);
    json_key(j, "inspected_at");
    json_string(j, v->inspected_at);
    json_object_end(j);
}

static int print_json(const sr_run *r, bool layers, const sr_inspection_info *insp)
{
    json_out jo, *j = &jo;
    json_init(j, stdout);
    json_object_begin(j);
    json_key(j, "id");
    json_int(j, r->id);
    json_key(j, "run_id"); /* the name reconstruct --json gives it */
    json_int(j, r->id);
    json_key(j, "instance_id");
    json_int(j, r->instance_id);
    json_key(j, "part_number");
    json_string(j, r->part_number);
    json_key(j, "status");
    json_string(j, r->ok ? "ok" : "failed");
    json_key(j, "error");
    json_string(j, r->ok ? NULL : r->error);
    json_key(j, "software_version");
    json_string(j, r->software_version);
    json_key(j, "started_at");
    json_string(j, r->started_at);
    json_key(j, "finished_at");
    json_string(j, r->finished_at[0] ? r->finished_at : NULL);
    json_key(j, "method");
    json_string(j, r->method);
    json_key(j, "symmetry");
    json_symmetry(j, &r->symmetry);
    json_key(j, "symmetry_fit"); /* reconstruct --symmetry auto: the proposal; else null */
    cli_symfit_json(j, r->symmetry_fit_json);
    json_key(j, "params");
    json_params(j, &r->params);
    json_key(j, "alignment");
    json_object_begin(j);
    json_key(j, "transform");
    if (r->has_alignment) {
        json_array_begin(j);
        for (int i = 0; i < 12; i++)
            json_number(j, r->alignment[i]);
        json_array_end(j);
    } else {
        json_null(j);
    }
    json_key(j, "given");
    json_bool(j, r->alignment_given);
    json_key(j, "fit_quality");
    if (r->fit_quality >= 0)
        json_number(j, r->fit_quality);
    else
        json_null(j);
    json_object_end(j);
    json_key(j, "timings");
    json_stored(j, r->timings_json);
    json_key(j, "restored_mesh");
    if (r->restored.tri_count > 0) {
        json_object_begin(j);
        json_key(j, "vertices");
        json_int(j, (int64_t)r->restored.vertex_count);
        json_key(j, "triangles");
        json_int(j, (int64_t)r->restored.tri_count);
        json_key(j, "volume_mm3");
        json_number(j, sr_mesh_volume(&r->restored));
        json_key(j, "closed");
        json_bool(j, sr_mesh_is_closed(&r->restored));
        json_object_end(j);
    } else {
        json_null(j);
    }
    double missing = 0;
    for (size_t i = 0; i < r->section_count; i++)
        missing += r->sections[i].volume_mm3;
    json_key(j, "missing_volume_mm3");
    json_number(j, missing);
    json_key(j, "sections");
    json_array_begin(j);
    for (size_t i = 0; i < r->section_count; i++)
        json_section(j, &r->sections[i]);
    json_array_end(j);
    json_key(j, "unbuilt_sections"); /* found missing, no closed patch: not restored */
    json_int(j, (int64_t)r->unbuilt_sections);
    json_key(j, "unbuilt_mm3");
    json_number(j, r->unbuilt_mm3);
    json_key(j, "advice");
    json_run_advice(j, r);
    json_key(j, "nominal");
    json_run_nominal(j, r->nominal);
    json_key(j, "scan_gaps"); /* the input's openings, closed before the reconstruction:
                                * not sections; null = a closed input */
    json_run_scan(j, r->scan);
    json_key(j, "inspection"); /* the latest (symrec inspect); null = never inspected */
    json_inspection(j, insp);
    if (layers) {
        json_key(j, "sectors");
        json_int(j, (int64_t)r->sectors);
        json_key(j, "layers");
        json_array_begin(j);
        for (size_t l = 0; l < r->layer_count; l++) {
            json_object_begin(j);
            json_key(j, "index");
            json_int(j, (int64_t)l);
            json_key(j, "z_mm");
            json_number(j, r->layer_z[l]);
            json_key(j, "damaged");
            json_array_begin(j);
            for (size_t k = 0; k < r->sectors; k++)
                json_point(j, r->damaged_xy + 2 * (l * r->sectors + k));
            json_array_end(j);
            json_key(j, "restored");
            json_array_begin(j);
            for (size_t k = 0; k < r->sectors; k++)
                json_point(j, r->restored_xy + 2 * (l * r->sectors + k));
            json_array_end(j);
            json_object_end(j);
        }
        json_array_end(j);
    }
    json_object_end(j);
    return json_finish(j);
}

static void timing_member(const char *key, size_t len, const char *val, const char *end,
                          void *user)
{
    int *n = user;
    char *stop;
    double v = strtod(val, &stop);
    printf("%s%.*s ", (*n)++ ? ", " : "", (int)len, key);
    if (stop == end)
        printf("%.3f s", v);
    else
        print_compact(val, end);
}

static void print_point(const double *xy)
{
    if (isfinite(xy[0]) && isfinite(xy[1]))
        printf(" %.3f,%.3f", xy[0], xy[1]);
    else
        printf(" -");
}

void cli_run_advice_print(const sr_run *r)
{
    for (size_t i = 0; i < r->section_count; i++)
        if (r->sections[i].features_json) {
            printf("    features of %zu: ", r->sections[i].index + 1);
            const char *f = r->sections[i].features_json;
            print_compact(f, f + strlen(f));
            printf("\n");
        }
    if (r->advice_count == 0) {
        printf("  advice:      none\n");
    } else {
        printf("  advice:\n");
        for (size_t i = 0; i < r->advice_count; i++) {
            const sr_run_advice *a = &r->advice[i];
            char where[32];
            if (a->section_index >= 0)
                snprintf(where, sizeof where, "section %ld", a->section_index + 1);
            else
                snprintf(where, sizeof where, "whole part");
            printf("    %s: %s (rule %s): %s\n", where, cli_tx(a->process),
                   a->rule_name[0] ? cli_tx(a->rule_name) : "-", cli_tx(a->reason));
        }
    }
}

static bool print_text(const sr_run *r, bool layers, const sr_inspection_info *insp)
{
    char sym[64];
    const sr_params *p = &r->params;
    printf("run %lld: instance %lld of part %s, %s\n", (long long)r->id, (long long)r->instance_id,
           cli_tx(r->part_number), r->ok ? "ok" : "failed");
    if (!r->ok)
        cli_print_field(stdout, "  error:       ", r->error);
    printf("  started:     %s, finished %s\n", r->started_at,
           r->finished_at[0] ? r->finished_at : "-");
    printf("  software:    symrec %s, method %s\n", cli_tx(r->software_version), cli_tx(r->method));
    printf("  symmetry:    %s\n", cli_sym_str(&r->symmetry, sym, sizeof sym));
    cli_symfit_print_line("  proposed:    by --symmetry auto: ", r->symmetry_fit_json);
    printf("  parameters:  set '%s': %d layers, %d sectors, gamma_axis %g, gamma_plane %g,\n"
           "               delta_d %g, min depth %g mm, min volume %g mm³\n",
           cli_tx(p->name), p->layers, p->sectors, p->gamma_axis, p->gamma_plane, p->delta_d,
           p->min_depth_mm, p->min_volume_mm3);
    if (r->has_alignment) {
        printf("  alignment:   scan -> aligned frame (%s), 3x4:\n",
               r->alignment_given ? "given by the user" : "found by search");
        for (int i = 0; i < 3; i++)
            printf("               %10.6f %10.6f %10.6f %12.4f\n", r->alignment[4 * i],
                   r->alignment[4 * i + 1], r->alignment[4 * i + 2], r->alignment[4 * i + 3]);
    } else {
        printf("  alignment:   not reached\n");
    }
    if (r->fit_quality >= 0)
        printf("  fit quality: %.3f\n", r->fit_quality);
    else
        printf("  fit quality: -\n");
    if (r->timings_json) {
        int n = 0;
        printf("  timings:     ");
        sr_json_for_members(r->timings_json, timing_member, &n);
        printf("\n");
    }
    if (r->restored.tri_count > 0)
        printf("  restored:    %zu triangles, volume %.1f mm³%s\n", r->restored.tri_count,
               sr_mesh_volume(&r->restored),
               sr_mesh_is_closed(&r->restored) ? ", closed" : ", not closed");
    else
        printf("  restored:    none\n");
    double missing = 0;
    for (size_t i = 0; i < r->section_count; i++)
        missing += r->sections[i].volume_mm3;
    if (r->unbuilt_sections)
        printf("  not built:   %zu section(s) found missing, about %.1f mm³ by voxels, gave no "
               "closed patch: not restored\n",
               r->unbuilt_sections, r->unbuilt_mm3);
    if (r->section_count == 0 && r->unbuilt_sections) {
        printf("  sections:    none built\n");
    } else if (r->section_count == 0) {
        printf("  sections:    none (nothing to repair)\n");
    } else {
        printf("  sections:    %zu, missing volume %.1f mm³\n", r->section_count, missing);
        static const char *const headers[] = {"#",           "layers",        "z mm",
                                              "where",       "depth max mm",  "depth mean mm",
                                              "volume mm³",  "area mm²",      "class"};
        static const bool right[] = {true, false, false, false, true, true, true, true, false};
        cli_table t;
        cli_table_init(&t, 9, headers, right);
        for (size_t i = 0; i < r->section_count; i++) {
            const sr_run_section *s = &r->sections[i];
            cli_table_cell(&t, "%zu", s->index + 1);
            cli_table_cell(&t, "%zu..%zu", s->layer_first, s->layer_last);
            cli_table_cell(&t, "%.2f..%.2f", s->z_min_mm, s->z_max_mm);
            if (s->has_angles)
                cli_table_cell(&t, "%.1f..%.1f deg", s->angle_from_deg, arc_end(s));
            else if (s->side)
                cli_table_cell(&t, "side %+d", s->side);
            else
                cli_table_cell(&t, "-");
            cli_table_cell(&t, "%.3f", s->depth_max_mm);
            cli_table_cell(&t, "%.3f", s->depth_mean_mm);
            cli_table_cell(&t, "%.1f", s->volume_mm3);
            cli_table_cell(&t, "%.1f", s->area_mm2);
            cli_table_cell(&t, "%s", s->damage_class);
        }
        bool ok = cli_table_print(&t, stdout, 4);
        cli_table_release(&t);
        if (!ok)
            return false;
    }
    cli_run_scan_print(r->scan);
    cli_nominal_print(r->nominal, "none recorded");
    cli_run_advice_print(r);
    if (insp)
        printf("  inspection:  %lld on %s: %s: %s (allowance %.3g mm, tolerance %.3g mm)\n",
               (long long)insp->id, insp->inspected_at, insp->verdict, cli_tx(insp->reasons),
               insp->allowance_mm, insp->tolerance_mm);
    if (layers) {
        printf("  layers:      %zu x %zu sectors (aligned frame, x,y in mm; - = no point)\n",
               r->layer_count, r->sectors);
        for (size_t l = 0; l < r->layer_count; l++) {
            printf("    layer %zu z %.4f\n      damaged: ", l, r->layer_z[l]);
            for (size_t k = 0; k < r->sectors; k++)
                print_point(r->damaged_xy + 2 * (l * r->sectors + k));
            printf("\n      restored:");
            for (size_t k = 0; k < r->sectors; k++)
                print_point(r->restored_xy + 2 * (l * r->sectors + k));
            printf("\n");
        }
    }
    return true;
}

static int run_show(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false, layers = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {"--layers", NULL, &layers},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"run show", usage_show, opts, 1, 1, "a run id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    int64_t id;
    if (!cli_parse_id("N", key, &id))
        return CLI_USAGE;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_run r;
    sr_status st = sr_catalog_run_get(
        cat, id, SR_RUN_WITH_MESHES | (layers ? SR_RUN_WITH_LAYERS : 0), &r, &err);
    sr_inspection_info insp;
    bool inspected = false;
    if (st == SR_OK) {
        st = sr_catalog_inspection_latest(cat, id, &insp, &inspected, &err);
        if (st != SR_OK)
            sr_run_release(&r);
    }
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    rc = CLI_OK;
    if (json)
        rc = print_json(&r, layers, inspected ? &insp : NULL);
    else if (!print_text(&r, layers, inspected ? &insp : NULL))
        rc = CLI_FAIL;
    sr_run_release(&r);
    return rc;
}

int cmd_run(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"list", run_list}, {"show", run_show}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "run", usage_run, subs, argc, argv);
}
