/*
 * random_pose.h: a reproducible random rigid pose for the tests that check an answer
 * is independent of where a part lies (alignment, symmetry fit).
 */
#ifndef SR_TEST_RANDOM_POSE_H
#define SR_TEST_RANDOM_POSE_H

/* p' = R p + t as a 3 x 4 row-major matrix from a seed: R = Rz(az) Ry(tilt) Rz(spin)
 * with the z axis tilted by 10..40 deg and spun at random, t up to 60 mm per
 * coordinate. The same seed gives the same pose. */
void test_random_pose(unsigned seed, double m[12]);

#endif
