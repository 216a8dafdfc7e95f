/*
 * same_surface.c: asserts that two closed meshes are the same surface (see
 * same_surface.h), for the tests of the local booleans against the whole-mesh ones.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "bridge/boolean.h"
#include "support/assert_near.h"
#include "support/same_surface.h"

/* A triangle as its 9 coordinates, rotated so the lexicographically least vertex comes
 * first (the orientation is kept). */
typedef struct ctri {
    double v[9];
} ctri;

static int pt_cmp(const double *a, const double *b)
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int ctri_cmp(const void *pa, const void *pb)
{
    const ctri *a = pa, *b = pb;
    for (int k = 0; k < 9; k++)
        if (a->v[k] != b->v[k])
            return a->v[k] < b->v[k] ? -1 : 1;
    return 0;
}

static ctri *canonical(const sr_mesh *m)
{
    ctri *t = malloc((m->tri_count ? m->tri_count : 1) * sizeof *t);
    assert_non_null(t);
    for (size_t i = 0; i < m->tri_count; i++) {
        const double *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = m->xyz + 3 * (size_t)m->tri[3 * i + k];
        int first = 0;
        for (int k = 1; k < 3; k++)
            if (pt_cmp(p[k], p[first]) < 0)
                first = k;
        for (int k = 0; k < 3; k++)
            memcpy(t[i].v + 3 * k, p[(first + k) % 3], 3 * sizeof(double));
    }
    qsort(t, m->tri_count, sizeof *t, ctri_cmp);
    return t;
}

/* The same closed surface: equal volumes, and equal triangle sets; where CGAL split a
 * face of the two unions' inputs in another order (the same points, other diagonals of
 * a flat polygon: the triangle sets differ), the surfaces must still coincide: a
 * deviation both ways of at most 1e-9 of the size. Returns how many triangles
 * differ. */
size_t assert_same_surface(const sr_mesh *x, const sr_mesh *y)
{
    assert_true(sr_mesh_is_closed(x));
    assert_true(sr_mesh_is_closed(y));
    sr_mesh_edges ex, ey;
    assert_int_equal(sr_mesh_edge_stats(x, &ex), SR_OK);
    assert_int_equal(sr_mesh_edge_stats(y, &ey), SR_OK);
    assert_int_equal(ex.nonmanifold_vertices, 0);
    assert_int_equal(ey.nonmanifold_vertices, 0);
    double vx = sr_mesh_volume(x), vy = sr_mesh_volume(y);
    assert_near(vx, vy, 1e-9 * fabs(vy));
    assert_int_equal(x->tri_count, y->tri_count);
    assert_int_equal(x->vertex_count, y->vertex_count);
    ctri *a = canonical(x), *b = canonical(y);
    size_t differ = 0;
    for (size_t i = 0; i < x->tri_count; i++)
        differ += ctri_cmp(&a[i], &b[i]) != 0;
    free(a);
    free(b);
    if (differ) {
        double lo[3], hi[3];
        sr_mesh_bbox(y, lo, hi);
        double size = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        sr_deviation dxy, dyx;
        assert_int_equal(sr_mesh_deviation(x, y, &dxy, NULL), SR_OK);
        assert_int_equal(sr_mesh_deviation(y, x, &dyx, NULL), SR_OK);
        print_message("%zu of %zu triangles differ; deviation %.3g / %.3g mm\n", differ,
                      x->tri_count, dxy.max_mm, dyx.max_mm);
        assert_true(dxy.max_mm <= 1e-9 * size);
        assert_true(dyx.max_mm <= 1e-9 * size);
    }
    return differ;
}
