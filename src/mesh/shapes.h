/*
 * shapes.h: closed, outward-oriented meshes of simple solids built from parameters,
 * with volumes known in closed form: the project's own test geometry and the parts of
 * the built-in demo catalogue. Pure C, no I/O.
 *
 * A solid of revolution is given as rings: ring i sits at height z[i] with radius
 * r_i(theta) (a function, so a chip or gouge is a local change of radius); two rings
 * at the same z make a flat annular step (a shoulder). Optional inner rings make a
 * hollow part (a bore). A prism is a simple polygon (counter-clockwise, no holes)
 * extruded along z.
 */
#ifndef SR_SHAPES_H
#define SR_SHAPES_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

/* Radius of a ring at angle theta (radians, [0, 2pi)); must be > 0. */
typedef double (*sr_ring_radius_fn)(double theta, size_t ring, void *user);

typedef struct sr_revolve_opts {
    size_t segments;            /* vertices per ring, >= 3 */
    size_t ring_count;          /* >= 2 */
    const double *ring_z;       /* ring_count heights, non-decreasing */
    sr_ring_radius_fn outer;    /* outer radius of ring i at theta */
    sr_ring_radius_fn inner;    /* NULL = solid (end caps are fans to the axis) */
    void *user;
} sr_revolve_opts;

/* Builds the closed surface of revolution described by opts. */
sr_status sr_shape_revolve(const sr_revolve_opts *opts, sr_mesh *out, sr_err *err);

/* A solid cylinder of radius r, z from z0 to z1, `segments` sides (a regular prism:
 * volume = segments/2 * r^2 * sin(2pi/segments) * (z1 - z0)). */
sr_status sr_shape_cylinder(double r, double z0, double z1, size_t segments, sr_mesh *out,
                            sr_err *err);

/* Axis-aligned box from min to max. */
sr_status sr_shape_box(const double min[3], const double max[3], sr_mesh *out, sr_err *err);

/* Extrudes a simple polygon (xy: count by 2, counter-clockwise, no holes) from z0 to
 * z1; the caps are ear-clipped. */
sr_status sr_shape_prism(const double *xy, size_t count, double z0, double z1, sr_mesh *out,
                         sr_err *err);

/* ---- the demo catalogue's parts ---- */

typedef struct sr_demo_part {
    const char *number;         /* part number, e.g. "SR-SHAFT-01" */
    const char *name;
    const char *material;
    const char *notes;          /* what the part is */
    const char *serial;         /* serial of its damaged instance */
    const char *damage_notes;   /* what is broken */
    int sym_kind;               /* an sr_sym_kind */
    int sym_order;              /* axial n-fold order, 0 = continuous */
    double sym_shift_mm;        /* glide shift */
} sr_demo_part;

/* Number of demo parts, and the i-th (i < count). */
size_t sr_demo_part_count(void);
const sr_demo_part *sr_demo_part_get(size_t i);

/* Builds the intact and the damaged mesh of demo part i, in its canonical frame. Either
 * out-pointer may be NULL. The missing volume is volume(intact) - volume(damaged). */
sr_status sr_demo_part_build(size_t i, sr_mesh *intact, sr_mesh *damaged, sr_err *err);

#endif
