/*
 * plan_advice.c: a build plan's process settings taken from the advice the repair rules
 * gave its section (plan.h's sr_plan_follow_advice). The advice row keeps the rule's
 * parameters_json as details_json.parameters (src/advice/rules.c), so a plan follows the
 * rule that fired even after the rule is edited: layer height, step-over, machining
 * allowance and the deposition rate (fed mass per minute times the share that stays,
 * over the material's density), and the preheat of the process on the material.
 */
#include "plan/plan.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/json_scan.h"

int sr_plan_process_builds(const char *process)
{
    static const char *const builds[] = {"spray_forming", "ded", "weld_buildup"};
    for (size_t i = 0; process && i < sizeof builds / sizeof builds[0]; i++)
        if (strcasecmp(process, builds[i]) == 0)
            return 1;
    return 0;
}

/* The figures an advice's details hold for the plan; NaN = not given, bad = text that
 * is not a number (its key kept for the message). */
typedef struct advice_figures {
    double layer_mm, step_over_mm, allowance_mm, rate_g_min, efficiency, preheat_c;
    char bad[32];
} advice_figures;

static double *figure_slot(advice_figures *f, const char *key, size_t len)
{
    const struct {
        const char *key;
        double *slot;
    } keys[] = {
        {"layer_mm", &f->layer_mm},
        {"step_over_mm", &f->step_over_mm},
        {"allowance_mm", &f->allowance_mm},
        {"deposition_rate_g_min", &f->rate_g_min},
        {"efficiency", &f->efficiency},
    };
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strlen(keys[i].key) == len && memcmp(keys[i].key, key, len) == 0)
            return keys[i].slot;
    return NULL;
}

/* A number member [val, end) into *slot; its key into f->bad when it is not one. */
static void take_number(advice_figures *f, double *slot, const char *key, size_t len,
                        const char *val, const char *end)
{
    char *stop = NULL;
    double v = strtod(val, &stop);
    if (stop == end && isfinite(v)) {
        *slot = v;
    } else if (!f->bad[0]) {
        snprintf(f->bad, sizeof f->bad, "%.*s", (int)(len < 31 ? len : 31), key);
    }
}

static void parameter_member(const char *key, size_t len, const char *val, const char *end,
                             void *user)
{
    advice_figures *f = user;
    double *slot = figure_slot(f, key, len);
    if (slot)
        take_number(f, slot, key, len, val, end);
}

static void details_member(const char *key, size_t len, const char *val, const char *end,
                           void *user)
{
    advice_figures *f = user;
    if (len == 10 && memcmp(key, "parameters", 10) == 0) {
        sr_json_for_members(val, parameter_member, f);
    } else if (len == 9 && memcmp(key, "preheat_c", 9) == 0 && *val != 'n') {
        take_number(f, &f->preheat_c, key, len, val, end);
    }
}

/* The advice for section `index`, else the whole part's; NULL when there is none. */
static const sr_run_advice *advice_for(const sr_run *run, size_t index)
{
    const sr_run_advice *part = NULL;
    for (size_t i = 0; i < run->advice_count; i++) {
        const sr_run_advice *a = &run->advice[i];
        if (a->section_index >= 0 && (size_t)a->section_index == index)
            return a;
        if (a->section_index < 0 && !part)
            part = a;
    }
    return part;
}

/* v into *dst when it is a number in (lo, hi] (lo itself allowed when closed); else the
 * message naming the rule and key. */
static sr_status take(double v, double lo, int closed, double hi, const char *key,
                      const sr_plan_advice *a, double *dst, unsigned bit, unsigned *taken,
                      sr_err *err)
{
    if (isnan(v))
        return SR_OK;
    if (!(closed ? v >= lo : v > lo) || !(v <= hi))
        return sr_err_set(err, SR_E_RANGE,
                          "the advice of rule '%s' gives %s %g: expected %s %g and at most %g",
                          a->rule[0] ? a->rule : "?", key, v, closed ? ">=" : ">", lo, hi);
    *dst = v;
    *taken |= bit;
    return SR_OK;
}

sr_status sr_plan_follow_advice(const sr_run *run, size_t section_index, sr_plan_opts *opts,
                                sr_plan_advice *out, sr_err *err)
{
    sr_plan_advice a;
    memset(&a, 0, sizeof a);
    a.preheat_c = NAN;
    const sr_run_advice *adv = advice_for(run, section_index);
    if (!adv) {
        *out = a;
        return SR_OK;
    }
    a.found = 1;
    snprintf(a.process, sizeof a.process, "%s", adv->process);
    snprintf(a.rule, sizeof a.rule, "%s", adv->rule_name);
    a.builds = sr_plan_process_builds(adv->process);
    advice_figures f = {NAN, NAN, NAN, NAN, NAN, NAN, ""};
    if (adv->details_json)
        sr_json_for_members(adv->details_json, details_member, &f);
    if (f.bad[0])
        return sr_err_set(err, SR_E_RANGE, "the advice of rule '%s' gives %s that is not a number",
                          a.rule[0] ? a.rule : "?", f.bad);
    a.preheat_c = f.preheat_c;
    if (!a.builds) {
        *out = a;
        return SR_OK;
    }
    sr_plan_opts o = *opts;
    double density = o.density_g_cm3 > 0 ? o.density_g_cm3 : 7.85;
    double efficiency = isnan(f.efficiency) ? 1.0 : f.efficiency;
    if (!(efficiency > 0 && efficiency <= 1))
        return sr_err_set(err, SR_E_RANGE,
                          "the advice of rule '%s' gives efficiency %g: expected > 0 and at "
                          "most 1",
                          a.rule[0] ? a.rule : "?", efficiency);
    double rate = isnan(f.rate_g_min) ? NAN : f.rate_g_min * efficiency / density;
    sr_status st =
        take(f.layer_mm, 0, 0, 1e4, "layer_mm", &a, &o.layer_mm, SR_PLAN_FROM_LAYER, &a.taken, err);
    if (st == SR_OK)
        st = take(f.step_over_mm, 0, 0, 1e4, "step_over_mm", &a, &o.step_over_mm,
                  SR_PLAN_FROM_STEP_OVER, &a.taken, err);
    if (st == SR_OK)
        st = take(f.allowance_mm, 0, 1, 1e4, "allowance_mm", &a, &o.allowance_mm,
                  SR_PLAN_FROM_ALLOWANCE, &a.taken, err);
    if (st == SR_OK)
        st = take(rate, 0, 0, 1e6, "a deposition rate (cm3/min)", &a, &o.rate_cm3_min,
                  SR_PLAN_FROM_RATE, &a.taken, err);
    if (st != SR_OK)
        return st;
    *opts = o;
    *out = a;
    return SR_OK;
}
