/*
 * test_mesh_float.c: sr_mesh_float_ready (src/mesh/mesh_float.c) and the STL writer
 * that uses it, on meshes with known answers: a box whose vertices lie apart at float
 * precision is kept whole (coordinates rounded, every triangle in order); the box with
 * a tetrahedron a nanometre thin beside it (five millimetres up: a float there is half a micrometre coarse), closed in double precision, loses the
 * tetrahedron at float precision: one vertex welded, two triangles flat, the other two
 * a flap, dropped; written as STL and read back, the file holds the box alone, closed.
 * Two sliver tetrahedra whose tips meet (q and q' one float position, r a float step
 * off): the weld crowds edge q-r with four triangles, so r is welded as well and both
 * slivers go; r a step beyond the neighbourhood stays, and the edge stays crowded.
 * The flaps' pairing (src/mesh/tri_flaps.c, shared with the closing of a scan) on four
 * triangles on one set of corners, two each way: which pairs it makes with and
 * without a first new triangle, and that unpicked triangles take no part.
 */
#include <math.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "bridge/mesh_io.h"
#include "mesh/mesh_float.h"
#include "mesh/shapes.h"
#include "mesh/tri_flaps.h"
#include "support/assert_near.h"
#include "support/tmpdir.h"

static const double box_lo[3] = {0.1, 0.2, 0.3}, box_hi[3] = {10.7, 20.9, 30.3};

/* The box with a closed tetrahedron (a, b, c, c') beside it, c' a nanometre above c:
 * 12 + 4 triangles, 8 + 4 vertices, closed in double precision. */
static void box_and_thin_tetrahedron(sr_mesh *m)
{
    sr_mesh box = {0}, tet = {0};
    assert_int_equal(sr_shape_box(box_lo, box_hi, &box, NULL), SR_OK);
    assert_int_equal(sr_mesh_alloc(&tet, 4, 4), SR_OK);
    const double xyz[12] = {40, 0, 5, 41, 0, 5, 40, 1, 5, 40, 1, 5 + 1e-9};
    const uint32_t tri[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
    memcpy(tet.xyz, xyz, sizeof xyz);
    memcpy(tet.tri, tri, sizeof tri);
    assert_true(sr_mesh_is_closed(&tet));
    assert_true(sr_mesh_volume(&tet) > 0);
    *m = box;
    assert_int_equal(sr_mesh_append(m, &tet), SR_OK);
    sr_mesh_release(&tet);
}

static void a_mesh_apart_at_float_precision_is_kept_whole(void **state)
{
    (void)state;
    sr_mesh box = {0}, out = {0};
    assert_int_equal(sr_shape_box(box_lo, box_hi, &box, NULL), SR_OK);
    assert_int_equal(sr_mesh_float_welds(&box), 0); /* the writer takes it as it is */
    sr_float_report r = {9, 9, 9, 9};
    assert_int_equal(sr_mesh_float_ready(&box, &out, &r), SR_OK);
    assert_int_equal(r.welded, 0);
    assert_int_equal(r.degenerate, 0);
    assert_int_equal(r.flaps, 0);
    assert_int_equal(r.crowded, 0);
    assert_int_equal(out.tri_count, box.tri_count);
    assert_int_equal(out.vertex_count, box.vertex_count);
    assert_memory_equal(out.tri, box.tri, 3 * box.tri_count * sizeof *box.tri);
    for (size_t i = 0; i < 3 * box.vertex_count; i++)
        assert_true(out.xyz[i] == (double)(float)box.xyz[i]);
    sr_mesh_release(&out);
    sr_mesh_release(&box);
}

static void a_nanometre_tetrahedron_is_welded_flat_and_its_flap_dropped(void **state)
{
    (void)state;
    sr_mesh m = {0}, out = {0}, box = {0};
    box_and_thin_tetrahedron(&m);
    assert_true(sr_mesh_is_closed(&m));
    assert_int_equal(sr_mesh_float_welds(&m), 1);
    sr_float_report r = {0, 0, 0, 0};
    assert_int_equal(sr_mesh_float_ready(&m, &out, &r), SR_OK);
    assert_int_equal(r.welded, 1);     /* c' onto c */
    assert_int_equal(r.degenerate, 2); /* the two triangles on c and c' */
    assert_int_equal(r.flaps, 2);      /* (a, c, b) and (a, b, c') = (a, b, c) */
    assert_int_equal(out.tri_count, 12);
    assert_int_equal(sr_shape_box(box_lo, box_hi, &box, NULL), SR_OK);
    assert_memory_equal(out.tri, box.tri, 3 * box.tri_count * sizeof *box.tri);
    assert_true(sr_mesh_is_closed(&out));
    assert_near(sr_mesh_volume(&out), sr_mesh_volume(&box), 1e-3);
    sr_mesh_release(&box);
    sr_mesh_release(&out);
    sr_mesh_release(&m);
}

/* Tetrahedron (p[0], p[1], p[2], p[3]) appended to m, its faces turned outward. */
static void append_tetrahedron(sr_mesh *m, const double p[4][3])
{
    sr_mesh tet = {0};
    assert_int_equal(sr_mesh_alloc(&tet, 4, 4), SR_OK);
    memcpy(tet.xyz, p, 12 * sizeof *tet.xyz);
    uint32_t tri[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
    memcpy(tet.tri, tri, sizeof tri);
    if (sr_mesh_volume(&tet) < 0)
        for (size_t t = 0; t < 4; t++) {
            uint32_t s = tet.tri[3 * t + 1];
            tet.tri[3 * t + 1] = tet.tri[3 * t + 2];
            tet.tri[3 * t + 2] = s;
        }
    assert_true(sr_mesh_volume(&tet) > 0);
    assert_int_equal(sr_mesh_append(m, &tet), SR_OK);
    sr_mesh_release(&tet);
}

/* The box with two sliver tetrahedra (A, B, q, r) and (C, D, q', r) beside it: q' a
 * nanometre above q (one float position), r one float step above q in z. Closed in
 * double precision; r is one vertex of both (a union's output has such tips). */
static void box_and_two_tips(sr_mesh *m, size_t *r_index)
{
    sr_mesh box = {0};
    assert_int_equal(sr_shape_box(box_lo, box_hi, &box, NULL), SR_OK);
    double r_z = (double)nextafterf(5.0f, 6.0f);
    const double t1[4][3] = {{40, 0, 5}, {41, 0, 5}, {40, 1, 5}, {40, 1, r_z}};
    const double t2[4][3] = {{40, 2, 6}, {39, 2, 5}, {40, 1, 5 + 1e-9}, {40, 1, r_z}};
    *m = box;
    append_tetrahedron(m, t1);
    append_tetrahedron(m, t2);
    /* the second's r is the first's */
    uint32_t r1 = 8 + 3, r2 = 12 + 3;
    for (size_t i = 3 * 16; i < 3 * m->tri_count; i++)
        if (m->tri[i] == r2)
            m->tri[i] = r1;
    assert_true(sr_mesh_is_closed(m));
    *r_index = r1;
}

static void an_edge_a_weld_crowds_is_welded_too(void **state)
{
    (void)state;
    sr_mesh m = {0}, out = {0};
    size_t r_index;
    box_and_two_tips(&m, &r_index);
    sr_float_report r = {0, 0, 0, 0};
    assert_int_equal(sr_mesh_float_ready(&m, &out, &r), SR_OK);
    /* q' onto q (edge q-r then has four triangles); the second tetrahedron's own r,
     * unused, onto r */
    assert_int_equal(r.welded, 2);
    assert_int_equal(r.crowded, 1);    /* r onto q, a float step below it */
    assert_int_equal(r.degenerate, 4); /* (A|B|C|D, q, r) */
    assert_int_equal(r.flaps, 4);      /* (A, B, q) against (A, B, r), and C, D alike */
    assert_int_equal(out.tri_count, 12);
    assert_true(sr_mesh_is_closed(&out));
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&out, &e), SR_OK);
    assert_int_equal(e.nonmanifold_edges, 0);

    /* a step more than the neighbourhood apart: r stays, the edge stays crowded */
    double z = 5.0;
    for (int k = 0; k <= SR_FLOAT_NEIGHBOUR_STEPS; k++)
        z = (double)nextafterf((float)z, 6.0f);
    m.xyz[3 * r_index + 2] = z;
    sr_mesh_release(&out);
    assert_int_equal(sr_mesh_float_ready(&m, &out, &r), SR_OK);
    assert_int_equal(r.welded, 1); /* q' alone: the unused r is where r was */
    assert_int_equal(r.crowded, 0);
    assert_int_equal(out.tri_count, 20);
    assert_int_equal(sr_mesh_edge_stats(&out, &e), SR_OK);
    assert_int_equal(e.nonmanifold_edges, 1);
    sr_mesh_release(&out);
    sr_mesh_release(&m);
}

static void stl_written_is_the_mesh_a_reader_welds_closed(void **state)
{
    sr_mesh m = {0}, back = {0};
    box_and_thin_tetrahedron(&m);
    char path[TMPDIR_PATH_MAX];
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_write(tmpdir_join(*state, "thin.stl", path), &m, NULL, &err), SR_OK);
    assert_int_equal(sr_mesh_read(path, &back, &err), SR_OK);
    /* before: the flap was written too, a second closed piece of no volume */
    assert_int_equal(back.tri_count, 12);
    assert_int_equal(back.vertex_count, 8);
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&back, &e), SR_OK);
    assert_int_equal(e.boundary_edges, 0);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_true(sr_mesh_is_closed(&back));
    sr_mesh_release(&back);
    sr_mesh_release(&m);

    /* the two tips: q' welded onto q crowds edge q-r; without r welded too the file
     * read back has a non-manifold edge */
    size_t r_index;
    box_and_two_tips(&m, &r_index);
    assert_int_equal(sr_mesh_write(tmpdir_join(*state, "tips.stl", path), &m, NULL, &err), SR_OK);
    assert_int_equal(sr_mesh_read(path, &back, &err), SR_OK);
    assert_int_equal(back.tri_count, 12);
    assert_int_equal(sr_mesh_edge_stats(&back, &e), SR_OK);
    assert_int_equal(e.nonmanifold_edges, 0);
    assert_true(sr_mesh_is_closed(&back));
    sr_mesh_release(&back);
    sr_mesh_release(&m);
}

static void a_mesh_of_flaps_only_is_refused_for_stl(void **state)
{
    sr_mesh tet = {0};
    assert_int_equal(sr_mesh_alloc(&tet, 4, 4), SR_OK);
    const double xyz[12] = {40, 0, 5, 41, 0, 5, 40, 1, 5, 40, 1, 5 + 1e-9};
    const uint32_t tri[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
    memcpy(tet.xyz, xyz, sizeof xyz);
    memcpy(tet.tri, tri, sizeof tri);
    char path[TMPDIR_PATH_MAX];
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_write(tmpdir_join(*state, "flat.stl", path), &tet, NULL, &err),
                     SR_E_INVALID);
    assert_non_null(strstr(err.msg, "float precision"));
    assert_non_null(strstr(err.msg, "flat.stl"));
    sr_mesh_release(&tet);
}

/* Four triangles on corners {3, 5, 9}: 0 and 2 turn one way (2 a rotation of 0), 1 and
 * 3 the other. Any two: 0 takes the first opposite (1), 2 takes 3. From triangle 2 on
 * (the closing's rule: each pair has a new one): 2 takes the first free opposite in
 * index order (1), 3 takes 0. With 1 not picked, 0 takes 3 and 2 stays. */
static void flaps_pair_the_first_free_opposite_triangle(void **state)
{
    (void)state;
    sr_mesh m = {0};
    assert_int_equal(sr_mesh_alloc(&m, 10, 4), SR_OK);
    memset(m.xyz, 0, 30 * sizeof *m.xyz);
    const uint32_t tri[12] = {3, 5, 9, 9, 5, 3, 5, 9, 3, 3, 9, 5};
    memcpy(m.tri, tri, sizeof tri);
    bool pick[4] = {true, true, true, true}, gone[4] = {false};
    assert_int_equal(sr_tri_flaps_pair(&m, pick, 0, gone), 4);
    assert_true(gone[0] && gone[1] && gone[2] && gone[3]);

    /* from triangle 2 on: the same four go, paired 2-1 and 3-0 (checked below by
     * taking 0 out of the pick: 3 then has only 1, which 2 took, and stays) */
    memset(gone, 0, sizeof gone);
    assert_int_equal(sr_tri_flaps_pair(&m, pick, 2, gone), 4);
    pick[0] = false;
    memset(gone, 0, sizeof gone);
    assert_int_equal(sr_tri_flaps_pair(&m, pick, 2, gone), 2);
    assert_true(!gone[0] && gone[1] && gone[2] && !gone[3]);

    /* nothing new: nothing pairs */
    memset(gone, 0, sizeof gone);
    assert_int_equal(sr_tri_flaps_pair(&m, pick, 4, gone), 0);

    /* 1 not picked: 0 takes 3, 2 has no free opposite left */
    bool pick2[4] = {true, false, true, true};
    memset(gone, 0, sizeof gone);
    assert_int_equal(sr_tri_flaps_pair(&m, pick2, 0, gone), 2);
    assert_true(gone[0] && !gone[1] && !gone[2] && gone[3]);
    sr_mesh_release(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_mesh_apart_at_float_precision_is_kept_whole),
        cmocka_unit_test(a_nanometre_tetrahedron_is_welded_flat_and_its_flap_dropped),
        cmocka_unit_test(an_edge_a_weld_crowds_is_welded_too),
        cmocka_unit_test(flaps_pair_the_first_free_opposite_triangle),
        cmocka_unit_test_setup_teardown(stl_written_is_the_mesh_a_reader_welds_closed, tmpdir_setup,
                                        tmpdir_teardown),
        cmocka_unit_test_setup_teardown(a_mesh_of_flaps_only_is_refused_for_stl, tmpdir_setup,
                                        tmpdir_teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
