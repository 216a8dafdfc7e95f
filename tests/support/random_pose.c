/*
 * random_pose.c: the tests' reproducible random rigid pose (random_pose.h).
 */
#include "support/random_pose.h"

#include <math.h>
#include <stdint.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void test_random_pose(unsigned seed, double m[12])
{
    uint64_t s = seed * 0x9E3779B97F4A7C15ull + 1;
    double u[6];
    for (int i = 0; i < 6; i++) { /* xorshift64 */
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        u[i] = (double)(s >> 11) / 9007199254740992.0;
    }
    double tilt = (10 + 30 * u[0]) * M_PI / 180, az = 2 * M_PI * u[1], spin = 2 * M_PI * u[2];
    double ca = cos(az), sa = sin(az), ct = cos(tilt), st = sin(tilt), cs = cos(spin),
           ss = sin(spin);
    /* R = Rz(az) Ry(tilt) Rz(spin) */
    const double r[9] = {ca * ct * cs - sa * ss,
                         -ca * ct * ss - sa * cs,
                         ca * st,
                         sa * ct * cs + ca * ss,
                         -sa * ct * ss + ca * cs,
                         sa * st,
                         -st * cs,
                         st * ss,
                         ct};
    for (int i = 0; i < 3; i++) {
        m[4 * i] = r[3 * i];
        m[4 * i + 1] = r[3 * i + 1];
        m[4 * i + 2] = r[3 * i + 2];
        m[4 * i + 3] = 120 * (u[3 + i] - 0.5);
    }
}
