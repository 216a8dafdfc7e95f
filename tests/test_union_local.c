/*
 * test_union_local.c: sr_boolean_union_local (src/bridge/boolean.h), the union of a
 * large scan and a small patch through the scan's neighbourhood of the patch only. The
 * claim under test is that it is the whole-mesh union (sr_boolean_compute): same
 * triangles up to order (compared exactly, after sorting), same volume, closed; on a
 * chipped cylinder with a box and with the patch the pipeline builds, on touching
 * coplanar faces, in place, and on three shared parts' posed damaged scans with the
 * patches the paper method builds for them (../shared/parts, skipped when absent).
 * Then the fall-backs to the whole-mesh union (a patch inside the scan, one away from
 * it, a neighbourhood too small to hold the intersection, a non-manifold result) and
 * the refusals, which must match the whole-mesh union's.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <cmocka.h>

#include "bridge/boolean.h"
#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "reconstruct.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/same_surface.h"
#include "support/truth.h"

#define PARTS_DIR "../shared/parts"

/* ---- geometry ---------------------------------------------------------------------- */

/* A cylinder r = 20, z 0..40 (96 segments, 41 rings) with, when chipped, a dent up to
 * 4 mm deep at theta = 0 over |theta| < 35 deg and z 14..26. */
static double chipped_radius(double theta, size_t ring, void *user)
{
    const int *chipped = user;
    double z = (double)ring;
    double az = remainder(theta, 2 * M_PI) * 180.0 / M_PI;
    if (!*chipped || fabs(az) >= 35 || z < 14 || z > 26)
        return 20.0;
    double u = fabs(az) / 35.0, v = fabs(z - 20) / 6.0;
    return 20.0 - 4.0 * cos(M_PI / 2 * u) * cos(M_PI / 2 * v);
}

static void make_cylinder(sr_mesh *m, int chipped)
{
    double z[41];
    for (int i = 0; i < 41; i++)
        z[i] = i;
    sr_revolve_opts o = {
        .segments = 96, .ring_count = 41, .ring_z = z, .outer = chipped_radius, .user = &chipped};
    assert_int_equal(sr_shape_revolve(&o, m, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(m));
}

static void make_box(sr_mesh *m, double x0, double y0, double z0, double x1, double y1,
                     double z1)
{
    double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

/* Unites a and b both ways and checks they agree; returns the local result's info. */
static void assert_local_is_whole(const sr_mesh *a, const sr_mesh *b,
                                  sr_local_union_info *info_out)
{
    sr_mesh whole, local;
    sr_err err;
    sr_status st = sr_boolean_compute(SR_BOOLEAN_UNION, a, "scan", b, "patch", &whole, &err);
    if (st != SR_OK)
        print_error("whole union: %s\n", err.msg);
    assert_int_equal(st, SR_OK);
    sr_local_union_info info;
    st = sr_boolean_union_local(a, "scan", NULL, b, "patch", 0, &local, &info, &err);
    if (st != SR_OK)
        print_error("local union: %s\n", err.msg);
    assert_int_equal(st, SR_OK);
    assert_same_surface(&local, &whole);
    if (info_out)
        *info_out = info;
    sr_mesh_release(&whole);
    sr_mesh_release(&local);
}

/* ---- the local union is the whole union ---------------------------------------------- */

static void chipped_cylinder_and_box_unite_locally_as_whole(void **state)
{
    sr_mesh cyl, box;
    make_cylinder(&cyl, 1);
    make_box(&box, 14, -7, 13.5, 21, 7, 26.5);
    sr_local_union_info info;
    assert_local_is_whole(&cyl, &box, &info);
    assert_int_equal(info.local, 1);
    assert_string_equal(info.fallback, "");
    /* only the triangles near the box went through CGAL */
    assert_true(info.neighbourhood_tris > 0);
    assert_true(info.neighbourhood_tris < cyl.tri_count / 4);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

static void chipped_cylinder_and_its_patch_unite_locally_as_whole(void **state)
{
    sr_mesh cyl, intact;
    make_cylinder(&cyl, 1);
    make_cylinder(&intact, 0);
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry.kind = SR_SYM_AXIAL;
    o.method = SR_METHOD_PAPER;
    /* 48/40 (and 96/80): at 60/80, 72/100, 120/160 and 240/320 Alg. 6's patch of this
     * chip has an edge shared by three triangles (patch.c), which every union refuses */
    o.sectors = 48;
    o.layers = 40;
    o.skip_union = 1;
    o.have_alignment = 1; /* the cylinder is in the canonical frame already */
    sr_xform_identity(o.alignment.xform);
    sr_recon_result r;
    assert_int_equal(sr_reconstruct(&cyl, &o, &r, NULL), SR_OK);
    assert_int_equal(r.section_count, 1);
    sr_local_union_info info;
    assert_local_is_whole(&cyl, &r.sections[0].patch, &info);
    assert_int_equal(info.local, 1);
    /* and the pipeline's own union gives back the intact volume up to the method's
     * error (its patch for the union reaches into the material: no voids left) */
    sr_recon_result_release(&r);
    o.skip_union = 0;
    assert_int_equal(sr_reconstruct(&cyl, &o, &r, NULL), SR_OK);
    assert_int_equal(r.restored_by_union, 1);
    assert_true(sr_mesh_is_closed(&r.restored));
    double vi = sr_mesh_volume(&intact), vd = sr_mesh_volume(&cyl);
    assert_true(r.restored_volume_mm3 > vd + 0.5 * (vi - vd));
    assert_true(r.restored_volume_mm3 < vi + 0.02 * (vi - vd));
    sr_recon_result_release(&r);
    sr_mesh_release(&cyl);
    sr_mesh_release(&intact);
}

/* A scan that crosses itself where the patch goes (a loose 1.2 mm block stuck through
 * the cylinder's wall beside the chip, a second shell): the plain unions refuse it; the
 * pipeline mends the scan's neighbourhood (the crossing triangles replaced by fills)
 * and unites, and says what it replaced. */
static void scan_crossing_itself_beside_the_chip_is_mended_and_united(void **state)
{
    (void)state;
    sr_mesh cyl, block, intact;
    make_cylinder(&cyl, 1);
    make_cylinder(&intact, 0);
    make_box(&block, 15.6, 11.2, 19.0, 16.8, 12.4, 20.2);
    assert_int_equal(sr_mesh_append(&cyl, &block), SR_OK);
    sr_mesh_release(&block);
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.method = SR_METHOD_ROBUST; /* its stacked patch, united with the crossing scan */
    o.symmetry.kind = SR_SYM_AXIAL;
    o.have_alignment = 1;
    sr_xform_identity(o.alignment.xform);
    sr_recon_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_reconstruct(&cyl, &o, &r, &err), SR_OK);
    assert_int_equal(r.section_count, 1);
    sr_mesh up = {0};
    assert_int_equal(sr_boolean_union_local(&cyl, NULL, NULL, &r.sections[0].patch, NULL, 0,
                                            &up, NULL, &err),
                     SR_E_INVALID);
    assert_string_equal(err.msg, "'first mesh' intersects itself where the other mesh is");
    assert_int_equal(r.restored_by_union, 1);
    assert_string_equal(r.union_note, "");
    assert_non_null(strstr(r.repair_note, "triangles replaced where it crossed itself"));
    assert_true(sr_mesh_is_closed(&r.restored));
    int crossing = 1;
    assert_int_equal(sr_mesh_self_intersects(&r.restored, &crossing, NULL), SR_OK);
    assert_int_equal(crossing, 0);
    /* the restored cylinder: the intact volume up to the patch's error (the chip is
     * 4 mm deep, about 500 mm^3) and the block's part outside the wall (< 1.8 mm^3) */
    double vi = sr_mesh_volume(&intact), vd = sr_mesh_volume(&cyl);
    assert_true(r.restored_volume_mm3 > vd + 0.9 * (vi - vd) - 1.8);
    assert_true(r.restored_volume_mm3 < vi + 0.02 * (vi - vd) + 1.8);
    sr_recon_result_release(&r);
    sr_mesh_release(&cyl);
    sr_mesh_release(&intact);
}

/* A scan every union refuses (a hole far from the chip: not closed): the restored part
 * falls back to the scan followed by the patch, mapped back to the scan's frame, and
 * says why. */
static void refused_union_falls_back_to_scan_and_patch_shells(void **state)
{
    (void)state;
    sr_mesh cyl;
    make_cylinder(&cyl, 1);
    /* drop one side triangle at the far side (theta = 180 deg), low down */
    size_t hole = cyl.tri_count;
    for (size_t t = 0; t < cyl.tri_count && hole == cyl.tri_count; t++) {
        const double *p = cyl.xyz + 3 * cyl.tri[3 * t];
        if (p[0] < -19.9 && p[2] > 4 && p[2] < 6)
            hole = t;
    }
    assert_true(hole < cyl.tri_count);
    memmove(cyl.tri + 3 * hole, cyl.tri + 3 * (hole + 1),
            3 * (cyl.tri_count - hole - 1) * sizeof(uint32_t));
    cyl.tri_count--;
    for (size_t v = 0; v < cyl.vertex_count; v++)
        cyl.xyz[3 * v] -= 5.0;
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.method = SR_METHOD_ROBUST; /* its stacked patch, refused by every union */
    o.symmetry.kind = SR_SYM_AXIAL;
    o.have_alignment = 1;
    sr_xform_identity(o.alignment.xform);
    o.alignment.xform[3] = 5.0; /* scan -> aligned moves x by 5: the patch comes back */
    sr_recon_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_reconstruct(&cyl, &o, &r, &err), SR_OK);
    assert_int_equal(r.section_count, 1);
    assert_int_equal(r.restored_by_union, 0);
    assert_string_equal(r.union_note,
                        "section 1: 'first mesh' is not closed (3 boundary edges)");
    const sr_mesh *p = &r.sections[0].patch; /* in the scan's frame by now */
    assert_int_equal(r.restored.vertex_count, cyl.vertex_count + p->vertex_count);
    assert_int_equal(r.restored.tri_count, cyl.tri_count + p->tri_count);
    assert_memory_equal(r.restored.xyz, cyl.xyz, 3 * cyl.vertex_count * sizeof(double));
    assert_memory_equal(r.restored.xyz + 3 * cyl.vertex_count, p->xyz,
                        3 * p->vertex_count * sizeof(double));
    assert_true(fabs(r.restored_volume_mm3 - sr_mesh_volume(&cyl) - sr_mesh_volume(p)) <
                1e-6);
    sr_recon_result_release(&r);
    sr_mesh_release(&cyl);
}

/* A box on a box's face: the touching faces vanish (coplanar patches). */
static void touching_faces_unite_locally_as_whole(void **state)
{
    sr_mesh a, b;
    make_box(&a, 0, 0, 0, 4, 4, 1);
    make_box(&b, 1, 1, 1, 2, 2, 2);
    sr_local_union_info info;
    assert_local_is_whole(&a, &b, &info);
    assert_int_equal(info.local, 1);
    sr_mesh_release(&b);
    /* and overlapping with shared planes */
    make_box(&b, 3, 0, 0, 5, 4, 1);
    assert_local_is_whole(&a, &b, &info);
    assert_int_equal(info.local, 1);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* out = a: a's arrays are reused, the result is the same. */
static void union_in_place_grows_the_first_mesh(void **state)
{
    sr_mesh cyl, box, whole;
    make_cylinder(&cyl, 1);
    make_box(&box, 14, -7, 13.5, 21, 7, 26.5);
    assert_int_equal(sr_boolean_union(&cyl, &box, &whole, NULL), SR_OK);
    sr_local_union_info info;
    assert_int_equal(sr_boolean_union_local(&cyl, NULL, NULL, &box, NULL, 0, &cyl, &info, NULL),
                     SR_OK);
    assert_int_equal(info.local, 1);
    assert_same_surface(&cyl, &whole);
    /* and into b */
    sr_mesh scan;
    make_cylinder(&scan, 1);
    assert_int_equal(sr_boolean_union_local(&scan, NULL, NULL, &box, NULL, 0, &box, NULL, NULL),
                     SR_OK);
    assert_same_surface(&box, &whole);
    sr_mesh_release(&scan);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
    sr_mesh_release(&whole);
}

/* Every shared part's posed damaged scan with the largest patch the paper method builds
 * for it (60/80): wherever the whole-mesh union succeeds, the local one is the same. */
static void shared_parts_unite_locally_as_whole(void **state)
{
    /* three of the nine (all take too long under ASan): a chip, a gouge in a hollow
     * part, and a gear, whose patches meet the scan at distinct intersection points
     * rounded to the same coordinates */
    static const char *const parts[] = {"shaft_chipped_shoulder", "bushing_gouged",
                                        "spur_gear_broken_tooth"};
    struct stat sb;
    if (stat(PARTS_DIR, &sb) != 0) {
        skip();
        return;
    }
    size_t compared = 0, local = 0;
    for (size_t p = 0; p < sizeof parts / sizeof parts[0]; p++) {
        char path[512], truth[512];
        snprintf(path, sizeof path, "%s/%s/damaged_posed.stl", PARTS_DIR, parts[p]);
        snprintf(truth, sizeof truth, "%s/%s/truth.json", PARTS_DIR, parts[p]);
        sr_mesh scan;
        assert_int_equal(sr_mesh_read(path, &scan, NULL), SR_OK);
        /* the symmetry and the pose from truth.json: the alignment search is not what
         * is tested here (and is slow under ASan) */
        sr_truth t;
        assert_int_equal(sr_truth_read(truth, &t, NULL), SR_OK);
        sr_recon_opts o;
        memset(&o, 0, sizeof o);
        o.symmetry = t.symmetry;
        o.have_alignment = 1;
        sr_truth_to_canonical(&t, o.alignment.xform);
        o.method = SR_METHOD_PAPER;
        o.sectors = 60; /* few patch faces: the whole-mesh unions are slow under ASan */
        o.layers = 80;
        o.skip_union = 1;
        sr_recon_result r;
        assert_int_equal(sr_reconstruct(&scan, &o, &r, NULL), SR_OK);
        assert_true(r.section_count >= 1);
        sr_mesh whole, loc;
        sr_local_union_info info;
        sr_err err;
        sr_status st = sr_boolean_union(&scan, &r.sections[0].patch, &whole, &err);
        if (st != SR_OK)
            print_error("%s: %s\n", parts[p], err.msg);
        assert_int_equal(st, SR_OK);
        st = sr_boolean_union_local(&scan, NULL, NULL, &r.sections[0].patch, NULL, 0, &loc,
                                    &info, &err);
        if (st != SR_OK)
            print_error("%s: %s\n", parts[p], err.msg);
        assert_int_equal(st, SR_OK);
        assert_same_surface(&loc, &whole);
        print_message("%s: %zu triangles, %s%s\n", parts[p], loc.tri_count,
                      info.local ? "local" : "whole: ", info.fallback);
        compared++;
        local += info.local == 1;
        sr_mesh_release(&whole);
        sr_mesh_release(&loc);
        sr_recon_result_release(&r);
        sr_mesh_release(&scan);
    }
    assert_int_equal(local, compared);
}

/* ---- fall-backs to the whole-mesh union ------------------------------------------------ */

/* A patch wholly inside the scan meets none of its triangles: the open neighbourhood
 * cannot tell inside from outside, the whole union can (the scan comes back). */
static void patch_inside_the_scan_falls_back_to_the_whole_union(void **state)
{
    sr_mesh cyl, box, out;
    make_cylinder(&cyl, 0);
    make_box(&box, -2, -2, 10, 2, 2, 20);
    sr_local_union_info info;
    assert_int_equal(sr_boolean_union_local(&cyl, NULL, NULL, &box, NULL, 0, &out, &info, NULL),
                     SR_OK);
    print_message("fallback: %s\n", info.fallback);
    assert_int_equal(info.local, 0);
    assert_non_null(strstr(info.fallback, "meets no triangle"));
    assert_same_surface(&out, &cyl);
    sr_mesh_release(&out);
    sr_mesh_release(&box);
    /* wholly outside: two shells, as the whole union gives them */
    make_box(&box, 30, 0, 0, 31, 1, 1);
    assert_local_is_whole(&cyl, &box, &info);
    assert_int_equal(info.local, 0);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

/* Boxes meeting along an edge: the local result does not close up, the whole union
 * decides, and refuses as it does on its own. */
static void edge_touching_union_falls_back_and_is_refused(void **state)
{
    sr_mesh a, b, out;
    sr_err err;
    make_box(&a, 0, 0, 0, 1, 1, 1);
    make_box(&b, 1, 1, 0, 2, 2, 1);
    sr_local_union_info info;
    assert_int_equal(sr_boolean_union_local(&a, NULL, NULL, &b, NULL, 0, &out, &info, &err),
                     SR_E_INVALID);
    assert_int_equal(info.local, 0);
    assert_msg_has(err, "the result would not be a manifold");
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* ---- refusals: the whole union's, named the same ------------------------------------------ */

static void open_scan_is_refused_as_by_the_whole_union(void **state)
{
    sr_mesh cyl, box, out;
    sr_err err, err2;
    make_cylinder(&cyl, 0);
    make_box(&box, 18, -2, 10, 22, 2, 20);
    cyl.tri_count--; /* a hole far from the box */
    assert_int_equal(sr_boolean_union_local(&cyl, "scan", NULL, &box, "patch", 0, &out, NULL, &err),
                     SR_E_INVALID);
    assert_int_equal(sr_boolean_compute(SR_BOOLEAN_UNION, &cyl, "scan", &box, "patch", &out,
                                        &err2),
                     SR_E_INVALID);
    assert_string_equal(err.msg, err2.msg);
    assert_string_equal(err.msg, "'scan' is not closed (3 boundary edges)");
    cyl.tri_count++;
    sr_mesh_flip(&box);
    assert_int_equal(sr_boolean_union_local(&cyl, "scan", NULL, &box, "patch", 0, &out, NULL, &err),
                     SR_E_INVALID);
    assert_msg_has(err, "'patch' is inside out");
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

/* Two cubes sharing a corner, far from the patch: still refused (the result must be a
 * manifold surface), as the whole union refuses it. */
static void nonmanifold_vertex_far_away_is_refused(void **state)
{
    sr_mesh a, second, b, out;
    sr_err err;
    make_box(&a, 0, 0, 0, 1, 1, 1);
    make_box(&second, 1, 1, 1, 2, 2, 2);
    uint32_t base = (uint32_t)a.vertex_count;
    assert_int_equal(sr_mesh_append(&a, &second), SR_OK);
    /* weld the second box's corner (1,1,1) onto the first's */
    uint32_t corner1 = UINT32_MAX, corner2 = UINT32_MAX;
    for (uint32_t v = 0; v < a.vertex_count; v++) {
        const double *p = a.xyz + 3 * v;
        if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
            if (v < base)
                corner1 = v;
            else
                corner2 = v;
        }
    }
    assert_true(corner1 != UINT32_MAX && corner2 != UINT32_MAX);
    for (size_t i = 0; i < 3 * a.tri_count; i++)
        if (a.tri[i] == corner2)
            a.tri[i] = corner1;
    make_box(&b, 1.5, 1.5, 1.5, 2.5, 2.5, 2.5);
    sr_mesh_release(&second);
    assert_int_equal(sr_boolean_union_local(&a, NULL, NULL, &b, NULL, 0, &out, NULL, &err),
                     SR_E_INVALID);
    assert_msg_has(err, "'first mesh' has a non-manifold vertex");
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* Crossing triangles are refused only near the patch, as by the whole union. */
static void self_intersection_is_refused_only_near_the_patch(void **state)
{
    sr_mesh a, second, b, out, whole;
    sr_err err;
    make_box(&a, 0, 0, 0, 1, 1, 1);
    make_box(&second, 0.5, 0.5, 0.5, 1.5, 1.5, 1.5);
    assert_int_equal(sr_mesh_append(&a, &second), SR_OK);
    sr_mesh_release(&second);
    make_box(&b, 0.8, 0.2, 0.2, 3, 0.8, 0.8);
    assert_int_equal(sr_boolean_union_local(&a, NULL, NULL, &b, NULL, 0, &out, NULL, &err),
                     SR_E_INVALID);
    assert_string_equal(err.msg, "'first mesh' intersects itself where the other mesh is");
    sr_mesh_release(&b);
    /* a patch on a far box of the scan: the crossing is left alone */
    make_box(&second, 5, 0, 0, 6, 1, 1);
    assert_int_equal(sr_mesh_append(&a, &second), SR_OK);
    sr_mesh_release(&second);
    make_box(&b, 5.5, 0.2, 0.2, 6.5, 0.8, 0.8);
    sr_local_union_info info;
    assert_int_equal(sr_boolean_union_local(&a, NULL, NULL, &b, NULL, 0, &out, &info, &err), SR_OK);
    assert_int_equal(info.local, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &whole, NULL), SR_OK);
    assert_near(sr_mesh_volume(&out), sr_mesh_volume(&whole), 1e-12);
    assert_int_equal(out.tri_count, whole.tri_count);
    sr_mesh_release(&out);
    sr_mesh_release(&whole);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void degenerate_scan_is_refused(void **state)
{
    sr_mesh cyl, box, out;
    sr_err err;
    make_cylinder(&cyl, 0);
    make_box(&box, 18, -2, 10, 22, 2, 20);
    assert_int_equal(sr_boolean_union_local(&cyl, NULL, NULL, &box, NULL, 0, &out, NULL, &err),
                     SR_OK);
    sr_mesh_release(&out);
    sr_mesh bad;
    assert_int_equal(sr_mesh_copy(&bad, &cyl), SR_OK);
    /* squash triangle 0 by moving its third vertex onto its first: zero area, still
     * closed (indices unchanged) */
    uint32_t v0 = bad.tri[0], v1 = bad.tri[1];
    double *p = bad.xyz + 3 * (size_t)bad.tri[2];
    const double *q0 = bad.xyz + 3 * (size_t)v0, *q1 = bad.xyz + 3 * (size_t)v1;
    for (int k = 0; k < 3; k++)
        p[k] = 0.5 * (q0[k] + q1[k]);
    sr_mesh_report rep;
    assert_int_equal(sr_mesh_validate(&bad, "x", &rep, NULL), SR_OK);
    assert_true(rep.degenerate_tris > 0);
    assert_int_equal(sr_boolean_union_local(&bad, NULL, NULL, &box, NULL, 0, &out, NULL, &err),
                     SR_E_INVALID);
    assert_msg_has(err, "degenerate (zero-area) triangles");
    sr_mesh_release(&bad);
    sr_mesh_release(&cyl);
    sr_mesh_release(&box);
}

static void negative_margin_is_refused(void **state)
{
    sr_mesh a, b, out;
    sr_err err;
    make_box(&a, 0, 0, 0, 1, 1, 1);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_union_local(&a, NULL, NULL, &b, NULL, -1, &out, NULL, &err),
                     SR_E_RANGE);
    assert_string_equal(err.msg, "bad union margin -1 mm: expected 0 or more");
    assert_int_equal(sr_boolean_union_local(&a, NULL, NULL, &b, NULL, NAN, &out, NULL, &err),
                     SR_E_RANGE);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(chipped_cylinder_and_box_unite_locally_as_whole),
        cmocka_unit_test(chipped_cylinder_and_its_patch_unite_locally_as_whole),
        cmocka_unit_test(scan_crossing_itself_beside_the_chip_is_mended_and_united),
        cmocka_unit_test(refused_union_falls_back_to_scan_and_patch_shells),
        cmocka_unit_test(touching_faces_unite_locally_as_whole),
        cmocka_unit_test(union_in_place_grows_the_first_mesh),
        cmocka_unit_test(shared_parts_unite_locally_as_whole),
        cmocka_unit_test(patch_inside_the_scan_falls_back_to_the_whole_union),
        cmocka_unit_test(edge_touching_union_falls_back_and_is_refused),
        cmocka_unit_test(open_scan_is_refused_as_by_the_whole_union),
        cmocka_unit_test(nonmanifold_vertex_far_away_is_refused),
        cmocka_unit_test(self_intersection_is_refused_only_near_the_patch),
        cmocka_unit_test(degenerate_scan_is_refused),
        cmocka_unit_test(negative_margin_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
