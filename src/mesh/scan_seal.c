/*
 * scan_seal.c: the last defects of a closed scan cut out and closed again
 * (scan_describe.h, sr_scan_seal). The closing of a scan's openings can leave a few
 * edges used other than once each way where rims it could not fill cleanly met: a
 * fan over a rim that folds in its plane laid on a sliver the scan kept, two fans
 * meeting at a vertex the rim walked through twice (a two-million-triangle open scan
 * of a shaft kept 31 such edges round one millimetre of its base's lace). One such
 * edge is enough for every boolean to refuse the whole scan, and so for every section
 * to be lost. Each defect is local: the triangles round it, out to a few rings, are
 * taken out, and the opening they leave, whose rim the rest of the surface walks
 * cleanly, is closed as any scan opening is.
 */
#include "mesh/scan_describe.h"

#include <stdlib.h>
#include <string.h>

#include "mesh/scan_int.h"

/* Rings of triangles taken out round a defect, tried from 0 (the defect's own
 * vertices' triangles) up to this many. */
#define SEAL_MAX_RINGS 4

/* How many times the directed edge a -> b is used, in the sorted keys[0..n). */
static size_t uses(const uint64_t *keys, size_t n, uint64_t a, uint64_t b)
{
    uint64_t k = a << 32 | b;
    size_t lo = 0, hi = n;
    while (lo < hi) { /* the first key >= k */
        size_t mid = lo + (hi - lo) / 2;
        if (keys[mid] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    size_t c = 0;
    while (lo + c < n && keys[lo + c] == k)
        c++;
    return c;
}

/* bad[v] for every vertex of an edge not used exactly once each way; returns their
 * count (SIZE_MAX: out of memory). */
static size_t mark_defects(const sr_mesh *mesh, bool *bad)
{
    size_t n = 3 * mesh->tri_count;
    uint64_t *keys = malloc((n + 1) * sizeof *keys);
    if (!keys)
        return SIZE_MAX;
    for (size_t t = 0; t < mesh->tri_count; t++)
        for (int k = 0; k < 3; k++)
            keys[3 * t + k] = (uint64_t)mesh->tri[3 * t + k] << 32 | mesh->tri[3 * t + (k + 1) % 3];
    if (sr_scan_sort_edges(keys, n, sizeof *keys, mesh->vertex_count) != SR_OK) {
        free(keys);
        return SIZE_MAX;
    }
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t a = keys[i] >> 32, b = keys[i] & UINT32_MAX;
        if (uses(keys, n, a, b) == 1 && uses(keys, n, b, a) == 1)
            continue;
        count += !bad[a] + !bad[b];
        bad[a] = bad[b] = true;
    }
    free(keys);
    return count;
}

/* One attempt: mesh (a copy) less every triangle within rings rings of a defect
 * (bad), closed again; *ok when then every edge is used once each way; *cut the
 * triangles taken out. */
static sr_status seal_rings(sr_mesh *mesh, const bool *bad, int rings, bool *ok, size_t *cut,
                            sr_err *err)
{
    *ok = false;
    size_t nv = mesh->vertex_count, nt = mesh->tri_count;
    bool *mark = malloc((nv + 1) * sizeof *mark), *next = malloc((nv + 1) * sizeof *next);
    bool *gone = calloc(nt + 1, sizeof *gone);
    if (!mark || !next || !gone) {
        free(mark);
        free(next);
        free(gone);
        return sr_err_set(err, SR_E_NOMEM, "out of memory sealing the closed scan");
    }
    memcpy(mark, bad, nv * sizeof *mark);
    for (int r = 0; r < rings; r++) {
        memcpy(next, mark, nv * sizeof *next);
        for (size_t t = 0; t < nt; t++) {
            const uint32_t *v = mesh->tri + 3 * t;
            if (mark[v[0]] || mark[v[1]] || mark[v[2]])
                next[v[0]] = next[v[1]] = next[v[2]] = true;
        }
        memcpy(mark, next, nv * sizeof *mark);
    }
    size_t n = 0;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *v = mesh->tri + 3 * t;
        gone[t] = mark[v[0]] || mark[v[1]] || mark[v[2]];
        n += gone[t];
    }
    free(mark);
    free(next);
    sr_status st = sr_scan_drop_triangles(mesh, gone, err);
    free(gone);
    if (st != SR_OK || mesh->tri_count == 0) /* nothing left round the defect to seal */
        return st;
    /* an attempt that fails is no seal, not an error: only memory is */
    sr_scan_desc d = {0};
    sr_status at = sr_scan_describe(mesh, NULL, &d, NULL);
    if (at == SR_OK)
        at = sr_scan_close_openings(mesh, &d, 0, NULL, NULL);
    if (at == SR_OK)
        at = sr_scan_drop_strays(mesh, &d, NULL);
    sr_scan_desc_release(&d);
    if (at == SR_E_NOMEM)
        return sr_err_set(err, SR_E_NOMEM, "out of memory sealing the closed scan");
    sr_mesh_edges es = {0};
    if (at == SR_OK && sr_mesh_edge_stats(mesh, &es) != SR_OK)
        return sr_err_set(err, SR_E_NOMEM, "out of memory sealing the closed scan");
    *ok = at == SR_OK && mesh->tri_count > 0 && es.boundary_edges == 0 &&
          es.nonmanifold_edges == 0 && es.misoriented_edges == 0;
    *cut = n;
    return SR_OK;
}

sr_status sr_scan_seal(sr_mesh *mesh, size_t *cut, sr_err *err)
{
    if (cut)
        *cut = 0;
    bool *bad = calloc(mesh->vertex_count + 1, sizeof *bad);
    if (!bad)
        return sr_err_set(err, SR_E_NOMEM, "out of memory sealing the closed scan");
    size_t nbad = mark_defects(mesh, bad);
    sr_status st = nbad == SIZE_MAX
                       ? sr_err_set(err, SR_E_NOMEM, "out of memory sealing the closed scan")
                       : SR_OK;
    for (int rings = 0; st == SR_OK && nbad > 0 && rings <= SEAL_MAX_RINGS; rings++) {
        sr_mesh m = {0};
        bool ok = false;
        size_t n = 0;
        st = sr_mesh_copy(&m, mesh);
        if (st != SR_OK) {
            st = sr_err_set(err, st, "out of memory sealing the closed scan");
            break;
        }
        st = seal_rings(&m, bad, rings, &ok, &n, err);
        if (st == SR_OK && ok) {
            sr_mesh_release(mesh);
            *mesh = m;
            if (cut)
                *cut = n;
            break;
        }
        sr_mesh_release(&m);
    }
    free(bad);
    return st;
}
