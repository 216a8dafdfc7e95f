/*
 * catalog_history.h: the questions a shop asks of its repair history, answered from
 * the run record (runs, sections, advice of sql/001_init.sql, indexed for this by
 * sql/003_history.sql, summed per part and month by sql/004_history_summary.sql): which runs were made for a part, an instance, a material or
 * in a date range, with their damage classes, missing volumes, advice and outcomes;
 * and summaries over the same selection (most frequent damage class and average
 * missing volume per part, repair vs replace, runs per month).
 *
 * The outcome of a run is read from its advice: "replace" when any advice says
 * replace (process 'replace', or beginning 'replace'), "repair" when there is other
 * advice, "none" when the run has no advice (nothing missing, or a failed run).
 * Dates filter the run's start time (UTC), both ends inclusive.
 */
#ifndef SR_CATALOG_HISTORY_H
#define SR_CATALOG_HISTORY_H

#include <stddef.h>
#include <stdint.h>

#include "catalog/catalog.h"
#include "base/status.h"
#include "base/symmetry.h"

/* Which runs. Every condition given must hold; NULL / 0 = any. */
typedef struct sr_history_filter {
    const char *part;           /* part number (ignoring ASCII case) or id */
    int64_t instance_id;        /* instance id; 0 = any */
    const char *material;       /* material name, ignoring ASCII case */
    const char *since;          /* 'YYYY-MM-DD': runs started on or after that day */
    const char *until;          /* 'YYYY-MM-DD': runs started on or before that day */
    const char *verdict;        /* 'pass', 'machine', 'rework': runs whose latest
                                 * inspection (catalog_inspect.h) said so */
} sr_history_filter;

typedef enum sr_history_outcome {
    SR_OUTCOME_NONE = 0,        /* no advice */
    SR_OUTCOME_REPAIR,          /* advice, none of it replace */
    SR_OUTCOME_REPLACE,         /* some advice says replace */
} sr_history_outcome;

/* "none", "repair", "replace". */
const char *sr_history_outcome_str(sr_history_outcome o);

/* One run of the history. Comma lists are distinct values in alphabetical order; one
 * too long for its field is cut after the last whole value that fits. */
typedef struct sr_history_row {
    int64_t run_id, instance_id;
    char started_at[32];        /* UTC ISO 8601 */
    char date[11];              /* its day, 'YYYY-MM-DD' */
    char part_number[64];
    char serial[64];            /* "" = unknown */
    char material[64];          /* "" = not given */
    sr_symmetry symmetry;
    char method[16];
    int ok;                     /* 1 ok, 0 failed */
    size_t section_count;
    double missing_volume_mm3;  /* sum of the sections' volumes */
    char classes[256];          /* damage classes, comma list; "" = no sections */
    char processes[256];        /* advised processes, comma list; "" = no advice */
    sr_history_outcome outcome;
    char verdict[8]; /* the latest inspection's verdict; "" = not inspected */
} sr_history_row;

/* Checks the filter alone (the checks and errors of sr_catalog_history below), so a
 * caller can refuse a bad filter before it prints anything. */
sr_status sr_catalog_history_check(sr_catalog *cat, const sr_history_filter *filter,
                                   sr_err *err);

/* Checks the filter (dates real 'YYYY-MM-DD', since <= until, a known verdict:
 * SR_E_RANGE naming the field; an unknown part, instance or material: SR_E_NOTFOUND "no part 'X' in the
 * catalogue" ...), then calls fn for each matching run, newest first (start time,
 * then id). fn returns non-zero to stop. No catalogue call may run inside fn. */
typedef int (*sr_history_fn)(const sr_history_row *row, void *user);
sr_status sr_catalog_history(sr_catalog *cat, const sr_history_filter *filter,
                             sr_history_fn fn, void *user, sr_err *err);

/* Per part, over the selected runs. */
typedef struct sr_history_part {
    char part_number[64];
    size_t runs;
    double avg_missing_volume_mm3;  /* mean over the part's runs of their missing volume */
    char top_class[32];         /* most frequent damage class of its sections ("" = none);
                                   ties go to the alphabetically first */
    size_t top_class_sections;  /* sections of that class */
    size_t sections;            /* sections of all classes */
    size_t repair, replace;     /* runs by outcome */
} sr_history_part;

typedef struct sr_history_month {
    char month[8];              /* 'YYYY-MM' of the start time */
    size_t runs;
} sr_history_month;

typedef struct sr_history_summary {
    size_t runs, failed;        /* selected runs; of them failed */
    size_t repair, replace, none;  /* runs by outcome */
    size_t pass, machine, rework;  /* runs by their latest inspection's verdict (the
                                    * others were not inspected) */
    double repair_fraction;     /* repair / (repair + replace); NaN when both are 0 */
    double avg_missing_volume_mm3;  /* over all selected runs; 0 when none */
    sr_history_part *parts;     /* by part number */
    size_t part_count;
    sr_history_month *months;   /* oldest first */
    size_t month_count;
} sr_history_summary;

/* Summaries over the runs the filter selects (the same checks and errors as
 * sr_catalog_history). *out only on success; release with sr_history_summary_release.
 * Answered from the running totals per part and month of sql/004_history_summary.sql
 * when the filter selects whole months (no instance, dates from a 1st to a month's
 * last day or open), else from the runs; the figures are the same either way (the
 * average volumes to the rounding of their sums). */
sr_status sr_catalog_history_summary(sr_catalog *cat, const sr_history_filter *filter,
                                     sr_history_summary *out, sr_err *err);
void sr_history_summary_release(sr_history_summary *s);

#endif
