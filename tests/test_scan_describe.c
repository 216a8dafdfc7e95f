/*
 * test_scan_describe.c: sr_scan_describe and sr_scan_drop_strays (src/mesh/scan_describe.c)
 * on meshes with known answers: a closed box 10 x 20 x 30 (no opening, one component);
 * the box with its top face (10 x 20) left off (one loop of 4 edges, 60 mm, spanning
 * 200 mm², open 200 / 2200 of the surface; closed in its plane: 6000 mm³ again); a
 * tube and an L-shaped prism without their bases (closed in the plane, the fill's area
 * the base's); the box with a stray triangle 20 mm above it
 * (dropped: 12 triangles and 8 vertices left; kept when "small" is set below its
 * 0.5 mm²), with a small triangle lying on its face
 * (kept: on the surface), with a second box beside it (kept: not small); bad options.
 * Rims that cross in their plane: a 10 x 10 rim with a fold (its edge from (5, 11) to
 * (6, 9) crosses the edge along y = 10 at (5.5, 10)) under a band and a cap is closed in
 * its plane through one made vertex there (filled 97.25 + 0.75 mm^2: the rest and the
 * fold), closed with no pinch; two pyramids (10 x 10 bases, 8 high) touching at a base
 * corner, without their bases, are closed in the plane, the corner split in two:
 * closed, no pinch, twice 800 / 3 mm^3. A triangle of the base kept inside the
 * opening (an island) is dropped, not filled round: the box closed, 6000 mm^3.
 * sr_scan_sort_edges (scan_int.h): 5000 edge records of 40 vertices in a scrambled
 * order come out as a comparison sort by key then input order puts them; none or one
 * record is left as it is.
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
#include "mesh/scan_describe.h"
#include "mesh/scan_int.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"
#include "support/open_face.h"

static void box(double x0, sr_mesh *out)
{
    const double lo[3] = {x0, 0, 0}, hi[3] = {x0 + 10, 20, 30};
    assert_int_equal(sr_shape_box(lo, hi, out, NULL), SR_OK);
}

/* Appends the triangle (a, b, c) as three new vertices. */
static void add_triangle(sr_mesh *m, const double a[3], const double b[3], const double c[3])
{
    sr_mesh t;
    assert_int_equal(sr_mesh_alloc(&t, 3, 1), SR_OK);
    memcpy(t.xyz, a, 3 * sizeof(double));
    memcpy(t.xyz + 3, b, 3 * sizeof(double));
    memcpy(t.xyz + 6, c, 3 * sizeof(double));
    t.tri[0] = 0;
    t.tri[1] = 1;
    t.tri[2] = 2;
    assert_int_equal(sr_mesh_append(m, &t), SR_OK);
    sr_mesh_release(&t);
}

/* A fin of three triangles on one edge: that edge is non-manifold, the other six are
 * boundary edges kept as their triangles walk them, in one loop; a stray triangle far
 * off adds no edge of either kind. */
static void a_fins_edge_is_non_manifold_and_a_strays_edges_are_not_counted(void **state)
{
    (void)state;
    const double xyz[] = {0, 0, 0, 0, 0, 10, 10, 0, 5, -10, 0, 5, 0, 10, 5};
    const uint32_t tri[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    sr_mesh m;
    assert_int_equal(sr_mesh_alloc(&m, 5, 3), SR_OK);
    memcpy(m.xyz, xyz, sizeof xyz);
    memcpy(m.tri, tri, sizeof tri);
    const double a[3] = {100, 100, 100}, b[3] = {100.1, 100, 100}, c[3] = {100, 100.1, 100};
    add_triangle(&m, a, b, c);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.strays, 1);
    assert_int_equal(d.nonmanifold_edges, 1);
    assert_int_equal(d.boundary_edges, 6);
    /* each boundary edge walked as its triangle walks it: (1 2) (2 0) (0 3) (3 1)
     * (1 4) (4 0); the walk from vertex 0 closes 0 3 1 2, and 1 4 is left open (out of
     * 0 again, its one edge is used) */
    size_t in_loops = 0;
    for (size_t i = 0; i < d.loop_count; i++)
        in_loops += d.loops[i].edges;
    assert_int_equal(in_loops, 6);
    assert_int_equal(d.loop_count, 2);
    const uint32_t walked[6][2] = {{1, 2}, {2, 0}, {0, 3}, {3, 1}, {1, 4}, {4, 0}};
    for (size_t i = 0; i < d.loop_count; i++) {
        const sr_scan_loop *l = &d.loops[i];
        for (size_t k = 0; k + (l->closed ? 0 : 1) < l->edges; k++) {
            uint32_t from = d.loop_verts[l->first + k];
            uint32_t to = d.loop_verts[l->first + (k + 1) % l->edges];
            bool found = false;
            for (int e = 0; e < 6; e++)
                found = found || (walked[e][0] == from && walked[e][1] == to);
            assert_true(found);
        }
    }
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_closed_box_has_no_opening_and_one_component(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_false(d.open);
    assert_int_equal(d.boundary_edges, 0);
    assert_int_equal(d.loop_count, 0);
    assert_int_equal(d.component_count, 1);
    assert_int_equal(d.components[0].triangles, 12);
    assert_near(d.components[0].area_mm2, 2200, 1e-9);
    assert_near(d.open_share, 0, 0);
    assert_int_equal(d.strays, 0);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_box_without_its_top_has_one_loop_round_it(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    size_t kept = 0;
    for (size_t t = 0; t < m.tri_count; t++) {
        bool top = true;
        for (int k = 0; k < 3; k++)
            top = top && m.xyz[3 * m.tri[3 * t + k] + 2] == 30;
        if (!top) {
            memmove(m.tri + 3 * kept, m.tri + 3 * t, 3 * sizeof *m.tri);
            kept++;
        }
    }
    assert_int_equal(kept, 10);
    m.tri_count = kept;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_true(d.open);
    assert_int_equal(d.boundary_edges, 4);
    assert_int_equal(d.loop_count, 1);
    assert_int_equal(d.loops[0].edges, 4);
    assert_true(d.loops[0].closed);
    assert_near(d.loops[0].length_mm, 60, 1e-9);
    assert_near(d.loops[0].span_mm, 200, 1e-9);
    assert_near(d.open_share, 200.0 / 2200.0, 1e-12);
    assert_int_equal(d.component_count, 1);
    assert_int_equal(d.strays, 0);
    /* closed in its plane by two triangles on the rim's corners: the box's volume again */
    size_t closed = 0;
    sr_scan_closing how = SR_SCAN_LEFT_OPEN;
    assert_int_equal(sr_scan_close_openings_how(&m, &d, 0, &closed, &how, NULL), SR_OK);
    assert_int_equal(closed, 1);
    assert_int_equal(how, SR_SCAN_IN_PLANE);
    assert_int_equal(m.tri_count, 12);
    assert_int_equal(m.vertex_count, 8);
    assert_true(sr_mesh_is_closed(&m));
    assert_near(sr_mesh_volume(&m), 6000, 1e-9);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

/* Area of triangles [from, tri_count) of m. */
static double area_from(const sr_mesh *m, size_t from)
{
    double a = 0;
    for (size_t t = from; t < m->tri_count; t++) {
        const double *p = m->xyz + 3 * m->tri[3 * t], *q = m->xyz + 3 * m->tri[3 * t + 1],
                     *r = m->xyz + 3 * m->tri[3 * t + 2];
        double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
        a += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return a;
}

static double r_outer(double theta, size_t ring, void *user)
{
    (void)theta, (void)ring, (void)user;
    return 10;
}

static double r_inner(double theta, size_t ring, void *user)
{
    (void)theta, (void)ring, (void)user;
    return 4;
}

/* Opens m at z = 0, describes it, closes it and checks: loops loops, all closed in their
 * plane, no new vertex, closed again with its volume, and the fill's area that of the
 * base (a fan from a concave rim's centroid folds outside it, a bore's rim fanned on its
 * own covers the bore twice over: either adds area). */
static void closes_in_plane(sr_mesh *m, size_t loops, double base_area)
{
    double volume = sr_mesh_volume(m);
    size_t nv = m->vertex_count;
    assert_true(test_drop_face_at(m, 0) > 0);
    size_t open_tris = m->tri_count;
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, loops);
    size_t closed = 0;
    sr_scan_closing how[2] = {SR_SCAN_LEFT_OPEN, SR_SCAN_LEFT_OPEN};
    assert_true(loops <= 2);
    assert_int_equal(sr_scan_close_openings_how(m, &d, 0, &closed, how, NULL), SR_OK);
    assert_int_equal(closed, loops);
    for (size_t i = 0; i < loops; i++)
        assert_int_equal(how[i], SR_SCAN_IN_PLANE);
    assert_int_equal(m->vertex_count, nv);
    assert_true(sr_mesh_is_closed(m));
    assert_near(sr_mesh_volume(m), volume, 1e-9 * volume);
    assert_near(area_from(m, open_tris), base_area, 1e-9 * base_area);
    sr_scan_desc_release(&d);
}

/* A tube (radii 10 and 4, 48 sides, z 0..12) and an L-shaped prism (20 x 20 less
 * 12 x 12: 256 mm^2, 10 high), each without the face it stood on. */
static void a_base_with_a_bore_or_a_concave_rim_is_closed_in_its_plane(void **state)
{
    (void)state;
    const double z[2] = {0, 12};
    sr_revolve_opts o = {0};
    o.segments = 48;
    o.ring_count = 2;
    o.ring_z = z;
    o.outer = r_outer;
    o.inner = r_inner;
    sr_mesh m;
    assert_int_equal(sr_shape_revolve(&o, &m, NULL), SR_OK);
    double polygon = 24 * sin(2 * M_PI / 48); /* 48/2 sin(2pi/48) r^2, per r^2 */
    closes_in_plane(&m, 2, polygon * (100 - 16));
    sr_mesh_release(&m);
    const double l[12] = {0, 0, 20, 0, 20, 8, 8, 8, 8, 20, 0, 20};
    assert_int_equal(sr_shape_prism(l, 6, 0, 10, &m, NULL), SR_OK);
    closes_in_plane(&m, 1, 256);
    sr_mesh_release(&m);
}

/* Closes m's one opening (or two) and checks it closed in its plane, closed after with
 * no pinched vertex; returns the area of the triangles the closing added at z = 0. */
static double close_flat(sr_mesh *m, size_t loops)
{
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, loops);
    size_t closed = 0, before = m->tri_count;
    sr_scan_closing how[2] = {SR_SCAN_LEFT_OPEN, SR_SCAN_LEFT_OPEN};
    assert_true(loops <= 2);
    assert_int_equal(sr_scan_close_openings_how(m, &d, 0, &closed, how, NULL), SR_OK);
    assert_int_equal(closed, loops);
    for (size_t i = 0; i < loops; i++)
        assert_int_equal(how[i], SR_SCAN_IN_PLANE);
    assert_true(sr_mesh_is_closed(m));
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(m, &e), SR_OK);
    assert_int_equal(e.nonmanifold_vertices, 0);
    double flat = 0;
    for (size_t t = before; t < m->tri_count; t++) {
        bool low = true;
        for (int k = 0; k < 3; k++)
            low = low && m->xyz[3 * m->tri[3 * t + k] + 2] == 0;
        if (low)
            flat += area_from(&(sr_mesh){m->xyz, m->tri + 3 * t, m->vertex_count, 1}, 0);
    }
    sr_scan_desc_release(&d);
    return flat;
}

static void rims_crossing_in_their_plane_are_cut_where_they_cross(void **state)
{
    (void)state;
    /* the rim A B C D E F G at z = 0, counter-clockwise from above; E -> F crosses C -> D;
     * over it a band to a copy shrunk by half towards (5, 5) at z = 10, capped at (5, 5) */
    const double rim[7][2] = {{0, 0}, {10, 0}, {10, 10}, {4, 10}, {5, 11}, {6, 9}, {0, 10}};
    sr_mesh m;
    assert_int_equal(sr_mesh_alloc(&m, 15, 21), SR_OK);
    for (int i = 0; i < 7; i++) {
        double *lo = m.xyz + 3 * i, *hi = m.xyz + 3 * (7 + i);
        lo[0] = rim[i][0], lo[1] = rim[i][1], lo[2] = 0;
        hi[0] = 2.5 + rim[i][0] / 2, hi[1] = 2.5 + rim[i][1] / 2, hi[2] = 10;
    }
    m.xyz[42] = 5, m.xyz[43] = 5, m.xyz[44] = 10;
    for (uint32_t i = 0; i < 7; i++) {
        uint32_t j = (i + 1) % 7, *t = m.tri + 9 * i;
        const uint32_t band[9] = {i, j, 7 + j, i, 7 + j, 7 + i, 14, 7 + i, 7 + j};
        memcpy(t, band, sizeof band);
    }
    assert_near(close_flat(&m, 1), 97.25 + 0.75, 1e-9);
    assert_int_equal(m.vertex_count, 16); /* one made where the rims cross, no pinch */
    const double *x = m.xyz + 3 * 15;
    assert_near(x[0], 5.5, 1e-12);
    assert_near(x[1], 10, 1e-12);
    assert_near(x[2], 0, 0);
    sr_mesh_release(&m);
}

/* A pyramid without its base: the square (x0, y0) .. (x0 + 10, y0 + 10) at z = 0, apex
 * 8 above its centre; base vertex `shared` of the square (counter-clockwise from
 * (x0, y0)) is vertex `at` of m when at < m's count, else a new one. */
static void add_pyramid(sr_mesh *m, double x0, double y0, int shared, uint32_t at)
{
    const double sq[4][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
    uint32_t nv = (uint32_t)m->vertex_count, id[5], next = nv;
    double xyz[15];
    size_t add = 0;
    for (int i = 0; i < 5; i++) {
        if (i == shared && at < nv) {
            id[i] = at;
            continue;
        }
        id[i] = next++;
        double *p = xyz + 3 * add++;
        p[0] = x0 + (i < 4 ? sq[i][0] : 5), p[1] = y0 + (i < 4 ? sq[i][1] : 5);
        p[2] = i < 4 ? 0 : 8;
    }
    double *v = realloc(m->xyz, 3 * (nv + add) * sizeof *v);
    uint32_t *t = realloc(m->tri, 3 * (m->tri_count + 4) * sizeof *t);
    assert_non_null(v);
    assert_non_null(t);
    memcpy(v + 3 * nv, xyz, 3 * add * sizeof *v);
    for (int i = 0; i < 4; i++) {
        uint32_t *w = t + 3 * (m->tri_count + (size_t)i);
        w[0] = id[i], w[1] = id[(i + 1) % 4], w[2] = id[4];
    }
    m->xyz = v;
    m->tri = t;
    m->vertex_count = nv + add;
    m->tri_count += 4;
}

static void two_pyramids_touching_at_a_corner_close_without_a_pinch(void **state)
{
    (void)state;
    sr_mesh m = {0};
    add_pyramid(&m, 0, 0, -1, 0);
    add_pyramid(&m, 10, 10, 0, 2); /* its corner (10, 10) is the first one's vertex 2 */
    assert_int_equal(m.vertex_count, 9);
    /* two loops (the walk leaves the shared corner by the first edge out of it) */
    assert_near(close_flat(&m, 2), 200, 1e-9);
    assert_int_equal(m.vertex_count, 10); /* the corner, once per pyramid */
    assert_near(sr_mesh_volume(&m), 2 * 800.0 / 3, 1e-9);
    sr_mesh_release(&m);
}

/* The box without its face at z = 0, with an island of it kept (a triangle at z = 0
 * inside the opening, the other way up: a fold): the island's rim is not a hole in the
 * fill, the island is flagged stray and dropped, the box is closed with its volume. */
static void an_island_left_in_the_base_is_dropped_not_filled_round(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    assert_int_equal(test_drop_face_at(&m, 0), 2);
    const double a[3] = {0.2, 5, 0}, b[3] = {2.2, 5, 0}, c[3] = {1.2, 8, 0};
    add_triangle(&m, a, b, c); /* facing up; 0.2 mm off the wall x = 0: not a stray */
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 2);
    assert_int_equal(d.component_count, 2);
    assert_int_equal(d.strays, 0); /* on the surface it was cut from: kept by describe */
    size_t closed = 0;
    sr_scan_closing how[2] = {SR_SCAN_LEFT_OPEN, SR_SCAN_LEFT_OPEN};
    assert_int_equal(sr_scan_close_openings_how(&m, &d, 0, &closed, how, NULL), SR_OK);
    assert_int_equal(closed, 2);
    assert_int_equal(how[0], SR_SCAN_IN_PLANE);
    assert_int_equal(how[1], SR_SCAN_IN_PLANE);
    assert_int_equal(d.strays, 1);
    assert_int_equal(d.stray_triangles, 1);
    assert_near(d.stray_area_mm2, 3, 1e-12);
    assert_int_equal(sr_scan_drop_strays(&m, &d, NULL), SR_OK);
    assert_int_equal(m.tri_count, 12); /* 10 walls and top, 2 of the fill */
    assert_true(sr_mesh_is_closed(&m));
    assert_near(sr_mesh_volume(&m), 6000, 1e-9);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

/* A box with one triangle of a side left out: a loop of three edges is closed by the
 * triangle it bounds, as it was (no vertex made at its centroid, no plane to fill), and
 * the box holds its volume again. */
static void a_triangle_left_out_is_put_back_as_it_was(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    size_t tris = m.tri_count, verts = m.vertex_count;
    uint32_t gone[3];
    memcpy(gone, m.tri + 3 * (tris - 1), sizeof gone);
    m.tri_count--; /* the last triangle left out */
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.loop_count, 1);
    assert_int_equal(d.loops[0].edges, 3);
    sr_scan_closing how[1] = {SR_SCAN_LEFT_OPEN};
    size_t closed = 0;
    assert_int_equal(sr_scan_close_openings_how(&m, &d, 0, &closed, how, NULL), SR_OK);
    assert_int_equal(closed, 1);
    assert_int_equal(how[0], SR_SCAN_IN_PLANE);
    assert_int_equal(m.tri_count, tris);
    assert_int_equal(m.vertex_count, verts);
    uint32_t *t = m.tri + 3 * (tris - 1); /* the same triangle, the same way round */
    int k = t[0] == gone[0] ? 0 : t[1] == gone[0] ? 1 : 2;
    assert_int_equal(t[k], gone[0]);
    assert_int_equal(t[(k + 1) % 3], gone[1]);
    assert_int_equal(t[(k + 2) % 3], gone[2]);
    assert_true(sr_mesh_is_closed(&m));
    assert_near(sr_mesh_volume(&m), 6000, 1e-9);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_stray_triangle_off_the_box_is_dropped(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    const double a[3] = {5, 10, 50}, b[3] = {6, 10, 50}, c[3] = {5, 11, 50};
    add_triangle(&m, a, b, c);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.component_count, 2);
    assert_int_equal(d.strays, 1);
    assert_int_equal(d.stray_triangles, 1);
    assert_near(d.stray_area_mm2, 0.5, 1e-12);
    assert_true(d.components[1].stray);
    assert_near(d.components[1].distance_mm, 20, 1e-12);
    /* the stray's own three edges are not openings of the part */
    assert_false(d.open);
    assert_int_equal(d.loop_count, 0);
    assert_int_equal(sr_scan_drop_strays(&m, &d, NULL), SR_OK);
    assert_int_equal(m.tri_count, 12);
    assert_int_equal(m.vertex_count, 8);
    for (size_t i = 0; i < 3 * m.tri_count; i++)
        assert_true(m.tri[i] < 8);
    /* at 0.01 % of the box's 2200 mm², 0.5 mm² is not small */
    sr_scan_desc_release(&d);
    add_triangle(&m, a, b, c);
    sr_scan_opts o = {.small_fraction = 1e-4};
    assert_int_equal(sr_scan_describe(&m, &o, &d, NULL), SR_OK);
    assert_int_equal(d.strays, 0);
    assert_near(d.components[1].distance_mm, -1, 0);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

/* The distance from the vertices of m's triangle t to m's first nt triangles, by brute
 * force. */
static double brute_distance(const sr_mesh *m, size_t nt, size_t t)
{
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        const double *p = m->xyz + 3 * (size_t)m->tri[3 * t + k];
        for (size_t u = 0; u < nt; u++) {
            double q[3];
            sr_tri_closest_point(p, m->xyz + 3 * (size_t)m->tri[3 * u],
                                 m->xyz + 3 * (size_t)m->tri[3 * u + 1],
                                 m->xyz + 3 * (size_t)m->tri[3 * u + 2], q);
            double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                            (p[2] - q[2]) * (p[2] - q[2]));
            best = d < best ? d : best;
        }
    }
    return best;
}

/* Strays over a dense surface (a 512-sided cylinder r 10, z 0..100: 2048 triangles on
 * the grid the distances are looked up in) are measured to the nearest triangle however
 * many cells away it lies, as brute force measures them: one 15 mm out from a wall, one
 * on the axis inside (about 10 mm from the wall), one 40 mm past the top (off the
 * grid). */
static void strays_over_a_dense_surface_are_measured_to_the_nearest_triangle(void **state)
{
    (void)state;
    sr_mesh m;
    assert_int_equal(sr_shape_cylinder(10, 0, 100, 512, &m, NULL), SR_OK);
    size_t nt = m.tri_count;
    const double at[3][3] = {{25, 0, 50}, {0, 0, 50}, {0, 0, 140}};
    double want[3];
    for (int k = 0; k < 3; k++) {
        const double *p = at[k];
        const double b[3] = {p[0] + 0.1, p[1], p[2]}, c[3] = {p[0], p[1] + 0.1, p[2]};
        add_triangle(&m, p, b, c);
        want[k] = brute_distance(&m, nt, nt + (size_t)k);
    }
    assert_true(want[0] > 14.9 && want[1] > 9.8 && want[1] < 10 && want[2] > 39.9);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.component_count, 4);
    assert_int_equal(d.strays, 3);
    for (int k = 0; k < 3; k++) { /* the ranks tie by area: found by distance */
        bool found = false;
        for (size_t c = 1; c < 4; c++)
            found = found || fabs(d.components[c].distance_mm - want[k]) <= 1e-12;
        assert_true(found);
    }
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);
}

static void a_small_piece_on_the_surface_or_a_large_one_is_kept(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    /* on the face x = 0: a fragment of the surface, not a stray */
    const double a[3] = {0, 5, 5}, b[3] = {0, 6, 5}, c[3] = {0, 5, 6};
    add_triangle(&m, a, b, c);
    sr_scan_desc d;
    assert_int_equal(sr_scan_describe(&m, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.component_count, 2);
    assert_int_equal(d.strays, 0);
    assert_near(d.components[1].distance_mm, 0, 1e-12);
    assert_true(d.open); /* the fragment's edges are its own openings */
    assert_int_equal(d.loop_count, 1);
    assert_int_equal(sr_scan_drop_strays(&m, &d, NULL), SR_OK);
    assert_int_equal(m.tri_count, 13);
    sr_scan_desc_release(&d);
    sr_mesh_release(&m);

    sr_mesh two, other;
    box(0, &two);
    box(50, &other);
    assert_int_equal(sr_mesh_append(&two, &other), SR_OK);
    assert_int_equal(sr_scan_describe(&two, NULL, &d, NULL), SR_OK);
    assert_int_equal(d.component_count, 2);
    assert_int_equal(d.strays, 0);
    assert_false(d.open);
    sr_scan_desc_release(&d);
    sr_mesh_release(&two);
    sr_mesh_release(&other);
}

static void bad_options_are_refused(void **state)
{
    (void)state;
    sr_mesh m;
    box(0, &m);
    sr_scan_desc d;
    memset(&d, 0x5a, sizeof d);
    sr_scan_opts o = {.small_fraction = 2};
    sr_err err;
    sr_err_clear(&err);
    assert_int_equal(sr_scan_describe(&m, &o, &d, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "small fraction"));
    o = (sr_scan_opts){.off_surface_mm = -1};
    assert_int_equal(sr_scan_describe(&m, &o, &d, NULL), SR_E_RANGE);
    o = (sr_scan_opts){.off_surface_mm = INFINITY};
    assert_int_equal(sr_scan_describe(&m, &o, &d, NULL), SR_E_RANGE);
    assert_int_equal(d.triangles, (size_t)0x5a5a5a5a5a5a5a5aULL); /* untouched */
    sr_scan_desc_release(NULL);
    sr_mesh_release(&m);
}

typedef struct keyed {
    uint64_t key; /* lo << 32 | hi */
    uint32_t seq; /* the input order */
} keyed;

static int by_key_then_seq(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->seq > b->seq) - (a->seq < b->seq);
}

static void edges_sort_by_key_keeping_the_order_of_equal_ones(void **state)
{
    (void)state;
    enum { N = 5000, NV = 40 };
    keyed *r = malloc(N * sizeof *r), *want = malloc(N * sizeof *want);
    assert_non_null(r);
    assert_non_null(want);
    uint32_t x = 12345; /* a fixed scramble: many keys repeat (40 * 39 / 2 pairs) */
    for (uint32_t i = 0; i < N; i++) {
        x = x * 1103515245u + 12345u;
        uint64_t a = (x >> 8) % NV, b = (x >> 20) % NV;
        r[i] = (keyed){a < b ? a << 32 | b : b << 32 | a, i};
    }
    memcpy(want, r, N * sizeof *r);
    qsort(want, N, sizeof *want, by_key_then_seq);
    assert_int_equal(sr_scan_sort_edges(r, N, sizeof *r, NV), SR_OK);
    for (size_t i = 0; i < N; i++) {
        assert_true(r[i].key == want[i].key);
        assert_int_equal(r[i].seq, want[i].seq);
    }
    keyed one = {7ull << 32 | 9, 3};
    assert_int_equal(sr_scan_sort_edges(&one, 1, sizeof one, 10), SR_OK);
    assert_true(one.key == (7ull << 32 | 9) && one.seq == 3);
    assert_int_equal(sr_scan_sort_edges(NULL, 0, sizeof one, 10), SR_OK);
    free(r);
    free(want);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_closed_box_has_no_opening_and_one_component),
        cmocka_unit_test(a_box_without_its_top_has_one_loop_round_it),
        cmocka_unit_test(a_fins_edge_is_non_manifold_and_a_strays_edges_are_not_counted),
        cmocka_unit_test(a_base_with_a_bore_or_a_concave_rim_is_closed_in_its_plane),
        cmocka_unit_test(rims_crossing_in_their_plane_are_cut_where_they_cross),
        cmocka_unit_test(two_pyramids_touching_at_a_corner_close_without_a_pinch),
        cmocka_unit_test(an_island_left_in_the_base_is_dropped_not_filled_round),
        cmocka_unit_test(a_triangle_left_out_is_put_back_as_it_was),
        cmocka_unit_test(a_stray_triangle_off_the_box_is_dropped),
        cmocka_unit_test(strays_over_a_dense_surface_are_measured_to_the_nearest_triangle),
        cmocka_unit_test(a_small_piece_on_the_surface_or_a_large_one_is_kept),
        cmocka_unit_test(bad_options_are_refused),
        cmocka_unit_test(edges_sort_by_key_keeping_the_order_of_equal_ones),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
