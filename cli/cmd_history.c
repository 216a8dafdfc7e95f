/*
 * cmd_history.c: `symrec history`: the repair history of a part, an instance, a
 * material or a date range (src/catalog/catalog_history.h): the runs with their damage
 * classes, missing volumes, advice and outcomes, and summaries (most frequent damage
 * per part, average missing volume, repair vs replace, runs per month). Output as a
 * table, CSV (RFC 4180: a header row, fields with commas, quotes or line breaks quoted,
 * quotes doubled, lines ended CRLF) or one JSON object {"runs": [...], "summary": {...}}.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "catalog/catalog_history.h"
#include "inspect/inspect.h"
#include "cli.h"
#include "json_out.h"

static const char usage_history[] =
    "usage: symrec [--db FILE] history [--part P] [--instance N] [--material M]\n"
    "                                  [--since DATE] [--until DATE]\n"
    "                                  [--verdict pass|machine|rework] [--summary]\n"
    "                                  [--json | --csv]\n"
    "\n"
    "The recorded reconstruction runs that match every filter given, newest first:\n"
    "run id, start date (UTC), part, serial, material, symmetry, method, status,\n"
    "number of missing sections, missing volume (mm³, the sum of the sections'), damage\n"
    "classes, processes advised and the outcome: 'replace' when any advice says\n"
    "replace, 'repair' when there is other advice, 'none' without advice; once the\n"
    "repaired part is inspected (symrec inspect), the latest inspection's verdict:\n"
    "'pass', 'machine' or 'rework'.\n"
    "\n"
    "  --part P        runs of instances of part P (number or id)\n"
    "  --instance N    runs of instance N\n"
    "  --material M    runs of parts made of material M (name, ignoring case)\n"
    "  --since DATE    runs started on or after DATE (YYYY-MM-DD, UTC)\n"
    "  --until DATE    runs started on or before DATE (YYYY-MM-DD, UTC)\n"
    "  --verdict V     runs whose latest inspection said V: pass, machine or rework\n"
    "  --summary       the summaries instead of the run list: runs, repair vs replace,\n"
    "                  average missing volume (mm³), runs by inspection verdict; per\n"
    "                  part the most frequent damage\n"
    "                  class and average missing volume; runs per month (with --csv:\n"
    "                  one CSV row per part)\n"
    "  --json          one JSON object: \"runs\" (array) and \"summary\" (object)\n"
    "  --csv           CSV with a header row (RFC 4180); a text cell starting with\n"
    "                  =, +, -, @, TAB or CR gets a leading ' so a spreadsheet shows it\n"
    "                  as text (numbers are written as they are)\n";

/* ---- CSV ---- */

/* A text cell (formula-leading text neutralised, escape.c). */
static void csv_field(FILE *f, const char *s, bool last)
{
    cli_csv_text(f, s, last);
}

static void csv_fieldf(FILE *f, bool last, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void csv_fieldf(FILE *f, bool last, const char *fmt, ...)
{
    char buf[128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    cli_csv_number(f, buf, last); /* a number cell: "-1.5" stays a number */
}

/* ---- rows ---- */

/* A comma list as a JSON array of strings. */
static void json_list(json_out *j, const char *list)
{
    json_array_begin(j);
    for (const char *p = list; *p;) {
        size_t n = strcspn(p, ",");
        char item[256];
        snprintf(item, sizeof item, "%.*s", (int)n, p);
        json_string(j, item);
        p += n + (p[n] == ',');
    }
    json_array_end(j);
}

typedef enum { OUT_TABLE, OUT_CSV, OUT_JSON } out_kind;

typedef struct rows_ctx {
    out_kind kind;
    json_out *j;
    cli_table t;
    size_t count;
} rows_ctx;

static int row_out(const sr_history_row *r, void *user)
{
    rows_ctx *c = user;
    c->count++;
    char sym[64];
    cli_sym_str(&r->symmetry, sym, sizeof sym);
    /* the outcome follows the latest inspection */
    const char *outcome = r->verdict[0] ? r->verdict : sr_history_outcome_str(r->outcome);
    if (c->kind == OUT_JSON) {
        json_out *j = c->j;
        json_object_begin(j);
        json_key(j, "run_id");
        json_int(j, r->run_id);
        json_key(j, "date");
        json_string(j, r->date);
        json_key(j, "started_at");
        json_string(j, r->started_at);
        json_key(j, "instance_id");
        json_int(j, r->instance_id);
        json_key(j, "part_number");
        json_string(j, r->part_number);
        json_key(j, "serial");
        json_string(j, r->serial[0] ? r->serial : NULL);
        json_key(j, "material");
        json_string(j, r->material[0] ? r->material : NULL);
        json_key(j, "symmetry");
        json_symmetry(j, &r->symmetry);
        json_key(j, "method");
        json_string(j, r->method);
        json_key(j, "status");
        json_string(j, r->ok ? "ok" : "failed");
        json_key(j, "sections");
        json_int(j, (int64_t)r->section_count);
        json_key(j, "missing_volume_mm3");
        json_number(j, r->missing_volume_mm3);
        json_key(j, "damage_classes");
        json_list(j, r->classes);
        json_key(j, "advice");
        json_list(j, r->processes);
        json_key(j, "outcome");
        json_string(j, outcome);
        json_key(j, "verdict");
        json_string(j, r->verdict[0] ? r->verdict : NULL);
        json_object_end(j);
        return 0;
    }
    if (c->kind == OUT_CSV) {
        FILE *f = stdout;
        csv_fieldf(f, false, "%lld", (long long)r->run_id);
        csv_field(f, r->date, false);
        csv_field(f, r->started_at, false);
        csv_fieldf(f, false, "%lld", (long long)r->instance_id);
        csv_field(f, r->part_number, false);
        csv_field(f, r->serial, false);
        csv_field(f, r->material, false);
        csv_field(f, sym, false);
        csv_field(f, r->method, false);
        csv_field(f, r->ok ? "ok" : "failed", false);
        csv_fieldf(f, false, "%zu", r->section_count);
        csv_fieldf(f, false, "%.3f", r->missing_volume_mm3);
        csv_field(f, r->classes, false);
        csv_field(f, r->processes, false);
        csv_field(f, outcome, true);
        return 0;
    }
    cli_table *t = &c->t;
    cli_table_cell(t, "%lld", (long long)r->run_id);
    cli_table_cell(t, "%s", r->date);
    cli_table_cell(t, "%s", r->part_number);
    cli_table_cell(t, "%s", r->serial[0] ? r->serial : "-");
    cli_table_cell(t, "%s", r->material[0] ? r->material : "-");
    cli_table_cell(t, "%s", sym);
    cli_table_cell(t, "%s", r->ok ? "ok" : "failed");
    cli_table_cell(t, "%zu", r->section_count);
    cli_table_cell(t, "%.1f", r->missing_volume_mm3);
    cli_table_cell(t, "%s", r->classes[0] ? r->classes : "-");
    cli_table_cell(t, "%s", r->processes[0] ? r->processes : "-");
    cli_table_cell(t, "%s", outcome);
    return 0;
}

/* ---- summary ---- */

static void summary_json(json_out *j, const sr_history_summary *s)
{
    json_object_begin(j);
    json_key(j, "runs");
    json_int(j, (int64_t)s->runs);
    json_key(j, "failed");
    json_int(j, (int64_t)s->failed);
    json_key(j, "repair");
    json_int(j, (int64_t)s->repair);
    json_key(j, "replace");
    json_int(j, (int64_t)s->replace);
    json_key(j, "no_advice");
    json_int(j, (int64_t)s->none);
    json_key(j, "repair_fraction");
    json_number(j, s->repair_fraction); /* null when no run was advised */
    json_key(j, "avg_missing_volume_mm3");
    json_number(j, s->avg_missing_volume_mm3);
    json_key(j, "verdicts");
    json_object_begin(j);
    json_key(j, "pass");
    json_int(j, (int64_t)s->pass);
    json_key(j, "machine");
    json_int(j, (int64_t)s->machine);
    json_key(j, "rework");
    json_int(j, (int64_t)s->rework);
    json_object_end(j);
    json_key(j, "parts");
    json_array_begin(j);
    for (size_t i = 0; i < s->part_count; i++) {
        const sr_history_part *p = &s->parts[i];
        json_object_begin(j);
        json_key(j, "part_number");
        json_string(j, p->part_number);
        json_key(j, "runs");
        json_int(j, (int64_t)p->runs);
        json_key(j, "avg_missing_volume_mm3");
        json_number(j, p->avg_missing_volume_mm3);
        json_key(j, "most_frequent_class");
        json_string(j, p->top_class[0] ? p->top_class : NULL);
        json_key(j, "most_frequent_class_sections");
        json_int(j, (int64_t)p->top_class_sections);
        json_key(j, "sections");
        json_int(j, (int64_t)p->sections);
        json_key(j, "repair");
        json_int(j, (int64_t)p->repair);
        json_key(j, "replace");
        json_int(j, (int64_t)p->replace);
        json_object_end(j);
    }
    json_array_end(j);
    json_key(j, "months");
    json_array_begin(j);
    for (size_t i = 0; i < s->month_count; i++) {
        json_object_begin(j);
        json_key(j, "month");
        json_string(j, s->months[i].month);
        json_key(j, "runs");
        json_int(j, (int64_t)s->months[i].runs);
        json_object_end(j);
    }
    json_array_end(j);
    json_object_end(j);
}

static void summary_csv(const sr_history_summary *s)
{
    FILE *f = stdout;
    fputs("part,runs,avg_missing_volume_mm3,most_frequent_class,most_frequent_class_sections,"
          "sections,repair,replace\r\n",
          f);
    for (size_t i = 0; i < s->part_count; i++) {
        const sr_history_part *p = &s->parts[i];
        csv_field(f, p->part_number, false);
        csv_fieldf(f, false, "%zu", p->runs);
        csv_fieldf(f, false, "%.3f", p->avg_missing_volume_mm3);
        csv_field(f, p->top_class, false);
        csv_fieldf(f, false, "%zu", p->top_class_sections);
        csv_fieldf(f, false, "%zu", p->sections);
        csv_fieldf(f, false, "%zu", p->repair);
        csv_fieldf(f, true, "%zu", p->replace);
    }
}

static bool summary_table(const sr_history_summary *s)
{
    printf("runs: %zu (%zu failed)\n", s->runs, s->failed);
    if (isnan(s->repair_fraction))
        printf("repair vs replace: %zu repair, %zu replace, %zu without advice\n", s->repair,
               s->replace, s->none);
    else
        printf("repair vs replace: %zu repair, %zu replace (%.0f %% repaired), %zu without "
               "advice\n",
               s->repair, s->replace, 100 * s->repair_fraction, s->none);
    printf("average missing volume: %.1f mm³ per run\n", s->avg_missing_volume_mm3);
    if (s->pass + s->machine + s->rework)
        printf("inspected: %zu pass, %zu machine, %zu rework (latest inspection of each run)\n",
               s->pass, s->machine, s->rework);
    if (s->part_count) {
        printf("\nper part:\n");
        static const char *const headers[] = {"part",    "runs",   "avg missing mm³",
                                              "most frequent damage", "sections", "repair",
                                              "replace"};
        static const bool right[] = {false, true, true, false, true, true, true};
        cli_table t;
        cli_table_init(&t, 7, headers, right);
        for (size_t i = 0; i < s->part_count; i++) {
            const sr_history_part *p = &s->parts[i];
            cli_table_cell(&t, "%s", p->part_number);
            cli_table_cell(&t, "%zu", p->runs);
            cli_table_cell(&t, "%.1f", p->avg_missing_volume_mm3);
            if (p->top_class[0])
                cli_table_cell(&t, "%s (%zu)", p->top_class, p->top_class_sections);
            else
                cli_table_cell(&t, "-");
            cli_table_cell(&t, "%zu", p->sections);
            cli_table_cell(&t, "%zu", p->repair);
            cli_table_cell(&t, "%zu", p->replace);
        }
        bool ok = cli_table_print(&t, stdout, 2);
        cli_table_release(&t);
        if (!ok)
            return false;
    }
    if (s->month_count) {
        printf("\nruns per month:\n");
        for (size_t i = 0; i < s->month_count; i++)
            printf("  %s  %zu\n", s->months[i].month, s->months[i].runs);
    }
    return true;
}

int cmd_history(const cli_ctx *ctx, int argc, char **argv)
{
    const char *part = NULL, *instance = NULL, *material = NULL, *since = NULL, *until = NULL,
               *verdict = NULL;
    bool json = false, csv = false, summary = false;
    const cli_opt opts[] = {{"--part", &part, NULL},         {"--instance", &instance, NULL},
                            {"--material", &material, NULL}, {"--since", &since, NULL},
                            {"--until", &until, NULL},       {"--verdict", &verdict, NULL},
                            {"--summary", NULL, &summary},   {"--json", NULL, &json},
                            {"--csv", NULL, &csv},           {NULL, NULL, NULL}};
    const cli_spec spec = {"history", usage_history, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, NULL, NULL, &rc))
        return rc;
    if (json && csv)
        return cli_usage_error("history takes --json or --csv, not both");
    sr_history_filter filter = {0};
    filter.part = part;
    filter.material = material;
    filter.since = since;
    filter.until = until;
    filter.verdict = verdict;
    if (instance && !cli_parse_id("--instance", instance, &filter.instance_id))
        return CLI_USAGE;
    if (part && !*part)
        return cli_usage_error("bad --part '': expected a part number or id");
    if (material && !*material)
        return cli_usage_error("bad --material '': expected a material name");
    if (since && !cli_date_valid(since))
        return cli_usage_error("bad --since '%s': expected a date YYYY-MM-DD", since);
    if (until && !cli_date_valid(until))
        return cli_usage_error("bad --until '%s': expected a date YYYY-MM-DD", until);
    if (verdict && sr_inspect_verdict_parse(verdict) < 0)
        return cli_usage_error("bad --verdict '%s': expected pass, machine or rework", verdict);
    if (since && until && strcmp(since, until) > 0)
        return cli_usage_error("bad dates: --since %s is after --until %s", since, until);

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    /* the filter is checked first, so nothing is printed before an error */
    sr_history_summary sum;
    memset(&sum, 0, sizeof sum);
    sr_status st = sr_catalog_history_check(cat, &filter, &err);
    if (st == SR_OK && (json || summary))
        st = sr_catalog_history_summary(cat, &filter, &sum, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    rc = CLI_OK;
    if (summary && !json) {
        sr_catalog_close(cat);
        if (csv)
            summary_csv(&sum);
        else if (!summary_table(&sum))
            rc = CLI_FAIL;
        sr_history_summary_release(&sum);
        return rc;
    }

    rows_ctx c;
    memset(&c, 0, sizeof c);
    c.kind = json ? OUT_JSON : csv ? OUT_CSV : OUT_TABLE;
    static const char *const headers[] = {"run",      "date",     "part",     "serial",
                                          "material", "symmetry", "status",   "sections",
                                          "missing mm³", "damage", "advice", "outcome"};
    static const bool right[] = {true,  false, false, false, false, false,
                                 false, true,  true,  false, false, false};
    cli_table_init(&c.t, 12, headers, right);
    json_out jo;
    if (json) {
        json_init(&jo, stdout);
        c.j = &jo;
        json_object_begin(&jo);
        json_key(&jo, "runs");
        json_array_begin(&jo);
    } else if (csv) {
        fputs("run_id,date,started_at,instance_id,part,serial,material,symmetry,method,"
              "status,sections,missing_volume_mm3,damage_classes,advice,outcome\r\n",
              stdout);
    }
    st = sr_catalog_history(cat, &filter, row_out, &c, &err);
    sr_catalog_close(cat);
    if (st != SR_OK) {
        if (json)
            json_discard(&jo);
        cli_table_release(&c.t);
        sr_history_summary_release(&sum);
        return cli_fail(st, &err);
    }
    if (json) {
        json_array_end(&jo);
        json_key(&jo, "summary");
        summary_json(&jo, &sum);
        json_object_end(&jo);
        rc = json_finish(&jo);
    } else if (c.kind == OUT_TABLE) {
        if (c.count == 0)
            printf("no runs\n");
        else if (!cli_table_print(&c.t, stdout, 0))
            rc = CLI_FAIL;
    }
    cli_table_release(&c.t);
    sr_history_summary_release(&sum);
    return rc;
}
