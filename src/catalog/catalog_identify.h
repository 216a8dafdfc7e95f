/*
 * catalog_identify.h: which catalogue part a scan is of (`symrec identify`, `instance
 * add --part auto`), and the stored shape descriptors that make it quick
 * (sql/006_part_descriptor.sql).
 *
 * sr_catalog_identify ranks every part that has an intact mesh by the distance of its
 * shape descriptor (src/align/shape_descriptor.h: pose-invariant, scale kept) from
 * the scan's, registers the scan to the intact meshes of the closest few
 * (src/align/identify.h: trimmed, so the scan's damage does not pull the fit) and
 * sorts those by score. The verdict: a match when the best fit holds (coverage and
 * lacking within the bounds of identify.h); too close to call when the second scores
 * within SR_IDENTIFY_MARGIN of it; otherwise no match - a scan of a part that is not
 * in the catalogue must not be given another part's number.
 *
 * One design filed under two numbers (a copy of a part, a part renumbered) cannot be
 * ranked apart by any scan: candidates within the margin of the first whose intact
 * meshes are the first's (each registered to the other within the tolerance: the
 * coverage and lacking bounds of SR_IDENTIFY_SAME_*) are one answer, the first's
 * `same_design`, and the margin is taken to the next other design.
 */
#ifndef SR_CATALOG_IDENTIFY_H
#define SR_CATALOG_IDENTIFY_H

#include <stddef.h>
#include <stdint.h>

#include "align/identify.h"
#include "catalog/catalog.h"

/* Two intact meshes are one design when, the second registered to the first, at
 * least this share of each lies within the tolerance of the other (samples falling
 * between two tessellations of one surface aside) and the RMS is within the match
 * bound of identify.h. */
#define SR_IDENTIFY_SAME_COVERAGE 0.98
#define SR_IDENTIFY_SAME_LACKING 0.02

/* Parts always registered: the descriptor ranks the right part among the first few
 * on damaged scans (a quarter of the volume missing shifts the D2 distribution), and
 * the rest of the shortlist keeps the margin to the second honest. */
#define SR_IDENTIFY_SHORTLIST 4
/* Parts whose descriptor lies within this many octaves of the closest one are
 * registered too, up to SR_IDENTIFY_NEAR_MAX in all (or --top): damage moves a
 * scan's descriptor by up to a few hundredths of an octave (0.03 measured on the
 * shared parts' broken bracket). */
#define SR_IDENTIFY_NEAR_OCTAVES 0.05
#define SR_IDENTIFY_NEAR_MAX 10
#define SR_IDENTIFY_TOP_MAX 20
#define SR_IDENTIFY_TOP_DEFAULT 3

typedef struct sr_identify_opts {
    double tol_mm; /* 0: 0.5 % of the scan's bounding-box diagonal */
    size_t top;    /* candidates wanted (1..SR_IDENTIFY_TOP_MAX); 0 = SR_IDENTIFY_TOP_DEFAULT */
} sr_identify_opts;

typedef enum sr_identify_verdict {
    SR_IDENTIFY_NO_MATCH = 0,
    SR_IDENTIFY_MATCH,     /* cand[0] is the scan's part (cand[1..same_design - 1] its
                            * design under other numbers) */
    SR_IDENTIFY_TOO_CLOSE, /* cand[0] and another design both fit, within the margin */
} sr_identify_verdict;

typedef struct sr_identify_candidate {
    int64_t part_id;
    int64_t mesh_id; /* the part's intact mesh */
    char number[64];
    char name[128];
    double descriptor_distance; /* octaves */
    sr_identify_fit fit;
} sr_identify_candidate;

typedef struct sr_identify_result {
    sr_identify_verdict verdict;
    double tol_mm;    /* as used */
    size_t parts;     /* parts with an intact mesh compared */
    size_t described; /* their descriptors computed by this call */
    size_t stored;    /* of those, stored in the catalogue (0 when read-only) */
    size_t registered; /* parts registered to the scan (the shortlist) */
    size_t count;      /* candidates given, best score first (<= registered); cand[]
                        * holds all registered */
    size_t same_design; /* the first this many candidates are one design (>= 1 when
                         * count > 0); the margin is to cand[same_design] */
    sr_identify_candidate *cand;
} sr_identify_result;

/* Identifies `scan` (a validated mesh with some area) against the catalogue. Parts
 * without a stored descriptor of the current version get one computed, and stored
 * when the catalogue is writable (the backfill of migration 006). SR_E_NOTFOUND when
 * no part has an intact mesh; SR_E_RANGE for a bad opts->top or tol_mm; SR_E_INVALID
 * for the scan; SR_E_DB, SR_E_NOMEM. *out only on success; release it with
 * sr_identify_result_release. */
sr_status sr_catalog_identify(sr_catalog *cat, const sr_mesh *scan, const sr_identify_opts *opts,
                              sr_identify_result *out, sr_err *err);

/* Frees the candidates; accepts a zeroed result. */
void sr_identify_result_release(sr_identify_result *res);

/* The stored descriptor of a mesh; SR_E_NOTFOUND when it has none (of the current
 * version), SR_E_FORMAT for a damaged one. For checks and tests. */
sr_status sr_catalog_mesh_descriptor(sr_catalog *cat, int64_t mesh_id, sr_shape_descriptor *out,
                                     sr_err *err);

#endif
