/*
 * symmetry_fit.h: which kind of symmetry a scan has (`reconstruct --symmetry auto`,
 * `symrec symmetry`): every kind fitted (continuous axial, n-fold axial with its order,
 * mirror, glide with its shift), each scored by one measure that is comparable across
 * kinds, and the highest symmetry that fits proposed with a confidence, or two
 * candidates when two kinds that do not contain each other fit equally well. The
 * method is described at the top of symmetry_fit.c. Pure C, no I/O.
 */
#ifndef SR_SYMMETRY_FIT_H
#define SR_SYMMETRY_FIT_H

#include "align/align.h"
#include "base/status.h"
#include "base/symmetry.h"
#include "mesh/mesh.h"

/* The candidates, highest symmetry first (the order of the figures below). */
typedef enum sr_symfit_cand {
    SR_SYMFIT_ROUND = 0, /* continuous axial */
    SR_SYMFIT_NFOLD,     /* axial of the order found (none: not fitted) */
    SR_SYMFIT_MIRROR,
    SR_SYMFIT_GLIDE, /* with the shift found (0: the glide fit is a mirror) */
    SR_SYMFIT_COUNT
} sr_symfit_cand;

typedef struct sr_symfit_figure {
    int fitted;         /* 0: the kind could not be fitted (n-fold: no order found) */
    double consistency; /* 0..1: share of the scan's surface samples whose image under
                            * the symmetry lies on the scan (within tol_mm, normals
                            * within 30 deg); axial: matched by most of its turns;
                            * the worst grid cells (damage) left out, see the .c */
    double rms_mm;      /* the aligner's residual of this kind's fit, mm */
} sr_symfit_figure;

typedef struct sr_symmetry_fit {
    sr_symmetry proposal;    /* kind, order (axial), shift_mm (glide) */
    sr_symmetry alternative; /* ambiguous: the other candidate; else kind SR_SYM_NONE */
    int ambiguous;           /* 1: proposal and alternative fit equally well (the proposal
                            * is the one ranked higher) */
    double confidence;       /* 0..1 */
    sr_alignment alignment;  /* the proposal's alignment (scan -> canonical) */
    sr_symfit_figure fig[SR_SYMFIT_COUNT];
    int order;             /* the order found on the axial fit (0: none: round, or no
                            * rotational symmetry) */
    double glide_shift_mm; /* the shift the glide fit found */
    double noise_mm;       /* the scan's noise as measured (best fit's residual / sqrt 2) */
    double tol_mm;         /* the tolerance of the consistency, mm */
    size_t samples;        /* surface samples scored */
    double seconds;        /* time of the whole fit, s */
} sr_symmetry_fit;

/* Fits every kind to `mesh` (a validated mesh with some area) and proposes one.
 * Errors: SR_E_INVALID (empty mesh, NaN, no area), SR_E_NOMEM. Deterministic. */
sr_status sr_symmetry_propose(const sr_mesh *mesh, sr_symmetry_fit *out, sr_err *err);

/* Name of a candidate: "axial", "axial n-fold", "mirror", "glide". */
const char *sr_symfit_cand_name(sr_symfit_cand c);

#endif
