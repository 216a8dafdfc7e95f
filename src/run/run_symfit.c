/*
 * run_symfit.c: a symmetry proposal as JSON and as one summary line (run_symfit.h).
 */
#include "run/run_symfit.h"

#include <stdio.h>

#include "base/jsonbuf.h"

const char *sr_symfit_sym_str(const sr_symmetry *sym, char *buf, size_t size)
{
    if (sym->kind == SR_SYM_AXIAL && sym->order == 0)
        snprintf(buf, size, "axial, continuous");
    else if (sym->kind == SR_SYM_AXIAL)
        snprintf(buf, size, "axial, %d-fold", sym->order);
    else if (sym->kind == SR_SYM_GLIDE)
        snprintf(buf, size, "glide, shift %.2f mm", sym->shift_mm);
    else
        snprintf(buf, size, "%s", sr_sym_kind_name(sym->kind));
    return buf;
}

void sr_symfit_summary(const sr_symmetry_fit *f, char *buf, size_t size)
{
    char a[64], b[64], nf[48] = "";
    sr_symfit_sym_str(&f->proposal, a, sizeof a);
    if (f->fig[SR_SYMFIT_NFOLD].fitted)
        snprintf(nf, sizeof nf, ", %d-fold %.3f", f->order, f->fig[SR_SYMFIT_NFOLD].consistency);
    char figs[200];
    snprintf(figs, sizeof figs, "consistency axial %.3f%s, mirror %.3f, glide %.3f",
             f->fig[SR_SYMFIT_ROUND].consistency, nf, f->fig[SR_SYMFIT_MIRROR].consistency,
             f->fig[SR_SYMFIT_GLIDE].consistency);
    if (f->ambiguous)
        snprintf(buf, size, "ambiguous: %s or %s, confidence %.2f (%s)", a,
                 sr_symfit_sym_str(&f->alternative, b, sizeof b), f->confidence, figs);
    else
        snprintf(buf, size, "%s, confidence %.2f (%s)", a, f->confidence, figs);
}

static void sym_json(sr_jsonbuf *jb, const sr_symmetry *sym)
{
    if (sym->kind == SR_SYM_NONE) {
        sr_jsonbuf_null(jb);
        return;
    }
    sr_jsonbuf_object_begin(jb);
    sr_jsonbuf_key(jb, "kind");
    sr_jsonbuf_string(jb, sr_sym_kind_name(sym->kind));
    if (sym->kind == SR_SYM_AXIAL) {
        sr_jsonbuf_key(jb, "order"); /* 0 = continuous */
        sr_jsonbuf_int(jb, sym->order);
    }
    if (sym->kind == SR_SYM_GLIDE) {
        sr_jsonbuf_key(jb, "shift_mm");
        sr_jsonbuf_number(jb, sym->shift_mm);
    }
    sr_jsonbuf_object_end(jb);
}

sr_status sr_symfit_json(const sr_symmetry_fit *f, char **out, sr_err *err)
{
    static const char *const keys[SR_SYMFIT_COUNT] = {"axial", "axial_nfold", "mirror", "glide"};
    sr_jsonbuf jb;
    sr_jsonbuf_init(&jb);
    sr_jsonbuf_object_begin(&jb);
    sr_jsonbuf_key(&jb, "proposal");
    sym_json(&jb, &f->proposal);
    sr_jsonbuf_key(&jb, "ambiguous");
    sr_jsonbuf_bool(&jb, f->ambiguous != 0);
    sr_jsonbuf_key(&jb, "alternative");
    sym_json(&jb, &f->alternative);
    sr_jsonbuf_key(&jb, "confidence");
    sr_jsonbuf_number(&jb, f->confidence);
    sr_jsonbuf_key(&jb, "consistency");
    sr_jsonbuf_object_begin(&jb);
    for (int c = 0; c < SR_SYMFIT_COUNT; c++) {
        sr_jsonbuf_key(&jb, keys[c]);
        if (f->fig[c].fitted)
            sr_jsonbuf_number(&jb, f->fig[c].consistency);
        else
            sr_jsonbuf_null(&jb);
    }
    sr_jsonbuf_object_end(&jb);
    sr_jsonbuf_key(&jb, "order_found");
    sr_jsonbuf_int(&jb, f->order);
    sr_jsonbuf_key(&jb, "glide_shift_found_mm");
    sr_jsonbuf_number(&jb, f->glide_shift_mm);
    sr_jsonbuf_key(&jb, "noise_mm");
    sr_jsonbuf_number(&jb, f->noise_mm);
    sr_jsonbuf_key(&jb, "tolerance_mm");
    sr_jsonbuf_number(&jb, f->tol_mm);
    sr_jsonbuf_key(&jb, "samples");
    sr_jsonbuf_int(&jb, (int64_t)f->samples);
    sr_jsonbuf_key(&jb, "seconds");
    sr_jsonbuf_number(&jb, f->seconds);
    char line[512];
    sr_symfit_summary(f, line, sizeof line);
    sr_jsonbuf_key(&jb, "summary");
    sr_jsonbuf_string(&jb, line);
    sr_jsonbuf_object_end(&jb);
    return sr_jsonbuf_take(&jb, out, err);
}
