/*
 * nominal.h: the nominal model as a second opinion on a reconstruction (issue 19,
 * item 3). When the damaged instance's part has an intact mesh (its nominal, CAD
 * model), that mesh is registered to the scan (align/register.h: robust and trimmed,
 * so the missing material does not pull it; started from the reconstruction's symmetry
 * alignment when given, nominal_start.c), and what it has that the scan lacks,
 * registered intact − scan by one exact CGAL difference (bridge/boolean.h), is the
 * nominal's missing material. By default that is measured cell by cell instead
 * (nominal_cells.c: exact volumes per cell without a boolean, pieces without meshes), a
 * fraction of a second where the difference over nearly coincident surfaces takes
 * seconds, and closed scans that cross themselves (noisy ones), which the exact
 * difference refuses, are measured too; the exact difference runs when its meshes are
 * wanted (a restoration by the nominal). That is split into its connected pieces; pieces thinner
 * than the registration's own scatter are the slivers two tessellations of one surface
 * leave between them, not damage, and are dropped. Each kept piece is given to the
 * symmetry section whose patch it overlaps most; the figures per section (symmetry
 * volume, nominal volume, their disagreement in mm³ and %, and the surface deviation
 * between the patch and the nominal pieces) say where the two agree.
 *
 * The nominal is checked before it is believed: a scan of its part lies on it, so the
 * registration covers at least the part's intact share of it (register.h: a scan lacks
 * up to a quarter), and the scan holds no material the nominal lacks beyond a layer of
 * the registration tolerance over its surface. A nominal failing either (a different
 * part, a wrong revision) is flagged "does not fit this scan", with the figures.
 *
 * Geometry core plus the CGAL bridge, as reconstruct.h: no I/O, no catalogue. Results
 * are in the scan's frame, as the reconstruction's.
 */
#ifndef SR_NOMINAL_H
#define SR_NOMINAL_H

#include <stddef.h>

#include "align/align.h"
#include "align/register.h"
#include "base/status.h"
#include "mesh/mesh.h"
#include "paper/patch.h"

/* Valid when zeroed. */
typedef struct sr_nominal_opts {
    double tol_mm;         /* registration tolerance; 0 = register.h's default */
    size_t samples;        /* registration samples; 0 = register.h's default */
    double min_volume_mm3; /* smallest piece kept (the run's min_volume_mm3); 0 = 1 mm³ */
    const sr_alignment *alignment; /* the scan's symmetry alignment (the reconstruction's):
                                    * the registration starts from it; NULL = the full
                                    * start search of sr_register */
    int order;                     /* axial: the order the reconstruction used (0 =
                                    * continuous) */
    /* 1: the missing material by the exact difference, as meshes (`missing`: a
     * restoration by the nominal needs them; seconds on nearly coincident surfaces),
     * falling back to the cells when it refuses a scan that crosses itself; 0: measured
     * by cells (a fraction of a second; pieces without meshes) */
    int exact_pieces;
} sr_nominal_opts;

/* The smallest registration coverage a nominal of the scan's part reaches: a damaged
 * scan lacks up to a quarter of the part (register.h). */
#define SR_NOMINAL_MIN_COVERAGE 0.75

/* One piece of the nominal's missing material. */
typedef struct sr_nominal_piece {
    sr_mesh mesh; /* closed, scan frame */
    double volume_mm3, area_mm2;
    double thickness_mm; /* 2 V / A: a slab's thickness, a sliver's mean gap */
    long section;        /* the section with the largest share of it (0-based); -1 =
                          * most of it is near no section */
    double outside_mm3;  /* its share near no section's patch (only the nominal sees) */
    double centroid[3];  /* volume centroid of that share (of the whole piece when
                          * that share is under the smallest volume) */
} sr_nominal_piece;

/* One symmetry section beside the nominal pieces given to it. */
typedef struct sr_nominal_section {
    double symmetry_mm3; /* the section's volume as the symmetry found it */
    double nominal_mm3;  /* the nominal's volume near its patch (0 = none): each piece
                          * is split among the sections by where its surface lies (a
                          * thin skin over the part can join two damage sites into
                          * one piece) */
    double diff_mm3;     /* nominal − symmetry */
    double diff_pct;     /* diff as % of the nominal (of the symmetry when nominal is 0) */
    double dev_mean_mm;  /* mean distance from the patch's surface to the pieces' */
    double dev_max_mm;   /* the largest (at the vertices and centroids of the patch, or
                            * of 20,000 of its triangles evenly strided); both < 0
                            * when the section has no piece. One way only: a piece carries
                            * the thin skin two tessellations of one surface leave over the
                            * whole part where it touches it, which is not a deviation */
    size_t pieces;       /* pieces with a share of at least the smallest volume */
} sr_nominal_section;

typedef struct sr_nominal_result {
    sr_register_result reg;   /* intact -> scan */
    sr_mesh registered;       /* the intact mesh in the scan's frame */
    sr_mesh missing;          /* the kept pieces as one mesh (scan frame) */
    sr_nominal_piece *pieces; /* kept, largest first */
    size_t piece_count;
    sr_nominal_section *sections; /* one per symmetry section, same order */
    size_t section_count;
    size_t slivers;            /* pieces dropped as thinner than sliver_mm or smaller
                                 * than the smallest volume */
    double sliver_mm3;         /* their summed volume */
    double sliver_mm;          /* the thickness below which a piece is a sliver */
    double min_volume_mm3;     /* the smallest piece or share counted, as used */
    double nominal_mm3;        /* kept pieces' volume: the nominal's missing volume */
    double symmetry_mm3;       /* the sections' volume */
    double diff_mm3, diff_pct; /* nominal − symmetry, % as per section */
    double extra_mm3;          /* scan material outside the registered nominal */
    double extra_limit_mm3;    /* the scan's area x the registration tolerance */
    size_t only_nominal;       /* pieces with a share near no section of at least the
                                * smallest volume ... */
    double only_nominal_mm3;   /* ... and those shares' volume */
    size_t only_symmetry;      /* sections with no piece */
    int poor;                  /* 1: the nominal does not fit this scan (note says why) */
    char note[240];
    /* 1: the registration ran the full start search (no alignment, or the start from
     * it did not hold) */
    int full_search;
    /* 1: the volumes are measured cell by cell (the winding number's integral over each
     * cell of a grid: opts->exact_pieces 0, or the exact difference refused the scan):
     * pieces have no mesh, `missing` is empty and thickness_mm is 0 */
    int by_cells;
    double cell_mm; /* the cells' size when by_cells */
    /* why the exact difference refused ("" when not asked or when it did not) */
    char exact_note[200];
    double seconds;       /* time taken, s */
} sr_nominal_result;

/* The nominal's second opinion on a reconstruction of `scan` whose sections are
 * secs[0..count) (patches in the scan's frame; count may be 0). `intact` is the part's
 * intact mesh in any frame. opts may be NULL. SR_E_INVALID naming the mesh when the
 * registration or the measure refuses it (a scan or nominal that is not closed), with
 * the message; SR_E_NOMEM. *out only on success (release with sr_nominal_result_release). */
sr_status sr_nominal_compare(const sr_mesh *scan, const sr_mesh *intact, const sr_section *secs,
                             size_t count, const sr_nominal_opts *opts, sr_nominal_result *out,
                             sr_err *err);

/* Frees *r's meshes and arrays and zeroes it; accepts NULL and a zeroed result. */
void sr_nominal_result_release(sr_nominal_result *r);

#endif
