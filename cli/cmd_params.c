/*
 * cmd_params.c: `symrec params list|show|set`: named parameter sets for
 * reconstruction (layers, sectors, the paper's thresholds, the smallest section
 * reported). `set` changes only the fields given: an existing set keeps the others, a
 * new one starts from "default". The catalogue range-checks the result.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "cli.h"
#include "json_out.h"

static const char usage_params[] =
    "usage: symrec [--db FILE] params list [--json]\n"
    "       symrec [--db FILE] params show NAME [--json]\n"
    "       symrec [--db FILE] params set NAME [--layers N] [--sectors N]\n"
    "                              [--gamma G] [--gamma-axis G] [--gamma-plane G]\n"
    "                              [--delta-d D]\n"
    "                              [--min-depth MM] [--min-volume MM3] [--notes T]\n"
    "\n"
    "  list    every parameter set\n"
    "  show    one set\n"
    "  set     create or change a set\n";

static const char usage_list[] =
    "usage: symrec [--db FILE] params list [--json]\n"
    "\n"
    "Lists the named parameter sets (\"default\" is always there).\n"
    "\n"
    "  --json   one JSON array of parameter set objects\n";

static const char usage_show[] =
    "usage: symrec [--db FILE] params show NAME [--json]\n"
    "\n"
    "Shows one parameter set.\n"
    "\n"
    "  --json   one JSON object\n";

static const char usage_set[] =
    "usage: symrec [--db FILE] params set NAME [--layers N] [--sectors N]\n"
    "                              [--gamma G] [--gamma-axis G] [--gamma-plane G]\n"
    "                              [--delta-d D]\n"
    "                              [--min-depth MM] [--min-volume MM3] [--notes T]\n"
    "\n"
    "Creates parameter set NAME (starting from \"default\") or changes the fields given.\n"
    "\n"
    "  --layers N        number of layers the part is sliced into, 1..100000\n"
    "  --sectors N       polar sectors per layer, 3..100000\n"
    "  --gamma-axis G    axial damage threshold (Alg. 4), 0 < G <= 1\n"
    "  --gamma-plane G   planar damage threshold (Alg. 5), 0 < G <= 1\n"
    "  --gamma G         both thresholds at once, as 'reconstruct --gamma' sets them\n"
    "  --delta-d D       alignment symmetry threshold (Alg. 3), 0 < D <= 1\n"
    "  --min-depth MM    smallest depth reported as a missing section, mm\n"
    "  --min-volume MM3  smallest volume reported as a missing section, mm³\n"
    "  --notes T         free text\n";

static void print_params_text(const sr_params *p)
{
    printf("parameter set %s\n", cli_tx(p->name));
    printf("  layers:        %d\n", p->layers);
    printf("  sectors:       %d\n", p->sectors);
    printf("  gamma_axis:    %g\n", p->gamma_axis);
    printf("  gamma_plane:   %g\n", p->gamma_plane);
    printf("  delta_d:       %g\n", p->delta_d);
    printf("  min depth:     %g mm\n", p->min_depth_mm);
    printf("  min volume:    %g mm³\n", p->min_volume_mm3);
    if (p->notes[0])
        cli_print_field(stdout, "  notes:         ", p->notes);
}

typedef struct params_vec {
    sr_params *v;
    size_t count, cap;
    bool nomem;
} params_vec;

static int add_params(const sr_params *p, void *user)
{
    params_vec *pv = user;
    sr_params *v = sr_grow(pv->v, pv->count, &pv->cap, sizeof *v);
    if (!v) {
        pv->nomem = true;
        return 1;
    }
    pv->v = v;
    pv->v[pv->count++] = *p;
    return 0;
}

static int print_list(const params_vec *pv, bool json);

static int params_list(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"params list", usage_list, opts, 0, 0, NULL};
    int rc;
    if (!cli_parse(&spec, argc, argv, NULL, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    params_vec pv = {NULL, 0, 0, false};
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_catalog_params_list(cat, add_params, &pv, &err);
    sr_catalog_close(cat);
    if (st == SR_OK && pv.nomem)
        st = sr_err_set(&err, SR_E_NOMEM, "out of memory listing parameter sets");
    rc = st == SR_OK ? print_list(&pv, json) : cli_fail(st, &err);
    free(pv.v);
    return rc;
}

static int print_list(const params_vec *pv, bool json)
{
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_array_begin(&j);
        for (size_t i = 0; i < pv->count; i++)
            json_params(&j, &pv->v[i]);
        json_array_end(&j);
        return json_finish(&j);
    }
    static const char *const headers[] = {"name", "layers", "sectors", "gamma_axis",
                                          "gamma_plane", "delta_d", "min depth mm",
                                          "min volume mm³", "notes"};
    static const bool right[] = {false, true, true, true, true, true, true, true, false};
    cli_table t;
    cli_table_init(&t, 9, headers, right);
    for (size_t i = 0; i < pv->count; i++) {
        const sr_params *p = &pv->v[i];
        cli_table_cell(&t, "%s", p->name);
        cli_table_cell(&t, "%d", p->layers);
        cli_table_cell(&t, "%d", p->sectors);
        cli_table_cell(&t, "%g", p->gamma_axis);
        cli_table_cell(&t, "%g", p->gamma_plane);
        cli_table_cell(&t, "%g", p->delta_d);
        cli_table_cell(&t, "%g", p->min_depth_mm);
        cli_table_cell(&t, "%g", p->min_volume_mm3);
        cli_table_cell(&t, "%s", p->notes);
    }
    bool ok = cli_table_print(&t, stdout, 0);
    cli_table_release(&t);
    return ok ? CLI_OK : CLI_FAIL;
}

static int params_show(const cli_ctx *ctx, int argc, char **argv)
{
    bool json = false;
    const cli_opt opts[] = {{"--json", NULL, &json}, {NULL, NULL, NULL}};
    const cli_spec spec = {"params show", usage_show, opts, 1, 1, "a parameter set name"};
    const char *name;
    int rc;
    if (!cli_parse(&spec, argc, argv, &name, NULL, &rc))
        return rc;
    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_params p;
    sr_status st = sr_catalog_params_get(cat, name, &p, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_params(&j, &p);
        return json_finish(&j);
    }
    print_params_text(&p);
    return CLI_OK;
}

static int params_set(const cli_ctx *ctx, int argc, char **argv)
{
    const char *layers = NULL, *sectors = NULL, *gamma_axis = NULL, *gamma_plane = NULL;
    const char *gamma = NULL, *delta_d = NULL, *min_depth = NULL, *min_volume = NULL, *notes = NULL;
    bool json = false;
    const cli_opt opts[] = {
        {"--layers", &layers, NULL},
        {"--sectors", &sectors, NULL},
        {"--gamma", &gamma, NULL},
        {"--gamma-axis", &gamma_axis, NULL},
        {"--gamma-plane", &gamma_plane, NULL},
        {"--delta-d", &delta_d, NULL},
        {"--min-depth", &min_depth, NULL},
        {"--min-volume", &min_volume, NULL},
        {"--notes", &notes, NULL},
        {"--json", NULL, &json},
        {NULL, NULL, NULL},
    };
    const cli_spec spec = {"params set", usage_set, opts, 1, 1, "a parameter set name"};
    const char *name;
    int rc;
    if (!cli_parse(&spec, argc, argv, &name, NULL, &rc))
        return rc;
    sr_params p;
    if (strlen(name) == 0 || strlen(name) >= sizeof p.name)
        return cli_usage_error("bad NAME '%s': expected 1..%zu characters", name,
                               sizeof p.name - 1);
    if (notes && strlen(notes) >= sizeof p.notes)
        return cli_usage_error("bad --notes: longer than %zu characters", sizeof p.notes - 1);
    /* Parse everything before touching the catalogue. */
    int n_layers = 0, n_sectors = 0;
    double g_both = 0, g_axis = 0, g_plane = 0, d_d = 0, m_depth = 0, m_volume = 0;
    const char *unit = "a number 0 < x <= 1";
    if ((layers && !cli_parse_int("--layers", layers, 1, 100000, NULL, &n_layers)) ||
        (sectors && !cli_parse_int("--sectors", sectors, 3, 100000, NULL, &n_sectors)) ||
        (gamma && !cli_parse_double("--gamma", gamma, 1e-300, 1, unit, &g_both)) ||
        (gamma_axis && !cli_parse_double("--gamma-axis", gamma_axis, 1e-300, 1, unit, &g_axis)) ||
        (gamma_plane &&
         !cli_parse_double("--gamma-plane", gamma_plane, 1e-300, 1, unit, &g_plane)) ||
        (delta_d && !cli_parse_double("--delta-d", delta_d, 1e-300, 1, unit, &d_d)) ||
        (min_depth && !cli_parse_double("--min-depth", min_depth, 0, 1e6,
                                        "a depth in mm, 0..1000000", &m_depth)) ||
        (min_volume && !cli_parse_double("--min-volume", min_volume, 0, 1e12,
                                         "a volume in mm³, 0..1e12", &m_volume)))
        return CLI_USAGE;

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_WRITE, "set the parameter set", &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    bool existed = true;
    sr_status st = sr_catalog_params_get(cat, name, &p, &err);
    if (st == SR_E_NOTFOUND) {
        existed = false;
        sr_err_clear(&err);
        st = sr_catalog_params_get(cat, "default", &p, &err);
        if (st == SR_OK) {
            snprintf(p.name, sizeof p.name, "%s", name);
            p.notes[0] = '\0';
        }
    }
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    if (layers)
        p.layers = n_layers;
    if (sectors)
        p.sectors = n_sectors;
    if (gamma)
        p.gamma_axis = p.gamma_plane = g_both;
    if (gamma_axis)
        p.gamma_axis = g_axis;
    if (gamma_plane)
        p.gamma_plane = g_plane;
    if (delta_d)
        p.delta_d = d_d;
    if (min_depth)
        p.min_depth_mm = m_depth;
    if (min_volume)
        p.min_volume_mm3 = m_volume;
    if (notes)
        snprintf(p.notes, sizeof p.notes, "%s", notes);
    st = sr_catalog_params_put(cat, &p, &err);
    sr_catalog_close(cat);
    if (st != SR_OK)
        return cli_fail(st, &err);
    cli_note("%s parameter set '%s'", existed ? "updated" : "created", cli_tx(p.name));
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_params(&j, &p);
        return json_finish(&j);
    }
    print_params_text(&p);
    return CLI_OK;
}

int cmd_params(const cli_ctx *ctx, int argc, char **argv)
{
    static const cli_subcommand subs[] = {{"list", params_list}, {"show", params_show}, {"set", params_set}, {NULL, NULL}};
    return cli_run_subcommand(ctx, "params", usage_params, subs, argc, argv);
}
