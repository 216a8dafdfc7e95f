/*
 * test_scan_peel.c: sr_scan_peel_folds, sr_scan_peel_plane_rims and
 * sr_scan_close_peeling (src/mesh/scan_peel.c), and the fans of a walk through a vertex twice (src/mesh/scan_close.c), on meshes with
 * known answers. A block 40 x 12 x 30 (x -20..20) with a notch 8 x 6 x 8 (x 12..20,
 * y 0..6, z 0..8: 384 mm^3) cut at the face it stood on, that face left off as a scanner
 * leaves it, and a fold kept in its plane: a triangle at z = 0 inside the opening,
 * facing up (into the part), joined to the rim at the corner (-20, 0, 0), the walk
 * round the opening passing that corner twice (one loop of 7 + 3 edges, as on the
 * generated flange s60221409p13). The plane's fill would have to cover the fold twice:
 * the loop is fanned, one fan per cycle of its walk (one fan for both used its edges to
 * the corner four times: not manifold), closed with the block's volume, 14400 - 384
 * mm^3. Peeled first, the fold goes (1 triangle), the face is closed in its plane at
 * once, and the reconstruction by the mirror x = 0 finds the notch: one section of
 * 384 mm^3 from z = 0 to 8. A triangle of the face kept facing out (down) is no fold:
 * nothing is peeled, the closing keeps it. Three more scraps of the face facing out,
 * petals joined at one point of the opening: the walk cut where it passes a vertex
 * twice, each scrap's cycle is a hole in the face's fill, closed at once; where the fill
 * fails all the same, sr_scan_peel_plane_rims peels all four scraps and the face then
 * closes in its plane; the closing by sr_scan_close_peeling restores the notch. A second
 * scrap joined to the first at a corner, a tent standing on its edges, is peeled too
 * (growth through corners). A box without its top and no
 * fold: closed at once, nothing peeled. The fills reported are the triangles made.
 * Which pass's closing is kept (sr_scan_peel_kept): not one that leaves an edge fewer
 * bad by fanning an opening the first closing filled (a bracket's base, 2,717 mm^2).
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
#include "mesh/mesh.h"
#include "mesh/scan_describe.h"
#include "mesh/scan_int.h"
#include "mesh/shapes.h"
#include "reconstruct.h"
#include "support/assert_near.h"
#include "support/mesh_edit.h"
#include "support/open_face.h"

#define BLOCK_MM3 (40.0 * 12.0 * 30.0)
#define NOTCH_MM3 (8.0 * 6.0 * 8.0)

static void box(sr_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    assert_int_equal(sr_shape_box(lo, hi, m, NULL), SR_OK);
}

/* The index of m's vertex at p (exactly). */
static uint32_t vertex_at(const sr_mesh *m, const double p[3])
{
    for (size_t v = 0; v < m->vertex_count; v++)
        if (memcmp(m->xyz + 3 * v, p, 3 * sizeof *p) == 0)
            return (uint32_t)v;
    fail_msg("no vertex at (%g, %g, %g)", p[0], p[1], p[2]);
    return 0;
}

/* Appends the triangle (m's vertex at, a, b): a and b as new vertices. */
static void add_at(sr_mesh *m, uint32_t at, const double a[3], const double b[3])
{
    uint32_t va = test_add_vertex(m, a), vb = test_add_vertex(m, b);
    test_add_triangle(m, at, va, vb);
}

/* Vertex at numbered last, the last one in its place: the rims are walked from the
 * lowest vertex, so the walk round the opening passes at once out along the rim and
 * once into what stands on it there, one loop through it twice (as the scanned
 * flange's). */
static void number_last(sr_mesh *scan, uint32_t at)
{
    uint32_t last = (uint32_t)scan->vertex_count - 1;
    double tmp[3];
    memcpy(tmp, scan->xyz + 3 * (size_t)at, sizeof tmp);
    memcpy(scan->xyz + 3 * (size_t)at, scan->xyz + 3 * (size_t)last, sizeof tmp);
    memcpy(scan->xyz + 3 * (size_t)last, tmp, sizeof tmp);
    for (size_t i = 0; i < 3 * scan->tri_count; i++)
        scan->tri[i] = scan->tri[i] == at ? last : scan->tri[i] == last ? at : scan->tri[i];
}

/* The notched block without the face it stood on; with a triangle at z = 0 from the
 * corner (-20, 0, 0) into the opening, facing up (a fold) or down (the face kept). */
static void notched_scan(sr_mesh *scan, bool up)
{
    sr_mesh block, notch;
    box(&block, -20, 0, 0, 20, 12, 30);
    box(&notch, 12, -1, -1, 25, 6, 8);
    sr_err err = {{0}};
    assert_int_equal(sr_boolean_difference(&block, &notch, scan, &err), SR_OK);
    assert_near(sr_mesh_volume(scan), BLOCK_MM3 - NOTCH_MM3, 1e-6);
    assert_true(test_drop_face_at(scan, 0) > 0);
    const double corner[3] = {-20, 0, 0}, a[3] = {-10, 2, 0}, b[3] = {-12, 5, 0};
    uint32_t at = vertex_at(scan, corner);
    if (up)
        add_at(scan, at, a, b); /* counter-clockwise seen from above: facing up */
    else
        add_at(scan, at, b, a);
    number_last(scan, at);
    sr_mesh_release(&block);
    sr_mesh_release(&notch);
}

static bool closed_manifold(const sr_mesh *m)
{
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    return e.boundary_edges == 0 && e.nonmanifold_edges == 0 && e.misoriented_edges == 0;
}

/* Closes m by sr_scan_close_peeling and checks: peeled triangles peeled, loops loops (the
 * first closed in its plane), closed and manifold, volume mm^3. */
static void closes_peeling(sr_mesh *m, size_t peeled, size_t loops, double volume)
{
    sr_scan_desc d;
    sr_scan_closing *how = NULL;
    size_t n = SIZE_MAX;
    assert_int_equal(sr_scan_close_peeling(m, &d, &how, &n, NULL), SR_OK);
    assert_int_equal(n, peeled);
    assert_int_equal(d.loop_count, loops);
    assert_int_equal(how[0], SR_SCAN_IN_PLANE);
    assert_true(closed_manifold(m));
    assert_near(sr_mesh_volume(m), volume, 1e-6);
    free(how);
    sr_scan_desc_release(&d);
}

/* The reconstruction of scan (built in the aligned frame) by the mirror x = 0. */
static void reconstruct_mirror(const sr_mesh *scan, sr_recon_result *r)
{
    sr_recon_opts o;
    memset(&o, 0, sizeof o);
    o.symmetry = (sr_symmetry){SR_SYM_MIRROR, 0, 0};
    o.have_alignment = 1;
    sr_xform_identity(o.alignment.xform);
    sr_err err = {{0}};
    assert_int_equal(sr_reconstruct(scan, &o, r, &err), SR_OK);
}

static void a_walk_through_a_vertex_twice_is_fanned_cycle_by_cycle(void **state)
{
    (void)state;
    sr_mesh scan;
    notched_scan(&scan, true);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.component_count, 1); /* joined at the corner: no island */
    assert_int_equal(d.loop_count, 1);      /* through the corner twice */
    assert_int_equal(d.loops[0].edges, 10); /* 7 round the face, 3 round the fold */
    sr_scan_closing how[1];
    assert_int_equal(sr_scan_close_openings_how(&scan, &d, 0, NULL, how, NULL), SR_OK);
    assert_int_equal(how[0], SR_SCAN_BY_FAN); /* the fill would cover the fold twice */
    assert_true(closed_manifold(&scan));      /* one fan per cycle, not one for both */
    assert_near(sr_mesh_volume(&scan), BLOCK_MM3 - NOTCH_MM3, 1e-6);
    sr_scan_desc_release(&d);
    sr_mesh_release(&scan);
}

static void a_fold_in_the_base_is_peeled_and_the_notch_restored(void **state)
{
    (void)state;
    sr_mesh scan;
    notched_scan(&scan, true);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    size_t peeled = 0;
    assert_int_equal(sr_scan_peel_folds(&scan, &d, NULL, &peeled, NULL), SR_OK);
    assert_int_equal(peeled, 1);
    sr_scan_desc_release(&d);
    closes_peeling(&scan, 0, 1, BLOCK_MM3 - NOTCH_MM3); /* in its plane, at once */
    sr_recon_result r;
    reconstruct_mirror(&scan, &r);
    assert_int_equal(r.section_count, 1);
    assert_true(fabs(r.sections[0].volume_mm3 - NOTCH_MM3) <= 0.01 * NOTCH_MM3);
    assert_true(fabs(r.sections[0].z_min) < 1e-6 && fabs(r.sections[0].z_max - 8) < 1e-6);
    sr_recon_result_release(&r);
    sr_mesh_release(&scan);
}

static void a_piece_of_the_base_facing_out_is_kept(void **state)
{
    (void)state;
    sr_mesh scan;
    notched_scan(&scan, false);
    size_t tris = scan.tri_count;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    size_t peeled = 1;
    assert_int_equal(sr_scan_peel_folds(&scan, &d, NULL, &peeled, NULL), SR_OK);
    assert_int_equal(peeled, 0);
    assert_int_equal(scan.tri_count, tris);
    sr_scan_desc_release(&d);
    closes_peeling(&scan, 0, 1, BLOCK_MM3 - NOTCH_MM3);
    sr_mesh_release(&scan);
}

/* A needle of a wall's lowest row standing on the rim at the corner (-20, 0, 0) of the
 * opening, lying within the noise of the face's plane, facing sideways (no scrap of the
 * face, none of the peels takes it), joined to the rim there only: the walk round the
 * opening runs out along it and back, a cycle 0.01 mm wide in the plane (a fork's
 * open scan kept four such at one corner of its base: s46368p10). Outlined for the
 * face's fill it wound the face twice along itself and the face was fanned from its
 * centroid; closed alone (zipped: no vertex made), the face fills in its plane at
 * once. */
static void a_needle_on_the_rim_is_closed_alone_and_the_face_in_its_plane(void **state)
{
    (void)state;
    sr_mesh block, notch, scan;
    box(&block, -20, 0, 0, 20, 12, 30);
    box(&notch, 12, -1, -1, 25, 6, 8);
    assert_int_equal(sr_boolean_difference(&block, &notch, &scan, NULL), SR_OK);
    assert_true(test_drop_face_at(&scan, 0) > 0);
    const double corner[3] = {-20, 0, 0}, a[3] = {-17, 3.01, 0.03}, b[3] = {-17.01, 3, -0.03};
    uint32_t at = vertex_at(&scan, corner);
    add_at(&scan, at, a, b);
    number_last(&scan, at);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 1);      /* through the corner twice */
    assert_int_equal(d.loops[0].edges, 10); /* 7 round the face, 3 round the needle */
    sr_scan_closing how[1];
    size_t verts = scan.vertex_count;
    assert_int_equal(sr_scan_close_openings_how(&scan, &d, 0, NULL, how, NULL), SR_OK);
    assert_int_equal(how[0], SR_SCAN_IN_PLANE);
    assert_int_equal(scan.vertex_count, verts); /* the needle zipped shut, no centroid */
    assert_true(closed_manifold(&scan));
    assert_near(sr_mesh_volume(&scan), BLOCK_MM3 - NOTCH_MM3, 1e-3);
    sr_scan_desc_release(&d);
    sr_mesh_release(&block);
    sr_mesh_release(&notch);
    sr_mesh_release(&scan);
}

/* Scraps of the face the part stood on kept facing out, as a scanner keeps the ones the
 * noise tilted past its cut: a fan of petals round a point of the face, joined to one
 * another and to the rim only at vertices, so the walk round the opening passes each
 * joint twice (as on the generated bracket s1123581p02, whose base met its damage). */
static void petals_at(sr_mesh *scan, uint32_t at, const double *p, size_t n)
{
    for (size_t i = 0; i + 1 < n; i += 2)
        add_at(scan, at, p + 3 * (i + 1), p + 3 * i); /* clockwise from above: facing down */
}

static void scraps_of_the_base_facing_out_are_filled_round_or_peeled(void **state)
{
    (void)state;
    sr_mesh scan;
    notched_scan(&scan, false);          /* a scrap at the corner (-20, 0, 0), facing out */
    const double joint[3] = {-10, 2, 0}; /* the scrap's corner in the opening */
    const double petals[] = {-8, 3, 0, -7, 1, 0, -12, 0.5, 0, -13, 1.5, 0, -9, 5, 0, -11, 5.5, 0};
    petals_at(&scan, vertex_at(&scan, joint), petals, 6);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.component_count, 1); /* all joined at vertices */
    assert_int_equal(d.loop_count, 4);      /* the opening's walk, and a cycle per petal */
    sr_scan_closing how[4];
    sr_mesh as_is;
    assert_int_equal(sr_mesh_copy(&as_is, &scan), SR_OK);
    assert_int_equal(sr_scan_close_openings_how(&as_is, &d, 0, NULL, how, NULL), SR_OK);
    /* the opening's walk cut where it passes a vertex twice: the cycle round each scrap
     * is a hole in the face's fill, which the scrap, facing out, covers */
    for (size_t i = 0; i < 4; i++)
        assert_int_equal(how[i], SR_SCAN_IN_PLANE);
    assert_true(closed_manifold(&as_is));
    assert_near(sr_mesh_volume(&as_is), BLOCK_MM3 - NOTCH_MM3, 1e-6);
    sr_mesh_release(&as_is);
    /* where the fill fails all the same, every scrap lying in its plane goes, whichever
     * way it faces: the corner's and the three petals; then the face closes in its
     * plane at once */
    sr_mesh peeled_all;
    assert_int_equal(sr_mesh_copy(&peeled_all, &scan), SR_OK);
    size_t n = 0;
    how[0] = SR_SCAN_BY_FAN;
    assert_int_equal(sr_scan_peel_plane_rims(&peeled_all, &d, how, &n, NULL), SR_OK);
    assert_int_equal(n, 4);
    closes_peeling(&peeled_all, 0, 1, BLOCK_MM3 - NOTCH_MM3);
    sr_mesh_release(&peeled_all);
    sr_scan_desc_release(&d);
    sr_scan_closing *closing = NULL;
    size_t peeled = 0;
    assert_int_equal(sr_scan_close_peeling(&scan, &d, &closing, &peeled, NULL), SR_OK);
    assert_int_equal(peeled, 0); /* closed at once */
    for (size_t i = 0; i < d.loop_count; i++)
        assert_int_equal(closing[i], SR_SCAN_IN_PLANE); /* the face in its plane */
    assert_true(closed_manifold(&scan));
    assert_near(sr_mesh_volume(&scan), BLOCK_MM3 - NOTCH_MM3, 1e-6);
    free(closing);
    sr_scan_desc_release(&d);
    sr_recon_result r;
    reconstruct_mirror(&scan, &r);
    assert_int_equal(r.section_count, 1);
    assert_true(fabs(r.sections[0].volume_mm3 - NOTCH_MM3) <= 0.01 * NOTCH_MM3);
    sr_recon_result_release(&r);
    sr_mesh_release(&scan);
}

/* A second scrap lying in the face (facing out too) joined to the first only at its
 * corner a, with no edge on the rim: a tent stands on it (the two close a tetrahedron),
 * as the lace of a noisy base left such scraps, strips one sliver wide joined at
 * vertices. No edge of it is ever left on the rim: only growth through corners reaches
 * it. */
static void a_scrap_reached_only_through_corners_is_peeled(void **state)
{
    (void)state;
    sr_mesh scan;
    notched_scan(&scan, false); /* the first scrap: (corner, b, a) */
    const double pa[3] = {-10, 2, 0}, pr[3] = {-7, 4, 0}, pp[3] = {-6, 1, 0};
    uint32_t a = vertex_at(&scan, pa);
    add_at(&scan, a, pr, pp); /* the second scrap (a, r, p), clockwise from above */
    uint32_t r = (uint32_t)scan.vertex_count - 2, p = r + 1;
    const double top[3] = {-23.0 / 3, 7.0 / 3, 2}; /* above the second scrap's centroid */
    uint32_t q = test_add_vertex(&scan, top);      /* the tent's apex */
    test_add_triangle(&scan, r, a, q);
    test_add_triangle(&scan, p, r, q);
    test_add_triangle(&scan, a, p, q);
    size_t tris = scan.tri_count;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&scan, NULL, &d, NULL), SR_OK);
    size_t n = 0;
    assert_int_equal(sr_scan_peel_plane_rims(&scan, &d, NULL, &n, NULL), SR_OK);
    assert_int_equal(n, 2); /* both scraps; the tent stands */
    assert_int_equal(scan.tri_count, tris - 2);
    for (size_t t = scan.tri_count - 3; t < scan.tri_count; t++) /* the tent, last */
        assert_true(scan.xyz[3 * scan.tri[3 * t + 2] + 2] == 2);
    sr_scan_desc_release(&d);
    sr_mesh_release(&scan);
}

/* The open bracket s1346269p06's closings: the first left one edge bad and fanned
 * 10.9 mm^2 of specks; peeling every plane's folds mended the edge but fanned its base
 * (2,727.8 mm^2, its largest opening 2,717.2 mm^2), across its bores. */
static void a_peel_fanning_a_filled_opening_is_not_kept(void **state)
{
    (void)state;
    const double top = 2717.2;
    sr_scan_closing_cost first = {1, 0, 10.9, 0}, peeled = {0, 0, 2727.8, 0};
    assert_false(sr_scan_peel_kept(1, &first, &peeled, top));
    assert_false(sr_scan_peel_kept(0, &first, &peeled, top));
    /* an edge fewer with no more than a speck (1 % of the largest opening) more fanned */
    peeled.fan_mm2 = 10.9 + 0.009 * top;
    assert_true(sr_scan_peel_kept(1, &first, &peeled, top));
    peeled.fan_mm2 = 10.9 + 0.011 * top;
    assert_false(sr_scan_peel_kept(1, &first, &peeled, top));
    /* as many edges bad: kept when every plane then fills and the fans fall by at least
     * half the span the planes fanned */
    sr_scan_closing_cost fanned = {1, 1, 800, 700}, filled = {1, 0, 449, 0};
    assert_true(sr_scan_peel_kept(1, &fanned, &filled, top));
    filled.fan_mm2 = 451;
    assert_false(sr_scan_peel_kept(1, &fanned, &filled, top));
    /* pass 2 (scraps peeled off failed planes): every plane filled, no more bad, less
     * fanned */
    filled.fan_mm2 = 799;
    assert_true(sr_scan_peel_kept(2, &fanned, &filled, top));
    filled.bad_edges = 2;
    assert_false(sr_scan_peel_kept(2, &fanned, &filled, top));
}

static void an_open_box_without_folds_is_closed_at_once(void **state)
{
    (void)state;
    sr_mesh m;
    box(&m, 0, 0, 0, 10, 20, 30);
    assert_int_equal(test_drop_face_at(&m, 30), 2);
    closes_peeling(&m, 0, 1, 6000);
    sr_mesh_release(&m);
}

/* The fills sr_scan_close_peeling reports (sr_scan_desc.fills, src/mesh/scan_fills.c)
 * are the triangles it made: a box without its top and its bottom gets two triangles
 * in each of those planes, 400 mm² in all, every corner at z 0 or 30, none of the
 * walls'; a closed box gets none. */
static void the_fills_are_the_triangles_the_closing_made(void **state)
{
    (void)state;
    sr_mesh m;
    box(&m, 0, 0, 0, 10, 20, 30);
    assert_int_equal(test_drop_face_at(&m, 30), 2);
    assert_int_equal(test_drop_face_at(&m, 0), 2);
    sr_scan_desc d;
    sr_scan_closing *how = NULL;
    assert_int_equal(sr_scan_close_peeling(&m, &d, &how, NULL, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(&m));
    assert_int_equal(d.fills.tri_count, 4);
    assert_near(sr_mesh_area(&d.fills), 400, 1e-9);
    for (size_t t = 0; t < d.fills.tri_count; t++) {
        double z = d.fills.xyz[3 * d.fills.tri[3 * t] + 2];
        assert_true(z == 0 || z == 30);
        for (int k = 1; k < 3; k++)
            assert_true(d.fills.xyz[3 * d.fills.tri[3 * t + k] + 2] == z);
    }
    free(how);
    sr_scan_desc_release(&d);
    assert_int_equal(d.fills.tri_count, 0);
    sr_mesh_release(&m);
    box(&m, 0, 0, 0, 10, 20, 30);
    assert_int_equal(sr_scan_close_peeling(&m, &d, &how, NULL, NULL), SR_OK);
    assert_int_equal(d.fills.tri_count, 0);
    free(how);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_walk_through_a_vertex_twice_is_fanned_cycle_by_cycle),
        cmocka_unit_test(a_fold_in_the_base_is_peeled_and_the_notch_restored),
        cmocka_unit_test(a_piece_of_the_base_facing_out_is_kept),
        cmocka_unit_test(a_needle_on_the_rim_is_closed_alone_and_the_face_in_its_plane),
        cmocka_unit_test(scraps_of_the_base_facing_out_are_filled_round_or_peeled),
        cmocka_unit_test(a_scrap_reached_only_through_corners_is_peeled),
        cmocka_unit_test(a_peel_fanning_a_filled_opening_is_not_kept),
        cmocka_unit_test(an_open_box_without_folds_is_closed_at_once),
        cmocka_unit_test(the_fills_are_the_triangles_the_closing_made),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
