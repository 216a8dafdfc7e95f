/*
 * params_default.h: the one table of the reconstruction's default parameters, the
 * values of the seeded 'default' parameter set (sql/001_init.sql). The CLI runs with it
 * when no catalogue is open, and the stages that take 0 as "the default" (reconstruct.c
 * for layers, sectors, gamma, delta_d and the smallest section volume; paper/analyse.c
 * for gamma) resolve that 0 from it, so a default is written down once in C.
 *
 * The SQL seeds its own copy of the row (the schema is plain SQL, not generated);
 * tests/test_catalog.c checks that the seeded 'default' row of a new catalogue equals
 * this table field by field (notes excepted), so the two cannot drift apart.
 */
#ifndef SR_PARAMS_DEFAULT_H
#define SR_PARAMS_DEFAULT_H

#include "run/run.h"

/* Writes the 'default' set into *out: name "default", 320 layers, 240 sectors,
 * gamma_axis = gamma_plane = 0.95, delta_d 0.05, min_depth_mm 0.1, min_volume_mm3 1.0,
 * and notes saying it is the built-in copy. Always passes sr_params_check. */
void sr_params_default(sr_params *out);

#endif
