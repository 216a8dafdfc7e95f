/*
 * mesh_facts.h: what a mesh file holds, as a shop engineer checks it before use (the
 * facts `symrec check` prints, in the manner of admesh): size, volume, area, whether it
 * is a closed and consistently oriented solid, its degenerate and duplicate triangles,
 * its connected pieces, and the unit its size suggests.
 */
#ifndef SR_MESH_FACTS_H
#define SR_MESH_FACTS_H

#include <stddef.h>

#include "base/status.h"
#include "mesh/mesh.h"

typedef struct sr_mesh_facts {
    size_t vertices, triangles;
    double bbox_min[3], bbox_max[3]; /* as read (mm unless the unit says otherwise) */
    double largest_extent;           /* the largest side of the bounding box */
    double volume, area;             /* enclosed volume (meaningful when closed), area */
    sr_mesh_edges edges;             /* boundary, non-manifold, misoriented edges ... */
    int closed;                      /* no boundary and no non-manifold edge */
    int oriented;                    /* closed, and no misoriented edge */
    int outward;                     /* oriented with a positive volume */
    size_t degenerate_triangles;     /* a repeated vertex or zero area */
    size_t duplicate_triangles;      /* the same three vertices as an earlier one */
    size_t components;               /* pieces joined through shared vertices */
    size_t largest_component;        /* triangles in the largest piece */
    const char *likely_unit;         /* sr_unit_guess of the largest extent */
} sr_mesh_facts;

/* The facts of a validated mesh. SR_E_NOMEM. */
sr_status sr_mesh_facts_get(const sr_mesh *mesh, sr_mesh_facts *out, sr_err *err);

/* The unit a part of this largest extent (a number as read) was most likely drawn in,
 * for machined parts of about 5 mm to 3 m: "mm" for 5..3000, "in" for 1..5 (a 2.5
 * read as mm is a 2.5 in = 63.5 mm part far more often than a 2.5 mm one), "m" below 1,
 * "um" above 3000. A guess: the caller says so. */
const char *sr_unit_guess(double largest_extent);

#endif
