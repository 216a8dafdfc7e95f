/*
 * run_symfit.h: a symmetry proposal (align/symmetry_fit.h) as the run record keeps it
 * and the CLI prints it: one JSON object (the proposal, the alternative when
 * ambiguous, the confidence, the consistency of every kind, the measured noise and
 * tolerance, a one-line summary) and that summary line alone. No I/O.
 *
 * The object:
 *   {"proposal": {"kind": "axial", "order": 20} | {"kind": "glide", "shift_mm": 10} | ...,
 *    "ambiguous": false, "alternative": null | {...}, "confidence": 0.97,
 *    "consistency": {"axial": 0.42, "axial_nfold": 0.99 | null, "mirror": 1.0,
 *                    "glide": 0.35},
 *    "order_found": 20, "glide_shift_found_mm": 7.67,
 *    "noise_mm": 0.005, "tolerance_mm": 0.21, "samples": 3000, "seconds": 1.7,
 *    "summary": "axial 20-fold, confidence 0.97 (consistency ...)"}
 */
#ifndef SR_RUN_SYMFIT_H
#define SR_RUN_SYMFIT_H

#include <stddef.h>

#include "align/symmetry_fit.h"
#include "base/status.h"

/* "axial, continuous", "axial, 20-fold", "mirror", "glide, shift 10 mm". */
const char *sr_symfit_sym_str(const sr_symmetry *sym, char *buf, size_t size);

/* One line: the proposal (or "ambiguous: A or B"), the confidence, the consistency of
 * each kind. */
void sr_symfit_summary(const sr_symmetry_fit *f, char *buf, size_t size);

/* The JSON object above into *out (malloc'd; free it). SR_E_NOMEM. */
sr_status sr_symfit_json(const sr_symmetry_fit *f, char **out, sr_err *err);

#endif
