/*
 * params_default.c: the table of params_default.h. Change a value here and in the
 * 'default' row of sql/001_init.sql (or a new migration) together: test_catalog fails
 * until both agree.
 */
#include "run/params_default.h"

static const sr_params default_set = {
    .name = "default",
    .layers = 320, /* the paper's finest Table 2 setting */
    .sectors = 240,
    .gamma_axis = 0.95, /* the thresholds are symrec's choice, not the paper's */
    .gamma_plane = 0.95,
    .delta_d = 0.05,
    .min_depth_mm = 0.1,
    .min_volume_mm3 = 1.0,
    .notes = "built-in copy of the seeded 'default' set",
};

void sr_params_default(sr_params *out)
{
    *out = default_set;
}
