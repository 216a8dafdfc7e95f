/*
 * symmetry.c: names, parsing and checks of symmetry kinds (see symmetry.h).
 */
#include "base/symmetry.h"

#include <math.h>
#include <string.h>

static const char *const kind_names[] = {"none", "axial", "mirror", "glide"};

const char *sr_sym_kind_name(sr_sym_kind kind)
{
    if ((unsigned)kind > SR_SYM_GLIDE)
        return "none";
    return kind_names[kind];
}

sr_status sr_sym_kind_parse(const char *text, const char *field, sr_sym_kind *out, sr_err *err)
{
    for (int k = SR_SYM_AXIAL; k <= SR_SYM_GLIDE; k++) {
        if (text && strcmp(text, kind_names[k]) == 0) {
            *out = (sr_sym_kind)k;
            return SR_OK;
        }
    }
    return sr_err_set(err, SR_E_RANGE, "bad %s '%s': expected axial, mirror or glide",
                      field, text ? text : "");
}

sr_status sr_symmetry_check(const sr_symmetry *sym, sr_err *err)
{
    if (sym->kind < SR_SYM_AXIAL || sym->kind > SR_SYM_GLIDE)
        return sr_err_set(err, SR_E_RANGE, "bad symmetry kind %d", (int)sym->kind);
    if (sym->order != 0 && (sym->order < 2 || sym->order > 360))
        return sr_err_set(err, SR_E_RANGE, "bad order %d: expected 0 (continuous) or 2..360",
                          sym->order);
    if (!isfinite(sym->shift_mm) || sym->shift_mm < 0)
        return sr_err_set(err, SR_E_RANGE, "bad shift %g mm: expected a finite value >= 0",
                          sym->shift_mm);
    return SR_OK;
}
