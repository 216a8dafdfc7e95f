/*
 * run_scan.h: the run's record of its input read as a scan (run.h's sr_run_scan), made
 * from the description of the scan (mesh/scan_describe.h). Pure C, no I/O.
 */
#ifndef SR_RUN_SCAN_H
#define SR_RUN_SCAN_H

#include "base/status.h"
#include "mesh/scan_describe.h"
#include "run/run.h"

/* *out gets a new record (sr_run_scan_free) of d: its figures and one gap per loop,
 * closed_by from how (d->loop_count entries; NULL: every gap 'open'). A closed input
 * without strays (or d NULL) is no scan record: *out NULL, SR_OK. SR_E_NOMEM. */
sr_status sr_run_scan_from_desc(const sr_scan_desc *d, const sr_scan_closing *how,
                                sr_run_scan **out, sr_err *err);

#endif
