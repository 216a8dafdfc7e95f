/*
 * test_patch.c: axial analysis (Alg. 4) and patch meshes (Alg. 6) on a chipped
 * cylinder with a known chip: the analysis finds exactly the chipped cells, every patch
 * is closed and outward oriented, its volume equals the cell formula to rounding, and
 * the chip's true volume within the discretisation error derived below.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "paper/analyse.h"
#include "bridge/boolean.h"
#include "paper/patch.h"
#include "slice/slice.h"
#include "support/assert_near.h"

/* How far a patch's surface may sit from the cells' exact boundary: the polygon library
 * rounds outline points to 1e-5 mm (at most 0.71e-5 mm off), and where cells of
 * neighbouring layers touch only along an edge the outlines are pulled in by up to
 * 0.6 um (stack_mesh.h). So |mesh volume - cell volume| <= area x this. */
#define PATCH_ROUNDING_MM 6.1e-4

/* Solid of revolution: ring i at z[i], segment s at angle 2 pi s / seg with radius
 * r[i * seg + s]; fan caps. Closed, outward. */
static void revolve(sr_mesh *m, size_t rings, const double *z, size_t seg, const double *r)
{
    assert_int_equal(sr_mesh_alloc(m, rings * seg + 2, 2 * seg * (rings - 1) + 2 * seg), SR_OK);
    for (size_t i = 0; i < rings; i++)
        for (size_t s = 0; s < seg; s++) {
            double a = 2 * M_PI * (double)s / (double)seg, *p = m->xyz + 3 * (i * seg + s);
            p[0] = r[i * seg + s] * cos(a);
            p[1] = r[i * seg + s] * sin(a);
            p[2] = z[i];
        }
    uint32_t c0 = (uint32_t)(rings * seg), c1 = c0 + 1;
    double *p0 = m->xyz + 3 * c0, *p1 = m->xyz + 3 * c1;
    p0[0] = p0[1] = p1[0] = p1[1] = 0;
    p0[2] = z[0];
    p1[2] = z[rings - 1];
    uint32_t *t = m->tri;
    for (size_t i = 0; i + 1 < rings; i++)
        for (size_t s = 0; s < seg; s++) {
            uint32_t a = (uint32_t)(i * seg + s), b = (uint32_t)(i * seg + (s + 1) % seg);
            uint32_t A = a + (uint32_t)seg, B = b + (uint32_t)seg;
            uint32_t q[6] = {a, b, B, a, B, A};
            memcpy(t, q, sizeof q);
            t += 6;
        }
    for (size_t s = 0; s < seg; s++) {
        uint32_t a = (uint32_t)s, b = (uint32_t)((s + 1) % seg);
        uint32_t q[6] = {c0, b, a, c1, a + (uint32_t)((rings - 1) * seg),
                         b + (uint32_t)((rings - 1) * seg)};
        memcpy(t, q, sizeof q);
        t += 6;
    }
}

enum { N = 36, SUB = 8, SEG = N * SUB, LAYERS = 20 };
static const double R = 20, H = 40, DEPTH = 3;
/* chip: sectors 4..9 (inclusive), z in [10, 20] (layers 5..9 with dz = 2) */
static const size_t J0 = 4, J1 = 9;

static void chipped_cylinder(sr_mesh *m, int chipped)
{
    double z[6] = {0, 10, 10, 20, 20, H};
    double *r = malloc(6 * SEG * sizeof *r);
    for (size_t i = 0; i < 6; i++)
        for (size_t s = 0; s < SEG; s++) {
            int in_chip = s >= J0 * SUB && s <= (J1 + 1) * SUB;
            r[i * SEG + s] = (chipped && (i == 2 || i == 3) && in_chip) ? R - DEPTH : R;
        }
    revolve(m, 6, z, SEG, r);
    free(r);
    /* the ring pairs at z = 10 and 20 make flat steps: weld the coincident vertices */
    assert_int_equal(sr_mesh_weld_exact(m), SR_OK);
}

static void cylinder_has_no_damage(void **state)
{
    sr_mesh m;
    chipped_cylinder(&m, 0);
    sr_slice_opts so = {.layers = LAYERS, .sectors = N};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&m, &so, &g, NULL), SR_OK);
    for (size_t c = 0; c < LAYERS * N; c++)
        assert_near(g.r[c], R, 1e-9);
    sr_analyse_opts ao = {.symmetry = {SR_SYM_AXIAL, 0, 0}, .gamma_axis = 0.95,
                          .min_depth_mm = 0.01};
    sr_analysis a;
    assert_int_equal(sr_analyse(&g, &ao, &a, NULL), SR_OK);
    assert_int_equal(a.damaged_cells, 0);
    sr_section *secs = NULL;
    size_t count = 99;
    assert_int_equal(sr_patch_build(&g, &a, &secs, &count, NULL), SR_OK);
    assert_int_equal(count, 0);
    sr_sections_release(secs, count);
    sr_analysis_release(&a);
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

static void chipped_cylinder_patch_matches_chip(void **state)
{
    sr_mesh intact, damaged;
    chipped_cylinder(&intact, 0);
    chipped_cylinder(&damaged, 1);
    assert_true(sr_mesh_is_closed(&damaged));
    double chip = sr_mesh_volume(&intact) - sr_mesh_volume(&damaged);

    sr_slice_opts so = {.layers = LAYERS, .sectors = N};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&damaged, &so, &g, NULL), SR_OK);
    sr_analyse_opts ao = {.symmetry = {SR_SYM_AXIAL, 0, 0}, .gamma_axis = 0.95,
                          .min_depth_mm = 0.01};
    sr_analysis a;
    assert_int_equal(sr_analyse(&g, &ao, &a, NULL), SR_OK);
    /* exactly the chipped cells: sectors J0..J1, layers 5..9 */
    for (size_t l = 0; l < LAYERS; l++)
        for (size_t j = 0; j < N; j++) {
            int expect = l >= 5 && l <= 9 && j >= J0 && j <= J1;
            assert_int_equal(a.damaged[l * N + j], expect);
            if (expect) {
                assert_near(g.r[l * N + j], R - DEPTH, 1e-9);
                assert_near(a.restored_r[l * N + j], R, 1e-9);
            }
        }
    sr_section *secs = NULL;
    size_t count = 0;
    assert_int_equal(sr_patch_build(&g, &a, &secs, &count, NULL), SR_OK);
    assert_int_equal(count, 1);
    sr_section *s = &secs[0];
    assert_true(sr_mesh_is_closed(&s->patch));
    assert_int_equal(s->layer_first, 5);
    assert_int_equal(s->layer_last, 9);
    assert_near(s->z_min, 10, 1e-9);
    assert_near(s->z_max, 20, 1e-9);
    assert_int_equal(s->sector_first, J0);
    assert_int_equal(s->sector_count, J1 - J0 + 1);
    assert_near(s->angle_min_deg, 40, 1e-9);
    assert_near(s->angle_max_deg, 100, 1e-9);
    assert_near(s->depth_max_mm, DEPTH, 1e-9);
    /* the patch encloses the cell formula: (R^2 - (R-d)^2)/2 sin(D) dz per cell */
    double D = 2 * M_PI / N, dz = H / LAYERS;
    double cells = 0.5 * (R * R - (R - DEPTH) * (R - DEPTH)) * sin(D) * dz * 6 * 5;
    assert_near(s->volume_mm3, cells, 1e-9 * cells);
    assert_near(sr_mesh_volume(&s->patch), cells, PATCH_ROUNDING_MM * sr_mesh_area(&s->patch));
    /* Discretisation error against the true chip: the scan's wall is SUB chords per
     * sector, the patch one chord per sector: per cell the difference is
     * (R^2 - (R-d)^2)/2 (SUB sin(D/SUB) - sin D) dz; and the chip's ends sit one
     * sub-chord outside the damaged sectors: at most R d D/SUB dz per end per layer. */
    double chord = 0.5 * (R * R - (R - DEPTH) * (R - DEPTH)) * (SUB * sin(D / SUB) - sin(D)) *
                   dz * 30;
    double ends = 2 * R * DEPTH * (D / SUB) * 10.0;
    double bound = chord + ends;
    assert_true(fabs(s->volume_mm3 - chip) <= bound);
    assert_true(bound < 0.05 * chip); /* and the bound itself is small: under 5 % */
    sr_sections_release(secs, count);
    sr_analysis_release(&a);
    sr_layer_grid_release(&g);
    sr_mesh_release(&intact);
    sr_mesh_release(&damaged);
}

static void chip_across_the_seam_is_one_section(void **state)
{
    /* rotate the chipped cylinder so the chip straddles angle 0 */
    sr_mesh m;
    chipped_cylinder(&m, 1);
    double a = -7 * 2 * M_PI / N;
    double rz[12] = {cos(a), -sin(a), 0, 0, sin(a), cos(a), 0, 0, 0, 0, 1, 0};
    sr_mesh_transform(&m, rz);
    sr_slice_opts so = {.layers = LAYERS, .sectors = N};
    sr_layer_grid g;
    assert_int_equal(sr_slice_accurate(&m, &so, &g, NULL), SR_OK);
    sr_analyse_opts ao = {.symmetry = {SR_SYM_AXIAL, 0, 0}, .min_depth_mm = 0.01};
    sr_analysis an;
    assert_int_equal(sr_analyse(&g, &ao, &an, NULL), SR_OK);
    sr_section *secs = NULL;
    size_t count = 0;
    assert_int_equal(sr_patch_build(&g, &an, &secs, &count, NULL), SR_OK);
    assert_int_equal(count, 1);
    assert_int_equal(secs[0].sector_first, N - 3);
    assert_int_equal(secs[0].sector_count, 6);
    assert_true(sr_mesh_is_closed(&secs[0].patch));
    assert_true(secs[0].angle_min_deg > secs[0].angle_max_deg); /* wraps through 0 */
    sr_sections_release(secs, count);
    sr_analysis_release(&an);
    sr_layer_grid_release(&g);
    sr_mesh_release(&m);
}

static void irregular_damage_patch_is_closed_with_cell_volume(void **state)
{
    /* a synthetic grid with ragged damage: random radii, steps between neighbours,
     * damage reaching the axis (r = 0) and a full ring: every section stays closed */
    enum { L = 12, S = 24 };
    sr_layer_grid g;
    assert_int_equal(sr_layer_grid_alloc(&g, L, S, -3.0, 0.5), SR_OK);
    sr_analysis a = {L, S, calloc(L * S, sizeof(double)), calloc(L * S, 1), 0, 0, 0, 0};
    unsigned seed = 12345;
    for (size_t c = 0; c < L * S; c++) {
        seed = seed * 1103515245u + 12345u;
        double u = (double)((seed >> 8) & 0xffff) / 65536.0;
        g.r[c] = 10 + 2 * u;
        a.restored_r[c] = g.r[c];
        size_t l = c / S, j = c % S;
        int dmg = (l >= 2 && l <= 6 && (j <= 3 || j >= 21)) || l == 9 ||
                  (l == 10 && j % 3 == 0);
        if (dmg) {
            a.damaged[c] = 1;
            a.restored_r[c] = 14 + u;
            if (l == 4 && j == 1)
                g.r[c] = 0; /* nothing left in this cell */
        }
    }
    sr_section *secs = NULL;
    size_t count = 0;
    assert_int_equal(sr_patch_build(&g, &a, &secs, &count, NULL), SR_OK);
    assert_int_equal(count, 2); /* the block + the ring with its teeth */
    double total = 0;
    for (size_t i = 0; i < count; i++) {
        sr_mesh_edges e;
        assert_int_equal(sr_mesh_edge_stats(&secs[i].patch, &e), SR_OK);
        assert_int_equal(e.boundary_edges, 0);
        assert_int_equal(e.misoriented_edges, 0);
        assert_int_equal(e.nonmanifold_edges, 0);
        assert_int_equal(e.nonmanifold_vertices, 0);
        assert_near(sr_mesh_volume(&secs[i].patch), secs[i].volume_mm3,
                    PATCH_ROUNDING_MM * sr_mesh_area(&secs[i].patch));
        assert_true(secs[i].volume_mm3 > 0);
        total += secs[i].volume_mm3;
    }
    double expect = 0, sn = sin(2 * M_PI / S);
    for (size_t c = 0; c < L * S; c++)
        if (a.damaged[c])
            expect += 0.5 * (a.restored_r[c] * a.restored_r[c] - g.r[c] * g.r[c]) * sn * 0.5;
    assert_near(total, expect, 1e-9 * expect);
    sr_sections_release(secs, count);
    sr_analysis_release(&a);
    sr_layer_grid_release(&g);
}

static void cells_touching_along_an_edge_give_a_manifold_patch(void **state)
{
    /* One section whose cells (1, 0) and (0, 1) meet only along an edge (border 1 at
     * z = 1; cells (0, 0) and (1, 1) are not in it) and whose cells (2, 1) and (2, 2)
     * meet only at a point (radial intervals [10, 12] and [12, 14]): the union of
     * blocks gives four faces on that edge; the patch must still be a closed 2-manifold
     * free of crossings, enclosing the cell volume. */
    enum { L = 3, S = 24 };
    sr_layer_grid g;
    assert_int_equal(sr_layer_grid_alloc(&g, L, S, 0.0, 1.0), SR_OK);
    sr_analysis a = {L, S, calloc(L * S, sizeof(double)), calloc(L * S, 1), 0, 0, 0, 0};
    static const int in[L][4] = {{0, 1, 1, 1}, {1, 0, 0, 1}, {1, 1, 1, 1}};
    for (size_t l = 0; l < L; l++)
        for (size_t j = 0; j < S; j++) {
            size_t c = l * S + j;
            g.r[c] = 13;
            a.restored_r[c] = 13;
            if (j < 4 && in[l][j]) {
                a.damaged[c] = 1;
                g.r[c] = 10;
            }
        }
    a.restored_r[2 * S + 1] = 12;
    g.r[2 * S + 2] = 12;
    a.restored_r[2 * S + 2] = 14;
    sr_section *secs = NULL;
    size_t count = 0;
    assert_int_equal(sr_patch_build(&g, &a, &secs, &count, NULL), SR_OK);
    assert_int_equal(count, 1);
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&secs[0].patch, &e), SR_OK);
    assert_int_equal(e.boundary_edges, 0);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_int_equal(e.nonmanifold_vertices, 0);
    assert_int_equal(e.misoriented_edges, 0);
    int crosses = -1;
    assert_int_equal(sr_mesh_self_intersects(&secs[0].patch, &crosses, NULL), SR_OK);
    assert_int_equal(crosses, 0);
    double expect = 0, sn = sin(2 * M_PI / S);
    for (size_t c = 0; c < L * S; c++)
        if (a.damaged[c])
            expect += 0.5 * (a.restored_r[c] * a.restored_r[c] - g.r[c] * g.r[c]) * sn;
    assert_near(secs[0].volume_mm3, expect, 1e-9 * expect);
    assert_near(sr_mesh_volume(&secs[0].patch), expect,
                PATCH_ROUNDING_MM * sr_mesh_area(&secs[0].patch));
    sr_sections_release(secs, count);
    sr_analysis_release(&a);
    sr_layer_grid_release(&g);
}

static void analysis_refuses_bad_thresholds(void **state)
{
    sr_layer_grid g;
    assert_int_equal(sr_layer_grid_alloc(&g, 2, 8, 0, 1), SR_OK);
    sr_analysis a;
    sr_err err = {{0}};
    sr_analyse_opts o = {.symmetry = {SR_SYM_AXIAL, 0, 0}, .gamma_axis = 1.5};
    assert_int_equal(sr_analyse(&g, &o, &a, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "gamma_axis"));
    o.gamma_axis = 0.9;
    o.min_depth_mm = -1;
    assert_int_equal(sr_analyse(&g, &o, &a, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "min_depth"));
    o.min_depth_mm = 0;
    o.gamma_plane = -0.1;
    assert_int_equal(sr_analyse(&g, &o, &a, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "gamma_plane"));
    sr_layer_grid_release(&g);
}

static void mirror_restores_the_shorter_side(void **state)
{
    /* layer of 8 sectors, plane x = 0: sector j pairs with 3 - j (mod 8) */
    sr_layer_grid g;
    assert_int_equal(sr_layer_grid_alloc(&g, 1, 8, 0, 1), SR_OK);
    double r[8] = {10, 12, 12, 10, 7, 9, 9, 7};
    r[0] = 6; /* damaged: its partner (sector 3) has 10 */
    memcpy(g.r, r, sizeof r);
    sr_analyse_opts o = {.symmetry = {SR_SYM_MIRROR, 0, 0}, .gamma_plane = 0.95, .fixed_plane = 1};
    sr_analysis a;
    assert_int_equal(sr_analyse(&g, &o, &a, NULL), SR_OK);
    assert_int_equal(a.damaged_cells, 1);
    assert_int_equal(a.damaged[0], 1);
    assert_near(a.restored_r[0], 10, 0);
    sr_analysis_release(&a);
    sr_layer_grid_release(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cylinder_has_no_damage),
        cmocka_unit_test(chipped_cylinder_patch_matches_chip),
        cmocka_unit_test(chip_across_the_seam_is_one_section),
        cmocka_unit_test(irregular_damage_patch_is_closed_with_cell_volume),
        cmocka_unit_test(cells_touching_along_an_edge_give_a_manifold_patch),
        cmocka_unit_test(analysis_refuses_bad_thresholds),
        cmocka_unit_test(mirror_restores_the_shorter_side),
    };
    return cmocka_run_group_tests_name("patch", tests, NULL, NULL);
}
