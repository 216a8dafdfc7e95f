/*
 * open_face.c: a face of a test mesh left off (open_face.h).
 */
#include "support/open_face.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

size_t test_drop_face_at(sr_mesh *m, double z0)
{
    return test_drop_face_on(m, 2, z0);
}

size_t test_drop_face_on(sr_mesh *m, int axis, double at)
{
    size_t kept = 0;
    for (size_t t = 0; t < m->tri_count; t++) {
        bool on = true;
        for (int k = 0; k < 3; k++)
            on = on && fabs(m->xyz[3 * m->tri[3 * t + k] + axis] - at) < 1e-12;
        if (!on) {
            memmove(m->tri + 3 * kept, m->tri + 3 * t, 3 * sizeof *m->tri);
            kept++;
        }
    }
    size_t gone = m->tri_count - kept;
    m->tri_count = kept;
    return gone;
}
