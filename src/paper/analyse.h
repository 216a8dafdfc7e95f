/*
 * analyse.h: symmetry analysis of a sliced, aligned model (paper Algorithm 4, axial,
 * and Algorithm 5, planar mirror and glide reflection), producing per layer the
 * polyline pair of the paper: the damaged outline (the slice grid's farthest points)
 * and the restored outline, and the cells where they differ (damaged cells).
 *
 * Readings of the paper (ALGORITHMS.md): Alg. 4 takes D_max per layer and restores a
 * sector whose D_j < gamma_axis * D_max to D_max at the sector's angle. Alg. 5 uses one
 * plane for the whole model (angle phi through the z axis, searched in half-sector
 * steps around the aligned plane x = 0, Diff_min starting at +inf); for each mirrored
 * pair of sectors with min/max < gamma_plane the shorter is replaced by the mirror image
 * of the longer. Glide: the partner of layer l is the layer one shift away (both
 * directions, where they exist). A cell is damaged only when the restored radius
 * exceeds the damaged one by more than min_depth_mm.
 */
#ifndef SR_ANALYSE_H
#define SR_ANALYSE_H

#include "slice/slice.h"
#include "base/symmetry.h"

typedef struct sr_analysis {
    size_t layers, sectors;
    double *restored_r;         /* layers by sectors: restored outline radius */
    unsigned char *damaged;     /* layers by sectors: 1 where restored > damaged */
    double plane_angle;         /* planar: angle of the plane's trace (rad); canonical pi/2 */
    double shift_mm;            /* glide: the shift used */
    double fit_diff;            /* planar: mean relative mirror difference at the plane */
    size_t damaged_cells;
} sr_analysis;

/* Valid when zeroed but for the symmetry: every 0 is the default named, resolved by
 * sr_analyse (the gammas from the parameter table, run/params_default.h). */
typedef struct sr_analyse_opts {
    sr_symmetry symmetry;       /* required: axial, mirror or glide */
    double gamma_axis;          /* (0,1]; 0 = the 'default' set's (0.95) */
    double gamma_plane;         /* (0,1]; 0 = the 'default' set's (0.95) */
    double min_depth_mm;        /* >= 0; 0 = any depth counts */
    int fixed_plane;            /* planar: 0 = search phi around pi/2 (Alg. 5, the
                                 * default); 1 = take the aligned plane, phi = pi/2 */
} sr_analyse_opts;

/* Runs Alg. 4 or 5 on grid. *out only on success. */
sr_status sr_analyse(const sr_layer_grid *grid, const sr_analyse_opts *opts,
                     sr_analysis *out, sr_err *err);

void sr_analysis_release(sr_analysis *a);

#endif
