/*
 * nominal_int.h: what the files of the nominal comparison share (nominal.h is the
 * interface). nominal.c owns sr_nominal_compare: the difference, its pieces, the
 * sections and the judgement; nominal_start.c the registration of the intact mesh
 * started from the symmetry alignment; nominal_cells.c the missing volume measured
 * cell by cell when the exact difference refuses the scan.
 */
#ifndef SR_NOMINAL_INT_H
#define SR_NOMINAL_INT_H

#include "nominal.h"

/* Registers `intact` to `scan` (out: intact -> scan). With o->alignment (the scan's
 * symmetry alignment) the intact mesh is aligned by the same symmetry and the few
 * poses the two canonical frames leave open (the axes' signs, the turn about an axis)
 * are the starts of a short registration (register.h's sr_register_from); when that
 * does not hold (coverage under SR_NOMINAL_MIN_COVERAGE) or there is no alignment,
 * the full start search (sr_register) runs. *full says whether it ran. As sr_register
 * for errors. */
sr_status nominal_register(const sr_mesh *scan, const sr_mesh *intact, const sr_nominal_opts *o,
                           sr_register_result *out, int *full, sr_err *err);

/* The section whose box (boxes: count x {lo[3], hi[3], reach}) is nearest p, within
 * its reach; count when none is (nominal.c). */
size_t nominal_nearest_section(const double p[3], const double *boxes, size_t count);

/* One piece of the cell measure: cells over the scatter joined through faces, edges
 * and corners, with the ring of cells around them. */
typedef struct nominal_cell_piece {
    double volume_mm3;          /* sum of its cells' intact - scan volume */
    double centroid[3];         /* volume-weighted sum of its cells' centres */
    double outside_centroid[3]; /* the same over its cells near no section */
    double *share;              /* count + 1: its volume per section, the last near none */
} nominal_cell_piece;

typedef struct nominal_cell_pieces {
    nominal_cell_piece *pieces;
    size_t count;
    double extra_mm3; /* scan - intact summed over the cells where it is over the scatter */
    double cell_mm;   /* the cells' size */
} nominal_cell_pieces;

/* The nominal's missing material by cells (nominal_cells.c): registered intact minus
 * scan, both closed (they may cross themselves), on a grid of cells of 1/50 of the
 * meshes' joint box diagonal; sliver_mm sets the scatter (a cell's difference counts
 * when over 2 sliver_mm x the cell's face). boxes: count x 7 as nominal.c's section
 * boxes. *out zeroed on entry; SR_E_NOMEM (out released), SR_E_INVALID for meshes with
 * no extent. Release with nominal_cell_pieces_release. */
sr_status nominal_cells(const sr_mesh *registered, const sr_mesh *scan, const double *boxes,
                        size_t count, double sliver_mm, nominal_cell_pieces *out, sr_err *err);

/* Frees p's arrays and zeroes it; accepts NULL. */
void nominal_cell_pieces_release(nominal_cell_pieces *p);

#endif
