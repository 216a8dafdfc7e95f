/*
 * fuzz_seeds.c: the fuzz targets' seed corpus, written by the project's own writers
 * (see fuzz_seeds.h).
 */
#include "support/fuzz_seeds.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "bridge/mesh_io.h"
#include "mesh/mesh.h"
#include "mesh/shapes.h"

const char *const sr_fuzz_formats[] = {"stl", "obj", "ply", "off", "gltf", "glb", NULL};

static int write_one(const char *dir, const char *fmt, const char *name, const sr_mesh *m,
                     int ascii)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s/%s.%s", dir, fmt, name, fmt);
    sr_write_opts o = {ascii};
    return sr_mesh_write(path, m, &o, NULL) == SR_OK ? 1 : -1;
}

int sr_fuzz_write_seeds(const char *dir)
{
    sr_mesh box = {0}, cyl = {0};
    const double lo[3] = {0, 0, 0}, hi[3] = {10, 20, 30};
    int n = 0;
    if (sr_shape_box(lo, hi, &box, NULL) != SR_OK ||
        sr_shape_cylinder(10.0, -5.0, 15.0, 16, &cyl, NULL) != SR_OK) {
        n = -1;
        goto out;
    }
    for (size_t f = 0; sr_fuzz_formats[f]; f++) {
        const char *fmt = sr_fuzz_formats[f];
        char sub[1024];
        snprintf(sub, sizeof sub, "%s/%s", dir, fmt);
        if (mkdir(sub, 0755) != 0 && errno != EEXIST) {
            n = -1;
            goto out;
        }
        int has_ascii = strcmp(fmt, "stl") == 0 || strcmp(fmt, "ply") == 0;
        int r = write_one(dir, fmt, "box", &box, 0) + write_one(dir, fmt, "cylinder", &cyl, 0);
        if (has_ascii)
            r += write_one(dir, fmt, "box_ascii", &box, 1) +
                 write_one(dir, fmt, "cylinder_ascii", &cyl, 1);
        if (r != (has_ascii ? 4 : 2)) {
            n = -1;
            goto out;
        }
        n += r;
        if (strcmp(fmt, "gltf") == 0 || strcmp(fmt, "glb") == 0) {
            char path[1024];
            snprintf(path, sizeof path, "%s/%s/scene.%s", dir, fmt, fmt);
            sr_scene_mesh two[2] = {{"box", &box, {0.8f, 0.2f, 0.2f, 1.0f}},
                                    {"cylinder", &cyl, {0.2f, 0.2f, 0.8f, 1.0f}}};
            if (sr_scene_write(path, two, 2, "{\"units\":\"mm\"}", NULL) != SR_OK) {
                n = -1;
                goto out;
            }
            n++;
        }
    }
out:
    sr_mesh_release(&box);
    sr_mesh_release(&cyl);
    return n;
}
