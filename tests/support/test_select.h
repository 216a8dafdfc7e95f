/* test_select: which of a test binary's cmocka tests run, from the environment.
 *
 *   SYMREC_TEST_FILTER=glob,glob,...  only the tests whose names match one of the globs
 *   SYMREC_TEST_SKIP=glob,...         all but those
 *   SYMREC_TEST_SHARD=K/N             the K-th of N shards (1-based): tests i with
 *                                     i mod N = K-1, counted after FILTER and SKIP
 *
 * tests/run_tests.sh uses them to run the long binaries as shards side by side.
 */
#ifndef SYMREC_TEST_SELECT_H
#define SYMREC_TEST_SELECT_H

#include <stddef.h>
#include <stdarg.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

/* Keeps, in order, the tests of tests[0..n) that the environment selects; returns how
 * many. A malformed SYMREC_TEST_SHARD is reported on stderr and exits with status 2. */
size_t sr_test_select(struct CMUnitTest *tests, size_t n);

#endif
