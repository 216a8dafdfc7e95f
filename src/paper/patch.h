/*
 * patch.h: missing sections and their closed patch meshes (paper Algorithm 6).
 *
 * Damaged cells (layer, sector) are grouped into missing sections: runs of consecutive
 * damaged sectors in a layer (wrapping round) joined across consecutive layers where
 * they share a sector (4-connectivity on the cylinder grid). Each section becomes one
 * closed, outward-oriented triangle surface: the union over its cells of the cylindrical
 * blocks {sector j's wedge, r in [damaged r, restored r], the layer's slab
 * [L - dz/2, L + dz/2]}, with straight chords between sector borders. So the surface
 * has the inner face from the damaged outline (Polylines(0,.)), the outer face from the
 * restored outline (Polylines(1,.)), side walls at the run ends and where neighbouring
 * radii step, and caps on the first and last layers and where layers differ; faces are
 * split where a neighbour's corner lies on their edge, so no T-junction is left.
 * The patch volume is then exactly sum over cells of (ro^2 - ri^2)/2 sin(2pi/N) dz.
 */
#ifndef SR_PATCH_H
#define SR_PATCH_H

#include "paper/analyse.h"
#include "mesh/mesh.h"
#include "slice/slice.h"

typedef struct sr_section {
    size_t layer_first, layer_last;
    double z_min, z_max;        /* mm, aligned frame */
    size_t cell_count;
    size_t sector_first;        /* the covered arc starts at this sector ... */
    size_t sector_count;        /* ... and spans this many (wrapping) */
    double angle_min_deg, angle_max_deg; /* that arc in degrees, min in [0, 360) */
    double depth_max_mm, depth_mean_mm;  /* restored r - damaged r over the cells */
    double volume_mm3;          /* the missing volume. Paper method: the enclosed volume of
                                 * the patch. Robust method: sum of the layers' missing
                                 * areas x layer thickness; its patch mesh is that region
                                 * grown a little into the damaged part (so no fracture
                                 * surface is left exposed between layer planes) */
    double area_mm2;            /* paper: surface area of the patch; robust: area of the
                                 * lost surface (restored outline x layer thickness) */
    sr_mesh patch;              /* closed, outward oriented; aligned frame */
} sr_section;

/* Builds the sections of `a` on `grid`, largest volume first. Writes *out and
 * *count only on success; zero sections is a success (nothing to repair). */
sr_status sr_patch_build(const sr_layer_grid *grid, const sr_analysis *a, sr_section **out,
                         size_t *count, sr_err *err);

/* The volume of a section by the cell formula (what its patch must enclose). */
double sr_section_cell_volume(const sr_layer_grid *grid, const sr_analysis *a,
                              const int *section_of, int s);

void sr_sections_release(sr_section *sections, size_t count);

#endif
