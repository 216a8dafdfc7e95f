/*
 * units.h: the length units a mesh file may be drawn in, and the one place their
 * factors to millimetres live. symrec works in millimetres throughout; a file in
 * another unit is scaled to mm as it is read (bridge/mesh_io.h's sr_mesh_read_units),
 * and the unit it was read in is kept with the stored mesh (catalogue, meshes.source_unit).
 * Pure C, no I/O.
 */
#ifndef SR_UNITS_H
#define SR_UNITS_H

#include <stdbool.h>

/* SR_UNIT_DEFAULT (zero) means "the file format's own unit" (mesh_io.h's
 * sr_format_unit: metres for glTF/GLB, millimetres for the formats that state none). */
typedef enum sr_unit {
    SR_UNIT_DEFAULT = 0,
    SR_UNIT_MM,
    SR_UNIT_CM,
    SR_UNIT_M,
    SR_UNIT_IN,
} sr_unit;

/* The list the CLI's messages and help name. */
#define SR_UNIT_NAMES "mm, cm, m or in"

/* "mm", "cm", "m", "in" (exact, lower case) into *out; false (and *out untouched) for
 * anything else, NULL included. */
bool sr_unit_parse(const char *name, sr_unit *out);

/* The unit's name ("mm", "cm", "m", "in"); "default" for SR_UNIT_DEFAULT and for a value
 * outside the enum. */
const char *sr_unit_name(sr_unit unit);

/* Millimetres in one unit: 1, 10, 1000, 25.4 (exact by definition); 1 for SR_UNIT_DEFAULT
 * and a value outside the enum. */
double sr_unit_mm(sr_unit unit);

/* Whether a part whose largest side is extent_mm millimetres (as read, after scaling)
 * is of the size a machined part has (sr_unit_guess says "mm": 5 mm .. 3 m). When it is
 * not, *likely is the unit the file's own numbers (extent_mm / sr_unit_mm(stated)) were
 * more likely drawn in: a unit of this enum other than `stated`, or SR_UNIT_DEFAULT when
 * no other unit gives a plausible size either. */
bool sr_unit_size_plausible(double extent_mm, sr_unit stated, sr_unit *likely);

#endif
