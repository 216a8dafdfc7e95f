/*
 * test_mend.c: mending a surface that crosses itself (src/bridge/mend.h) and the union
 * that mends a scan's neighbourhood first (sr_boolean_union_local_mending,
 * src/bridge/boolean.h). The fold is made the way scan noise makes one: a vertex of a
 * cylinder pushed past its neighbour along the surface, so its fan lies over the
 * neighbour's. Known answers: no crossing is left, the mesh stays closed (or keeps its
 * border), the enclosed volume moves by no more than the fold's own size, vertices keep
 * their indices; the mending union has the volume of the unfolded union; what cannot be
 * mended is refused with a message and the mesh untouched. Unfolding
 * (sr_mesh_unfold): a fold of noise's size comes out by moving vertices, within the
 * cap, topology and volume kept; one too large for the cap is left, and said.
 * Folded slivers (sr_mesh_clean_folded_slivers): a cap noise folded over its long edge
 * is flipped, and a box with one stays the box exactly. The crossings of a mesh are
 * the same found on 1, 2 or 3 threads.
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
#include "bridge/mend.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"
#include "support/assert_near.h"

static double ring_radius(double theta, size_t ring, void *user)
{
    (void)theta, (void)ring, (void)user;
    return 20.0;
}

/* A cylinder r = 20, z 0..40, 96 segments (3.75 deg), 41 rings (1 mm apart). */
static void make_ringed_cylinder(sr_mesh *m)
{
    double z[41];
    for (int i = 0; i < 41; i++)
        z[i] = i;
    sr_revolve_opts o = {.segments = 96, .ring_count = 41, .ring_z = z, .outer = ring_radius};
    assert_int_equal(sr_shape_revolve(&o, m, NULL), SR_OK);
    assert_true(sr_mesh_is_closed(m));
}

static size_t nearest_vertex(const sr_mesh *m, double x, double y, double z)
{
    size_t best = 0;
    double bd = INFINITY;
    for (size_t v = 0; v < m->vertex_count; v++) {
        const double *p = m->xyz + 3 * v;
        double d = (p[0] - x) * (p[0] - x) + (p[1] - y) * (p[1] - y) + (p[2] - z) * (p[2] - z);
        if (d < bd) {
            bd = d;
            best = v;
        }
    }
    return best;
}

/* Folds the surface at angle deg, height z: the vertex there is moved 1.4 times the way
 * to its neighbour 3.75 deg further on, so its triangles lie over the neighbour's. */
static void fold_at(sr_mesh *m, double deg, double z)
{
    double a = deg * M_PI / 180.0, b = (deg + 3.75) * M_PI / 180.0;
    size_t v = nearest_vertex(m, 20 * cos(a), 20 * sin(a), z);
    size_t w = nearest_vertex(m, 20 * cos(b), 20 * sin(b), z);
    assert_true(v != w);
    double *p = m->xyz + 3 * v;
    const double *q = m->xyz + 3 * w;
    for (int k = 0; k < 3; k++)
        p[k] += 1.4 * (q[k] - p[k]);
}

static int crosses(const sr_mesh *m)
{
    int x = -1;
    assert_int_equal(sr_mesh_self_intersects(m, &x, NULL), SR_OK);
    return x;
}

/* Mends m (whole mesh), which must cross itself before: afterwards nothing crosses, it
 * is closed and keeps its vertices (indices stay valid). */
static void mend_closed_mesh(sr_mesh *m, sr_mend_report *rep)
{
    assert_true(crosses(m));
    size_t nv = m->vertex_count;
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_mend_crossings(m, NULL, rep, &err), SR_OK);
    assert_true(rep->crossing_pairs > 0);
    assert_false(crosses(m));
    assert_true(sr_mesh_is_closed(m));
    assert_int_equal(m->vertex_count, nv);
}

/* ---- sr_mesh_mend_crossings --------------------------------------------------------- */

static void folded_cylinder_is_mended_closed_and_keeps_its_volume(void **state)
{
    (void)state;
    sr_mesh m, clean;
    make_ringed_cylinder(&m);
    assert_int_equal(sr_mesh_copy(&clean, &m), SR_OK);
    fold_at(&m, -40, 20);
    sr_mend_report rep;
    mend_closed_mesh(&m, &rep);
    assert_true(rep.removed_tris >= 2);
    assert_true(rep.filled_tris > 0);
    assert_true(rep.rounds >= 1);
    sr_mesh_edges e;
    assert_int_equal(sr_mesh_edge_stats(&m, &e), SR_OK);
    assert_int_equal(e.misoriented_edges, 0);
    assert_int_equal(e.nonmanifold_vertices, 0);
    /* the fill spans the fold's rim: the volume moves by at most the volume of a
     * cylinder sliver over the removed triangles (a few 1 x 1.3 mm cells, each at most
     * 0.011 mm from the chord: well under 0.1 mm^3) */
    assert_near(sr_mesh_volume(&m), sr_mesh_volume(&clean), 0.1);
    /* and the surface stays where it was, within the fold's size */
    sr_deviation d;
    assert_int_equal(sr_mesh_deviation(&m, &clean, &d, NULL), SR_OK);
    assert_true(d.max_mm < 1.0);
    sr_mesh_release(&m);
    sr_mesh_release(&clean);
}

/* A box [0, 10]^3 with every face a grid of 1 mm squares (two triangles each), closed
 * (the faces share their border vertices exactly). */
static void make_grid_box(sr_mesh *m)
{
    enum { N = 10 };
    assert_int_equal(sr_mesh_alloc(m, 6 * (N + 1) * (N + 1), 6 * 2 * N * N), SR_OK);
    size_t nv = 0, nt = 0;
    for (int axis = 0; axis < 3; axis++)
        for (int side = 0; side < 2; side++) {
            int u = (axis + 1) % 3, v = (axis + 2) % 3; /* (u, v, axis) right-handed */
            size_t base = nv;
            for (int j = 0; j <= N; j++)
                for (int i = 0; i <= N; i++) {
                    double *p = m->xyz + 3 * nv++;
                    p[axis] = side ? N : 0;
                    p[u] = i;
                    p[v] = j;
                }
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    uint32_t a = (uint32_t)(base + j * (N + 1) + i), b = a + 1,
                             c = a + N + 1, d = c + 1;
                    uint32_t q[6] = {a, b, d, a, d, c}; /* counter-clockwise seen from +axis */
                    if (!side) {                         /* outward is -axis: reversed */
                        q[1] = d, q[2] = b, q[4] = c, q[5] = d;
                    }
                    memcpy(m->tri + 3 * nt, q, sizeof q);
                    nt += 2;
                }
        }
    assert_int_equal(sr_mesh_weld_exact(m), SR_OK);
    assert_true(sr_mesh_is_closed(m));
    assert_near(sr_mesh_volume(m), 1000.0, 1e-9);
}

/* Noise folds a scan along a sharp edge: two neighbouring vertices on the box's edge
 * x = z = 10 pushed past each other along it (y 5 -> 6.3, y 6 -> 5.3), so their fans on
 * the top and the side overlap across the edge. Every point stays on the box, so the
 * mended surface must be the box exactly: the new triangles run through the pushed
 * points, the edge kept as an edge. Filled from the hole's rim alone, the corner was
 * cut (here: 999.17 mm^3, deviation max 0.33 / 0.58 mm). */
static void fold_across_a_sharp_edge_keeps_the_edge(void **state)
{
    (void)state;
    sr_mesh m, clean;
    make_grid_box(&m);
    assert_int_equal(sr_mesh_copy(&clean, &m), SR_OK);
    size_t a = nearest_vertex(&m, 10, 5, 10), b = nearest_vertex(&m, 10, 6, 10);
    m.xyz[3 * a + 1] = 6.3;
    m.xyz[3 * b + 1] = 5.3;
    sr_mend_report rep;
    mend_closed_mesh(&m, &rep);
    assert_true(rep.removed_tris > 0);
    assert_int_equal(rep.rim_filled, 0); /* every hole filled from its points */
    /* both ways: the mended surface lies on the box and covers all of it */
    sr_deviation on, covers;
    assert_int_equal(sr_mesh_deviation(&m, &clean, &on, NULL), SR_OK);
    assert_int_equal(sr_mesh_deviation(&clean, &m, &covers, NULL), SR_OK);
    print_message("sharp edge: %zu triangles replaced, volume %.6f mm^3, deviation max %.3g / "
                  "%.3g mm\n",
                  rep.removed_tris, sr_mesh_volume(&m), on.max_mm, covers.max_mm);
    assert_near(sr_mesh_volume(&m), 1000.0, 1e-9);
    assert_true(on.max_mm < 1e-9);
    assert_true(covers.max_mm < 1e-9);
    sr_mesh_release(&m);
    sr_mesh_release(&clean);
}

static void mesh_without_crossings_is_left_as_it_is(void **state)
{
    (void)state;
    sr_mesh m;
    make_ringed_cylinder(&m);
    uint32_t *tri = m.tri;
    size_t nt = m.tri_count;
    sr_mend_report rep;
    assert_int_equal(sr_mesh_mend_crossings(&m, NULL, &rep, NULL), SR_OK);
    assert_int_equal(rep.crossing_pairs, 0);
    assert_int_equal(rep.rounds, 0);
    assert_int_equal(rep.removed_tris, 0);
    assert_ptr_equal(m.tri, tri);
    assert_int_equal(m.tri_count, nt);
    sr_mesh_release(&m);
}

static void fold_outside_the_box_is_not_looked_at(void **state)
{
    (void)state;
    sr_mesh m;
    make_ringed_cylinder(&m);
    fold_at(&m, -40, 20);
    uint32_t *tri = m.tri;
    double box[6] = {-25, -25, 30, 25, 25, 45}; /* z 30..45: the fold is at z = 20 */
    sr_mend_report rep;
    assert_int_equal(sr_mesh_mend_crossings(&m, box, &rep, NULL), SR_OK);
    assert_int_equal(rep.rounds, 0);
    assert_ptr_equal(m.tri, tri);
    assert_true(crosses(&m));
    /* a box around it: mended */
    double near[6] = {10, -20, 15, 20, -5, 25};
    assert_int_equal(sr_mesh_mend_crossings(&m, near, &rep, NULL), SR_OK);
    assert_true(rep.rounds >= 1);
    assert_false(crosses(&m));
    sr_mesh_release(&m);
}

/* The cylinder's side without its caps: an open sheet whose border must stay. */
static void open_side(const sr_mesh *closed, sr_mesh *side)
{
    assert_int_equal(sr_mesh_copy(side, closed), SR_OK);
    size_t w = 0;
    for (size_t t = 0; t < side->tri_count; t++) {
        const uint32_t *f = side->tri + 3 * t;
        int on_side = 1; /* the caps are fans to a vertex on the axis */
        for (int k = 0; k < 3; k++) {
            const double *p = side->xyz + 3 * f[k];
            if (fabs(hypot(p[0], p[1]) - 20.0) > 1e-9)
                on_side = 0;
        }
        if (!on_side)
            continue;
        memmove(side->tri + 3 * w, f, 3 * sizeof *f);
        w++;
    }
    side->tri_count = w;
}

static void open_sheet_is_mended_and_keeps_its_border(void **state)
{
    (void)state;
    sr_mesh closed, side;
    make_ringed_cylinder(&closed);
    open_side(&closed, &side);
    sr_mesh_edges before, after;
    assert_int_equal(sr_mesh_edge_stats(&side, &before), SR_OK);
    assert_true(before.boundary_edges == 2 * 96);
    fold_at(&side, 100, 20);
    assert_true(crosses(&side));
    sr_mend_report rep;
    assert_int_equal(sr_mesh_mend_crossings(&side, NULL, &rep, NULL), SR_OK);
    assert_false(crosses(&side));
    assert_int_equal(sr_mesh_edge_stats(&side, &after), SR_OK);
    assert_int_equal(after.boundary_edges, before.boundary_edges);
    assert_int_equal(after.nonmanifold_edges, 0);
    assert_int_equal(after.misoriented_edges, 0);
    sr_mesh_release(&side);
    sr_mesh_release(&closed);
}

static void fold_at_the_border_is_refused_and_mesh_untouched(void **state)
{
    (void)state;
    sr_mesh closed, side;
    make_ringed_cylinder(&closed);
    open_side(&closed, &side);
    fold_at(&side, 100, 40); /* a vertex of the top border itself */
    assert_true(crosses(&side));
    uint32_t *tri = side.tri;
    size_t nt = side.tri_count;
    sr_mend_report rep;
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_mend_crossings(&side, NULL, &rep, &err), SR_E_INVALID);
    assert_msg_has(err, "cannot mend the crossings");
    assert_msg_has(err, "border");
    assert_int_equal(rep.reached_border, 1);
    assert_ptr_equal(side.tri, tri);
    assert_int_equal(side.tri_count, nt);
    sr_mesh_release(&side);
    sr_mesh_release(&closed);
}

static void non_manifold_input_is_refused(void **state)
{
    (void)state;
    /* two triangles on the same edge run the same way */
    double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0};
    uint32_t tri[] = {0, 1, 2, 0, 1, 3};
    sr_mesh m = {xyz, tri, 4, 2};
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_mend_crossings(&m, NULL, NULL, &err), SR_E_INVALID);
    assert_msg_has(err, "not an oriented manifold");
    assert_ptr_equal(m.tri, tri);
    /* NaN coordinates: named as the validator names them */
    double bad[] = {0, 0, 0, 1, 0, 0, NAN, 1, 0};
    uint32_t one[] = {0, 1, 2};
    sr_mesh n = {bad, one, 3, 1};
    assert_int_equal(sr_mesh_mend_crossings(&n, NULL, NULL, &err), SR_E_INVALID);
    assert_msg_has(err, "mesh to mend");
}

/* ---- the mending union -------------------------------------------------------------- */

static void folded_scan_unites_with_a_patch_over_the_fold(void **state)
{
    (void)state;
    sr_mesh scan, clean, box, out, ref;
    make_ringed_cylinder(&scan);
    assert_int_equal(sr_mesh_copy(&clean, &scan), SR_OK);
    fold_at(&scan, -30, 20); /* x = 17.3: inside the box */
    double lo[3] = {15, -18, 12}, hi[3] = {25, 18, 28};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);

    /* the plain local union refuses the fold */
    sr_err err = {{0}};
    sr_mesh_init(&out);
    assert_int_equal(sr_boolean_union_local(&scan, "scan", NULL, &box, "patch", 0, &out, NULL,
                                            &err),
                     SR_E_INVALID);
    assert_msg_has(err, "'scan' intersects itself where the other mesh is");

    /* the mending one unites; the fold lies inside the box, so the result is the union of
     * the unfolded cylinder and the box */
    sr_local_union_info info;
    assert_int_equal(sr_boolean_union_local_mending(&scan, "scan", NULL, &box, "patch", 0,
                                                    &out, &info, &err),
                     SR_OK);
    assert_int_equal(info.local, 1);
    assert_true(info.mended_tris >= 2);
    assert_true(sr_mesh_is_closed(&out));
    assert_false(crosses(&out));
    assert_int_equal(sr_boolean_union(&clean, &box, &ref, NULL), SR_OK);
    assert_near(sr_mesh_volume(&out), sr_mesh_volume(&ref), 1e-6 * sr_mesh_volume(&ref));
    sr_deviation d;
    assert_int_equal(sr_mesh_deviation(&out, &ref, &d, NULL), SR_OK);
    assert_true(d.max_mm < 1e-6);

    /* a scan without a fold: nothing mended, the plain union's result */
    sr_mesh plain;
    assert_int_equal(sr_boolean_union_local_mending(&clean, "scan", NULL, &box, "patch", 0,
                                                    &plain, &info, NULL),
                     SR_OK);
    assert_int_equal(info.mended_tris, 0);
    assert_near(sr_mesh_volume(&plain), sr_mesh_volume(&ref), 1e-9 * sr_mesh_volume(&ref));
    sr_mesh_release(&plain);
    sr_mesh_release(&ref);
    sr_mesh_release(&out);
    sr_mesh_release(&box);
    sr_mesh_release(&scan);
    sr_mesh_release(&clean);
}

/* ---- sr_mesh_unfold ------------------------------------------------------------------ */

/* Folds at deg, z by `times` the way to the neighbour 3.75 deg on (1.31 mm away). */
static void fold_by(sr_mesh *m, double deg, double z, double times)
{
    double a = deg * M_PI / 180.0, b = (deg + 3.75) * M_PI / 180.0;
    size_t v = nearest_vertex(m, 20 * cos(a), 20 * sin(a), z);
    size_t w = nearest_vertex(m, 20 * cos(b), 20 * sin(b), z);
    double *p = m->xyz + 3 * v;
    const double *q = m->xyz + 3 * w;
    for (int k = 0; k < 3; k++)
        p[k] += times * (q[k] - p[k]);
}

/* A vertex pushed 4 % past its neighbour (0.05 mm, noise's size): unfolded, nothing
 * crosses, no vertex farther than the cap from where it was, the triangles as they
 * were, the volume within what the moved vertices can sweep. */
static void fold_of_noise_size_is_unfolded_within_the_cap(void **state)
{
    (void)state;
    sr_mesh m, before;
    make_ringed_cylinder(&m);
    fold_by(&m, 30, 20, 1.04);
    assert_true(crosses(&m));
    assert_int_equal(sr_mesh_copy(&before, &m), SR_OK);
    sr_unfold_report rep;
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_unfold(&m, 0.1, &rep, &err), SR_OK);
    assert_true(rep.crossing_pairs > 0);
    assert_int_equal(rep.remaining_pairs, 0);
    assert_false(crosses(&m));
    assert_true(rep.moved_vertices >= 1);
    assert_true(rep.max_move_mm > 0 && rep.max_move_mm <= 0.1 + 1e-9);
    assert_int_equal(m.tri_count, before.tri_count);
    assert_memory_equal(m.tri, before.tri, 3 * m.tri_count * sizeof *m.tri);
    for (size_t v = 0; v < m.vertex_count; v++) {
        const double *p = m.xyz + 3 * v, *q = before.xyz + 3 * v;
        double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                        (p[2] - q[2]) * (p[2] - q[2]));
        assert_true(d <= 0.1 + 1e-9);
    }
    /* each moved vertex sweeps at most the cap over its share of the surface (one
     * 1 x 1.31 mm cell) */
    print_message("%zu crossing pairs, %zu vertices moved, at most %.3f mm; volume %+.3f mm^3\n",
                  rep.crossing_pairs, rep.moved_vertices, rep.max_move_mm,
                  sr_mesh_volume(&m) - sr_mesh_volume(&before));
    assert_near(sr_mesh_volume(&m), sr_mesh_volume(&before),
                (double)rep.moved_vertices * 0.1 * 1.31);
    sr_mesh_release(&m);
    sr_mesh_release(&before);
}

/* A fold of 1.8 mm is beyond a 0.1 mm cap: what still crosses is said (for the mender),
 * and no vertex went farther than the cap. Without crossings nothing moves. */
static void fold_beyond_the_cap_is_left_and_said(void **state)
{
    (void)state;
    sr_mesh m, before;
    make_ringed_cylinder(&m);
    sr_unfold_report rep;
    assert_int_equal(sr_mesh_unfold(&m, 0.1, &rep, NULL), SR_OK);
    assert_int_equal(rep.crossing_pairs, 0);
    assert_int_equal(rep.moved_vertices, 0);
    fold_at(&m, -40, 20);
    assert_int_equal(sr_mesh_copy(&before, &m), SR_OK);
    assert_int_equal(sr_mesh_unfold(&m, 0.1, &rep, NULL), SR_OK);
    assert_true(rep.crossing_pairs > 0);
    assert_true(rep.remaining_pairs > 0);
    assert_true(crosses(&m));
    assert_true(rep.max_move_mm <= 0.1 + 1e-9);
    sr_mesh_release(&m);
    sr_mesh_release(&before);
}

/* A box whose edge from vertex a to b (edge[0], edge[1]) is split by a vertex w a
 * micrometre from a: the two triangles at the edge become four, two of them needles. */
static void box_with_needles(const double lo[3], const double hi[3], sr_mesh *box, sr_mesh *m,
                             uint32_t edge[2])
{
    assert_int_equal(sr_shape_box(lo, hi, box, NULL), SR_OK);
    /* the edge of triangle 0 from its first vertex to its second */
    uint32_t a = box->tri[0], b = box->tri[1];
    assert_int_equal(sr_mesh_alloc(m, box->vertex_count + 1, box->tri_count + 2), SR_OK);
    memcpy(m->xyz, box->xyz, 3 * box->vertex_count * sizeof *m->xyz);
    uint32_t w = (uint32_t)box->vertex_count;
    double len = 0;
    for (int k = 0; k < 3; k++)
        len += pow(box->xyz[3 * b + k] - box->xyz[3 * a + k], 2);
    len = sqrt(len);
    for (int k = 0; k < 3; k++)
        m->xyz[3 * w + k] =
            box->xyz[3 * a + k] + 1e-3 / len * (box->xyz[3 * b + k] - box->xyz[3 * a + k]);
    size_t t = 0;
    for (size_t f = 0; f < box->tri_count; f++) {
        const uint32_t *v = box->tri + 3 * f;
        int split = -1;
        for (int e = 0; e < 3; e++)
            if ((v[e] == a && v[(e + 1) % 3] == b) || (v[e] == b && v[(e + 1) % 3] == a))
                split = e;
        if (split < 0) {
            memcpy(m->tri + 3 * t++, v, 3 * sizeof *v);
            continue;
        }
        uint32_t p = v[split], q = v[(split + 1) % 3], r = v[(split + 2) % 3];
        uint32_t one[3] = {p, w, r}, two[3] = {w, q, r};
        memcpy(m->tri + 3 * t++, one, sizeof one);
        memcpy(m->tri + 3 * t++, two, sizeof two);
    }
    assert_int_equal(t, box->tri_count + 2);
    assert_true(sr_mesh_is_closed(m));
    edge[0] = a;
    edge[1] = b;
}

/* Collapsing edges under 5 um folds the needles away (12 triangles again, closed, the
 * volume to the half micrometre the corner moved); an edge limit under the micrometre
 * changes nothing. */
static void needles_fold_away_and_longer_edges_stay(void **state)
{
    (void)state;
    double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    sr_mesh box, m;
    uint32_t edge[2];
    box_with_needles(lo, hi, &box, &m, edge);
    double vol = sr_mesh_volume(&box);
    size_t n = 9;
    int crossed = 7;
    assert_int_equal(sr_mesh_collapse_short_edges(&m, 1e-4, &n, &crossed, NULL), SR_OK);
    assert_int_equal(n, 0);
    assert_int_equal(crossed, 0);
    assert_int_equal(m.tri_count, box.tri_count + 2);
    assert_int_equal(sr_mesh_collapse_short_edges(&m, 5e-3, &n, &crossed, NULL), SR_OK);
    assert_int_equal(n, 1);
    assert_int_equal(crossed, 0);
    assert_int_equal(m.tri_count, box.tri_count);
    assert_int_equal(m.vertex_count, box.vertex_count);
    assert_true(sr_mesh_is_closed(&m));
    /* the corner moved half a micrometre along the edge */
    assert_near(sr_mesh_volume(&m), vol, 0.1);
    sr_mesh_release(&box);
    sr_mesh_release(&m);
}

/* The needled box with a plate inside it 0.2 um behind the face the corner a moves
 * into (the face across the split edge): the collapse moves a half micrometre along
 * the edge, and the face's triangles at a then cross the plate. Nothing is kept: the
 * mesh is unchanged and *crossed says why. */
static void a_collapse_that_crosses_is_not_kept(void **state)
{
    (void)state;
    double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    sr_mesh box, m, plate;
    uint32_t edge[2];
    box_with_needles(lo, hi, &box, &m, edge);
    const double *a = box.xyz + 3 * edge[0], *b = box.xyz + 3 * edge[1];
    double p0[3], p1[3];
    for (int k = 0; k < 3; k++) {
        double along = b[k] - a[k], in = 0.5 * (lo[k] + hi[k]) - a[k];
        if (fabs(along) > 0) { /* the edge's axis: 0.2 um behind the face, 1 mm deep */
            p0[k] = a[k] + copysign(2e-4, along);
            p1[k] = a[k] + copysign(1.0, along);
        } else { /* across: from 10 um off the corner inwards */
            p0[k] = a[k] + copysign(0.01, in);
            p1[k] = a[k] + copysign(5.0, in);
        }
    }
    double plo[3], phi[3];
    for (int k = 0; k < 3; k++) {
        plo[k] = fmin(p0[k], p1[k]);
        phi[k] = fmax(p0[k], p1[k]);
    }
    assert_int_equal(sr_shape_box(plo, phi, &plate, NULL), SR_OK);
    assert_int_equal(sr_mesh_append(&m, &plate), SR_OK);
    int crosses = 1;
    assert_int_equal(sr_mesh_self_intersects(&m, &crosses, NULL), SR_OK);
    assert_int_equal(crosses, 0);
    size_t tris = m.tri_count, verts = m.vertex_count, n = 9;
    int crossed = 0;
    assert_int_equal(sr_mesh_collapse_short_edges(&m, 5e-3, &n, &crossed, NULL), SR_OK);
    assert_int_equal(n, 0);
    assert_int_equal(crossed, 1);
    assert_int_equal(m.tri_count, tris);
    assert_int_equal(m.vertex_count, verts);
    /* the plate moved 1 um further back: the same collapse is kept */
    for (size_t v = box.vertex_count + 1; v < m.vertex_count; v++)
        for (int k = 0; k < 3; k++)
            if (fabs(m.xyz[3 * v + k] - p0[k]) < 1e-9)
                m.xyz[3 * v + k] = p0[k] + copysign(1e-3, p1[k] - p0[k]);
    assert_int_equal(sr_mesh_collapse_short_edges(&m, 5e-3, &n, &crossed, NULL), SR_OK);
    assert_int_equal(n, 1);
    assert_int_equal(crossed, 0);
    sr_mesh_release(&plate);
    sr_mesh_release(&box);
    sr_mesh_release(&m);
}

/* ---- sr_mesh_clean_folded_slivers ---------------------------------------------------- */

/* Finds the triangle with these three vertices (in this cyclic order). */
static size_t triangle_of(const sr_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    for (size_t t = 0; t < m->tri_count; t++)
        for (int r = 0; r < 3; r++) {
            const uint32_t *f = m->tri + 3 * t;
            if (f[r] == a && f[(r + 1) % 3] == b && f[(r + 2) % 3] == c)
                return t;
        }
    fail_msg("no triangle %u %u %u", a, b, c);
    return 0;
}

/* A scanner's cap folded by noise: on the grid box's top (z = 10), a vertex w put into
 * the triangle (4,4)-(5,4)-(5,5) next to its edge along y = 4, then moved 0.02 mm across
 * that edge (as noise does to a vertex 0.01 mm from it). The cap (a, b, w) now faces
 * down and lies over the triangle beyond the edge. Every point stays on the box, so the
 * cleaned surface must be the box exactly: no crossing, closed, volume 1000, area 600;
 * the fold is a cap's, so an edge flip cures it and no triangle is lost. */
static void make_folded_cap_box(sr_mesh *f)
{
    sr_mesh m;
    make_grid_box(&m);
    uint32_t a = (uint32_t)nearest_vertex(&m, 4, 4, 10), b = (uint32_t)nearest_vertex(&m, 5, 4, 10),
             d = (uint32_t)nearest_vertex(&m, 5, 5, 10);
    size_t t = triangle_of(&m, a, b, d);
    assert_int_equal(sr_mesh_alloc(f, m.vertex_count + 1, m.tri_count + 2), SR_OK);
    memcpy(f->xyz, m.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    memcpy(f->tri, m.tri, 3 * m.tri_count * sizeof *m.tri);
    uint32_t w = (uint32_t)m.vertex_count;
    double pw[3] = {4.5, 3.98, 10.0};
    memcpy(f->xyz + 3 * w, pw, sizeof pw);
    uint32_t fan[9] = {a, b, w, b, d, w, d, a, w};
    memcpy(f->tri + 3 * t, fan, 3 * sizeof *fan);
    memcpy(f->tri + 3 * m.tri_count, fan + 3, 6 * sizeof *fan);
    f->vertex_count = m.vertex_count + 1;
    f->tri_count = m.tri_count + 2;
    sr_mesh_release(&m);
}

static void folded_cap_is_flipped_and_the_box_stays_exact(void **state)
{
    (void)state;
    sr_mesh f;
    make_folded_cap_box(&f);
    assert_true(sr_mesh_is_closed(&f));
    assert_true(crosses(&f));
    sr_sliver_report rep;
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_clean_folded_slivers(&f, 0.1, &rep, &err), SR_OK);
    assert_true(rep.crossing_pairs > 0);
    assert_int_equal(rep.faces_removed, 0);
    assert_false(crosses(&f));
    assert_true(sr_mesh_is_closed(&f));
    assert_near(sr_mesh_volume(&f), 1000.0, 1e-9);
    assert_near(sr_mesh_area(&f), 600.0, 1e-9);
    sr_mesh_release(&f);
}

/* A surface that does not cross itself is left exactly as it is; a bad bound is refused
 * and a non-manifold mesh too, each with the mesh untouched. */
static void clean_surface_is_left_and_bad_input_refused(void **state)
{
    (void)state;
    sr_mesh m, before;
    make_grid_box(&m);
    assert_int_equal(sr_mesh_copy(&before, &m), SR_OK);
    sr_sliver_report rep;
    assert_int_equal(sr_mesh_clean_folded_slivers(&m, 0.1, &rep, NULL), SR_OK);
    assert_int_equal(rep.crossing_pairs, 0);
    assert_int_equal(m.tri_count, before.tri_count);
    assert_memory_equal(m.tri, before.tri, 3 * m.tri_count * sizeof *m.tri);
    assert_memory_equal(m.xyz, before.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_clean_folded_slivers(&m, 0.0, &rep, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "bound"));
    memcpy(m.tri + 3, m.tri, 3 * sizeof *m.tri); /* a triangle twice: not a manifold */
    assert_int_equal(sr_mesh_clean_folded_slivers(&m, 0.1, &rep, &err), SR_E_INVALID);
    assert_memory_equal(m.xyz, before.xyz, 3 * m.vertex_count * sizeof *m.xyz);
    sr_mesh_release(&m);
    sr_mesh_release(&before);
}

/* ---- sr_mesh_unfold_scan --------------------------------------------------------------- */

/* The one-pass unfold gives exactly what the two steps give one after the other
 * (slivers cleaned, then sr_mesh_unfold over the whole mesh): the same triangles, byte
 * for byte, and the same vertices to rounding (a ring's points are summed in the order of
 * a mesh built once, not twice), on a folded cap (cured by a flip) and on a vertex folded past
 * its neighbour by noise (cured by moving vertices); the input is left as it was. */
static void expect_one_pass_equals_two_steps(const sr_mesh *in)
{
    sr_mesh two;
    assert_int_equal(sr_mesh_copy(&two, in), SR_OK);
    sr_sliver_report s2;
    sr_unfold_report u2;
    assert_int_equal(sr_mesh_clean_folded_slivers(&two, 0.1, &s2, NULL), SR_OK);
    assert_int_equal(sr_mesh_unfold(&two, 0.1, &u2, NULL), SR_OK);
    sr_mesh one, copy;
    assert_int_equal(sr_mesh_copy(&copy, in), SR_OK);
    sr_sliver_report s1;
    sr_unfold_report u1;
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_unfold_scan(in, 0.1, &one, &s1, &u1, &err), SR_OK);
    assert_true(s1.crossing_pairs > 0);
    assert_int_equal(s1.crossing_pairs, s2.crossing_pairs);
    assert_int_equal(s1.faces_removed, s2.faces_removed);
    assert_int_equal(u1.moved_vertices, u2.moved_vertices);
    assert_int_equal(u1.remaining_pairs, 0);
    assert_false(crosses(&one));
    assert_true(sr_mesh_is_closed(&one));
    assert_int_equal(one.vertex_count, two.vertex_count);
    assert_int_equal(one.tri_count, two.tri_count);
    assert_memory_equal(one.tri, two.tri, 3 * one.tri_count * sizeof *one.tri);
    for (size_t i = 0; i < 3 * one.vertex_count; i++) /* ring sums in another order */
        assert_near(one.xyz[i], two.xyz[i], 1e-12);
    assert_memory_equal(in->xyz, copy.xyz, 3 * in->vertex_count * sizeof *in->xyz);
    sr_mesh_release(&one);
    sr_mesh_release(&two);
    sr_mesh_release(&copy);
}

static void one_pass_unfold_equals_the_two_steps(void **state)
{
    (void)state;
    sr_mesh m;
    make_folded_cap_box(&m);
    expect_one_pass_equals_two_steps(&m);
    sr_mesh_release(&m);
    make_ringed_cylinder(&m);
    fold_by(&m, 30, 20, 1.04);
    expect_one_pass_equals_two_steps(&m);
    sr_mesh_release(&m);
}

/* Nothing crosses: the answer is empty (the scan as it is). A bad bound and a
 * non-manifold scan are refused with the answer empty. */
static void one_pass_unfold_leaves_clean_scans_and_refuses_bad_input(void **state)
{
    (void)state;
    sr_mesh m, out;
    make_grid_box(&m);
    sr_sliver_report s;
    sr_unfold_report u;
    assert_int_equal(sr_mesh_unfold_scan(&m, 0.1, &out, &s, &u, NULL), SR_OK);
    assert_int_equal(s.crossing_pairs, 0);
    assert_int_equal(u.moved_vertices, 0);
    assert_int_equal(out.tri_count, 0);
    assert_null(out.xyz);
    sr_err err = {{0}};
    assert_int_equal(sr_mesh_unfold_scan(&m, -1.0, &out, &s, &u, &err), SR_E_RANGE);
    assert_non_null(strstr(err.msg, "bound"));
    memcpy(m.tri + 3, m.tri, 3 * sizeof *m.tri);
    assert_int_equal(sr_mesh_unfold_scan(&m, 0.1, &out, NULL, NULL, &err), SR_E_INVALID);
    assert_int_equal(out.tri_count, 0);
    sr_mesh_release(&m);
}

/* A cross: a bar along x and one along y piercing its sides, at x0 along x. */
static void append_cross(sr_mesh *m, double x0)
{
    sr_mesh a, b;
    const double alo[3] = {x0, 1, 0}, ahi[3] = {x0 + 3, 2, 1};
    const double blo[3] = {x0 + 1, 0, 0.25}, bhi[3] = {x0 + 2, 3, 0.75};
    assert_int_equal(sr_shape_box(alo, ahi, &a, NULL), SR_OK);
    assert_int_equal(sr_shape_box(blo, bhi, &b, NULL), SR_OK);
    assert_int_equal(sr_mesh_append(m, &a), SR_OK);
    assert_int_equal(sr_mesh_append(m, &b), SR_OK);
    sr_mesh_release(&a);
    sr_mesh_release(&b);
}

/* The crossings of a mesh found on several threads (crossings_cgal.cpp): a row of
 * 6,001 crosses (144,024 triangles: three slabs of at most about 65,536, taken in turn
 * by one thread, by two, or each by its own of three), 4 mm apart along x so the cuts
 * between the slabs pass through some. Known answers: one cross alone crosses itself in
 * some number of pairs k > 0, found on one thread; the row crosses in 6,001 k pairs,
 * the same pairs in the same order on 1, 2 and 3 threads,
 * each pair once with its lower triangle first, both triangles of one cross. A box
 * has none. */
static void crossings_are_the_same_on_any_number_of_threads(void **state)
{
    (void)state;
    sr_mesh one = {0}, row = {0};
    append_cross(&one, 0);
    uint32_t *p1 = NULL;
    size_t k = 0;
    assert_int_equal(sr_mesh_crossing_pairs(&one, 1, &p1, &k, NULL), SR_OK);
    assert_true(k > 0);
    free(p1);
    /* the row made from copies of one cross moved along x (appending 6,001 times
     * copied the growing row each time: a minute and a half under ASan) */
    const size_t crosses = 6001, nv = one.vertex_count, nt = one.tri_count;
    assert_int_equal(sr_mesh_alloc(&row, crosses * nv, crosses * nt), SR_OK);
    for (size_t i = 0; i < crosses; i++) {
        for (size_t v = 0; v < nv; v++) {
            double *q = row.xyz + 3 * (i * nv + v);
            memcpy(q, one.xyz + 3 * v, 3 * sizeof *q);
            q[0] += 4.0 * (double)i;
        }
        for (size_t c = 0; c < 3 * nt; c++)
            row.tri[3 * i * nt + c] = (uint32_t)(i * nv) + one.tri[c];
    }
    assert_int_equal(row.tri_count, 144024);
    uint32_t *p[3] = {NULL, NULL, NULL};
    size_t n[3];
    for (int t = 0; t < 3; t++)
        assert_int_equal(sr_mesh_crossing_pairs(&row, t + 1, &p[t], &n[t], NULL), SR_OK);
    assert_int_equal(n[0], 6001 * k);
    for (int t = 1; t < 3; t++) {
        assert_int_equal(n[t], n[0]);
        assert_memory_equal(p[t], p[0], 2 * n[0] * sizeof(uint32_t));
    }
    for (size_t i = 0; i < n[0]; i++) {
        assert_true(p[0][2 * i] < p[0][2 * i + 1]);
        assert_int_equal(p[0][2 * i] / 24, p[0][2 * i + 1] / 24); /* 24 triangles a cross */
        if (i)
            assert_true(p[0][2 * i - 2] < p[0][2 * i] ||
                        (p[0][2 * i - 2] == p[0][2 * i] && p[0][2 * i - 1] < p[0][2 * i + 1]));
    }
    for (int t = 0; t < 3; t++)
        free(p[t]);
    sr_mesh box;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    assert_int_equal(sr_mesh_crossing_pairs(&box, 2, &p1, &k, NULL), SR_OK);
    assert_int_equal(k, 0);
    free(p1);
    sr_mesh_release(&box);
    sr_mesh_release(&one);
    sr_mesh_release(&row);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(folded_cylinder_is_mended_closed_and_keeps_its_volume),
        cmocka_unit_test(fold_across_a_sharp_edge_keeps_the_edge),
        cmocka_unit_test(mesh_without_crossings_is_left_as_it_is),
        cmocka_unit_test(fold_outside_the_box_is_not_looked_at),
        cmocka_unit_test(open_sheet_is_mended_and_keeps_its_border),
        cmocka_unit_test(fold_at_the_border_is_refused_and_mesh_untouched),
        cmocka_unit_test(non_manifold_input_is_refused),
        cmocka_unit_test(needles_fold_away_and_longer_edges_stay),
        cmocka_unit_test(a_collapse_that_crosses_is_not_kept),
        cmocka_unit_test(folded_scan_unites_with_a_patch_over_the_fold),
        cmocka_unit_test(fold_of_noise_size_is_unfolded_within_the_cap),
        cmocka_unit_test(fold_beyond_the_cap_is_left_and_said),
        cmocka_unit_test(folded_cap_is_flipped_and_the_box_stays_exact),
        cmocka_unit_test(clean_surface_is_left_and_bad_input_refused),
        cmocka_unit_test(one_pass_unfold_equals_the_two_steps),
        cmocka_unit_test(one_pass_unfold_leaves_clean_scans_and_refuses_bad_input),
        cmocka_unit_test(crossings_are_the_same_on_any_number_of_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
