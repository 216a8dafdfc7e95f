/*
 * test_clip_local.c: sr_boolean_intersection_local (src/bridge/clip_local.h), a large
 * mesh clipped to a small one through its neighbourhood of the small one only (the
 * image method clips each image of a scan to a section's hull so). The claim under
 * test is that it is the whole-mesh intersection (sr_boolean_compute): the same
 * surface (tests/support/same_surface.h) on a chipped cylinder and boxes across its
 * surface, on a slab whose volume is known, on a turned and on a mirrored image of the
 * cylinder (as the image method makes them), and with a piece of the small mesh no
 * triangle of the large one cuts; then the fall-backs to the whole-mesh intersection (a
 * box inside the cylinder, one away from it) and the refusals, which must be the
 * whole-mesh intersection's. The mapped form (sr_boolean_intersection_local_mapped,
 * no copy of the large mesh) gives the very arrays the mapped copy gives, for a turn, a
 * mirror, a rotation about a skew axis and a fall-back, and refuses a singular map.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "bridge/boolean.h"
#include "bridge/clip_local.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/same_surface.h"

/* A cylinder r = 20, z 0..40 (96 segments, 41 rings) with a dent up to 4 mm deep at
 * theta = 0 over |theta| < 35 deg and z 14..26. */
static double chipped_radius(double theta, size_t ring, void *user)
{
    (void)user;
    double z = (double)ring;
    double az = remainder(theta, 2 * M_PI) * 180.0 / M_PI;
    if (fabs(az) >= 35 || z < 14 || z > 26)
        return 20.0;
    double u = fabs(az) / 35.0, v = fabs(z - 20) / 6.0;
    return 20.0 - 4.0 * cos(M_PI / 2 * u) * cos(M_PI / 2 * v);
}

static void make_cylinder(sr_mesh *m)
{
    double z[41];
    for (int i = 0; i < 41; i++)
        z[i] = i;
    sr_revolve_opts o = {
        .segments = 96, .ring_count = 41, .ring_z = z, .outer = chipped_radius, .user = NULL};
    assert_int_equal(sr_shape_revolve(&o, m, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(m));
}

static void make_box(sr_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

/* Clips a to b both ways, checks they agree and returns the local call's info. */
static sr_local_clip_info assert_clip_is_whole(const sr_mesh *a, const sr_mesh *b)
{
    sr_mesh whole, local;
    sr_err err;
    sr_status st = sr_boolean_compute(SR_BOOLEAN_INTERSECTION, a, "image", b, "hull", &whole, &err);
    if (st != SR_OK)
        print_error("whole intersection: %s\n", err.msg);
    assert_int_equal(st, SR_OK);
    sr_local_clip_info info;
    st = sr_boolean_intersection_local(a, "image", b, "hull", 0, &local, &info, &err);
    if (st != SR_OK)
        print_error("local intersection: %s\n", err.msg);
    assert_int_equal(st, SR_OK);
    if (whole.tri_count)
        assert_same_surface(&local, &whole);
    else
        assert_int_equal(local.tri_count, 0);
    sr_mesh_release(&whole);
    sr_mesh_release(&local);
    return info;
}

/* ---- the local intersection is the whole one ------------------------------------------ */

static void box_across_the_chip_clips_locally_as_whole(void **state)
{
    sr_mesh cyl, box;
    make_cylinder(&cyl);
    make_box(&box, 14, -7, 13.5, 21, 7, 26.5);
    sr_local_clip_info info = assert_clip_is_whole(&cyl, &box);
    assert_int_equal(info.local, 1);
    assert_string_equal(info.fallback, "");
    /* only the triangles near the box went through CGAL */
    assert_true(info.neighbourhood_tris > 0);
    assert_true(info.neighbourhood_tris < cyl.tri_count / 4);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

/* A slab z 2..8 of the cylinder, away from the chip: the 96-gon's area times 6. */
static void slab_of_the_cylinder_has_its_known_volume(void **state)
{
    sr_mesh cyl, box, out;
    make_cylinder(&cyl);
    make_box(&box, -30, -30, 2, 30, 30, 8);
    sr_local_clip_info info = assert_clip_is_whole(&cyl, &box);
    assert_int_equal(info.local, 1);
    sr_err err;
    assert_int_equal(
        sr_boolean_intersection_local(&cyl, "image", &box, "hull", 0, &out, NULL, &err), SR_OK);
    double area = 0.5 * 96 * 20.0 * 20.0 * sin(2 * M_PI / 96);
    assert_near(sr_mesh_volume(&out), 6.0 * area, 1e-9 * 6.0 * area);
    sr_mesh_release(&out);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

/* The images the image method clips: the cylinder turned 180 deg about its axis, and
 * mirrored in x = 0 (faces turned over), each clipped where the chip is. */
static void turned_and_mirrored_images_clip_locally_as_whole(void **state)
{
    static const double turn[12] = {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0};
    static const double mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    const double *xf[2] = {turn, mirror};
    for (int i = 0; i < 2; i++) {
        sr_mesh img, box;
        make_cylinder(&img);
        sr_mesh_transform(&img, xf[i]);
        if (i == 1)
            sr_mesh_flip(&img);
        make_box(&box, 14, -7, 13.5, 21, 7, 26.5);
        /* the chip was at +x: the image is whole there */
        sr_local_clip_info info = assert_clip_is_whole(&img, &box);
        assert_int_equal(info.local, 1);
        sr_mesh_release(&img);
        sr_mesh_release(&box);
    }
}

/* The mapped form is the mapped copy's intersection, to the bit: the same vertices and
 * triangles in the same order (a box across the chip, and one inside: the fall-back). */
static void mapped_clip_is_the_mapped_copys(void **state)
{
    (void)state;
    static const double turn[12] = {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0};
    static const double mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    double skew[12]; /* 0.7 rad about (1, 2, 2)/3, then moved */
    double u[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3}, c = cos(0.7), sn = sin(0.7);
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) {
            double cross = r == k ? 0 : ((r + 1) % 3 == k ? -1 : 1) * u[3 - r - k];
            skew[4 * r + k] = (r == k ? c : 0) + (1 - c) * u[r] * u[k] + sn * cross;
        }
        skew[4 * r + 3] = 0.3 * (r + 1);
    }
    const double *xf[3] = {turn, mirror, skew};
    const double boxes[2][6] = {{14, -7, 13.5, 21, 7, 26.5}, {-5, -5, 5, 5, 5, 10}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++) {
            sr_mesh cyl, img, box, a = {0}, b = {0};
            make_cylinder(&cyl);
            make_cylinder(&img);
            sr_mesh_transform(&img, xf[i]);
            if (i == 1)
                sr_mesh_flip(&img);
            const double *q = boxes[j];
            make_box(&box, q[0], q[1], q[2], q[3], q[4], q[5]);
            sr_local_clip_info ia, ib;
            sr_err err;
            assert_int_equal(
                sr_boolean_intersection_local(&img, "image", &box, "hull", 0, &a, &ia, &err),
                SR_OK);
            assert_int_equal(sr_boolean_intersection_local_mapped(&cyl, "image", xf[i], &box,
                                                                  "hull", 0, &b, &ib, &err),
                             SR_OK);
            assert_int_equal(ia.local, ib.local);
            if (i < 2) /* the second box lies inside the turned and mirrored cylinder */
                assert_int_equal(ia.local, j == 0);
            assert_int_equal(ia.neighbourhood_tris, ib.neighbourhood_tris);
            assert_true(a.tri_count > 0);
            assert_int_equal(a.tri_count, b.tri_count);
            assert_int_equal(a.vertex_count, b.vertex_count);
            assert_memory_equal(a.tri, b.tri, 3 * a.tri_count * sizeof *a.tri);
            assert_memory_equal(a.xyz, b.xyz, 3 * a.vertex_count * sizeof *a.xyz);
            sr_mesh_release(&a);
            sr_mesh_release(&b);
            sr_mesh_release(&cyl);
            sr_mesh_release(&img);
            sr_mesh_release(&box);
        }
    sr_mesh cyl, box, out;
    make_cylinder(&cyl);
    make_box(&box, 14, -7, 13.5, 21, 7, 26.5);
    static const double flat[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
    sr_err err;
    assert_int_equal(sr_boolean_intersection_local_mapped(&cyl, "image", flat, &box, "hull", 0,
                                                          &out, NULL, &err),
                     SR_E_RANGE);
    assert_non_null(strstr(err.msg, "singular"));
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

/* A hull of two pieces, one across the surface and one inside the cylinder that no
 * triangle cuts (placed by rays: kept whole), and a third outside it (dropped). */
static void piece_no_triangle_cuts_is_placed_by_rays(void **state)
{
    sr_mesh cyl, b1, b2, b3, three;
    make_cylinder(&cyl);
    make_box(&b1, -21, -5, 2, -15, 5, 8);
    make_box(&b2, -5, -5, 30, 5, 5, 35);
    make_box(&b3, 25, -5, 30, 30, 5, 35);
    assert_int_equal(sr_mesh_copy(&three, &b1), SR_OK);
    assert_int_equal(sr_mesh_append(&three, &b2), SR_OK);
    assert_int_equal(sr_mesh_append(&three, &b3), SR_OK);
    sr_local_clip_info info = assert_clip_is_whole(&cyl, &three);
    assert_int_equal(info.local, 1);
    sr_mesh out;
    assert_int_equal(
        sr_boolean_intersection_local(&cyl, "image", &three, "hull", 0, &out, NULL, NULL), SR_OK);
    /* the inner box whole (500 mm3) and b1's part inside the 96-gon */
    double v = sr_mesh_volume(&out);
    assert_true(v > 500.0 + 0.9 * 4 * 10 * 6);
    assert_true(v < 500.0 + 6 * 10 * 6);
    sr_mesh_release(&out);
    sr_mesh_release(&cyl);
    sr_mesh_release(&b1);
    sr_mesh_release(&b2);
    sr_mesh_release(&b3);
    sr_mesh_release(&three);
}

/* ---- fall-backs and refusals ------------------------------------------------------- */

static void box_inside_falls_back_and_is_kept(void **state)
{
    sr_mesh cyl, box;
    make_cylinder(&cyl);
    make_box(&box, -5, -5, 5, 5, 5, 10);
    sr_local_clip_info info = assert_clip_is_whole(&cyl, &box);
    assert_int_equal(info.local, 0);
    assert_string_equal(info.fallback, "'hull' meets no triangle of 'image'");
    sr_mesh out;
    assert_int_equal(
        sr_boolean_intersection_local(&cyl, "image", &box, "hull", 0, &out, NULL, NULL), SR_OK);
    assert_near(sr_mesh_volume(&out), 500.0, 1e-9);
    sr_mesh_release(&out);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

static void box_away_falls_back_and_gives_nothing(void **state)
{
    sr_mesh cyl, box, out;
    make_cylinder(&cyl);
    make_box(&box, 30, 30, 5, 35, 35, 10);
    sr_local_clip_info info;
    assert_int_equal(
        sr_boolean_intersection_local(&cyl, "image", &box, "hull", 0, &out, &info, NULL), SR_OK);
    assert_int_equal(info.local, 0);
    assert_int_equal(out.tri_count, 0);
    sr_mesh_release(&out);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

static void open_image_is_refused_as_whole(void **state)
{
    sr_mesh cyl, box, out;
    make_cylinder(&cyl);
    make_box(&box, 14, -7, 13.5, 21, 7, 26.5);
    cyl.tri_count--; /* a hole */
    sr_err whole, local;
    assert_int_equal(
        sr_boolean_compute(SR_BOOLEAN_INTERSECTION, &cyl, "image", &box, "hull", &out, &whole),
        SR_E_INVALID);
    assert_int_equal(
        sr_boolean_intersection_local(&cyl, "image", &box, "hull", 0, &out, NULL, &local),
        SR_E_INVALID);
    assert_string_equal(local.msg, whole.msg);
    assert_msg_has(local, "not closed");
    cyl.tri_count++;
    assert_int_equal(
        sr_boolean_intersection_local(&cyl, "image", &box, "hull", -1, &out, NULL, &local),
        SR_E_RANGE);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(box_across_the_chip_clips_locally_as_whole),
        cmocka_unit_test(slab_of_the_cylinder_has_its_known_volume),
        cmocka_unit_test(turned_and_mirrored_images_clip_locally_as_whole),
        cmocka_unit_test(mapped_clip_is_the_mapped_copys),
        cmocka_unit_test(piece_no_triangle_cuts_is_placed_by_rays),
        cmocka_unit_test(box_inside_falls_back_and_is_kept),
        cmocka_unit_test(box_away_falls_back_and_gives_nothing),
        cmocka_unit_test(open_image_is_refused_as_whole),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
