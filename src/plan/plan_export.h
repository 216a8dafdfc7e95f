/*
 * plan_export.h: writes a build plan (plan.h) for people and machines: plan.json (every
 * layer's missing region, deposit region and paths, the figures, the units), one
 * layer_NNN.svg drawing per layer (NNN = layer number from 001, deposit region filled,
 * missing region outlined, paths drawn, a scale bar in mm) and plan.gcode for a DED or
 * spray-forming cell, with the machine parameters as a settings struct.
 *
 * G-code (RS-274 as LinuxCNC/Marlin read it): G21 (mm) and G90 (absolute) first, then
 * one block per layer opened by a comment "; layer N z=Z" where Z is the layer's top
 * (z_top_mm: the deposition height). Each path: G0 up to Z + travel height, G0 to its
 * first point, G0 down to Z, the "on" code, one "G1 X Y Z F" per further point (every G1
 * carries X, Y and the layer's Z and the feed), the "off" code. The program ends with
 * the off code, G0 up by the travel height and M2. The header comments give the build
 * time: exactly these moves, the G1 at their feed and the G0 at the rapid rate the
 * settings assume (sr_plan_time; the writer and the timer walk the same moves). Coordinates are the aligned frame of the run (the
 * symmetry axis or in-plane axis is z): set the part up with that axis along the
 * machine's z and the work zero on it.
 */
#ifndef SR_PLAN_EXPORT_H
#define SR_PLAN_EXPORT_H

#include "plan/plan.h"
#include "base/status.h"

/* Machine settings. Start from sr_plan_machine_init (a zeroed struct is not valid). */
typedef struct sr_plan_machine {
    double feed_mm_min;        /* deposition feed, > 0; default 0 = the plan's rate laid
                                  down as beads: rate / (step-over x layer) */
    double rapid_mm_min;       /* speed of the G0 travel moves, for the build time, > 0;
                                  default 5000 mm/min */
    double travel_height_mm;   /* clearance above the layer for travel, >= 0; default 5 */
    char on_code[32];          /* starts deposition (laser/spray on); default "M3" */
    char off_code[32];         /* stops it; default "M5" */
} sr_plan_machine;

void sr_plan_machine_init(sr_plan_machine *m);

/* The deposition feed of plan p under machine m (NULL = defaults): m's feed when set,
 * else p's rate over the bead cross-section (step-over x layer), in mm/min. */
double sr_plan_feed(const sr_plan *p, const sr_plan_machine *m);

/* Sets p's feed_mm_min, deposit_time_min, travel_length_mm, travel_time_min and
 * build_time_min to those of the moves plan.gcode makes under m (NULL = defaults).
 * SR_E_RANGE from sr_plan_machine_check. */
sr_status sr_plan_time(sr_plan *p, const sr_plan_machine *m, sr_err *err);

/* Range checks naming the field: feed_mm_min in [0, 1e6] (0 = from the rate),
 * rapid_mm_min in (0, 1e6], travel_height_mm in
 * [0, 1e4], codes 1..31 printable characters without ';', '(' or ')'. SR_E_RANGE. */
sr_status sr_plan_machine_check(const sr_plan_machine *m, sr_err *err);

/* Writes plan.json, layer_001.svg .. layer_NNN.svg and plan.gcode into dir (created
 * when missing; its parent must exist), each file mode 0666 & ~umask. SR_E_IO naming
 * the file on any failure (a file whose write failed is removed, files already
 * written are left: write into a folder of its own and put it in place once the
 * whole set is written, as `symrec plan` does). machine NULL = defaults. */
sr_status sr_plan_export(const sr_plan *plan, const sr_plan_machine *machine,
                         const char *dir, sr_err *err);

/* The single writers behind sr_plan_export. layer is 0-based. */
sr_status sr_plan_write_json(const sr_plan *plan, const sr_plan_machine *machine,
                             const char *path, sr_err *err);
sr_status sr_plan_write_svg(const sr_plan *plan, size_t layer, const char *path,
                            sr_err *err);
sr_status sr_plan_write_gcode(const sr_plan *plan, const sr_plan_machine *machine,
                              const char *path, sr_err *err);

#endif
