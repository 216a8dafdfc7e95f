/*
 * shapes.c: closed, outward-oriented meshes of parametric solids (see shapes.h):
 * surfaces of revolution given as rings (solid or hollow, with flat steps), cylinders,
 * boxes and prisms (a simple counter-clockwise polygon extruded along z, caps cut by
 * ear clipping). The demo catalogue's parts are built from these in demo_parts.c.
 *
 * Every builder validates its parameters first (SR_E_RANGE naming the field) and only
 * then allocates, so an accepted input always yields a closed, consistently oriented
 * mesh without zero-area triangles; nothing is written to *out on failure.
 *
 * Revolve layout: ring i, vertex k sits at angle theta_k = 2 pi k / segments. Bands
 * between consecutive rings are quads split along (i,k)-(i+1,k+1); two rings at the same
 * z form a flat annulus, and two identical rings at the same z share their vertices (no
 * band), which lets a hollow part step its outer wall where its bore does not.
 */
#include "mesh/shapes.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define SHAPES_PI 3.14159265358979323846

/* ---------------------------------------------------------------- revolve ---- */

/* How ring b's radii compare with ring a's at every angle: 0 all equal, +1 all larger,
 * -1 all smaller, 2 mixed (some equal or crossing). */
static int ring_compare(const double *a, const double *b, size_t segments)
{
    int sign = 0;
    for (size_t k = 0; k < segments; k++) {
        int s = b[k] > a[k] ? 1 : b[k] < a[k] ? -1 : 0;
        if (k == 0)
            sign = s;
        else if (s != sign)
            return 2;
    }
    return sign;
}

/* Checks the same-z runs of one surface ("outer" or "inner"): every flat band steps all
 * the way round in one direction, a run keeps one direction, the bottom run of the outer
 * surface steps outward and the top run inward (the inner surface the other way), so no
 * two flat faces overlap. r is ring_count by segments. */
static sr_status check_flat_steps(const char *what, const double *z, const double *r,
                                  size_t ring_count, size_t segments, int inner_surface,
                                  sr_err *err)
{
    int run_sign = 0;
    for (size_t i = 0; i + 1 < ring_count; i++) {
        if (z[i] != z[i + 1]) {
            run_sign = 0;
            continue;
        }
        int c = ring_compare(r + i * segments, r + (i + 1) * segments, segments);
        if (c == 2)
            return sr_err_set(err, SR_E_RANGE,
                              "revolve rings %zu and %zu share 'ring_z' = %g but their '%s' "
                              "radii neither all match nor all step the same way",
                              i, i + 1, z[i], what);
        if (c == 0)
            continue;
        if (run_sign != 0 && c != run_sign)
            return sr_err_set(err, SR_E_RANGE,
                              "revolve rings at 'ring_z' = %g step the '%s' radius out and "
                              "back in (flat faces would overlap)",
                              z[i], what);
        run_sign = c;
        int want_bottom = inner_surface ? -1 : 1;
        if (z[i] == z[0] && c != want_bottom)
            return sr_err_set(err, SR_E_RANGE,
                              "revolve rings %zu and %zu at the bottom 'ring_z' = %g must step "
                              "the '%s' radius %s",
                              i, i + 1, z[i], what, want_bottom > 0 ? "outward" : "inward");
        if (z[i] == z[ring_count - 1] && c != -want_bottom)
            return sr_err_set(err, SR_E_RANGE,
                              "revolve rings %zu and %zu at the top 'ring_z' = %g must step "
                              "the '%s' radius %s",
                              i, i + 1, z[i], what, want_bottom > 0 ? "inward" : "outward");
    }
    return SR_OK;
}

/* Evaluates a radius function on every ring and angle into r (ring_count by segments)
 * and checks each value is finite and > 0. */
static sr_status eval_radii(const char *what, sr_ring_radius_fn fn, void *user,
                            size_t ring_count, size_t segments, const double *theta, double *r,
                            sr_err *err)
{
    for (size_t i = 0; i < ring_count; i++) {
        for (size_t k = 0; k < segments; k++) {
            double v = fn(theta[k], i, user);
            if (!isfinite(v) || !(v > 0))
                return sr_err_set(err, SR_E_RANGE,
                                  "revolve '%s' radius of ring %zu at theta %.6g is %g, must "
                                  "be finite and > 0",
                                  what, i, theta[k], v);
            r[i * segments + k] = v;
        }
    }
    return SR_OK;
}

/* Gives every ring of one surface the index of its first vertex, reusing the previous
 * ring's vertices when the two are identical and at the same z. Returns the number of
 * distinct rings; base[i] counts from `first`. */
static size_t assign_rings(const double *z, const double *r, size_t ring_count,
                           size_t segments, size_t first, size_t *base)
{
    size_t distinct = 0;
    for (size_t i = 0; i < ring_count; i++) {
        if (i > 0 && z[i] == z[i - 1] &&
            ring_compare(r + (i - 1) * segments, r + i * segments, segments) == 0) {
            base[i] = base[i - 1];
            continue;
        }
        base[i] = first + distinct * segments;
        distinct++;
    }
    return distinct;
}

/* Appends the 2*segments triangles joining ring a to ring b (a quad per segment).
 * Unflipped, the faces look along theta x (b - a): outward for an outer wall rising in
 * z, downward for a flat step going outward. */
static uint32_t *emit_band(uint32_t *t, size_t a, size_t b, size_t segments, int flip)
{
    for (size_t k = 0; k < segments; k++) {
        size_t k1 = (k + 1) % segments;
        uint32_t va = (uint32_t)(a + k), vb = (uint32_t)(a + k1);
        uint32_t vc = (uint32_t)(b + k1), vd = (uint32_t)(b + k);
        uint32_t q[6] = {va, vb, vc, va, vc, vd};
        if (flip) {
            q[1] = vc, q[2] = vb;
            q[4] = vd, q[5] = vc;
        }
        memcpy(t, q, sizeof q);
        t += 6;
    }
    return t;
}

sr_status sr_shape_revolve(const sr_revolve_opts *opts, sr_mesh *out, sr_err *err)
{
    assert(opts && out);
    const size_t S = opts->segments, R = opts->ring_count;
    const double *z = opts->ring_z;
    const int hollow = opts->inner != NULL;

    if (S < 3)
        return sr_err_set(err, SR_E_RANGE, "revolve 'segments' is %zu, must be at least 3", S);
    if (R < 2)
        return sr_err_set(err, SR_E_RANGE, "revolve 'ring_count' is %zu, must be at least 2",
                          R);
    if (!z)
        return sr_err_set(err, SR_E_RANGE, "revolve 'ring_z' is missing");
    if (!opts->outer)
        return sr_err_set(err, SR_E_RANGE, "revolve 'outer' radius function is missing");
    /* Vertices: one ring per surface per ring index at most, plus two centres. */
    if (S > SR_MESH_MAX_COUNT / 4 / R)
        return sr_err_set(err, SR_E_RANGE,
                          "revolve 'segments' x 'ring_count' (%zu x %zu) is too large", S, R);
    for (size_t i = 0; i < R; i++) {
        if (!isfinite(z[i]))
            return sr_err_set(err, SR_E_RANGE, "revolve 'ring_z[%zu]' is %g, must be finite",
                              i, z[i]);
        if (i > 0 && z[i] < z[i - 1])
            return sr_err_set(err, SR_E_RANGE,
                              "revolve 'ring_z[%zu]' = %g is below 'ring_z[%zu]' = %g "
                              "(heights must not decrease)",
                              i, z[i], i - 1, z[i - 1]);
    }
    if (!(z[R - 1] > z[0]))
        return sr_err_set(err, SR_E_RANGE,
                          "revolve 'ring_z' spans no height (all rings at z = %g)", z[0]);

    sr_status st = SR_OK;
    sr_mesh m = {0};
    double *theta = malloc(3 * S * sizeof *theta); /* theta, then (cos, sin) pairs */
    double *ro = malloc(R * S * sizeof *ro);
    double *ri = hollow ? malloc(R * S * sizeof *ri) : NULL;
    size_t *base_o = malloc(R * sizeof *base_o);
    size_t *base_i = malloc(R * sizeof *base_i);
    if (!theta || !ro || (hollow && !ri) || !base_o || !base_i) {
        st = sr_err_set(err, SR_E_NOMEM, "revolve: out of memory for %zu x %zu rings", R, S);
        goto cleanup;
    }
    double *cs = theta + S;
    for (size_t k = 0; k < S; k++) {
        theta[k] = 2.0 * SHAPES_PI * (double)k / (double)S;
        cs[2 * k] = cos(theta[k]);
        cs[2 * k + 1] = sin(theta[k]);
    }

    st = eval_radii("outer", opts->outer, opts->user, R, S, theta, ro, err);
    if (st != SR_OK)
        goto cleanup;
    if (hollow) {
        st = eval_radii("inner", opts->inner, opts->user, R, S, theta, ri, err);
        if (st != SR_OK)
            goto cleanup;
        for (size_t i = 0; i < R * S; i++) {
            if (!(ri[i] < ro[i])) {
                st = sr_err_set(err, SR_E_RANGE,
                                "revolve 'inner' radius of ring %zu at theta %.6g is %g, not "
                                "below the 'outer' radius %g",
                                i / S, theta[i % S], ri[i], ro[i]);
                goto cleanup;
            }
        }
        /* At a flat step the wall below and the wall above must overlap radially, or the
         * part comes apart at that z and its two flat faces would overlap. */
        for (size_t i = 0; i + 1 < R; i++) {
            if (z[i] != z[i + 1])
                continue;
            for (size_t k = 0; k < S; k++) {
                size_t a = i * S + k, b = (i + 1) * S + k;
                if (!(ri[b] < ro[a] && ri[a] < ro[b])) {
                    st = sr_err_set(err, SR_E_RANGE,
                                    "revolve rings %zu and %zu at 'ring_z' = %g do not "
                                    "overlap at theta %.6g (the wall would come apart)",
                                    i, i + 1, z[i], theta[k]);
                    goto cleanup;
                }
            }
        }
    }
    st = check_flat_steps("outer", z, ro, R, S, 0, err);
    if (st == SR_OK && hollow)
        st = check_flat_steps("inner", z, ri, R, S, 1, err);
    if (st != SR_OK)
        goto cleanup;

    /* Layout: outer rings, then inner rings (hollow) or the two cap centres (solid). */
    size_t n_outer = assign_rings(z, ro, R, S, 0, base_o);
    size_t n_inner = hollow ? assign_rings(z, ri, R, S, n_outer * S, base_i) : 0;
    size_t band_o = 0, band_i = 0;
    for (size_t i = 0; i + 1 < R; i++) {
        band_o += base_o[i] != base_o[i + 1];
        if (hollow)
            band_i += base_i[i] != base_i[i + 1];
    }
    size_t vcount = (n_outer + n_inner) * S + (hollow ? 0 : 2);
    size_t tcount = 2 * S * (band_o + band_i) + (hollow ? 4 * S : 2 * S);
    if (sr_mesh_alloc(&m, vcount, tcount) != SR_OK) {
        st = sr_err_set(err, SR_E_NOMEM, "revolve: out of memory for %zu triangles", tcount);
        goto cleanup;
    }

    for (int surf = 0; surf < 1 + hollow; surf++) {
        const double *r = surf ? ri : ro;
        const size_t *base = surf ? base_i : base_o;
        for (size_t i = 0; i < R; i++) {
            double *p = m.xyz + 3 * base[i];
            for (size_t k = 0; k < S; k++) {
                p[3 * k] = r[i * S + k] * cs[2 * k];
                p[3 * k + 1] = r[i * S + k] * cs[2 * k + 1];
                p[3 * k + 2] = z[i];
            }
        }
    }
    uint32_t *t = m.tri;
    for (size_t i = 0; i + 1 < R; i++) {
        if (base_o[i] != base_o[i + 1])
            t = emit_band(t, base_o[i], base_o[i + 1], S, 0);
        if (hollow && base_i[i] != base_i[i + 1])
            t = emit_band(t, base_i[i], base_i[i + 1], S, 1);
    }
    if (hollow) {
        /* Annular end caps from the bore out to the wall: down at the bottom, up on top. */
        t = emit_band(t, base_i[0], base_o[0], S, 0);
        t = emit_band(t, base_i[R - 1], base_o[R - 1], S, 1);
    } else {
        uint32_t c0 = (uint32_t)(n_outer * S), c1 = c0 + 1;
        double *p0 = m.xyz + 3 * (size_t)c0, *p1 = m.xyz + 3 * (size_t)c1;
        p0[0] = p0[1] = p1[0] = p1[1] = 0;
        p0[2] = z[0];
        p1[2] = z[R - 1];
        for (size_t k = 0; k < S; k++) {
            uint32_t k1 = (uint32_t)((k + 1) % S);
            uint32_t lo = (uint32_t)base_o[0], hi = (uint32_t)base_o[R - 1];
            uint32_t f[6] = {c0, lo + k1, lo + (uint32_t)k, c1, hi + (uint32_t)k, hi + k1};
            memcpy(t, f, sizeof f);
            t += 6;
        }
    }
    assert((size_t)(t - m.tri) == 3 * tcount);
    *out = m;
    m = (sr_mesh){0};

cleanup:
    sr_mesh_release(&m);
    free(theta);
    free(ro);
    free(ri);
    free(base_o);
    free(base_i);
    return st;
}

/* --------------------------------------------------------------- cylinder ---- */

static double constant_radius(double theta, size_t ring, void *user)
{
    return *(const double *)user;
}

sr_status sr_shape_cylinder(double r, double z0, double z1, size_t segments, sr_mesh *out,
                            sr_err *err)
{
    if (!isfinite(r) || !(r > 0))
        return sr_err_set(err, SR_E_RANGE, "cylinder radius 'r' is %g, must be finite and > 0",
                          r);
    if (!isfinite(z0) || !isfinite(z1) || !(z1 > z0))
        return sr_err_set(err, SR_E_RANGE,
                          "cylinder 'z1' (%g) must be finite and above 'z0' (%g)", z1, z0);
    if (segments < 3)
        return sr_err_set(err, SR_E_RANGE, "cylinder 'segments' is %zu, must be at least 3",
                          segments);
    double z[2] = {z0, z1};
    sr_revolve_opts o = {.segments = segments, .ring_count = 2, .ring_z = z,
                         .outer = constant_radius, .user = &r};
    return sr_shape_revolve(&o, out, err);
}

/* -------------------------------------------------------------------- box ---- */

sr_status sr_shape_box(const double min[3], const double max[3], sr_mesh *out, sr_err *err)
{
    static const char axis[3] = {'x', 'y', 'z'};
    for (int k = 0; k < 3; k++) {
        if (!isfinite(min[k]) || !isfinite(max[k]) || !(max[k] > min[k]))
            return sr_err_set(err, SR_E_RANGE,
                              "box 'max[%d]' (%g) must be finite and above 'min[%d]' (%g) "
                              "(%c)",
                              k, max[k], k, min[k], axis[k]);
    }
    /* Corner v has x from bit 0, y from bit 1, z from bit 2. */
    static const uint32_t f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                      {0, 1, 5}, {0, 5, 4}, {1, 3, 7}, {1, 7, 5},
                                      {3, 2, 6}, {3, 6, 7}, {2, 0, 4}, {2, 4, 6}};
    sr_mesh m;
    if (sr_mesh_alloc(&m, 8, 12) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "box: out of memory");
    for (int v = 0; v < 8; v++) {
        m.xyz[3 * v] = (v & 1) ? max[0] : min[0];
        m.xyz[3 * v + 1] = (v & 2) ? max[1] : min[1];
        m.xyz[3 * v + 2] = (v & 4) ? max[2] : min[2];
    }
    memcpy(m.tri, f, sizeof f);
    *out = m;
    return SR_OK;
}

/* ------------------------------------------------------------------ prism ---- */

/* Twice the signed area of triangle abc (> 0 when counter-clockwise). */
static double orient2(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* p on the closed segment ab, given that a, b, p are collinear. */
static int on_segment(const double *a, const double *b, const double *p)
{
    return fmin(a[0], b[0]) <= p[0] && p[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= p[1] &&
           p[1] <= fmax(a[1], b[1]);
}

/* Closed segments ab and cd share at least one point. */
static int segments_touch(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = orient2(a, b, c), o2 = orient2(a, b, d);
    double o3 = orient2(c, d, a), o4 = orient2(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return 1;
    return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
           (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

/* Checks xy is a simple counter-clockwise polygon; O(n^2), fine for hand-made outlines. */
static sr_status check_polygon(const double *xy, size_t n, sr_err *err)
{
    if (n < 3)
        return sr_err_set(err, SR_E_RANGE,
                          "prism polygon 'xy' has %zu points, needs at least 3", n);
    for (size_t i = 0; i < 2 * n; i++) {
        if (!isfinite(xy[i]))
            return sr_err_set(err, SR_E_RANGE,
                              "prism polygon 'xy' point %zu has a NaN or infinite coordinate",
                              i / 2);
    }
    for (size_t i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n), *c = xy + 2 * ((i + 2) % n);
        if (a[0] == b[0] && a[1] == b[1])
            return sr_err_set(err, SR_E_RANGE,
                              "prism polygon 'xy' points %zu and %zu coincide", i, (i + 1) % n);
        /* Adjacent edges folding back onto each other. */
        if (orient2(a, b, c) == 0 &&
            (a[0] - b[0]) * (c[0] - b[0]) + (a[1] - b[1]) * (c[1] - b[1]) > 0)
            return sr_err_set(err, SR_E_RANGE,
                              "prism polygon 'xy' is not simple: it folds back at point %zu",
                              (i + 1) % n);
    }
    for (size_t i = 0; i < n; i++) {
        for (size_t j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1)
                continue; /* adjacent through the closing edge */
            if (segments_touch(xy + 2 * i, xy + 2 * ((i + 1) % n), xy + 2 * j,
                               xy + 2 * ((j + 1) % n)))
                return sr_err_set(err, SR_E_RANGE,
                                  "prism polygon 'xy' is not simple: edges %zu and %zu touch",
                                  i, j);
        }
    }
    double area2 = 0;
    for (size_t i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        area2 += a[0] * b[1] - a[1] * b[0];
    }
    if (!(area2 > 0))
        return sr_err_set(err, SR_E_RANGE,
                          "prism polygon 'xy' is clockwise (signed area %g), give its points "
                          "counter-clockwise",
                          area2 / 2);
    return SR_OK;
}

/* Ear clipping of a simple CCW polygon into n - 2 triangles (tri: (n-2) by 3 indices).
 * An ear is a strictly convex vertex whose triangle holds no other remaining vertex, not
 * even on its boundary, so no output triangle has zero area. Returns 0 if it gets stuck,
 * which only a nearly degenerate outline can cause. */
static int ear_clip(const double *xy, size_t n, uint32_t *tri)
{
    size_t *next = malloc(n * sizeof *next), *prev = malloc(n * sizeof *prev);
    if (!next || !prev) {
        free(next);
        free(prev);
        return -1;
    }
    for (size_t i = 0; i < n; i++) {
        next[i] = (i + 1) % n;
        prev[i] = (i + n - 1) % n;
    }
    size_t left = n, v = 0, since_clip = 0, out = 0;
    int ok = 1;
    while (left > 3) {
        size_t a = prev[v], b = v, c = next[v];
        const double *pa = xy + 2 * a, *pb = xy + 2 * b, *pc = xy + 2 * c;
        int ear = orient2(pa, pb, pc) > 0;
        for (size_t p = next[c]; ear && p != a; p = next[p]) {
            const double *q = xy + 2 * p;
            if (orient2(pa, pb, q) >= 0 && orient2(pb, pc, q) >= 0 && orient2(pc, pa, q) >= 0)
                ear = 0;
        }
        if (ear) {
            tri[3 * out] = (uint32_t)a;
            tri[3 * out + 1] = (uint32_t)b;
            tri[3 * out + 2] = (uint32_t)c;
            out++;
            next[a] = c;
            prev[c] = a;
            left--;
            since_clip = 0;
            v = c;
        } else {
            v = next[v];
            if (++since_clip > left) {
                ok = 0;
                break;
            }
        }
    }
    if (ok) {
        size_t a = prev[v], c = next[v];
        if (!(orient2(xy + 2 * a, xy + 2 * v, xy + 2 * c) > 0)) {
            ok = 0;
        } else {
            tri[3 * out] = (uint32_t)a;
            tri[3 * out + 1] = (uint32_t)v;
            tri[3 * out + 2] = (uint32_t)c;
        }
    }
    free(next);
    free(prev);
    return ok;
}

sr_status sr_shape_prism(const double *xy, size_t count, double z0, double z1, sr_mesh *out,
                         sr_err *err)
{
    assert(out && (xy || count == 0));
    if (!isfinite(z0) || !isfinite(z1) || !(z1 > z0))
        return sr_err_set(err, SR_E_RANGE,
                          "prism 'z1' (%g) must be finite and above 'z0' (%g)", z1, z0);
    sr_status st = check_polygon(xy, count, err);
    if (st != SR_OK)
        return st;
    if (count > SR_MESH_MAX_COUNT / 4)
        return sr_err_set(err, SR_E_RANGE, "prism polygon 'xy' has too many points (%zu)",
                          count);
    const size_t n = count, cap = n - 2;
    sr_mesh m;
    if (sr_mesh_alloc(&m, 2 * n, 2 * cap + 2 * n) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "prism: out of memory for %zu points", n);
    int clipped = ear_clip(xy, n, m.tri);
    if (clipped != 1) {
        sr_mesh_release(&m);
        if (clipped < 0)
            return sr_err_set(err, SR_E_NOMEM, "prism: out of memory for %zu points", n);
        return sr_err_set(err, SR_E_RANGE,
                          "prism polygon 'xy' could not be triangulated (nearly degenerate "
                          "outline)");
    }
    for (size_t i = 0; i < n; i++) {
        double *lo = m.xyz + 3 * i, *hi = m.xyz + 3 * (n + i);
        lo[0] = hi[0] = xy[2 * i];
        lo[1] = hi[1] = xy[2 * i + 1];
        lo[2] = z0;
        hi[2] = z1;
    }
    /* The ear triangles are the top cap as they stand; the bottom cap is them reversed. */
    uint32_t *bottom = m.tri + 3 * cap;
    for (size_t t = 0; t < cap; t++) {
        uint32_t a = m.tri[3 * t], b = m.tri[3 * t + 1], c = m.tri[3 * t + 2];
        bottom[3 * t] = a;
        bottom[3 * t + 1] = c;
        bottom[3 * t + 2] = b;
        m.tri[3 * t] = (uint32_t)n + a;
        m.tri[3 * t + 1] = (uint32_t)n + b;
        m.tri[3 * t + 2] = (uint32_t)n + c;
    }
    /* Side quads: edge direction x z is the outward normal of a CCW outline. */
    uint32_t *t = m.tri + 6 * cap;
    for (size_t i = 0; i < n; i++) {
        uint32_t a = (uint32_t)i, b = (uint32_t)((i + 1) % n);
        uint32_t f[6] = {a, b, (uint32_t)n + b, a, (uint32_t)n + b, (uint32_t)n + a};
        memcpy(t, f, sizeof f);
        t += 6;
    }
    *out = m;
    return SR_OK;
}
