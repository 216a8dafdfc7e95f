/*
 * mesh_shells.h: the shells of a closed mesh (its connected components, triangles
 * joined through shared vertices) and the removal of small voids: closed shells of
 * negative enclosed volume, the empty pockets a patch can trap against a noisy
 * fracture surface when the two are united. A scanner sees only the outside of a part,
 * so a void in a restored scan is made by the restoration, never measured.
 */
#ifndef SR_MESH_SHELLS_H
#define SR_MESH_SHELLS_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

typedef struct sr_void_report {
    size_t shells;          /* shells of the mesh before */
    size_t voids_dropped;   /* void shells removed */
    double void_volume_mm3; /* their summed volume (positive), mm^3 */
} sr_void_report;

/* Removes from mesh every shell whose enclosed volume is negative (a void, its faces
 * turned inward) and no larger than max_void_mm3 in magnitude; vertices only those
 * shells used are dropped too. The rest keeps its order. The mesh should be closed and
 * oriented (a shell that is not closed has no meaningful volume and may be dropped or
 * kept). max_void_mm3 negative or not finite: SR_E_RANGE. SR_E_NOMEM; mesh unchanged on
 * error. report may be NULL. */
sr_status sr_mesh_drop_voids(sr_mesh *mesh, double max_void_mm3, sr_void_report *report,
                             sr_err *err);

/* Removes every shell whose enclosed volume is smaller than min_volume_mm3 in
 * magnitude, solid or void: the slivers a boolean leaves where two nearly coincident
 * surfaces cross (report->voids_dropped counts them all). Errors as above. */
sr_status sr_mesh_drop_small_shells(sr_mesh *mesh, double min_volume_mm3,
                                    sr_void_report *report, sr_err *err);

/* How many shells enclose less than min_volume_mm3 in magnitude, solid or void, and
 * (shells, may be NULL) how many there are; SIZE_MAX when out of memory. */
size_t sr_mesh_count_small_shells(const sr_mesh *mesh, double min_volume_mm3, size_t *shells);

#endif
