/*
 * progress.h: how long work tells its caller where it is. The library calls a sink at
 * each phase (and, where a phase loops over items it knows the count of, per item);
 * the CLI draws it on stderr (cli/progress.c). A NULL sink, or one without a function,
 * costs one test per call. Calls come from the calling thread only, never from inside
 * a parallel loop.
 */
#ifndef SR_PROGRESS_H
#define SR_PROGRESS_H

#include <stddef.h>

/* phase: a short name ("align", "union"); done of total steps of the whole job
 * (total 0: not known). */
typedef void (*sr_progress_fn)(void *user, const char *phase, size_t done, size_t total);

typedef struct sr_progress {
    sr_progress_fn fn;
    void *user;
} sr_progress;

static inline void sr_progress_step(const sr_progress *p, const char *phase, size_t done,
                                    size_t total)
{
    if (p && p->fn)
        p->fn(p->user, phase, done, total);
}

#endif
