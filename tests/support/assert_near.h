/*
 * assert_near.h: floating-point assertion for cmocka 1.1.5 (Debian 12), which has no
 * assert_double_equal. Include after <cmocka.h>. Fails when |a - b| > tol or either
 * value is NaN, printing both values. assert_msg_has(err, text): an sr_err's message
 * must contain text (needs <string.h>).
 */
#ifndef SR_TEST_ASSERT_NEAR_H
#define SR_TEST_ASSERT_NEAR_H

#include <math.h>
#include <stdio.h>

#define assert_near(a, b, tol)                                                         \
    do {                                                                               \
        double sr_an_a_ = (double)(a), sr_an_b_ = (double)(b), sr_an_t_ = (double)(tol); \
        if (!(fabs(sr_an_a_ - sr_an_b_) <= sr_an_t_)) {                               \
            print_error("%s = %.17g, expected %s = %.17g within %g\n", #a, sr_an_a_,  \
                        #b, sr_an_b_, sr_an_t_);                                       \
            fail();                                                                    \
        }                                                                              \
    } while (0)

/* Fails unless the sr_err `err` holds `text` in its message, printing both. */
#define assert_msg_has(err, text)                                                    \
    do {                                                                             \
        if (!strstr((err).msg, (text))) {                                            \
            print_error("message '%s' lacks '%s'\n", (err).msg, (text));             \
            fail();                                                                  \
        }                                                                            \
    } while (0)

#endif
