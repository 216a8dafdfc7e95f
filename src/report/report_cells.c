/*
 * report_cells.c: the readable cells of the report's feature and advice tables
 * (report_int.h), made from the JSON texts the run stores (a section's features_json, an
 * advice's details_json; section_features.h and rules.h say what they hold). A shop
 * reader gets named figures with their units ("height 14 mm, share of the part 0.88 %"),
 * the reasons and the rules fired as lists and the advice's process parameters as one
 * line ("layer 0.8 mm, step-over 1.2 mm, ..."), never JSON. A member this file does not
 * know is still shown, named from its key with the unit its suffix gives (_mm, _mm2,
 * _mm3, _deg, _c, _g, _g_min, _g_cm3, _fraction). The texts themselves go to the data
 * block (rp_put_json) for scripts.
 */
#include "report/report_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_scan.h"

/* How a known member reads: its label and unit; pct: a fraction shown as a percentage. */
typedef struct label {
    const char *key, *label, *unit;
    bool pct;
} label;

static const label labels[] = {
    {"height_mm", "height", "mm", false},
    {"length_mm", "length", "mm", false},
    {"breadth_mm", "breadth", "mm", false},
    {"width_mm", "width (narrow way)", "mm", false},
    {"circ_width_mm", "width round the axis", "mm", false},
    {"axial_width_mm", "width along the axis", "mm", false},
    {"local_radius_mm", "local radius", "mm", false},
    {"depth_fraction", "depth / local radius", "", true},
    {"part_fraction", "share of the part's volume", "", true},
    {"coverage", "coverage round the part", "", true},
    {"layer_loss_max", "largest loss of one layer", "", true},
    {"aspect", "length / breadth", "", false},
    {"wall_a", "wall beside it (a)", "", false},
    {"wall_b", "wall beside it (b)", "", false},
    {"shoulder_z_mm", "shoulder at z", "mm", false},
    {"cells", "grid cells", "", false},
    {"surface", "surface", "", false},
    {"layer_mm", "layer", "mm", false},
    {"step_over_mm", "step-over", "mm", false},
    {"allowance_mm", "allowance", "mm", false},
    {"deposition_rate_g_min", "deposition rate", "g/min", false},
    {"efficiency", "efficiency", "", true},
    {"density_g_cm3", "density", "g/cm³", false},
    {"missing_volume_mm3", "missing volume", "mm³", false},
    {"missing_mass_g", "missing mass", "g", false},
    {"lost_fraction", "lost share of the part", "", true},
    {"preheat_c", "preheat", "°C", false},
    {"part_advice", "whole-part advice", "", false},
};

/* Unit suffixes of keys not in the table, longest first. */
static const struct {
    const char *suffix, *unit;
    bool pct;
} suffixes[] = {
    {"_g_cm3", "g/cm³", false}, {"_g_min", "g/min", false}, {"_fraction", "", true},
    {"_mm3", "mm³", false},     {"_mm2", "mm²", false},     {"_deg", "°", false},
    {"_pct", "%", false},       {"_mm", "mm", false},       {"_min", "min", false},
    {"_c", "°C", false},        {"_g", "g", false},         {"_s", "s", false},
};

/* A JSON string's text (the span with its quotes) as HTML, escapes decoded. */
static void put_jstring(sb *b, const char *v, const char *end)
{
    char buf[8];
    for (const char *p = v + 1; p < end - 1; p++) {
        if (*p != '\\') {
            char one[2] = {*p, 0};
            sb_html(b, one);
            continue;
        }
        p++;
        if (p >= end - 1)
            break;
        switch (*p) {
        case 'n':
        case 't':
        case 'r':
        case 'b':
        case 'f': sb_put(b, " "); break;
        case 'u': {
            unsigned long c = 0;
            if (end - 1 - p < 5)
                return;
            char hex[5] = {p[1], p[2], p[3], p[4], 0};
            c = strtoul(hex, NULL, 16);
            p += 4;
            /* a surrogate pair */
            if (c >= 0xD800 && c < 0xDC00 && end - 1 - p >= 6 && p[1] == '\\' && p[2] == 'u') {
                char lo[5] = {p[3], p[4], p[5], p[6], 0};
                unsigned long l = strtoul(lo, NULL, 16);
                if (l >= 0xDC00 && l < 0xE000) {
                    c = 0x10000 + ((c - 0xD800) << 10) + (l - 0xDC00);
                    p += 6;
                }
            }
            if (c < 0x20 || (c >= 0xD800 && c < 0xE000))
                c = 0xFFFD;
            if (c < 0x80) {
                char one[2] = {(char)c, 0};
                sb_html(b, one);
                break;
            }
            size_t n = 0;
            if (c < 0x800) {
                buf[n++] = (char)(0xC0 | (c >> 6));
            } else if (c < 0x10000) {
                buf[n++] = (char)(0xE0 | (c >> 12));
                buf[n++] = (char)(0x80 | ((c >> 6) & 0x3F));
            } else {
                buf[n++] = (char)(0xF0 | (c >> 18));
                buf[n++] = (char)(0x80 | ((c >> 12) & 0x3F));
                buf[n++] = (char)(0x80 | ((c >> 6) & 0x3F));
            }
            buf[n++] = (char)(0x80 | (c & 0x3F));
            buf[n] = 0;
            sb_put(b, buf);
            break;
        }
        default: {
            char one[2] = {*p, 0};
            sb_html(b, one);
        }
        }
    }
}

/* A number as a reader wants it: 3 significant digits, no exponent below 1e6. */
static void put_number(sb *b, double v)
{
    double a = fabs(v);
    if (!isfinite(v))
        sb_put(b, "unknown");
    else if (a >= 1000 && a < 1e6)
        sb_printf(b, "%.0f", v);
    else
        sb_printf(b, "%.3g", v);
}

static bool key_is(const char *k, size_t klen, const char *name)
{
    return strlen(name) == klen && memcmp(k, name, klen) == 0;
}

/* Calls fn for each element of the JSON array [v, end); false when it is not one. */
typedef void (*element_fn)(const char *v, const char *end, size_t i, void *user);
static bool for_elements(const char *v, const char *end, element_fn fn, void *user)
{
    if (v >= end || *v != '[')
        return false;
    const char *p = sr_json_skip_space(v + 1);
    size_t i = 0;
    while (p < end && *p != ']') {
        const char *e = sr_json_value_end(p);
        if (!e || e > end)
            return false;
        fn(p, e, i++, user);
        p = sr_json_skip_space(e);
        if (*p == ',')
            p = sr_json_skip_space(p + 1);
    }
    return true;
}

static void put_value(sb *b, const char *v, const char *end, const char *unit, bool pct, int depth);

/* One member as "label value unit" (the figure list's item). */
typedef struct figs {
    sb *b;
    size_t n;                /* figures written so far */
    const char *const *skip; /* keys left out (NULL-terminated), or NULL */
    int depth;
} figs;

static void figure(const char *k, size_t klen, const char *v, const char *end, void *user)
{
    figs *f = user;
    for (const char *const *s = f->skip; s && *s; s++)
        if (key_is(k, klen, *s))
            return;
    const char *name = NULL, *unit = "";
    bool pct = false;
    for (size_t i = 0; i < sizeof labels / sizeof labels[0]; i++)
        if (key_is(k, klen, labels[i].key)) {
            name = labels[i].label;
            unit = labels[i].unit;
            pct = labels[i].pct;
        }
    char key[96];
    snprintf(key, sizeof key, "%.*s", (int)(klen < 95 ? klen : 95), k);
    if (!name) {
        size_t n = strlen(key);
        for (size_t i = 0; i < sizeof suffixes / sizeof suffixes[0]; i++) {
            size_t sl = strlen(suffixes[i].suffix);
            if (n > sl && strcmp(key + n - sl, suffixes[i].suffix) == 0) {
                key[n - sl] = '\0';
                unit = suffixes[i].unit;
                pct = suffixes[i].pct;
                break;
            }
        }
        for (char *c = key; *c; c++)
            if (*c == '_')
                *c = ' ';
        name = key;
    }
    sb_put(f->b, f->n++ ? ", <span class=\"fig\">" : "<span class=\"fig\">");
    sb_html(f->b, name);
    sb_put(f->b, " ");
    put_value(f->b, v, end, unit, pct, f->depth + 1);
    sb_put(f->b, "</span>");
}

typedef struct list_acc {
    sb *b;
    int depth;
} list_acc;

static void list_item(const char *v, const char *end, size_t i, void *user)
{
    list_acc *a = user;
    if (i)
        sb_put(a->b, ", ");
    put_value(a->b, v, end, "", false, a->depth);
}

/* A value: a number with its unit, a string, yes/no, unknown (null), a list, or an
 * object's figures in parentheses (nesting cut at depth 4). */
static void put_value(sb *b, const char *v, const char *end, const char *unit, bool pct, int depth)
{
    if (depth > 4) {
        sb_put(b, "…");
        return;
    }
    if (*v == '"') {
        put_jstring(b, v, end);
    } else if (*v == '{') {
        figs f = {b, 0, NULL, depth};
        char *text = strndup(v, (size_t)(end - v));
        if (!text) {
            b->failed = true;
            return;
        }
        sb_put(b, "(");
        sr_json_for_members(text, figure, &f);
        sb_put(b, ")");
        free(text);
    } else if (*v == '[') {
        list_acc a = {b, depth};
        if (end - v <= 2 || !for_elements(v, end, list_item, &a))
            sb_put(b, "none");
    } else if (strncmp(v, "true", 4) == 0) {
        sb_put(b, "yes");
    } else if (strncmp(v, "false", 5) == 0) {
        sb_put(b, "no");
    } else if (strncmp(v, "null", 4) == 0) {
        sb_put(b, "unknown");
    } else {
        char *stop;
        double x = strtod(v, &stop);
        if (stop == v) {
            sb_put(b, "?");
            return;
        }
        put_number(b, pct ? 100 * x : x);
        if (pct)
            sb_put(b, " %");
        else if (*unit)
            sb_printf(b, "%s%s", strcmp(unit, "°") == 0 ? "" : " ", unit);
    }
}

/* ---- the feature cell ---- */

/* Members the feature table shows in its own columns, or below as lists. */
static const char *const feature_shown[] = {
    "class",     "layers",       "z_min_mm",      "z_max_mm",   "angle_min_deg", "angle_max_deg",
    "arc_deg",   "depth_max_mm", "depth_mean_mm", "volume_mm3", "area_mm2",      "location",
    "locations", "reasons",      "side",          NULL};

typedef struct member_span {
    const char *name;
    const char *v, *end;
} member_span;

static void find_member(const char *k, size_t klen, const char *v, const char *end, void *user)
{
    member_span *m = user;
    if (!m->v && key_is(k, klen, m->name)) {
        m->v = v;
        m->end = end;
    }
}

static member_span member(const char *json, const char *name)
{
    member_span m = {name, NULL, NULL};
    sr_json_for_members(json, find_member, &m);
    return m;
}

static void li_item(const char *v, const char *end, size_t i, void *user)
{
    sb *b = user;
    sb_put(b, "<li>");
    put_value(b, v, end, "", false, 1);
    sb_put(b, "</li>");
}

/* A list member as <ul class="cls">; nothing when absent or empty. */
static void put_list(sb *b, const char *json, const char *name, const char *title, const char *cls,
                     element_fn item)
{
    member_span m = member(json, name);
    if (!m.v || *m.v != '[' || *sr_json_skip_space(m.v + 1) == ']')
        return;
    sb_printf(b, "<div class=\"%s\">%s<ul>", cls, title);
    for_elements(m.v, m.end, item, b);
    sb_put(b, "</ul></div>");
}

void rp_feature_cell(sb *b, const char *features_json)
{
    if (!features_json || *sr_json_skip_space(features_json) != '{') {
        sb_put(b, "-");
        return;
    }
    member_span loc = member(features_json, "locations");
    if (!loc.v)
        loc = member(features_json, "location");
    if (loc.v) {
        sb_put(b, "<div class=\"where\">at the ");
        put_value(b, loc.v, loc.end, "", false, 1);
        sb_put(b, "</div>");
    }
    figs f = {b, 0, feature_shown, 0};
    sb_put(b, "<div class=\"figs\">");
    sr_json_for_members(features_json, figure, &f);
    sb_put(b, "</div>");
    put_list(b, features_json, "reasons", "why this class:", "reasons", li_item);
}

/* ---- the advice cell ---- */

static const char *const advice_shown[] = {"applied",           "rules_fired", "rules_blocked",
                                           "rules_unevaluated", "parameters",  NULL};

typedef struct fired_acc {
    sb *b;
    member_span applied;
} fired_acc;

static void fired_item(const char *v, const char *end, size_t i, void *user)
{
    fired_acc *a = user;
    sb_put(a->b, "<li>");
    put_value(a->b, v, end, "", false, 1);
    if (a->applied.v && *a->applied.v == '"' && a->applied.end - a->applied.v == end - v &&
        memcmp(a->applied.v, v, (size_t)(end - v)) == 0)
        sb_put(a->b, " <em>(applied)</em>");
    sb_put(a->b, "</li>");
}

/* {"rule": name, "why": text, ...}: "name: why", the other members after it. */
static void ruled_item(const char *v, const char *end, size_t i, void *user)
{
    sb *b = user;
    char *text = strndup(v, (size_t)(end - v));
    if (!text) {
        b->failed = true;
        return;
    }
    sb_put(b, "<li>");
    member_span rule = member(text, "rule"), why = member(text, "why");
    if (rule.v && why.v) {
        put_value(b, rule.v, rule.end, "", false, 1);
        sb_put(b, ": ");
        put_value(b, why.v, why.end, "", false, 1);
        static const char *const shown[] = {"rule", "why", NULL};
        sb put = {0};
        figs f = {&put, 0, shown, 1};
        sr_json_for_members(text, figure, &f);
        if (f.n && put.p) {
            sb_put(b, " (");
            sb_put(b, put.p);
            sb_put(b, ")");
        }
        b->failed |= put.failed;
        free(put.p);
    } else {
        put_value(b, v, end, "", false, 1);
    }
    sb_put(b, "</li>");
    free(text);
}

void rp_advice_cell(sb *b, const char *details_json)
{
    if (!details_json || *sr_json_skip_space(details_json) != '{') {
        sb_put(b, "-");
        return;
    }
    member_span par = member(details_json, "parameters");
    if (par.v && *par.v == '{' && *sr_json_skip_space(par.v + 1) != '}') {
        char *text = strndup(par.v, (size_t)(par.end - par.v));
        if (!text) {
            b->failed = true;
            return;
        }
        figs f = {b, 0, NULL, 0};
        sb_put(b, "<div class=\"params\">process parameters: ");
        sr_json_for_members(text, figure, &f);
        sb_put(b, "</div>");
        free(text);
    }
    member_span fired = member(details_json, "rules_fired");
    if (fired.v && *fired.v == '[' && *sr_json_skip_space(fired.v + 1) != ']') {
        fired_acc a = {b, member(details_json, "applied")};
        sb_put(b, "<div class=\"rules\">rules fired:<ol>");
        for_elements(fired.v, fired.end, fired_item, &a);
        sb_put(b, "</ol></div>");
    }
    put_list(b, details_json, "rules_blocked", "rules passed over:", "rules", ruled_item);
    put_list(b, details_json, "rules_unevaluated", "rules not evaluated:", "rules", ruled_item);
    figs f = {b, 0, advice_shown, 0};
    sb_put(b, "<div class=\"figs\">");
    sr_json_for_members(details_json, figure, &f);
    sb_put(b, "</div>");
}

/* ---- the texts for scripts ---- */

void rp_put_json(sb *b, const char *json)
{
    if (!json || !*sr_json_skip_space(json)) {
        sb_put(b, "null");
        return;
    }
    /* valid JSON (the catalogue checks every stored text) has '<', '>' and '&' only in
     * strings, where \u escapes mean the same */
    for (const char *p = json; *p; p++) {
        if (*p == '<')
            sb_put(b, "\\u003c");
        else if (*p == '>')
            sb_put(b, "\\u003e");
        else if (*p == '&')
            sb_put(b, "\\u0026");
        else {
            const char *q = p;
            while (q[1] && q[1] != '<' && q[1] != '>' && q[1] != '&')
                q++;
            sb_putn(b, p, (size_t)(q - p + 1));
            p = q;
        }
    }
}
