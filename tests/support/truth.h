/*
 * truth.h: the few answers the accuracy test and the benchmark need from a shared
 * part's truth.json (../shared/parts/<part>/truth.json, see its README): the
 * symmetry kind with its order or glide shift, the intact and missing volumes, and the
 * rigid pose that moved the canonical part into damaged_posed.stl / damaged_scan.stl
 * (p_posed = R p_canonical + t). A plain string search for each key, no JSON library:
 * the files are machine-written with unique top-level keys, and only these are read.
 * Plus the geometry the two consumers share: the posed frame's transform back to the
 * canonical frame, and the alignment error of a found axis or plane against the pose.
 */
#ifndef SR_TEST_TRUTH_H
#define SR_TEST_TRUTH_H

#include "align.h"
#include "mesh.h"
#include "status.h"
#include "symmetry.h"

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

#endif
