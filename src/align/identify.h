/*
 * identify.h: which of several candidate parts a scan is of, and how well it fits
 * each: the geometry of `symrec identify` (the catalogue side, which picks the
 * candidates by their shape descriptors, is src/catalog/catalog_identify.c).
 *
 * The scan is prepared once (its surface, samples and shape descriptor); each
 * candidate part's intact mesh is then registered to it by the trimmed robust
 * registration of register.h (scan = moving, part = fixed: a damaged scan is a subset
 * of the part's surface plus fracture faces, and the Tukey weights leave those out),
 * with fewer samples and steps than `compare --align` since only the ranking and a
 * transform good to the tolerance are wanted. For each fit:
 *   coverage  share of the scan's samples within tol of the part (fracture faces and
 *             a wrong part lower it);
 *   inside    share of the scan's samples farther than tol but inside the part's solid
 *             (fracture faces: the scan of a broken part lies on or in its part);
 *   rms_mm    RMS distance of those samples;
 *   lacking   share of the part's samples farther than tol from the scan: what the
 *             scan lacks of the part (the damage, up to about a quarter; a larger
 *             part that merely contains the scan lacks much more);
 *   score     coverage x (1 - lacking) x (1 - (rms / tol)^2 / 2), in 0..1.
 * A single tolerance serves every candidate so that their scores compare: by default
 * 0.5 % of the scan's bounding-box diagonal, as register.h uses for one pair.
 */
#ifndef SR_IDENTIFY_H
#define SR_IDENTIFY_H

#include <stddef.h>

#include "align/shape_descriptor.h"
#include "base/status.h"
#include "mesh/mesh.h"

/* A match needs all three bounds, each following from what a right part gives and a
 * wrong one cannot:
 *  - coverage: every sample of the scan's own surface lies within tol of the right
 *    part once registered (tol is many times a scan's noise), and its fracture faces
 *    inside the part's solid: together at least SR_IDENTIFY_MIN_COVERAGE. A part of
 *    another shape or size has the scan pass outside it. The fracture faces are not
 *    bounded by the volume lost (a flat cut along a shaft loses a sixth of the volume
 *    and leaves a quarter of the scan's area as fracture), but the part's own surface
 *    is still most of the scan: at least SR_IDENTIFY_MIN_ON within tol;
 *  - lacking: the damage takes at most about a quarter of the part's surface with a
 *    quarter of its volume; a part larger than the scan's lacks more;
 *  - RMS: on the right part the inliers' distances are noise and registration error,
 *    a small fraction of tol; on a wrong part that merely passes near the scan they
 *    spread over [0, tol], an RMS of about tol / sqrt(3) = 0.58 tol. */
#define SR_IDENTIFY_MIN_COVERAGE 0.80
#define SR_IDENTIFY_MIN_ON 0.50
#define SR_IDENTIFY_MAX_LACKING 0.30
#define SR_IDENTIFY_MAX_RMS_TOL 0.25
/* The first is too close to call when the second scores within this of it. */
#define SR_IDENTIFY_MARGIN 0.05

typedef struct sr_identify_scan sr_identify_scan;

/* Prepares a validated scan with some area (borrowed: it must outlive the handle). tol_mm > 0 sets the tolerance, 0 takes
 * 0.5 % of the scan's bounding-box diagonal. SR_E_INVALID (naming "scan"), SR_E_NOMEM.
 * *out only on success; free with sr_identify_scan_free. */
sr_status sr_identify_scan_make(const sr_mesh *scan, double tol_mm, sr_identify_scan **out,
                                sr_err *err);
/* Accepts NULL. */
void sr_identify_scan_free(sr_identify_scan *scan);
const sr_shape_descriptor *sr_identify_scan_descriptor(const sr_identify_scan *scan);
double sr_identify_scan_tol(const sr_identify_scan *scan);

typedef struct sr_identify_fit {
    double mat[12];  /* scan -> part frame: p' = M[:, :3] p + M[:, 3] (3 x 4 row-major) */
    double coverage; /* 0..1 */
    double inside;   /* 0..1: farther than tol, inside the part (fracture faces) */
    double rms_mm;
    double lacking; /* 0..1 */
    double score;   /* 0..1 */
    double tol_mm;  /* the tolerance coverage and lacking were taken at */
} sr_identify_fit;

/* Fits the scan to each of `count` part meshes (validated, with some area): out[i]
 * for parts[i]. Candidates run on every core (OpenMP); the result does not depend on
 * how many. SR_E_INVALID naming the candidate's index, SR_E_NOMEM; out is complete
 * only on SR_OK. */
sr_status sr_identify_fit_parts(sr_identify_scan *scan, const sr_mesh *const *parts, size_t count,
                                sr_identify_fit *out, sr_err *err);

/* Whether a fit is good enough to be the scan's part (the three bounds above). */
int sr_identify_fit_matches(const sr_identify_fit *fit);

#endif
