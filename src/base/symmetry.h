/*
 * symmetry.h: the kinds of symmetry a part can be restored by, as the engineer picks
 * them: axial (continuous, or n-fold cyclic with an order), planar mirror, and planar
 * glide reflection (mirror combined with a shift along the plane). Names and parsing
 * only; the geometry lives in align/axial/planar.
 */
#ifndef SR_SYMMETRY_H
#define SR_SYMMETRY_H

#include "base/status.h"

typedef enum sr_sym_kind {
    SR_SYM_NONE = 0,
    SR_SYM_AXIAL,
    SR_SYM_MIRROR,
    SR_SYM_GLIDE,
} sr_sym_kind;

/* sr_symmetry.order for sr_reconstruct only: find the axial order (order_detect.h) */
#define SR_ORDER_AUTO (-1)

typedef struct sr_symmetry {
    sr_sym_kind kind;
    int order;          /* axial: n-fold order (>= 2), 0 = continuous; unused otherwise */
    double shift_mm;    /* glide: shift along the plane, mm; 0 = find by search */
} sr_symmetry;

/* "axial", "mirror", "glide" (or "none"). */
const char *sr_sym_kind_name(sr_sym_kind kind);

/* Parses a kind name; SR_E_RANGE with a message naming `field` otherwise. */
sr_status sr_sym_kind_parse(const char *text, const char *field, sr_sym_kind *out, sr_err *err);

/* Checks a symmetry's fields (order 0 or 2..360, shift finite and >= 0). */
sr_status sr_symmetry_check(const sr_symmetry *sym, sr_err *err);

#endif
