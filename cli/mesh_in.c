/*
 * mesh_in.c: how every command reads a mesh file the user names: the --units option
 * (mm, cm, m, in; the default is the format's own: mm for STL/OBJ/PLY/OFF, metres for
 * glTF/GLB), the read scaled to mm (bridge/mesh_io.h), and one warning line when the
 * size in mm is not a machined part's (5 mm .. 3 m) and another unit would make it one:
 *   symrec: warning: 'cube.stl' is 1 mm across (largest side, read in mm): small for a
 *   machined part; if it was drawn in in, give --units in
 * The warning is a note (cli_note): --quiet suppresses it.
 */
#include "cli.h"

#include "bridge/mesh_io.h"
#include "mesh/mesh_facts.h"

bool cli_parse_units(const char *opt, const char *text, sr_unit *out)
{
    if (!text) {
        *out = SR_UNIT_DEFAULT;
        return true;
    }
    if (sr_unit_parse(text, out))
        return true;
    cli_usage_error("bad %s '%s': expected %s", opt, text, SR_UNIT_NAMES);
    return false;
}

sr_status cli_mesh_read(const char *path, sr_unit unit, sr_mesh *out, sr_unit *used, sr_err *err)
{
    sr_unit stated = unit != SR_UNIT_DEFAULT ? unit : sr_format_unit(sr_format_from_path(path));
    sr_status st = sr_mesh_read_units(path, stated, out, err);
    if (st != SR_OK)
        return st;
    double lo[3], hi[3], extent = 0;
    sr_mesh_bbox(out, lo, hi);
    for (int k = 0; k < 3; k++)
        extent = hi[k] - lo[k] > extent ? hi[k] - lo[k] : extent;
    sr_unit likely;
    if (!sr_unit_size_plausible(extent, stated, &likely)) {
        const char *name = sr_unit_name(stated);
        const char *size = extent < 5 ? "small" : "large";
        if (likely != SR_UNIT_DEFAULT)
            cli_note(
                "warning: '%s' is %.4g %s across (largest side, read in %s): %s for a machined "
                "part; if it was drawn in %s, give --units %s",
                path, extent / sr_unit_mm(stated), name, name, size, sr_unit_name(likely),
                sr_unit_name(likely));
        else
            cli_note(
                "warning: '%s' is %.4g %s across (largest side, read in %s): %s for a machined "
                "part; check --units",
                path, extent / sr_unit_mm(stated), name, name, size);
    }
    if (used)
        *used = stated;
    return SR_OK;
}
