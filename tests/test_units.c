/*
 * test_units.c: the length units of mesh files (src/mesh/units.h): names parsed
 * exactly, factors to mm, and which sizes look like a part drawn in another unit.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "mesh/units.h"
#include "support/test_select.h"

static void names_parse_exactly_and_nothing_else(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        sr_unit unit;
        double mm;
    } known[] = {{"mm", SR_UNIT_MM, 1},
                 {"cm", SR_UNIT_CM, 10},
                 {"m", SR_UNIT_M, 1000},
                 {"in", SR_UNIT_IN, 25.4}};
    for (size_t i = 0; i < 4; i++) {
        sr_unit u = SR_UNIT_DEFAULT;
        assert_true(sr_unit_parse(known[i].name, &u));
        assert_int_equal(u, known[i].unit);
        assert_string_equal(sr_unit_name(u), known[i].name);
        assert_true(sr_unit_mm(u) == known[i].mm);
    }
    static const char *const bad[] = {"furlong", "MM", "inch", "", "m ", "km", "um"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sr_unit u = SR_UNIT_CM;
        assert_false(sr_unit_parse(bad[i], &u));
        assert_int_equal(u, SR_UNIT_CM); /* untouched */
    }
    sr_unit u = SR_UNIT_CM;
    assert_false(sr_unit_parse(NULL, &u));
    assert_string_equal(sr_unit_name(SR_UNIT_DEFAULT), "default");
    assert_true(sr_unit_mm(SR_UNIT_DEFAULT) == 1.0);
}

static void a_machined_part_size_is_plausible_in_any_unit(void **state)
{
    (void)state;
    sr_unit likely = SR_UNIT_CM;
    assert_true(sr_unit_size_plausible(40.0, SR_UNIT_MM, &likely));
    assert_true(sr_unit_size_plausible(25.4, SR_UNIT_IN, &likely));  /* a 1 in cube */
    assert_true(sr_unit_size_plausible(2000.0, SR_UNIT_M, &likely)); /* a 2 m frame */
    assert_true(sr_unit_size_plausible(50.0, SR_UNIT_CM, &likely));
    assert_int_equal(likely, SR_UNIT_CM); /* untouched when plausible */
}

static void a_size_from_another_unit_names_that_unit(void **state)
{
    (void)state;
    sr_unit likely = SR_UNIT_DEFAULT;
    /* a 1 in cube whose numbers were read as mm */
    assert_false(sr_unit_size_plausible(1.0, SR_UNIT_MM, &likely));
    assert_int_equal(likely, SR_UNIT_IN);
    /* a 0.1 m part read as mm: 0.1 mm */
    assert_false(sr_unit_size_plausible(0.1, SR_UNIT_MM, &likely));
    assert_int_equal(likely, SR_UNIT_M);
    /* a glTF drawn in mm read in its default metres: 120 becomes 120000 mm */
    assert_false(sr_unit_size_plausible(120000.0, SR_UNIT_M, &likely));
    assert_int_equal(likely, SR_UNIT_MM);
    /* a size no unit of the four makes plausible */
    assert_false(sr_unit_size_plausible(1e-4, SR_UNIT_MM, &likely));
    assert_int_equal(likely, SR_UNIT_DEFAULT);
}

int main(void)
{
    struct CMUnitTest tests[] = {
        cmocka_unit_test(names_parse_exactly_and_nothing_else),
        cmocka_unit_test(a_machined_part_size_is_plausible_in_any_unit),
        cmocka_unit_test(a_size_from_another_unit_names_that_unit),
    };
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
