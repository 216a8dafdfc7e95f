/*
 * register.h: rigid registration of one mesh to another (a scan to a model, a restored
 * part to the catalogue part, a repaired part to its restoration), robust to what one
 * of them lacks: a damaged scan is missing up to a quarter of the part, and a repaired
 * one carries extra stock, so neither may pull the fit.
 *
 * The method (src/align/register.c):
 *   - start poses from the two surfaces' principal axes (area-weighted second moments):
 *     the four proper sign choices, each also turned about every principal axis of the
 *     fixed mesh in 30 degree steps (principal axes of a symmetric or damaged part are
 *     ambiguous, and damage moves them), plus the identity;
 *   - each start refined by a short robust ICP on a few hundred samples, the best few
 *     again on a thousand, the best of those to convergence on several thousand;
 *   - the ICP: samples of the moving surface, their closest points on the fixed one,
 *     point-to-plane residuals under Tukey biweights whose cut-off anneals towards
 *     4.685 x the robust scale of the distances (samples in the damage or the extra
 *     stock get weight 0), a damped Gauss-Newton step on a small rotation and
 *     translation.
 * The result says how well it holds: the share of the moving surface's samples within
 * tol_mm of the fixed surface (its coverage) and their RMS distance.
 */
#ifndef SR_REGISTER_H
#define SR_REGISTER_H

#include <stddef.h>

#include "base/status.h"
#include "mesh/mesh.h"

typedef struct sr_register_opts {
    double tol_mm;  /* a sample within this of the other surface counts as on it;
                              0 = 0.5 % of the fixed mesh's bounding-box diagonal */
    size_t samples; /* samples of the moving mesh in the final fit; 0 = 4000 */
} sr_register_opts;

typedef struct sr_register_result {
    double mat[12];        /* moving -> fixed: p' = M[:, :3] p + M[:, 3] (3 x 4 row-major) */
    double rotation_deg;   /* the rotation's angle */
    double translation_mm; /* |M[:, 3]| */
    double tol_mm;         /* as used */
    double coverage;       /* share of the moving samples within tol_mm of the fixed mesh */
    double rms_mm;         /* RMS distance of those samples */
    double median_mm;      /* median distance of all samples */
    size_t samples;
} sr_register_result;

/* Registers `moving` to `fixed` (validated meshes with some area). opts may be NULL.
 * SR_E_INVALID naming the mesh when one has no area; SR_E_NOMEM. */
sr_status sr_register(const sr_mesh *moving, const sr_mesh *fixed, const sr_register_opts *opts,
                      sr_register_result *out, sr_err *err);

/* As sr_register, but from the given start poses only (start: count x 12, each a 3 x 4
 * row-major moving -> fixed), for a caller that knows the pose to within a few % of the
 * size up to a few discrete choices (an alignment both meshes share, up to the signs of
 * its axes): each start gets the short robust ICP on a few hundred samples (first
 * cut-off 3 % of the fixed mesh's diagonal), the best two the medium stage, the best
 * of those the final fit. SR_E_RANGE when count is 0 or over 160; as sr_register
 * otherwise. */
sr_status sr_register_from(const sr_mesh *moving, const sr_mesh *fixed, const double *start,
                           size_t count, const sr_register_opts *opts, sr_register_result *out,
                           sr_err *err);

/* How well `moving` lies on `fixed` as they are (no registration): *out with the
 * identity, coverage, RMS and median as sr_register gives them. */
sr_status sr_register_check(const sr_mesh *moving, const sr_mesh *fixed,
                            const sr_register_opts *opts, sr_register_result *out, sr_err *err);

/* Share of the smaller of the two bounding boxes that lies inside the other (0..1). */
double sr_bbox_overlap(const sr_mesh *a, const sr_mesh *b);

#endif
