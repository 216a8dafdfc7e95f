/*
 * test_nominal.c: the nominal's second opinion (src/nominal.c) and its run record
 * (src/run/run_nominal.c). Known answers: an L-shaped bar (no proper symmetry, so the
 * registration has one answer) with its long leg's end cut off (15 x 12 x 15 mm =
 * 2700 mm³), turned and moved, gives back the cut as the nominal's missing volume and
 * agrees with a section whose patch is the cut; a section elsewhere is one only the
 * symmetry sees; the intact bar against itself has nothing missing; a different part
 * (a cylinder) as the nominal is flagged, not believed; a scan that is not closed is
 * refused naming it; a bad reference is refused. Started from the bar's mirror
 * alignment the registration needs no search; a scan crossing itself (a box through
 * one face) is measured by cells and still gives the cut.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "bridge/boolean.h"
#include "mesh/shapes.h"
#include "nominal.h"
#include "run/run_build.h"
#include "support/assert_near.h"

/* An L: 60 x 40 outline, 12 mm legs, 15 mm thick. */
static void l_bar(sr_mesh *out)
{
    const double xy[] = {0, 0, 60, 0, 60, 12, 12, 12, 12, 40, 0, 40};
    assert_int_equal(sr_shape_prism(xy, 6, 0, 15, out, NULL), SR_OK);
}

/* The pose of the scan: 40 degrees about z, then 25 about x, then moved. */
static void pose(double m[12])
{
    double a = 40 * M_PI / 180, b = 25 * M_PI / 180;
    double rz[9] = {cos(a), -sin(a), 0, sin(a), cos(a), 0, 0, 0, 1};
    double rx[9] = {1, 0, 0, 0, cos(b), -sin(b), 0, sin(b), cos(b)};
    const double t[3] = {120, -35, 60};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 3; k++)
                s += rx[3 * i + k] * rz[3 * k + j];
            m[4 * i + j] = s;
        }
        m[4 * i + 3] = t[i];
    }
}

/* *scan = the bar less the end of its long leg, posed; *cut = that end, posed. */
static void cut_bar(sr_mesh *scan, sr_mesh *cut)
{
    sr_mesh bar, box;
    l_bar(&bar);
    const double lo[3] = {45, -5, -5}, hi[3] = {70, 20, 20};
    assert_int_equal(sr_shape_box(lo, hi, &box, NULL), SR_OK);
    sr_err err = {{0}};
    assert_int_equal(
        sr_boolean_compute(SR_BOOLEAN_DIFFERENCE, &bar, "bar", &box, "box", scan, &err), SR_OK);
    assert_int_equal(
        sr_boolean_compute(SR_BOOLEAN_INTERSECTION, &bar, "bar", &box, "box", cut, &err), SR_OK);
    double m[12];
    pose(m);
    sr_mesh_transform(scan, m);
    sr_mesh_transform(cut, m);
    sr_mesh_release(&bar);
    sr_mesh_release(&box);
}

/* *out = the box [lo, hi], posed as the scan. */
static void posed_box(const double lo[3], const double hi[3], sr_mesh *out)
{
    assert_int_equal(sr_shape_box(lo, hi, out, NULL), SR_OK);
    double m[12];
    pose(m);
    sr_mesh_transform(out, m);
}

static void the_cut_comes_back_and_agrees_with_its_section(void **state)
{
    (void)state;
    sr_mesh scan, cut, bar, far;
    cut_bar(&scan, &cut);
    l_bar(&bar);
    /* section 1: the cut, as the symmetry would find it, 100 mm³ short; section 2: a
     * box far from any damage (only the symmetry sees it) */
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2};
    posed_box(lo, hi, &far);
    sr_section secs[2];
    memset(secs, 0, sizeof secs);
    secs[0].patch = cut;
    secs[0].volume_mm3 = 2600;
    secs[1].patch = far;
    secs[1].volume_mm3 = 8;
    sr_nominal_result r;
    sr_err err = {{0}};
    sr_nominal_opts exact = {0};
    exact.exact_pieces = 1;
    assert_int_equal(sr_nominal_compare(&scan, &bar, secs, 2, &exact, &r, &err), SR_OK);
    assert_int_equal(r.by_cells, 0);
    assert_true(r.missing.tri_count > 0);
    assert_near(r.nominal_mm3, 2700, 2700 * 1e-4);
    assert_int_equal(r.piece_count, 1);
    assert_int_equal(r.pieces[0].section, 0);
    assert_false(r.poor);
    assert_int_equal(r.full_search, 1); /* no alignment given */
    assert_true(r.reg.coverage > 0.75 && r.reg.coverage < 0.99);
    assert_int_equal(r.section_count, 2);
    assert_near(r.sections[0].nominal_mm3, 2700, 0.3);
    assert_near(r.sections[0].diff_mm3, 100, 0.3);
    assert_near(r.sections[0].diff_pct, 100.0 * 100 / 2700, 0.01);
    assert_true(r.sections[0].dev_mean_mm < 1e-3 && r.sections[0].dev_max_mm < 1e-3);
    assert_int_equal(r.sections[1].pieces, 0);
    assert_true(r.sections[1].dev_max_mm < 0);
    assert_int_equal(r.only_symmetry, 1);
    assert_int_equal(r.only_nominal, 0);
    assert_near(r.symmetry_mm3, 2608, 1e-9);
    assert_true(r.extra_mm3 < 1);

    /* the record keeps the figures and the piece's box */
    sr_run_nominal *rec = NULL;
    assert_int_equal(sr_run_nominal_from(&r, "symmetry", &rec, &err), SR_OK);
    assert_string_equal(rec->reference, "symmetry");
    assert_int_equal(rec->section_count, 2);
    assert_int_equal(rec->piece_count, 1);
    assert_near(rec->nominal_mm3, r.nominal_mm3, 0);
    assert_near(rec->sections[0].diff_mm3, r.sections[0].diff_mm3, 0);
    assert_int_equal(rec->pieces[0].section, 0);
    assert_near(rec->pieces[0].outside_mm3, 0, 0.3);
    double m2[12], centre[3], want[3] = {52.5, 6, 7.5}; /* the cut's centre, posed */
    pose(m2);
    sr_xform_apply(m2, want, centre);
    for (int k = 0; k < 3; k++)
        assert_near(rec->pieces[0].centroid[k], centre[k], 1e-2);
    sr_run_nominal_free(rec);
    sr_nominal_result_release(&r);
    sr_nominal_result_release(&r); /* a released result releases again */
    sr_mesh_release(&scan);
    sr_mesh_release(&cut);
    sr_mesh_release(&bar);
    sr_mesh_release(&far);
}

static void without_sections_the_cut_is_only_the_nominals(void **state)
{
    (void)state;
    sr_mesh scan, cut, bar;
    cut_bar(&scan, &cut);
    l_bar(&bar);
    sr_nominal_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_nominal_compare(&scan, &bar, NULL, 0, NULL, &r, &err), SR_OK);
    assert_int_equal(r.by_cells, 1); /* the default measure */
    assert_near(r.nominal_mm3, 2700, 2700 * 1e-4);
    assert_int_equal(r.only_nominal, 1);
    assert_near(r.only_nominal_mm3, 2700, 0.3);
    assert_int_equal(r.pieces[0].section, -1);
    assert_near(r.diff_pct, 100, 1e-9);
    sr_nominal_result_release(&r);
    sr_mesh_release(&scan);
    sr_mesh_release(&cut);
    sr_mesh_release(&bar);
}

static void an_intact_scan_misses_nothing(void **state)
{
    (void)state;
    sr_mesh bar, scan;
    l_bar(&bar);
    l_bar(&scan);
    double m[12];
    pose(m);
    sr_mesh_transform(&scan, m);
    sr_nominal_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_nominal_compare(&scan, &bar, NULL, 0, NULL, &r, &err), SR_OK);
    assert_int_equal(r.piece_count, 0);
    assert_near(r.nominal_mm3, 0, 0);
    assert_true(r.reg.coverage > 0.999);
    assert_false(r.poor);
    sr_nominal_result_release(&r);
    sr_mesh_release(&bar);
    sr_mesh_release(&scan);
}

/* The catalogue holds the wrong part's mesh: a cylinder as the bar's nominal. */
static void a_different_part_as_the_nominal_is_flagged(void **state)
{
    (void)state;
    sr_mesh scan, cut, cyl;
    cut_bar(&scan, &cut);
    assert_int_equal(sr_shape_cylinder(20, 0, 15, 64, &cyl, NULL), SR_OK);
    sr_section sec;
    memset(&sec, 0, sizeof sec);
    sec.patch = cut;
    sec.volume_mm3 = 2700;
    sr_nominal_result r;
    sr_err err = {{0}};
    assert_int_equal(sr_nominal_compare(&scan, &cyl, &sec, 1, NULL, &r, &err), SR_OK);
    assert_true(r.poor);
    assert_non_null(strstr(r.note, "does not fit this scan"));
    /* and the disagreement is large, not silently small */
    assert_true(r.extra_mm3 > r.extra_limit_mm3 || r.reg.coverage < SR_NOMINAL_MIN_COVERAGE);
    assert_true(fabs(r.diff_pct) > 20);
    sr_nominal_result_release(&r);
    sr_mesh_release(&scan);
    sr_mesh_release(&cut);
    sr_mesh_release(&cyl);
}

static void a_scan_that_is_not_closed_is_refused(void **state)
{
    (void)state;
    sr_mesh scan, cut, bar;
    cut_bar(&scan, &cut);
    l_bar(&bar);
    scan.tri_count--; /* one triangle gone: a hole */
    sr_nominal_result r;
    memset(&r, 0x5a, sizeof r);
    sr_nominal_result before = r;
    sr_err err = {{0}};
    assert_int_equal(sr_nominal_compare(&scan, &bar, NULL, 0, NULL, &r, &err), SR_E_INVALID);
    assert_msg_has(err, "the scan");
    assert_memory_equal(&r, &before, sizeof r); /* *out untouched */
    sr_mesh_release(&scan);
    sr_mesh_release(&cut);
    sr_mesh_release(&bar);
}

/* The registration starts from the scan's symmetry alignment (the bar is a mirror about
 * its mid-plane z = 7.5): no search of the principal frames, the same answer. */
static void from_the_symmetry_alignment_no_search_runs(void **state)
{
    (void)state;
    sr_mesh scan, cut, bar;
    cut_bar(&scan, &cut);
    l_bar(&bar);
    sr_symmetry mirror = {SR_SYM_MIRROR, 0, 0};
    sr_alignment al;
    sr_err err = {{0}};
    assert_int_equal(sr_align(&scan, &mirror, NULL, &al, &err), SR_OK);
    sr_nominal_opts o = {0};
    o.alignment = &al;
    sr_nominal_result r;
    assert_int_equal(sr_nominal_compare(&scan, &bar, NULL, 0, &o, &r, &err), SR_OK);
    assert_int_equal(r.full_search, 0);
    assert_near(r.nominal_mm3, 2700, 2700 * 1e-4);
    assert_true(r.reg.coverage > 0.75 && r.reg.coverage < 0.99);
    assert_int_equal(r.by_cells, 1);
    sr_nominal_result_release(&r);
    /* a wrong part's start does not hold: the full search runs, and it is flagged */
    sr_mesh cyl;
    assert_int_equal(sr_shape_cylinder(20, 0, 15, 64, &cyl, NULL), SR_OK);
    assert_int_equal(sr_nominal_compare(&scan, &cyl, NULL, 0, &o, &r, &err), SR_OK);
    assert_int_equal(r.full_search, 1);
    assert_true(r.poor);
    sr_nominal_result_release(&r);
    sr_mesh_release(&cyl);
    sr_mesh_release(&scan);
    sr_mesh_release(&cut);
    sr_mesh_release(&bar);
}

/* A scan that crosses itself (a 4 x 4 x 6 mm box through the short leg's top face, as
 * a noise fold): the exact difference, asked for, refuses it; the cells measure the
 * cut. */
static void a_scan_crossing_itself_is_measured_by_cells(void **state)
{
    (void)state;
    sr_mesh scan, cut, bar, fold;
    cut_bar(&scan, &cut);
    l_bar(&bar);
    const double lo[3] = {2, 30, 12}, hi[3] = {6, 34, 18};
    posed_box(lo, hi, &fold);
    assert_int_equal(sr_mesh_append(&scan, &fold), SR_OK);
    sr_section sec;
    memset(&sec, 0, sizeof sec);
    sec.patch = cut;
    sec.volume_mm3 = 2700;
    sr_nominal_result r;
    sr_err err = {{0}};
    sr_nominal_opts exact = {0};
    exact.exact_pieces = 1;
    assert_int_equal(sr_nominal_compare(&scan, &bar, &sec, 1, &exact, &r, &err), SR_OK);
    assert_int_equal(r.by_cells, 1);
    assert_non_null(strstr(r.exact_note, "intersects itself"));
    assert_near(r.nominal_mm3, 2700, 2700 * 0.001);
    assert_int_equal(r.piece_count, 1);
    assert_int_equal(r.pieces[0].section, 0);
    assert_near(r.sections[0].nominal_mm3, 2700, 2700 * 0.001);
    assert_true(r.sections[0].dev_mean_mm >= 0 && r.sections[0].dev_mean_mm < 0.05);
    assert_int_equal(r.missing.tri_count, 0);
    assert_near(r.extra_mm3, 96, 96 * 0.05); /* the fold's box: counted twice inside */
    assert_false(r.poor);
    sr_nominal_result_release(&r);
    sr_mesh_release(&scan);
    sr_mesh_release(&cut);
    sr_mesh_release(&bar);
    sr_mesh_release(&fold);
}

static void a_bad_reference_is_refused(void **state)
{
    (void)state;
    sr_nominal_result r;
    memset(&r, 0, sizeof r);
    sr_run_nominal *rec = NULL;
    sr_err err = {{0}};
    assert_int_equal(sr_run_nominal_from(&r, "cad", &rec, &err), SR_E_RANGE);
    assert_null(rec);
    assert_msg_has(err, "bad reference 'cad'");
    sr_run_nominal_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_cut_comes_back_and_agrees_with_its_section),
        cmocka_unit_test(without_sections_the_cut_is_only_the_nominals),
        cmocka_unit_test(an_intact_scan_misses_nothing),
        cmocka_unit_test(a_different_part_as_the_nominal_is_flagged),
        cmocka_unit_test(a_scan_that_is_not_closed_is_refused),
        cmocka_unit_test(from_the_symmetry_alignment_no_search_runs),
        cmocka_unit_test(a_scan_crossing_itself_is_measured_by_cells),
        cmocka_unit_test(a_bad_reference_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
