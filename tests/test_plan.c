/*
 * test_plan.c: build plans (src/plan/plan.h) and their files (src/plan/plan_export.h) on runs
 * built in memory: an axial run (a radius-20 cylinder whose restored outline is the
 * full circle, with a 2 mm deep chip over 40 degrees in 6 of 10 layers) and a planar
 * run (a 40 x 20 rectangle with a 3 mm notch on the +x side). The missing area of a
 * layer is known exactly: the shoelace area of the restored outline minus that of the
 * damaged one (the damaged outline lies inside the restored one). Checked: layer count,
 * areas and volumes, every path point inside the layer's missing region grown by the
 * allowance and never inside the damaged part, resampling to other thicknesses, the
 * patterns, the G-code line by line, the SVG and JSON files, and every refusal.
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

#include "bridge/polygon.h"
#include "plan/plan.h"
#include "plan/plan_export.h"
#include "support/assert_near.h"
#include "support/tmpdir.h"

#define DEG (3.14159265358979323846 / 180.0)
#define SECTORS 72  /* 5 degrees each */
#define LAYERS 10   /* dz = 1 mm, layer l at z = l + 0.5 */

/* Fills the layer arrays of a run: restored point of sector j at radius rr(l, j) and
 * damaged at rd(l, j) on the sector's centre angle; radius <= 0 means no point. */
typedef double (*radius_fn)(size_t l, size_t j, int damaged);

static void make_run(sr_run *run, radius_fn radius, sr_sym_kind kind)
{
    memset(run, 0, sizeof *run);
    run->id = 42;
    run->symmetry.kind = kind;
    run->layer_count = LAYERS;
    run->sectors = SECTORS;
    run->layer_z = calloc(LAYERS, sizeof(double));
    run->damaged_xy = calloc(LAYERS * SECTORS * 2, sizeof(double));
    run->restored_xy = calloc(LAYERS * SECTORS * 2, sizeof(double));
    assert_non_null(run->layer_z);
    assert_non_null(run->damaged_xy);
    assert_non_null(run->restored_xy);
    for (size_t l = 0; l < LAYERS; l++) {
        run->layer_z[l] = (double)l + 0.5;
        for (size_t j = 0; j < SECTORS; j++) {
            double a = ((double)j + 0.5) * 360.0 / SECTORS * DEG;
            for (int d = 0; d < 2; d++) {
                double r = radius(l, j, d);
                double *p = (d ? run->damaged_xy : run->restored_xy) + 2 * (l * SECTORS + j);
                p[0] = r > 0 ? r * cos(a) : NAN;
                p[1] = r > 0 ? r * sin(a) : NAN;
            }
        }
    }
    run->sections = calloc(1, sizeof *run->sections);
    assert_non_null(run->sections);
    run->section_count = 1;
}

static void free_run(sr_run *run)
{
    free(run->layer_z);
    free(run->damaged_xy);
    free(run->restored_xy);
    free(run->sections);
}

/* Cylinder r = 20; chip r = 18 in layers 2..7, sectors 2..9 (10..50 degrees). */
static double chip_radius(size_t l, size_t j, int damaged)
{
    if (damaged && l >= 2 && l <= 7 && j >= 2 && j <= 9)
        return 18.0;
    return 20.0;
}

/* Section 1: layers 2..7, the arc 10..50 degrees. */
static void set_chip_section(sr_run *run)
{
    sr_run_section *s = &run->sections[0];
    s->index = 0;
    s->layer_first = 2;
    s->layer_last = 7;
    s->z_min_mm = 2.0;
    s->z_max_mm = 8.0;
    s->has_angles = 1;
    s->angle_from_deg = 10.0;
    s->angle_to_deg = 50.0;
}

static void make_axial_run(sr_run *run)
{
    make_run(run, chip_radius, SR_SYM_AXIAL);
    set_chip_section(run);
}

/* Rectangle |x| <= 20, |y| <= 10 seen from the centre; a notch to x = 17 over the
 * sectors within 15 degrees of +x (j = 0..2 and 69..71) in layers 0..3. */
static double rect_radius(size_t l, size_t j, int damaged)
{
    double a = ((double)j + 0.5) * 360.0 / SECTORS * DEG;
    double c = fabs(cos(a)), s = fabs(sin(a));
    double r = fmin(c > 1e-12 ? 20.0 / c : INFINITY, s > 1e-12 ? 10.0 / s : INFINITY);
    if (damaged && l <= 3 && (j <= 2 || j >= 69))
        r = 17.0 / c;
    return r;
}

static void make_planar_run(sr_run *run, int side)
{
    make_run(run, rect_radius, SR_SYM_MIRROR);
    sr_run_section *s = &run->sections[0];
    s->layer_first = 0;
    s->layer_last = 3;
    s->z_min_mm = 0.0;
    s->z_max_mm = 4.0;
    s->side = side;
}

/* Shoelace area of one layer's outline (NaN points skipped). */
static double outline_area(const double *grid, size_t l)
{
    double a = 0, px = NAN, py = NAN, fx = NAN, fy = NAN;
    for (size_t j = 0; j < SECTORS; j++) {
        const double *p = grid + 2 * (l * SECTORS + j);
        if (!isfinite(p[0]))
            continue;
        if (isfinite(px))
            a += px * p[1] - p[0] * py;
        else {
            fx = p[0];
            fy = p[1];
        }
        px = p[0];
        py = p[1];
    }
    a += px * fy - fx * py;
    return 0.5 * a;
}

static double expected_missing_area(const sr_run *run, size_t l)
{
    return outline_area(run->restored_xy, l) - outline_area(run->damaged_xy, l);
}

/* The damaged outline of a run layer as a region. */
static void damaged_region(const sr_run *run, size_t l, sr_poly2 *out)
{
    double xy[2 * SECTORS];
    size_t k = 0;
    for (size_t j = 0; j < SECTORS; j++) {
        const double *p = run->damaged_xy + 2 * (l * SECTORS + j);
        if (isfinite(p[0])) {
            xy[2 * k] = p[0];
            xy[2 * k + 1] = p[1];
            k++;
        }
    }
    sr_poly2_init(out);
    assert_int_equal(sr_poly2_add_contour(out, xy, k, NULL), SR_OK);
}

/* Every path point of every layer lies inside the layer's missing region grown by the
 * allowance (boundary included) and not strictly inside the damaged outline of any run
 * layer the plan layer was built from. Returns the number of points checked. */
static size_t check_paths_inside(const sr_run *run, const sr_plan *plan)
{
    size_t checked = 0;
    for (size_t k = 0; k < plan->layer_count; k++) {
        const sr_plan_layer *L = &plan->layers[k];
        sr_poly2 grown;
        sr_poly2_init(&grown);
        assert_int_equal(sr_poly2_offset(&L->missing, plan->opts.allowance_mm, 1, &grown, NULL),
                         SR_OK);
        for (size_t rl = L->run_layer_first; rl <= L->run_layer_last; rl++) {
            sr_poly2 dam;
            damaged_region(run, rl, &dam);
            for (size_t i = 0; i < sr_poly2_point_count(&L->paths); i++) {
                double x = L->paths.xy[2 * i], y = L->paths.xy[2 * i + 1];
                if (sr_poly2_contains(&grown, x, y) == 0) {
                    print_error("layer %zu point (%g, %g) outside the grown region\n", k, x, y);
                    fail();
                }
                assert_int_not_equal(sr_poly2_contains(&dam, x, y), 1);
                checked++;
            }
            sr_poly2_release(&dam);
        }
        sr_poly2_release(&grown);
    }
    return checked;
}

static void axial_chip_plan_has_section_layers_and_exact_areas(void **state)
{
    sr_run run;
    sr_plan plan;
    make_axial_run(&run);
    double area = expected_missing_area(&run, 2); /* sin 5deg (20 + 7*38 + 20) = 26.67 */
    assert_near(area, sin(5 * DEG) * 306.0, 1e-9);
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_int_equal(plan.layer_count, 6);
    assert_near(plan.opts.layer_mm, 1.0, 1e-12);
    double deposit = 0;
    for (size_t k = 0; k < 6; k++) {
        const sr_plan_layer *L = &plan.layers[k];
        assert_int_equal(L->run_layer_first, k + 2);
        assert_int_equal(L->run_layer_last, k + 2);
        assert_near(L->z_bottom_mm, 2.0 + (double)k, 1e-12);
        assert_near(L->z_top_mm, 3.0 + (double)k, 1e-12);
        assert_near(L->missing_area_mm2, area, 1e-3);
        assert_near(sr_poly2_area(&L->missing), L->missing_area_mm2, 1e-12);
        /* the allowance adds material outside the restored outline and at the ends */
        assert_true(L->region_area_mm2 > area + 0.4 * 0.5 * 14.0);
        assert_true(L->paths.contour_count > 0);
        assert_near(L->raster_angle_deg, k % 2 ? 90.0 : 0.0, 1e-12);
        /* beads 1 mm apart cover the region: path length x step-over ~ area */
        double cover = L->path_length_mm * 1.0 / L->region_area_mm2;
        assert_true(cover > 0.6 && cover < 1.4);
        deposit += L->region_area_mm2 * 1.0;
    }
    assert_near(plan.missing_volume_mm3, 6.0 * area, 6e-3);
    assert_near(plan.deposit_volume_mm3, deposit, 1e-9);
    assert_near(plan.deposit_mass_g, deposit / 1000.0 * 7.85, 1e-12);
    /* the default feed lays 1 cm3/min down as 1 mm x 1 mm beads: 1000 mm/min; the build
     * time is that path's time plus the travel between paths at 5000 mm/min */
    assert_near(plan.feed_mm_min, 1000.0, 1e-9);
    assert_near(plan.deposit_time_min, plan.path_length_mm / 1000.0, 1e-12);
    assert_true(plan.travel_length_mm > 6 * 2 * 5.0); /* up and down 5 mm per path at least */
    assert_near(plan.travel_time_min, plan.travel_length_mm / 5000.0, 1e-12);
    assert_near(plan.build_time_min, plan.deposit_time_min + plan.travel_time_min, 1e-12);
    assert_true(check_paths_inside(&run, &plan) > 100);
    sr_plan_release(&plan);
    free_run(&run);
}

/* The wedge keeps the section to its own arc: a second chip elsewhere in the same
 * layers is not part of section 1's region. */
static double two_chip_radius(size_t l, size_t j, int damaged)
{
    if (damaged && l >= 2 && l <= 7 && j >= 40 && j <= 43)
        return 19.0;
    return chip_radius(l, j, damaged);
}

static void axial_plan_stays_in_the_sections_wedge(void **state)
{
    sr_run run;
    sr_plan plan;
    make_run(&run, two_chip_radius, SR_SYM_AXIAL);
    set_chip_section(&run);
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_near(plan.layers[0].missing_area_mm2, sin(5 * DEG) * 306.0, 1e-3);
    for (size_t k = 0; k < plan.layer_count; k++)
        for (size_t i = 0; i < sr_poly2_point_count(&plan.layers[k].region); i++) {
            double x = plan.layers[k].region.xy[2 * i], y = plan.layers[k].region.xy[2 * i + 1];
            double a = atan2(y, x) / DEG;
            assert_true(a > 0 && a < 60); /* 10..50 deg, half a sector and 0.5 mm more */
        }
    sr_plan_release(&plan);
    free_run(&run);
}

static void thicker_and_thinner_layers_resample_by_union(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_plan_opts o;
    make_axial_run(&run);
    double area = expected_missing_area(&run, 2);
    sr_plan_opts_init(&o);
    o.layer_mm = 2.0;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, NULL), SR_OK);
    assert_int_equal(plan.layer_count, 3);
    assert_int_equal(plan.layers[1].run_layer_first, 4);
    assert_int_equal(plan.layers[1].run_layer_last, 5);
    assert_near(plan.missing_volume_mm3, 6.0 * area, 6e-3);
    check_paths_inside(&run, &plan);
    sr_plan_release(&plan);
    o.layer_mm = 0.4; /* 6 mm / 0.4 = 15 layers */
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, NULL), SR_OK);
    assert_int_equal(plan.layer_count, 15);
    assert_near(plan.missing_volume_mm3, 6.0 * area, 6e-3);
    assert_near(plan.layers[14].z_top_mm, 8.0, 1e-9);
    sr_plan_release(&plan);
    free_run(&run);
}

static void planar_notch_plan_uses_the_sections_side(void **state)
{
    sr_run run;
    sr_plan plan;
    make_planar_run(&run, +1);
    double area = expected_missing_area(&run, 0);
    assert_true(area > 3.0 * 10.0); /* a notch 3 mm deep and more than 10 mm high */
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_int_equal(plan.layer_count, 4);
    for (size_t k = 0; k < 4; k++) {
        assert_near(plan.layers[k].missing_area_mm2, area, 1e-3);
        assert_true(plan.layers[k].paths.contour_count > 0);
    }
    assert_near(plan.missing_volume_mm3, 4.0 * area, 4e-3);
    assert_true(check_paths_inside(&run, &plan) > 50);
    sr_plan_release(&plan);
    free_run(&run);

    make_planar_run(&run, -1); /* the other side has nothing missing */
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_int_equal(plan.layer_count, 4);
    assert_near(plan.missing_volume_mm3, 0.0, 0);
    assert_int_equal(plan.layers[0].paths.contour_count, 0);
    sr_plan_release(&plan);
    free_run(&run);
}

static void contour_pattern_gives_closed_rings_only(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_plan_opts o;
    make_planar_run(&run, +1);
    sr_plan_opts_init(&o);
    o.pattern = SR_PLAN_CONTOUR;
    o.step_over_mm = 0.5;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, NULL), SR_OK);
    const sr_plan_layer *L = &plan.layers[0];
    assert_true(L->paths.contour_count >= 3); /* 3.5 mm wide with allowance: 3+ rings */
    for (size_t c = 0; c < L->paths.contour_count; c++) {
        const double *first = L->paths.xy + 2 * L->paths.start[c];
        const double *last = L->paths.xy + 2 * (L->paths.start[c + 1] - 1);
        assert_int_equal(L->path_kind[c], SR_PLAN_PATH_RING);
        assert_near(first[0], last[0], 0);
        assert_near(first[1], last[1], 0);
    }
    check_paths_inside(&run, &plan);
    sr_plan_release(&plan);
    o.pattern = SR_PLAN_RASTER;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, NULL), SR_OK);
    for (size_t c = 0; c < plan.layers[0].paths.contour_count; c++)
        assert_int_equal(plan.layers[0].path_kind[c], SR_PLAN_PATH_RASTER);
    /* joined into a zig-zag: fewer paths than raster lines */
    assert_true(plan.layers[0].paths.contour_count < 4);
    check_paths_inside(&run, &plan);
    sr_plan_release(&plan);
    free_run(&run);
}

/* A sector without a damaged point (the surface is gone there) is bridged by a chord:
 * the region still lies outside what is left. */
static double hole_radius(size_t l, size_t j, int damaged)
{
    if (damaged && j == 5 && l >= 2 && l <= 7)
        return 0; /* no point */
    return chip_radius(l, j, damaged);
}

static void sector_without_damaged_point_is_bridged(void **state)
{
    sr_run run;
    sr_plan plan;
    make_run(&run, hole_radius, SR_SYM_AXIAL);
    set_chip_section(&run);
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_near(plan.layers[0].missing_area_mm2, expected_missing_area(&run, 2), 1e-3);
    check_paths_inside(&run, &plan);
    sr_plan_release(&plan);
    free_run(&run);
}

static char *read_text(const tmpdir *d, const char *name)
{
    char path[TMPDIR_PATH_MAX];
    size_t size;
    char *text = (char *)tmpdir_read_file(tmpdir_join(d, name, path), &size);
    assert_non_null(text);
    return text;
}

/* Value of word `letter` (e.g. 'Z') on a G-code line; 0 when absent. */
static int gcode_word(const char *line, char letter, double *out)
{
    for (const char *p = line; *p; p++)
        if (*p == letter && (p == line || p[-1] == ' ')) {
            char *end;
            *out = strtod(p + 1, &end);
            return end != p + 1;
        }
    return 0;
}

/* Length of the move on a G-code line from *at (NaN where not known yet), updating *at
 * with the words it gives; 0 while any coordinate is unknown. */
static double move_length(const char *line, double at[3])
{
    double to[3] = {at[0], at[1], at[2]}, v;
    const char axes[3] = {'X', 'Y', 'Z'};
    for (int i = 0; i < 3; i++)
        if (gcode_word(line, axes[i], &v))
            to[i] = v;
    double len = 0;
    if (isfinite(at[0]) && isfinite(at[1]) && isfinite(at[2]))
        len = sqrt((to[0] - at[0]) * (to[0] - at[0]) + (to[1] - at[1]) * (to[1] - at[1]) +
                   (to[2] - at[2]) * (to[2] - at[2]));
    memcpy(at, to, sizeof to);
    return len;
}

static void export_writes_json_svg_per_layer_and_parsable_gcode(void **state)
{
    sr_run run;
    sr_plan plan;
    tmpdir d;
    char path[TMPDIR_PATH_MAX];
    make_axial_run(&run);
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_int_equal(tmpdir_make(&d), 0);
    sr_plan_machine m;
    sr_plan_machine_init(&m);
    m.feed_mm_min = 450;
    strcpy(m.on_code, "M3 S800");
    assert_int_equal(sr_plan_export(&plan, &m, tmpdir_join(&d, "out", path), NULL), SR_OK);

    struct stat sb;
    for (size_t k = 1; k <= 6; k++) {
        char name[64];
        snprintf(name, sizeof name, "out/layer_%03zu.svg", k);
        assert_int_equal(stat(tmpdir_join(&d, name, path), &sb), 0);
        char *svg = read_text(&d, name);
        assert_non_null(strstr(svg, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
        assert_non_null(strstr(svg, "id=\"region\""));
        assert_non_null(strstr(svg, " mm</text>"));
        assert_non_null(strstr(svg, "</svg>"));
        free(svg);
    }
    assert_int_not_equal(stat(tmpdir_join(&d, "out/layer_007.svg", path), &sb), 0);

    char *json = read_text(&d, "out/plan.json");
    assert_non_null(strstr(json, "\"layer_count\":6"));
    assert_non_null(strstr(json, "\"units\":{\"length\":\"mm\""));
    assert_non_null(strstr(json, "\"kind\":\"ring\""));
    assert_non_null(strstr(json, "\"on_code\":\"M3 S800\""));
    assert_null(strstr(json, "nan"));
    free(json);

    char *gcode = read_text(&d, "out/plan.gcode");
    size_t layer = 0, g1 = 0, g1_in_layer[7] = {0};
    int units = 0, absolute = 0, on = 0;
    double z_layer = NAN, v;
    /* the machine's clock: each move's length at its feed (G0 at the 5000 mm/min rapid
     * rate the plan assumes), counted once the tool's position is known */
    double at[3] = {NAN, NAN, NAN}, minutes = 0;
    for (char *line = strtok(gcode, "\n"); line; line = strtok(NULL, "\n")) {
        if (strncmp(line, "; layer ", 8) == 0) {
            layer++;
            assert_true(layer <= 6);
            assert_int_equal(strtoul(line + 8, NULL, 10), layer);
            const char *z = strstr(line, "z=");
            assert_non_null(z);
            z_layer = strtod(z + 2, NULL);
            assert_near(z_layer, plan.layers[layer - 1].z_top_mm, 1e-5);
        } else if (line[0] == ';') {
            continue;
        } else if (strcmp(line, "G21") == 0) {
            units = 1;
        } else if (strcmp(line, "G90") == 0) {
            absolute = 1;
        } else if (strcmp(line, "M3 S800") == 0) {
            on = 1;
        } else if (strcmp(line, "M5") == 0) {
            on = 0;
        } else if (strncmp(line, "G1 ", 3) == 0) {
            assert_true(units && absolute && on && layer > 0);
            assert_true(gcode_word(line, 'X', &v) && isfinite(v));
            assert_true(gcode_word(line, 'Y', &v) && isfinite(v));
            assert_true(gcode_word(line, 'Z', &v));
            assert_near(v, z_layer, 1e-9);
            assert_true(gcode_word(line, 'F', &v));
            assert_near(v, 450.0, 0);
            minutes += move_length(line, at) / v;
            g1++;
            g1_in_layer[layer]++;
        } else if (strncmp(line, "G0 ", 3) == 0) {
            assert_true(units && absolute && !on); /* travel with deposition off */
            minutes += move_length(line, at) / 5000.0;
        } else {
            assert_string_equal(line, "M2");
        }
    }
    assert_int_equal(layer, 6);
    for (size_t k = 1; k <= 6; k++)
        assert_true(g1_in_layer[k] > 10);
    assert_true(g1 > 60);
    /* the build time written is the time of these moves (to the 5 decimals written) */
    sr_plan timed = plan;
    assert_int_equal(sr_plan_time(&timed, &m, NULL), SR_OK);
    assert_near(timed.feed_mm_min, 450.0, 0);
    assert_near(minutes, timed.build_time_min, 1e-6 * timed.build_time_min);
    assert_true(timed.build_time_min > plan.path_length_mm / 450.0);
    free(gcode);
    char *head = read_text(&d, "out/plan.gcode");
    char want[64];
    snprintf(want, sizeof want, "; build time %.2f min:", timed.build_time_min);
    assert_non_null(strstr(head, want));
    free(head);
    tmpdir_remove(&d);
    sr_plan_release(&plan);
    free_run(&run);
}

/* A zeroed sr_plan_opts is valid: each 0 is its default, the allowance 0 none. */
static void zeroed_opts_plan_with_the_defaults_and_no_allowance(void **state)
{
    sr_run run;
    sr_plan zeroed, init;
    sr_plan_opts o;
    make_axial_run(&run);
    memset(&o, 0, sizeof o);
    assert_int_equal(sr_plan_build(&run, 0, &o, &zeroed, NULL), SR_OK);
    sr_plan_opts_init(&o);
    o.allowance_mm = 0;
    assert_int_equal(sr_plan_build(&run, 0, &o, &init, NULL), SR_OK);
    assert_near(zeroed.opts.step_over_mm, 1.0, 0);
    assert_near(zeroed.opts.allowance_mm, 0, 0);
    assert_near(zeroed.opts.density_g_cm3, 7.85, 0);
    assert_near(zeroed.opts.rate_cm3_min, 1.0, 0);
    assert_near(zeroed.opts.layer_mm, init.opts.layer_mm, 0);
    assert_int_equal(zeroed.layer_count, init.layer_count);
    assert_near(zeroed.deposit_volume_mm3, init.deposit_volume_mm3, 0);
    assert_near(zeroed.deposit_mass_g, init.deposit_mass_g, 0);
    assert_near(zeroed.build_time_min, init.build_time_min, 0);
    sr_plan_release(&zeroed);
    sr_plan_release(&init);
    free_run(&run);
}

static void negative_step_over_refused_naming_field(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_plan_opts o;
    sr_err err = {{0}};
    make_axial_run(&run);
    sr_plan_opts_init(&o);
    o.step_over_mm = -1;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, &err), SR_E_RANGE);
    assert_msg_has(err, "step_over_mm must be > 0");
    free_run(&run);
}

static void negative_allowance_refused_naming_field(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_plan_opts o;
    sr_err err = {{0}};
    make_axial_run(&run);
    sr_plan_opts_init(&o);
    o.allowance_mm = -0.5;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, &err), SR_E_RANGE);
    assert_msg_has(err, "allowance_mm must be >= 0");
    free_run(&run);
}

static void other_bad_options_refused_naming_field(void **state)
{
    sr_plan_opts o;
    sr_err err = {{0}};
    sr_plan_opts_init(&o);
    assert_int_equal(sr_plan_opts_check(&o, &err), SR_OK);
    o.layer_mm = -1;
    assert_int_equal(sr_plan_opts_check(&o, &err), SR_E_RANGE);
    assert_msg_has(err, "layer_mm");
    sr_plan_opts_init(&o);
    o.density_g_cm3 = NAN;
    assert_int_equal(sr_plan_opts_check(&o, &err), SR_E_RANGE);
    assert_msg_has(err, "density_g_cm3");
    sr_plan_opts_init(&o);
    o.rate_cm3_min = -1;
    assert_int_equal(sr_plan_opts_check(&o, &err), SR_E_RANGE);
    assert_msg_has(err, "rate_cm3_min");
    sr_plan_opts_init(&o);
    o.pattern = (sr_plan_pattern)9;
    assert_int_equal(sr_plan_opts_check(&o, &err), SR_E_RANGE);
    assert_msg_has(err, "pattern 9");
    sr_plan_pattern pat;
    assert_int_equal(sr_plan_pattern_parse("raster", "--pattern", &pat, &err), SR_OK);
    assert_int_equal(pat, SR_PLAN_RASTER);
    assert_int_equal(sr_plan_pattern_parse("spiral", "--pattern", &pat, &err), SR_E_RANGE);
    assert_msg_has(err, "--pattern 'spiral'");
}

static void too_thin_layers_refused(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_plan_opts o;
    sr_err err = {{0}};
    make_axial_run(&run);
    sr_plan_opts_init(&o);
    o.layer_mm = 1e-5;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, &err), SR_E_RANGE);
    assert_msg_has(err, "layer_mm 1e-05 gives 600000 layers");
    free_run(&run);
}

static void bad_machine_settings_refused_naming_field(void **state)
{
    sr_plan_machine m;
    sr_err err = {{0}};
    sr_plan_machine_init(&m);
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_OK);
    m.feed_mm_min = 0; /* the rate's feed */
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_OK);
    m.feed_mm_min = -1;
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_E_RANGE);
    assert_msg_has(err, "feed_mm_min");
    sr_plan_machine_init(&m);
    m.rapid_mm_min = 0;
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_E_RANGE);
    assert_msg_has(err, "rapid_mm_min");
    sr_plan_machine_init(&m);
    m.travel_height_mm = -1;
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_E_RANGE);
    assert_msg_has(err, "travel_height_mm");
    sr_plan_machine_init(&m);
    strcpy(m.off_code, "M5; M2");
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_E_RANGE);
    assert_msg_has(err, "off_code 'M5; M2'");
    sr_plan_machine_init(&m);
    m.on_code[0] = 0;
    assert_int_equal(sr_plan_machine_check(&m, &err), SR_E_RANGE);
    assert_msg_has(err, "on_code must be 1..31 characters");
}

/* The advice of a run's section sets the plan's settings: the rule's layer, step-over,
 * allowance and fed rate x efficiency / density; a section without advice takes the
 * whole part's; a process that builds nothing is reported, not followed; a parameter
 * that is not a number is refused naming the rule. */
static void a_plan_follows_the_advice_of_its_section(void **state)
{
    sr_run run;
    make_axial_run(&run);
    sr_run_advice adv[2];
    memset(adv, 0, sizeof adv);
    adv[0].section_index = -1;
    strcpy(adv[0].process, "spray_forming");
    strcpy(adv[0].rule_name, "spray-small-loss");
    adv[0].details_json = (char *)"{\"parameters\":{\"layer_mm\":0.25,\"step_over_mm\":2.0,"
                                  "\"allowance_mm\":0.5,\"deposition_rate_g_min\":30,"
                                  "\"efficiency\":0.6},\"preheat_c\":null}";
    adv[1].section_index = 0;
    strcpy(adv[1].process, "ded");
    strcpy(adv[1].rule_name, "shoulder-ded");
    adv[1].details_json = (char *)"{\"applied\":\"shoulder-ded\",\"parameters\":{\"layer_mm\":0.8,"
                                  "\"step_over_mm\":1.2,\"allowance_mm\":0.8,"
                                  "\"deposition_rate_g_min\":10,\"efficiency\":0.8},"
                                  "\"preheat_c\":250}";
    run.advice = adv;
    run.advice_count = 2;
    sr_plan_opts o;
    sr_plan_opts_init(&o);
    o.density_g_cm3 = 8.0;
    sr_plan_advice a;
    sr_err err = {{0}};
    assert_int_equal(sr_plan_follow_advice(&run, 0, &o, &a, &err), SR_OK);
    assert_true(a.found && a.builds);
    assert_string_equal(a.process, "ded");
    assert_string_equal(a.rule, "shoulder-ded");
    assert_int_equal(a.taken, SR_PLAN_FROM_LAYER | SR_PLAN_FROM_STEP_OVER | SR_PLAN_FROM_ALLOWANCE |
                                  SR_PLAN_FROM_RATE);
    assert_near(o.layer_mm, 0.8, 0);
    assert_near(o.step_over_mm, 1.2, 0);
    assert_near(o.allowance_mm, 0.8, 0);
    assert_near(o.rate_cm3_min, 10 * 0.8 / 8.0, 1e-15);
    assert_near(a.preheat_c, 250, 0);
    /* the plan built with them: 0.8 mm layers over the 6 mm slab, the feed laying 1
     * cm3/min down as 1.2 x 0.8 mm beads */
    sr_plan plan;
    assert_int_equal(sr_plan_build(&run, 0, &o, &plan, &err), SR_OK);
    assert_int_equal(plan.layer_count, 8);
    assert_near(plan.feed_mm_min, 1000.0 / (1.2 * 0.8), 1e-9);
    sr_plan_release(&plan);

    /* no advice for section 1 (0-based): the whole part's */
    run.sections[0].index = 1;
    sr_plan_opts_init(&o);
    assert_int_equal(sr_plan_follow_advice(&run, 1, &o, &a, &err), SR_OK);
    assert_string_equal(a.rule, "spray-small-loss");
    assert_near(o.layer_mm, 0.25, 0);
    assert_near(o.rate_cm3_min, 30 * 0.6 / 7.85, 1e-15);
    assert_true(isnan(a.preheat_c));
    run.sections[0].index = 0;

    /* replace: found, builds nothing, settings untouched */
    strcpy(adv[1].process, "replace");
    sr_plan_opts_init(&o);
    sr_plan_opts before = o;
    assert_int_equal(sr_plan_follow_advice(&run, 0, &o, &a, &err), SR_OK);
    assert_true(a.found && !a.builds);
    assert_int_equal(a.taken, 0);
    assert_memory_equal(&o, &before, sizeof o);

    /* a rule edited into nonsense */
    strcpy(adv[1].process, "ded");
    adv[1].details_json = (char *)"{\"parameters\":{\"layer_mm\":\"thick\"}}";
    assert_int_equal(sr_plan_follow_advice(&run, 0, &o, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "rule 'shoulder-ded' gives layer_mm that is not a number");
    adv[1].details_json = (char *)"{\"parameters\":{\"step_over_mm\":-2}}";
    assert_int_equal(sr_plan_follow_advice(&run, 0, &o, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "step_over_mm -2");
    adv[1].details_json = (char *)"{\"parameters\":{\"efficiency\":1.5,"
                                  "\"deposition_rate_g_min\":10}}";
    assert_int_equal(sr_plan_follow_advice(&run, 0, &o, &a, &err), SR_E_RANGE);
    assert_msg_has(err, "efficiency 1.5");
    run.advice = NULL;
    run.advice_count = 0;
    free_run(&run);
}

static void unknown_section_refused(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_err err = {{0}};
    make_axial_run(&run);
    assert_int_equal(sr_plan_build(&run, 3, NULL, &plan, &err), SR_E_NOTFOUND);
    assert_msg_has(err, "run 42 has no section 4");
    free_run(&run);
}

static void run_without_layers_refused(void **state)
{
    sr_run run;
    sr_plan plan;
    sr_err err = {{0}};
    make_axial_run(&run);
    size_t saved = run.layer_count;
    run.layer_count = 0;
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, &err), SR_E_INVALID);
    assert_msg_has(err, "run 42 has no layer polylines");
    run.layer_count = saved;
    run.sections[0].layer_last = 12;
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, &err), SR_E_INVALID);
    assert_msg_has(err, "covers layers 2..12 but the run has 10 layers");
    free_run(&run);
}

static void export_into_a_file_path_refused(void **state)
{
    sr_run run;
    sr_plan plan;
    tmpdir d;
    char path[TMPDIR_PATH_MAX];
    sr_err err = {{0}};
    make_axial_run(&run);
    assert_int_equal(sr_plan_build(&run, 0, NULL, &plan, NULL), SR_OK);
    assert_int_equal(tmpdir_make(&d), 0);
    assert_int_equal(tmpdir_write_text(tmpdir_join(&d, "file", path), "x"), 0);
    assert_int_equal(sr_plan_export(&plan, NULL, path, &err), SR_E_IO);
    assert_msg_has(err, "not a directory");
    assert_int_equal(sr_plan_export(&plan, NULL, tmpdir_join(&d, "no/such", path), &err),
                     SR_E_IO);
    assert_msg_has(err, "cannot create");
    tmpdir_remove(&d);
    sr_plan_release(&plan);
    free_run(&run);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(axial_chip_plan_has_section_layers_and_exact_areas),
        cmocka_unit_test(axial_plan_stays_in_the_sections_wedge),
        cmocka_unit_test(thicker_and_thinner_layers_resample_by_union),
        cmocka_unit_test(planar_notch_plan_uses_the_sections_side),
        cmocka_unit_test(contour_pattern_gives_closed_rings_only),
        cmocka_unit_test(sector_without_damaged_point_is_bridged),
        cmocka_unit_test(export_writes_json_svg_per_layer_and_parsable_gcode),
        cmocka_unit_test(a_plan_follows_the_advice_of_its_section),
        cmocka_unit_test(zeroed_opts_plan_with_the_defaults_and_no_allowance),
        cmocka_unit_test(negative_step_over_refused_naming_field),
        cmocka_unit_test(negative_allowance_refused_naming_field),
        cmocka_unit_test(other_bad_options_refused_naming_field),
        cmocka_unit_test(too_thin_layers_refused),
        cmocka_unit_test(bad_machine_settings_refused_naming_field),
        cmocka_unit_test(unknown_section_refused),
        cmocka_unit_test(run_without_layers_refused),
        cmocka_unit_test(export_into_a_file_path_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
