/*
 * align.h: finding a scan's symmetry element and the rigid transform that brings it to
 * the canonical frame (paper Algorithm 3, then better). Pure C on plain arrays.
 *
 * Canonical frame: axial — the symmetry axis is the z axis (x = y = 0); mirror and
 * glide — the symmetry plane is x = 0 and the chosen in-plane axis is z (for glide, the
 * shift direction). The transform maps scan coordinates to canonical ones:
 * p_canonical = M p_scan (3x4 row-major, see mesh.h); its inverse maps results back.
 *
 * Conventions of sr_align (the rest of the frame is a free choice, fixed here):
 *  - axial: the smallest rotation taking the axis to +z, the axis signed to point along
 *    the scan's +z (a part scanned upright stays upright); z = 0 at the mesh's lowest
 *    point along the axis, so the part lies in z >= 0;
 *  - mirror / glide: canonical x = the plane normal (signed along the scan's +x),
 *    z = the in-plane axis (signed along the scan's +z), y = z x x; z = 0 at the lowest
 *    point along z, y = 0 at the middle of the part's extent along y. For a mirror the
 *    in-plane axis is the in-plane principal direction of least spread (a convention);
 *    for a glide it is the shift direction;
 *  - when several planes are mirror planes of most of the surface (a bracket is
 *    symmetric about x = 0 and y = 0, a plate about its mid-plane), the one across which
 *    the part spreads widest is taken, among those scoring at least 0.8 of the best;
 *    opts->hint picks another.
 * Method 0 (default): candidates (normal-line axis fit of Pottmann & Randrup, principal
 * axes and planes of the area covariance, reflection-symmetric directions of the
 * normals, a glide shift scan) refined by a robust "symmetry ICP" that maps the scan
 * onto itself; see align_internal.h for the files. Method 1: the paper's Algorithm 3
 * alone (align_paper.c), a heuristic within a degree or so on dense round parts.
 */
#ifndef SR_ALIGN_H
#define SR_ALIGN_H

#include "mesh/mesh.h"
#include "base/status.h"
#include "base/symmetry.h"

typedef struct sr_align_opts {
    int method;            /* 0 = best (refined), 1 = paper Algorithm 3 only */
    int layers;            /* layers for the Alg. 3 search; 0 = 64 */
    int sectors;           /* sectors for the Alg. 3 search; 0 = 72 */
    double delta_d;        /* Alg. 3 threshold; 0 = 0.05 */
    double coarse_step_deg;/* Alg. 3 rotation grid step; 0 = 5 */
    double hint[3];        /* optional, scan frame: a rough direction of the wanted axis
                            * (axial) or plane normal (mirror, glide); among the
                            * candidates that fit (score >= 0.8 of the best) the one
                            * nearest the hint is taken. Zero = none (method 0 only) */
    int threads;           /* threads of the closest-point queries; 0 = all cores (at
                            * most 8). The alignment is the same for any number */
} sr_align_opts;

typedef struct sr_alignment {
    double xform[12];      /* scan -> canonical, rigid */
    double axis_point[3];  /* in the scan frame: a point on the axis / in the plane */
    double axis_dir[3];    /* axial: axis direction; planar: in-plane axis (canonical z) */
    double plane_normal[3];/* planar: the plane's normal (canonical x); zero for axial */
    double glide_shift_mm; /* glide: the shift found (or given), the smallest positive of
                            * the equivalent s, 3s, 5s...; 0 otherwise */
    double fit_rms_mm;     /* residual of the symmetry fit, mm (lower is better): RMS
                            * distance from the surface of the images of the inlier
                            * samples under the symmetry transform(s); the inlier
                            * tolerance itself when no sample fits */
    double fit_score;      /* 0..1 share of the surface consistent with the symmetry: area
                            * samples whose image lies within 0.4 % of the bounding-box
                            * diagonal of the surface (a wrong kind scores low) */
    int symmetric_layers;  /* Alg. 3 count at the chosen rotation (method 0: counted in
                            * the final canonical frame) */
} sr_alignment;

/* Finds the symmetry element of `mesh` for `sym` and the transform to the canonical
 * frame. opts may be NULL (defaults). For glide, sym->shift_mm > 0 fixes the shift,
 * 0 searches for it (shifts below 1.6 % of the bounding-box diagonal count as a
 * mirror, not a glide). Never fails on a poor fit: fit_rms_mm/fit_score say how poor.
 * Errors: SR_E_RANGE (bad sym or opts field, named in err), SR_E_INVALID (empty mesh,
 * NaN/Inf, index out of range, no triangle with an area), SR_E_NOMEM. Deterministic;
 * roughly linear in the triangle count (about 0.2-0.4 s for 100k triangles). *out is
 * written only on success. */
sr_status sr_align(const sr_mesh *mesh, const sr_symmetry *sym, const sr_align_opts *opts,
                   sr_alignment *out, sr_err *err);

/* Alignment from a user-given axis (point + direction) or plane (point + normal +
 * in-plane axis `dir`), for the override. For axial, normal is NULL. The given point
 * becomes the canonical origin and the given directions are kept as they are (not
 * re-signed); an in-plane axis not perpendicular to the normal is made so. The fit
 * fields, glide_shift_mm and symmetric_layers are 0 (nothing is measured).
 * sr_align_from_axis(a.axis_point, a.axis_dir, planar ? a.plane_normal : NULL)
 * reproduces a.xform of an sr_align result. SR_E_RANGE for a non-finite point, a zero
 * or non-finite direction or normal, or an in-plane axis along the normal. */
sr_status sr_align_from_axis(const double point[3], const double dir[3],
                             const double normal[3], sr_alignment *out, sr_err *err);

#endif
