/*
 * report_html.c: the self-contained HTML report of a run (report_html.h).
 *
 * The page is written into one growing buffer: the head with the inline stylesheet,
 * the static tables (run facts, missing sections, advice, parameters, alignment,
 * timings) made here with every text HTML-escaped, the layer selector, then the data
 * as one JSON block (<script type="application/json">, with '<', '>' and '&' written
 * as \u escapes so no text can end the element) and the inline script that draws the
 * 3D view on a 2D canvas (painter's order, flat shading, rotate by dragging, zoom by
 * the wheel) and the outlines of the selected layer as SVG, with the build plans of the
 * sections over them: each plan layer built from the selected run layer draws its
 * missing region (filled), its deposit region (dashed) and its deposition paths
 * (contour rings and raster runs in two colours). No address of any kind appears in
 * the page: it works from a single file, offline.
 *
 * The plans are made here with plan.h (sr_plan_build, the options given or the
 * defaults), one per section not advised 'replace'.
 *
 * Meshes over the display budget are reduced by vertex clustering (a grid coarsened
 * until the budget holds); the page states the stored and shown triangle counts.
 */
#include "report/report_html.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "plan/plan.h"
#include "base/symmetry.h"

#define DEFAULT_BUDGET 60000

/* ---- growing text ---- */

typedef struct sb {
    char *p;
    size_t len, cap;
    bool failed;
} sb;

static bool sb_room(sb *b, size_t n)
{
    if (b->failed)
        return false;
    if (b->len + n + 1 <= b->cap)
        return true;
    size_t cap = b->cap ? b->cap : 65536;
    while (cap < b->len + n + 1) {
        if (cap > SIZE_MAX / 2) {
            b->failed = true;
            return false;
        }
        cap *= 2;
    }
    char *p = realloc(b->p, cap);
    if (!p) {
        b->failed = true;
        return false;
    }
    b->p = p;
    b->cap = cap;
    return true;
}

static void sb_putn(sb *b, const char *s, size_t n)
{
    if (!sb_room(b, n))
        return;
    memcpy(b->p + b->len, s, n);
    b->len += n;
    b->p[b->len] = '\0';
}

static void sb_put(sb *b, const char *s)
{
    sb_putn(b, s, strlen(s));
}

static void sb_printf(sb *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void sb_printf(sb *b, const char *fmt, ...)
{
    char small[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->failed = true;
        return;
    }
    if ((size_t)n < sizeof small) {
        sb_putn(b, small, (size_t)n);
        return;
    }
    if (!sb_room(b, (size_t)n))
        return;
    va_start(ap, fmt);
    vsnprintf(b->p + b->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
}

/* Text as HTML character data or attribute value. */
static void sb_html(sb *b, const char *s)
{
    if (!s)
        return;
    for (const char *p = s; *p; p++) {
        switch (*p) {
        case '&':
            sb_put(b, "&amp;");
            break;
        case '<':
            sb_put(b, "&lt;");
            break;
        case '>':
            sb_put(b, "&gt;");
            break;
        case '"':
            sb_put(b, "&quot;");
            break;
        case '\'':
            sb_put(b, "&#39;");
            break;
        default:
            sb_putn(b, p, 1);
        }
    }
}

/* A JSON string for the data block: quotes, backslashes and control characters
 * escaped, and '<', '>', '&' as \u escapes so the text cannot close the script. */
static void sb_jstr(sb *b, const char *s)
{
    sb_put(b, "\"");
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; p++) {
        unsigned char c = *p;
        if (c == '"' || c == '\\') {
            char e[3] = {'\\', (char)c, 0};
            sb_put(b, e);
        } else if (c < 0x20 || c == '<' || c == '>' || c == '&') {
            sb_printf(b, "\\u%04x", c);
        } else {
            sb_putn(b, (const char *)p, 1);
        }
    }
    sb_put(b, "\"");
}

/* A number for the data block (null when not finite). */
static void sb_jnum(sb *b, double v, const char *fmt)
{
    if (isfinite(v))
        sb_printf(b, fmt, v);
    else
        sb_put(b, "null");
}

/* ---- decimation ---- */

typedef struct vkey {
    uint64_t key;
    uint32_t v;
} vkey;

static int vkey_cmp(const void *a, const void *b)
{
    uint64_t x = ((const vkey *)a)->key, y = ((const vkey *)b)->key;
    return x < y ? -1 : x > y;
}

/* One clustering pass at cell size h: vertices in a cell merge into their mean. */
static sr_status cluster(const sr_mesh *in, const double lo[3], double h, sr_mesh *out)
{
    size_t nv = in->vertex_count, nt = in->tri_count;
    vkey *keys = malloc(nv * sizeof *keys);
    uint32_t *map = malloc(nv * sizeof *map);
    if (!keys || !map) {
        free(keys);
        free(map);
        return SR_E_NOMEM;
    }
    for (size_t i = 0; i < nv; i++) {
        uint64_t k = 0;
        for (int a = 0; a < 3; a++) {
            double c = floor((in->xyz[3 * i + a] - lo[a]) / h);
            uint64_t ic = c < 0 ? 0 : c > 2097151 ? 2097151 : (uint64_t)c;
            k = (k << 21) | ic;
        }
        keys[i].key = k;
        keys[i].v = (uint32_t)i;
    }
    qsort(keys, nv, sizeof *keys, vkey_cmp);
    size_t clusters = 0;
    for (size_t i = 0; i < nv; i++) {
        if (i == 0 || keys[i].key != keys[i - 1].key)
            clusters++;
        map[keys[i].v] = (uint32_t)(clusters - 1);
    }
    free(keys);
    size_t kept = 0;
    for (size_t t = 0; t < nt; t++) {
        uint32_t a = map[in->tri[3 * t]], b = map[in->tri[3 * t + 1]], c = map[in->tri[3 * t + 2]];
        kept += a != b && b != c && a != c;
    }
    sr_mesh m = {0};
    sr_status st = sr_mesh_alloc(&m, clusters ? clusters : 1, kept ? kept : 1);
    if (st != SR_OK) {
        free(map);
        return st;
    }
    double *count = calloc(clusters ? clusters : 1, sizeof *count);
    if (!count) {
        free(map);
        sr_mesh_release(&m);
        return SR_E_NOMEM;
    }
    memset(m.xyz, 0, 3 * (clusters ? clusters : 1) * sizeof *m.xyz);
    for (size_t i = 0; i < nv; i++) {
        uint32_t c = map[i];
        for (int a = 0; a < 3; a++)
            m.xyz[3 * c + a] += in->xyz[3 * i + a];
        count[c] += 1;
    }
    for (size_t c = 0; c < clusters; c++)
        for (int a = 0; a < 3; a++)
            m.xyz[3 * c + a] /= count[c];
    free(count);
    size_t k = 0;
    for (size_t t = 0; t < nt; t++) {
        uint32_t a = map[in->tri[3 * t]], b = map[in->tri[3 * t + 1]], c = map[in->tri[3 * t + 2]];
        if (a != b && b != c && a != c) {
            m.tri[3 * k] = a;
            m.tri[3 * k + 1] = b;
            m.tri[3 * k + 2] = c;
            k++;
        }
    }
    free(map);
    m.vertex_count = clusters;
    m.tri_count = kept;
    *out = m;
    return SR_OK;
}

sr_status sr_report_decimate(const sr_mesh *in, size_t max_tri, sr_mesh *out, sr_err *err)
{
    if (in->tri_count <= max_tri) {
        sr_mesh m = {0};
        if (sr_mesh_copy(&m, in) != SR_OK)
            return sr_err_set(err, SR_E_NOMEM, "out of memory copying a mesh for the report");
        *out = m;
        return SR_OK;
    }
    if (max_tri == 0 || in->vertex_count == 0) {
        sr_mesh m = {0};
        *out = m;
        return SR_OK;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < in->vertex_count; i++)
        for (int a = 0; a < 3; a++) {
            double c = in->xyz[3 * i + a];
            if (c < lo[a])
                lo[a] = c;
            if (c > hi[a])
                hi[a] = c;
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diag > 0))
        diag = 1;
    /* start at the cell size that would give about max_tri triangles on a surface
     * (triangles ~ 2 (diag / h)^2), then coarsen by 1.3 until the budget holds */
    double h = diag / sqrt((double)max_tri / 2.0) / 2.0;
    if (h < diag / 2e6)
        h = diag / 2e6;
    for (int iter = 0; iter < 60; iter++, h *= 1.3) {
        sr_mesh m;
        sr_status st = cluster(in, lo, h, &m);
        if (st != SR_OK)
            return sr_err_set(err, st, "out of memory decimating a mesh for the report");
        if (m.tri_count <= max_tri) {
            *out = m;
            return SR_OK;
        }
        sr_mesh_release(&m);
    }
    sr_mesh m = {0};
    *out = m;
    return SR_OK;
}

/* ---- data block ---- */

static void put_mesh(sb *b, const sr_mesh *m)
{
    sb_put(b, "\"v\":[");
    for (size_t i = 0; i < 3 * m->vertex_count; i++) {
        if (i)
            sb_put(b, ",");
        sb_jnum(b, m->xyz[i], "%.6g");
    }
    sb_put(b, "],\"t\":[");
    for (size_t i = 0; i < 3 * m->tri_count; i++)
        sb_printf(b, i ? ",%u" : "%u", m->tri[i]);
    sb_put(b, "]");
}

static void put_points(sb *b, const double *xy, size_t n)
{
    sb_put(b, "[");
    for (size_t i = 0; i < 2 * n; i++) {
        if (i)
            sb_put(b, ",");
        sb_jnum(b, xy[i], "%.4f");
    }
    sb_put(b, "]");
}

/* A region or a set of polylines as [[x,y,x,y,...],...], 1e-5 mm (the polygon grid). */
static void put_poly(sb *b, const sr_poly2 *p)
{
    sb_put(b, "[");
    for (size_t c = 0; c < p->contour_count; c++) {
        sb_put(b, c ? ",[" : "[");
        for (size_t i = p->start[c]; i < p->start[c + 1]; i++) {
            if (i > p->start[c])
                sb_put(b, ",");
            sb_jnum(b, p->xy[2 * i], "%.5f");
            sb_put(b, ",");
            sb_jnum(b, p->xy[2 * i + 1], "%.5f");
        }
        sb_put(b, "]");
    }
    sb_put(b, "]");
}

/* ---- build plans ---- */

/* The plan of one section, or why there is none. */
typedef struct report_plan {
    const sr_run_section *section;
    bool replace;               /* advised 'replace': no plan */
    bool built;                 /* plan holds a plan */
    char why[512];              /* no plan, not replace: the plan module's message */
    const char *process;        /* the advised process ("" = none) */
    sr_plan plan;
} report_plan;

/* The advice for section `index` (0-based): replace when that section's or a
 * whole-part advice begins 'replace'; *process = the section's first advised process. */
static bool advised_replace(const sr_run *r, size_t index, const char **process)
{
    bool replace = false;
    *process = "";
    for (size_t i = 0; i < r->advice_count; i++) {
        const sr_run_advice *a = &r->advice[i];
        if (a->section_index >= 0 && (size_t)a->section_index != index)
            continue;
        if (a->section_index >= 0 && !**process)
            *process = a->process;
        if (strncasecmp(a->process, "replace", 7) == 0)
            replace = true;
    }
    return replace;
}

static void plans_release(report_plan *p, size_t n)
{
    for (size_t i = 0; p && i < n; i++)
        sr_plan_release(&p[i].plan);
    free(p);
}

/* One entry per section. SR_E_NOMEM only; a plan that cannot be made says why. */
static sr_status plans_build(const sr_run *r, const sr_plan_opts *opts, report_plan **out,
                             sr_err *err)
{
    *out = NULL;
    if (!r->section_count)
        return SR_OK;
    report_plan *p = calloc(r->section_count, sizeof *p);
    if (!p)
        return sr_err_set(err, SR_E_NOMEM, "out of memory building the report");
    for (size_t i = 0; i < r->section_count; i++) {
        p[i].section = &r->sections[i];
        p[i].replace = advised_replace(r, r->sections[i].index, &p[i].process);
        if (p[i].replace)
            continue;
        sr_err e;
        sr_err_clear(&e);
        sr_status st = sr_plan_build(r, r->sections[i].index, opts, &p[i].plan, &e);
        if (st == SR_E_NOMEM) {
            plans_release(p, r->section_count);
            return sr_err_set(err, SR_E_NOMEM, "out of memory building the report's plans");
        }
        p[i].built = st == SR_OK;
        if (!p[i].built)
            snprintf(p[i].why, sizeof p[i].why, "%s", e.msg[0] ? e.msg : sr_status_str(st));
    }
    *out = p;
    return SR_OK;
}

/* The build plan section: one row per section with the plan's figures, or why not. */
static void plan_table(sb *b, const sr_run *r, const report_plan *p)
{
    sb_put(b, "<section id=\"plans\"><h2>Build plans</h2>\n");
    if (r->section_count == 0) {
        sb_put(b, "<p>No missing section: no build plan.</p></section>\n");
        return;
    }
    bool all_replace = true;
    for (size_t i = 0; i < r->section_count; i++)
        all_replace = all_replace && p[i].replace;
    if (all_replace) {
        sb_put(b, "<p id=\"no-plan\">No build plan: the advice is to replace the part "
                  "(beyond repair).</p></section>\n");
        return;
    }
    const sr_plan *any = NULL;
    for (size_t i = 0; i < r->section_count && !any; i++)
        if (p[i].built)
            any = &p[i].plan;
    if (any)
        sb_printf(b, "<p class=\"note\">Per section, layer by layer along +z of the aligned "
                     "frame, as <code>symrec plan RUN --section K</code> writes it: pattern %s, "
                     "step-over %.3g mm, machining allowance %.3g mm, density %.3g g/cm³, "
                     "deposition rate %.3g cm³/min. The paths of the selected layer are "
                     "drawn in the plot above.</p>\n",
                  sr_plan_pattern_name(any->opts.pattern), any->opts.step_over_mm,
                  any->opts.allowance_mm, any->opts.density_g_cm3, any->opts.rate_cm3_min);
    sb_put(b, "<table id=\"plan-table\"><thead><tr><th>section</th><th>advice</th>"
              "<th>layers</th><th>layer (mm)</th><th>missing (mm³)</th>"
              "<th>deposit (mm³)</th><th>mass (g)</th><th>build time (min)</th>"
              "<th>path (mm)</th></tr></thead><tbody>\n");
    for (size_t i = 0; i < r->section_count; i++) {
        const report_plan *q = &p[i];
        sb_printf(b, "<tr class=\"plan\"><td class=\"n\">%zu</td><td>", q->section->index + 1);
        sb_html(b, q->process[0] ? q->process : "-");
        if (q->built) {
            const sr_plan *pl = &q->plan;
            sb_printf(b,
                      "</td><td class=\"n\">%zu</td><td class=\"n\">%.3f</td>"
                      "<td class=\"n\">%.1f</td><td class=\"n\">%.1f</td>"
                      "<td class=\"n\">%.2f</td><td class=\"n\">%.1f</td>"
                      "<td class=\"n\">%.0f</td></tr>\n",
                      pl->layer_count, pl->opts.layer_mm, pl->missing_volume_mm3,
                      pl->deposit_volume_mm3, pl->deposit_mass_g, pl->build_time_min,
                      pl->path_length_mm);
        } else {
            sb_put(b, "</td><td colspan=\"7\">No build plan: ");
            if (q->replace)
                sb_put(b, "the advice is to replace the part (beyond repair).");
            else
                sb_html(b, q->why);
            sb_put(b, "</td></tr>\n");
        }
    }
    sb_put(b, "</tbody></table></section>\n");
}

/* The plans in the data block: per section {"section", "replace", "why", and when
 * built "layer_mm", "allowance_mm", "step_over_mm", "layers": [{"zb", "z" (bottom and
 * top of the layer's slab, mm), "rf", "rl" (the run layers it was built from),
 * "m" (missing region), "g" (deposit region), "paths": [{"k": 1 ring | 2 raster,
 * "p": [x, y, ...]}]}]}. */
static void put_plans(sb *b, const sr_run *r, const report_plan *p)
{
    sb_put(b, ",\"plans\":[");
    for (size_t i = 0; i < r->section_count; i++) {
        const report_plan *q = &p[i];
        sb_printf(b, "%s{\"section\":%zu,\"replace\":%s,\"why\":", i ? "," : "",
                  q->section->index + 1, q->replace ? "true" : "false");
        if (q->built || q->replace)
            sb_put(b, "null");
        else
            sb_jstr(b, q->why);
        if (!q->built) {
            sb_put(b, ",\"layers\":[]}");
            continue;
        }
        const sr_plan *pl = &q->plan;
        sb_put(b, ",\"layer_mm\":");
        sb_jnum(b, pl->opts.layer_mm, "%.6g");
        sb_put(b, ",\"allowance_mm\":");
        sb_jnum(b, pl->opts.allowance_mm, "%.6g");
        sb_put(b, ",\"step_over_mm\":");
        sb_jnum(b, pl->opts.step_over_mm, "%.6g");
        sb_put(b, ",\"layers\":[");
        for (size_t k = 0; k < pl->layer_count; k++) {
            const sr_plan_layer *L = &pl->layers[k];
            sb_put(b, k ? ",{\"zb\":" : "{\"zb\":");
            sb_jnum(b, L->z_bottom_mm, "%.5f");
            sb_put(b, ",\"z\":");
            sb_jnum(b, L->z_top_mm, "%.5f");
            sb_printf(b, ",\"rf\":%zu,\"rl\":%zu,\"m\":", L->run_layer_first,
                      L->run_layer_last);
            put_poly(b, &L->missing);
            sb_put(b, ",\"g\":");
            put_poly(b, &L->region);
            sb_put(b, ",\"paths\":[");
            for (size_t c = 0; c < L->paths.contour_count; c++) {
                sb_printf(b, "%s{\"k\":%d,\"p\":[", c ? "," : "",
                          L->path_kind ? (int)L->path_kind[c] : 0);
                for (size_t j = L->paths.start[c]; j < L->paths.start[c + 1]; j++) {
                    if (j > L->paths.start[c])
                        sb_put(b, ",");
                    sb_jnum(b, L->paths.xy[2 * j], "%.5f");
                    sb_put(b, ",");
                    sb_jnum(b, L->paths.xy[2 * j + 1], "%.5f");
                }
                sb_put(b, "]}");
            }
            sb_put(b, "]}");
        }
        sb_put(b, "]}");
    }
    sb_put(b, "]");
}

/* ---- static parts ---- */

static const char style[] =
    "body{font:14px/1.45 system-ui,sans-serif;margin:0 auto;max-width:1100px;padding:1em;"
    "color:#1d232b;background:#fafbfc}"
    "h1{font-size:1.5em;margin:.2em 0}h2{font-size:1.15em;margin:1.4em 0 .4em;"
    "border-bottom:1px solid #d0d6de}"
    "table{border-collapse:collapse;margin:.3em 0}th,td{border:1px solid #d0d6de;"
    "padding:.2em .5em;text-align:left;vertical-align:top}th{background:#eef1f5}"
    "td.n{text-align:right;font-variant-numeric:tabular-nums}"
    "code{font-size:.9em;white-space:pre-wrap;word-break:break-all}"
    ".ok{color:#17653a}.failed{color:#a61b1b}.note{color:#5b6673;font-size:.92em}"
    "#view{border:1px solid #d0d6de;background:#fff;cursor:grab;touch-action:none;"
    "max-width:100%}"
    "#layer-plot svg{border:1px solid #d0d6de;background:#fff;max-width:100%;height:auto}"
    ".key{display:inline-block;width:2em;height:0;border-top:3px solid;margin:0 .3em "
    ".25em 1em}"
    ".swatch{display:inline-block;width:1.4em;height:.9em;margin:0 .3em -.1em 1em;"
    "background:#f6b26b;opacity:.6}";

/* The viewer and the outline plot. Plain ES5, no external anything. */
static const char script[] =
    "(function(){'use strict';\n"
    "var data=JSON.parse(document.getElementById('report-data').textContent);\n"
    "var cv=document.getElementById('view');\n"
    "var sp=document.getElementById('show-part'),sq=document.getElementById('show-patches');\n"
    "var meshes=[];\n"
    "if(data.restored)meshes.push({m:data.restored,col:[168,176,188],patch:false});\n"
    "data.patches.forEach(function(p){meshes.push({m:p,col:[232,96,28],patch:true});});\n"
    "var lo=[Infinity,Infinity,Infinity],hi=[-Infinity,-Infinity,-Infinity];\n"
    "meshes.forEach(function(e){var v=e.m.v;for(var i=0;i<v.length;i+=3)for(var k=0;k<3;k++)"
    "{if(v[i+k]<lo[k])lo[k]=v[i+k];if(v[i+k]>hi[k])hi[k]=v[i+k];}});\n"
    "var ctr=[(lo[0]+hi[0])/2,(lo[1]+hi[1])/2,(lo[2]+hi[2])/2];\n"
    "var rad=Math.max(1e-9,Math.sqrt(Math.pow(hi[0]-lo[0],2)+Math.pow(hi[1]-lo[1],2)"
    "+Math.pow(hi[2]-lo[2],2))/2);\n"
    "var yaw=0.6,pitch=0.45,zoom=1,pending=false;\n"
    "function draw(){pending=false;if(!cv||!cv.getContext)return;var g=cv.getContext('2d');\n"
    " var W=cv.width,H=cv.height;g.fillStyle='#ffffff';g.fillRect(0,0,W,H);\n"
    " if(!meshes.length){g.fillStyle='#5b6673';g.font='16px sans-serif';"
    "g.fillText('no meshes stored with this run',20,40);return;}\n"
    " var cy=Math.cos(yaw),sy=Math.sin(yaw),cp=Math.cos(pitch),spn=Math.sin(pitch);\n"
    " var s=zoom*0.45*Math.min(W,H)/rad;var faces=[];\n"
    " meshes.forEach(function(e){if(e.patch?(sq&&!sq.checked):(sp&&!sp.checked))return;\n"
    "  var v=e.m.v,t=e.m.t,n=v.length/3,P=new Float64Array(v.length);\n"
    "  for(var i=0;i<n;i++){var x=v[3*i]-ctr[0],y=v[3*i+1]-ctr[1],z=v[3*i+2]-ctr[2];\n"
    "   var x1=cy*x-sy*y,y1=sy*x+cy*y;P[3*i]=x1;P[3*i+1]=cp*y1-spn*z;P[3*i+2]=spn*y1+cp*z;}\n"
    "  var bias=e.patch?-4*rad:0;\n"
    "  for(var j=0;j<t.length;j+=3){var a=3*t[j],b=3*t[j+1],c=3*t[j+2];\n"
    "   var ux=P[b]-P[a],uy=P[b+1]-P[a+1],uz=P[b+2]-P[a+2],"
    "vx=P[c]-P[a],vy=P[c+1]-P[a+1],vz=P[c+2]-P[a+2];\n"
    "   var nx=uy*vz-uz*vy,ny=uz*vx-ux*vz,nz=ux*vy-uy*vx,nl=Math.sqrt(nx*nx+ny*ny+nz*nz);\n"
    "   if(!(nl>0))continue;var lum=0.35+0.65*Math.abs(ny)/nl;\n"
    "   faces.push({d:(P[a+1]+P[b+1]+P[c+1])/3+bias,P:P,a:a,b:b,c:c,col:e.col,lum:lum});}});\n"
    " faces.sort(function(p,q){return q.d-p.d;});\n"
    " for(var f=0;f<faces.length;f++){var F=faces[f],P=F.P;\n"
    "  var col='rgb('+Math.round(F.col[0]*F.lum)+','+Math.round(F.col[1]*F.lum)+','"
    "+Math.round(F.col[2]*F.lum)+')';g.fillStyle=col;g.strokeStyle=col;g.lineWidth=0.6;\n"
    "  g.beginPath();g.moveTo(W/2+s*P[F.a],H/2-s*P[F.a+2]);g.lineTo(W/2+s*P[F.b],H/2-s*P[F.b+2]);"
    "g.lineTo(W/2+s*P[F.c],H/2-s*P[F.c+2]);g.closePath();g.fill();g.stroke();}\n"
    "}\n"
    "function later(){if(!pending){pending=true;window.requestAnimationFrame(draw);}}\n"
    "if(cv){var drag=null;\n"
    " cv.addEventListener('pointerdown',function(ev){drag=[ev.clientX,ev.clientY];"
    "cv.setPointerCapture(ev.pointerId);});\n"
    " cv.addEventListener('pointermove',function(ev){if(!drag)return;"
    "yaw+=(ev.clientX-drag[0])*0.01;pitch+=(ev.clientY-drag[1])*0.01;"
    "drag=[ev.clientX,ev.clientY];later();});\n"
    " cv.addEventListener('pointerup',function(){drag=null;});\n"
    " cv.addEventListener('wheel',function(ev){ev.preventDefault();"
    "zoom*=ev.deltaY<0?1.1:1/1.1;later();},{passive:false});}\n"
    "if(sp)sp.addEventListener('change',later);if(sq)sq.addEventListener('change',later);\n"
    "var rs=document.getElementById('reset-view');if(rs)rs.addEventListener('click',"
    "function(){yaw=0.6;pitch=0.45;zoom=1;later();});\n"
    "draw();\n"
    /* outlines */
    "var sel=document.getElementById('layer-select'),plot=document.getElementById('layer-plot');\n"
    "var zb=document.getElementById('plot-zoom');\n"
    "var L=data.layers,ex=[Infinity,Infinity,-Infinity,-Infinity];\n"
    "function grow(a){for(var i=0;i+1<a.length;i+=2)"
    "{if(a[i]===null||a[i+1]===null)continue;if(a[i]<ex[0])ex[0]=a[i];if(a[i+1]<ex[1])"
    "ex[1]=a[i+1];if(a[i]>ex[2])ex[2]=a[i];if(a[i+1]>ex[3])ex[3]=a[i+1];}}\n"
    "L.forEach(function(l){grow(l.d);grow(l.r);});\n"
    /* build plans: the plan layers made from run layer i */
    "var PL=data.plans||[];\n"
    "PL.forEach(function(p){p.layers.forEach(function(q){q.g.forEach(grow);});});\n"
    "function planLayers(i){var out=[];PL.forEach(function(p){p.layers.forEach(function(q,k)"
    "{if(i>=q.rf&&i<=q.rl)out.push({p:p,q:q,k:k});});});return out;}\n"
    "function area(c,S,cls){var d='';c.forEach(function(a){if(a.length<6)return;d+='M';"
    "for(var j=0;j+1<a.length;j+=2)d+=(j?' L':'')+fmt(S.x(a[j]))+' '+fmt(S.y(a[j+1]));"
    "d+=' Z ';});return d?'<path class=\"'+cls+'\" d=\"'+d+'\"/>':'';}\n"
    "function path(a,S,cls){var pts=[];for(var j=0;j+1<a.length;j+=2)"
    "pts.push(fmt(S.x(a[j]))+','+fmt(S.y(a[j+1])));"
    "return pts.length>1?'<polyline class=\"'+cls+'\" points=\"'+pts.join(' ')+'\"/>':'';}\n"
    "function fmt(x){return (Math.round(x*1000)/1000).toString();}\n"
    "function lines(a,S,cls){var n=a.length/2,out='',cur=[];\n"
    " function flush(){if(cur.length>1)out+='<polyline class=\"'+cls+'\" points=\"'+"
    "cur.join(' ')+'\"/>';cur=[];}\n"
    " for(var i=0;i<=n&&n>0;i++){var k=i%n,x=a[2*k],y=a[2*k+1];"
    "if(x===null||y===null){flush();continue;}cur.push(fmt(S.x(x))+','+fmt(S.y(y)));}\n"
    " flush();return out;}\n"
    "function plotLayer(){if(!plot)return;if(!L.length||!(ex[2]>=ex[0])){plot.innerHTML="
    "'<p class=\"note\">no per-layer outlines stored with this run</p>';return;}\n"
    " var i=sel?parseInt(sel.value,10):0;if(!(i>=0&&i<L.length))i=0;var l=L[i];\n"
    " var pls=planLayers(i),plan='',np=0,E=ex,zoomed=false;\n"
    /* zoomed to the deposit regions of the layer's plans (with a margin) */
    " if(zb&&zb.checked&&pls.length){var z=[Infinity,Infinity,-Infinity,-Infinity];\n"
    "  pls.forEach(function(e){e.q.g.forEach(function(a){for(var j=0;j+1<a.length;j+=2){"
    "if(a[j]<z[0])z[0]=a[j];if(a[j+1]<z[1])z[1]=a[j+1];if(a[j]>z[2])z[2]=a[j];"
    "if(a[j+1]>z[3])z[3]=a[j+1];}});});\n"
    "  if(z[2]>=z[0]){var g=0.15*Math.max(z[2]-z[0],z[3]-z[1])+1;"
    "E=[z[0]-g,z[1]-g,z[2]+g,z[3]+g];zoomed=true;}}\n"
    " var W=640,H=640,m=30,span=Math.max(E[2]-E[0],E[3]-E[1],1e-9),k=(W-2*m)/span;\n"
    " var x0=(E[0]+E[2]-span)/2,y0=(E[1]+E[3]-span)/2;\n"
    " var S={x:function(x){return m+(x-x0)*k;},y:function(y){return H-m-(y-y0)*k;}};\n"
    " pls.forEach(function(e){plan+=area(e.q.m,S,'mr')+area(e.q.g,S,'gr');});\n"
    " pls.forEach(function(e){e.q.paths.forEach(function(t){var s=path(t.p,S,t.k===1?'tp ring':"
    "'tp raster');if(s){plan+=s;np++;}});});\n"
    " var cap=pls.length?pls.map(function(e){return 'section '+e.p.section+' plan layer '+"
    "(e.k+1)+'/'+e.p.layers.length;}).join(', ')+': '+np+' paths':'no build plan in this layer';\n"
    " var svg='<svg viewBox=\"0 0 '+W+' '+H+'\" width=\"'+W+'\" height=\"'+H+'\" role=\"img\">'+"
    "'<style>.dm{fill:none;stroke:#b3261e;stroke-width:2}.rs{fill:none;stroke:#1f5fbf;"
    "stroke-width:1.5;stroke-dasharray:6 4}.mr{fill:#f6b26b;fill-opacity:.45;stroke:none;"
    "fill-rule:nonzero}.gr{fill:none;stroke:#8a5a00;stroke-width:1;stroke-dasharray:3 3}"
    ".tp{fill:none;stroke-width:1.2}.ring{stroke:#0b7a3e}.raster{stroke:#6a1b9a}</style>'+"
    "plan+lines(l.r,S,'rs')+lines(l.d,S,'dm')+"
    "'<rect x=\"0\" y=\"0\" width=\"'+W+'\" height=\"44\" fill=\"#fff\" fill-opacity=\".85\"/>'+"
    "'<text x=\"'+m+'\" y=\"20\" font-size=\"13\">layer '+i+', z = '+fmt(l.z)+' mm (aligned "
    "frame; '+fmt(span)+' mm across'+(zoomed?', zoomed to the build plan':'')+')</text>'+"
    "'<text x=\"'+m+'\" y=\"38\" font-size=\"12\" class=\"plan-caption\">'+cap+'</text>'+"
    "'</svg>';\n"
    " plot.innerHTML=svg;plot.setAttribute('data-paths',String(np));}\n"
    "if(sel)sel.addEventListener('change',plotLayer);"
    "if(zb)zb.addEventListener('change',plotLayer);plotLayer();\n"
    "document.body.setAttribute('data-rendered','1');\n"
    "})();\n";

static const char *sym_text(const sr_symmetry *s, char *buf, size_t size)
{
    switch (s->kind) {
    case SR_SYM_AXIAL:
        if (s->order)
            snprintf(buf, size, "axial, %d-fold", s->order);
        else
            snprintf(buf, size, "axial, continuous");
        break;
    case SR_SYM_MIRROR:
        snprintf(buf, size, "mirror");
        break;
    case SR_SYM_GLIDE:
        snprintf(buf, size, "glide, shift %g mm", s->shift_mm);
        break;
    default:
        snprintf(buf, size, "-");
    }
    return buf;
}

static void fact(sb *b, const char *label, const char *value)
{
    sb_put(b, "<tr><th>");
    sb_html(b, label);
    sb_put(b, "</th><td>");
    sb_html(b, value && *value ? value : "-");
    sb_put(b, "</td></tr>\n");
}

/* The timings object ({"phase": seconds, ...}) as table rows; false when it is not a
 * flat object of numbers (then the caller shows the text). */
static bool timing_rows(sb *b, const char *json)
{
    const char *p = json;
    while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r')
        p++;
    if (*p++ != '{')
        return false;
    sb rows = {0};
    for (;;) {
        while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r' || *p == ',')
            p++;
        if (*p == '}')
            break;
        if (*p != '"')
            goto bad;
        const char *k = ++p;
        while (*p && *p != '"')
            p += (*p == '\\' && p[1]) ? 2 : 1;
        if (*p != '"')
            goto bad;
        size_t klen = (size_t)(p - k);
        p++;
        while (*p == ' ')
            p++;
        if (*p++ != ':')
            goto bad;
        char *end;
        double v = strtod(p, &end);
        if (end == p)
            goto bad;
        p = end;
        char key[128];
        snprintf(key, sizeof key, "%.*s", (int)(klen < 127 ? klen : 127), k);
        sb_put(&rows, "<tr><th>");
        sb_html(&rows, key);
        sb_printf(&rows, "</th><td class=\"n\">%.3f</td></tr>\n", v);
    }
    if (rows.failed)
        goto bad;
    if (rows.p)
        sb_put(b, rows.p);
    free(rows.p);
    return true;
bad:
    free(rows.p);
    return false;
}

/* Counter-clockwise end of an axial arc in [0, 360], as `run show` prints it. */
static double arc_end(const sr_run_section *s)
{
    if (s->angle_to_deg - s->angle_from_deg >= 360)
        return s->angle_from_deg + 360;
    return s->angle_to_deg > 360 ? s->angle_to_deg - 360 : s->angle_to_deg;
}

static void section_table(sb *b, const sr_run *r)
{
    sb_put(b, "<section id=\"sections\"><h2>Missing sections</h2>\n");
    if (r->section_count == 0) {
        sb_put(b, "<p>No missing section was found: nothing to repair.</p></section>\n");
        return;
    }
    sb_put(b, "<table id=\"feature-table\"><thead><tr><th>#</th><th>class</th>"
              "<th>layers</th><th>z from (mm)</th><th>z to (mm)</th>"
              "<th>angular range (deg) / side</th><th>depth max (mm)</th>"
              "<th>depth mean (mm)</th><th>volume (mm³)</th><th>area (mm²)</th>"
              "<th>further features</th></tr></thead><tbody>\n");
    for (size_t i = 0; i < r->section_count; i++) {
        const sr_run_section *s = &r->sections[i];
        sb_printf(b, "<tr class=\"section\" id=\"section-%zu\"><td class=\"n\">%zu</td><td>",
                  s->index + 1, s->index + 1);
        sb_html(b, s->damage_class);
        sb_printf(b,
                  "</td><td class=\"n\">%zu–%zu</td><td class=\"n\">%.2f</td>"
                  "<td class=\"n\">%.2f</td><td>",
                  s->layer_first, s->layer_last, s->z_min_mm, s->z_max_mm);
        if (s->has_angles)
            sb_printf(b, "%.1f° to %.1f° (%.1f° arc)", s->angle_from_deg, arc_end(s),
                      s->angle_to_deg - s->angle_from_deg);
        else if (s->side)
            sb_printf(b, "side %+d of the plane", s->side);
        else
            sb_put(b, "-");
        sb_printf(b,
                  "</td><td class=\"n\">%.2f</td><td class=\"n\">%.2f</td>"
                  "<td class=\"n\">%.1f</td><td class=\"n\">%.1f</td><td>",
                  s->depth_max_mm, s->depth_mean_mm, s->volume_mm3, s->area_mm2);
        if (s->features_json) {
            sb_put(b, "<code>");
            sb_html(b, s->features_json);
            sb_put(b, "</code>");
        } else {
            sb_put(b, "-");
        }
        sb_put(b, "</td></tr>\n");
    }
    sb_put(b, "</tbody></table></section>\n");
}

static void advice_table(sb *b, const sr_run *r)
{
    sb_put(b, "<section id=\"advice\"><h2>Advice</h2>\n");
    if (r->advice_count == 0) {
        sb_put(b, "<p>No advice was recorded with this run.</p></section>\n");
        return;
    }
    sb_put(b, "<table id=\"advice-table\"><thead><tr><th>section</th><th>process</th>"
              "<th>rule</th><th>reason</th><th>plan and rules fired</th></tr></thead>"
              "<tbody>\n");
    for (size_t i = 0; i < r->advice_count; i++) {
        const sr_run_advice *a = &r->advice[i];
        sb_put(b, "<tr class=\"advice\"><td>");
        if (a->section_index >= 0)
            sb_printf(b, "%ld", a->section_index + 1);
        else
            sb_put(b, "whole part");
        sb_put(b, "</td><td>");
        sb_html(b, a->process);
        sb_put(b, "</td><td>");
        if (a->rule_name[0])
            sb_html(b, a->rule_name);
        else if (a->rule_id)
            sb_printf(b, "rule %lld (deleted)", (long long)a->rule_id);
        else
            sb_put(b, "built in");
        sb_put(b, "</td><td>");
        sb_html(b, a->reason);
        sb_put(b, "</td><td><code>");
        sb_html(b, a->details_json ? a->details_json : "{}");
        sb_put(b, "</code></td></tr>\n");
    }
    sb_put(b, "</tbody></table></section>\n");
}

static void params_tables(sb *b, const sr_run *r)
{
    const sr_params *p = &r->params;
    char sym[64];
    sb_put(b, "<section id=\"parameters\"><h2>Parameters</h2>\n<table id=\"params-table\">\n");
    fact(b, "parameter set", p->name);
    fact(b, "symmetry", sym_text(&r->symmetry, sym, sizeof sym));
    fact(b, "method", r->method);
    sb_printf(b, "<tr><th>layers</th><td class=\"n\">%d</td></tr>\n", p->layers);
    sb_printf(b, "<tr><th>sectors</th><td class=\"n\">%d</td></tr>\n", p->sectors);
    sb_printf(b, "<tr><th>gamma_axis</th><td class=\"n\">%g</td></tr>\n", p->gamma_axis);
    sb_printf(b, "<tr><th>gamma_plane</th><td class=\"n\">%g</td></tr>\n", p->gamma_plane);
    sb_printf(b, "<tr><th>delta_d</th><td class=\"n\">%g</td></tr>\n", p->delta_d);
    sb_printf(b, "<tr><th>min depth (mm)</th><td class=\"n\">%g</td></tr>\n", p->min_depth_mm);
    sb_printf(b, "<tr><th>min volume (mm³)</th><td class=\"n\">%g</td></tr>\n",
              p->min_volume_mm3);
    sb_put(b, "</table></section>\n");

    sb_put(b, "<section id=\"alignment\"><h2>Alignment</h2>\n");
    if (r->has_alignment) {
        sb_printf(b, "<p>Scan to aligned frame, 3×4 (rotation | translation in mm), %s.</p>\n",
                  r->alignment_given ? "given by the user" : "found by search");
        sb_put(b, "<table id=\"alignment-table\">\n");
        for (int i = 0; i < 3; i++) {
            sb_put(b, "<tr>");
            for (int j = 0; j < 4; j++)
                sb_printf(b, "<td class=\"n\">%.6f</td>", r->alignment[4 * i + j]);
            sb_put(b, "</tr>\n");
        }
        sb_put(b, "</table>\n");
    } else {
        sb_put(b, "<p>The run did not reach the alignment.</p>\n");
    }
    if (r->fit_quality >= 0)
        sb_printf(b, "<p>Fit quality: %.3f (fraction of layers found symmetric).</p>\n",
                  r->fit_quality);
    sb_put(b, "</section>\n");

    sb_put(b, "<section id=\"timings\"><h2>Timings (s)</h2>\n");
    if (!r->timings_json) {
        sb_put(b, "<p>No timings recorded.</p>\n");
    } else {
        sb_put(b, "<table id=\"timings-table\">\n");
        size_t mark = b->len;
        if (!timing_rows(b, r->timings_json)) {
            b->len = mark;
            if (b->p)
                b->p[mark] = '\0';
            sb_put(b, "<tr><td><code>");
            sb_html(b, r->timings_json);
            sb_put(b, "</code></td></tr>\n");
        }
        sb_put(b, "</table>\n");
    }
    sb_put(b, "</section>\n");
}

/* ---- the page ---- */

sr_status sr_report_html(const sr_run *run, const sr_report_opts *opts, char **out,
                         size_t *out_len, sr_report_info *info, sr_err *err)
{
    size_t budget = opts && opts->max_triangles ? opts->max_triangles : DEFAULT_BUDGET;

    /* display meshes: each its share of the budget */
    size_t stored = run->restored.tri_count;
    for (size_t i = 0; i < run->section_count; i++)
        stored += run->sections[i].patch.tri_count;
    size_t nm = run->section_count + 1;
    sr_mesh *shown = calloc(nm, sizeof *shown);
    if (!shown)
        return sr_err_set(err, SR_E_NOMEM, "out of memory building the report");
    sr_status st = SR_OK;
    size_t tri_shown = 0;
    bool decimated = false;
    for (size_t i = 0; i < nm && st == SR_OK; i++) {
        const sr_mesh *m = i == 0 ? &run->restored : &run->sections[i - 1].patch;
        if (m->tri_count == 0)
            continue;
        size_t cap = stored <= budget ? m->tri_count
                                      : (size_t)((double)budget * (double)m->tri_count /
                                                 (double)stored);
        if (cap < 64)
            cap = m->tri_count < 64 ? m->tri_count : 64;
        st = sr_report_decimate(m, cap, &shown[i], err);
        if (st == SR_OK) {
            tri_shown += shown[i].tri_count;
            decimated |= shown[i].tri_count < m->tri_count;
        }
    }
    report_plan *plans = NULL;
    if (st == SR_OK) {
        sr_plan_opts defaults;
        sr_plan_opts_init(&defaults);
        st = plans_build(run, opts && opts->plan ? opts->plan : &defaults, &plans, err);
    }
    if (st != SR_OK) {
        for (size_t i = 0; i < nm; i++)
            sr_mesh_release(&shown[i]);
        free(shown);
        return st;
    }

    sb b = {0};
    char sym[64], title[256];
    snprintf(title, sizeof title, "symrec report: run %lld, part %s", (long long)run->id,
             run->part_number);
    sb_put(&b, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
               "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
               "<title>");
    sb_html(&b, title);
    sb_put(&b, "</title>\n<style>");
    sb_put(&b, style);
    sb_put(&b, "</style>\n</head>\n<body>\n<header>\n<h1>");
    sb_html(&b, title);
    sb_printf(&b, "</h1>\n<p>Status: <strong class=\"%s\">%s</strong>", run->ok ? "ok" : "failed",
              run->ok ? "ok" : "failed");
    if (!run->ok) {
        sb_put(&b, ": ");
        sb_html(&b, run->error);
    }
    sb_put(&b, "</p>\n</header>\n");

    /* the run's facts */
    sb_put(&b, "<section id=\"run\"><h2>Run</h2>\n<table id=\"run-table\">\n");
    char num[64];
    snprintf(num, sizeof num, "%lld", (long long)run->id);
    fact(&b, "run", num);
    fact(&b, "part", run->part_number);
    if (opts && opts->part_name)
        fact(&b, "part name", opts->part_name);
    if (opts && opts->material)
        fact(&b, "material", opts->material);
    snprintf(num, sizeof num, "%lld", (long long)run->instance_id);
    fact(&b, "instance", num);
    if (opts && opts->serial)
        fact(&b, "serial", opts->serial);
    if (opts && opts->received)
        fact(&b, "received", opts->received);
    fact(&b, "symmetry", sym_text(&run->symmetry, sym, sizeof sym));
    fact(&b, "method", run->method);
    fact(&b, "started (UTC)", run->started_at);
    fact(&b, "finished (UTC)", run->finished_at);
    fact(&b, "symrec version", run->software_version);
    double total = 0;
    for (size_t i = 0; i < run->section_count; i++)
        total += run->sections[i].volume_mm3;
    snprintf(num, sizeof num, "%zu, %.1f mm³ missing in all", run->section_count, total);
    fact(&b, "missing sections", num);
    sb_put(&b, "</table></section>\n");

    /* 3D view */
    sb_put(&b, "<section id=\"view3d\"><h2>Part and patches</h2>\n"
               "<p class=\"note\">The restored part (grey) with the patches that fill the "
               "missing sections (orange), in the scan frame; patches are drawn over the part, so a patch on "
               "the far side shows through. Drag to rotate, wheel to zoom."
               "</p>\n<p><label><input type=\"checkbox\" id=\"show-part\" checked> restored "
               "part</label> <label><input type=\"checkbox\" id=\"show-patches\" checked> "
               "patches</label> <button type=\"button\" id=\"reset-view\">reset view</button>"
               "</p>\n<canvas id=\"view\" width=\"720\" height=\"480\"></canvas>\n"
               "<p class=\"note\" id=\"view-note\">");
    if (stored == 0)
        sb_put(&b, "No meshes were stored with this run (or they were not read).");
    else if (decimated)
        sb_printf(&b, "Shown with %zu of the %zu stored triangles: meshes over the display "
                      "budget of %zu triangles were decimated by vertex clustering for this "
                      "view. All figures in the tables are from the stored meshes.",
                  tri_shown, stored, budget);
    else
        sb_printf(&b, "All %zu stored triangles shown.", stored);
    sb_put(&b, "</p>\n</section>\n");

    /* outlines */
    sb_put(&b, "<section id=\"layers\"><h2>Per-layer outlines</h2>\n");
    if (run->layer_count && run->sectors) {
        sb_put(&b, "<p class=\"note\">Damaged outline <span class=\"key\" "
                   "style=\"border-color:#b3261e\"></span> and restored outline <span "
                   "class=\"key\" style=\"border-color:#1f5fbf;border-top-style:dashed\">"
                   "</span> of one layer, in the aligned frame (mm); in a layer with a build "
                   "plan, the missing region<span class=\"swatch\"></span>, the deposit "
                   "region (allowance added) <span class=\"key\" style=\"border-color:"
                   "#8a5a00;border-top-style:dotted\"></span> and the deposition paths: "
                   "contour rings <span class=\"key\" style=\"border-color:#0b7a3e\">"
                   "</span> and raster <span class=\"key\" style=\"border-color:#6a1b9a\">"
                   "</span>.</p>\n"
                   "<p><label>Layer <select id=\"layer-select\">");
        size_t first = run->section_count ? run->sections[0].layer_first : 0;
        if (first >= run->layer_count)
            first = 0;
        for (size_t l = 0; l < run->layer_count; l++) {
            int in = 0;
            for (size_t s = 0; s < run->section_count; s++)
                if (l >= run->sections[s].layer_first && l <= run->sections[s].layer_last) {
                    in = (int)run->sections[s].index + 1;
                    break;
                }
            sb_printf(&b, "<option value=\"%zu\"%s>%zu, z %.2f mm", l, l == first ? " selected" : "",
                      l, run->layer_z[l]);
            if (in)
                sb_printf(&b, " (section %d)", in);
            sb_put(&b, "</option>");
        }
        sb_put(&b, "</select></label> <label><input type=\"checkbox\" id=\"plot-zoom\" "
                   "checked> zoom to the build plan</label></p>\n");
    } else {
        sb_put(&b, "<p class=\"note\">No per-layer outlines were stored with this run (or "
                   "they were not read).</p>\n");
    }
    sb_put(&b, "<div id=\"layer-plot\"></div>\n</section>\n");

    plan_table(&b, run, plans);
    section_table(&b, run);
    advice_table(&b, run);
    params_tables(&b, run);

    /* data */
    sb_printf(&b, "<footer class=\"note\"><p>Written by symrec %s from the catalogue's "
                  "record of run %lld.</p></footer>\n",
              run->software_version[0] ? run->software_version : "", (long long)run->id);
    sb_put(&b, "<script type=\"application/json\" id=\"report-data\">{\"run\":");
    sb_printf(&b, "%lld,\"part\":", (long long)run->id);
    sb_jstr(&b, run->part_number);
    sb_put(&b, ",\"restored\":");
    if (shown[0].tri_count) {
        sb_put(&b, "{");
        put_mesh(&b, &shown[0]);
        sb_put(&b, "}");
    } else {
        sb_put(&b, "null");
    }
    sb_put(&b, ",\"patches\":[");
    bool first_patch = true;
    for (size_t i = 1; i < nm; i++) {
        if (!shown[i].tri_count)
            continue;
        sb_printf(&b, "%s{\"section\":%zu,", first_patch ? "" : ",",
                  run->sections[i - 1].index + 1);
        put_mesh(&b, &shown[i]);
        sb_put(&b, "}");
        first_patch = false;
    }
    sb_put(&b, "],\"layers\":[");
    size_t per = 2 * run->sectors;
    for (size_t l = 0; l < run->layer_count && run->sectors; l++) {
        sb_put(&b, l ? ",{\"z\":" : "{\"z\":");
        sb_jnum(&b, run->layer_z[l], "%.4f");
        sb_put(&b, ",\"d\":");
        put_points(&b, run->damaged_xy + l * per, run->sectors);
        sb_put(&b, ",\"r\":");
        put_points(&b, run->restored_xy + l * per, run->sectors);
        sb_put(&b, "}");
    }
    sb_put(&b, "]");
    put_plans(&b, run, plans);
    sb_put(&b, "}</script>\n<script>\n");
    sb_put(&b, script);
    sb_put(&b, "</script>\n</body>\n</html>\n");

    for (size_t i = 0; i < nm; i++)
        sr_mesh_release(&shown[i]);
    free(shown);
    size_t plan_sections = 0, plan_layers = 0, replace_sections = 0;
    for (size_t i = 0; plans && i < run->section_count; i++) {
        plan_sections += plans[i].built;
        plan_layers += plans[i].built ? plans[i].plan.layer_count : 0;
        replace_sections += plans[i].replace;
    }
    plans_release(plans, run->section_count);
    if (b.failed || !b.p) {
        free(b.p);
        return sr_err_set(err, SR_E_NOMEM, "out of memory building the report");
    }
    if (info) {
        info->tri_stored = stored;
        info->tri_shown = tri_shown;
        info->decimated = decimated;
        info->plan_sections = plan_sections;
        info->plan_layers = plan_layers;
        info->replace_sections = replace_sections;
    }
    *out = b.p;
    *out_len = b.len;
    return SR_OK;
}
