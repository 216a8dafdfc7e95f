/*
 * test_boolean.c: the CGAL bridge (src/bridge/boolean.h): union, intersection and
 * difference of closed meshes with exact volumes, the touching-face case of a patch
 * sitting on a fracture surface, a chip cut out and put back, the self-intersection
 * test, surface deviation with values derived by hand, and every refusal of bad input.
 * The last case unites the shaft part's damaged.stl and missing.stl from
 * ../shared/parts (skipped when that folder is missing) and compares with intact.stl.
 * A union gives the same mesh to the bit whatever the heap held before it.
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
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/heap_stir.h"
#include "support/test_select.h"

#define SHAFT_DIR "../shared/parts/shaft_chipped_shoulder"

/* Axis-aligned box [x0,x1] x [y0,y1] x [z0,z1], 8 vertices, 12 outward triangles. */
static void make_box(sr_mesh *m, double x0, double y0, double z0, double x1, double y1,
                     double z1)
{
    const double v[8][3] = {{x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0},
                            {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}};
    static const uint32_t f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                      {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                      {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    assert_int_equal(sr_mesh_alloc(m, 8, 12), SR_OK);
    memcpy(m->xyz, v, sizeof v);
    memcpy(m->tri, f, sizeof f);
}

static void make_cube(sr_mesh *m) { make_box(m, 0, 0, 0, 1, 1, 1); }

/* Two boxes as one mesh (indices of the second shifted). */
static void make_two_boxes(sr_mesh *m, const double b0[6], const double b1[6])
{
    sr_mesh second;
    make_box(m, b0[0], b0[1], b0[2], b0[3], b0[4], b0[5]);
    make_box(&second, b1[0], b1[1], b1[2], b1[3], b1[4], b1[5]);
    assert_int_equal(sr_mesh_append(m, &second), SR_OK);
    sr_mesh_release(&second);
}

/* Drops the last triangle: a hole with three boundary edges. */
static void drop_last_triangle(sr_mesh *m) { m->tri_count--; }

static void assert_closed_with_volume(const sr_mesh *m, double volume, double tol)
{
    assert_true(m->tri_count > 0);
    assert_true(sr_mesh_is_closed(m));
    assert_near(sr_mesh_volume(m), volume, tol);
}

/* A sentinel mesh to check that failures leave *out untouched. */
static sr_mesh sentinel(void)
{
    sr_mesh s;
    s.xyz = (double *)(uintptr_t)0x10;
    s.tri = (uint32_t *)(uintptr_t)0x20;
    s.vertex_count = 7;
    s.tri_count = 9;
    return s;
}

static void assert_sentinel(const sr_mesh *s)
{
    assert_ptr_equal(s->xyz, (double *)(uintptr_t)0x10);
    assert_ptr_equal(s->tri, (uint32_t *)(uintptr_t)0x20);
    assert_int_equal(s->vertex_count, 7);
    assert_int_equal(s->tri_count, 9);
}

/* ---- booleans with exact volumes ---------------------------------------------- */

/* Unit cube [0,1]^3 and its copy shifted by half along x: four coplanar face pairs. */
static void overlapping_cubes_union_is_one_and_a_half(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &out, NULL), SR_OK);
    assert_closed_with_volume(&out, 1.5, 1e-12);
    double lo[3], hi[3];
    sr_mesh_bbox(&out, lo, hi);
    assert_near(lo[0], 0, 0);
    assert_near(hi[0], 1.5, 0);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void overlapping_cubes_intersection_is_half(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_intersection(&a, &b, &out, NULL), SR_OK);
    assert_closed_with_volume(&out, 0.5, 1e-12);
    double lo[3], hi[3];
    sr_mesh_bbox(&out, lo, hi);
    assert_near(lo[0], 0.5, 0);
    assert_near(hi[0], 1, 0);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void overlapping_cubes_difference_is_half(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_difference(&a, &b, &out, NULL), SR_OK);
    assert_closed_with_volume(&out, 0.5, 1e-12);
    double lo[3], hi[3];
    sr_mesh_bbox(&out, lo, hi);
    assert_near(lo[0], 0, 0);
    assert_near(hi[0], 0.5, 0);
    sr_mesh_release(&out);
    /* the other way round: b \ a is the right half [1, 1.5] */
    assert_int_equal(sr_boolean_compute(SR_BOOLEAN_DIFFERENCE, &b, "b", &a, "a", &out, NULL),
                     SR_OK);
    assert_closed_with_volume(&out, 0.5, 1e-12);
    sr_mesh_bbox(&out, lo, hi);
    assert_near(lo[0], 1, 0);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* Appends a vertex no triangle uses. */
static void add_unused_vertex(sr_mesh *m)
{
    double *xyz = realloc(m->xyz, 3 * (m->vertex_count + 1) * sizeof *xyz);
    assert_non_null(xyz);
    m->xyz = xyz;
    xyz[3 * m->vertex_count] = xyz[3 * m->vertex_count + 1] = xyz[3 * m->vertex_count + 2] = 9;
    m->vertex_count++;
}

/* Boxes in general position: union = sum of volumes, both shells kept; an unused
 * input vertex does not reach the result. */
static void disjoint_union_is_sum_of_volumes(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    add_unused_vertex(&a);
    make_box(&b, 3, 0.25, -1, 5, 1.25, 2);
    assert_int_equal(sr_boolean_union(&a, &b, &out, NULL), SR_OK);
    assert_closed_with_volume(&out, 1 + 2 * 1 * 3, 1e-12);
    assert_int_equal(out.tri_count, 24);
    assert_int_equal(out.vertex_count, 16);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void disjoint_intersection_is_empty(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    make_box(&b, 3, 0, 0, 4, 1, 1);
    out = sentinel();
    assert_int_equal(sr_boolean_intersection(&a, &b, &out, NULL), SR_OK);
    assert_int_equal(out.tri_count, 0);
    assert_int_equal(out.vertex_count, 0);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* A cube and a second cube sharing the face x = 1 exactly: the shared face goes. */
static void touching_full_face_union_is_sum(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    make_box(&b, 1, 0, 0, 2, 1, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &out, NULL), SR_OK);
    assert_closed_with_volume(&out, 2, 1e-12);
    assert_near(sr_mesh_area(&out), 10, 1e-12); /* 2x1x1 box: no internal faces */
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* The typical restore case: a small patch standing on part of a face of the part. */
static void touching_patch_union_is_sum(void **state)
{
    sr_mesh a, b, out;
    make_cube(&a);
    make_box(&b, 0.25, 0.3, 1, 0.75, 0.6, 1.4);
    assert_int_equal(sr_boolean_union(&a, &b, &out, NULL), SR_OK);
    assert_closed_with_volume(&out, 1 + 0.5 * 0.3 * 0.4, 1e-12);
    /* area: both areas minus twice the contact rectangle */
    double contact = 0.5 * 0.3;
    assert_near(sr_mesh_area(&out), 6 + 2 * (0.5 * 0.3 + 0.5 * 0.4 + 0.3 * 0.4) - 2 * contact,
                1e-12);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* The result may replace an input: its old arrays are released (ASan checks). */
static void union_in_place_releases_the_input(void **state)
{
    sr_mesh a, b;
    make_cube(&a);
    make_box(&b, 0.5, 0.5, 0.5, 1.5, 1.5, 1.5);
    assert_int_equal(sr_boolean_union(&a, &b, &a, NULL), SR_OK);
    assert_closed_with_volume(&a, 2 - 0.125, 1e-12);
    assert_int_equal(sr_boolean_difference(&a, &b, &b, NULL), SR_OK);
    assert_closed_with_volume(&b, 1 - 0.125, 1e-12);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* Box of side 2 rotated by 30 deg about z then 20 deg about x, centred at c. */
static void make_tilted_cube(sr_mesh *m, const double c[3])
{
    make_box(m, -1, -1, -1, 1, 1, 1);
    double cz = cos(M_PI / 6), sz = sin(M_PI / 6), cx = cos(M_PI / 9), sx = sin(M_PI / 9);
    /* Rx * Rz, then translate */
    double x[12] = {cz, -sz, 0, c[0], cx * sz, cx * cz, -sx, c[1], sx * sz, sx * cz, cx, c[2]};
    sr_mesh_transform(m, x);
}

/* Damage a box by cutting a tilted cube off its corner, cut the chip as the
 * intersection, put it back: the intact volume and surface return. */
static void chip_removed_then_reunited_restores_the_box(void **state)
{
    sr_mesh box, cutter, damaged, chip, restored;
    make_box(&box, 0, 0, 0, 4, 2, 2);
    const double corner[3] = {4, 2, 2};
    make_tilted_cube(&cutter, corner);
    double intact = sr_mesh_volume(&box);
    assert_near(intact, 16, 0);

    assert_int_equal(sr_boolean_difference(&box, &cutter, &damaged, NULL), SR_OK);
    assert_int_equal(sr_boolean_intersection(&box, &cutter, &chip, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(&damaged));
    assert_true(sr_mesh_is_closed(&chip));
    double vchip = sr_mesh_volume(&chip);
    assert_true(vchip > 0.5 && vchip < 4); /* a real chip, not nothing */
    assert_near(sr_mesh_volume(&damaged) + vchip, intact, 1e-9 * intact);

    sr_err err;
    assert_int_equal(sr_boolean_compute(SR_BOOLEAN_UNION, &damaged, "damaged", &chip,
                                        "patch", &restored, &err),
                     SR_OK);
    assert_closed_with_volume(&restored, intact, 1e-9 * intact);

    sr_deviation d;
    assert_int_equal(sr_mesh_deviation(&restored, &box, &d, NULL), SR_OK);
    assert_true(d.max_mm < 1e-9);
    assert_int_equal(d.samples, restored.vertex_count + restored.tri_count);
    assert_int_equal(sr_mesh_deviation(&box, &restored, &d, NULL), SR_OK);
    assert_true(d.max_mm < 1e-9);
    /* and the damaged part does deviate from the box */
    assert_int_equal(sr_mesh_deviation(&box, &damaged, &d, NULL), SR_OK);
    assert_true(d.max_mm > 0.1);

    sr_mesh_release(&box);
    sr_mesh_release(&cutter);
    sr_mesh_release(&damaged);
    sr_mesh_release(&chip);
    sr_mesh_release(&restored);
}

/* ---- refusals --------------------------------------------------------------------- */

static void open_first_input_is_refused_naming_it(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    drop_last_triangle(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'first mesh' is not closed (3 boundary edges)");
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void open_patch_is_refused_naming_it(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    drop_last_triangle(&b);
    assert_int_equal(
        sr_boolean_compute(SR_BOOLEAN_UNION, &a, "damaged", &b, "patch", &out, &err),
        SR_E_INVALID);
    assert_string_equal(err.msg, "'patch' is not closed (3 boundary edges)");
    assert_int_equal(sr_boolean_difference(&a, &b, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'second mesh' is not closed (3 boundary edges)");
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void self_intersecting_input_is_refused(void **state)
{
    const double b0[6] = {0, 0, 0, 1, 1, 1}, b1[6] = {0.5, 0.5, 0.5, 1.5, 1.5, 1.5};
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_two_boxes(&a, b0, b1);
    assert_true(sr_mesh_is_closed(&a)); /* closed, so only the CGAL test catches it */
    /* where the other mesh can cut it, a crossing is refused */
    make_box(&b, 0.8, 0.2, 0.2, 3, 0.8, 0.8);
    assert_int_equal(sr_boolean_union(&b, &a, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'second mesh' intersects itself where the other mesh is");
    assert_sentinel(&out);
    sr_mesh_release(&b);
    /* far from it (a noise fold elsewhere on a scan), the boolean goes ahead */
    make_box(&b, 2, 0, 0, 3, 1, 1);
    assert_int_equal(sr_boolean_union(&b, &a, &out, &err), SR_OK);
    assert_near(sr_mesh_volume(&out), 1.0 + sr_mesh_volume(&a), 1e-9);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void empty_input_is_refused(void **state)
{
    sr_mesh a, empty, out = sentinel();
    sr_err err;
    make_cube(&a);
    sr_mesh_init(&empty);
    assert_int_equal(sr_boolean_union(&a, &empty, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'second mesh' contains no triangles");
    assert_int_equal(sr_boolean_intersection(&empty, &a, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'first mesh' contains no triangles");
    assert_sentinel(&out);
    sr_mesh_release(&a);
}

static void inside_out_input_is_refused(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    sr_mesh_flip(&b);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'second mesh' is inside out (enclosed volume -1 mm^3)");
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void inconsistently_oriented_input_is_refused(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    uint32_t t = a.tri[1];
    a.tri[1] = a.tri[2];
    a.tri[2] = t; /* first triangle flipped: its 3 edges now run with their neighbours */
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'first mesh' is not consistently oriented (3 edges "
                                 "traversed the same way by both triangles)");
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* Two cubes sharing one corner vertex index: every edge is fine, the vertex is not. */
static void nonmanifold_vertex_input_is_refused(void **state)
{
    const double b0[6] = {0, 0, 0, 1, 1, 1}, b1[6] = {1, 1, 1, 2, 2, 2};
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_two_boxes(&a, b0, b1);
    /* second box's vertex 0 (8) is (1,1,1) = first box's vertex 6: weld it */
    for (size_t i = 0; i < 3 * a.tri_count; i++)
        if (a.tri[i] == 8)
            a.tri[i] = 6;
    assert_true(sr_mesh_is_closed(&a));
    make_box(&b, 3, 0, 0, 4, 1, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "'first mesh' has a non-manifold vertex"));
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* A unit cube whose first triangle (a, b, c) is split at the midpoint m of its edge ab,
 * closed again by the zero-area triangle (a, b, m): closed, oriented, one needle. */
static void make_needled_cube(sr_mesh *m)
{
    sr_mesh cube;
    make_cube(&cube);
    size_t nv = cube.vertex_count, nt = cube.tri_count;
    assert_int_equal(sr_mesh_alloc(m, nv + 1, nt + 2), SR_OK);
    memcpy(m->xyz, cube.xyz, 3 * nv * sizeof *m->xyz);
    memcpy(m->tri, cube.tri, 3 * nt * sizeof *m->tri);
    uint32_t a = cube.tri[0], b = cube.tri[1], c = cube.tri[2], mid = (uint32_t)nv;
    for (int k = 0; k < 3; k++)
        m->xyz[3 * nv + k] = 0.5 * (cube.xyz[3 * a + k] + cube.xyz[3 * b + k]);
    uint32_t added[9] = {a, mid, c, mid, b, c, a, b, mid};
    memcpy(m->tri, added, 3 * sizeof *added);                /* (a, m, c) replaces (a, b, c) */
    memcpy(m->tri + 3 * nt, added + 3, 6 * sizeof *added);   /* (m, b, c), the needle (a, b, m) */
    sr_mesh_release(&cube);
}

static void repair_removes_a_needle_and_the_union_then_works(void **state)
{
    (void)state;
    sr_mesh a, b, out;
    sr_err err = {{0}};
    make_needled_cube(&a);
    assert_true(sr_mesh_is_closed(&a));
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'first mesh' has 1 degenerate (zero-area) triangles");
    sr_repair_report rep = {0};
    assert_int_equal(sr_mesh_repair(&a, &rep, &err), SR_OK);
    assert_int_equal(rep.changed, 1);
    assert_int_equal(rep.degenerate_removed, 1);
    assert_closed_with_volume(&a, 1.0, 1e-12);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_OK);
    assert_closed_with_volume(&out, 1.5, 1e-9);
    sr_mesh_release(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void repair_leaves_a_clean_mesh_alone(void **state)
{
    (void)state;
    sr_mesh a;
    sr_err err = {{0}};
    make_cube(&a);
    double *xyz = a.xyz;
    sr_repair_report rep = {1, 7};
    assert_int_equal(sr_mesh_repair(&a, &rep, &err), SR_OK);
    assert_int_equal(rep.changed, 0);
    assert_int_equal(rep.degenerate_removed, 0);
    assert_ptr_equal(a.xyz, xyz);
    assert_int_equal(a.tri_count, 12);
    sr_mesh_release(&a);
}

static void degenerate_triangle_input_is_refused(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    /* squash the cube's top to a plane: every triangle of the top is zero-area... and
     * so are the four sides' upper triangles; count what validation counts */
    for (int v = 4; v < 8; v++)
        a.xyz[3 * v + 2] = 0;
    sr_mesh_report rep;
    assert_int_equal(sr_mesh_validate(&a, "x", &rep, NULL), SR_OK);
    assert_true(rep.degenerate_tris > 0);
    char want[128];
    snprintf(want, sizeof want, "'first mesh' has %zu degenerate (zero-area) triangles",
             rep.degenerate_tris);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_string_equal(err.msg, want);
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* Cubes meeting only along an edge: the union is not a manifold surface. */
static void edge_touching_union_is_refused(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    make_box(&b, 1, 1, 0, 2, 2, 1);
    assert_int_equal(sr_boolean_union(&a, &b, &out, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "cannot compute the union of 'first mesh' and "
                                    "'second mesh': the result would not be a manifold"));
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void unknown_operation_is_refused(void **state)
{
    sr_mesh a, b, out = sentinel();
    sr_err err;
    make_cube(&a);
    make_box(&b, 0.5, 0, 0, 1.5, 1, 1);
    assert_int_equal(sr_boolean_compute((sr_boolean_op)7, &a, NULL, &b, NULL, &out, &err),
                     SR_E_RANGE);
    assert_string_equal(err.msg, "unknown boolean operation 7");
    assert_sentinel(&out);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* ---- self-intersection test ------------------------------------------------------- */

static void self_intersects_tells_overlapping_shells(void **state)
{
    const double b0[6] = {0, 0, 0, 1, 1, 1}, b1[6] = {0.5, 0.5, 0.5, 1.5, 1.5, 1.5},
                 b2[6] = {2, 0, 0, 3, 1, 1};
    sr_mesh m;
    int hit = -1;
    make_two_boxes(&m, b0, b1);
    assert_int_equal(sr_mesh_self_intersects(&m, &hit, NULL), SR_OK);
    assert_int_equal(hit, 1);
    sr_mesh_release(&m);

    make_two_boxes(&m, b0, b2); /* disjoint shells */
    hit = -1;
    assert_int_equal(sr_mesh_self_intersects(&m, &hit, NULL), SR_OK);
    assert_int_equal(hit, 0);
    sr_mesh_release(&m);

    make_cube(&m);
    drop_last_triangle(&m); /* open is allowed */
    hit = -1;
    assert_int_equal(sr_mesh_self_intersects(&m, &hit, NULL), SR_OK);
    assert_int_equal(hit, 0);
    sr_mesh_release(&m);
}

static void self_intersects_refuses_empty_and_nonmanifold(void **state)
{
    sr_mesh m;
    sr_err err;
    int hit = -1;
    sr_mesh_init(&m);
    assert_int_equal(sr_mesh_self_intersects(&m, &hit, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'mesh' contains no triangles");

    /* a cube plus a copy of its first triangle: that edge has three triangles */
    make_cube(&m);
    uint32_t *tri = realloc(m.tri, 13 * 3 * sizeof *tri);
    assert_non_null(tri);
    m.tri = tri;
    memcpy(m.tri + 36, m.tri, 3 * sizeof *tri);
    m.tri_count = 13;
    assert_int_equal(sr_mesh_self_intersects(&m, &hit, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "'mesh' is not an oriented manifold"));
    assert_int_equal(hit, -1);
    sr_mesh_release(&m);
}

/* ---- deviation -------------------------------------------------------------------- */

/* Cube scaled by 1.1 about its centre: [-0.05, 1.05]^3. */
static void make_scaled_cube(sr_mesh *m) { make_box(m, -0.05, -0.05, -0.05, 1.05, 1.05, 1.05); }

/* Samples on the unit cube, inside the big one: a corner is 0.05 from the three
 * nearest faces of the big cube (the big corner is 0.05*sqrt(3) away, further), and a
 * triangle centroid, inside its face, is 0.05 from the parallel face. All 20 samples
 * (8 vertices + 12 centroids) are at 0.05. */
static void deviation_of_cube_from_scaled_cube_is_005(void **state)
{
    sr_mesh a, b;
    sr_deviation d;
    make_cube(&a);
    make_scaled_cube(&b);
    assert_int_equal(sr_mesh_deviation(&a, &b, &d, NULL), SR_OK);
    assert_int_equal(d.samples, 20);
    assert_near(d.max_mm, 0.05, 1e-15);
    assert_near(d.mean_mm, 0.05, 1e-15);
    assert_near(d.rms_mm, 0.05, 1e-15);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* The other way: the big cube's corners are outside the unit cube, nearest point its
 * corner, corner to corner 0.05*sqrt(3); its centroids are 0.05 above a face.
 * mean = (8 * 0.05 sqrt3 + 12 * 0.05) / 20, rms = 0.05 sqrt((8 * 3 + 12) / 20). */
static void deviation_of_scaled_cube_from_cube_is_corner_to_corner(void **state)
{
    sr_mesh a, b;
    sr_deviation d;
    make_scaled_cube(&a);
    make_cube(&b);
    assert_int_equal(sr_mesh_deviation(&a, &b, &d, NULL), SR_OK);
    assert_int_equal(d.samples, 20);
    assert_near(d.max_mm, 0.05 * sqrt(3), 1e-14);
    assert_near(d.mean_mm, (8 * 0.05 * sqrt(3) + 12 * 0.05) / 20, 1e-14);
    assert_near(d.rms_mm, 0.05 * sqrt(36.0 / 20), 1e-14);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* The reference may be open (a scan): the cube's top samples then find the side walls.
 * Top corners lie on the walls' top edges (0); top centroids (2/3, 1/3, 1) and
 * (1/3, 2/3, 1) are 1/3 from the nearest wall; every other sample lies on b (0). */
static void deviation_against_open_reference(void **state)
{
    sr_mesh a, b;
    sr_deviation d;
    make_cube(&a);
    make_cube(&b);
    memmove(b.tri + 6, b.tri + 12, 8 * 3 * sizeof *b.tri);
    b.tri_count = 10; /* top triangles {4,5,6}, {4,6,7} gone */
    assert_int_equal(sr_mesh_deviation(&a, &b, &d, NULL), SR_OK);
    assert_int_equal(d.samples, 20);
    assert_near(d.max_mm, 1.0 / 3, 1e-15);
    assert_near(d.mean_mm, 2.0 / 3 / 20, 1e-15);
    assert_near(d.rms_mm, sqrt(2.0 / 9 / 20), 1e-15);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

static void deviation_refuses_empty_and_nonfinite(void **state)
{
    sr_mesh a, empty;
    sr_deviation d = {1, 2, 3, 4};
    sr_err err;
    make_cube(&a);
    sr_mesh_init(&empty);
    assert_int_equal(sr_mesh_deviation(&a, &empty, &d, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'reference mesh' contains no triangles");
    assert_int_equal(sr_mesh_deviation(&empty, &a, &d, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'sampled mesh' contains no triangles");
    a.xyz[5] = NAN;
    assert_int_equal(sr_mesh_deviation(&a, &a, &d, &err), SR_E_INVALID);
    assert_non_null(strstr(err.msg, "'sampled mesh' has 1 vertices with NaN"));
    assert_near(d.max_mm, 1, 0); /* untouched */
    assert_int_equal(d.samples, 4);
    sr_mesh_release(&a);
}

static void deviation_refuses_reference_of_zero_area(void **state)
{
    sr_mesh a, b;
    sr_deviation d;
    sr_err err;
    make_cube(&a);
    make_cube(&b);
    for (int v = 0; v < 8; v++)
        b.xyz[3 * v + 2] = b.xyz[3 * v + 1] = 0; /* every vertex on the x axis */
    assert_int_equal(sr_mesh_deviation(&a, &b, &d, &err), SR_E_INVALID);
    assert_string_equal(err.msg, "'reference mesh' has no triangle of non-zero area");
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* ---- a real part ------------------------------------------------------------------ */

/* Binary STL reader, just enough for the shared parts; vertices welded exactly. */
static void read_binary_stl(const char *path, sr_mesh *m)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    unsigned char header[84];
    assert_int_equal(fread(header, 1, 84, f), 84);
    uint32_t n = (uint32_t)header[80] | (uint32_t)header[81] << 8 |
                 (uint32_t)header[82] << 16 | (uint32_t)header[83] << 24;
    assert_int_equal(sr_mesh_alloc(m, 3 * (size_t)n, n), SR_OK);
    for (uint32_t t = 0; t < n; t++) {
        unsigned char rec[50];
        assert_int_equal(fread(rec, 1, 50, f), 50);
        for (int k = 0; k < 9; k++) {
            float x;
            memcpy(&x, rec + 12 + 4 * k, 4); /* little-endian host */
            m->xyz[9 * (size_t)t + k] = x;
        }
        for (int k = 0; k < 3; k++)
            m->tri[3 * (size_t)t + k] = 3 * t + k;
    }
    fclose(f);
    assert_int_equal(sr_mesh_weld_exact(m), SR_OK);
}

/* The union of two cylinders (r 10, z 0..5, 36 sides), one turned by half a side: their
 * flat ends lie in the same planes, where corefinement finds the crossings of the two
 * outlines in an order set by its boxes' ids and triangulates the ends through them.
 * The same union after the heap was stirred 12 ways (blocks of 64 B to 20 kB, about
 * half freed) is the same mesh, to the bit: with the boxes' addresses as their ids it
 * came out two ways in 12 (box_ids_cgal.hpp). */
static void a_union_does_not_follow_the_heap(void **state)
{
    (void)state;
    sr_mesh a, b, first;
    sr_mesh_init(&a);
    sr_mesh_init(&b);
    sr_mesh_init(&first);
    assert_int_equal(sr_shape_cylinder(10, 0, 5, 36, &a, NULL), SR_OK);
    assert_int_equal(sr_shape_cylinder(10, 0, 5, 36, &b, NULL), SR_OK);
    double t = M_PI / 36, c = cos(t), s = sin(t);
    for (size_t v = 0; v < b.vertex_count; v++) {
        double *p = b.xyz + 3 * v, x = p[0], y = p[1];
        p[0] = c * x - s * y;
        p[1] = s * x + c * y;
    }
    assert_int_equal(sr_boolean_union(&a, &b, &first, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(&first));
    for (unsigned round = 0; round < 12; round++) {
        void **kept = test_heap_stir(round);
        sr_mesh u;
        sr_mesh_init(&u);
        assert_int_equal(sr_boolean_union(&a, &b, &u, NULL), SR_OK);
        test_assert_same_mesh(&u, &first);
        sr_mesh_release(&u);
        test_heap_settle(kept);
    }
    sr_mesh_release(&a);
    sr_mesh_release(&b);
    sr_mesh_release(&first);
}

static void shaft_damaged_united_with_missing_is_intact(void **state)
{
    struct stat st;
    if (stat(SHAFT_DIR "/damaged.stl", &st) != 0) {
        skip();
        return;
    }
    sr_mesh damaged, missing, intact, out;
    read_binary_stl(SHAFT_DIR "/damaged.stl", &damaged);
    read_binary_stl(SHAFT_DIR "/missing.stl", &missing);
    read_binary_stl(SHAFT_DIR "/intact.stl", &intact);
    assert_int_equal(damaged.tri_count, 2050);
    assert_int_equal(missing.tri_count, 112);
    sr_err err;
    sr_status s = sr_boolean_compute(SR_BOOLEAN_UNION, &damaged, "damaged.stl", &missing,
                                     "missing.stl", &out, &err);
    if (s != SR_OK)
        print_error("%s\n", err.msg);
    assert_int_equal(s, SR_OK);
    assert_true(sr_mesh_is_closed(&out));
    assert_near(sr_mesh_volume(&out), 140422.0, 1e-4 * 140422.0);
    assert_near(sr_mesh_volume(&out), sr_mesh_volume(&intact), 1e-4 * 140422.0);
    /* and it is the intact surface: float32 files, so deviation ~ float rounding */
    sr_deviation d;
    assert_int_equal(sr_mesh_deviation(&out, &intact, &d, NULL), SR_OK);
    assert_true(d.max_mm < 1e-3);
    sr_mesh_release(&damaged);
    sr_mesh_release(&missing);
    sr_mesh_release(&intact);
    sr_mesh_release(&out);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(overlapping_cubes_union_is_one_and_a_half),
        cmocka_unit_test(overlapping_cubes_intersection_is_half),
        cmocka_unit_test(overlapping_cubes_difference_is_half),
        cmocka_unit_test(disjoint_union_is_sum_of_volumes),
        cmocka_unit_test(disjoint_intersection_is_empty),
        cmocka_unit_test(touching_full_face_union_is_sum),
        cmocka_unit_test(touching_patch_union_is_sum),
        cmocka_unit_test(union_in_place_releases_the_input),
        cmocka_unit_test(chip_removed_then_reunited_restores_the_box),
        cmocka_unit_test(open_first_input_is_refused_naming_it),
        cmocka_unit_test(open_patch_is_refused_naming_it),
        cmocka_unit_test(self_intersecting_input_is_refused),
        cmocka_unit_test(empty_input_is_refused),
        cmocka_unit_test(inside_out_input_is_refused),
        cmocka_unit_test(inconsistently_oriented_input_is_refused),
        cmocka_unit_test(nonmanifold_vertex_input_is_refused),
        cmocka_unit_test(degenerate_triangle_input_is_refused),
        cmocka_unit_test(repair_removes_a_needle_and_the_union_then_works),
        cmocka_unit_test(repair_leaves_a_clean_mesh_alone),
        cmocka_unit_test(edge_touching_union_is_refused),
        cmocka_unit_test(unknown_operation_is_refused),
        cmocka_unit_test(self_intersects_tells_overlapping_shells),
        cmocka_unit_test(self_intersects_refuses_empty_and_nonmanifold),
        cmocka_unit_test(deviation_of_cube_from_scaled_cube_is_005),
        cmocka_unit_test(deviation_of_scaled_cube_from_cube_is_corner_to_corner),
        cmocka_unit_test(deviation_against_open_reference),
        cmocka_unit_test(deviation_refuses_empty_and_nonfinite),
        cmocka_unit_test(deviation_refuses_reference_of_zero_area),
        cmocka_unit_test(a_union_does_not_follow_the_heap),
        cmocka_unit_test(shaft_damaged_united_with_missing_is_intact),
    };
    /* SYMREC_TEST_FILTER/_SKIP: make valgrind leaves the heaviest cases to ASan */
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
