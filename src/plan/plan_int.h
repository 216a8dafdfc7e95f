/*
 * plan_int.h: the private interface between the files that implement plan.h. Not for
 * use outside src/plan/ (plan_export.c needs none of it).
 *
 *   plan.c        options, the missing and deposit regions per layer, the plan and its
 *                 figures (sr_plan_build)
 *   plan_paths.c  the tool paths of one layer's deposit region: contour rings, rasters
 */
#ifndef SR_PLAN_INT_H
#define SR_PLAN_INT_H

#include <stddef.h>

#include "plan/plan.h"

#define PI 3.14159265358979323846

/* ---- tool paths (plan_paths.c) ---- */

/* A growable list of polylines, each with its kind (SR_PLAN_PATH_*); zeroed is empty. */
typedef struct pathbuf {
    double *xy;
    size_t n, cap;            /* points */
    size_t *start;            /* count + 1 entries once anything is added */
    unsigned char *kind;
    size_t count, scap;       /* polylines */
} pathbuf;

/* Frees b's arrays and zeroes it. */
void pathbuf_release(pathbuf *b);
/* Moves the polylines into an sr_poly2 and a kind array (b emptied; both empty, kind
 * NULL, when b holds none). */
void pathbuf_take(pathbuf *b, sr_poly2 *paths, unsigned char **kind);
/* Length of the polyline of n points xy (interleaved x, y). */
double pl_polyline_length(const double *xy, size_t n);
/* Appends to b all paths of one layer's deposit region g, in deposition order, by
 * o->pattern and o->step_over_mm, the raster at angle_deg (none when g is empty).
 * SR_E_NOMEM, SR_E_RANGE (too many raster lines), or a polygon error. */
sr_status pl_layer_paths(const sr_plan_opts *o, const sr_poly2 *g, double angle_deg,
                         pathbuf *b, sr_err *err);

#endif
