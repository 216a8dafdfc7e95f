/*
 * synth_run.c: inline run records for the feature and rule tests (synth_run.h).
 */
#include "support/synth_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static void *must(void *p)
{
    if (!p) {
        fprintf(stderr, "synth_run: out of memory\n");
        abort();
    }
    return p;
}

void synth_run_make(sr_run *run, size_t layers, size_t sectors, double r_low, double r_high,
                    double z_step)
{
    memset(run, 0, sizeof *run);
    run->instance_id = 1;
    run->symmetry.kind = SR_SYM_AXIAL;
    snprintf(run->method, sizeof run->method, "paper");
    run->ok = 1;
    run->layer_count = layers;
    run->sectors = sectors;
    run->layer_z = must(calloc(layers, sizeof *run->layer_z));
    run->damaged_xy = must(calloc(layers * sectors * 2, sizeof *run->damaged_xy));
    run->restored_xy = must(calloc(layers * sectors * 2, sizeof *run->restored_xy));
    for (size_t l = 0; l < layers; l++) {
        run->layer_z[l] = (double)l + 0.5;
        double r = run->layer_z[l] < z_step ? r_low : r_high;
        for (size_t j = 0; j < sectors; j++) {
            double a = ((double)j + 0.5) * 2 * PI / (double)sectors;
            double *p = run->restored_xy + 2 * (l * sectors + j);
            p[0] = r * cos(a);
            p[1] = r * sin(a);
            run->damaged_xy[2 * (l * sectors + j)] = p[0];
            run->damaged_xy[2 * (l * sectors + j) + 1] = p[1];
        }
    }
}

sr_run_section *synth_run_dig(sr_run *run, size_t l0, size_t l1, size_t j0, size_t count,
                              double depth, int planar_side)
{
    size_t N = run->sectors;
    run->sections = must(realloc(run->sections, (run->section_count + 1) * sizeof *run->sections));
    sr_run_section *s = &run->sections[run->section_count];
    memset(s, 0, sizeof *s);
    s->index = run->section_count++;
    s->layer_first = l0;
    s->layer_last = l1;
    s->z_min_mm = (double)l0;
    s->z_max_mm = (double)l1 + 1;
    double step = 360.0 / (double)N;
    if (planar_side == 0) {
        s->has_angles = 1;
        s->angle_from_deg = (double)j0 * step;
        s->angle_to_deg = (double)(j0 + count) * step;
        if (s->angle_to_deg > 360.0 && count < N)
            s->angle_to_deg -= 360.0;   /* the record's wrap-around form */
    }
    s->side = planar_side;
    double wedge = 0.5 * sin(2 * PI / (double)N), dsum = 0;
    size_t cells = 0;
    for (size_t l = l0; l <= l1; l++) {
        for (size_t k = 0; k < count; k++) {
            size_t j = (j0 + k) % N;
            double *rp = run->restored_xy + 2 * (l * N + j);
            double *dp = run->damaged_xy + 2 * (l * N + j);
            double ro = hypot(rp[0], rp[1]);
            double ri = ro - depth;
            if (ri <= 0) {
                dp[0] = dp[1] = NAN;
                ri = 0;
            } else {
                dp[0] = rp[0] * ri / ro;
                dp[1] = rp[1] * ri / ro;
            }
            s->volume_mm3 += wedge * (ro * ro - ri * ri) * 1.0;
            s->depth_max_mm = fmax(s->depth_max_mm, ro - ri);
            dsum += ro - ri;
            cells++;
        }
    }
    s->depth_mean_mm = dsum / (double)cells;
    s->area_mm2 = 2.0 * s->volume_mm3 / fmax(depth, 1e-9);  /* a stand-in figure */
    snprintf(s->damage_class, sizeof s->damage_class, "unclassified");
    return s;
}

void synth_run_free(sr_run *run)
{
    free(run->layer_z);
    free(run->damaged_xy);
    free(run->restored_xy);
    for (size_t i = 0; i < run->section_count; i++)
        free(run->sections[i].features_json);
    free(run->sections);
    for (size_t i = 0; i < run->advice_count; i++)
        free(run->advice[i].details_json);
    free(run->advice);
    memset(run, 0, sizeof *run);
}

const sr_run_advice *synth_run_advice_for(const sr_run *run, long i)
{
    for (size_t k = 0; k < run->advice_count; k++)
        if (run->advice[k].section_index == i)
            return &run->advice[k];
    return NULL;
}
