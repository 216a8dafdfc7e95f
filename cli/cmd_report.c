/*
 * cmd_report.c: `symrec report RUN --out FILE.html`: reads run RUN whole (meshes and
 * layers) with its instance, part and the part's material (the density of the build
 * plans) and its latest inspection (the scan after repair taken into the model's frame
 * by the stored transform, reduced to the view's budget, its deviations recomputed from
 * the restored mesh: inspect.h's sr_inspect_deviations), has src/report/report_html.c
 * build the page, and writes
 * it atomically: into a temporary file beside FILE, flushed to disk, then renamed over
 * FILE, so FILE is either the old file or the whole new report, never half of one.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "catalog/catalog_inspect.h"
#include "catalog/catalog_rules.h"
#include "catalog/catalog_runs.h"
#include "cli.h"
#include "inspect/inspect.h"
#include "json_out.h"
#include "plan/plan.h"
#include "report/report_html.h"

static const char usage_report[] =
    "usage: symrec [--db FILE] report RUN --out FILE.html [--max-triangles N] [--json]\n"
    "\n"
    "Writes the report of run RUN as one self-contained HTML file that works offline\n"
    "(no network; the style, the scripts, three.js and the data are inside the file):\n"
    "the restored part with its patches highlighted and the scan in 3D (WebGL; it opens\n"
    "on the largest missing section; drag to rotate), the damaged and restored\n"
    "outline of each layer (mm, aligned frame) with the build plan drawn over it (the\n"
    "layer's missing region, deposit region and deposition paths: contour rings and\n"
    "raster), the build plan's figures per section (as 'symrec plan' makes it with its\n"
    "default settings and the density of the part's material; none for a section\n"
    "advised 'replace'), the missing sections with their features (z range mm, angles\n"
    "degrees or side, depth mm, volume mm³, area mm²), the advice with the rules that\n"
    "fired, and the run's parameters, alignment and timings. When the run was inspected\n"
    "('symrec inspect'), its latest inspection: the verdict, the scan after repair in\n"
    "3D coloured by its signed deviation from the restored model (a colour scale in mm\n"
    "with the tolerance band marked) and the figures of each section. It prints to A4\n"
    "(print it to PDF from a browser to send it).\n"
    "\n"
    "  --out FILE           the HTML file to write (replaced atomically)\n"
    "  --max-triangles N    display budget of the 3D view, the restored part and its\n"
    "                       patches together (the scan gets a quarter of it more)\n"
    "                       (default 60000; larger meshes are decimated for display)\n"
    "  --json               print {\"run\", \"out\", \"bytes\", \"triangles_stored\",\n"
    "                       \"triangles_shown\", \"decimated\", \"plan_sections\",\n"
    "                       \"plan_layers\", \"replace_sections\", \"inspection\"} (the\n"
    "                       inspection shown, null for none) instead of a sentence\n";

/* Writes data to path through a temporary file in the same folder and a rename. */
static bool write_atomic(const char *path, const char *data, size_t len)
{
    size_t n = strlen(path);
    char *tmp = malloc(n + 16);
    if (!tmp) {
        cli_error("out of memory writing '%s'", path);
        return false;
    }
    snprintf(tmp, n + 16, "%s.tmp-XXXXXX", path);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        cli_error("cannot write '%s': %s", path, strerror(errno));
        free(tmp);
        return false;
    }
    /* mkstemp makes the file 0600; give it the mode a plain fopen would */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    FILE *f = fdopen(fd, "wb");
    bool ok = f != NULL;
    if (!f)
        close(fd);
    if (ok && len && fwrite(data, 1, len, f) != len)
        ok = false;
    if (ok && fflush(f) != 0)
        ok = false;
    if (ok && fsync(fileno(f)) != 0)
        ok = false;
    int saved = errno;
    if (f && fclose(f) != 0 && ok) {
        ok = false;
        saved = errno;
    }
    if (ok && rename(tmp, path) != 0) {
        ok = false;
        saved = errno;
    }
    if (!ok) {
        unlink(tmp);
        cli_error("cannot write '%s': %s", path, strerror(saved));
    }
    free(tmp);
    return ok;
}

/* The run's latest inspection as the report shows it. */
typedef struct report_ins {
    bool found;
    sr_inspection_info info;
    sr_inspect_section *sections;
    size_t section_count;
    sr_mesh scan; /* model frame, display size */
    double *dev;
    sr_report_inspection shown;
} report_ins;

static void report_ins_release(report_ins *ri)
{
    free(ri->sections);
    sr_mesh_release(&ri->scan);
    free(ri->dev);
    memset(ri, 0, sizeof *ri);
}

/* Reads run's latest inspection with its scan (when kept) from cat; a scan that cannot
 * be read leaves the figures only. */
static sr_status load_inspection(sr_catalog *cat, const sr_run *run, report_ins *ri, sr_err *err)
{
    memset(ri, 0, sizeof *ri);
    sr_status st = sr_catalog_inspection_latest(cat, run->id, &ri->info, &ri->found, err);
    if (st == SR_OK && ri->found)
        st = sr_catalog_inspection_sections(cat, ri->info.id, &ri->sections, &ri->section_count,
                                            err);
    sr_err quiet;
    if (st == SR_OK && ri->found && ri->info.scan_mesh_id && run->restored.tri_count &&
        sr_catalog_mesh_load(cat, ri->info.scan_mesh_id, &ri->scan, &quiet) != SR_OK)
        sr_mesh_release(&ri->scan);
    return st;
}

/* The scan into the model's frame, reduced to max_tri, and its deviations; without
 * them (out of memory excepted) the page shows the figures only. */
static sr_status inspection_view(const sr_run *run, size_t max_tri, report_ins *ri, sr_err *err)
{
    if (!ri->scan.tri_count)
        return SR_OK;
    sr_mesh small = {0};
    sr_mesh_transform(&ri->scan, ri->info.transform);
    sr_status st = sr_report_decimate(&ri->scan, max_tri, &small, err);
    if (st != SR_OK)
        return st;
    sr_mesh_release(&ri->scan);
    ri->scan = small;
    ri->dev = malloc((ri->scan.vertex_count ? ri->scan.vertex_count : 1) * sizeof *ri->dev);
    if (!ri->dev)
        return sr_err_set(err, SR_E_NOMEM, "out of memory");
    sr_err quiet;
    if (sr_inspect_deviations(&run->restored, &ri->scan, ri->dev, &quiet) != SR_OK) {
        free(ri->dev);
        ri->dev = NULL;
    }
    return SR_OK;
}

int cmd_report(const cli_ctx *ctx, int argc, char **argv)
{
    const char *out = NULL, *max_tri = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--out", &out, NULL},
                            {"--max-triangles", &max_tri, NULL},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"report", usage_report, opts, 1, 1, "RUN"};
    const char *pos[1];
    int npos = 0, rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, &npos, &rc))
        return rc;
    int64_t run_id;
    if (!cli_parse_id("RUN", pos[0], &run_id))
        return CLI_USAGE;
    if (!out || !*out)
        return cli_usage_error("report needs --out FILE.html");
    /* the report is HTML: a file named .pdf (or anything else) would be lying */
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (!dot || (slash && dot < slash) ||
        (strcasecmp(dot, ".html") != 0 && strcasecmp(dot, ".htm") != 0))
        return cli_usage_error("bad --out '%s': the report is an HTML page, name it .html "
                               "(print it to PDF from a browser)",
                               out);
    int budget = 0;
    if (max_tri && !cli_parse_int("--max-triangles", max_tri, 100, 10000000,
                                  "a triangle count from 100 to 10000000", &budget))
        return CLI_USAGE;

    sr_catalog *cat;
    if (!cli_open(ctx, CLI_READ, NULL, &cat))
        return CLI_FAIL;
    sr_err err;
    sr_err_clear(&err);
    sr_run run;
    sr_status st = sr_catalog_run_get(cat, run_id, SR_RUN_WITH_MESHES | SR_RUN_WITH_LAYERS,
                                      &run, &err);
    if (st != SR_OK) {
        sr_catalog_close(cat);
        return cli_fail(st, &err);
    }
    /* the instance and part give serial, name and material; a run always has both */
    sr_instance_info inst;
    sr_part_info part;
    st = sr_catalog_instance_get(cat, run.instance_id, &inst, &err);
    if (st == SR_OK)
        st = sr_catalog_part_find(cat, run.part_number, &part, &err);
    /* the build plans as `symrec plan` makes them: default settings, the density of the
     * part's material when the catalogue knows it */
    sr_plan_opts po;
    sr_plan_opts_init(&po);
    sr_material mat;
    sr_err quiet;
    if (st == SR_OK && part.material[0] &&
        sr_catalog_material_get(cat, part.material, &mat, &quiet) == SR_OK &&
        isfinite(mat.density_g_cm3) && mat.density_g_cm3 > 0)
        po.density_g_cm3 = mat.density_g_cm3;
    /* the scan as received, for the 3D view (shown on demand); a run without one is
     * still reported */
    sr_mesh scan = {0};
    if (st == SR_OK && sr_catalog_instance_mesh(cat, run.instance_id, &scan, &quiet) != SR_OK)
        sr_mesh_release(&scan);
    report_ins ri = {0};
    if (st == SR_OK)
        st = load_inspection(cat, &run, &ri, &err);
    sr_catalog_close(cat);
    if (st == SR_OK && ri.found)
        st = inspection_view(&run, (budget ? (size_t)budget : 60000) / 4, &ri, &err);
    if (st != SR_OK) {
        report_ins_release(&ri);
        sr_mesh_release(&scan);
        sr_run_release(&run);
        return cli_fail(st, &err);
    }
    sr_report_opts ro = {.max_triangles = (size_t)budget,
                         .serial = inst.serial,
                         .received = inst.received,
                         .part_name = part.name,
                         .material = part.material,
                         .plan = &po,
                         .scan = scan.tri_count ? &scan : NULL};
    if (ri.found) {
        ri.shown = (sr_report_inspection){.id = ri.info.id,
                                          .inspected_at = ri.info.inspected_at,
                                          .verdict = ri.info.verdict,
                                          .reasons = ri.info.reasons,
                                          .tolerance_mm = ri.info.tolerance_mm,
                                          .allowance_mm = ri.info.allowance_mm,
                                          .sections = ri.sections,
                                          .section_count = ri.section_count,
                                          .scan = ri.dev ? &ri.scan : NULL,
                                          .deviation = ri.dev};
        ro.inspection = &ri.shown;
    }
    char *html = NULL;
    size_t len = 0;
    sr_report_info info;
    st = sr_report_html(&run, &ro, &html, &len, &info, &err);
    int64_t inspection_id = ri.found ? ri.info.id : 0;
    char verdict[sizeof ri.info.verdict];
    snprintf(verdict, sizeof verdict, "%s", ri.info.verdict);
    bool colours = ri.dev != NULL;
    report_ins_release(&ri);
    sr_mesh_release(&scan);
    sr_run_release(&run);
    if (st != SR_OK)
        return cli_fail(st, &err);
    bool ok = write_atomic(out, html, len);
    free(html);
    if (!ok)
        return CLI_FAIL;
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "run");
        json_int(&j, run_id);
        json_key(&j, "out");
        json_string(&j, out);
        json_key(&j, "bytes");
        json_int(&j, (int64_t)len);
        json_key(&j, "triangles_stored");
        json_int(&j, (int64_t)info.tri_stored);
        json_key(&j, "triangles_shown");
        json_int(&j, (int64_t)info.tri_shown);
        json_key(&j, "decimated");
        json_bool(&j, info.decimated != 0);
        json_key(&j, "plan_sections");
        json_int(&j, (int64_t)info.plan_sections);
        json_key(&j, "plan_layers");
        json_int(&j, (int64_t)info.plan_layers);
        json_key(&j, "replace_sections");
        json_int(&j, (int64_t)info.replace_sections);
        json_key(&j, "inspection");
        if (inspection_id)
            json_int(&j, inspection_id);
        else
            json_null(&j);
        json_object_end(&j);
        return json_finish(&j);
    } else {
        printf("report of run %lld written to %s (%zu bytes", (long long)run_id, out, len);
        if (info.decimated)
            printf("; 3D view decimated from %zu to %zu triangles", info.tri_stored,
                   info.tri_shown);
        printf(")\n");
        if (info.plan_sections)
            printf("build plan of %zu section%s, %zu layers with their tool paths\n",
                   info.plan_sections, info.plan_sections == 1 ? "" : "s", info.plan_layers);
        if (info.replace_sections)
            printf("no build plan for %zu section%s: the advice is to replace the part\n",
                   info.replace_sections, info.replace_sections == 1 ? "" : "s");
        if (inspection_id)
            printf("inspection %lld (%s) shown%s\n", (long long)inspection_id, verdict,
                   colours ? " with the scan's deviation colours" : ", figures only");
    }
    return CLI_OK;
}
