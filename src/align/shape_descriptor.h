/*
 * shape_descriptor.h: a pose-invariant summary of a part's surface for finding which
 * catalogue part a scan is of (`symrec identify`), cheap to compare against hundreds.
 *
 * It keeps scale (a shop's parts differ in size, so a part and its 0.8x copy must
 * differ) and tolerates what a damaged scan lacks and adds: up to a quarter of the
 * volume missing, fracture faces, noise and any triangle density. It holds
 *   - the surface area (mm^2);
 *   - the principal spreads: square roots of the eigenvalues of the area-weighted
 *     covariance of the surface, descending (mm);
 *   - the D2 shape distribution (Osada, Funkhouser, Chazelle and Dobkin, "Shape
 *     distributions", ACM TOG 21(4), 2002): the histogram of the distances between
 *     pairs of area-uniform surface samples, on a log2 axis (SR_SHAPE_D2_PER_OCTAVE
 *     bins per octave from 2^SR_SHAPE_D2_LOG2_MIN mm), so a change of scale is a shift
 *     and a comparison in octaves means the same for small and large parts.
 * Every figure is computed from the surface as a set (samples drawn by area, in the
 * mesh's triangle order, with a fixed seed), so a rigid motion of the mesh changes the
 * descriptor only by rounding.
 */
#ifndef SR_SHAPE_DESCRIPTOR_H
#define SR_SHAPE_DESCRIPTOR_H

#include "base/status.h"
#include "mesh/mesh.h"

#define SR_SHAPE_DESCRIPTOR_VERSION 1
#define SR_SHAPE_D2_BINS 144 /* 18 octaves */
#define SR_SHAPE_D2_PER_OCTAVE 8
#define SR_SHAPE_D2_LOG2_MIN (-4) /* the first bin starts at 1/16 mm */

typedef struct sr_shape_descriptor {
    double area_mm2;
    double spread_mm[3];         /* descending */
    double d2[SR_SHAPE_D2_BINS]; /* shares, summing to 1 */
} sr_shape_descriptor;

/* Computes the descriptor of a validated mesh with some area. SR_E_INVALID naming
 * `what` when no triangle has an area; SR_E_NOMEM. *out only on success. */
sr_status sr_shape_descriptor_compute(const sr_mesh *mesh, const char *what,
                                      sr_shape_descriptor *out, sr_err *err);

/* How far apart two descriptors are, in octaves (log2 of a size ratio): the earth
 * mover's distance between the D2 distributions on their log2 axis plus the mean
 * |log2| ratio of the principal spreads, halved. 0 for equal descriptors; a uniform
 * scaling by s gives about |log2 s|. Symmetric. */
double sr_shape_descriptor_distance(const sr_shape_descriptor *a, const sr_shape_descriptor *b);

#endif
