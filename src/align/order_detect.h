/*
 * order_detect.h: the order of an axial part's cyclic symmetry found from its aligned
 * layers (`reconstruct --order auto`): a gear's tooth count, a hex nut's 6, or 0 for a
 * part that is round (continuous axial symmetry).
 *
 * On the sector grid of the aligned part (slice.h: per layer and sector the farthest
 * distance from the axis) a part with n-fold symmetry matches itself turned by 360/n
 * degrees. For a turn by t sectors (fractional turns read between sectors linearly), a
 * layer's mismatch is the mean of |r(k) - r(k + t)| over its sectors, leaving out the
 * largest eighth (damage, a key, a stray triangle touch only a few sectors); the
 * part's mismatch at that turn is the median over the layers whose every sector holds
 * a surface point. Turns by 0.1373, 0.2719 and 0.3819 of a circle, which no order up to
 * 360 repeats, give the part's base mismatch:
 *  - base mismatch <= tolerance: round, order 0 (turned by anything it matches);
 *  - else, with best = the least mismatch over the turns by 360/n, n = 2..min(360,
 *    sectors / 2): no order when best > tolerance (no rotational symmetry found; the
 *    caller says so), else the largest n whose mismatch is within accept = max(2 best,
 *    tolerance / 4) while its turn by half the period, 180/n degrees, mismatches by
 *    more than max(4 accept, tolerance) (any smooth profile matches itself turned by
 *    a sector or two; a real period's half does not: a tooth onto a gap);
 * A divisor of the order matches as well (a 20-tooth gear matches by 36 degrees), and
 * a neighbour of the order does not (turned 360/n(n+1) degrees too far: on the posed
 * gear 0.30 mm at 21 against 3e-5 mm at 20), so the largest matching n is the order.
 * The grid must resolve one period: sectors >= 2 n.
 */
#ifndef SR_ORDER_DETECT_H
#define SR_ORDER_DETECT_H

#include "slice/slice.h"
#include "base/status.h"

typedef struct sr_order_detection {
    int order;              /* 0 = continuous (round, or no order found) */
    int round;              /* 1: the base mismatch is within the tolerance */
    double mismatch_mm;     /* the part's mismatch at 360/order degrees (order > 0) */
    double base_mm;         /* the base mismatch (turns no order repeats) */
    size_t layers_used;     /* layers with a surface point in every sector */
} sr_order_detection;

/* Finds the order from `grid` (the aligned part's sector grid). tolerance_mm > 0: the
 * mismatch a matching turn may keep (scan noise and facets; reconstruct.c uses
 * max(0.05 mm, 4 x the scan's noise)). SR_E_RANGE for a bad tolerance or a grid of
 * fewer than 4 sectors; SR_E_INVALID when no layer has a point in every sector; SR_E_NOMEM.
 * *out only on success. */
sr_status sr_order_detect(const sr_layer_grid *grid, double tolerance_mm,
                          sr_order_detection *out, sr_err *err);

#endif
