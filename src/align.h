/*
 * align.h: finding a scan's symmetry element and the rigid transform that brings it to
 * the canonical frame (paper Algorithm 3, then better). Pure C on plain arrays.
 *
 * Canonical frame: axial — the symmetry axis is the z axis (x = y = 0); mirror and
 * glide — the symmetry plane is x = 0 and the chosen in-plane axis is z (for glide, the
 * shift direction). The transform maps scan coordinates to canonical ones:
 * p_canonical = M p_scan (3x4 row-major, see mesh.h); its inverse maps results back.
 */
#ifndef SR_ALIGN_H
#define SR_ALIGN_H

#include "mesh.h"
#include "status.h"
#include "symmetry.h"

typedef struct sr_align_opts {
    int method;            /* 0 = best (refined), 1 = paper Algorithm 3 only */
    int layers;            /* layers for the Alg. 3 search; 0 = 64 */
    int sectors;           /* sectors for the Alg. 3 search; 0 = 72 */
    double delta_d;        /* Alg. 3 threshold; 0 = 0.05 */
    double coarse_step_deg;/* Alg. 3 rotation grid step; 0 = 5 */
} sr_align_opts;

typedef struct sr_alignment {
    double xform[12];      /* scan -> canonical, rigid */
    double axis_point[3];  /* in the scan frame: a point on the axis / in the plane */
    double axis_dir[3];    /* axial: axis direction; planar: in-plane axis (canonical z) */
    double plane_normal[3];/* planar: the plane's normal (canonical x); zero for axial */
    double glide_shift_mm; /* glide: the shift found (or given); 0 otherwise */
    double fit_rms_mm;     /* residual of the symmetry fit, mm (lower is better) */
    double fit_score;      /* 0..1 share of the surface consistent with the symmetry */
    int symmetric_layers;  /* Alg. 3 count at the chosen rotation */
} sr_alignment;

/* Finds the symmetry element of `mesh` for `sym` and the transform to the canonical
 * frame. opts may be NULL (defaults). For glide, sym->shift_mm > 0 fixes the shift,
 * 0 searches for it. Never fails on a poor fit: fit_rms_mm/fit_score say how poor. */
sr_status sr_align(const sr_mesh *mesh, const sr_symmetry *sym, const sr_align_opts *opts,
                   sr_alignment *out, sr_err *err);

/* Alignment from a user-given axis (point + direction) or plane (point + normal +
 * in-plane axis), for the override. For axial, normal may be NULL. */
sr_status sr_align_from_axis(const double point[3], const double dir[3],
                             const double normal[3], sr_alignment *out, sr_err *err);

#endif
