/*
 * truth.h: the few answers the accuracy test and the benchmark need from a shared
 * part's truth.json (../shared/parts/<part>/truth.json, see its README): the
 * symmetry kind with its order or glide shift, the intact and missing volumes, and the
 * rigid pose that moved the canonical part into damaged_posed.stl / damaged_scan.stl
 * (p_posed = R p_canonical + t). A plain string search for each key, no JSON library:
 * the files are machine-written with unique top-level keys, and only these are read.
 * Plus the geometry the two consumers share: the posed frame's transform back to the
 * canonical frame, the alignment error of a found axis or plane against the pose, and
 * the patches' overlap with the intact part and the true missing volume.
 */
#ifndef SR_TEST_TRUTH_H
#define SR_TEST_TRUTH_H

#include "align/align.h"
#include "mesh/mesh.h"
#include "paper/patch.h"
#include "base/status.h"
#include "base/symmetry.h"

typedef struct sr_truth {
    char name[96];
    sr_symmetry symmetry;      /* kind, order (0 = absent), shift_mm (glide, else 0) */
    double intact_volume;      /* mm^3 */
    double missing_volume;     /* mm^3 */
    double R[9];               /* pose.rotation_matrix_3x3, row-major */
    double t[3];               /* pose.translation */
} sr_truth;

/* Reads `path` (a truth.json). *out only on success; SR_E_IO when the file cannot be
 * read, SR_E_FORMAT naming the missing or malformed key otherwise. */
sr_status sr_truth_read(const char *path, sr_truth *out, sr_err *err);

/* The 3x4 row-major transform posed -> canonical: p_can = R^T (p - t). */
void sr_truth_to_canonical(const sr_truth *truth, double m[12]);

/* How far a found symmetry element is from the truth, in the posed frame.
 *  angle_deg: axial, the angle between the found axis and the pose's z axis (sign
 *             ignored); mirror/glide, the angle between the found plane normal and the
 *             pose's x axis (sign ignored).
 *  offset_mm: axial, the distance from the true axis point nearest `centre` to the
 *             found axis line; mirror/glide, the distance of the true plane's point
 *             nearest `centre` from the found plane.
 * centre: a point near the middle of the part (e.g. its bbox centre), posed frame. */
typedef struct sr_truth_align_error {
    double angle_deg, offset_mm;
} sr_truth_align_error;
void sr_truth_align_error_of(const sr_truth *truth, const sr_alignment *found,
                             const double centre[3], sr_truth_align_error *out);

/* How well the patches of `sections` (count of them, in the scan's frame, where they are
 * reported) fill the truth: *outside = patch volume outside `intact`, *covered = the
 * part of `missing` the patches cover, mm^3, by CGAL booleans. intact and missing are
 * canonical; they are moved to the scan's frame by the inverse of m (scan -> canonical,
 * e.g. sr_truth_to_canonical), so the patches are taken as they are. Outputs only on
 * success; a boolean's refusal is returned with its message. */
sr_status sr_truth_patch_overlap(const sr_section *sections, size_t count, const double m[12],
                                 const sr_mesh *intact, const sr_mesh *missing,
                                 double *outside, double *covered, sr_err *err);

#endif
