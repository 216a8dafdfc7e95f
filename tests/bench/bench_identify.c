/*
 * bench_identify.c: section 6 of `make bench`, the Done-when experiment of `symrec
 * identify` (issue 19, item 1). A catalogue (build/bench-identify/cat.db, made anew
 * each run) holds the nine shared intact parts (../shared/parts or $SYMREC_PARTS),
 * the demo parts and the intact parts of ../shared/partgen sets as distractors
 * (similar families, other dimensions):
 *   - $SYMREC_IDENTIFY_GEN: colon-separated folders of partgen output (each part a
 *     folder with intact.stl), e.g. the Makefile's IDENTIFY_GEN_DIRS;
 *   - otherwise build/bench-identify/gen, made once by `partgen --seed 6262 --count
 *     100 --no-scan` (intact models only; minutes the first time, then cached).
 * Then every shared part's posed (damaged_posed.stl) and noisy (damaged_scan.stl)
 * scan is identified: right when its own part is first with the verdict `match`,
 * alone or among the numbers of one design (identify names a design filed twice as
 * one answer); the margin is its score minus the next other design's. Each scan
 * again with its own part removed: right when the verdict is `no match`. Two demo
 * parts are the same design as two shared parts (twin_of): with the shared part
 * removed, the demo part's match is counted apart. Last, the catalogue is filled with
 * copies of distractors scaled by 0.9 and 1.1 up to 200 parts, and the 18 scans are
 * identified again, timed (sr_catalog_identify: descriptors read, pre-filter,
 * registrations; the scan file already read) against the 0.5 s target.
 */
#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bridge/mesh_io.h"
#include "catalog/catalog_identify.h"
#include "mesh/shapes.h"

static const char *const shared[] = {
    "bracket_broken_ear", "bushing_gouged",     "flange_broken_rim",      "keyed_shaft_dent",
    "lever_posed",        "rail_glide_chipped", "shaft_chipped_shoulder", "spur_gear_broken_tooth",
    "u_clamp_broken_arm",
};
#define NSHARED (sizeof shared / sizeof shared[0])
#define TARGET_PARTS 200

/* Demo parts of the same design as a shared part (the same dimensions: the notes of
 * both say so): with both in the catalogue, the match names the two as one design,
 * and with the shared part removed the demo part is a right match, reported apart
 * from the strict count. */
static const char *twin_of(const char *part)
{
    if (strcmp(part, "bushing_gouged") == 0)
        return "SR-BUSH-02"; /* OD 50 / ID 30 / length 60 */
    if (strcmp(part, "shaft_chipped_shoulder") == 0)
        return "SR-SHAFT-01"; /* dia 40 / 60 / 30 steps, 100 long */
    return NULL;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static bool add_part(sr_catalog *cat, const char *number, const char *name, const sr_mesh *m)
{
    sr_err err;
    sr_part_new p = {.number = number, .name = name, .mesh = m, .allow_open = 1};
    if (sr_catalog_part_add(cat, &p, NULL, &err) != SR_OK) {
        printf("  cannot add part %s: %s\n", number, err.msg);
        return false;
    }
    return true;
}

/* The folders of distractor parts: $SYMREC_IDENTIFY_GEN, or a cached partgen set. */
static const char *gen_dirs(char *buf, size_t size)
{
    const char *env = getenv("SYMREC_IDENTIFY_GEN");
    if (env && *env)
        return env;
    const char *dir = "build/bench-identify/gen";
    snprintf(buf, size, "%s", dir);
    struct stat sb;
    if (stat("build/bench-identify/gen/README.md", &sb) == 0)
        return buf;
    if (access("../shared/partgen/partgen", X_OK) != 0)
        return NULL;
    printf("  making 100 distractor parts: partgen --seed 6262 --count 100 --no-scan (once; "
           "intact models only, about ten minutes)\n");
    if (system("../shared/partgen/partgen --seed 6262 --count 100 --no-scan --out "
               "build/bench-identify/gen --jobs 2 > build/bench-identify/gen.log 2>&1") != 0)
        return NULL;
    return buf;
}

/* Adds every <dir>/<part>/intact.stl of the folders in `dirs` (colon-separated);
 * returns how many. Keeps their paths in *paths for the scaled copies. */
static size_t add_distractors(sr_catalog *cat, const char *dirs, glob_t *g)
{
    char *copy = strdup(dirs);
    size_t added = 0;
    int flags = 0;
    for (char *tok = strtok(copy, ":"); tok; tok = strtok(NULL, ":")) {
        char pat[1024];
        snprintf(pat, sizeof pat, "%s/*/intact.stl", tok);
        glob(pat, flags, NULL, g);
        flags = GLOB_APPEND;
    }
    free(copy);
    for (size_t i = 0; i < g->gl_pathc; i++) {
        sr_mesh m;
        if (sr_mesh_read(g->gl_pathv[i], &m, NULL) != SR_OK)
            continue;
        char number[64], name[128];
        snprintf(number, sizeof number, "GEN-%03zu", i);
        const char *e = strrchr(g->gl_pathv[i], '/'), *b = e;
        while (b > g->gl_pathv[i] && b[-1] != '/')
            b--;
        snprintf(name, sizeof name, "%.*s", (int)(e - b), b);
        if (add_part(cat, number, name, &m))
            added++;
        sr_mesh_release(&m);
    }
    return added;
}

typedef struct tally {
    int right, twin, total;
    double min_margin, max_s, sum_s, cpu_s;
    int runs;
} tally;

/* Identifies each shared part's posed and noisy scans; `own` true: each must be its
 * part with a match, false: (the part removed first) no match. */
static void identify_all(sr_catalog *cat, const char *parts, bool own, tally *t, bool print)
{
    static const char *const files[2] = {"damaged_posed.stl", "damaged_scan.stl"};
    for (size_t p = 0; p < NSHARED; p++) {
        sr_part_info removed_info;
        sr_mesh removed_mesh;
        sr_mesh_init(&removed_mesh);
        if (!own) { /* take the part out, to put it back after */
            if (sr_catalog_part_find(cat, shared[p], &removed_info, NULL) != SR_OK ||
                sr_catalog_part_mesh(cat, removed_info.id, &removed_mesh, NULL) != SR_OK ||
                sr_catalog_part_remove(cat, shared[p], 0, NULL, NULL) != SR_OK) {
                printf("  cannot remove %s\n", shared[p]);
                continue;
            }
        }
        for (int f = 0; f < 2; f++) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s/%s", parts, shared[p], files[f]);
            sr_mesh scan;
            sr_err err;
            if (sr_mesh_read(path, &scan, &err) != SR_OK) {
                printf("  %s\n", err.msg);
                continue;
            }
            sr_identify_result res;
            double t0 = now_s();
            clock_t c0 = clock();
            sr_status st = sr_catalog_identify(cat, &scan, NULL, &res, &err);
            double dt = now_s() - t0;
            t->cpu_s += (double)(clock() - c0) / CLOCKS_PER_SEC;
            sr_mesh_release(&scan);
            if (st != SR_OK) {
                printf("  %s: %s\n", path, err.msg);
                continue;
            }
            t->total++;
            t->runs++;
            t->sum_s += dt;
            if (dt > t->max_s)
                t->max_s = dt;
            const sr_identify_candidate *a = &res.cand[0];
            size_t k = res.same_design;
            double margin = a->fit.score - (res.registered > k ? res.cand[k].fit.score : 0);
            /* its own part first: alone, or among the numbers of its one design */
            bool own_first = false;
            for (size_t i = 0; i < k && res.verdict == SR_IDENTIFY_MATCH; i++)
                own_first = own_first || strcmp(res.cand[i].number, shared[p]) == 0;
            bool ok = own ? own_first : res.verdict == SR_IDENTIFY_NO_MATCH;
            const char *twin = twin_of(shared[p]);
            bool by_twin = false;
            if (!ok && twin && !own && res.verdict == SR_IDENTIFY_MATCH)
                by_twin = strcmp(a->number, twin) == 0;
            if (ok)
                t->right++;
            if (by_twin)
                t->twin++;
            if (own && ok && (t->min_margin < 0 || margin < t->min_margin))
                t->min_margin = margin;
            if (print || (!ok && !by_twin))
                printf("  %-24s %-6s %-8s first %-22.22s score %.3f cover %5.1f %% lack %5.1f %% "
                       "margin %.3f  %.3f s%s\n",
                       shared[p], f ? "noisy" : "posed",
                       res.verdict == SR_IDENTIFY_MATCH       ? "match"
                       : res.verdict == SR_IDENTIFY_TOO_CLOSE ? "close"
                                                              : "no-match",
                       a->number, a->fit.score, 100 * a->fit.coverage, 100 * a->fit.lacking, margin,
                       dt,
                       ok        ? ""
                       : by_twin ? "  (a demo part of the same design)"
                                 : "  WRONG");
            sr_identify_result_release(&res);
        }
        if (!own) {
            add_part(cat, shared[p], shared[p], &removed_mesh);
            sr_mesh_release(&removed_mesh);
        }
    }
}

void bench_identify(void);
void bench_identify(void)
{
    const char *parts = getenv("SYMREC_PARTS");
    if (!parts || !*parts)
        parts = "../shared/parts";
    char probe[1024];
    snprintf(probe, sizeof probe, "%s/%s/intact.stl", parts, shared[0]);
    if (access(probe, R_OK) != 0) {
        printf("  skipped: no shared parts in '%s'\n", parts);
        return;
    }
    mkdir("build", 0777);
    mkdir("build/bench-identify", 0777);
    char genbuf[256];
    const char *gen = gen_dirs(genbuf, sizeof genbuf);
    if (!gen) {
        printf(
            "  skipped: no distractors ($SYMREC_IDENTIFY_GEN unset, partgen failed or absent)\n");
        return;
    }
    const char *db = "build/bench-identify/cat.db";
    unlink(db);
    char side[300];
    snprintf(side, sizeof side, "%s-wal", db);
    unlink(side);
    snprintf(side, sizeof side, "%s-shm", db);
    unlink(side);
    sr_catalog *cat;
    sr_err err;
    if (sr_catalog_open(db, SR_CATALOG_CREATE, &cat, &err) != SR_OK) {
        printf("  %s\n", err.msg);
        return;
    }
    double t0 = now_s();
    size_t n = 0;
    for (size_t i = 0; i < NSHARED; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s/intact.stl", parts, shared[i]);
        sr_mesh m;
        if (sr_mesh_read(path, &m, &err) == SR_OK && add_part(cat, shared[i], shared[i], &m))
            n++;
        sr_mesh_release(&m);
    }
    size_t demo = 0;
    for (size_t i = 0; i < sr_demo_part_count(); i++) {
        sr_mesh m;
        const sr_demo_part *d = sr_demo_part_get(i);
        if (sr_demo_part_build(i, &m, NULL, &err) == SR_OK && add_part(cat, d->number, d->name, &m))
            demo++;
        sr_mesh_release(&m);
    }
    glob_t g;
    memset(&g, 0, sizeof g);
    size_t dist = add_distractors(cat, gen, &g);
    printf("  catalogue: %zu shared + %zu demo + %zu partgen parts (%s), built with their "
           "descriptors in %.1f s\n",
           n, demo, dist, gen, now_s() - t0);
    tally own = {0, 0, 0, -1, 0, 0, 0, 0}, none = {0, 0, 0, -1, 0, 0, 0, 0};
    identify_all(cat, parts, true, &own, true);
    printf("  own part first with a match: %d / %d, smallest margin %.3f (score of the first "
           "minus the second); %d more too close to call between the part and its demo twin\n",
           own.right, own.total, own.min_margin, own.twin);
    identify_all(cat, parts, false, &none, true);
    printf("  own part removed, no match: %d / %d; %d more matched to the demo part of the same "
           "design\n",
           none.right, none.total, none.twin);
    /* up to 200 parts: scaled copies of the distractors */
    size_t count = n + demo + dist;
    for (size_t i = 0; count < TARGET_PARTS && i < 2 * g.gl_pathc; i++) {
        sr_mesh m;
        if (sr_mesh_read(g.gl_pathv[i / 2], &m, NULL) != SR_OK)
            continue;
        double s = i % 2 ? 1.1 : 0.9;
        const double xf[12] = {s, 0, 0, 0, 0, s, 0, 0, 0, 0, s, 0};
        sr_mesh_transform(&m, xf);
        char number[64];
        snprintf(number, sizeof number, "GEN-%03zu-x%.1f", i / 2, s);
        if (add_part(cat, number, "scaled distractor", &m))
            count++;
        sr_mesh_release(&m);
    }
    globfree(&g);
    tally timed = {0, 0, 0, -1, 0, 0, 0, 0};
    identify_all(cat, parts, true, &timed, false);
    printf("  %zu parts: identify (descriptors read, pre-filter, registrations) mean %.3f s, "
           "max %.3f s over %d scans (target < 0.5 s); CPU time (all threads) mean %.3f s; right "
           "%d / %d (+%d twins)\n",
           count, timed.runs ? timed.sum_s / timed.runs : 0, timed.max_s, timed.runs,
           timed.runs ? timed.cpu_s / timed.runs : 0, timed.right, timed.total, timed.twin);
    double load[3];
    if (getloadavg(load, 3) == 3)
        printf("  (load average %.1f on %ld CPUs while timing: other work shares them)\n", load[0],
               sysconf(_SC_NPROCESSORS_ONLN));
    sr_catalog_close(cat);
}
