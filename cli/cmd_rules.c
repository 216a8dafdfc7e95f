/*
 * cmd_rules.c: `symrec rules list|show|set|add|enable|disable`: the repair rules of
 * the catalogue (src/catalog/catalog_rules.h), the rows the advice of every run is drawn from
 * (src/advice/rules.h). `set` changes one field of one rule in one transaction; the library
 * checks the value and the whole rule, so a refused change leaves the rule as it was.
 * The same rows may be edited with plain SQL (table repair_rules).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "catalog/catalog_rules.h"
#include "cli.h"
#include "json_out.h"

static const char usage_rules[] =
    "usage: symrec [--db FILE] rules list [--enabled] [--json]\n"
    "       symrec [--db FILE] rules show NAME|ID [--json]\n"
    "       symrec [--db FILE] rules set NAME|ID FIELD VALUE [--json]\n"
    "       symrec [--db FILE] rules add NAME --process P --reason TEXT --source TEXT\n"
    "                              [--priority N] [--scope section|part] [--disabled]\n"
    "                              [--json]\n"
    "       symrec [--db FILE] rules enable|disable NAME|ID\n"
    "\n"
    "  list     every rule, in the order they are tried (priority, then id)\n"
    "  show     one rule with all its fields\n"
    "  set      change one field of a rule (null clears a condition)\n"
    "  add      add a rule (give its conditions with `rules set`)\n"
    "  enable   apply a rule again\n"
    "  disable  keep a rule but stop applying it\n";

static const char usage_list[] =
    "usage: symrec [--db FILE] rules list [--enabled] [--json]\n"
    "\n"
    "Lists the repair rules in the order the advice tries them: priority (lower first),\n"
    "then id. Conditions are shown as a summary; see `rules show` for every field.\n"
    "\n"
    "  --enabled  only the rules that are applied\n"
    "  --json     one JSON array of rule objects (every field; null = any)\n";

static const char usage_show[] =
    "usage: symrec [--db FILE] rules show NAME|ID [--json]\n"
    "\n"
    "Shows one rule (by name, ignoring case, or by id) with every field.\n"
    "\n"
    "  --json   one JSON object\n";

static const char usage_set[] =
    "usage: symrec [--db FILE] rules set NAME|ID FIELD VALUE [--json]\n"
    "\n"
    "Changes one field of a rule in one transaction; the next advice uses it.\n"
    "VALUE `null` clears a condition (any value then matches). Fields:\n"
    "  name, priority (lower first), enabled (0/1), scope (section|part), process,\n"
    "  parameters_json (a JSON object), reason ({figure} is filled in), source;\n"
    "  conditions: symmetry_kind, class, material, material_family, location,\n"
    "  min/max_volume_mm3 (mm³), min/max_depth_mm (mm), min/max_lost_fraction,\n"
    "  min/max_depth_fraction, min/max_section_fraction (0..1), feature (a figure\n"
    "  of the section, e.g. arc_deg), feature_min, feature_max.\n"
    "An unknown field is a usage error (exit 2); a value the rule refuses is an\n"
    "error (exit 1) and changes nothing.\n"
    "\n"
    "  --json   print the rule as stored, as one JSON object\n";

static const char usage_add[] =
    "usage: symrec [--db FILE] rules add NAME --process P --reason TEXT --source TEXT\n"
    "                              [--priority N] [--scope section|part] [--disabled]\n"
    "                              [--json]\n"
    "\n"
    "Adds a rule with no conditions (it applies to every section, or with --scope part\n"
    "to every part); narrow it with `symrec rules set NAME FIELD VALUE`.\n"
    "\n"
    "  --process P     spray_forming, ded, weld_buildup, machining, inspect, replace,\n"
    "                  manual_review\n"
    "  --reason TEXT   shown with the advice\n"
    "  --source TEXT   where the rule's thresholds come from\n"
    "  --priority N    lower is tried first (default 100)\n"
    "  --scope S       section (default) or part\n"
    "  --disabled      add it switched off\n"
    "  --json          print the rule as stored, as one JSON object\n";

static const char usage_enable[] = "usage: symrec [--db FILE] rules enable NAME|ID [--json]\n"
                                   "\n"
                                   "Applies the rule again.\n"
                                   "\n"
                                   "  --json   print the rule as stored, as one JSON object\n";

static const char usage_disable[] = "usage: symrec [--db FILE] rules disable NAME|ID [--json]\n"
                                    "\n"
                                    "Keeps the rule but stops applying it.\n"
                                    "\n"
                                    "  --json   print the rule as stored, as one JSON object\n";

static void json_rule(json_out *j, const sr_rule *r)
{
    json_object_begin(j);
    json_key(j, "id");
    json_int(j, r->id);
    for (size_t i = 0; sr_rule_field_name(i); i++) {
        const char *name = sr_rule_field_name(i);
        char buf[1100];
        sr_rule_get_field(r, name, buf, sizeof buf, NULL);
        json_key(j, name);
        sr_rule_field_kind kind = sr_rule_field_kind_of(name);
        bool unset = strcmp(buf, "null") == 0 &&
                     (kind == SR_RULE_FIELD_NUMBER || kind == SR_RULE_FIELD_TEXT);
        if (unset)
            json_null(j);
        else if (kind == SR_RULE_FIELD_NUMBER || kind == SR_RULE_FIELD_INT)
            json_number(j, strtod(buf, NULL));
        else
            json_string(j, buf);
    }
    /* the parameters as the object they are (parameters_json keeps the text) */
    json_key(j, "parameters");
    json_raw(j, r->parameters_json[0] ? r->parameters_json : "{}");
    json_key(j, "created_at");
    json_string(j, r->created_at);
    json_key(j, "updated_at");
    json_string(j, r->updated_at[0] ? r->updated_at : NULL);
    json_object_end(j);
}

/* "class=chip max_depth_mm=3" */
static void conditions_str(const sr_rule *r, char *out, size_t size)
{
    size_t o = 0;
    out[0] = '\0';
    for (size_t i = 0; sr_rule_field_name(i); i++) {
        const char *name = sr_rule_field_name(i);
        static const char *const not_conditions[] = {"name", "priority", "enabled", "scope",
                                                     "process", "parameters_json", "reason",
                                                     "source", NULL};
        bool skip = false;
        for (size_t k = 0; not_conditions[k]; k++)
            skip |= strcmp(name, not_conditions[k]) == 0;
        char buf[1100];
        sr_rule_get_field(r, name, buf, sizeof buf, NULL);
        if (skip || strcmp(buf, "null") == 0 || o + 1 >= size)
            continue;
        int n = snprintf(out + o, size - o, "%s%s=%s", o ? " " : "", name, buf);
        o = n < 0 ? o : (size_t)n + o >= size ? size - 1 : o + (size_t)n;
    }
    if (!out[0])
        snprintf(out, size, "(any)");
}

static void print_rule_text(const sr_rule *r)
{
    printf("rule %s (id %lld)\n", cli_tx(r->name), (long long)r->id);
    for (size_t i = 1; sr_rule_field_name(i); i++) {
        const char *name = sr_rule_field_name(i);
        char buf[1100], label[32];
        sr_rule_get_field(r, name, buf, sizeof buf, NULL);
        snprintf(label, sizeof label, "  %s:", name);
        printf("%-24s%s\n", label, strcmp(buf, "null") == 0 ? "-" : cli_tx(buf));
    }
    printf("%-24s%s\n", "  created:", r->created_at);
    printf("%-24s%s\n", "  updated:", r->updated_at[0] ? r->updated_at : "-");
}

typedef struct rule_list {
    sr_rule *v;
    size_t count;
} rule_list;

static int rules_list(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false, enabled = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {"--enabled", NULL, &enabled},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"rules list", usage_list, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    rule_list rl = {NULL, 0};
    sr_status st = sr_catalog_rule_load(cat, enabled, &rl.v, &rl.count, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_array_begin(&j);
        for (size_t i = 0; i < rl.count; i++)
            json_rule(&j, &rl.v[i]);
        json_array_end(&j);
        free(rl.v);
        return json_finish(&j);
    }
    static const char *const headers[] = {"id", "name", "priority", "on", "scope",
                                          "conditions", "process"};
    static const bool right[] = {true, false, true, false, false, false, false};
    cli_table t;
    cli_table_init(&t, 7, headers, right);
    for (size_t i = 0; i < rl.count; i++) {
        const sr_rule *r = &rl.v[i];
        char cond[400];
        conditions_str(r, cond, sizeof cond);
        cli_table_cell(&t, "%lld", (long long)r->id);
        cli_table_cell(&t, "%s", r->name);
        cli_table_cell(&t, "%d", r->priority);
        cli_table_cell(&t, "%s", r->enabled ? "yes" : "no");
        cli_table_cell(&t, "%s", r->scope);
        cli_table_cell(&t, "%s", cond);
        cli_table_cell(&t, "%s", r->process);
    }
    bool ok = cli_table_print(&t, stdout, 0);
    cli_table_release(&t);
    free(rl.v);
    return ok ? CLI_OK : CLI_FAIL;
}

static int print_rule(const sr_rule *r, bool json)
{
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_rule(&j, r);
        return json_finish(&j);
    }
    print_rule_text(r);
    return CLI_OK;
}

static int rules_show(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"rules show", usage_show, opts, 1, 1, "a rule name or id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_rule r;
    sr_status st = sr_catalog_rule_get(cat, key, &r, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    return print_rule(&r, json);
}

static int rules_set(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"rules set", usage_set, opts, 3, 3,
                           "NAME|ID FIELD VALUE"};
    const char *pos[3];
    int n, rc;
    if (!cli_parse(&spec, argc, argv, pos, &n, &rc))
        return rc;
    if (sr_rule_field_kind_of(pos[1]) == SR_RULE_FIELD_UNKNOWN)
        return cli_usage_error("unknown rule field '%s' (see 'symrec rules set --help')",
                               pos[1]);
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "change the rule", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_rule r;
    sr_status st = sr_catalog_rule_set(cat, pos[0], pos[1], pos[2], &r, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    char buf[1100];
    sr_rule_get_field(&r, pos[1], buf, sizeof buf, NULL);
    cli_note("updated rule '%s': %s = %s", cli_tx(r.name), pos[1], cli_tx(buf));
    return print_rule(&r, json);
}

static int rules_add(const cli_ctx *ctx, int argc, char **argv)
{
    const char *process = NULL, *reason = NULL, *source = NULL, *priority = NULL;
    const char *scope = NULL;
    bool disabled = false, json = false;
    const cli_opt opts[] = {
        {"--process", &process, NULL}, {"--reason", &reason, NULL},
        {"--source", &source, NULL},   {"--priority", &priority, NULL},
        {"--scope", &scope, NULL},     {"--disabled", NULL, &disabled},
        {"--json", NULL, &json},       {NULL, NULL, NULL},
    };
    const cli_spec spec = {"rules add", usage_add, opts, 1, 1, "a rule name"};
    const char *name;
    int rc;
    if (!cli_parse(&spec, argc, argv, &name, NULL, &rc))
        return rc;
    if (!process || !reason || !source)
        return cli_usage_error("'rules add' needs --process, --reason and --source");
    int prio = 100;
    if (priority && !cli_parse_int("--priority", priority, -1000000, 1000000, NULL, &prio))
        return CLI_USAGE;
    sr_rule r;
    sr_rule_init(&r);
    r.priority = prio;
    r.enabled = disabled ? 0 : 1;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = SR_OK;
    const char *const fields[][2] = {{"name", name}, {"process", process}, {"reason", reason},
                                     {"source", source}, {"scope", scope ? scope : "section"}};
    for (size_t i = 0; st == SR_OK && i < sizeof fields / sizeof fields[0]; i++)
        st = sr_rule_set_field(&r, fields[i][0], fields[i][1], &err);
    if (st != SR_OK)
        return cli_fail(st, &err);
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "add the rule", &cat))
        return CLI_FAIL;
    int64_t id;
    st = sr_catalog_rule_add(cat, &r, &id, &err);
    if (st == SR_OK)
        st = sr_catalog_rule_get(cat, name, &r, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    cli_note("added rule '%s' (id %lld)", cli_tx(r.name), (long long)id);
    return print_rule(&r, json);
}

static int rules_enable(const cli_ctx *ctx, int argc, char **argv, int on)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {on ? "rules enable" : "rules disable",
                           on ? usage_enable : usage_disable, opts, 1, 1, "a rule name or id"};
    const char *key;
    int rc;
    if (!cli_parse(&spec, argc, argv, &key, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "change the rule", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_rule_enable(cat, key, on, &err);
    sr_rule r;
    if (st == SR_OK && json)
        st = sr_catalog_rule_get(cat, key, &r, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    cli_note("%s rule '%s'", on ? "enabled" : "disabled", cli_tx(key));
    return json ? print_rule(&r, true) : CLI_OK;
}

static int rules_enable_on(const cli_ctx *ctx, int argc, char **argv)
{
    return rules_enable(ctx, argc, argv, 1);
}

static int rules_disable(const cli_ctx *ctx, int argc, char **argv)
{
    return rules_enable(ctx, argc, argv, 0);
}

int cmd_rules(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {
        {"list", rules_list},       {"show", rules_show},
        {"set", rules_set},         {"add", rules_add},
        {"enable", rules_enable_on}, {"disable", rules_disable},
        {NULL, NULL},
    };
    return cli_run_subcommand(ctx, "rules", usage_rules, subs, argc, argv);
}
