/*
 * units.c: length units of mesh files (units.h): names, factors to millimetres, and
 * whether a size read in a stated unit looks like a part drawn in another one.
 */
#include "mesh/units.h"

#include <string.h>

#include "mesh/mesh_facts.h"

static const struct {
    sr_unit unit;
    const char *name;
    double mm;
} units[] = {
    {SR_UNIT_MM, "mm", 1.0},
    {SR_UNIT_CM, "cm", 10.0},
    {SR_UNIT_M, "m", 1000.0},
    {SR_UNIT_IN, "in", 25.4},
};

#define UNIT_COUNT (sizeof units / sizeof units[0])

bool sr_unit_parse(const char *name, sr_unit *out)
{
    if (!name)
        return false;
    for (size_t i = 0; i < UNIT_COUNT; i++)
        if (strcmp(name, units[i].name) == 0) {
            *out = units[i].unit;
            return true;
        }
    return false;
}

const char *sr_unit_name(sr_unit unit)
{
    for (size_t i = 0; i < UNIT_COUNT; i++)
        if (units[i].unit == unit)
            return units[i].name;
    return "default";
}

double sr_unit_mm(sr_unit unit)
{
    for (size_t i = 0; i < UNIT_COUNT; i++)
        if (units[i].unit == unit)
            return units[i].mm;
    return 1.0;
}

bool sr_unit_size_plausible(double extent_mm, sr_unit stated, sr_unit *likely)
{
    if (strcmp(sr_unit_guess(extent_mm), "mm") == 0)
        return true;
    /* the file's own numbers, and the first other unit that makes them a machined
     * part's size; inches before centimetres and metres, as sr_unit_guess prefers */
    double raw = extent_mm / sr_unit_mm(stated);
    static const sr_unit order[] = {SR_UNIT_MM, SR_UNIT_IN, SR_UNIT_CM, SR_UNIT_M};
    *likely = SR_UNIT_DEFAULT;
    for (size_t i = 0; i < sizeof order / sizeof order[0]; i++)
        if (order[i] != stated && strcmp(sr_unit_guess(raw * sr_unit_mm(order[i])), "mm") == 0) {
            *likely = order[i];
            break;
        }
    return false;
}
