/*
 * reconstruct.h: one reconstruction of a damaged scan, end to end: align (align.h),
 * slice (slice.h, Alg. 2), analyse (analyse.h, Alg. 4/5), build the sections' closed
 * patch meshes (patch.h, Alg. 6) and the restored part (damaged ∪ patches by CGAL's
 * corefinement, boolean.h). Results are in the frame of the input scan so they overlay
 * it; the layer grid and analysis stay in the aligned frame. No I/O, no catalogue: the
 * CLI reads the input and records the result.
 */
#ifndef SR_RECONSTRUCT_H
#define SR_RECONSTRUCT_H

#include "align/align.h"
#include "images/image_restore.h"
#include "paper/analyse.h"
#include "mesh/mesh.h"
#include "align/order_detect.h"
#include "paper/patch.h"
#include "slice/slice.h"
#include "base/progress.h"
#include "base/symmetry.h"

/* Which reconstruction runs between alignment and the union. */
typedef enum sr_recon_method {
    SR_METHOD_IMAGE = 0,        /* default: the scan's own images under the symmetry,
                                 * voted on voxels and clipped exactly
                                 * (images/image_restore.h) */
    SR_METHOD_PAPER = 1,        /* the paper's Algorithms 4-6 on the sector grid */
    SR_METHOD_ROBUST = 2,       /* real cross-sections restored layer by layer by the
                                 * symmetry's vote (region_sections.h): the method
                                 * before the image one */
} sr_recon_method;

/* "robust" / "paper" / "image"; parse returns SR_E_RANGE naming `field` for anything else. */
const char *sr_recon_method_name(sr_recon_method m);
sr_status sr_recon_method_parse(const char *text, const char *field, sr_recon_method *out,
                                sr_err *err);

/* Valid when zeroed but for the symmetry. A 0 marked "default set" takes the value of
 * the 'default' parameter set from the core's table (run/params_default.h: 320 layers,
 * 240 sectors, gamma 0.95, delta_d 0.05, 1 mm^3), resolved by sr_reconstruct. */
typedef struct sr_recon_opts {
    sr_symmetry symmetry;       /* axial: order SR_ORDER_AUTO finds it (order_detect.h) */
    sr_recon_method method;     /* default (0) image */
    double open_mm;             /* robust: noise filter radius; 0 = from the scan's noise */
    double min_volume_mm3;      /* smallest section kept, every method; 0 = default set */
    size_t layers;              /* 0 = default set */
    size_t sectors;             /* 0 = default set */
    double gamma_axis;          /* 0 = default set */
    double gamma_plane;         /* 0 = default set */
    double delta_d;             /* 0 = default set */
    double pitch_mm;            /* image: voxel pitch; 0 = from the part's size */
    double min_depth_mm;        /* depth below which a cell is not damage; 0 = none (not
                                 * the default set's 0.1 mm: the CLI passes that) */
    int have_alignment;         /* 1: use `alignment` instead of searching (override) */
    sr_alignment alignment;
    int skip_union;             /* 1: restored = scan + patches as separate shells */
    int threads;                /* threads of the alignment's queries and the image
                                 * method's vote; 0 = all cores. The result is the same
                                 * for any number */
    const sr_progress *progress; /* told each phase as it starts; NULL = nobody */
    const sr_mesh *gap_fills;    /* image: the triangles the closing of an open scan made
                                 * (sr_scan_desc.fills), the scan's frame; a section lying
                                 * behind them is a gap's (sr_gap_sag). NULL = none */
} sr_recon_opts;

/* Image method: what lay behind the fill of a scan gap (a lens between the flat fill and
 * the surface the scanner did not see), restored with the part but not a section: no
 * damage, no repair. */
typedef struct sr_gap_sag {
    double volume_mm3;
    double depth_max_mm; /* deepest, from the fill out to the restored surface */
    double fill_share;   /* share of its patch's surface lying on the fills */
    double centre[3];    /* of the part of it on the fills, scan frame, mm */
} sr_gap_sag;

/* Seconds per phase. analyse_s covers every method's finding of the sections (for the
 * image method: vote_s + clip_s + continue_s); union_s the union, the mending of what
 * it refused and the move back to the scan's frame; finish_s the figures read back
 * from the restored part. */
typedef struct sr_recon_timings {
    double align_s, slice_s, analyse_s, patch_s, union_s, total_s;
    double unfold_s;            /* image: the noisy scan's folds undone */
    double vote_s;              /* image: occupancy, vote, sections grouped */
    double clip_s;              /* image: hulls and the images clipped to them */
    double continue_s;          /* image, mirror: the layer method across the plane */
    double finish_s;            /* figures from the restored part, volumes */
} sr_recon_timings;

typedef struct sr_recon_result {
    sr_alignment alignment;
    sr_layer_grid grid;         /* damaged outline, aligned frame */
    sr_analysis analysis;       /* restored outline + damaged cells */
    sr_section *sections;       /* patches in the scan frame */
    size_t section_count;
    sr_mesh restored;           /* scan frame */
    int restored_by_union;      /* 1: one closed surface from the boolean union */
    char union_note[600];       /* why the union fell back, if it did */
    char repair_note[200];      /* what was repaired in the scan for the union, if anything */
    double scan_volume_mm3, restored_volume_mm3, patch_volume_mm3;
    sr_recon_method method;     /* the method that ran */
    double open_mm;             /* robust: the noise filter radius used */
    double noise_mm;            /* robust: the scan noise estimated from the fit, mm */
    int order;                  /* axial: the order used (0 = continuous) */
    int order_auto;             /* 1: it was found (order_found holds the figures) */
    sr_order_detection order_found;
    sr_image_info image;        /* image method: pitch, voxels, phase times */
    size_t unfold_pairs;        /* image: crossing triangle pairs of the scan found ... */
    size_t unfold_left;         /* ... of which still crossing after the unfolding */
    size_t unfold_sliver_tris;  /* folded slivers' triangles gone (needles collapsed) */
    size_t unfold_vertices;     /* scan vertices moved to unfold them */
    double unfold_max_mm;       /* the farthest one moved */
    sr_gap_sag *gap_sags;       /* image, open scans: sections found behind gap fills,
                                 * taken out of sections (restored all the same) */
    size_t gap_sag_count;
    sr_recon_timings timings;
} sr_recon_result;

/* The phases of t in their order with their names ("align", "slice", "unfold", "vote",
 * "clip", "continue", "analyse", "patch", "union", "finish", "total"): writes up to
 * SR_RECON_PHASES names and seconds, returns the count. */
#define SR_RECON_PHASES 11
size_t sr_recon_timings_list(const sr_recon_timings *t, const char *names[],
                             double seconds[]);

/* Runs the pipeline. *out only on success (release with sr_recon_result_release). */
sr_status sr_reconstruct(const sr_mesh *scan, const sr_recon_opts *opts, sr_recon_result *out,
                         sr_err *err);

/* sr_reconstruct on a scan handed over, so that a big scan is held once, not twice: the
 * image method unfolds it in place (a noisy scan's folds undone: its own arrays are
 * released before the unfolded ones are made; its closed slivers dropped). On return,
 * also on failure, *scan is the scan the reconstruction used (unfolded where noise had
 * folded it, else as given), the caller's to release; empty only when the unfolding ran
 * out of memory after the scan's arrays went (SR_E_NOMEM). The result is the same as
 * sr_reconstruct's on the scan as given. */
sr_status sr_reconstruct_owned(sr_mesh *scan, const sr_recon_opts *opts, sr_recon_result *out,
                               sr_err *err);

void sr_recon_result_release(sr_recon_result *r);

#endif
