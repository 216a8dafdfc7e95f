/*
 * progress.c: progress of long work on stderr (progress.h says what is shown when).
 * The work thread stores the phase under a mutex; a ticker thread wakes every 100 ms
 * and draws. Only one progress runs at a time (a command's work is one job).
 */
#include "progress.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

struct cli_progress {
    sr_progress sink;
    char what[32];
    double t0, after;
    bool tty;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t ticker;
    bool stop;
    /* where the work is */
    char phase[32];
    size_t done, total;
    unsigned serial; /* bumped at each phase */
    /* what was shown */
    unsigned shown; /* serial of the last plain line */
    bool drawn;     /* a bar is on the terminal line */
    bool printed;   /* anything was shown */
};

static cli_progress *active;
static pthread_mutex_t active_lock = PTHREAD_MUTEX_INITIALIZER;

double cli_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Draws or prints what is due; p->lock held. */
static void draw(cli_progress *p)
{
    double t = cli_now_s() - p->t0;
    if (t < p->after || !p->phase[0])
        return;
    if (p->tty) {
        char bar[21];
        size_t fill = p->total ? 20 * p->done / p->total : 0;
        for (size_t i = 0; i < 20; i++)
            bar[i] = i < fill ? '#' : '-';
        bar[20] = 0;
        if (p->total)
            fprintf(stderr, "\r\033[Ksymrec: %s [%s] %zu/%zu %s  %.1f s", p->what, bar, p->done + 1,
                    p->total, p->phase, t);
        else
            fprintf(stderr, "\r\033[Ksymrec: %s: %s  %.1f s", p->what, p->phase, t);
        fflush(stderr);
        p->drawn = true;
        p->printed = true;
    } else if (p->shown != p->serial) {
        if (p->total)
            fprintf(stderr, "symrec: %s: %s (%zu/%zu) at %.1f s\n", p->what, p->phase, p->done + 1,
                    p->total, t);
        else
            fprintf(stderr, "symrec: %s: %s at %.1f s\n", p->what, p->phase, t);
        fflush(stderr);
        p->shown = p->serial;
        p->printed = true;
    }
}

static void *tick(void *arg)
{
    cli_progress *p = arg;
    pthread_mutex_lock(&p->lock);
    while (!p->stop) {
        draw(p);
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 100000000L;
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&p->wake, &p->lock, &until);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

static void sink_fn(void *user, const char *phase, size_t done, size_t total)
{
    cli_progress_phase(user, phase, done, total);
}

cli_progress *cli_progress_begin(bool quiet, const char *what)
{
    if (quiet)
        return NULL;
    cli_progress *p = calloc(1, sizeof *p);
    if (!p)
        return NULL; /* progress is a courtesy: the work goes on without it */
    snprintf(p->what, sizeof p->what, "%s", what);
    p->t0 = cli_now_s();
    p->after = 1.0;
    const char *env = getenv("SYMREC_PROGRESS_AFTER");
    if (env && *env) {
        char *end;
        double v = strtod(env, &end);
        if (*end == 0 && v >= 0 && v < 1e6)
            p->after = v;
    }
    p->tty = isatty(STDERR_FILENO) != 0;
    p->sink.fn = sink_fn;
    p->sink.user = p;
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    if (pthread_create(&p->ticker, NULL, tick, p) != 0) {
        pthread_mutex_destroy(&p->lock);
        pthread_cond_destroy(&p->wake);
        free(p);
        return NULL;
    }
    pthread_mutex_lock(&active_lock);
    active = p;
    pthread_mutex_unlock(&active_lock);
    return p;
}

const sr_progress *cli_progress_sink(cli_progress *p)
{
    return p ? &p->sink : NULL;
}

void cli_progress_phase(cli_progress *p, const char *phase, size_t done, size_t total)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    snprintf(p->phase, sizeof p->phase, "%s", phase ? phase : "");
    p->done = done;
    p->total = total;
    p->serial++;
    draw(p); /* every phase shown, however short (once past the delay) */
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

void cli_progress_end(cli_progress *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&active_lock);
    if (active == p)
        active = NULL;
    pthread_mutex_unlock(&active_lock);
    pthread_mutex_lock(&p->lock);
    p->stop = true;
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    pthread_join(p->ticker, NULL);
    if (p->tty && p->drawn)
        fputs("\r\033[K", stderr);
    else if (!p->tty && p->printed)
        fprintf(stderr, "symrec: %s: done in %.1f s\n", p->what, cli_now_s() - p->t0);
    fflush(stderr);
    pthread_mutex_destroy(&p->lock);
    pthread_cond_destroy(&p->wake);
    free(p);
}

void cli_progress_interrupt(void)
{
    pthread_mutex_lock(&active_lock);
    cli_progress *p = active;
    if (p) {
        pthread_mutex_lock(&p->lock);
        if (p->tty && p->drawn) {
            fputs("\r\033[K", stderr);
            p->drawn = false;
        }
        pthread_mutex_unlock(&p->lock);
    }
    pthread_mutex_unlock(&active_lock);
}
