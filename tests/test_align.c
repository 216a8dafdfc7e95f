/*
 * test_align.c: finding the symmetry element of a scan and the transform to the
 * canonical frame (align.h).
 *
 * Exact CAD geometry (src/mesh/shapes.h solids and meshes built here) is moved by a known
 * random rigid pose and must be found again within 0.01 deg and 0.01 mm: cylinders and
 * stepped, chipped solids of revolution (axial), a 6-fold star prism (n-fold), a
 * mirror prism, a box with three mirror planes (the widest-spread rule, and the hint
 * picking another), a glide-symmetric bar (shift searched, and given). A wrong kind
 * must show in the fit score; runs are deterministic. The paper's Algorithm 3 alone
 * (method 1) is checked as the heuristic it is (a degree or so). The frame conventions
 * (rigid, axis to x = y = 0, z = 0 at the lowest point, plane to x = 0) and the override
 * (sr_align_from_axis) are checked exactly; every rejected input has its own case, and
 * a failing call must leave *out untouched.
 *
 * Then the nine shared parts (../shared/parts/<part>/, skipped when absent): the damaged
 * part in its pose (damaged_posed.stl, the CAD mesh) and the dense noisy scan
 * (damaged_scan.stl, sigma 0.02 mm) are aligned given only the symmetry kind of
 * truth.json (+ the gear's order); the axis or plane must match the pose within bounds
 * set just above what was measured (angle, and the largest offset between the found and
 * the true element over the part's extent). The measured numbers are printed.
 *
 * SYMREC_TEST_FILTER=<glob> runs only the matching cases (e.g. "part_*").
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "align/align.h"
#include "bridge/boolean.h"
#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/random_pose.h"
#include "support/truth.h"

#define PARTS_DIR "../shared/parts"

/* ---------------------------------------------------------------- helpers ---- */

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Angle between two lines, degrees (sign ignored). */
static double line_angle_deg(const double a[3], const double b[3])
{
    double c = fabs(dot3(a, b)) / sqrt(dot3(a, a) * dot3(b, b));
    return acos(c > 1 ? 1 : c) * 180 / M_PI;
}

/* Column k of the rotation of a 3x4 transform. */
static void column(const double m[12], int k, double out[3])
{
    out[0] = m[k];
    out[1] = m[4 + k];
    out[2] = m[8 + k];
}

/* Largest distance, over the mesh's extent along the true axis (point tp, direction
 * td), between the true axis and the found one. */
static double axis_offset(const sr_mesh *mesh, const double tp[3], const double td[3],
                          const sr_alignment *a)
{
    double worst = 0;
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        const double *p = mesh->xyz + 3 * v;
        double d[3] = {p[0] - tp[0], p[1] - tp[1], p[2] - tp[2]};
        double s = dot3(d, td) / dot3(td, td);
        double q[3] = {tp[0] + s * td[0], tp[1] + s * td[1], tp[2] + s * td[2]};
        double e[3] = {q[0] - a->axis_point[0], q[1] - a->axis_point[1],
                       q[2] - a->axis_point[2]};
        double along = dot3(e, a->axis_dir);
        double r2 = dot3(e, e) - along * along;
        double r = sqrt(r2 > 0 ? r2 : 0);
        worst = r > worst ? r : worst;
    }
    return worst;
}

/* Largest distance, over the mesh's footprint on the true plane (point tp, unit normal
 * tn), between the true plane and the found one. */
static double plane_offset(const sr_mesh *mesh, const double tp[3], const double tn[3],
                           const sr_alignment *a)
{
    double worst = 0;
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        const double *p = mesh->xyz + 3 * v;
        double s = dot3(p, tn) - dot3(tp, tn);
        double q[3] = {p[0] - s * tn[0], p[1] - s * tn[1], p[2] - s * tn[2]};
        double e[3] = {q[0] - a->axis_point[0], q[1] - a->axis_point[1],
                       q[2] - a->axis_point[2]};
        double r = fabs(dot3(e, a->plane_normal));
        worst = r > worst ? r : worst;
    }
    return worst;
}

/* The rotation of xform is orthonormal with determinant +1, and axis_dir /
 * plane_normal / axis_point agree with it. */
static void assert_frame_consistent(const sr_alignment *a, int planar)
{
    const double *m = a->xform;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = m[4 * i] * m[4 * j] + m[4 * i + 1] * m[4 * j + 1] +
                       m[4 * i + 2] * m[4 * j + 2];
            assert_near(d, i == j, 1e-12);
        }
    double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                 m[2] * (m[4] * m[9] - m[5] * m[8]);
    assert_near(det, 1, 1e-12);
    /* canonical z is axis_dir, the canonical origin is axis_point */
    for (int k = 0; k < 3; k++)
        assert_near(m[8 + k], a->axis_dir[k], 1e-12);
    double o[3];
    sr_xform_apply(m, a->axis_point, o);
    for (int k = 0; k < 3; k++)
        assert_near(o[k], 0, 1e-9);
    if (planar)
        for (int k = 0; k < 3; k++)
            assert_near(m[k], a->plane_normal[k], 1e-12);
    assert_true(a->fit_score >= 0 && a->fit_score <= 1);
    assert_true(a->fit_rms_mm >= 0);
}

static double radius_const20(double theta, size_t ring, void *user)
{
    (void)theta;
    (void)ring;
    (void)user;
    return 20;
}

/* Stepped shaft: r 20 (z 0..40), 30 (z 40..55), 15 (z 55..90), with a chip: the
 * shoulder's rings lose 4 mm of radius between 0 and 70 deg. */
static double radius_stepped_chipped(double theta, size_t ring, void *user)
{
    (void)user;
    static const double r[] = {20, 20, 30, 30, 15, 15};
    double v = r[ring];
    if ((ring == 2 || ring == 3) && theta < 70 * M_PI / 180)
        v -= 4;
    return v;
}

static void make_stepped(sr_mesh *m)
{
    static const double z[] = {0, 40, 40, 55, 55, 90};
    sr_revolve_opts o = {0};
    o.segments = 128;
    o.ring_count = 6;
    o.ring_z = z;
    o.outer = radius_stepped_chipped;
    sr_err err;
    assert_int_equal(sr_shape_revolve(&o, m, &err), SR_OK);
}

/* Runs sr_align on `mesh` moved by pose `seed`; checks the axis (canonical z through
 * the origin) or plane (canonical x = 0) within the bounds; returns the alignment. */
static sr_alignment align_posed(const sr_mesh *canon, unsigned seed, const sr_symmetry *sym,
                                const sr_align_opts *opts, double max_deg, double max_mm)
{
    sr_mesh m;
    assert_int_equal(sr_mesh_copy(&m, canon), SR_OK);
    double pose[12];
    test_random_pose(seed, pose);
    sr_mesh_transform(&m, pose);
    sr_alignment a;
    sr_err err = {{0}};
    assert_int_equal(sr_align(&m, sym, opts, &a, &err), SR_OK);
    double tp[3] = {pose[3], pose[7], pose[11]}, tz[3], tx[3];
    column(pose, 2, tz);
    column(pose, 0, tx);
    double ang, off;
    if (sym->kind == SR_SYM_AXIAL) {
        ang = line_angle_deg(a.axis_dir, tz);
        off = axis_offset(&m, tp, tz, &a);
    } else {
        ang = line_angle_deg(a.plane_normal, tx);
        off = plane_offset(&m, tp, tx, &a);
    }
    if (!(ang <= max_deg && off <= max_mm)) {
        print_error("pose %u: angle %.6f deg (max %g), offset %.6f mm (max %g)\n", seed, ang,
                    max_deg, off, max_mm);
        fail();
    }
    assert_frame_consistent(&a, sym->kind != SR_SYM_AXIAL);
    sr_mesh_release(&m);
    return a;
}

/* ------------------------------------------------------- exact CAD geometry ---- */

static void axial_cylinder_axis_found_in_any_pose(void **state)
{
    (void)state;
    sr_mesh c;
    sr_err err;
    assert_int_equal(sr_shape_cylinder(20, 0, 60, 96, &c, &err), SR_OK);
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    for (unsigned seed = 1; seed <= 2; seed++) {
        sr_alignment a = align_posed(&c, seed, &sym, NULL, 0.01, 0.01);
        assert_true(a.fit_score > 0.95);
        assert_true(a.fit_rms_mm < 0.05);
        for (int k = 0; k < 3; k++)
            assert_near(a.plane_normal[k], 0, 0);
        assert_near(a.glide_shift_mm, 0, 0);
    }
    sr_mesh_release(&c);
}

static void axial_chipped_stepped_shaft_axis_found(void **state)
{
    (void)state;
    sr_mesh m;
    make_stepped(&m);
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_alignment a = align_posed(&m, 7, &sym, NULL, 0.01, 0.01);
    /* the chip (part of the shoulder) has no rotated partner */
    assert_true(a.fit_score > 0.7 && a.fit_score < 0.99);
    sr_mesh_release(&m);
}

static void axial_canonical_frame_puts_axis_on_z_and_part_above_zero(void **state)
{
    (void)state;
    sr_mesh m;
    make_stepped(&m);
    double pose[12];
    test_random_pose(11, pose);
    sr_mesh_transform(&m, pose);
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_alignment a;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, NULL), SR_OK);
    sr_mesh_transform(&m, a.xform);
    double lo[3], hi[3];
    sr_mesh_bbox(&m, lo, hi);
    assert_near(lo[2], 0, 1e-9);  /* z = 0 at the lowest point */
    assert_near(hi[2], 90, 0.01); /* the part's length along the axis */
    /* the journal ring (r = 15 at z = 90) is round about the new z axis */
    for (size_t v = 0; v < m.vertex_count; v++) {
        const double *p = m.xyz + 3 * v;
        if (p[2] > 89.99 && hypot(p[0], p[1]) > 1)
            assert_near(hypot(p[0], p[1]), 15, 0.005);
    }
    /* the axis direction keeps the scan's +z side up */
    assert_true(a.axis_dir[2] > 0);
    sr_mesh_release(&m);
}

/* A 6-pointed star (outer radius 30, inner 18) extruded 0..12: 6-fold symmetric. */
static void make_star(sr_mesh *m, int points, double ro, double ri)
{
    double xy[2 * 24];
    for (int i = 0; i < 2 * points; i++) {
        double r = i % 2 ? ri : ro, t = M_PI * i / points;
        xy[2 * i] = r * cos(t);
        xy[2 * i + 1] = r * sin(t);
    }
    sr_err err;
    assert_int_equal(sr_shape_prism(xy, (size_t)(2 * points), 0, 12, m, &err), SR_OK);
}

static void axial_nfold_star_axis_found(void **state)
{
    (void)state;
    sr_mesh m;
    make_star(&m, 6, 30, 18);
    sr_symmetry sym = {SR_SYM_AXIAL, 6, 0};
    sr_alignment a = align_posed(&m, 5, &sym, NULL, 0.01, 0.01);
    assert_true(a.fit_score > 0.95);
    /* the star is not round: as a continuous axis it fits far worse */
    sr_symmetry cont = {SR_SYM_AXIAL, 0, 0};
    sr_alignment b = align_posed(&m, 5, &cont, NULL, 1, 0.5);
    assert_true(b.fit_score < a.fit_score - 0.2);
    sr_mesh_release(&m);
}

/* An arrow-like heptagon (counter-clockwise), mirror-symmetric about x = 0 only,
 * extruded 0..20. */
static void make_arrow(sr_mesh *m)
{
    static const double xy[] = {0, 40, -20, 15, -8, 15, -8, -30, 8, -30, 8, 15, 20, 15};
    sr_err err;
    assert_int_equal(sr_shape_prism(xy, 7, 0, 20, m, &err), SR_OK);
}

static void mirror_arrow_plane_found_and_frame_puts_it_at_x0(void **state)
{
    (void)state;
    sr_mesh m;
    make_arrow(&m);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    sr_alignment a = align_posed(&m, 3, &sym, NULL, 0.01, 0.01);
    assert_true(a.fit_score > 0.95);
    /* in the canonical frame the part is its own mirror image in x = 0 */
    sr_mesh p;
    assert_int_equal(sr_mesh_copy(&p, &m), SR_OK);
    double pose[12];
    test_random_pose(3, pose);
    sr_mesh_transform(&p, pose);
    sr_mesh_transform(&p, a.xform);
    double lo[3], hi[3];
    sr_mesh_bbox(&p, lo, hi);
    assert_near(lo[0], -20, 0.01);
    assert_near(hi[0], 20, 0.01);
    assert_near(lo[2], 0, 1e-9);             /* z = 0 at the lowest point along z */
    assert_near(lo[1] + hi[1], 0, 1e-9);     /* y centred */
    assert_near(a.glide_shift_mm, 0, 0);
    sr_mesh_release(&p);
    sr_mesh_release(&m);
}

/* A lever on the mirror x = 0: a web (box wlo..whi) between two bosses standing on
 * z = 0 (radius, height, y of each, segments round), less the damage `cut`. */
typedef struct boss {
    double r, h, y;
    size_t segments;
} boss;

static void lever_less(const double wlo[3], const double whi[3], boss b1, boss b2,
                       const sr_mesh *cut, sr_mesh *lever)
{
    sr_mesh web, c1, c2, a, b;
    assert_int_equal(sr_shape_box(wlo, whi, &web, NULL), SR_OK);
    assert_int_equal(sr_shape_cylinder(b1.r, 0, b1.h, b1.segments, &c1, NULL), SR_OK);
    assert_int_equal(sr_shape_cylinder(b2.r, 0, b2.h, b2.segments, &c2, NULL), SR_OK);
    for (size_t v = 0; v < c1.vertex_count; v++)
        c1.xyz[3 * v + 1] += b1.y;
    for (size_t v = 0; v < c2.vertex_count; v++)
        c2.xyz[3 * v + 1] += b2.y;
    assert_int_equal(sr_boolean_union(&web, &c1, &a, NULL), SR_OK);
    assert_int_equal(sr_boolean_union(&a, &c2, &b, NULL), SR_OK);
    assert_int_equal(sr_boolean_difference(&b, cut, lever, NULL), SR_OK);
    sr_mesh_release(&web);
    sr_mesh_release(&c1);
    sr_mesh_release(&c2);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* A lever: web 8 wide and 8 thick from y = -30 to 52, a boss of radius 14 (20 high) at
 * y = -30, one of radius 8 (16 high) at y = 52, less a chip (its planes tilted 12 deg)
 * off the +x side of the small boss and the web from y = 10 on. The web's faces reflect
 * onto themselves whatever the plane's tilt about z, and the chip took what pinned that
 * tilt at the far end: without the restarts the fit settled 2.2 deg and 3.5 mm off in
 * one of these poses (1.6 deg on a generated lever). */
static void mirror_lever_with_a_chipped_boss_keeps_its_plane(void **state)
{
    (void)state;
    sr_mesh chip, lever;
    double clo[3] = {1.0, 10, 3}, chi[3] = {30, 70, 30};
    assert_int_equal(sr_shape_box(clo, chi, &chip, NULL), SR_OK);
    double t = 12 * M_PI / 180, c = cos(t), sn = sin(t); /* the fracture's planes tilted */
    double tilt[12] = {c, 0, -sn, 1.0 - 1.0 * c, 0, 1, 0, 0, sn, 0, c, -1.0 * sn};
    sr_mesh_transform(&chip, tilt);
    double wlo[3] = {-4, -30, 0}, whi[3] = {4, 52, 8};
    lever_less(wlo, whi, (boss){14, 20, -30, 64}, (boss){8, 16, 52, 48}, &chip, &lever);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    for (unsigned seed = 1; seed <= 3; seed++)
        align_posed(&lever, seed, &sym, NULL, 0.1, 0.05);
    sr_mesh_release(&chip);
    sr_mesh_release(&lever);
}

/* A lever whose damage took the half of one boss beside the plane (a cut 1.2 mm off it,
 * parallel to it, through the whole boss: the generated lever s2207p14): what is left
 * of the plane's evidence pivots about the other boss, whose round walls reflect onto
 * themselves about any plane through its axis. The restarts tilted about the part's
 * centre left the fit 1.4 deg off, pivoting there (the restored boss 1.5 mm out: 45 %
 * of the loss missed); restarted about points along the plane too, it is found. */
static void mirror_lever_with_half_a_boss_gone_keeps_its_plane(void **state)
{
    (void)state;
    sr_mesh cut, lever;
    double clo[3] = {-20, -50, -1}, chi[3] = {-1.2, -14, 20};
    assert_int_equal(sr_shape_box(clo, chi, &cut, NULL), SR_OK);
    double wlo[3] = {-3.45, -31, 0}, whi[3] = {3.45, 31, 7};
    lever_less(wlo, whi, (boss){12, 17.5, -31, 64}, (boss){16, 13, 31, 64}, &cut, &lever);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    for (unsigned seed = 1; seed <= 3; seed++)
        align_posed(&lever, seed, &sym, NULL, 0.1, 0.05);
    sr_mesh_release(&cut);
    sr_mesh_release(&lever);
}

/* A box 80 x 30 x 6: three mirror planes. The plane across the widest spread (x = 0)
 * is preferred over the thin mid-plane and the y mid-plane. */
static void mirror_prefers_the_plane_across_the_widest_spread(void **state)
{
    (void)state;
    sr_mesh m;
    sr_err err;
    double lo[3] = {-40, -15, 0}, hi[3] = {40, 15, 6};
    assert_int_equal(sr_shape_box(lo, hi, &m, &err), SR_OK);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    align_posed(&m, 9, &sym, NULL, 0.01, 0.01);
    sr_mesh_release(&m);
}

/* The same box with a hint along its y axis: the y = 0 plane, which also fits, is
 * taken instead. */
static void mirror_hint_picks_another_good_plane(void **state)
{
    (void)state;
    sr_mesh m;
    sr_err err;
    double lo[3] = {-40, -15, 0}, hi[3] = {40, 15, 6};
    assert_int_equal(sr_shape_box(lo, hi, &m, &err), SR_OK);
    double pose[12], ty[3];
    test_random_pose(9, pose);
    sr_mesh_transform(&m, pose);
    column(pose, 1, ty);
    sr_align_opts o = {0};
    /* a rough hint, 20 deg off */
    double tx[3];
    column(pose, 0, tx);
    for (int k = 0; k < 3; k++)
        o.hint[k] = cos(20 * M_PI / 180) * ty[k] + sin(20 * M_PI / 180) * tx[k];
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    sr_alignment a;
    assert_int_equal(sr_align(&m, &sym, &o, &a, &err), SR_OK);
    assert_true(line_angle_deg(a.plane_normal, ty) < 0.01);
    /* without the hint: the plane across the 80 mm length */
    assert_int_equal(sr_align(&m, &sym, NULL, &a, &err), SR_OK);
    assert_true(line_angle_deg(a.plane_normal, tx) < 0.01);
    sr_mesh_release(&m);
}

/* Rail-like bar along z (0..200): a foot on -y (so y -> -y is no symmetry) and
 * bumps 6 mm high on +x at z = 20k + 2 .. 20k + 10 and on -x at z = 20k + 12 ..
 * 20k + 20: glide
 * symmetric for (x, y, z) -> (-x, y, z + 10) away from the ends, not mirror
 * symmetric. Made of overlapping boxes (alignment needs no closed surface). */
static void make_glide_bar(sr_mesh *m)
{
    sr_err err;
    double lo[3] = {-5, -3, 0}, hi[3] = {5, 3, 200};
    assert_int_equal(sr_shape_box(lo, hi, m, &err), SR_OK);
    sr_mesh b;
    double flo[3] = {-10, -6, 0}, fhi[3] = {10, -3, 200};
    assert_int_equal(sr_shape_box(flo, fhi, &b, &err), SR_OK);
    assert_int_equal(sr_mesh_append(m, &b), SR_OK);
    sr_mesh_release(&b);
    for (int k = 0; k < 10; k++) {
        double plo[3] = {5, -3, 20.0 * k + 2}, phi[3] = {11, 3, 20.0 * k + 10};
        assert_int_equal(sr_shape_box(plo, phi, &b, &err), SR_OK);
        assert_int_equal(sr_mesh_append(m, &b), SR_OK);
        sr_mesh_release(&b);
        double nlo[3] = {-11, -3, 20.0 * k + 12}, nhi[3] = {-5, 3, 20.0 * k + 20};
        assert_int_equal(sr_shape_box(nlo, nhi, &b, &err), SR_OK);
        assert_int_equal(sr_mesh_append(m, &b), SR_OK);
        sr_mesh_release(&b);
    }
}

static void glide_bar_plane_and_shift_found(void **state)
{
    (void)state;
    sr_mesh m;
    make_glide_bar(&m);
    sr_symmetry sym = {SR_SYM_GLIDE, 0, 0};
    sr_alignment a = align_posed(&m, 4, &sym, NULL, 0.01, 0.01);
    assert_near(a.glide_shift_mm, 10, 0.01);
    /* the in-plane axis is the shift direction: the bar's length */
    double pose[12], tz[3];
    test_random_pose(4, pose);
    column(pose, 2, tz);
    assert_true(line_angle_deg(a.axis_dir, tz) < 0.01);
    sr_mesh_release(&m);
}

static void glide_given_shift_is_kept(void **state)
{
    (void)state;
    sr_mesh m;
    make_glide_bar(&m);
    sr_symmetry sym = {SR_SYM_GLIDE, 0, 10};
    sr_alignment a = align_posed(&m, 6, &sym, NULL, 0.01, 0.01);
    assert_near(a.glide_shift_mm, 10, 0);
    sr_mesh_release(&m);
}

static void wrong_kind_shows_a_poor_fit(void **state)
{
    (void)state;
    /* the glide bar is no solid of revolution, and no mirror */
    sr_mesh m;
    make_glide_bar(&m);
    sr_symmetry ax = {SR_SYM_AXIAL, 0, 0}, mi = {SR_SYM_MIRROR, 0, 0},
                gl = {SR_SYM_GLIDE, 0, 0};
    sr_alignment a, b, c;
    assert_int_equal(sr_align(&m, &ax, NULL, &a, NULL), SR_OK);
    assert_int_equal(sr_align(&m, &mi, NULL, &b, NULL), SR_OK);
    assert_int_equal(sr_align(&m, &gl, NULL, &c, NULL), SR_OK);
    assert_true(c.fit_score > 0.9);
    assert_true(a.fit_score < 0.6);
    assert_true(b.fit_score < c.fit_score - 0.03);
    sr_mesh_release(&m);
}

static void alignment_is_deterministic(void **state)
{
    (void)state;
    sr_mesh m;
    make_stepped(&m);
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_alignment a, b;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, NULL), SR_OK);
    assert_int_equal(sr_align(&m, &sym, NULL, &b, NULL), SR_OK);
    assert_memory_equal(&a, &b, sizeof a);
    sr_mesh_release(&m);
}

/* The queries spread over two threads give the alignment one thread gives, to the bit:
 * a posed chipped lever (the mirror search with its tilted restarts), the glide bar
 * (the shift scan) and the stepped shaft (the axial search), each also within its
 * bounds both ways. */
static void one_thread_and_two_give_the_same_alignment(void **state)
{
    (void)state;
    sr_mesh chip, lever, bar, shaft;
    double clo[3] = {1.0, 10, 3}, chi[3] = {30, 70, 30};
    assert_int_equal(sr_shape_box(clo, chi, &chip, NULL), SR_OK);
    double wlo[3] = {-4, -30, 0}, whi[3] = {4, 52, 8};
    lever_less(wlo, whi, (boss){14, 20, -30, 64}, (boss){8, 16, 52, 48}, &chip, &lever);
    make_glide_bar(&bar);
    make_stepped(&shaft);
    const sr_mesh *parts[3] = {&lever, &bar, &shaft};
    sr_symmetry syms[3] = {{SR_SYM_MIRROR, 0, 0}, {SR_SYM_GLIDE, 0, 0}, {SR_SYM_AXIAL, 0, 0}};
    double bound_deg[3] = {0.1, 0.01, 0.05}, bound_mm[3] = {0.05, 0.01, 0.05};
    for (int i = 0; i < 3; i++) {
        sr_align_opts one = {.threads = 1}, two = {.threads = 2};
        sr_alignment a = align_posed(parts[i], 7, &syms[i], &one, bound_deg[i], bound_mm[i]);
        sr_alignment b = align_posed(parts[i], 7, &syms[i], &two, bound_deg[i], bound_mm[i]);
        assert_memory_equal(&a, &b, sizeof a);
    }
    sr_mesh_release(&chip);
    sr_mesh_release(&lever);
    sr_mesh_release(&bar);
    sr_mesh_release(&shaft);
}

/* The paper's Algorithm 3 alone, on a cylinder dense in vertices (many rings, as
 * Algorithm 1 needs vertices in every layer): a heuristic, within a degree or so. */
static void paper_method_aligns_a_dense_cylinder(void **state)
{
    (void)state;
    double z[81];
    for (int i = 0; i <= 80; i++)
        z[i] = i;
    sr_revolve_opts o = {0};
    o.segments = 144;
    o.ring_count = 81;
    o.ring_z = z;
    o.outer = radius_const20;
    sr_mesh m;
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_align_opts opts = {0};
    opts.method = 1;
    opts.layers = 40;
    opts.coarse_step_deg = 10; /* then 2 and 0.4 deg around the winner */
    sr_alignment a = align_posed(&m, 2, &sym, &opts, 0.3, 0.25); /* measured 0.18, 0.13 */
    assert_true(a.symmetric_layers >= 20); /* most of the 40 layers */
    sr_mesh_release(&m);
}

static double radius_egg(double theta, size_t ring, void *user)
{
    (void)ring;
    (void)user;
    return 30 + 10 * cos(theta);
}

/* Algorithm 3 for a mirror: an egg-shaped prism (r = 30 + 10 cos theta, z 0..60, a
 * ring every 1.5 mm) is mirror-symmetric about y = 0, a plane containing the slicing
 * axis (method 0 would prefer the mid-height plane z = 30, across the wider spread). */
static void paper_method_finds_a_mirror_plane_through_the_slicing_axis(void **state)
{
    (void)state;
    double z[41];
    for (int i = 0; i <= 40; i++)
        z[i] = 1.5 * i;
    sr_revolve_opts ro = {0};
    ro.segments = 120;
    ro.ring_count = 41;
    ro.ring_z = z;
    ro.outer = radius_egg;
    sr_mesh m;
    assert_int_equal(sr_shape_revolve(&ro, &m, NULL), SR_OK);
    double pose[12], ty[3];
    test_random_pose(8, pose);
    sr_mesh_transform(&m, pose);
    column(pose, 1, ty);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    sr_align_opts opts = {0};
    opts.method = 1;
    opts.layers = 40;
    sr_alignment a;
    assert_int_equal(sr_align(&m, &sym, &opts, &a, NULL), SR_OK);
    /* a heuristic: plane angles come in half-sector steps (2.5 deg), tilts in 0.4 deg
     * steps on a 10 deg grid; measured 3.3 deg */
    double ang = line_angle_deg(a.plane_normal, ty);
    if (!(ang < 4)) {
        print_error("paper mirror plane off by %.3f deg\n", ang);
        fail();
    }
    assert_true(a.symmetric_layers >= 20);
    assert_frame_consistent(&a, 1);
    sr_mesh_release(&m);
}

/* ------------------------------------------------------------ the override ---- */

static void from_axis_builds_the_axial_frame(void **state)
{
    (void)state;
    double p[3] = {1, 2, 3}, d[3] = {0, 0, 2};
    sr_alignment a;
    assert_int_equal(sr_align_from_axis(p, d, NULL, &a, NULL), SR_OK);
    static const double want[12] = {1, 0, 0, -1, 0, 1, 0, -2, 0, 0, 1, -3};
    for (int i = 0; i < 12; i++)
        assert_near(a.xform[i], want[i], 1e-15);
    /* a tilted axis: its points go to x = y = 0, the given point to the origin */
    double p2[3] = {5, -1, 2}, d2[3] = {1, 1, 0};
    assert_int_equal(sr_align_from_axis(p2, d2, NULL, &a, NULL), SR_OK);
    double q[3] = {15, 9, 2}, o[3];
    sr_xform_apply(a.xform, q, o);
    assert_near(o[0], 0, 1e-12);
    assert_near(o[1], 0, 1e-12);
    assert_near(o[2], sqrt(200.0), 1e-12);
    sr_xform_apply(a.xform, p2, o);
    for (int k = 0; k < 3; k++)
        assert_near(o[k], 0, 1e-12);
    assert_frame_consistent(&a, 0);
}

static void from_axis_builds_the_planar_frame(void **state)
{
    (void)state;
    double p[3] = {0, 0, 0}, t[3] = {0, 1, 0}, n[3] = {0, 0, 3};
    sr_alignment a;
    assert_int_equal(sr_align_from_axis(p, t, n, &a, NULL), SR_OK);
    /* canonical x = the normal (scan z), canonical z = the in-plane axis (scan y) */
    double q[3] = {7, 8, 9}, o[3];
    sr_xform_apply(a.xform, q, o);
    assert_near(o[0], 9, 1e-15);
    assert_near(o[2], 8, 1e-15);
    assert_near(fabs(o[1]), 7, 1e-15);
    assert_frame_consistent(&a, 1);
    /* an in-plane axis not quite in the plane is made perpendicular to the normal */
    double t2[3] = {0, 1, 0.5};
    assert_int_equal(sr_align_from_axis(p, t2, n, &a, NULL), SR_OK);
    assert_near(a.axis_dir[2], 0, 1e-15);
    assert_near(a.axis_dir[1], 1, 1e-15);
}

static void from_axis_round_trips_an_alignment(void **state)
{
    (void)state;
    sr_mesh m;
    make_arrow(&m);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    sr_alignment a, b;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, NULL), SR_OK);
    assert_int_equal(sr_align_from_axis(a.axis_point, a.axis_dir, a.plane_normal, &b, NULL),
                     SR_OK);
    for (int i = 0; i < 12; i++)
        assert_near(b.xform[i], a.xform[i], 1e-9);
    sym.kind = SR_SYM_AXIAL;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, NULL), SR_OK);
    assert_int_equal(sr_align_from_axis(a.axis_point, a.axis_dir, NULL, &b, NULL), SR_OK);
    for (int i = 0; i < 12; i++)
        assert_near(b.xform[i], a.xform[i], 1e-9);
    sr_mesh_release(&m);
}

static sr_alignment sentinel_alignment(void)
{
    sr_alignment a;
    memset(&a, 0x5a, sizeof a);
    return a;
}

static void assert_alignment_untouched(const sr_alignment *a)
{
    sr_alignment s = sentinel_alignment();
    assert_memory_equal(a, &s, sizeof s);
}

static void from_axis_rejects_a_zero_direction(void **state)
{
    (void)state;
    double p[3] = {0, 0, 0}, d[3] = {0, 0, 0};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align_from_axis(p, d, NULL, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "axis direction");
    assert_alignment_untouched(&a);
}

static void from_axis_rejects_a_non_finite_point(void **state)
{
    (void)state;
    double p[3] = {0, NAN, 0}, d[3] = {0, 0, 1};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align_from_axis(p, d, NULL, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "axis point");
    assert_alignment_untouched(&a);
}

static void from_axis_rejects_a_zero_normal(void **state)
{
    (void)state;
    double p[3] = {0, 0, 0}, d[3] = {0, 0, 1}, n[3] = {0, 0, 0};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align_from_axis(p, d, n, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "plane normal");
    assert_alignment_untouched(&a);
}

static void from_axis_rejects_an_axis_along_the_normal(void **state)
{
    (void)state;
    double p[3] = {0, 0, 0}, d[3] = {0, 0, 1}, n[3] = {0, 0, -2};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align_from_axis(p, d, n, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "parallel");
    assert_alignment_untouched(&a);
}

/* ------------------------------------------------------- rejected inputs ---- */

static void align_rejects_an_empty_mesh(void **state)
{
    (void)state;
    sr_mesh m = {0};
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, &err), SR_E_INVALID);
    assert_msg_has(err, "no triangles");
    assert_alignment_untouched(&a);
}

static void align_rejects_a_nan_vertex(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_shape_cylinder(10, 0, 10, 8, &m, NULL), SR_OK);
    m.xyz[4] = NAN;
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, &err), SR_E_INVALID);
    assert_msg_has(err, "NaN");
    assert_alignment_untouched(&a);
    sr_mesh_release(&m);
}

static void align_rejects_a_mesh_without_area(void **state)
{
    (void)state;
    /* two triangles, both on one line */
    sr_mesh m;
    assert_int_equal(sr_mesh_alloc(&m, 3, 2), SR_OK);
    static const double v[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    static const uint32_t f[6] = {0, 1, 2, 2, 1, 0};
    memcpy(m.xyz, v, sizeof v);
    memcpy(m.tri, f, sizeof f);
    sr_symmetry sym = {SR_SYM_MIRROR, 0, 0};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    assert_int_equal(sr_align(&m, &sym, NULL, &a, &err), SR_E_INVALID);
    assert_msg_has(err, "area");
    assert_alignment_untouched(&a);
    sr_mesh_release(&m);
}

static void align_rejects_a_bad_symmetry(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_shape_cylinder(10, 0, 10, 8, &m, NULL), SR_OK);
    sr_alignment a = sentinel_alignment();
    sr_err err;
    sr_symmetry none = {SR_SYM_NONE, 0, 0};
    assert_int_equal(sr_align(&m, &none, NULL, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "kind");
    sr_symmetry order = {SR_SYM_AXIAL, 1, 0};
    assert_int_equal(sr_align(&m, &order, NULL, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "order");
    sr_symmetry shift = {SR_SYM_GLIDE, 0, -1};
    assert_int_equal(sr_align(&m, &shift, NULL, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "shift");
    assert_alignment_untouched(&a);
    sr_mesh_release(&m);
}

static void align_rejects_bad_options(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_shape_cylinder(10, 0, 10, 8, &m, NULL), SR_OK);
    sr_symmetry sym = {SR_SYM_AXIAL, 0, 0};
    sr_alignment a = sentinel_alignment();
    sr_err err;
    static const struct {
        sr_align_opts o;
        const char *field;
    } bad[] = {
        {{.method = 2}, "method"},
        {{.method = -1}, "method"},
        {{.layers = -5}, "layers"},
        {{.sectors = 3}, "sectors"},
        {{.sectors = -1}, "sectors"},
        {{.delta_d = -0.1}, "delta_d"},
        {{.delta_d = 1.5}, "delta_d"},
        {{.delta_d = NAN}, "delta_d"},
        {{.coarse_step_deg = -1}, "coarse_step_deg"},
        {{.coarse_step_deg = 90}, "coarse_step_deg"},
        {{.hint = {0, INFINITY, 0}}, "hint"},
        {{.threads = -1}, "threads"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(sr_align(&m, &sym, &bad[i].o, &a, &err), SR_E_RANGE);
        assert_msg_has(err, bad[i].field);
    }
    assert_alignment_untouched(&a);
    sr_mesh_release(&m);
}

/* ----------------------------------------------------------- shared parts ---- */

typedef struct part_case {
    const char *name;
    /* bounds (measured, then a margin): posed CAD mesh, then dense noisy scan */
    double posed_deg, posed_mm, scan_deg, scan_mm;
} part_case;

/* Measured (deg, mm; posed / scan): shaft 0.0001 0.0003 / 0.0009 0.0009, bushing
 * 0.0001 0.0001 / 0.0007 0.0006, keyed shaft 0.0001 0.0002 / 0.0008 0.0010, flange
 * 0.0002 0.0001 / 0.0004 0.0007, gear 0.0000 0.0000 / 0.0023 0.0005, bracket 0.0001
 * 0.0001 / 0.0015 0.0009, U clamp 0.0002 0.0001 / 0.0016 0.0008, rail 0.0000 0.0000 /
 * 0.0011 0.0008 (shift 10.000 / 9.999), lever 0.0001 0.0001 / 0.0005 0.0007. The goal
 * (issue 6) is 0.1 deg and 0.05 mm; the bounds are about twice the measured values. */
static const part_case parts[] = {
    {"shaft_chipped_shoulder", 0.001, 0.001, 0.002, 0.002},
    {"bushing_gouged", 0.001, 0.001, 0.002, 0.002},
    {"keyed_shaft_dent", 0.001, 0.001, 0.002, 0.002},
    {"flange_broken_rim", 0.001, 0.001, 0.002, 0.002},
    {"spur_gear_broken_tooth", 0.001, 0.001, 0.005, 0.002},
    {"bracket_broken_ear", 0.001, 0.001, 0.003, 0.002},
    {"u_clamp_broken_arm", 0.001, 0.001, 0.003, 0.002},
    {"rail_glide_chipped", 0.001, 0.001, 0.003, 0.002},
    {"lever_posed", 0.001, 0.001, 0.002, 0.002},
};

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void check_part_file(const part_case *pc, const sr_truth *truth, const char *file,
                            double max_deg, double max_mm)
{
    char path[512];
    snprintf(path, sizeof path, PARTS_DIR "/%s/%s", pc->name, file);
    sr_mesh m;
    sr_err err = {{0}};
    double r0 = cpu_seconds();
    sr_status st = sr_mesh_read(path, &m, &err);
    double rsecs = cpu_seconds() - r0;
    if (st != SR_OK) {
        print_error("%s\n", err.msg);
        fail();
    }
    sr_symmetry sym = truth->symmetry;
    sym.shift_mm = 0; /* the glide shift is searched */
    sr_alignment a;
    double t0 = cpu_seconds();
    assert_int_equal(sr_align(&m, &sym, NULL, &a, &err), SR_OK);
    double secs = cpu_seconds() - t0;
    const double *R = truth->R;
    double tz[3] = {R[2], R[5], R[8]}, tx[3] = {R[0], R[3], R[6]};
    double ang, off;
    if (sym.kind == SR_SYM_AXIAL) {
        ang = line_angle_deg(a.axis_dir, tz);
        off = axis_offset(&m, truth->t, tz, &a);
    } else {
        ang = line_angle_deg(a.plane_normal, tx);
        off = plane_offset(&m, truth->t, tx, &a);
    }
    printf("    %-24s %-18s %7zu tri  angle %.4f deg  offset %.4f mm  fit %.3f / %.4f mm"
           "  %.2f s cpu (read %.2f s)",
           pc->name, file, m.tri_count, ang, off, a.fit_score, a.fit_rms_mm, secs, rsecs);
    if (sym.kind == SR_SYM_GLIDE)
        printf("  shift %.3f mm", a.glide_shift_mm);
    printf("\n");
    if (!(ang <= max_deg && off <= max_mm)) {
        print_error("%s/%s: angle %.5f deg (max %g), offset %.5f mm (max %g)\n", pc->name,
                    file, ang, max_deg, off, max_mm);
        fail();
    }
    if (sym.kind == SR_SYM_GLIDE)
        assert_near(a.glide_shift_mm, truth->symmetry.shift_mm, 0.01);
    assert_frame_consistent(&a, sym.kind != SR_SYM_AXIAL);
    sr_mesh_release(&m);
}

static void run_part(const part_case *pc)
{
    char path[512];
    snprintf(path, sizeof path, PARTS_DIR "/%s/truth.json", pc->name);
    if (access(path, R_OK) != 0)
        skip();
    sr_truth truth;
    sr_err err = {{0}};
    if (sr_truth_read(path, &truth, &err) != SR_OK) {
        print_error("%s\n", err.msg);
        fail();
    }
    check_part_file(pc, &truth, "damaged_posed.stl", pc->posed_deg, pc->posed_mm);
    check_part_file(pc, &truth, "damaged_scan.stl", pc->scan_deg, pc->scan_mm);
}

#define PART_TEST(fn, i)                                                               \
    static void fn(void **state)                                                       \
    {                                                                                  \
        (void)state;                                                                   \
        run_part(&parts[i]);                                                           \
    }
PART_TEST(part_shaft_chipped_shoulder, 0)
PART_TEST(part_bushing_gouged, 1)
PART_TEST(part_keyed_shaft_dent, 2)
PART_TEST(part_flange_broken_rim, 3)
PART_TEST(part_spur_gear_broken_tooth, 4)
PART_TEST(part_bracket_broken_ear, 5)
PART_TEST(part_u_clamp_broken_arm, 6)
PART_TEST(part_rail_glide_chipped, 7)
PART_TEST(part_lever_posed, 8)

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(axial_cylinder_axis_found_in_any_pose),
        cmocka_unit_test(axial_chipped_stepped_shaft_axis_found),
        cmocka_unit_test(axial_canonical_frame_puts_axis_on_z_and_part_above_zero),
        cmocka_unit_test(axial_nfold_star_axis_found),
        cmocka_unit_test(mirror_arrow_plane_found_and_frame_puts_it_at_x0),
        cmocka_unit_test(mirror_lever_with_a_chipped_boss_keeps_its_plane),
        cmocka_unit_test(mirror_lever_with_half_a_boss_gone_keeps_its_plane),
        cmocka_unit_test(mirror_prefers_the_plane_across_the_widest_spread),
        cmocka_unit_test(mirror_hint_picks_another_good_plane),
        cmocka_unit_test(glide_bar_plane_and_shift_found),
        cmocka_unit_test(glide_given_shift_is_kept),
        cmocka_unit_test(wrong_kind_shows_a_poor_fit),
        cmocka_unit_test(alignment_is_deterministic),
        cmocka_unit_test(one_thread_and_two_give_the_same_alignment),
        cmocka_unit_test(paper_method_aligns_a_dense_cylinder),
        cmocka_unit_test(paper_method_finds_a_mirror_plane_through_the_slicing_axis),
        cmocka_unit_test(from_axis_builds_the_axial_frame),
        cmocka_unit_test(from_axis_builds_the_planar_frame),
        cmocka_unit_test(from_axis_round_trips_an_alignment),
        cmocka_unit_test(from_axis_rejects_a_zero_direction),
        cmocka_unit_test(from_axis_rejects_a_non_finite_point),
        cmocka_unit_test(from_axis_rejects_a_zero_normal),
        cmocka_unit_test(from_axis_rejects_an_axis_along_the_normal),
        cmocka_unit_test(align_rejects_an_empty_mesh),
        cmocka_unit_test(align_rejects_a_nan_vertex),
        cmocka_unit_test(align_rejects_a_mesh_without_area),
        cmocka_unit_test(align_rejects_a_bad_symmetry),
        cmocka_unit_test(align_rejects_bad_options),
        cmocka_unit_test(part_shaft_chipped_shoulder),
        cmocka_unit_test(part_bushing_gouged),
        cmocka_unit_test(part_keyed_shaft_dent),
        cmocka_unit_test(part_flange_broken_rim),
        cmocka_unit_test(part_spur_gear_broken_tooth),
        cmocka_unit_test(part_bracket_broken_ear),
        cmocka_unit_test(part_u_clamp_broken_arm),
        cmocka_unit_test(part_rail_glide_chipped),
        cmocka_unit_test(part_lever_posed),
    };
    /* SYMREC_TEST_FILTER=pattern runs only the matching cases (cmocka glob) */
    const char *filter = getenv("SYMREC_TEST_FILTER");
    if (filter && *filter)
        cmocka_set_test_filter(filter);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
