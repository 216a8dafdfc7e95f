/*
 * test_mesh.c: the core mesh type: validation, bbox, volume, area, edge topology,
 * welding, transforms, subsets. Geometry is built inline with exact answers.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>


#include "mesh/mesh.h"
#include "support/assert_near.h"

/* Unit cube [0,1]^3, 8 vertices, 12 outward triangles. */
static void make_cube(sr_mesh *m)
{
    static const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    static const uint32_t f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                      {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                      {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    assert_int_equal(sr_mesh_alloc(m, 8, 12), SR_OK);
    memcpy(m->xyz, v, sizeof v);
    memcpy(m->tri, f, sizeof f);
}

/* A regular n-gon prism (cylinder approximation) of radius r, height h. */
static void make_prism(sr_mesh *m, int n, double r, double h)
{
    assert_int_equal(sr_mesh_alloc(m, 2 * n + 2, 4 * n), SR_OK);
    for (int i = 0; i < n; i++) {
        double a = 2 * M_PI * i / n;
        double *p = m->xyz + 3 * i, *q = m->xyz + 3 * (n + i);
        p[0] = q[0] = r * cos(a);
        p[1] = q[1] = r * sin(a);
        p[2] = 0;
        q[2] = h;
    }
    double *c0 = m->xyz + 3 * (2 * n), *c1 = m->xyz + 3 * (2 * n + 1);
    c0[0] = c0[1] = c0[2] = 0;
    c1[0] = c1[1] = 0;
    c1[2] = h;
    uint32_t *t = m->tri;
    for (int i = 0; i < n; i++) {
        uint32_t a = i, b = (i + 1) % n, A = n + a, B = n + b;
        uint32_t tris[4][3] = {{a, b, B}, {a, B, A}, {2 * n, b, a}, {2 * n + 1, A, B}};
        memcpy(t, tris, sizeof tris);
        t += 12;
    }
}

static void cube_volume_area_bbox_are_exact(void **state)
{
    sr_mesh m;
    make_cube(&m);
    assert_near(sr_mesh_volume(&m), 1.0, 1e-15);
    assert_near(sr_mesh_area(&m), 6.0, 1e-15);
    double lo[3], hi[3];
    sr_mesh_bbox(&m, lo, hi);
    for (int k = 0; k < 3; k++) {
        assert_near(lo[k], 0.0, 0);
        assert_near(hi[k], 1.0, 0);
    }
    assert_true(sr_mesh_is_closed(&m));
    sr_mesh_release(&m);
}

static void prism_volume_matches_polygon_formula(void **state)
{
    for (int n = 3; n <= 96; n *= 2) {
        sr_mesh m;
        make_prism(&m, n, 20.0, 50.0);
        double expect = 0.5 * n * 400.0 * sin(2 * M_PI / n) * 50.0;
        assert_near(sr_mesh_volume(&m), expect, 1e-9 * expect);
        assert_true(sr_mesh_is_closed(&m));
        sr_mesh_release(&m);
    }
}

static void volume_is_translation_invariant_far_from_origin(void **state)
{
    sr_mesh m;
    make_cube(&m);
    double t[12] = {1, 0, 0, 1e6, 0, 1, 0, -2e6, 0, 0, 1, 3e6};
    sr_mesh_transform(&m, t);
    assert_near(sr_mesh_volume(&m), 1.0, 1e-9);
    sr_mesh_release(&m);
}

/* The volume on each side of a plane x = x0, without a boolean: the unit cube cut at
 * 0.3 holds 0.3 and 0.7; cut through its face x = 0 or beyond it, all on one side. A
 * hexagonal prism (radius 2, height 3; its slanted sides crossed) cut at x = 0.5: the
 * hexagon's part beyond is 2 sqrt 3 (a strip 0.5 wide and 2 sqrt 3 high, then a
 * triangle 1 wide), so 6 sqrt 3 above and 12 sqrt 3 below. */
static void volume_across_a_plane_is_each_sides_share(void **state)
{
    (void)state;
    sr_mesh m;
    make_cube(&m);
    double below, above;
    sr_mesh_volume_across_x(&m, 0.3, &below, &above);
    assert_near(below, 0.3, 1e-14);
    assert_near(above, 0.7, 1e-14);
    sr_mesh_volume_across_x(&m, 0.0, &below, &above);
    assert_near(below, 0.0, 1e-15);
    assert_near(above, 1.0, 1e-14);
    sr_mesh_volume_across_x(&m, 2.0, &below, &above);
    assert_near(below, 1.0, 1e-14);
    assert_near(above, 0.0, 1e-15);
    sr_mesh_release(&m);
    make_prism(&m, 6, 2.0, 3.0);
    sr_mesh_volume_across_x(&m, 0.5, &below, &above);
    assert_near(above, 6.0 * sqrt(3.0), 1e-12);
    assert_near(below, 12.0 * sqrt(3.0), 1e-12);
    assert_near(below + above, sr_mesh_volume(&m), 1e-12);
    sr_mesh_release(&m);
}

static void flipped_mesh_has_negative_volume(void **state)
{
    sr_mesh m;
    make_cube(&m);
    sr_mesh_flip(&m);
    assert_near(sr_mesh_volume(&m), -1.0, 1e-15);
    assert_true(sr_mesh_is_closed(&m));
    sr_mesh_release(&m);
}

/* The top of the unit cube (its triangles 2 and 3: {4,5,6} and {4,6,7}) as a mesh of
 * its own: 4 vertices in the order first used (4, 5, 6, 7), 2 triangles, area 1, and
 * each vertex's index in the cube. */
static void subset_keeps_the_chosen_triangles_in_order(void **state)
{
    (void)state;
    sr_mesh m, top;
    make_cube(&m);
    uint8_t keep[12] = {0, 0, 1, 1};
    uint32_t orig[8];
    assert_int_equal(sr_mesh_subset(&m, keep, &top, orig), SR_OK);
    assert_int_equal(top.vertex_count, 4);
    assert_int_equal(top.tri_count, 2);
    static const uint32_t want_tri[6] = {0, 1, 2, 0, 2, 3}, want_orig[4] = {4, 5, 6, 7};
    assert_memory_equal(top.tri, want_tri, sizeof want_tri);
    assert_memory_equal(orig, want_orig, sizeof want_orig);
    for (int v = 0; v < 4; v++)
        assert_memory_equal(top.xyz + 3 * v, m.xyz + 3 * want_orig[v], 3 * sizeof(double));
    assert_near(sr_mesh_area(&top), 1.0, 1e-12);
    sr_mesh_release(&top);
    memset(keep, 0, sizeof keep);
    assert_int_equal(sr_mesh_subset(&m, keep, &top, NULL), SR_OK);
    assert_int_equal(top.tri_count, 0);
    assert_int_equal(top.vertex_count, 0);
    sr_mesh_release(&top);
    sr_mesh_release(&m);
}

static void missing_face_gives_boundary_edges(void **state)
{
    sr_mesh m;
    make_cube(&m);
    m.tri_count = 11;
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.edge_count, 18);
    assert_int_equal(e.boundary_edges, 3);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_false(sr_mesh_is_closed(&m));
    sr_mesh_release(&m);
}

static void one_flipped_face_is_misoriented(void **state)
{
    sr_mesh m;
    make_cube(&m);
    uint32_t tmp = m.tri[1];
    m.tri[1] = m.tri[2];
    m.tri[2] = tmp;
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.boundary_edges, 0);
    assert_int_equal(e.misoriented_edges, 3);
    assert_false(sr_mesh_is_closed(&m));
    sr_mesh_release(&m);
}

/* Two cubes sharing one corner vertex: every edge is fine, the vertex has two fans. */
static void cubes_sharing_a_corner_have_a_nonmanifold_vertex(void **state)
{
    sr_mesh m, second;
    make_cube(&m);
    make_cube(&second);
    double t[12] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1};
    sr_mesh_transform(&second, t);
    assert_int_equal(sr_mesh_append(&m, &second), SR_OK);
    sr_mesh_release(&second);
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.nonmanifold_vertices, 0); /* two separate cubes so far */
    /* weld the second cube's (1,1,1) corner onto the first's */
    uint32_t keep = UINT32_MAX, drop = UINT32_MAX;
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const double *p = m.xyz + 3 * v;
        if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
            if (keep == UINT32_MAX)
                keep = v;
            else
                drop = v;
        }
    }
    assert_true(drop != UINT32_MAX);
    for (size_t i = 0; i < 3 * m.tri_count; i++)
        if (m.tri[i] == drop)
            m.tri[i] = keep;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.edge_count, 36);
    assert_int_equal(e.boundary_edges, 0);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_int_equal(e.nonmanifold_vertices, 1);
    assert_true(sr_mesh_is_closed(&m)); /* closed: edges only */
    /* an open fan is one fan: a cube without one face has none */
    sr_mesh c;
    make_cube(&c);
    c.tri_count = 10;
    assert_int_equal(sr_mesh_edge_stats(&c, &e), SR_OK);
    assert_int_equal(e.boundary_edges, 4);
    assert_int_equal(e.nonmanifold_vertices, 0);
    sr_mesh_release(&m);
    sr_mesh_release(&c);
}

static void three_faces_on_an_edge_are_nonmanifold(void **state)
{
    sr_mesh m, extra;
    make_cube(&m);
    /* a fin triangle on edge 0-1 */
    assert_int_equal(sr_mesh_alloc(&extra, 0, 0), SR_OK);
    sr_mesh_release(&extra);
    double *xyz = realloc(m.xyz, 9 * 3 * sizeof(double));
    uint32_t *tri = realloc(m.tri, 13 * 3 * sizeof(uint32_t));
    assert_non_null(xyz);
    assert_non_null(tri);
    m.xyz = xyz;
    m.tri = tri;
    m.xyz[24] = 0.5;
    m.xyz[25] = -1;
    m.xyz[26] = 0;
    m.tri[36] = 0;
    m.tri[37] = 1;
    m.tri[38] = 8;
    m.vertex_count = 9;
    m.tri_count = 13;
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.nonmanifold_edges, 1);
    assert_int_equal(e.boundary_edges, 2);
    assert_false(sr_mesh_is_closed(&m));
    sr_mesh_release(&m);
}

static void validate_accepts_cube(void **state)
{
    sr_mesh m;
    make_cube(&m);
    sr_mesh_report r;
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_validate(&m, "cube", &r, &err), SR_OK);
    assert_int_equal(r.degenerate_tris, 0);
    sr_mesh_release(&m);
}

static void validate_rejects_empty(void **state)
{
    sr_mesh m;
    sr_mesh_init(&m);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_validate(&m, "e.stl", NULL, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "'e.stl' contains no triangles"));
}

static void validate_rejects_nan_and_names_vertex(void **state)
{
    sr_mesh m;
    make_cube(&m);
    m.xyz[3 * 5 + 1] = NAN;
    sr_err err = {{0}};
    sr_mesh_report r;
    assert_int_equal(sr_mesh_validate(&m, "n.stl", &r, &err), SR_E_INVALID);
    assert_int_equal(r.nonfinite_vertices, 1);
    assert_non_null(strstr(err.msg, "vertex 5"));
    sr_mesh_release(&m);
}

static void validate_rejects_inf(void **state)
{
    sr_mesh m;
    make_cube(&m);
    m.xyz[0] = -INFINITY;
    assert_int_equal(sr_mesh_validate(&m, "i", NULL, NULL), SR_E_INVALID);
    sr_mesh_release(&m);
}

static void validate_rejects_index_out_of_range(void **state)
{
    sr_mesh m;
    make_cube(&m);
    m.tri[3 * 7 + 2] = 8;
    sr_err err = {{0}};
    sr_mesh_report r;
    assert_int_equal(sr_mesh_validate(&m, "o.obj", &r, &err), SR_E_INVALID);
    assert_int_equal(r.bad_indices, 1);
    assert_non_null(strstr(err.msg, "triangle 7"));
    sr_mesh_release(&m);
}

static void validate_counts_degenerate_faces(void **state)
{
    sr_mesh m;
    make_cube(&m);
    m.tri[1] = m.tri[0];          /* repeated index */
    m.xyz[3 * 4] = 0;             /* already collinear? make face 2 (4,5,6) zero area: */
    m.xyz[3 * 5 + 0] = 0;
    m.xyz[3 * 5 + 1] = 0;
    m.xyz[3 * 5 + 2] = 1;         /* 5 == 4 coordinates -> faces using 4 and 5 collapse */
    sr_mesh_report r;
    assert_int_equal(sr_mesh_validate(&m, "d", &r, NULL), SR_OK);
    assert_true(r.degenerate_tris >= 2);
    sr_mesh_release(&m);
}

static void weld_merges_split_vertices(void **state)
{
    sr_mesh m;
    make_cube(&m);
    /* un-share: every triangle gets its own three vertices (36 vertices) */
    sr_mesh s;
    assert_int_equal(sr_mesh_alloc(&s, 36, 12), SR_OK);
    for (size_t i = 0; i < 36; i++) {
        memcpy(s.xyz + 3 * i, m.xyz + 3 * m.tri[i], 3 * sizeof(double));
        s.tri[i] = (uint32_t)i;
    }
    s.xyz[2] = -0.0; /* -0 must weld with +0 */
    assert_false(sr_mesh_is_closed(&s));
    assert_int_equal(sr_mesh_weld_exact(&s), SR_OK);
    assert_int_equal(s.vertex_count, 8);
    assert_int_equal(s.tri_count, 12);
    assert_true(sr_mesh_is_closed(&s));
    assert_near(sr_mesh_volume(&s), 1.0, 1e-15);
    sr_mesh_release(&s);
    sr_mesh_release(&m);
}

static void weld_drops_collapsed_triangles(void **state)
{
    sr_mesh m;
    make_cube(&m);
    memcpy(m.xyz + 3 * 6, m.xyz + 3 * 5, 3 * sizeof(double)); /* vertex 6 onto 5 */
    assert_int_equal(sr_mesh_weld_exact(&m), SR_OK);
    assert_int_equal(m.vertex_count, 7);
    /* faces (4,5,6) and (1,6,5) collapse */
    assert_int_equal(m.tri_count, 10);
    sr_mesh_release(&m);
}

static void rotation_keeps_volume_and_inverse_restores(void **state)
{
    sr_mesh m, orig;
    make_prism(&m, 24, 10, 30);
    assert_int_equal(sr_mesh_copy(&orig, &m), SR_OK);
    double a = 0.7, b = -1.2;
    double rz[12] = {cos(a), -sin(a), 0, 5, sin(a), cos(a), 0, -7, 0, 0, 1, 11};
    double rx[12] = {1, 0, 0, 0, 0, cos(b), -sin(b), 0, 0, sin(b), cos(b), 0};
    double r[12], inv[12];
    sr_xform_mul(r, rz, rx);
    sr_mesh_transform(&m, r);
    assert_near(sr_mesh_volume(&m), sr_mesh_volume(&orig), 1e-9);
    sr_xform_rigid_inverse(inv, r);
    sr_mesh_transform(&m, inv);
    for (size_t i = 0; i < m.vertex_count * 3; i++)
        assert_near(m.xyz[i], orig.xyz[i], 1e-12);
    sr_mesh_release(&m);
    sr_mesh_release(&orig);
}

/* A mirror's image of a closed prism, mapped (sr_mesh_map), still faces out: the same
 * positive volume; transformed alone it is inside out. A turn keeps the orientation. */
static void a_mapped_mirror_image_faces_out(void **state)
{
    (void)state;
    sr_mesh m, t;
    make_prism(&m, 24, 10, 30);
    double v = sr_mesh_volume(&m);
    const double mirror[12] = {-1, 0, 0, 3, 0, 1, 0, 0, 0, 0, 1, 0};
    const double turn[12] = {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 2};
    assert_near(sr_xform_det(mirror), -1, 0);
    assert_near(sr_xform_det(turn), 1, 0);
    assert_int_equal(sr_mesh_copy(&t, &m), SR_OK);
    sr_mesh_transform(&t, mirror);
    assert_near(sr_mesh_volume(&t), -v, 1e-9);
    sr_mesh_release(&t);
    assert_int_equal(sr_mesh_copy(&t, &m), SR_OK);
    sr_mesh_map(&t, mirror);
    assert_near(sr_mesh_volume(&t), v, 1e-9);
    assert_near(t.xyz[0], 3 - m.xyz[0], 1e-12);
    sr_mesh_release(&t);
    assert_int_equal(sr_mesh_copy(&t, &m), SR_OK);
    sr_mesh_map(&t, turn);
    assert_near(sr_mesh_volume(&t), v, 1e-9);
    assert_memory_equal(t.tri, m.tri, 3 * m.tri_count * sizeof *m.tri);
    sr_mesh_release(&t);
    sr_mesh_release(&m);
}

static void xform_mul_applies_right_first(void **state)
{
    double t[12] = {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0};            /* x += 1 */
    double s[12] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0};            /* scale 2 */
    double ts[12], p[3] = {1, 1, 1}, out[3];
    sr_xform_mul(ts, t, s); /* scale, then translate */
    sr_xform_apply(ts, p, out);
    assert_near(out[0], 3, 0);
    assert_near(out[1], 2, 0);
}

static void append_and_copy_keep_geometry(void **state)
{
    sr_mesh a, b;
    make_cube(&a);
    make_prism(&b, 8, 1, 1);
    double vb = sr_mesh_volume(&b);
    sr_mesh c;
    assert_int_equal(sr_mesh_copy(&c, &a), SR_OK);
    assert_int_equal(sr_mesh_append(&c, &b), SR_OK);
    assert_int_equal(c.vertex_count, a.vertex_count + b.vertex_count);
    assert_int_equal(c.tri_count, 12 + b.tri_count);
    assert_near(sr_mesh_area(&c), sr_mesh_area(&a) + sr_mesh_area(&b), 1e-12);
    assert_true(c.tri[3 * 12] >= 8);
    (void)vb;
    sr_mesh_release(&a);
    sr_mesh_release(&b);
    sr_mesh_release(&c);
    sr_mesh_release(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cube_volume_area_bbox_are_exact),
        cmocka_unit_test(prism_volume_matches_polygon_formula),
        cmocka_unit_test(volume_is_translation_invariant_far_from_origin),
        cmocka_unit_test(volume_across_a_plane_is_each_sides_share),
        cmocka_unit_test(flipped_mesh_has_negative_volume),
        cmocka_unit_test(missing_face_gives_boundary_edges),
        cmocka_unit_test(subset_keeps_the_chosen_triangles_in_order),
        cmocka_unit_test(one_flipped_face_is_misoriented),
        cmocka_unit_test(three_faces_on_an_edge_are_nonmanifold),
        cmocka_unit_test(cubes_sharing_a_corner_have_a_nonmanifold_vertex),
        cmocka_unit_test(validate_accepts_cube),
        cmocka_unit_test(validate_rejects_empty),
        cmocka_unit_test(validate_rejects_nan_and_names_vertex),
        cmocka_unit_test(validate_rejects_inf),
        cmocka_unit_test(validate_rejects_index_out_of_range),
        cmocka_unit_test(validate_counts_degenerate_faces),
        cmocka_unit_test(weld_merges_split_vertices),
        cmocka_unit_test(weld_drops_collapsed_triangles),
        cmocka_unit_test(rotation_keeps_volume_and_inverse_restores),
        cmocka_unit_test(a_mapped_mirror_image_faces_out),
        cmocka_unit_test(xform_mul_applies_right_first),
        cmocka_unit_test(append_and_copy_keep_geometry),
    };
    return cmocka_run_group_tests_name("mesh", tests, NULL, NULL);
}
