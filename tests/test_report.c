/*
 * test_report.c: the HTML report of a run (src/report/report_html.h). A synthetic run (two
 * sections with known figures, one with a patch mesh, advice whose reason holds HTML
 * metacharacters, 3 layers x 8 sectors of outlines, a restored box) is stored in a
 * fresh catalogue and read back whole, then the page is checked: the section figures
 * and classes in the feature table, the advice text escaped, the parameters,
 * alignment and timings, balanced structure, nothing that reaches the network, and
 * the decimation of meshes over the display budget. The feature and advice cells are
 * read as figures with units and lists, never JSON; the compact outlines and meshes of
 * the data block are decoded here in C (the format of src/report/report_data.c) and
 * compared with the run's; three.js is in the page once.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "catalog/catalog.h"
#include "bridge/polygon.h"
#include "catalog/catalog_runs.h"
#include "inspect/inspect.h"
#include "plan/plan.h"
#include "report/report_html.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/json_query.h"
#include "support/synth_run.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    sr_catalog *cat;
    int64_t instance;
} fixture;

static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    assert_non_null(fx);
    assert_int_equal(tmpdir_make(&fx->dir), 0);
    char db[TMPDIR_PATH_MAX];
    tmpdir_join(&fx->dir, "cat.db", db);
    sr_err err = {{0}};
    assert_int_equal(sr_catalog_open(db, SR_CATALOG_CREATE, &fx->cat, &err), SR_OK);
    sr_mesh m = {0};
    assert_int_equal(sr_shape_cylinder(10, 0, 20, 16, &m, &err), SR_OK);
    sr_part_new part = {.number = "P<1>&\"x\"", .name = "shaft", .material = "42CrMo4",
                        .mesh = &m};
    int64_t id;
    assert_int_equal(sr_catalog_part_add(fx->cat, &part, &id, &err), SR_OK);
    sr_instance_new inst = {.part = "P<1>&\"x\"", .mesh = &m, .serial = "SN-1"};
    assert_int_equal(sr_catalog_instance_add(fx->cat, &inst, &fx->instance, &err), SR_OK);
    sr_mesh_release(&m);
    *state = fx;
    return 0;
}

static int teardown(void **state)
{
    fixture *fx = *state;
    sr_catalog_close(fx->cat);
    tmpdir_remove(&fx->dir);
    free(fx);
    return 0;
}

static void box(double at, double size, sr_mesh *out)
{
    double lo[3] = {at, at, at}, hi[3] = {at + size, at + size, at + size};
    sr_err err = {{0}};
    assert_int_equal(sr_shape_box(lo, hi, out, &err), SR_OK);
}

#define LAYERS 3
#define SECTORS 8

/* Stores the synthetic run, the first section's features and advice details as given,
 * and reads it back whole into *out. */
static void stored_run_with(fixture *fx, const char *features, const char *details, sr_run *out)
{
    sr_run r;
    memset(&r, 0, sizeof r);
    r.instance_id = fx->instance;
    r.symmetry = (sr_symmetry){SR_SYM_AXIAL, 0, 0};
    r.params = (sr_params){"coarse", LAYERS, SECTORS, 0.9, 0.8, 0.07, 0.2, 1.5, ""};
    snprintf(r.method, sizeof r.method, "robust");
    r.has_alignment = 1;
    for (int i = 0; i < 12; i++)
        r.alignment[i] = (i % 5 == 0) ? 1.0 : 0.0;
    r.alignment[3] = -12.5;
    r.fit_quality = 0.875;
    r.ok = 1;
    snprintf(r.started_at, sizeof r.started_at, "2024-03-01T10:00:00Z");
    snprintf(r.finished_at, sizeof r.finished_at, "2024-03-01T10:00:02Z");
    r.timings_json = "{\"align\":0.5,\"total\":1.25}";
    double z[LAYERS], dam[LAYERS * SECTORS * 2], res[LAYERS * SECTORS * 2];
    for (int l = 0; l < LAYERS; l++) {
        z[l] = 2.0 + 4.0 * l;
        for (int k = 0; k < SECTORS; k++) {
            double a = 2 * 3.14159265358979 * k / SECTORS;
            res[2 * (l * SECTORS + k)] = 10 * cos(a);
            res[2 * (l * SECTORS + k) + 1] = 10 * sin(a);
            dam[2 * (l * SECTORS + k)] = (k == 2 ? 7 : 10) * cos(a);
            dam[2 * (l * SECTORS + k) + 1] = (k == 2 ? 7 : 10) * sin(a);
        }
    }
    dam[2 * 5] = dam[2 * 5 + 1] = NAN;
    r.layer_count = LAYERS;
    r.sectors = SECTORS;
    r.layer_z = z;
    r.damaged_xy = dam;
    r.restored_xy = res;
    sr_run_section sec[2];
    memset(sec, 0, sizeof sec);
    sec[0].index = 0;
    sec[0].layer_first = 0;
    sec[0].layer_last = 2;
    sec[0].z_min_mm = 0.25;
    sec[0].z_max_mm = 11.75;
    sec[0].has_angles = 1;
    sec[0].angle_from_deg = 80;
    sec[0].angle_to_deg = 100;
    sec[0].volume_mm3 = 345.6;
    sec[0].area_mm2 = 78.9;
    sec[0].depth_max_mm = 3.05;
    sec[0].depth_mean_mm = 1.5;
    snprintf(sec[0].damage_class, sizeof sec[0].damage_class, "chip");
    sec[0].features_json = (char *)features; /* stored, not changed */
    box(8, 2, &sec[0].patch);
    sec[1].index = 1;
    sec[1].layer_first = 1;
    sec[1].layer_last = 1;
    sec[1].z_min_mm = 4;
    sec[1].z_max_mm = 8;
    sec[1].side = -1;
    sec[1].volume_mm3 = 12.25;
    sec[1].area_mm2 = 6.5;
    sec[1].depth_max_mm = 0.75;
    sec[1].depth_mean_mm = 0.5;
    snprintf(sec[1].damage_class, sizeof sec[1].damage_class, "gouge");
    r.sections = sec;
    r.section_count = 2;
    sr_run_advice adv[2] = {
        {0, 0, "", "spray_forming", "fill <b>chip</b> & machine \"flush\"", NULL},
        {-1, 0, "", "inspect", "check runout", NULL},
    };
    adv[0].details_json = (char *)details;
    r.advice = adv;
    r.advice_count = 2;
    box(-10, 20, &r.restored);
    sr_err err = {{0}};
    int64_t id;
    if (sr_catalog_run_add(fx->cat, &r, &id, &err) != SR_OK)
        fail_msg("run add: %s", err.msg);
    sr_mesh_release(&sec[0].patch);
    sr_mesh_release(&r.restored);
    if (sr_catalog_run_get(fx->cat, id, SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS, out, &err) !=
        SR_OK)
        fail_msg("run get: %s", err.msg);
}

/* The synthetic run with small features and details texts. */
static void stored_run(fixture *fx, sr_run *out)
{
    stored_run_with(fx, "{\"location\":\"shoulder <A>\"}",
                    "{\"rules_fired\":[\"spray-small-chip\"],\"layers\":12}", out);
}

static size_t count_of(const char *hay, const char *needle)
{
    size_t n = 0, len = strlen(needle);
    for (const char *p = strstr(hay, needle); p; p = strstr(p + len, needle))
        n++;
    return n;
}

static char *data_block(const char *html);

static char *build(const sr_run *r, size_t budget, sr_report_info *info)
{
    sr_report_opts o = {.max_triangles = budget};
    char *html = NULL;
    size_t len = 0;
    sr_err err = {{0}};
    if (sr_report_html(r, &o, &html, &len, info, &err) != SR_OK)
        fail_msg("report: %s", err.msg);
    assert_int_equal(strlen(html), len);
    return html;
}

static void report_shows_the_section_figures_in_the_feature_table(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *html = build(&r, 0, NULL);
    const char *table = strstr(html, "<table id=\"feature-table\">");
    assert_non_null(table);
    const char *end = strstr(table, "</table>");
    assert_non_null(end);
    size_t n = (size_t)(end - table);
    char *t = strndup(table, n);
    assert_int_equal(count_of(t, "<tr class=\"section\""), 2);
    /* section 1: chip, layers 0-2, z 0.25..11.75, 80..100 deg, depth 3.05/1.50,
     * volume 345.6, area 78.9; section 2: gouge on side -1 */
    assert_non_null(strstr(t, "<td>chip</td>"));
    assert_non_null(strstr(t, ">0.25<"));
    assert_non_null(strstr(t, ">11.75<"));
    assert_non_null(strstr(t, "80.0° to 100.0° (20.0° arc)"));
    assert_non_null(strstr(t, ">3.05<"));
    assert_non_null(strstr(t, ">1.50<"));
    assert_non_null(strstr(t, ">345.6<"));
    assert_non_null(strstr(t, ">78.9<"));
    assert_non_null(strstr(t, "<td>gouge</td>"));
    assert_non_null(strstr(t, "side -1 of the plane"));
    assert_non_null(strstr(t, ">12.2<")); /* 12.25 is exact in binary: %.1f rounds to even */
    /* the features text, escaped */
    assert_non_null(strstr(t, "shoulder &lt;A&gt;"));
    free(t);
    free(html);
    sr_run_release(&r);
}

/* A nominal record set on the stored run (as reconstruct makes one): the table, the
 * flag escaped, what only the nominal sees; none without it. */
static void report_shows_symmetry_vs_nominal(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *html = build(&r, 0, NULL);
    assert_null(strstr(html, "id=\"nominal\""));
    free(html);
    sr_run_nominal *n = calloc(1, sizeof *n);
    sr_run_nominal_section *secs = calloc(2, sizeof *secs);
    sr_run_nominal_piece *pieces = calloc(1, sizeof *pieces);
    assert_true(n && secs && pieces);
    strcpy(n->reference, "symmetry");
    n->coverage = 0.5;
    n->nominal_mm3 = 400;
    n->symmetry_mm3 = 357.85;
    n->diff_mm3 = 42.15;
    n->diff_pct = 10.5375;
    n->min_volume_mm3 = 1;
    n->poor = 1;
    strcpy(n->note, "the nominal model does not fit <this> scan");
    secs[0] = (sr_run_nominal_section){0, 345.6, 380, 34.4, 9.05, 0.125, 0.75, 1};
    secs[1] = (sr_run_nominal_section){1, 12.25, 0, -12.25, -100, -1, -1, 0};
    pieces[0] = (sr_run_nominal_piece){400, 2, 0, 20, {1, 2, 3}};
    n->sections = secs;
    n->section_count = 2;
    n->pieces = pieces;
    n->piece_count = 1;
    r.nominal = n;
    html = build(&r, 0, NULL);
    const char *t = strstr(html, "<section id=\"nominal\">");
    assert_non_null(t);
    assert_non_null(strstr(t, "Missing by the nominal 400.0 mm³, by the symmetry 357.9 mm³: "
                              "disagreement +42.1 mm³ (+10.5 %)"));
    assert_non_null(strstr(t, "the nominal model does not fit &lt;this&gt; scan"));
    assert_non_null(strstr(t, "<td class=\"n\">345.6</td><td class=\"n\">380.0</td>"
                              "<td class=\"n\">+34.4</td><td class=\"n\">+9.1</td>"
                              "<td>0.125 / 0.750</td>"));
    assert_non_null(strstr(t, "only the symmetry sees it"));
    assert_non_null(strstr(t, "Only the nominal sees 20.0 mm³ around (1.0, 2.0, 3.0) mm"));
    free(html);
    sr_run_release(&r);
}

static void report_escapes_advice_and_names(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *html = build(&r, 0, NULL);
    assert_non_null(strstr(html, "fill &lt;b&gt;chip&lt;/b&gt; &amp; machine &quot;flush&quot;"));
    assert_null(strstr(html, "<b>chip"));
    assert_non_null(strstr(html, "<td>spray_forming</td>"));
    assert_non_null(strstr(html, "spray-small-chip"));
    assert_non_null(strstr(html, "<td>whole part</td>"));
    /* the part number in the title and the data block, never raw */
    assert_non_null(strstr(html, "part P&lt;1&gt;&amp;&quot;x&quot;</title>"));
    assert_non_null(strstr(html, "\"part\":\"P\\u003c1\\u003e\\u0026\\\"x\\\"\""));
    assert_null(strstr(html, "P<1>"));
    free(html);
    sr_run_release(&r);
}

/* The page without the embedded three.js (its <script id="three-js"> element), malloc'd;
 * the library's own text is checked apart (it names XML namespaces, not addresses). */
static char *page_without_three(const char *html)
{
    const char *open = "<script id=\"three-js\">";
    const char *a = strstr(html, open);
    assert_non_null(a);
    const char *e = strstr(a, "</script>");
    assert_non_null(e);
    e += strlen("</script>");
    size_t n = (size_t)(a - html), m = strlen(e);
    char *out = malloc(n + m + 1);
    assert_non_null(out);
    memcpy(out, html, n);
    memcpy(out + n, e, m + 1);
    return out;
}

static void report_is_self_contained_and_balanced(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *whole = build(&r, 0, NULL);
    char *html = page_without_three(whole);
    assert_int_equal(strncmp(html, "<!DOCTYPE html>\n<html lang=\"en\">", 31), 0);
    size_t len = strlen(html);
    assert_string_equal(html + len - 8, "</html>\n");
    assert_null(strstr(html, "http://"));
    assert_null(strstr(html, "https://"));
    assert_null(strstr(html, "<link"));
    assert_null(strstr(html, " src="));
    assert_null(strstr(html, "url("));
    assert_null(strstr(html, "import "));
    static const char *const tags[] = {"table", "section", "script", "style", "select",
                                       "thead", "tbody",   "code",   "p",     "ul",
                                       "ol",    "li",      "div"};
    for (size_t i = 0; i < sizeof tags / sizeof tags[0]; i++) {
        char open1[32], open2[32], close[32];
        snprintf(open1, sizeof open1, "<%s>", tags[i]);
        snprintf(open2, sizeof open2, "<%s ", tags[i]);
        snprintf(close, sizeof close, "</%s>", tags[i]);
        size_t o = count_of(html, open1) + count_of(html, open2), c = count_of(html, close);
        if (o != c)
            fail_msg("<%s>: %zu opened, %zu closed", tags[i], o, c);
    }
    assert_int_equal(count_of(html, "<script"), 2);
    assert_int_equal(count_of(whole, "<script"), 3);
    assert_int_equal(count_of(html, "<canvas id=\"view\""), 1);
    free(html);
    free(whole);
    sr_run_release(&r);
}

static void report_embeds_three_js_once_and_a_fallback_without_webgl(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *html = build(&r, 0, NULL);
    const char *lib = strstr(html, "<script id=\"three-js\">");
    assert_non_null(lib);
    assert_int_equal(count_of(html, "<script id=\"three-js\">"), 1);
    /* three.js itself (Debian libjs-three's three.min.js), whole: its revision, its
     * renderer, and the element closed only after it */
    const char *end = strstr(lib, "</script>");
    assert_non_null(end);
    assert_true(end - lib > 500000);
    char *text = strndup(lib, (size_t)(end - lib));
    assert_non_null(strstr(text, "REVISION=\""));
    assert_non_null(strstr(text, "WebGLRenderer"));
    free(text);
    /* the view's script after it, and the note shown without WebGL */
    assert_non_null(strstr(end, "new T.WebGLRenderer("));
    assert_non_null(strstr(html, "<p id=\"view-fallback\" hidden>The 3D view needs WebGL"));
    free(html);
    sr_run_release(&r);
}

static void report_shows_parameters_alignment_timings_and_layers(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *html = build(&r, 0, NULL);
    assert_non_null(strstr(html, "<tr><th>parameter set</th><td>coarse</td></tr>"));
    assert_non_null(strstr(html, "<tr><th>sectors</th><td class=\"n\">8</td></tr>"));
    assert_non_null(strstr(html, "<td class=\"n\">-12.500000</td>"));
    assert_non_null(strstr(html, "Fit quality: 0.875"));
    assert_non_null(strstr(html, "<tr><th>align</th><td class=\"n\">0.500</td></tr>"));
    assert_non_null(strstr(html, "<tr><th>total</th><td class=\"n\">1.250</td></tr>"));
    /* one option per layer, the first section's first layer selected */
    assert_int_equal(count_of(html, "<option value="), LAYERS);
    assert_non_null(strstr(html, "<option value=\"0\" selected>0, z 2.00 mm (section 1)"));
    /* the data block: 3 layers (decoded in outlines_round_trip) */
    char *json = data_block(html);
    assert_int_equal(jq_len(json, "$.layers.z"), LAYERS);
    assert_near(jq_num(json, "$.layers.n"), SECTORS, 0);
    free(json);
    /* the restored box and one patch, all shown */
    assert_non_null(strstr(html, "All 24 stored triangles shown."));
    assert_int_equal(count_of(html, "{\"section\":1,\"volume_mm3\":345.6,\"mesh\":{"), 1);
    free(html);
    sr_run_release(&r);
}

static void report_decimates_meshes_over_the_budget_and_says_so(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    sr_mesh_release(&r.restored);
    sr_err err = {{0}};
    assert_int_equal(sr_shape_cylinder(10, 0, 20, 400, &r.restored, &err), SR_OK);
    size_t stored = r.restored.tri_count + 12;
    sr_report_info info;
    char *html = build(&r, 200, &info);
    assert_int_equal(info.tri_stored, stored);
    assert_true(info.decimated);
    assert_true(info.tri_shown <= 200);
    assert_true(info.tri_shown >= 20);
    char note[160];
    snprintf(note, sizeof note, "Shown with %zu of the %zu stored triangles", info.tri_shown,
             stored);
    assert_non_null(strstr(html, note));
    free(html);
    sr_run_release(&r);
}

static void decimate_keeps_a_small_mesh_and_reduces_a_large_one(void **state)
{
    (void)state;
    sr_err err = {{0}};
    sr_mesh big = {0}, out = {0};
    assert_int_equal(sr_shape_cylinder(5, 0, 50, 2000, &big, &err), SR_OK);
    assert_int_equal(sr_report_decimate(&big, big.tri_count, &out, &err), SR_OK);
    assert_int_equal(out.tri_count, big.tri_count);
    assert_memory_equal(out.xyz, big.xyz, 3 * big.vertex_count * sizeof(double));
    sr_mesh_release(&out);
    assert_int_equal(sr_report_decimate(&big, 1000, &out, &err), SR_OK);
    assert_true(out.tri_count <= 1000 && out.tri_count > 100);
    for (size_t t = 0; t < out.tri_count; t++) {
        uint32_t a = out.tri[3 * t], b = out.tri[3 * t + 1], c = out.tri[3 * t + 2];
        assert_true(a < out.vertex_count && b < out.vertex_count && c < out.vertex_count);
        assert_true(a != b && b != c && a != c);
    }
    /* every vertex stays inside the cylinder's bounding box */
    for (size_t i = 0; i < out.vertex_count; i++) {
        assert_true(fabs(out.xyz[3 * i]) <= 5 + 1e-9 && fabs(out.xyz[3 * i + 1]) <= 5 + 1e-9);
        assert_true(out.xyz[3 * i + 2] >= -1e-9 && out.xyz[3 * i + 2] <= 50 + 1e-9);
    }
    sr_mesh_release(&out);
    sr_mesh_release(&big);
}

static void report_of_a_failed_run_without_meshes(void **state)
{
    fixture *fx = *state;
    sr_run w;
    memset(&w, 0, sizeof w);
    w.instance_id = fx->instance;
    w.symmetry = (sr_symmetry){SR_SYM_MIRROR, 0, 0};
    w.params = (sr_params){"default", 10, 12, 0.9, 0.8, 0.07, 0.2, 1.5, ""};
    snprintf(w.method, sizeof w.method, "paper");
    w.fit_quality = -1;
    snprintf(w.error, sizeof w.error, "cannot align 'scan' <no area>");
    sr_err err = {{0}};
    int64_t id;
    assert_int_equal(sr_catalog_run_add(fx->cat, &w, &id, &err), SR_OK);
    sr_run r;
    assert_int_equal(sr_catalog_run_get(fx->cat, id, SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS,
                                        &r, &err),
                     SR_OK);
    char *html = build(&r, 0, NULL);
    assert_non_null(strstr(html, "<strong class=\"failed\">failed</strong>: cannot align "
                              "&#39;scan&#39; &lt;no area&gt;"));
    assert_non_null(strstr(html, "No meshes were stored with this run"));
    assert_non_null(strstr(html, "No missing section was found"));
    assert_non_null(strstr(html, "The run did not reach the alignment."));
    assert_null(strstr(html, "feature-table"));
    free(html);
    sr_run_release(&r);
}

/* ---- build plans and tool paths ---- */

/* A shaft r = 20 (10 layers 1 mm apart, 72 sectors of 5 degrees) with a chip 2 mm
 * deep in layers 2..7, sectors 2..9 (10..50 degrees), as tests/test_plan.c's, made by
 * tests/support/synth_run.c, stored with the advice `process` for the chip and read
 * back whole (layers included, or not: `what`). */
static void chipped_shaft_run(fixture *fx, const char *process, unsigned what, sr_run *out)
{
    sr_run r;
    synth_run_make(&r, 10, 72, 20, 20, 0);
    sr_run_section *sec = synth_run_dig(&r, 2, 7, 2, 8, 2.0, 0);
    snprintf(sec->damage_class, sizeof sec->damage_class, "chip");
    r.instance_id = fx->instance;
    r.params = (sr_params){"coarse", 10, 72, 0.9, 0.8, 0.07, 0.2, 1.5, ""};
    r.fit_quality = -1;
    sr_run_advice adv = {0, 0, "", "", "because", NULL};
    snprintf(adv.process, sizeof adv.process, "%s", process);
    r.advice = &adv;
    r.advice_count = 1;
    sr_err err = {{0}};
    int64_t id;
    if (sr_catalog_run_add(fx->cat, &r, &id, &err) != SR_OK)
        fail_msg("run add: %s", err.msg);
    r.advice = NULL;
    r.advice_count = 0;
    synth_run_free(&r);
    if (sr_catalog_run_get(fx->cat, id, what, out, &err) != SR_OK)
        fail_msg("run get: %s", err.msg);
}

/* The page's JSON data block, malloc'd. */
static char *data_block(const char *html)
{
    const char *open = "<script type=\"application/json\" id=\"report-data\">";
    const char *p = strstr(html, open);
    assert_non_null(p);
    p += strlen(open);
    const char *end = strstr(p, "</script>");
    assert_non_null(end);
    char *json = strndup(p, (size_t)(end - p));
    assert_non_null(json);
    assert_true(jq_valid(json));
    return json;
}

/* Reads the numbers of a JSON array of numbers ("[1.5,-2,...]") into xy (cap doubles);
 * returns how many. */
static size_t read_numbers(const char *text, double *xy, size_t cap)
{
    assert_non_null(text);
    const char *p = text;
    assert_int_equal(*p, '[');
    p++;
    size_t n = 0;
    while (*p && *p != ']') {
        char *end;
        double v = strtod(p, &end);
        assert_true(end > p);
        assert_true(n < cap);
        xy[n++] = v;
        p = end;
        if (*p == ',')
            p++;
    }
    assert_int_equal(*p, ']');
    return n;
}

/* A region from the data block ("[[x,y,...],[...]]" at path). */
static void read_region(const char *json, const char *path, sr_poly2 *out)
{
    sr_poly2_init(out);
    long n = jq_len(json, path);
    assert_true(n >= 0);
    static double xy[20000];
    for (long c = 0; c < n; c++) {
        char sub[200];
        snprintf(sub, sizeof sub, "%s[%ld]", path, c);
        char *text = jq_text(json, sub);
        size_t k = read_numbers(text, xy, sizeof xy / sizeof xy[0]);
        free(text);
        assert_int_equal(k % 2, 0);
        assert_int_equal(sr_poly2_add_contour(out, xy, k / 2, NULL), SR_OK);
    }
}

/* The damaged outline of run layer l as a region. */
static void damaged_region(const sr_run *r, size_t l, sr_poly2 *out)
{
    sr_poly2_init(out);
    assert_int_equal(sr_poly2_add_contour(out, r->damaged_xy + 2 * l * r->sectors, r->sectors,
                                          NULL),
                     SR_OK);
}

static void report_carries_the_tool_paths_of_every_planned_layer(void **state)
{
    fixture *fx = *state;
    sr_run r;
    chipped_shaft_run(fx, "spray_forming", SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS, &r);
    /* the plan `symrec plan` would make: default settings */
    sr_plan plan;
    sr_err err = {{0}};
    assert_int_equal(sr_plan_build(&r, 0, NULL, &plan, &err), SR_OK);
    assert_int_equal(plan.layer_count, 6); /* run layers 2..7, one plan layer each */
    sr_report_info info;
    char *html = build(&r, 0, &info);
    assert_int_equal(info.plan_sections, 1);
    assert_int_equal(info.plan_layers, 6);
    assert_int_equal(info.replace_sections, 0);
    /* the plan table row: 6 layers of 1 mm */
    assert_non_null(strstr(html, "<table id=\"plan-table\">"));
    assert_non_null(strstr(html, "<td>spray_forming</td><td class=\"n\">6</td>"
                                 "<td class=\"n\">1.000</td>"));
    char *json = data_block(html);
    assert_int_equal(jq_len(json, "$.plans"), 1);
    assert_near(jq_num(json, "$.plans[0].section"), 1, 0);
    assert_int_equal(jq_len(json, "$.plans[0].layers"), 6);
    double allowance = jq_num(json, "$.plans[0].allowance_mm");
    assert_near(allowance, 0.5, 0);
    size_t points = 0, rings = 0, rasters = 0;
    static double xy[20000];
    for (size_t k = 0; k < plan.layer_count; k++) {
        const sr_plan_layer *L = &plan.layers[k];
        char path[160];
        snprintf(path, sizeof path, "$.plans[0].layers[%zu].rf", k);
        assert_near(jq_num(json, path), (double)L->run_layer_first, 0);
        snprintf(path, sizeof path, "$.plans[0].layers[%zu].rl", k);
        assert_near(jq_num(json, path), (double)L->run_layer_last, 0);
        snprintf(path, sizeof path, "$.plans[0].layers[%zu].z", k);
        assert_near(jq_num(json, path), L->z_top_mm, 1e-5);
        /* the missing region as the page carries it: the plan's, to the grid */
        sr_poly2 missing, grown;
        snprintf(path, sizeof path, "$.plans[0].layers[%zu].m", k);
        read_region(json, path, &missing);
        assert_near(sr_poly2_area(&missing), L->missing_area_mm2, 1e-6);
        assert_true(L->missing_area_mm2 > 10);
        sr_poly2_init(&grown);
        assert_int_equal(sr_poly2_offset(&missing, allowance, 1, &grown, NULL), SR_OK);
        sr_poly2 dam;
        damaged_region(&r, L->run_layer_first, &dam);
        /* the paths: as many as planned, of the planned kinds and lengths, every point
         * inside the missing region grown by the allowance and never inside the part */
        snprintf(path, sizeof path, "$.plans[0].layers[%zu].paths", k);
        assert_int_equal(jq_len(json, path), (long)L->paths.contour_count);
        assert_true(L->paths.contour_count > 0);
        for (size_t c = 0; c < L->paths.contour_count; c++) {
            snprintf(path, sizeof path, "$.plans[0].layers[%zu].paths[%zu].k", k, c);
            assert_near(jq_num(json, path), L->path_kind[c], 0);
            rings += L->path_kind[c] == SR_PLAN_PATH_RING;
            rasters += L->path_kind[c] == SR_PLAN_PATH_RASTER;
            snprintf(path, sizeof path, "$.plans[0].layers[%zu].paths[%zu].p", k, c);
            char *text = jq_text(json, path);
            size_t n = read_numbers(text, xy, sizeof xy / sizeof xy[0]);
            free(text);
            assert_int_equal(n, 2 * (L->paths.start[c + 1] - L->paths.start[c]));
            for (size_t i = 0; i < n; i += 2) {
                assert_near(xy[i], L->paths.xy[2 * L->paths.start[c] + i], 1e-5);
                if (sr_poly2_contains(&grown, xy[i], xy[i + 1]) == 0)
                    fail_msg("layer %zu path %zu point (%g, %g) outside the missing region "
                             "grown by %g mm", k, c, xy[i], xy[i + 1], allowance);
                assert_int_not_equal(sr_poly2_contains(&dam, xy[i], xy[i + 1]), 1);
                points++;
            }
        }
        sr_poly2_release(&dam);
        sr_poly2_release(&grown);
        sr_poly2_release(&missing);
    }
    assert_true(points > 100);
    assert_true(rings >= 6);  /* contour+raster: a ring per layer at least */
    assert_true(rasters > 0);
    /* the plot draws them: the script knows the plan layers and both kinds of path */
    assert_non_null(strstr(html, "function planLayers(i)"));
    assert_non_null(strstr(html, "'tp ring':'tp raster'"));
    free(json);
    free(html);
    sr_plan_release(&plan);
    sr_run_release(&r);
}

static void report_of_a_replace_run_says_there_is_no_build_plan(void **state)
{
    fixture *fx = *state;
    sr_run r;
    chipped_shaft_run(fx, "replace", SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS, &r);
    sr_report_info info;
    char *html = build(&r, 0, &info);
    assert_int_equal(info.plan_sections, 0);
    assert_int_equal(info.plan_layers, 0);
    assert_int_equal(info.replace_sections, 1);
    assert_non_null(strstr(html, "<p id=\"no-plan\">No build plan: the advice is to replace "
                                 "the part (beyond repair).</p>"));
    assert_null(strstr(html, "plan-table"));
    char *json = data_block(html);
    assert_int_equal(jq_len(json, "$.plans"), 1);
    char *rep = jq_text(json, "$.plans[0].replace");
    assert_string_equal(rep, "1");
    free(rep);
    assert_int_equal(jq_len(json, "$.plans[0].layers"), 0);
    free(json);
    free(html);
    sr_run_release(&r);
}

static void a_section_without_a_plan_says_why(void **state)
{
    fixture *fx = *state;
    sr_run r;
    /* read without the layer polylines: the plan module refuses, the page says why */
    chipped_shaft_run(fx, "ded", SR_RUN_WITH_MESHES, &r);
    sr_report_info info;
    char *html = build(&r, 0, &info);
    assert_int_equal(info.plan_sections, 0);
    assert_int_equal(info.replace_sections, 0);
    char want[128];
    snprintf(want, sizeof want, "<td colspan=\"7\">No build plan: run %lld has no layer polylines",
             (long long)r.id);
    assert_non_null(strstr(html, want));
    char *json = data_block(html);
    char *why = jq_text(json, "$.plans[0].why");
    assert_non_null(why);
    assert_non_null(strstr(why, "has no layer polylines"));
    free(why);
    free(json);
    free(html);
    sr_run_release(&r);
}

/* ---- readable cells ---- */

/* A section's features and an advice's details as the demo's run stores them (shortened),
 * with a member no table knows, a yes, an unknown and an escaped degree sign. */
static const char demo_features[] =
    "{\"class\":\"chip\",\"layers\":{\"first\":160,\"last\":204,\"count\":45},"
    "\"z_min_mm\":50.0001,\"z_max_mm\":63.9987,\"depth_max_mm\":6.002,"
    "\"height_mm\":13.99862804557371,\"part_fraction\":0.008816033369990591,"
    "\"local_radius_mm\":29.999938776559762,\"aspect\":2.917473127849353,\"cells\":2215,"
    "\"location\":\"shoulder\",\"locations\":[\"shoulder\"],\"surface\":\"outer\","
    "\"reasons\":[\"shoulder: the restored radius steps by 15 mm beside the loss\","
    "\"chip: 40.8 mm long by 14 mm, 6 mm deep at 80\\u00b0 <x>\"],"
    "\"new_gap_mm2\":2.5,\"flag\":true,\"nothing\":null}";
static const char demo_details[] =
    "{\"applied\":\"shoulder-ded\",\"rules_fired\":[\"shoulder-ded\",\"ded-medium-depth\","
    "\"catch-all-review\"],\"rules_blocked\":[{\"rule\":\"spray-small\",\"why\":\"depth "
    "6 mm > 2 mm\"}],\"rules_unevaluated\":[{\"rule\":\"hard-alloy\",\"scope\":\"section\","
    "\"why\":\"the part has no material family\",\"outranks_applied\":true}],"
    "\"parameters\":{\"layer_mm\":0.8,\"step_over_mm\":1.2,\"allowance_mm\":0.8,"
    "\"deposition_rate_g_min\":10,\"efficiency\":0.8},\"class\":\"chip\","
    "\"material\":\"42CrMo4\",\"density_g_cm3\":7.85,\"missing_mass_g\":9.722449295845495,"
    "\"lost_fraction\":0.008816033369990591,\"preheat_c\":250}";

/* The text of an HTML fragment: tags dropped, the five entities decoded; malloc'd. */
static char *text_of(const char *html, size_t n)
{
    char *out = malloc(n + 1);
    assert_non_null(out);
    size_t o = 0;
    static const char *const ent[][2] = {
        {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}, {"&quot;", "\""}, {"&#39;", "'"}};
    for (size_t i = 0; i < n; i++) {
        if (html[i] == '<') {
            while (i < n && html[i] != '>')
                i++;
            continue;
        }
        bool done = false;
        for (size_t e = 0; e < 5 && !done; e++) {
            size_t el = strlen(ent[e][0]);
            if (i + el <= n && strncmp(html + i, ent[e][0], el) == 0) {
                out[o++] = ent[e][1][0];
                i += el - 1;
                done = true;
            }
        }
        if (!done)
            out[o++] = html[i];
    }
    out[o] = '\0';
    return out;
}

/* The text of the element that starts at the first `open` in html (up to `close`). */
static char *text_at(const char *html, const char *open, const char *close)
{
    const char *a = strstr(html, open);
    if (!a)
        fail_msg("no '%s' in the page", open);
    const char *e = strstr(a, close);
    assert_non_null(e);
    return text_of(a, (size_t)(e - a));
}

static void feature_and_advice_cells_read_as_figures_with_units(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run_with(fx, demo_features, demo_details, &r);
    char *html = build(&r, 0, NULL);
    char *f = text_at(html, "<tr class=\"section\" id=\"section-1\">", "</tr>");
    static const char *const want_f[] = {
        "at the shoulder",
        "height 14 mm",
        "share of the part's volume 0.882 %",
        "local radius 30 mm",
        "length / breadth 2.92",
        "grid cells 2215",
        "surface outer",
        "new gap 2.5 mm²",
        "flag yes",
        "nothing unknown",
        "why this class:",
        "shoulder: the restored radius steps by 15 mm beside the loss",
        "6 mm deep at 80° <x>"};
    for (size_t i = 0; i < sizeof want_f / sizeof want_f[0]; i++)
        if (!strstr(f, want_f[i]))
            fail_msg("feature cell: no '%s' in '%s'", want_f[i], f);
    /* the figures in their own columns are not repeated, and no key shows */
    assert_null(strstr(f, "z min"));
    assert_null(strstr(f, "_mm"));
    /* the reasons as a list, the markup escaped */
    assert_non_null(strstr(html, "<li>shoulder: the restored radius steps by 15 mm beside "
                                 "the loss</li>"));
    assert_non_null(strstr(html, "at 80° &lt;x&gt;</li>"));
    char *a = text_at(html, "<tr class=\"advice\">", "</tr>");
    static const char *const want_a[] = {
        "process parameters: layer 0.8 mm, step-over 1.2 mm, allowance 0.8 mm, "
        "deposition rate 10 g/min, efficiency 80 %",
        "rules fired:shoulder-ded (applied)ded-medium-depthcatch-all-review",
        "rules passed over:spray-small: depth 6 mm > 2 mm",
        "rules not evaluated:hard-alloy: the part has no material family (scope section, "
        "outranks applied yes)",
        "class chip",
        "material 42CrMo4",
        "density 7.85 g/cm³",
        "missing mass 9.72 g",
        "lost share of the part 0.882 %",
        "preheat 250 °C"};
    for (size_t i = 0; i < sizeof want_a / sizeof want_a[0]; i++)
        if (!strstr(a, want_a[i]))
            fail_msg("advice cell: no '%s' in '%s'", want_a[i], a);
    /* the rules fired as an ordered list */
    assert_non_null(strstr(html, "<ol><li>shoulder-ded <em>(applied)</em></li>"
                                 "<li>ded-medium-depth</li><li>catch-all-review</li></ol>"));
    free(a);
    free(f);
    free(html);
    sr_run_release(&r);
}

static void no_table_cell_shows_json(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run_with(fx, demo_features, demo_details, &r);
    char *html = build(&r, 0, NULL);
    size_t cells = 0;
    for (const char *p = strstr(html, "<td"); p; p = strstr(p + 1, "<td")) {
        const char *e = strstr(p, "</td>");
        assert_non_null(e);
        char *t = text_of(p, (size_t)(e - p));
        if (strstr(t, "{\"") || strstr(t, "\":") || strstr(t, "[\"") || strstr(t, "<code>"))
            fail_msg("a table cell shows JSON: '%s'", t);
        free(t);
        cells++;
    }
    assert_true(cells > 40);
    assert_null(strstr(html, "&quot;:"));
    /* the texts stay in the data block for scripts, as stored */
    char *json = data_block(html);
    assert_near(jq_num(json, "$.sections[0].features.height_mm"), 13.99862804557371, 1e-12);
    char *reason = jq_text(json, "$.sections[0].features.reasons[1]");
    assert_string_equal(reason, "chip: 40.8 mm long by 14 mm, 6 mm deep at 80° <x>");
    free(reason);
    assert_near(jq_num(json, "$.advice[0].details.parameters.step_over_mm"), 1.2, 0);
    assert_true(jq_has(json, "$.advice[0].details.rules_fired", "catch-all-review"));
    assert_true(isnan(jq_num(json, "$.advice[1].section")));
    free(json);
    free(html);
    sr_run_release(&r);
}

/* ---- compact data ---- */

/* base64 text (n characters) into bytes; returns how many. */
static size_t unbase64(const char *s, size_t n, unsigned char *out, size_t cap)
{
    size_t o = 0;
    uint32_t acc = 0;
    int bits = 0;
    for (size_t i = 0; i < n && s[i] != '='; i++) {
        const char *abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char *c = strchr(abc, s[i]);
        assert_non_null(c);
        acc = (acc << 6) | (uint32_t)(c - abc);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            assert_true(o < cap);
            out[o++] = (unsigned char)(acc >> bits);
        }
    }
    return o;
}

/* A string member at path of the data block, base64-decoded (malloc'd, *n bytes). */
static unsigned char *b64_member(const char *json, const char *path, size_t *n)
{
    char *text = jq_text(json, path);
    assert_non_null(text);
    size_t len = strlen(text);
    unsigned char *out = malloc(len + 1);
    assert_non_null(out);
    *n = unbase64(text, len, out, len + 1);
    free(text);
    return out;
}

typedef struct dpt {
    long long x, y;
    bool present;
} dpt;

/* Decodes the "layers" member (report_data.c's format) into xy (layers x 2 outlines,
 * restored then damaged, x n points, NaN for a missing one). */
static void decode_outlines(const char *json, size_t layers, size_t n, double *rest_xy,
                            double *dam_xy)
{
    size_t len;
    unsigned char *p = b64_member(json, "$.layers.enc", &len);
    double q = jq_num(json, "$.layers.q");
    assert_near(q, 0.001, 0);
    size_t pos = 0, run = 0;
    dpt *below = calloc(n, sizeof *below), *rest = calloc(n, sizeof *rest);
    assert_true(below && rest);
#define VARINT(v)                                                                                  \
    do {                                                                                           \
        unsigned long long v_ = 0;                                                                 \
        int sh_ = 0;                                                                               \
        unsigned char c_;                                                                          \
        do {                                                                                       \
            assert_true(pos < len);                                                                \
            c_ = p[pos++];                                                                         \
            v_ |= (unsigned long long)(c_ & 127) << sh_;                                           \
            sh_ += 7;                                                                              \
        } while (c_ & 128);                                                                        \
        (v) = v_;                                                                                  \
    } while (0)
    for (size_t l = 0; l < layers; l++)
        for (int kind = 0; kind < 2; kind++) {
            dpt last = {0, 0, false};
            double *xy = (kind ? dam_xy : rest_xy) + 2 * n * l;
            for (size_t k = 0; k < n; k++) {
                dpt ref = kind ? rest[k] : (l ? below[k] : (dpt){0, 0, false});
                dpt pred = ref.present ? ref : last;
                if (!pred.present)
                    pred.x = pred.y = 0;
                dpt pt = {pred.x, pred.y, true};
                if (run) {
                    run--;
                } else {
                    unsigned long long t, u;
                    VARINT(t);
                    if (t == 0) {
                        pt.present = false;
                    } else if (t == 1) {
                        VARINT(u);
                        run = (size_t)u;
                    } else {
                        t -= 2;
                        VARINT(u);
                        pt.x += t & 1 ? -(long long)((t + 1) / 2) : (long long)(t / 2);
                        pt.y += u & 1 ? -(long long)((u + 1) / 2) : (long long)(u / 2);
                    }
                }
                if (pt.present)
                    last = pt;
                if (!kind)
                    rest[k] = pt;
                xy[2 * k] = pt.present ? (double)pt.x * q : NAN;
                xy[2 * k + 1] = pt.present ? (double)pt.y * q : NAN;
            }
            if (kind == 1)
                memcpy(below, rest, n * sizeof *below);
        }
#undef VARINT
    assert_int_equal(pos, len); /* every byte used */
    assert_int_equal(run, 0);
    free(below);
    free(rest);
    free(p);
}

/* The outlines of r through the page and back: every point within half the quantum,
 * every missing point missing. Returns the encoded text's length. */
static size_t outlines_round_trip(const sr_run *r)
{
    char *html = build(r, 0, NULL);
    char *json = data_block(html);
    size_t n = r->sectors, L = r->layer_count;
    assert_int_equal(jq_len(json, "$.layers.z"), (long)L);
    double *rest = malloc(2 * n * L * sizeof *rest), *dam = malloc(2 * n * L * sizeof *dam);
    assert_true(rest && dam);
    decode_outlines(json, L, n, rest, dam);
    for (size_t i = 0; i < 2 * n * L; i++) {
        double want[2] = {r->restored_xy[i], r->damaged_xy[i]}, got[2] = {rest[i], dam[i]};
        for (int k = 0; k < 2; k++) {
            /* a point with one coordinate missing is missing */
            size_t pair = i & ~(size_t)1;
            const double *w = k ? r->damaged_xy : r->restored_xy;
            bool missing = isnan(w[pair]) || isnan(w[pair + 1]);
            if (missing)
                assert_true(isnan(got[k]));
            else if (!(fabs(got[k] - want[k]) <= 0.0005 + 1e-12))
                fail_msg("outline value %zu (%s): %.6f, stored %.6f", i, k ? "damaged" : "restored",
                         got[k], want[k]);
        }
    }
    char *enc = jq_text(json, "$.layers.enc");
    size_t len = strlen(enc);
    free(enc);
    free(rest);
    free(dam);
    free(json);
    free(html);
    return len;
}

static void outlines_are_compact_and_decode_to_the_run_s(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r); /* 3 x 8, a missing point */
    outlines_round_trip(&r);
    sr_run_release(&r);
    chipped_shaft_run(fx, "ded", SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS, &r);
    assert_int_equal(r.layer_count * r.sectors, 720);
    size_t len = outlines_round_trip(&r);
    /* 2 x 720 points: as decimal text ("-12.3456," twice) about 26 kB; encoded, the
     * layers that repeat the one below and the damaged points on the restored cost a
     * byte a run */
    if (len > 1500)
        fail_msg("outlines of 2 x 720 points take %zu characters", len);
    sr_run_release(&r);
}

static void meshes_decode_to_the_shown_meshes_and_the_scan_is_offered(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    char *html = build(&r, 0, NULL);
    char *json = data_block(html);
    size_t n;
    unsigned char *v = b64_member(json, "$.restored.v", &n);
    assert_int_equal(n, 3 * r.restored.vertex_count * 4);
    assert_near(jq_num(json, "$.restored.nv"), (double)r.restored.vertex_count, 0);
    for (size_t i = 0; i < 3 * r.restored.vertex_count; i++) {
        float f;
        memcpy(&f, v + 4 * i, 4); /* little-endian, as the machine running the tests */
        assert_near(f, r.restored.xyz[i], 1e-5);
    }
    free(v);
    unsigned char *t = b64_member(json, "$.restored.t", &n);
    assert_int_equal(n, 3 * r.restored.tri_count * 4);
    assert_memory_equal(t, r.restored.tri, n);
    free(t);
    assert_near(jq_num(json, "$.patches[0].mesh.nt"), 12, 0);
    assert_null(jq_text(json, "$.scan"));
    assert_null(strstr(html, "id=\"show-scan\""));
    free(json);
    free(html);
    /* with the scan: a mesh of its own, its checkbox off at first */
    sr_mesh scan = {0};
    box(-10, 20, &scan);
    sr_report_opts o = {.scan = &scan};
    size_t len;
    sr_err err = {{0}};
    sr_report_info info;
    assert_int_equal(sr_report_html(&r, &o, &html, &len, &info, &err), SR_OK);
    assert_int_equal(info.tri_stored, 24); /* the scan is not the run's */
    json = data_block(html);
    assert_near(jq_num(json, "$.scan.nt"), 12, 0);
    assert_non_null(strstr(html, "<input type=\"checkbox\" id=\"show-scan\"> scan</label>"));
    free(json);
    free(html);
    sr_mesh_release(&scan);
    /* a large scan is cut to a quarter of the budget; the run's meshes keep theirs */
    assert_int_equal(sr_shape_cylinder(10, 0, 20, 400, &scan, &err), SR_OK);
    assert_true(scan.tri_count > 400);
    o.max_triangles = 400;
    assert_int_equal(sr_report_html(&r, &o, &html, &len, &info, &err), SR_OK);
    assert_false(info.decimated);
    assert_int_equal(info.tri_shown, 24);
    json = data_block(html);
    double scan_shown = jq_num(json, "$.scan.nt");
    assert_true(scan_shown >= 20 && scan_shown <= 100);
    free(json);
    free(html);
    sr_mesh_release(&scan);
    sr_run_release(&r);
}

/* The inspection section (issue 20): the restored box's copy 0.5 mm along +x as the
 * scan after repair; its deviations by sr_inspect_deviations are known (+0.5 on the
 * four corners outside, 0 on the four still on the box's y and z faces), carried in
 * the data block as given, with the scale (range max(2 x 0.8, 5 x 0.1) = 1.6 mm), the
 * legend's ticks and band and one table row per section. */
static void report_shows_the_inspection_with_its_deviations(void **state)
{
    fixture *fx = *state;
    sr_run r;
    stored_run(fx, &r);
    sr_mesh scan = {0};
    assert_int_equal(sr_mesh_copy(&scan, &r.restored), SR_OK);
    assert_int_equal(scan.vertex_count, 8);
    const double shift[12] = {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0};
    sr_mesh_transform(&scan, shift);
    double dev[8];
    sr_err err = {{0}};
    assert_int_equal(sr_inspect_deviations(&r.restored, &scan, dev, &err), SR_OK);
    double lo[3], hi[3];
    sr_mesh_bbox(&r.restored, lo, hi);
    for (size_t v = 0; v < 8; v++)
        assert_near(dev[v], scan.xyz[3 * v] > hi[0] ? 0.5 : 0.0, 1e-9);
    sr_inspect_section sec = {.index = 0, .underfill_mm3 = 12.5, .verdict = SR_INSPECT_REWORK};
    snprintf(sec.reasons, sizeof sec.reasons, "under-fill <12.5> mm3");
    sr_report_inspection ins = {.id = 7,
                                .inspected_at = "2024-03-02T09:00:00Z",
                                .verdict = "rework",
                                .reasons = "section 1: rework",
                                .tolerance_mm = 0.1,
                                .allowance_mm = 0.8,
                                .sections = &sec,
                                .section_count = 1,
                                .scan = &scan,
                                .deviation = dev};
    sr_report_opts o = {.inspection = &ins};
    char *html = NULL;
    size_t len;
    assert_int_equal(sr_report_html(&r, &o, &html, &len, NULL, &err), SR_OK);
    assert_int_equal(count_of(html, "<tr class=\"inspection\">"), 1);
    assert_non_null(strstr(html, "<td>rework</td><td class=\"n\">12.5</td>"));
    assert_non_null(strstr(html, "under-fill &lt;12.5&gt; mm3"));
    assert_non_null(strstr(html, "<canvas id=\"inspect-view\""));
    assert_non_null(strstr(html, "<span class=\"tick\" style=\"left:46.88%\">-0.10</span>"));
    assert_non_null(strstr(html, "<span class=\"tick\" style=\"left:100.00%\">+1.60</span>"));
    assert_non_null(strstr(html, "id=\"inspect-band\" class=\"scale-band\" "
                                 "style=\"left:46.88%;width:6.25%\""));
    char *json = data_block(html);
    assert_near(jq_num(json, "$.inspection.range_mm"), 1.6, 1e-12);
    assert_near(jq_num(json, "$.inspection.stops[1][0]"), -0.1, 1e-12);
    assert_near(jq_num(json, "$.inspection.scan.nv"), 8, 0);
    size_t n;
    unsigned char *d = b64_member(json, "$.inspection.deviation", &n);
    assert_int_equal(n, 8 * 4);
    for (size_t v = 0; v < 8; v++) {
        float f;
        memcpy(&f, d + 4 * v, 4);
        assert_near(f, dev[v], 1e-7);
    }
    free(d);
    free(json);
    free(html);
    /* without the scan: the figures only */
    ins.scan = NULL;
    assert_int_equal(sr_report_html(&r, &o, &html, &len, NULL, &err), SR_OK);
    assert_null(strstr(html, "<canvas id=\"inspect-view\""));
    assert_int_equal(count_of(html, "<tr class=\"inspection\">"), 1);
    json = data_block(html);
    assert_null(jq_text(json, "$.inspection.scan"));
    free(json);
    free(html);
    /* no inspection, no section */
    html = build(&r, 0, NULL);
    assert_null(strstr(html, "id=\"inspection\""));
    free(html);
    sr_mesh_release(&scan);
    sr_run_release(&r);
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(report_shows_the_section_figures_in_the_feature_table),
        T(report_escapes_advice_and_names),
        T(report_is_self_contained_and_balanced),
        T(report_embeds_three_js_once_and_a_fallback_without_webgl),
        T(feature_and_advice_cells_read_as_figures_with_units),
        T(no_table_cell_shows_json),
        T(outlines_are_compact_and_decode_to_the_run_s),
        T(meshes_decode_to_the_shown_meshes_and_the_scan_is_offered),
        T(report_shows_parameters_alignment_timings_and_layers),
        T(report_decimates_meshes_over_the_budget_and_says_so),
        cmocka_unit_test(decimate_keeps_a_small_mesh_and_reduces_a_large_one),
        T(report_of_a_failed_run_without_meshes),
        T(report_shows_symmetry_vs_nominal),
        T(report_carries_the_tool_paths_of_every_planned_layer),
        T(report_of_a_replace_run_says_there_is_no_build_plan),
        T(a_section_without_a_plan_says_why),
        T(report_shows_the_inspection_with_its_deviations),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
