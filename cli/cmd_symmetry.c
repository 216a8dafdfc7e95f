/*
 * cmd_symmetry.c: `symrec symmetry`: which symmetry a scan has (align/symmetry_fit.h),
 * fitted and printed without reconstructing or recording anything; and the one way a
 * proposal is printed, shared with `reconstruct --symmetry auto` and `run show`
 * (cli_symfit_*).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "cli.h"
#include "json_out.h"
#include "base/json_scan.h"
#include "run/run_symfit.h"

static const char usage[] =
    "usage: symrec [--db FILE] symmetry (INSTANCE | --mesh FILE [--units U]) [--json]\n"
    "\n"
    "Fits every kind of symmetry to a damaged scan and proposes the one it has, as\n"
    "'reconstruct --symmetry auto' does (nothing is reconstructed or recorded):\n"
    "continuous axial, n-fold axial with its order (2..60), mirror, and glide with\n"
    "its shift. Each kind is scored by its consistency: the share of the scan's\n"
    "surface whose image under the symmetry lies on the scan again (within a\n"
    "tolerance set by the measured noise). The highest symmetry that fits is\n"
    "proposed (a round shaft is axial, though it has mirror planes too; a gear is\n"
    "axial with its tooth count), with a confidence 0..1; when a mirror and a glide\n"
    "fit equally well it says \"ambiguous\" with both.\n"
    "\n"
    "  INSTANCE     a damaged instance id from the catalogue\n"
    "  --mesh FILE  a mesh file instead (STL, OBJ, PLY, OFF, glTF, GLB)\n"
    "  --units U    --mesh only: the unit FILE is drawn in: mm, cm, m or in (default:\n"
    "               mm for .stl .obj .ply .off, m for .gltf .glb)\n"
    "  --json       one JSON object: source and the fit (proposal, ambiguous,\n"
    "               alternative, confidence, consistency per kind, order_found,\n"
    "               glide_shift_found_mm, noise_mm, tolerance_mm, seconds, summary)\n"
    "\n"
    "Lengths in mm, time in s.\n";

/* The "summary" member of a fit's JSON object (run_symfit.h) into buf ("" if none). */
static void summary_of(const char *key, size_t key_len, const char *val, const char *end,
                       void *user)
{
    char *buf = user;
    if (key_len != 7 || strncmp(key, "summary", 7) != 0 || *val != '"' || end - val < 2)
        return;
    size_t n = (size_t)(end - val - 2);
    if (n > 511)
        n = 511;
    memcpy(buf, val + 1, n);
    buf[n] = '\0';
}

void cli_symfit_print_line(const char *label, const char *fit_json)
{
    char buf[512] = "";
    if (!fit_json)
        return;
    sr_json_for_members(fit_json, summary_of, buf);
    printf("%s%s\n", label, buf);
}

void cli_symfit_json(json_out *j, const char *fit_json)
{
    if (fit_json)
        json_raw(j, fit_json);
    else
        json_null(j);
}

sr_status cli_symfit_run(const sr_mesh *scan, sr_symmetry_fit *fit, char **fit_json, sr_err *err)
{
    sr_status st = sr_symmetry_propose(scan, fit, err);
    if (st == SR_OK)
        st = sr_symfit_json(fit, fit_json, err);
    return st;
}

bool cli_symfit_auto(const sr_mesh *scan, const char *source, sr_symmetry *sym, char **fit_json)
{
    cli_note("fitting the symmetry of %s (%zu triangles)...", cli_tx(source), scan->tri_count);
    sr_symmetry_fit fit;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = cli_symfit_run(scan, &fit, fit_json, &err);
    if (st != SR_OK) {
        cli_fail(st, &err);
        return false;
    }
    *sym = fit.proposal;
    char line[512];
    sr_symfit_summary(&fit, line, sizeof line);
    cli_note("symmetry proposed: %s", line);
    return true;
}

static void print_human(const char *source, const sr_symmetry_fit *f)
{
    char a[64], b[64];
    printf("symmetry of %s\n", cli_tx(source));
    if (f->ambiguous)
        printf("  proposal:    ambiguous: %s or %s (the first is used by reconstruct)\n",
               sr_symfit_sym_str(&f->proposal, a, sizeof a),
               sr_symfit_sym_str(&f->alternative, b, sizeof b));
    else
        printf("  proposal:    %s\n", sr_symfit_sym_str(&f->proposal, a, sizeof a));
    printf("  confidence:  %.2f\n", f->confidence);
    printf("  consistency: share of the surface whose image lies on the scan (0..1)\n");
    printf("    axial, continuous  %.3f\n", f->fig[SR_SYMFIT_ROUND].consistency);
    if (f->fig[SR_SYMFIT_NFOLD].fitted)
        printf("    axial, %d-fold%*s %.3f\n", f->order, f->order < 10 ? 5 : 4, "",
               f->fig[SR_SYMFIT_NFOLD].consistency);
    else
        printf("    axial, n-fold      -     (no order 2..60 found)\n");
    printf("    mirror             %.3f\n", f->fig[SR_SYMFIT_MIRROR].consistency);
    if (f->glide_shift_mm > 0)
        printf("    glide              %.3f (shift %.2f mm)\n", f->fig[SR_SYMFIT_GLIDE].consistency,
               f->glide_shift_mm);
    else
        printf("    glide              %.3f (no shift found: a mirror)\n",
               f->fig[SR_SYMFIT_GLIDE].consistency);
    printf("  noise %.3f mm, tolerance %.3f mm, %zu samples, %.2f s\n", f->noise_mm, f->tol_mm,
           f->samples, f->seconds);
}

int cmd_symmetry(const cli_ctx *ctx, int argc, char **argv)
{
    const char *mesh_file = NULL, *units = NULL;
    bool json = false;
    const cli_opt opts[] = {{"--mesh", &mesh_file, NULL},
                            {"--units", &units, NULL},
                            {"--json", NULL, &json},
                            {NULL, NULL, NULL}};
    const cli_spec spec = {"symmetry", usage, opts, 0, 1, "INSTANCE"};
    const char *pos[1];
    int npos = 0, rc;
    if (!cli_parse(&spec, argc - 1, argv + 1, pos, &npos, &rc))
        return rc;
    if ((npos == 1) == (mesh_file != NULL))
        return cli_usage_error("'symmetry' needs an INSTANCE id or --mesh FILE, not both "
                               "(see 'symrec symmetry --help')");
    int64_t id = 0;
    if (!mesh_file && !cli_parse_id("INSTANCE", pos[0], &id))
        return CLI_USAGE;
    if (units && !mesh_file)
        return cli_usage_error("--units applies to --mesh FILE only (a stored scan is in mm)");
    sr_unit unit;
    if (!cli_parse_units("--units", units, &unit))
        return CLI_USAGE;
    sr_mesh scan;
    sr_mesh_init(&scan);
    sr_err err;
    sr_err_clear(&err);
    sr_status st;
    char source[4200];
    if (mesh_file) {
        st = cli_mesh_read(mesh_file, unit, &scan, NULL, &err);
        snprintf(source, sizeof source, "'%s'", mesh_file);
    } else {
        sr_catalog *cat = NULL;
        if (!cli_open(ctx, CLI_READ, "read the instance", &cat))
            return CLI_FAIL;
        sr_instance_info inst;
        st = sr_catalog_instance_get(cat, id, &inst, &err);
        if (st == SR_OK)
            st = sr_catalog_instance_mesh(cat, id, &scan, &err);
        if (st == SR_OK)
            snprintf(source, sizeof source, "instance %lld (part %s, serial %s)", (long long)id,
                     inst.part_number, inst.serial[0] ? inst.serial : "-");
        sr_catalog_close(cat);
    }
    if (st != SR_OK) {
        sr_mesh_release(&scan);
        return cli_fail(st, &err);
    }
    cli_note("fitting the symmetry of %s (%zu triangles)...", cli_tx(source), scan.tri_count);
    sr_symmetry_fit fit;
    char *fit_json = NULL;
    st = cli_symfit_run(&scan, &fit, &fit_json, &err);
    sr_mesh_release(&scan);
    if (st != SR_OK)
        return cli_fail(st, &err);
    rc = CLI_OK;
    if (json) {
        json_out j;
        json_init(&j, stdout);
        json_object_begin(&j);
        json_key(&j, "source");
        json_string(&j, mesh_file ? mesh_file : source);
        json_key(&j, "instance_id");
        if (mesh_file)
            json_null(&j);
        else
            json_int(&j, id);
        json_key(&j, "symmetry_fit");
        cli_symfit_json(&j, fit_json);
        json_object_end(&j);
        rc = json_finish(&j);
    } else {
        print_human(source, &fit);
    }
    free(fit_json);
    return rc;
}
