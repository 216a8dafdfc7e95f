/*
 * test_grow.c: sr_grow (src/base/grow.h), the doubling step of every growable array:
 * 16 the first time, then twice the room, the array's contents kept; the same pointer
 * back while there is room; an impossible size refused with the array and its room
 * kept.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdlib.h>

#include "base/grow.h"

static void doubles_from_sixteen_and_keeps_the_contents(void **state)
{
    (void)state;
    int *v = NULL;
    size_t count = 0, cap = 0;
    for (int i = 0; i < 100; i++) {
        int *nv = sr_grow(v, count, &cap, sizeof *v);
        assert_non_null(nv);
        if (count < 16)
            assert_int_equal(cap, 16);
        v = nv;
        v[count++] = i;
    }
    assert_int_equal(cap, 128); /* 16, 32, 64, 128 */
    for (int i = 0; i < 100; i++)
        assert_int_equal(v[i], i);
    /* room left: the same array back, its room unchanged */
    assert_ptr_equal(sr_grow(v, count, &cap, sizeof *v), v);
    assert_int_equal(cap, 128);
    free(v);
}

static void an_impossible_size_is_refused_and_the_array_kept(void **state)
{
    (void)state;
    size_t cap = 0;
    char *v = sr_grow(NULL, 0, &cap, 1);
    assert_non_null(v);
    v[0] = 'x';
    size_t full = cap;
    assert_null(sr_grow(v, full, &cap, SIZE_MAX / 4));
    assert_int_equal(cap, full);
    assert_int_equal(v[0], 'x');
    free(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(doubles_from_sixteen_and_keeps_the_contents),
        cmocka_unit_test(an_impossible_size_is_refused_and_the_array_kept),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
