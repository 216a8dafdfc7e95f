/*
 * run.h: the record of one reconstruction run as plain data, owned by the core: the
 * parameter set it ran with (sr_params, with its range checks), its missing sections
 * with their feature-level description (sr_run_section), the advice the rules gave
 * (sr_run_advice) and the whole run (sr_run: what was asked, the alignment, the
 * per-layer polyline pairs, the sections, the advice, the restored mesh, the timings).
 *
 * The stages that fill a run (run_build.h, section_features.h, rules.h) and those that
 * read one (plan.h, report_html.h) need nothing but this header; the catalogue
 * (catalog_runs.h) stores and reads these structs but does not define them. A run's
 * heap fields belong to the run once it is built (sr_run_from_result) or read back
 * (sr_catalog_run_get): free them with sr_run_release.
 */
#ifndef SR_RUN_H
#define SR_RUN_H

#include <stddef.h>
#include <stdint.h>

#include "mesh/mesh.h"
#include "base/status.h"
#include "base/symmetry.h"

/* ---- named parameter sets ---- */

typedef struct sr_params {
    char name[64];
    int layers;                 /* N_layers, >= 1 */
    int sectors;                /* N_sectors, >= 3 */
    double gamma_axis;          /* Alg. 4 threshold, (0,1] */
    double gamma_plane;         /* Alg. 5 threshold, (0,1] */
    double delta_d;             /* Alg. 3 threshold, (0,1] */
    double min_depth_mm;        /* smallest depth reported as a section, >= 0 */
    double min_volume_mm3;      /* smallest volume reported as a section, >= 0 */
    char notes[256];
} sr_params;

/* Range checks of a parameter set; the message names the field. */
sr_status sr_params_check(const sr_params *p, sr_err *err);

/* ---- the run record ---- */

/* One missing section of a run, with its feature-level description. */
typedef struct sr_run_section {
    int64_t id;                 /* row id (read back; ignored by add) */
    size_t index;               /* 0 first (largest volume) */
    size_t layer_first, layer_last;
    double z_min_mm, z_max_mm;  /* aligned frame */
    int has_angles;             /* axial: 1, with the angular range below */
    double angle_from_deg;      /* [0, 360) */
    double angle_to_deg;        /* counter-clockwise end, may exceed 360 when wrapping */
    int side;                   /* planar: +1 / -1 side of the plane; 0 for axial */
    double volume_mm3, area_mm2, depth_max_mm, depth_mean_mm;
    char damage_class[32];      /* 'chip', 'gouge', 'wear_band', 'broken_feature', 'crack' ... */
    char *features_json;        /* further features as one JSON object; NULL = none */
    sr_mesh patch;              /* closed patch, scan frame; empty (0 triangles) = not kept */
} sr_run_section;

/* One piece of advice: for a section (section_index >= 0) or the whole part (-1). */
typedef struct sr_run_advice {
    long section_index;
    int64_t rule_id;            /* the rule that gave it; 0 = none (built in / deleted) */
    char rule_name[64];         /* read back (from the rule row, "" when gone) */
    char process[64];           /* 'spray_forming', 'ded', 'weld_buildup', 'replace', ... */
    char reason[512];
    char *details_json;         /* the plan and the rules fired, one JSON object; NULL = {} */
} sr_run_advice;

/* The nominal model's second opinion on a run (nominal.h), as recorded. */
typedef struct sr_run_nominal_section {
    size_t index; /* the run's section index (0 first) */
    double symmetry_mm3, nominal_mm3, diff_mm3, diff_pct;
    double dev_mean_mm, dev_max_mm; /* patch vs nominal surface; < 0 = no nominal piece */
    size_t pieces;
} sr_run_nominal_section;

typedef struct sr_run_nominal_piece {
    double volume_mm3, thickness_mm;
    long section;       /* the section with the largest share; -1 = none */
    double outside_mm3; /* its share near no section: only the nominal sees it */
    double centroid[3]; /* volume centroid of that share (of the piece when under
                           * min_volume_mm3), scan
                           * frame, mm */
} sr_run_nominal_piece;

typedef struct sr_run_nominal {
    char reference[16];              /* what the restoration is: 'symmetry' or 'nominal' */
    double transform[12];            /* intact -> scan, 3x4 row-major */
    double coverage, rms_mm, tol_mm; /* the registration's */
    double nominal_mm3, symmetry_mm3, diff_mm3, diff_pct;
    double sliver_mm, sliver_mm3;
    double min_volume_mm3; /* smallest piece or share counted */
    size_t slivers;
    double extra_mm3, extra_limit_mm3;
    int poor; /* 1: the nominal does not fit the scan (note) */
    char note[240];
    double seconds;
    /* how nominal_mm3 was measured: "exact" (one CGAL difference), "cells" (exact
     * volumes per cell of a grid of cell_mm), "" = not known (recorded before schema
     * version 10); exact_note: why the exact difference was refused ("" = it was not) */
    char method[8];
    double cell_mm;
    char exact_note[200];
    sr_run_nominal_section *sections;
    size_t section_count;
    sr_run_nominal_piece *pieces;
    size_t piece_count;
} sr_run_nominal;

/* Frees a nominal record (and its arrays); accepts NULL. */
void sr_run_nominal_free(sr_run_nominal *n);

/* How the nominal's missing material was measured, as a phrase for the CLI and the
 * report ("by one exact difference ...", "by cells of 0.250 mm ...; the exact
 * difference refused the scan: why", or that it was not recorded), into out. */
void sr_run_nominal_method_text(const sr_run_nominal *n, char *out, size_t size);

/* One opening of an open scan (mesh/scan_describe.h), closed before the reconstruction:
 * a scan gap, kept apart from the sections. */
typedef struct sr_run_scan_gap {
    size_t edges;
    double length_mm, area_mm2;
    double centre[3];  /* rim centroid, scan frame, mm */
    char closed_by[8]; /* 'plane', 'fan' or 'open' */
} sr_run_scan_gap;

/* The input read as a scan, as recorded (sql/011_scan_gaps.sql, 012_scan_sealed.sql,
 * 014_scan_uncurled.sql, 015_gap_sags.sql). */
typedef struct sr_run_scan {
    size_t triangles, boundary_edges, components, strays, stray_triangles;
    double open_area_mm2, open_share, stray_area_mm2;
    size_t sealed_triangles; /* cut out round the closing's defects and closed again */
    size_t uncurled_vertices; /* rim vertices merged where a rim twisted in its plane */
    size_t sags;           /* lenses restored behind gap fills, not sections (015_gap_sags.sql) */
    double sag_mm3;        /* their volume */
    sr_run_scan_gap *gaps; /* gap_count, longest rim first */
    size_t gap_count;
} sr_run_scan;

/* Frees a scan record (and its gaps); accepts NULL. */
void sr_run_scan_free(sr_run_scan *s);

typedef struct sr_run {
    int64_t id;                 /* read back; ignored by add */
    int64_t instance_id;        /* required */
    char part_number[64];       /* read back */
    sr_symmetry symmetry;       /* as used (glide: the shift found) */
    sr_params params;           /* every parameter as used, with the set's name */
    char method[16];            /* 'paper' or 'robust' */
    int has_alignment;          /* 0 when the run failed before aligning */
    double alignment[12];       /* scan -> aligned frame, 3x4 row-major (mesh.h) */
    int alignment_given;        /* 1 = set by the user */
    double fit_quality;         /* 0..1; < 0 = not reached */
    int ok;                     /* 1 ok, 0 failed (then error says why) */
    char error[512];
    char software_version[32];  /* SR_VERSION */
    char started_at[32], finished_at[32]; /* UTC ISO 8601; finished "" = did not finish */
    char *timings_json;         /* {"align":0.1,...} seconds; NULL = none */
    char *symmetry_fit_json;    /* the symmetry `--symmetry auto` proposed, the whole fit as
                                 * one JSON object (run/run_symfit.h); NULL = the symmetry
                                 * was the user's */

    size_t layer_count, sectors;
    double *layer_z;            /* layer_count heights, aligned frame */
    double *damaged_xy;         /* layer_count x sectors x (x, y); NaN = no point */
    double *restored_xy;        /* same shape */

    sr_run_section *sections;
    size_t section_count;
    sr_run_advice *advice;
    size_t advice_count;
    sr_mesh restored;           /* scan frame; empty = none */
    sr_run_nominal *nominal;    /* the nominal's second opinion; NULL = none */
    sr_run_scan *scan;          /* the input's openings and strays; NULL = a closed input */
    size_t unbuilt_sections;    /* found missing, no closed patch built: not in sections */
    double unbuilt_mm3;         /* their volume by the vote's voxels */
} sr_run;

/* Frees the heap fields of a run (built by sr_run_from_result or read by
 * sr_catalog_run_get) and zeroes it; accepts NULL. */
void sr_run_release(sr_run *run);

#endif
