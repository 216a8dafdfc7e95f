/*
 * test_compare.c: sr_compare_meshes (src/mesh/compare.c): two unit cubes 0.1 mm apart
 * (deviation 0.1 both ways, Hausdorff 0.1, volume difference 0), a cube against itself
 * (all zero), the volume difference in mm³ and %, denser sampling finding a maximum
 * that vertices and centroids miss (a plate under a pyramid, exact answer known), and
 * the refusals: NaN, no triangle with an area, too many samples; and the same figures,
 * to the last bit, with one thread as with two (the queries run in fixed blocks).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include <omp.h>

#include "mesh/compare.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

static void cube(double x0, double size, sr_mesh *out)
{
    const double lo[3] = {x0, 0, 0}, hi[3] = {x0 + size, size, size};
    assert_int_equal(sr_shape_box(lo, hi, out, NULL), SR_OK);
}

static void unit_cubes_offset_by_0_1_deviate_by_0_1_with_equal_volumes(void **state)
{
    (void)state;
    sr_mesh a, b;
    cube(0, 1, &a);
    cube(0.1, 1, &b);
    sr_compare_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_compare_meshes(&a, "a", &b, "b", NULL, &r, &err), SR_OK);
    assert_near(r.volume_a_mm3, 1, 1e-12);
    assert_near(r.volume_b_mm3, 1, 1e-12);
    assert_near(r.volume_diff_mm3, 0, 1e-12);
    assert_near(r.volume_diff_pct, 0, 1e-10);
    assert_near(r.area_a_mm2, 6, 1e-12);
    assert_int_equal(r.closed_a, 1);
    assert_int_equal(r.closed_b, 1);
    /* a point of a's face x = 0 is 0.1 from b's face x = 0.1, and no sample is farther */
    assert_near(r.a_to_b.max_mm, 0.1, 1e-12);
    assert_near(r.b_to_a.max_mm, 0.1, 1e-12);
    assert_near(r.hausdorff_mm, 0.1, 1e-12);
    assert_true(r.a_to_b.mean_mm > 0 && r.a_to_b.mean_mm < 0.1);
    assert_true(r.a_to_b.rms_mm >= r.a_to_b.mean_mm && r.a_to_b.rms_mm <= 0.1);
    assert_int_equal(r.a_to_b.samples, a.vertex_count + a.tri_count);

    /* denser sampling: more samples, the same maximum (it is reached on a face) */
    sr_compare_opts o = {.samples = 2000};
    assert_int_equal(sr_compare_meshes(&a, "a", &b, "b", &o, &r, &err), SR_OK);
    assert_true(r.a_to_b.samples >= 2000 && r.b_to_a.samples >= 2000);
    assert_near(r.a_to_b.max_mm, 0.1, 1e-12);
    assert_near(r.hausdorff_mm, 0.1, 1e-12);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void a_cube_against_itself_is_zero_everywhere(void **state)
{
    (void)state;
    sr_mesh a;
    cube(0, 1, &a);
    sr_compare_result r;
    sr_err err = {{0}};
    sr_compare_opts o = {.samples = 500};
    assert_int_equal(sr_compare_meshes(&a, NULL, &a, NULL, &o, &r, &err), SR_OK);
    assert_near(r.volume_diff_mm3, 0, 0);
    assert_near(r.volume_diff_pct, 0, 0);
    assert_near(r.a_to_b.max_mm, 0, 1e-12);
    assert_near(r.a_to_b.mean_mm, 0, 1e-12);
    assert_near(r.a_to_b.rms_mm, 0, 1e-12);
    assert_near(r.b_to_a.max_mm, 0, 1e-12);
    assert_near(r.hausdorff_mm, 0, 1e-12);
    sr_mesh_release(&a);
}

static void volume_difference_is_b_minus_a_in_mm3_and_percent_of_a(void **state)
{
    (void)state;
    sr_mesh a, b;
    cube(0, 2, &a);     /* 8 mm³ */
    cube(0, 1, &b);     /* 1 mm³, inside a and touching it */
    sr_compare_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_compare_meshes(&a, "a", &b, "b", NULL, &r, &err), SR_OK);
    assert_near(r.volume_diff_mm3, -7, 1e-12);
    assert_near(r.volume_diff_pct, -87.5, 1e-10);
    /* a's far corner (2,2,2) is sqrt(3) from b's corner (1,1,1) */
    assert_near(r.a_to_b.max_mm, sqrt(3.0), 1e-12);
    assert_near(r.hausdorff_mm, sqrt(3.0), 1e-12);
    /* every point of b's surface lies within 1 of a's */
    assert_true(r.b_to_a.max_mm <= 1 + 1e-12);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* A 10 x 10 plate (2 triangles, z = 0) against an open pyramid over it (apex at the
 * centre, height h): the plate's centre is the farthest point, at h 5 / sqrt(h² + 25)
 * from the slanted faces; the corners touch. Vertices and centroids miss the centre;
 * dense sampling gets close to it. */
static void denser_sampling_finds_a_maximum_between_the_vertices(void **state)
{
    (void)state;
    double plate_xyz[] = {0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0};
    uint32_t plate_tri[] = {0, 1, 2, 0, 2, 3};
    sr_mesh plate = {plate_xyz, plate_tri, 4, 2};
    double h = 4;
    double pyr_xyz[] = {0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0, 5, 5, h};
    uint32_t pyr_tri[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    sr_mesh pyr = {pyr_xyz, pyr_tri, 5, 4};
    double exact = h * 5 / sqrt(h * h + 25);
    sr_compare_result sparse, dense;
    sr_err err = {{0}};
    assert_int_equal(sr_compare_meshes(&plate, "plate", &pyr, "pyramid", NULL, &sparse, &err),
                     SR_OK);
    sr_compare_opts o = {.samples = 20000};
    assert_int_equal(sr_compare_meshes(&plate, "plate", &pyr, "pyramid", &o, &dense, &err),
                     SR_OK);
    assert_int_equal(sparse.closed_a, 0);
    assert_true(sparse.a_to_b.max_mm < 0.8 * exact);
    assert_true(dense.a_to_b.max_mm <= exact + 1e-12);
    assert_true(dense.a_to_b.max_mm > 0.98 * exact);
    assert_true(dense.a_to_b.samples >= 20000);
}

/* A cylinder against a box round it: many samples, distances all different. The queries
 * are spread over threads in fixed blocks combined in order, so one thread and two give
 * the same bits. */
static void one_thread_and_two_give_the_same_figures(void **state)
{
    (void)state;
    sr_mesh cyl, box;
    assert_int_equal(sr_shape_cylinder(4, 0, 10, 48, &cyl, NULL), SR_OK);
    const double lo[3] = {-5, -5, -1}, hi[3] = {5, 5, 11};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    sr_compare_opts o = {.samples = 100000};
    sr_compare_result r[2];
    sr_err err = {{0}};
    int threads = omp_get_max_threads();
    for (int k = 0; k < 2; k++) {
        omp_set_num_threads(k + 1);
        assert_int_equal(sr_compare_meshes(&cyl, "cylinder", &box, "box", &o, &r[k], &err), SR_OK);
    }
    omp_set_num_threads(threads);
    assert_true(r[0].a_to_b.samples >= 100000);
    assert_true(r[0].a_to_b.mean_mm > 0.5);
    assert_memory_equal(&r[0].a_to_b, &r[1].a_to_b, sizeof r[0].a_to_b);
    assert_memory_equal(&r[0].b_to_a, &r[1].b_to_a, sizeof r[0].b_to_a);
    assert_true(r[0].hausdorff_mm == r[1].hausdorff_mm);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

static void a_mesh_with_nan_is_refused_by_name(void **state)
{
    (void)state;
    sr_mesh a, b;
    cube(0, 1, &a);
    cube(0, 1, &b);
    b.xyz[3] = NAN;
    sr_compare_result r;
    memset(&r, 0x11, sizeof r);
    sr_compare_result before = r;
    sr_err err = {{0}};
    assert_int_equal(sr_compare_meshes(&a, "ref.stl", &b, "restored.stl", NULL, &r, &err),
                     SR_E_INVALID);
    assert_msg_has(err, "restored.stl");
    assert_memory_equal(&r, &before, sizeof r);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void a_mesh_without_area_is_refused(void **state)
{
    (void)state;
    sr_mesh a;
    cube(0, 1, &a);
    double flat_xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    uint32_t flat_tri[] = {0, 1, 2};
    sr_mesh flat = {flat_xyz, flat_tri, 3, 1};
    sr_compare_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_compare_meshes(&a, "a.stl", &flat, "line.stl", NULL, &r, &err),
                     SR_E_INVALID);
    assert_msg_has(err, "'line.stl'");
    assert_msg_has(err, "no triangle of non-zero area");
    sr_mesh_release(&a);
}

static void too_many_samples_are_refused(void **state)
{
    (void)state;
    sr_mesh a;
    cube(0, 1, &a);
    sr_compare_result r;
    sr_err err = {{0}};
    sr_compare_opts o = {.samples = SR_COMPARE_MAX_SAMPLES + 1};
    assert_int_equal(sr_compare_meshes(&a, "a", &a, "a", &o, &r, &err), SR_E_RANGE);
    assert_msg_has(err, "bad samples");
    sr_mesh_release(&a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(unit_cubes_offset_by_0_1_deviate_by_0_1_with_equal_volumes),
        cmocka_unit_test(a_cube_against_itself_is_zero_everywhere),
        cmocka_unit_test(volume_difference_is_b_minus_a_in_mm3_and_percent_of_a),
        cmocka_unit_test(denser_sampling_finds_a_maximum_between_the_vertices),
        cmocka_unit_test(one_thread_and_two_give_the_same_figures),
        cmocka_unit_test(a_mesh_with_nan_is_refused_by_name),
        cmocka_unit_test(a_mesh_without_area_is_refused),
        cmocka_unit_test(too_many_samples_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
