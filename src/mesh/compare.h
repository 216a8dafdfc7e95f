/*
 * compare.h: how far one mesh is from another, so a user (and the accuracy tests and
 * the bench) can check a restoration against a reference part: both volumes and their
 * difference, and the surface deviation both ways (boolean.h's sr_mesh_deviation: the
 * distance from sample points of one surface to the nearest point of the other) with
 * the (sampled) Hausdorff distance, the larger of the two maxima.
 *
 * Sampling: by default the samples of a surface are its vertices and triangle
 * centroids (what sr_mesh_deviation takes). A maximum between samples is missed, so
 * the figures are lower bounds of the true maxima; opts.samples asks for at least that
 * many samples per surface, spread by area (each triangle cut into k x k similar
 * triangles, k from its share of the area), which tightens them.
 */
#ifndef SR_COMPARE_H
#define SR_COMPARE_H

#include <stddef.h>

#include "bridge/boolean.h"
#include "mesh/mesh.h"
#include "base/status.h"

typedef struct sr_compare_opts {
    size_t samples;             /* at least this many samples per surface (up to
                                 * SR_COMPARE_MAX_SAMPLES); 0 = vertices + centroids */
} sr_compare_opts;

#define SR_COMPARE_MAX_SAMPLES ((size_t)20000000)

typedef struct sr_compare_result {
    double volume_a_mm3, volume_b_mm3;  /* enclosed volumes (meaningful when closed) */
    double area_a_mm2, area_b_mm2;
    int closed_a, closed_b;             /* sr_mesh_is_closed */
    double volume_diff_mm3;             /* volume_b - volume_a */
    double volume_diff_pct;             /* 100 * diff / |volume_a|; NaN when volume_a is 0 */
    sr_deviation a_to_b;                /* samples on a, distances to b's surface */
    sr_deviation b_to_a;                /* samples on b, distances to a's surface */
    double hausdorff_mm;                /* max(a_to_b.max_mm, b_to_a.max_mm) */
} sr_compare_result;

/* Compares a with b. a_what/b_what name them in messages (NULL: "first mesh",
 * "second mesh"). opts may be NULL (defaults). SR_E_INVALID when a mesh fails
 * sr_mesh_validate or has no triangle of non-zero area, SR_E_RANGE for opts.samples
 * above SR_COMPARE_MAX_SAMPLES, SR_E_NOMEM. *out only on success. */
sr_status sr_compare_meshes(const sr_mesh *a, const char *a_what, const sr_mesh *b,
                            const char *b_what, const sr_compare_opts *opts,
                            sr_compare_result *out, sr_err *err);

#endif
