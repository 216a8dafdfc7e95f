/*
 * test_features.c: the feature-level description of missing sections
 * (src/advice/section_features.h) on run records built inline (tests/support/synth_run.h): a
 * shaft of radius 20 stepping to 30 at z = 50, 100 layers 1 mm apart, 72 sectors of
 * 5 degrees, with chips, bands, deep losses and narrow losses dug out at known places.
 * Each class, location and figure is checked against what the geometry makes exact.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "advice/section_features.h"
#include "support/assert_near.h"
#include "support/json_query.h"
#include "support/synth_run.h"

#define PI 3.14159265358979323846
#define SECTOR_RAD (5.0 * PI / 180.0)

static void shaft(sr_run *run)
{
    synth_run_make(run, 100, 72, 20.0, 30.0, 50.0);
}

static sr_features describe_one(const sr_run *run, size_t i, double part_volume)
{
    sr_feature_part part = {part_volume, 0};
    sr_features f;
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_features_compute(run, i, &part, &f, &err);
    if (st != SR_OK)
        fail_msg("sr_features_compute: %s", err.msg);
    assert_true(f.reason_count > 0);
    return f;
}

static bool has_reason(const sr_features *f, const char *text)
{
    for (size_t i = 0; i < f->reason_count; i++)
        if (strstr(f->reasons[i], text))
            return true;
    return false;
}

static void chip_at_the_shoulder_is_a_chip_with_its_exact_range(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    /* 30 degrees (6 sectors from 45 deg) x 5 layers (z 45..50), 2 mm deep, just below
     * the step at z = 50. */
    synth_run_dig(&run, 45, 49, 9, 6, 2.0, 0);
    sr_features f = describe_one(&run, 0, 0);
    assert_string_equal(f.damage_class, "chip");
    assert_true(f.axial);
    assert_near(f.angle_min_deg, 45.0, 1e-12);
    assert_near(f.angle_max_deg, 75.0, 1e-12);
    assert_near(f.arc_deg, 30.0, 1e-12);
    assert_int_equal(f.layer_count, 5);
    assert_near(f.z_min_mm, 45.0, 0);
    assert_near(f.z_max_mm, 50.0, 0);
    assert_near(f.depth_max_mm, 2.0, 1e-12);
    assert_int_equal(f.cell_count, 30);
    assert_near(f.local_radius_mm, 20.0, 1e-9);
    assert_near(f.depth_fraction, 0.1, 1e-9);
    assert_near(f.circ_width_mm, 6 * SECTOR_RAD * 20.0, 1e-9);
    assert_near(f.axial_width_mm, 5.0, 1e-9);
    assert_near(f.width_mm, 5.0, 1e-9);
    assert_near(f.coverage, 6.0 / 72.0, 1e-12);
    /* one layer: 6 of 72 wedges lose (20^2 - 18^2) of their 20^2 */
    assert_near(f.layer_loss_max, 6.0 * (400.0 - 324.0) / (72.0 * 400.0), 1e-12);
    assert_true(sr_features_at(&f, "shoulder"));
    assert_string_equal(f.locations[0], "shoulder");
    assert_near(f.shoulder_z_mm, 50.0, 1e-12);
    assert_true(has_reason(&f, "chip"));
    assert_true(has_reason(&f, "shoulder"));
    synth_run_free(&run);
}

static void chip_on_a_plain_stretch_is_on_the_body(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    sr_features f = describe_one(&run, 0, 0);
    assert_string_equal(f.damage_class, "chip");
    assert_false(sr_features_at(&f, "shoulder"));
    assert_int_equal(f.location_count, 1);
    assert_string_equal(f.locations[0], "body");
    assert_true(isnan(f.shoulder_z_mm));
    synth_run_free(&run);
}

static void chip_reaching_the_first_layer_is_at_the_end_face(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 0, 4, 30, 6, 2.0, 0);
    sr_features f = describe_one(&run, 0, 0);
    assert_true(sr_features_at(&f, "end_face"));
    assert_false(sr_features_at(&f, "body"));
    synth_run_free(&run);
}

static void range_across_zero_degrees_wraps(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 24, 69, 6, 2.0, 0);   /* 345 .. 375 (= 15) */
    assert_near(run.sections[0].angle_to_deg, 15.0, 1e-12);
    sr_features f = describe_one(&run, 0, 0);
    assert_near(f.angle_min_deg, 345.0, 1e-12);
    assert_near(f.angle_max_deg, 375.0, 1e-12);
    assert_near(f.arc_deg, 30.0, 1e-12);
    assert_int_equal(f.cell_count, 30);
    assert_string_equal(f.damage_class, "chip");
    synth_run_free(&run);
}

static void shallow_band_all_round_is_a_wear_band(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 29, 0, 72, 0.5, 0);
    run.sections[0].angle_from_deg = 0;
    run.sections[0].angle_to_deg = 360;
    sr_features f = describe_one(&run, 0, 0);
    assert_string_equal(f.damage_class, "wear_band");
    assert_near(f.coverage, 1.0, 0);
    assert_near(f.arc_deg, 360.0, 0);
    assert_near(f.depth_fraction, 0.025, 1e-12);
    assert_true(has_reason(&f, "wear band"));
    synth_run_free(&run);
}

static void deep_loss_is_a_broken_feature(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 10, 29, 0, 18, 12.0, 0);   /* 90 deg, 12 of 20 mm deep */
    sr_features f = describe_one(&run, 0, 0);
    assert_string_equal(f.damage_class, "broken_feature");
    assert_near(f.depth_fraction, 0.6, 1e-12);
    assert_true(has_reason(&f, "of the local radius"));
    synth_run_free(&run);
}

static void large_fraction_of_the_cross_section_is_a_broken_feature(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    /* half the circumference, 6 mm (30 % of the radius) deep: not deep enough by depth,
     * but each layer loses 36 * (400 - 196) / (72 * 400) = 25.5 % of its area */
    synth_run_dig(&run, 10, 19, 0, 36, 6.0, 0);
    sr_features f = describe_one(&run, 0, 0);
    assert_near(f.layer_loss_max, 36.0 * 204.0 / (72.0 * 400.0), 1e-12);
    assert_string_equal(f.damage_class, "broken_feature");
    assert_true(has_reason(&f, "of its cross-section"));
    synth_run_free(&run);
}

static void narrow_deep_loss_is_a_crack(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 10, 29, 20, 1, 8.0, 0);    /* one 5-degree sector, 8 mm deep */
    sr_features f = describe_one(&run, 0, 0);
    assert_near(f.width_mm, SECTOR_RAD * 20.0, 1e-9);
    assert_near(f.wall_a, 1.0, 0);    /* the shaft on both sides */
    assert_near(f.wall_b, 1.0, 0);
    assert_string_equal(f.damage_class, "crack");
    assert_true(has_reason(&f, "crack"));
    synth_run_free(&run);
}

/* Turns the shaft's shoulder into a rim 5 mm thick (z 50..55, radius 30; radius 20 above). */
static void thin_rim(sr_run *run)
{
    for (size_t l = 55; l < run->layer_count; l++) {
        for (size_t j = 0; j < run->sectors; j++) {
            double *p = run->restored_xy + 2 * (l * run->sectors + j);
            double *d = run->damaged_xy + 2 * (l * run->sectors + j);
            p[0] *= 20.0 / 30.0;
            p[1] *= 20.0 / 30.0;
            d[0] = p[0];
            d[1] = p[1];
        }
    }
}

static void loss_through_a_thin_rim_is_a_broken_feature(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    thin_rim(&run);
    /* 60 deg of the rim, 8 mm deep (27 % of its radius), its whole 5 mm thickness */
    synth_run_dig(&run, 50, 54, 0, 12, 8.0, 0);
    sr_features f = describe_one(&run, 0, 0);
    assert_near(f.width_mm, 5.0, 1e-9);
    assert_near(f.wall_a, 20.0 / 30.0, 1e-9);   /* below: the radius-20 body */
    assert_near(f.wall_b, 20.0 / 30.0, 1e-9);   /* above: the radius-20 journal */
    assert_string_equal(f.damage_class, "broken_feature");
    assert_true(has_reason(&f, "through the feature"));
    synth_run_free(&run);
}

static void shallow_nick_in_a_thin_rim_is_not_broken(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    thin_rim(&run);
    synth_run_dig(&run, 50, 54, 0, 4, 2.0, 0);   /* 2 mm deep: less than the 5 mm rim */
    sr_features f = describe_one(&run, 0, 0);
    assert_string_equal(f.damage_class, "chip");
    synth_run_free(&run);
}

static void long_narrow_shallow_loss_is_a_gouge(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 30, 31, 0, 12, 1.0, 0);    /* 60 deg x 2 layers, 1 mm deep */
    sr_features f = describe_one(&run, 0, 0);
    assert_near(f.length_mm, 12 * SECTOR_RAD * 20.0, 1e-9);
    assert_near(f.width_mm, 2.0, 1e-9);
    assert_string_equal(f.damage_class, "gouge");
    synth_run_free(&run);
}

static void part_fraction_needs_the_part_volume(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    sr_run_section *s = synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    double vol = s->volume_mm3;
    sr_features f = describe_one(&run, 0, 1000.0 * vol);
    assert_near(f.part_fraction, 0.001, 1e-15);
    f = describe_one(&run, 0, 0);
    assert_true(isnan(f.part_fraction));
    assert_true(has_reason(&f, "part volume unknown"));
    double v;
    assert_false(sr_features_value(&f, "part_fraction", &v));
    synth_run_free(&run);
}

static void planar_sections_are_ear_or_edge_by_their_distance_from_the_plane(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    run.symmetry.kind = SR_SYM_MIRROR;
    /* Around 0 deg (x up to 20: the far end from the plane x = 0) and around 80 deg
     * (x about 3.5 of 20: next to the plane), both on side +1. */
    synth_run_dig(&run, 20, 24, 70, 4, 2.0, +1);
    synth_run_dig(&run, 30, 34, 15, 2, 2.0, +1);
    sr_features ear = describe_one(&run, 0, 0);
    sr_features edge = describe_one(&run, 1, 0);
    assert_false(ear.axial);
    assert_int_equal(ear.side, 1);
    assert_true(sr_features_at(&ear, "ear"));
    assert_near(ear.extent_max_mm, 20.0 * cos(2.5 * PI / 180.0), 1e-9);
    assert_near(ear.coverage, 4.0 / 36.0, 1e-12);
    assert_true(sr_features_at(&edge, "edge"));
    assert_near(edge.extent_max_mm, 20.0 * cos(77.5 * PI / 180.0), 1e-9);
    double v;
    assert_false(sr_features_value(&ear, "arc_deg", &v));   /* planar: no angles */
    assert_true(sr_features_value(&ear, "side", &v));
    assert_near(v, 1.0, 0);
    synth_run_free(&run);
}

static void json_carries_the_figures_and_reasons(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 45, 49, 9, 6, 2.0, 0);
    sr_features f = describe_one(&run, 0, 0);
    char *json;
    assert_int_equal(sr_features_to_json(&f, &json, NULL), SR_OK);
    assert_true(jq_valid(json));
    char *cls = jq_text(json, "$.class");
    assert_string_equal(cls, "chip");
    free(cls);
    char *loc = jq_text(json, "$.location");
    assert_string_equal(loc, "shoulder");
    free(loc);
    assert_near(jq_num(json, "$.angle_min_deg"), 45.0, 0);
    assert_near(jq_num(json, "$.angle_max_deg"), 75.0, 0);
    assert_near(jq_num(json, "$.z_min_mm"), 45.0, 0);
    assert_near(jq_num(json, "$.depth_max_mm"), 2.0, 1e-12);
    assert_near(jq_num(json, "$.layers.count"), 5, 0);
    assert_true(isnan(jq_num(json, "$.part_fraction")));   /* null: unknown */
    assert_true(jq_len(json, "$.reasons") >= 1);
    assert_true(jq_has(json, "$.locations", "shoulder"));
    free(json);
    synth_run_free(&run);
}

static void describe_fills_every_section_and_is_deterministic(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    synth_run_dig(&run, 10, 29, 40, 1, 8.0, 0);
    sr_feature_part part = {200000.0, 0};
    assert_int_equal(sr_features_describe(&run, &part, NULL), SR_OK);
    assert_string_equal(run.sections[0].damage_class, "chip");
    assert_string_equal(run.sections[1].damage_class, "crack");
    char *first = strdup(run.sections[1].features_json);
    assert_int_equal(sr_features_describe(&run, &part, NULL), SR_OK);  /* replaces, no leak */
    assert_string_equal(first, run.sections[1].features_json);
    free(first);
    synth_run_free(&run);
}

static void without_outlines_widths_come_from_the_range(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    free(run.damaged_xy);
    run.damaged_xy = NULL;
    sr_feature_part part = {0, 20.0};
    sr_features f;
    assert_int_equal(sr_features_compute(&run, 0, &part, &f, NULL), SR_OK);
    assert_false(f.have_cells);
    assert_near(f.circ_width_mm, 30.0 * PI / 180.0 * 20.0, 1e-9);
    assert_near(f.depth_fraction, 0.1, 1e-12);
    assert_true(isnan(f.layer_loss_max));
    assert_true(has_reason(&f, "no per-layer outlines"));
    assert_string_equal(f.damage_class, "chip");
    synth_run_free(&run);
}

static void section_index_out_of_range_is_refused(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    sr_features f;
    sr_err err;
    assert_int_equal(sr_features_compute(&run, 0, NULL, &f, &err), SR_E_RANGE);
    assert_msg_has(err, "no section 0");
    synth_run_free(&run);
}

static void section_beyond_the_layers_is_refused_and_nothing_changes(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    synth_run_dig(&run, 20, 24, 30, 6, 2.0, 0);
    run.sections[1].layer_last = 100;
    sr_err err;
    assert_int_equal(sr_features_describe(&run, NULL, &err), SR_E_RANGE);
    assert_msg_has(err, "section 1: layer 100 beyond the run's 100 layers");
    assert_null(run.sections[0].features_json);      /* all or nothing */
    assert_string_equal(run.sections[0].damage_class, "unclassified");
    synth_run_free(&run);
}

static void inverted_layer_range_is_refused(void **state)
{
    (void)state;
    sr_run run;
    shaft(&run);
    synth_run_dig(&run, 20, 24, 9, 6, 2.0, 0);
    run.sections[0].layer_first = 30;
    sr_features f;
    sr_err err;
    assert_int_equal(sr_features_compute(&run, 0, NULL, &f, &err), SR_E_RANGE);
    assert_msg_has(err, "layer_last 24 < layer_first 30");
    synth_run_free(&run);
}

static void figures_are_known_by_name(void **state)
{
    (void)state;
    assert_true(sr_features_is_figure("depth_max_mm"));
    assert_true(sr_features_is_figure("arc_deg"));
    assert_true(sr_features_is_figure("layer_count"));
    assert_false(sr_features_is_figure("depth"));
    assert_false(sr_features_is_figure(""));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(chip_at_the_shoulder_is_a_chip_with_its_exact_range),
        cmocka_unit_test(chip_on_a_plain_stretch_is_on_the_body),
        cmocka_unit_test(chip_reaching_the_first_layer_is_at_the_end_face),
        cmocka_unit_test(range_across_zero_degrees_wraps),
        cmocka_unit_test(shallow_band_all_round_is_a_wear_band),
        cmocka_unit_test(deep_loss_is_a_broken_feature),
        cmocka_unit_test(large_fraction_of_the_cross_section_is_a_broken_feature),
        cmocka_unit_test(narrow_deep_loss_is_a_crack),
        cmocka_unit_test(long_narrow_shallow_loss_is_a_gouge),
        cmocka_unit_test(loss_through_a_thin_rim_is_a_broken_feature),
        cmocka_unit_test(shallow_nick_in_a_thin_rim_is_not_broken),
        cmocka_unit_test(part_fraction_needs_the_part_volume),
        cmocka_unit_test(planar_sections_are_ear_or_edge_by_their_distance_from_the_plane),
        cmocka_unit_test(json_carries_the_figures_and_reasons),
        cmocka_unit_test(describe_fills_every_section_and_is_deterministic),
        cmocka_unit_test(without_outlines_widths_come_from_the_range),
        cmocka_unit_test(section_index_out_of_range_is_refused),
        cmocka_unit_test(section_beyond_the_layers_is_refused_and_nothing_changes),
        cmocka_unit_test(inverted_layer_range_is_refused),
        cmocka_unit_test(figures_are_known_by_name),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
