/*
 * rim_crossings.c: how many times the rims of a plane's openings cross one another in
 * the plane (scan_int.h, sr_scan_rim_crossings), counted before their fill is
 * triangulated. Each crossing is a point the constrained triangulation must make, and
 * CGAL 5.5 records each in its constraint hierarchy at a cost that grows with the
 * constraints already there: a base left in thousands of noisy scraps (a
 * 658,000-triangle spline, 4,938 loops) kept one fill running for minutes. A uniform
 * grid over the segments, each pair tested in the one cell where their bounding boxes'
 * overlap begins, so each pair is counted once.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "mesh/scan_int.h"

/* The sign of the turn a -> b -> c. */
static int turn(const double *a, const double *b, const double *c)
{
    double v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    return (v > 0) - (v < 0);
}

/* Whether segments ab and cd cross properly (each one's ends strictly either side of
 * the other). */
static bool cross(const double *a, const double *b, const double *c, const double *d)
{
    return turn(a, b, c) * turn(a, b, d) < 0 && turn(c, d, a) * turn(c, d, b) < 0;
}

size_t sr_scan_rim_crossings(const double *uv, const size_t *start, size_t loop_count, size_t limit)
{
    size_t n = start[loop_count];
    if (n < 4)
        return 0;
    uint32_t *next = malloc(n * sizeof *next);
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], uv[2 * i + k]);
            hi[k] = fmax(hi[k], uv[2 * i + k]);
        }
    size_t side = (size_t)ceil(sqrt((double)n));
    side = side < 1 ? 1 : side > 1024 ? 1024 : side;
    double cell = fmax(hi[0] - lo[0], hi[1] - lo[1]) / (double)side;
    size_t *first = calloc(side * side + 1, sizeof *first);
    if (!next || !first || !(cell > 0) || !isfinite(cell)) {
        free(next);
        free(first);
        return limit + 1; /* no room to count (or no extent): as if too many */
    }
    for (size_t c = 0; c < loop_count; c++)
        for (size_t i = start[c]; i < start[c + 1]; i++)
            next[i] = (uint32_t)(i + 1 < start[c + 1] ? i + 1 : start[c]);
#define CELL_OF(x, k) ((size_t)fmin((double)(side - 1), floor(((x)-lo[k]) / cell)))
    /* each segment's cells: counted, then listed */
    for (size_t i = 0; i < n; i++) {
        const double *a = uv + 2 * i, *b = uv + 2 * (size_t)next[i];
        size_t x0 = CELL_OF(fmin(a[0], b[0]), 0), x1 = CELL_OF(fmax(a[0], b[0]), 0);
        size_t y0 = CELL_OF(fmin(a[1], b[1]), 1), y1 = CELL_OF(fmax(a[1], b[1]), 1);
        for (size_t y = y0; y <= y1; y++)
            for (size_t x = x0; x <= x1; x++)
                first[y * side + x + 1]++;
    }
    size_t cells = side * side, total = 0;
    for (size_t c = 0; c < cells; c++) {
        total += first[c + 1];
        first[c + 1] = total;
    }
    uint32_t *seg = malloc((total + 1) * sizeof *seg);
    size_t *fill = calloc(cells + 1, sizeof *fill);
    if (!seg || !fill) {
        free(next);
        free(first);
        free(seg);
        free(fill);
        return limit + 1;
    }
    for (size_t i = 0; i < n; i++) {
        const double *a = uv + 2 * i, *b = uv + 2 * (size_t)next[i];
        size_t x0 = CELL_OF(fmin(a[0], b[0]), 0), x1 = CELL_OF(fmax(a[0], b[0]), 0);
        size_t y0 = CELL_OF(fmin(a[1], b[1]), 1), y1 = CELL_OF(fmax(a[1], b[1]), 1);
        for (size_t y = y0; y <= y1; y++)
            for (size_t x = x0; x <= x1; x++) {
                size_t c = y * side + x;
                seg[first[c] + fill[c]++] = (uint32_t)i;
            }
    }
    size_t found = 0;
    for (size_t c = 0; c < cells && found <= limit; c++)
        for (size_t p = first[c]; p < first[c + 1] && found <= limit; p++)
            for (size_t q = p + 1; q < first[c + 1]; q++) {
                uint32_t i = seg[p], j = seg[q];
                if (next[i] == j || next[j] == i)
                    continue; /* neighbours meet at their shared end */
                const double *a = uv + 2 * (size_t)i, *b = uv + 2 * (size_t)next[i];
                const double *d = uv + 2 * (size_t)j, *e = uv + 2 * (size_t)next[j];
                double mx = fmax(fmin(a[0], b[0]), fmin(d[0], e[0]));
                double my = fmax(fmin(a[1], b[1]), fmin(d[1], e[1]));
                if (CELL_OF(mx, 0) + side * CELL_OF(my, 1) != c)
                    continue; /* counted where their boxes' overlap begins */
                if (cross(a, b, d, e) && ++found > limit)
                    break;
            }
#undef CELL_OF
    free(next);
    free(first);
    free(seg);
    free(fill);
    return found;
}
