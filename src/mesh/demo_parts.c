/*
 * demo_parts.c: the parts of the built-in demo catalogue (see shapes.h): a table of
 * what each part is, and builders of its intact and damaged meshes in the canonical
 * frame (axial: axis = z; mirror and glide: plane x = 0 with z in the plane).
 *
 * Both meshes of a part come from the same parametric description, the damaged one with
 * a local change (a smaller ring radius over a few rings and azimuths, or an outline with
 * a corner cut away), so each is closed and the missing volume is exactly
 * volume(intact) - volume(damaged). Each mesh has a few thousand triangles at most.
 */
#include "mesh/shapes.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "base/symmetry.h"

#define DEMO_PI 3.14159265358979323846
#define DEG (DEMO_PI / 180.0)

static const sr_demo_part parts[] = {
    {
        .number = "SR-SHAFT-01",
        .name = "stepped shaft",
        .material = "42CrMo4",
        .notes = "stepped shaft: dia 40 body z 0..50, dia 60 shoulder z 50..70, dia 30 "
                 "journal z 70..100",
        .serial = "SN-24-0117",
        .damage_notes = "chip off the shoulder's lower edge, azimuth -40..+40 deg, up to 6 mm "
                        "deep at z = 50 tapering out by z = 64",
        .sym_kind = SR_SYM_AXIAL,
        .sym_order = 0,
        .sym_shift_mm = 0,
    },
    {
        .number = "SR-BUSH-02",
        .name = "plain bushing",
        .material = "CuSn12",
        .notes = "hollow bushing: OD 50, ID 30, 60 long",
        .serial = "SN-24-0342",
        .damage_notes = "gouge in the outer wall, up to 4 mm deep, azimuth 85..155 deg, "
                        "z 20..40; the bore is intact",
        .sym_kind = SR_SYM_AXIAL,
        .sym_order = 0,
        .sym_shift_mm = 0,
    },
    {
        .number = "SR-BRKT-03",
        .name = "mounting bracket",
        .material = "AlSi10Mg",
        .notes = "plate bracket 12 thick: base 60 x 40 with a 16 x 8 slot on top, two ears "
                 "16 wide with R8 ends reaching x = +-48",
        .serial = "SN-24-0588",
        .damage_notes = "the +x ear broken off beyond a skewed line from (37, -20) to (35, -4)",
        .sym_kind = SR_SYM_MIRROR,
        .sym_order = 0,
        .sym_shift_mm = 0,
    },
    {
        .number = "SR-RAIL-04",
        .name = "notched rail",
        .material = "S355",
        .notes = "rail along z (-5..95), 24 wide (x), 16 high (y); notches 6 long x 4.5 deep "
                 "on the -x side at z = 0, 20, .., 80 and on the +x side at z = 10, 30, .., 90",
        .serial = "SN-24-0901",
        .damage_notes = "the +x tooth between the notches at z = 50 and z = 70 chipped along "
                        "a skewed line from (7.5, 56) to (12, 64)",
        .sym_kind = SR_SYM_GLIDE,
        .sym_order = 0,
        .sym_shift_mm = 10,
    },
};

#define PART_COUNT (sizeof parts / sizeof parts[0])

size_t sr_demo_part_count(void)
{
    return PART_COUNT;
}

const sr_demo_part *sr_demo_part_get(size_t i)
{
    return i < PART_COUNT ? &parts[i] : NULL;
}

/* 1 for |u| <= 0.5, a cos^2 fall to 0 at |u| = 1: a damage profile with a flat bottom
 * and smooth edges. */
static double plateau(double u)
{
    u = fabs(u);
    if (u <= 0.5)
        return 1;
    if (u >= 1)
        return 0;
    double c = cos(DEMO_PI * (u - 0.5));
    return c * c;
}

/* Angle from `centre` to theta, in [-pi, pi]. */
static double azimuth_from(double theta, double centre)
{
    return remainder(theta - centre, 2 * DEMO_PI);
}

/* A revolved part: ring heights, base radii, and an optional damage depth function
 * subtracted from the outer radius. */
typedef struct ring_part {
    const double *z;
    const double *outer;
    double inner;                 /* 0 = solid */
    double (*damage)(double theta, double z, double r); /* depth at (theta, z) of a ring
                                                          * of base radius r */
} ring_part;

static double ring_outer(double theta, size_t ring, void *user)
{
    const ring_part *p = user;
    double r = p->outer[ring];
    return p->damage ? r - p->damage(theta, p->z[ring], r) : r;
}

static double ring_inner(double theta, size_t ring, void *user)
{
    return ((const ring_part *)user)->inner;
}

/* ---- 1: stepped shaft ---- */

/* Extra rings every 2 mm on the shoulder's lower part resolve the chip. */
static const double shaft_z[] = {0, 50, 50, 52, 54, 56, 58, 60, 62, 64, 70, 70, 100};
static const double shaft_r[] = {20, 20, 30, 30, 30, 30, 30, 30, 30, 30, 30, 15, 15};

static double shaft_chip(double theta, double z, double r)
{
    if (z < 50 || z > 64 || r != 30) /* the shoulder only, not the body's top ring */
        return 0;
    return 6.0 * (64.0 - z) / 14.0 * plateau(azimuth_from(theta, 0) / (40 * DEG));
}

static sr_status build_shaft(bool damaged, sr_mesh *out, sr_err *err)
{
    ring_part p = {shaft_z, shaft_r, 0, damaged ? shaft_chip : NULL};
    sr_revolve_opts o = {.segments = 96,
                         .ring_count = sizeof shaft_z / sizeof shaft_z[0],
                         .ring_z = shaft_z,
                         .outer = ring_outer,
                         .user = &p};
    return sr_shape_revolve(&o, out, err);
}

/* ---- 2: bushing ---- */

static const double bush_z[] = {0, 20, 22, 24, 26, 28, 30, 32, 34, 36, 38, 40, 60};
static const double bush_r[] = {25, 25, 25, 25, 25, 25, 25, 25, 25, 25, 25, 25, 25};

static double bush_gouge(double theta, double z, double r)
{
    return 4.0 * plateau((z - 30.0) / 10.0) * plateau(azimuth_from(theta, 120 * DEG) / (35 * DEG));
}

static sr_status build_bushing(bool damaged, sr_mesh *out, sr_err *err)
{
    ring_part p = {bush_z, bush_r, 15, damaged ? bush_gouge : NULL};
    sr_revolve_opts o = {.segments = 72,
                         .ring_count = sizeof bush_z / sizeof bush_z[0],
                         .ring_z = bush_z,
                         .outer = ring_outer,
                         .inner = ring_inner,
                         .user = &p};
    return sr_shape_revolve(&o, out, err);
}

/* ---- 3: bracket ---- */

#define EAR_STEPS 12            /* segments of each ear's R8 half circle */
#define BRKT_HALF (EAR_STEPS + 1 + 4)
#define BRKT_MAX (2 * BRKT_HALF)

/* Writes the right half of the bracket outline (counter-clockwise, from the bottom of
 * the +x ear up to the slot) into xy and returns its point count. */
static size_t bracket_right_half(bool damaged, double xy[2 * BRKT_HALF])
{
    size_t n = 0;
    if (!damaged) {
        for (int j = 0; j <= EAR_STEPS; j++, n++) {
            double a = -DEMO_PI / 2 + DEMO_PI * j / EAR_STEPS;
            xy[2 * n] = 40 + 8 * cos(a);
            xy[2 * n + 1] = -12 + 8 * sin(a);
        }
        xy[0] = 40, xy[1] = -20; /* exact ends of the half circle */
        xy[2 * (n - 1)] = 40, xy[2 * (n - 1) + 1] = -4;
    } else {
        static const double cut[] = {37, -20, 35, -4};
        for (; n < 2; n++)
            xy[2 * n] = cut[2 * n], xy[2 * n + 1] = cut[2 * n + 1];
    }
    static const double rest[] = {30, -4, 30, 20, 8, 20, 8, 12};
    for (size_t i = 0; i < 4; i++, n++)
        xy[2 * n] = rest[2 * i], xy[2 * n + 1] = rest[2 * i + 1];
    return n;
}

/* Fills xy with the whole bracket outline and returns its point count: the right half
 * (intact or broken), then the intact right half mirrored to x < 0 in reverse order, so
 * the intact outline is symmetric about x = 0 bit for bit. */
static size_t bracket_outline(bool damaged, double xy[2 * BRKT_MAX])
{
    double half[2 * BRKT_HALF];
    size_t n = bracket_right_half(damaged, xy);
    size_t h = bracket_right_half(false, half);
    for (size_t i = h; i-- > 0; n++) {
        xy[2 * n] = -half[2 * i];
        xy[2 * n + 1] = half[2 * i + 1];
    }
    return n;
}

static sr_status build_bracket(bool damaged, sr_mesh *out, sr_err *err)
{
    double xy[2 * BRKT_MAX];
    size_t n = bracket_outline(damaged, xy);
    return sr_shape_prism(xy, n, 0, 12, out, err);
}

/* ---- 4: glide rail ---- */

#define RAIL_W 12.0             /* half width */
#define RAIL_DEPTH 4.5          /* notch depth */
#define RAIL_MAX 48

/* The rail's outline in the (x, z) plane as (x, v) pairs, counter-clockwise. */
static size_t rail_outline(bool damaged, double xv[2 * RAIL_MAX])
{
    const double w = RAIL_W, d = w - RAIL_DEPTH;
    size_t n = 0;
#define PUT(X, V) (xv[2 * n] = (X), xv[2 * n + 1] = (V), n++)
    PUT(-w, -5);
    PUT(w, -5);
    for (int c = 10; c <= 90; c += 20) {     /* +x side, going up */
        PUT(w, c - 3);
        PUT(d, c - 3);
        if (damaged && c == 50) {            /* the tooth 53..67 chipped */
            PUT(d, 56);
            PUT(w, 64);
        } else {
            PUT(d, c + 3);
            PUT(w, c + 3);
        }
    }
    PUT(w, 95);
    PUT(-w, 95);
    for (int c = 80; c >= 0; c -= 20) {      /* -x side, going down */
        PUT(-w, c + 3);
        PUT(-d, c + 3);
        PUT(-d, c - 3);
        PUT(-w, c - 3);
    }
#undef PUT
    return n;
}

static sr_status build_rail(bool damaged, sr_mesh *out, sr_err *err)
{
    double xv[2 * RAIL_MAX];
    size_t n = rail_outline(damaged, xv);
    sr_mesh m;
    sr_status st = sr_shape_prism(xv, n, -8, 8, &m, err);
    if (st != SR_OK)
        return st;
    /* Rotate +90 deg about x: (x, y, z) -> (x, -z, y), the outline's v becomes z and the
     * extrusion runs along y. A rotation keeps the outward orientation. */
    static const double rot[12] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0};
    sr_mesh_transform(&m, rot);
    *out = m;
    return SR_OK;
}

/* ---- table of builders ---- */

typedef sr_status (*part_builder)(bool damaged, sr_mesh *out, sr_err *err);
static const part_builder builders[PART_COUNT] = {build_shaft, build_bushing, build_bracket,
                                                  build_rail};

sr_status sr_demo_part_build(size_t i, sr_mesh *intact, sr_mesh *damaged, sr_err *err)
{
    if (i >= PART_COUNT)
        return sr_err_set(err, SR_E_RANGE, "demo part %zu does not exist (there are %zu)", i,
                          (size_t)PART_COUNT);
    sr_mesh a = {0}, b = {0};
    sr_status st = SR_OK;
    if (intact && (st = builders[i](false, &a, err)) != SR_OK)
        return st;
    if (damaged && (st = builders[i](true, &b, err)) != SR_OK) {
        sr_mesh_release(&a);
        return st;
    }
    if (intact)
        *intact = a;
    if (damaged)
        *damaged = b;
    return SR_OK;
}
