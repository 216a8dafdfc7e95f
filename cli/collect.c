/*
 * collect.c: gathers the catalogue's parts and instances into growable arrays, so
 * that commands can size table columns and look related records up per row without
 * calling the catalogue from inside its own listing callback.
 */
#include <stdlib.h>
#include <string.h>

#include "base/grow.h"
#include "cli.h"

typedef struct gather_parts {
    cli_parts *parts;
    bool nomem;
} gather_parts;

static int add_part(const sr_part_info *p, void *user)
{
    gather_parts *g = user;
    sr_part_info *v = sr_grow(g->parts->v, g->parts->count, &g->parts->cap, sizeof *v);
    if (!v) {
        g->nomem = true;
        return 1;
    }
    g->parts->v = v;
    g->parts->v[g->parts->count++] = *p;
    return 0;
}

sr_status cli_parts_load(sr_catalog *cat, const sr_part_filter *filter, cli_parts *out,
                         sr_err *err)
{
    memset(out, 0, sizeof *out);
    gather_parts g = {out, false};
    sr_status st = sr_catalog_part_list(cat, filter, add_part, &g, err);
    if (st == SR_OK && g.nomem)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory listing parts");
    if (st != SR_OK)
        cli_parts_release(out);
    return st;
}

void cli_parts_release(cli_parts *parts)
{
    free(parts->v);
    memset(parts, 0, sizeof *parts);
}

typedef struct gather_instances {
    cli_instances *list;
    bool nomem;
} gather_instances;

static int add_instance(const sr_instance_info *in, void *user)
{
    gather_instances *g = user;
    sr_instance_info *v = sr_grow(g->list->v, g->list->count, &g->list->cap, sizeof *v);
    if (!v) {
        g->nomem = true;
        return 1;
    }
    g->list->v = v;
    g->list->v[g->list->count++] = *in;
    return 0;
}

sr_status cli_instances_load(sr_catalog *cat, const char *part, cli_instances *out,
                             sr_err *err)
{
    memset(out, 0, sizeof *out);
    gather_instances g = {out, false};
    sr_status st = sr_catalog_instance_list(cat, part, add_instance, &g, err);
    if (st == SR_OK && g.nomem)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory listing instances");
    if (st != SR_OK)
        cli_instances_release(out);
    return st;
}

void cli_instances_release(cli_instances *instances)
{
    free(instances->v);
    memset(instances, 0, sizeof *instances);
}
