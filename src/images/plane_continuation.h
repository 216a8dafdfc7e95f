/*
 * plane_continuation.h: the image method's continuation across a mirror plane.
 *
 * A break through the plane takes material from both sides, which no image of the scan
 * carries (the lever's broken boss corner: the mirror restores 40 % of it). Where a
 * section reaches the plane (its clipped image within two voxels of x = 0), the layer
 * method's continuity along z is asked (region_sections.h: each layer's lost piece
 * carried up or down to the feature's own end face), in a box round those pieces only;
 * a layer section over the same place that holds a quarter more than the image's, and
 * adds across the plane what the image could not, becomes that section's piece to
 * unite (the union makes it exact against the scan, as any image). Parts whose damage
 * stops at the plane agree with it and are left as they are.
 */
#ifndef SYMREC_PLANE_CONTINUATION_H
#define SYMREC_PLANE_CONTINUATION_H

#include <stddef.h>

#include "base/status.h"
#include "base/symmetry.h"
#include "mesh/mesh.h"
#include "paper/patch.h"
#include "slice/slice.h"

typedef struct sr_continuation_opts {
    sr_symmetry symmetry;   /* anything but a mirror: nothing is done */
    double pitch_mm;        /* the image vote's voxel pitch (the plane's reach: 2 of it) */
    double open_mm;         /* the layer method's noise filter */
    double min_depth_mm, min_volume_mm3;
} sr_continuation_opts;

/* For each of sections[0..count) (the image pieces, aligned frame, before the union)
 * that reaches the plane, replaces its patch by the layer method's section that carries
 * it across, if there is one; *continued adds the pieces taken over. A layer method
 * that fails leaves the images' answer as it is (SR_OK). */
sr_status sr_continue_across_plane(const sr_mesh *aligned, const sr_layer_grid *grid,
                                   const sr_continuation_opts *o, sr_section *sections,
                                   size_t count, size_t *continued, sr_err *err);

#endif
