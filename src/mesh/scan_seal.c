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

typedef struct edge_way {
    uint64_t key; /* lo << 32 | hi */
    uint64_t up;  /* 1 when its triangle walks it lo -> hi */
} edge_way;

/* bad[v] for every vertex of an edge not used exactly once each way; returns their
 * count (SIZE_MAX: out of memory). The edges sorted by vertex pair, each pair's run
 * counted both ways. */
static size_t mark_defects(const sr_mesh *mesh, bool *bad)
{
    size_t n = 3 * mesh->tri_count;
    edge_way *e = malloc((n + 1) * sizeof *e);
    if (!e)
        return SIZE_MAX;
    for (size_t t = 0; t < mesh->tri_count; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = mesh->tri[3 * t + k], b = mesh->tri[3 * t + (k + 1) % 3];
            e[3 * t + k] = (edge_way){a < b ? a << 32 | b : b << 32 | a, a < b};
        }
    if (sr_scan_sort_edges(e, n, sizeof *e, mesh->vertex_count) != SR_OK) {
        free(e);
        return SIZE_MAX;
    }
    size_t count = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i, up = 0;
        for (; j < n && e[j].key == e[i].key; j++)
            up += e[j].up;
        if (!(j - i == 2 && up == 1)) {
            uint64_t a = e[i].key >> 32, b = e[i].key & UINT32_MAX;
            count += !bad[a] + !bad[b];
            bad[a] = bad[b] = true;
        }
        i = j;
    }
    free(e);
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
