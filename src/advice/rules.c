/*
 * rules.c: the repair-rule engine of rules.h: three-valued evaluation of a rule's
 * conditions on a section (or on the whole part), the choice of advice in priority
 * order with the material's process limits, the advice's details_json (rules fired,
 * blocked, unevaluated), reason texts with figures filled in, and sr_advise_run, which
 * describes and advises a run in place before it is stored or printed.
 */
#include "advice/rules.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/jsonbuf.h"

/* ---- conditions ---- */

typedef struct verdict_acc {
    bool no, unknown;
    char *why;
    size_t size;
} verdict_acc;

static void acc_bool(verdict_acc *a, bool holds)
{
    if (!holds)
        a->no = true;
}

static void acc_unknown(verdict_acc *a, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void acc_unknown(verdict_acc *a, const char *fmt, ...)
{
    if (!a->unknown && a->why && a->size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(a->why, a->size, fmt, ap);
        va_end(ap);
    }
    a->unknown = true;
}

/* min <= v <= max for the bounds that are set; v NaN = unknown (why). */
static void acc_range(verdict_acc *a, double lo, double hi, double v, const char *what)
{
    if (isnan(lo) && isnan(hi))
        return;
    if (isnan(v)) {
        acc_unknown(a, "%s is not known", what);
        return;
    }
    acc_bool(a, (isnan(lo) || v >= lo) && (isnan(hi) || v <= hi));
}

/* Sum of the sections' volumes / the part's volume; NaN when that is unknown. */
static double lost_fraction(const sr_rule_part *part, const sr_run *run)
{
    if (!(part->volume_mm3 > 0))
        return NAN;
    double total = 0;
    for (size_t i = 0; i < run->section_count; i++)
        total += run->sections[i].volume_mm3;
    return total / part->volume_mm3;
}

static void material_conditions(verdict_acc *a, const sr_rule *r, const sr_rule_part *part)
{
    bool has_material = part->material && *part->material;
    if (r->material[0]) {
        if (!has_material)
            acc_unknown(a, "the part has no material (condition material = '%s')", r->material);
        else
            acc_bool(a, strcasecmp(r->material, part->material) == 0);
    }
    if (r->material_family[0]) {
        if (!has_material)
            acc_unknown(a, "the part has no material (condition material_family = '%s')",
                        r->material_family);
        else if (!part->info)
            acc_unknown(a, "material '%s' is not in the catalogue, so its family is not known",
                        part->material);
        else if (!part->info->family[0])
            acc_unknown(a, "material '%s' has no family in the catalogue", part->material);
        else
            acc_bool(a, strcmp(r->material_family, part->info->family) == 0);
    }
}

sr_rule_verdict sr_rule_evaluate(const sr_rule *r, const sr_rule_part *part,
                                 const sr_features *f, size_t f_count, char *why, size_t size)
{
    verdict_acc a = {false, false, why, size};
    if (why && size)
        why[0] = '\0';
    bool whole = strcmp(r->scope, "part") == 0;
    if (r->symmetry_kind[0]) {
        if (part->symmetry == SR_SYM_NONE)
            acc_unknown(&a, "the run's symmetry is not known");
        else
            acc_bool(&a, strcmp(r->symmetry_kind, sr_sym_kind_name(part->symmetry)) == 0);
    }
    material_conditions(&a, r, part);

    /* Section figures, or for a part rule their aggregate over the sections. */
    bool any_class = false, any_location = false;
    double volume = 0, depth = 0, depth_fraction = 0, section_fraction = 0;
    size_t n = whole ? f_count : (f ? 1 : 0);
    for (size_t i = 0; i < n; i++) {
        const sr_features *s = &f[i];
        any_class |= r->damage_class[0] && strcmp(s->damage_class, r->damage_class) == 0;
        any_location |= r->location[0] && sr_features_at(s, r->location);
        volume += s->volume_mm3;
        depth = fmax(depth, s->depth_max_mm);
        depth_fraction = isnan(depth_fraction) || isnan(s->depth_fraction)
                             ? NAN : fmax(depth_fraction, s->depth_fraction);
        section_fraction = isnan(section_fraction) || isnan(s->part_fraction)
                               ? NAN : fmax(section_fraction, s->part_fraction);
    }
    if (r->damage_class[0])
        acc_bool(&a, any_class);
    if (r->location[0])
        acc_bool(&a, any_location);
    acc_range(&a, r->min_volume_mm3, r->max_volume_mm3, volume, "the missing volume");
    acc_range(&a, r->min_depth_mm, r->max_depth_mm, depth, "the depth");
    acc_range(&a, r->min_depth_fraction, r->max_depth_fraction, depth_fraction,
              "the depth as a fraction of the local radius");
    acc_range(&a, r->min_section_fraction, r->max_section_fraction, section_fraction,
              "the section's fraction of the part's volume (part volume unknown)");
    acc_range(&a, r->min_lost_fraction, r->max_lost_fraction, part->lost_fraction,
              "the lost fraction of the part (part volume unknown)");
    if (r->feature[0]) {
        double v;
        if (whole)
            acc_unknown(&a, "feature '%s': feature conditions apply to sections, not to the "
                        "whole part", r->feature);
        else if (!f || !sr_features_value(f, r->feature, &v))
            acc_unknown(&a, "the section has no feature '%s'", r->feature);
        else
            acc_bool(&a, (isnan(r->feature_min) || v >= r->feature_min) &&
                             (isnan(r->feature_max) || v <= r->feature_max));
    }
    if (a.no)
        return SR_RULE_NO;
    return a.unknown ? SR_RULE_UNKNOWN : SR_RULE_YES;
}

/* ---- reasons ---- */

/* The rule's reason with {name} replaced by the figure of that name. */
static void fill_reason(const char *tmpl, const sr_features *f, const sr_rule_part *part,
                        double lost, char *out, size_t size)
{
    size_t o = 0;
    out[0] = '\0';
    for (const char *p = tmpl; *p && o + 1 < size;) {
        const char *close = *p == '{' ? strchr(p, '}') : NULL;
        char name[64], val[64];
        val[0] = '\0';
        if (close && (size_t)(close - p - 1) < sizeof name) {
            memcpy(name, p + 1, (size_t)(close - p - 1));
            name[close - p - 1] = '\0';
            double v;
            if (strcmp(name, "lost_fraction_pct") == 0 && !isnan(lost))
                snprintf(val, sizeof val, "%.1f", 100 * lost);
            else if (strcmp(name, "part_fraction_pct") == 0 && f && !isnan(f->part_fraction))
                snprintf(val, sizeof val, "%.1f", 100 * f->part_fraction);
            else if (strcmp(name, "class") == 0 && f)
                snprintf(val, sizeof val, "%s", f->damage_class);
            else if (strcmp(name, "location") == 0 && f && f->location_count)
                snprintf(val, sizeof val, "%s", f->locations[0]);
            else if (strcmp(name, "material") == 0 && part->material && *part->material)
                snprintf(val, sizeof val, "%s", part->material);
            else if (f && sr_features_value(f, name, &v))
                snprintf(val, sizeof val, "%.3g", v);
        }
        if (val[0]) {
            o += (size_t)snprintf(out + o, size - o, "%s", val);
            if (o >= size)
                o = size - 1;
            p = close + 1;
        } else {
            out[o++] = *p++;
            out[o] = '\0';
        }
    }
}

/* ---- choosing ---- */

typedef struct unevaluated {
    const sr_rule *rule;
    char why[200];
    bool outranks;
} unevaluated;

typedef struct blocked {
    const sr_rule *rule;
    char why[400];
} blocked;

typedef struct choice {
    const sr_rule *applied;
    const sr_rule **fired;
    size_t fired_count;
    unevaluated *unknown;
    size_t unknown_count;
    blocked *blocked;
    size_t blocked_count;
} choice;

static void choice_release(choice *c)
{
    free(c->fired);
    free(c->unknown);
    free(c->blocked);
    memset(c, 0, sizeof *c);
}

/* Why the material rules out rule r at this depth; NULL if it does not. */
static const char *material_blocks(const sr_rule *r, const sr_rule_part *part, double depth,
                                   char *buf, size_t size)
{
    if (!part->info)
        return NULL;
    const sr_material_limit *l = sr_material_limit_of(part->info, r->process);
    if (!l)
        return NULL;
    if (!l->suitable) {
        snprintf(buf, size, "process '%s' is not suitable for %s%s%s", r->process,
                 part->info->name, l->notes[0] ? ": " : "", l->notes);
        return buf;
    }
    if (!isnan(l->max_depth_mm) && depth > l->max_depth_mm) {
        snprintf(buf, size, "process '%s' on %s is limited to %g mm deep; the loss is %.3g mm",
                 r->process, part->info->name, l->max_depth_mm, depth);
        return buf;
    }
    return NULL;
}

/* Tries the rules of one scope on a section (f, 1) or the part (f, count). */
static sr_status choose(const sr_rule *rules, size_t rule_count, bool whole,
                        const sr_rule_part *part, const sr_features *f, size_t f_count,
                        choice *c, sr_err *err)
{
    memset(c, 0, sizeof *c);
    c->fired = calloc(rule_count + 1, sizeof *c->fired);
    c->unknown = calloc(rule_count + 1, sizeof *c->unknown);
    c->blocked = calloc(rule_count + 1, sizeof *c->blocked);
    if (!c->fired || !c->unknown || !c->blocked) {
        choice_release(c);
        return sr_err_set(err, SR_E_NOMEM, "out of memory applying %zu rules", rule_count);
    }
    double depth = 0;
    for (size_t i = 0; i < f_count; i++)
        depth = fmax(depth, f[i].depth_max_mm);
    for (size_t i = 0; i < rule_count; i++) {
        const sr_rule *r = &rules[i];
        if (!r->enabled || (strcmp(r->scope, "part") == 0) != whole)
            continue;
        unevaluated *u = &c->unknown[c->unknown_count];
        sr_rule_verdict v = sr_rule_evaluate(r, part, f, f_count, u->why, sizeof u->why);
        if (v == SR_RULE_UNKNOWN) {
            u->rule = r;
            u->outranks = c->applied == NULL;
            c->unknown_count++;
        } else if (v == SR_RULE_YES) {
            c->fired[c->fired_count++] = r;
            if (c->applied)
                continue;
            blocked *b = &c->blocked[c->blocked_count];
            if (material_blocks(r, part, depth, b->why, sizeof b->why)) {
                b->rule = r;
                c->blocked_count++;
            } else {
                c->applied = r;
            }
        }
    }
    return SR_OK;
}

static void json_rule_list(sr_jsonbuf *jb, const choice *c)
{
    sr_jsonbuf_key(jb, "applied");
    sr_jsonbuf_string(jb, c->applied ? c->applied->name : NULL);
    sr_jsonbuf_key(jb, "rules_fired");
    sr_jsonbuf_array_begin(jb);
    for (size_t i = 0; i < c->fired_count; i++)
        sr_jsonbuf_string(jb, c->fired[i]->name);
    sr_jsonbuf_array_end(jb);
    sr_jsonbuf_key(jb, "rules_blocked");
    sr_jsonbuf_array_begin(jb);
    for (size_t i = 0; i < c->blocked_count; i++) {
        sr_jsonbuf_object_begin(jb);
        sr_jsonbuf_key(jb, "rule");
        sr_jsonbuf_string(jb, c->blocked[i].rule->name);
        sr_jsonbuf_key(jb, "why");
        sr_jsonbuf_string(jb, c->blocked[i].why);
        sr_jsonbuf_object_end(jb);
    }
    sr_jsonbuf_array_end(jb);
}

static void json_unknown(sr_jsonbuf *jb, const choice *c, bool outranks_all)
{
    for (size_t i = 0; i < c->unknown_count; i++) {
        sr_jsonbuf_object_begin(jb);
        sr_jsonbuf_key(jb, "rule");
        sr_jsonbuf_string(jb, c->unknown[i].rule->name);
        sr_jsonbuf_key(jb, "scope");
        sr_jsonbuf_string(jb, c->unknown[i].rule->scope);
        sr_jsonbuf_key(jb, "why");
        sr_jsonbuf_string(jb, c->unknown[i].why);
        sr_jsonbuf_key(jb, "outranks_applied");
        sr_jsonbuf_bool(jb, outranks_all || c->unknown[i].outranks);
        sr_jsonbuf_object_end(jb);
    }
}

/* Fills one advice from a choice. f: the section's features (or the largest section's
 * for the part advice; NULL when there are none). */
static sr_status make_advice(const choice *c, const choice *part_choice, long index,
                             const sr_rule_part *part, const sr_features *f, double volume,
                             double lost, sr_run_advice *out, sr_err *err)
{
    memset(out, 0, sizeof *out);
    out->section_index = index;
    const sr_rule *r = c->applied;
    if (r) {
        out->rule_id = r->id;
        snprintf(out->rule_name, sizeof out->rule_name, "%s", r->name);
        snprintf(out->process, sizeof out->process, "%s", r->process);
        fill_reason(r->reason, f, part, lost, out->reason, sizeof out->reason);
    } else {
        snprintf(out->process, sizeof out->process, "manual_review");
        snprintf(out->reason, sizeof out->reason,
                 "no enabled rule applies: refer to the repair engineer");
    }
    sr_jsonbuf jb;
    sr_jsonbuf_init(&jb);
    sr_jsonbuf_object_begin(&jb);
    json_rule_list(&jb, c);
    sr_jsonbuf_key(&jb, "rules_unevaluated");
    sr_jsonbuf_array_begin(&jb);
    json_unknown(&jb, c, false);
    if (part_choice)
        json_unknown(&jb, part_choice, true);
    sr_jsonbuf_array_end(&jb);
    sr_jsonbuf_key(&jb, "parameters");
    sr_jsonbuf_raw(&jb, r ? r->parameters_json : "{}");
    if (index >= 0 && f) {
        sr_jsonbuf_key(&jb, "class");
        sr_jsonbuf_string(&jb, f->damage_class);
        sr_jsonbuf_key(&jb, "location");
        sr_jsonbuf_string(&jb, f->location_count ? f->locations[0] : NULL);
    }
    sr_jsonbuf_key(&jb, "material");
    sr_jsonbuf_string(&jb, part->material && *part->material ? part->material : NULL);
    double density = part->info ? part->info->density_g_cm3 : NAN;
    sr_jsonbuf_key(&jb, "density_g_cm3");
    sr_jsonbuf_number(&jb, density);
    sr_jsonbuf_key(&jb, "missing_volume_mm3");
    sr_jsonbuf_number(&jb, volume);
    sr_jsonbuf_key(&jb, "missing_mass_g");
    sr_jsonbuf_number(&jb, volume * density / 1000.0);  /* mm^3 * g/cm^3 / 1000 */
    sr_jsonbuf_key(&jb, "lost_fraction");
    sr_jsonbuf_number(&jb, lost);
    if (index >= 0 && part_choice && part_choice->applied) {
        sr_jsonbuf_key(&jb, "part_advice");
        sr_jsonbuf_string(&jb, part_choice->applied->name);
    }
    const sr_material_limit *l = r && part->info ? sr_material_limit_of(part->info, r->process)
                                                 : NULL;
    if (l && !isnan(l->preheat_c)) {
        sr_jsonbuf_key(&jb, "preheat_c");
        sr_jsonbuf_number(&jb, l->preheat_c);
    }
    sr_jsonbuf_object_end(&jb);
    return sr_jsonbuf_take(&jb, &out->details_json, err);
}

static void advice_free(sr_run_advice *a, size_t count)
{
    if (!a)
        return;
    for (size_t i = 0; i < count; i++)
        free(a[i].details_json);
    free(a);
}

sr_status sr_rules_advise(const sr_rule *rules, size_t rule_count, const sr_rule_part *part,
                          const sr_run *run, const sr_features *fs, sr_run_advice **out,
                          size_t *count, sr_err *err)
{
    size_t n = run->section_count;
    sr_rule_part whole_part = *part;
    whole_part.lost_fraction = lost_fraction(part, run);
    part = &whole_part;
    double lost = part->lost_fraction;
    sr_run_advice *adv = calloc(n + 1, sizeof *adv);
    if (!adv)
        return sr_err_set(err, SR_E_NOMEM, "out of memory for the advice of %zu sections", n);
    size_t made = 0;
    choice pc;
    sr_status st = choose(rules, rule_count, true, part, fs, n, &pc, err);
    if (st != SR_OK) {
        free(adv);
        return st;
    }
    if (pc.applied) {
        double total = 0;
        for (size_t i = 0; i < n; i++)
            total += run->sections[i].volume_mm3;
        st = make_advice(&pc, NULL, -1, part, n ? &fs[0] : NULL, total, lost, &adv[made], err);
        if (st == SR_OK)
            made++;
    }
    for (size_t i = 0; st == SR_OK && i < n; i++) {
        choice sc;
        st = choose(rules, rule_count, false, part, &fs[i], 1, &sc, err);
        if (st != SR_OK)
            break;
        st = make_advice(&sc, &pc, (long)i, part, &fs[i], run->sections[i].volume_mm3, lost,
                         &adv[made], err);
        choice_release(&sc);
        if (st == SR_OK)
            made++;
    }
    choice_release(&pc);
    if (st != SR_OK) {
        advice_free(adv, made);
        return st;
    }
    *out = adv;
    *count = made;
    return SR_OK;
}

/* ---- describe and advise a run in place ---- */

sr_status sr_advise_run(const sr_rule *rules, size_t rule_count, const char *material,
                        const sr_material *info, double part_volume_mm3, sr_run *run,
                        sr_err *err)
{
    size_t n = run->section_count;
    sr_feature_part fp = {part_volume_mm3 > 0 ? part_volume_mm3 : 0, 0};
    sr_features *fs = calloc(n ? n : 1, sizeof *fs);
    char **json = calloc(n ? n : 1, sizeof *json);
    sr_run_advice *adv = NULL;
    size_t adv_count = 0;
    sr_rule_part part = {material, info, run->symmetry.kind, fp.volume_mm3, NAN};
    sr_status st = SR_OK;
    if (!fs || !json)
        st = sr_err_set(err, SR_E_NOMEM, "out of memory describing %zu sections", n);
    for (size_t i = 0; st == SR_OK && i < n; i++) {
        st = sr_features_compute(run, i, &fp, &fs[i], err);
        if (st == SR_OK)
            st = sr_features_to_json(&fs[i], &json[i], err);
    }
    if (st == SR_OK)
        st = sr_rules_advise(rules, rule_count, &part, run, fs, &adv, &adv_count, err);
    if (st == SR_OK) {
        for (size_t i = 0; i < n; i++) {
            sr_run_section *s = &run->sections[i];
            free(s->features_json);
            s->features_json = json[i];
            json[i] = NULL;
            snprintf(s->damage_class, sizeof s->damage_class, "%s", fs[i].damage_class);
        }
        advice_free(run->advice, run->advice_count);
        run->advice = adv;
        run->advice_count = adv_count;
    }
    if (json)
        for (size_t i = 0; i < n; i++)
            free(json[i]);
    free(json);
    free(fs);
    return st;
}
