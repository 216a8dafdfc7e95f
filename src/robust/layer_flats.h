/*
 * layer_flats.h: how much flat face across z lies at each layer's plane, so the robust
 * method can tell a real loss from the ragged cut of a noisy flat face.
 *
 * A plane that lies within the noise of a face perpendicular to z (a shoulder, the end
 * of a notch or a slot, a flange's top) cuts that face wherever the noise lifts it
 * above the plane: the contour gets a ragged fringe up to the face's size, different in
 * the layer and in each of its symmetry images, and the vote reads the difference as
 * damage. On the noisy rail (glide, its image planes one shift away land on the
 * matching notch ends) that gave four one-layer "sections" of 1.2-1.7 mm^3. Such a
 * fringe is never larger than the flat face the planes cut, and it lives in that one
 * layer; region_sections.c drops a section of one layer whose area is no larger than
 * this layer's flat area. (Moving the planes off the faces instead was tried: it biased
 * the samples on near-horizontal fractures and hole tops, +1.3 % on the noisy U clamp.)
 *
 * Flat face: a triangle whose unit normal has |n_z| >= SR_LAYER_FLATS_NZ. A layer's
 * flat area: the area of the flat triangles whose z-extent comes within margin_mm of
 * its plane z_init + (l + 1/2) dz or of an image plane (that plane + shifts[k]), summed
 * over the planes; read off a z histogram (bins of margin_mm / 4) built in one pass
 * over the triangles, so a face counts within margin_mm to margin_mm + one bin.
 */
#ifndef SR_LAYER_FLATS_H
#define SR_LAYER_FLATS_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

/* |n_z| of a flat face's triangle: within about 18 degrees of horizontal */
#define SR_LAYER_FLATS_NZ 0.95

/* Default of margin_mm: twice the robust method's smallest noise filter radius. */
#define SR_LAYER_FLATS_MARGIN_MM 0.05

/* The layer grid (z_init, dz, layers) is required; the options after it are valid
 * when zeroed, each 0 the default named. */
typedef struct sr_layer_flats_opts {
    double z_init, dz;      /* layer l's plane is z_init + (l + 1/2) dz; dz > 0 */
    size_t layers;          /* >= 1 */
    double margin_mm;       /* a face this near a plane is at it, > 0;
                             * 0 = SR_LAYER_FLATS_MARGIN_MM */
    const double *shifts;   /* image planes at plane + shifts[k]; may be NULL */
    size_t shift_count;
} sr_layer_flats_opts;

/* Writes each layer's flat area, mm^2, into area_out (layers doubles). SR_E_RANGE for
 * bad options (no layers, dz or margin not > 0, a value not finite); SR_E_NOMEM.
 * area_out only on success. */
sr_status sr_layer_flats_area(const sr_mesh *mesh, const sr_layer_flats_opts *opts,
                              double *area_out, sr_err *err);

#endif
