/*
 * bench_catalog.c: catalogue figures for `make bench` (called from bench_main.c):
 * storing and loading a 1M-triangle mesh (a closed torus grid, 1000 x 500 quads)
 * through the public catalogue API, the pieces of the insert (validation, measuring,
 * closedness, blob encoding) timed apart, and the catalogue's bytes per million
 * triangles on disk. Works in a fresh /tmp/symrec-bench-XXXXXX directory it removes.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "catalog/catalog.h"
#include "mesh/mesh.h"
#include "catalog/mesh_blob.h"

#define PI 3.14159265358979323846

void bench_catalog(void);

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Closed, outward torus: nu segments around the axis, nv around the tube. */
static sr_status make_torus(size_t nu, size_t nv, double big_r, double small_r, sr_mesh *out)
{
    sr_mesh m;
    sr_status st = sr_mesh_alloc(&m, nu * nv, 2 * nu * nv);
    if (st != SR_OK)
        return st;
    for (size_t i = 0; i < nu; i++) {
        double u = 2 * PI * (double)i / (double)nu;
        for (size_t j = 0; j < nv; j++) {
            double v = 2 * PI * (double)j / (double)nv;
            double *p = m.xyz + 3 * (i * nv + j);
            p[0] = (big_r + small_r * cos(v)) * cos(u);
            p[1] = (big_r + small_r * cos(v)) * sin(u);
            p[2] = small_r * sin(v);
        }
    }
    uint32_t *t = m.tri;
    for (size_t i = 0; i < nu; i++) {
        for (size_t j = 0; j < nv; j++) {
            uint32_t a = (uint32_t)(i * nv + j), b = (uint32_t)(((i + 1) % nu) * nv + j);
            uint32_t c = (uint32_t)(((i + 1) % nu) * nv + (j + 1) % nv);
            uint32_t d = (uint32_t)(i * nv + (j + 1) % nv);
            uint32_t q[6] = {a, b, c, a, c, d};
            memcpy(t, q, sizeof q);
            t += 6;
        }
    }
    *out = m;
    return SR_OK;
}

static long long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long long)sb.st_size : -1;
}

static void remove_catalogue(const char *dir, const char *db)
{
    static const char *const suffix[] = {"", "-wal", "-shm"};
    char p[256];
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s%s", db, suffix[i]);
        unlink(p);
    }
    rmdir(dir);
}

void bench_catalog(void)
{
    sr_mesh torus = {0};
    sr_err err = {{0}};
    if (make_torus(1000, 500, 50.0, 10.0, &torus) != SR_OK) {
        printf("  cannot build the torus: out of memory\n");
        return;
    }
    double mesh_mib = (double)(torus.vertex_count * 24 + torus.tri_count * 12) / (1 << 20);
    printf("  mesh: closed torus, %zu triangles, %zu vertices, %.1f MiB in memory\n",
           torus.tri_count, torus.vertex_count, mesh_mib);

    /* the pieces of an insert that run before the write transaction */
    double t = now();
    sr_status st = sr_mesh_validate(&torus, "torus", NULL, &err);
    double t_validate = now() - t;
    t = now();
    volatile double vol = sr_mesh_volume(&torus), area = sr_mesh_area(&torus);
    double t_measure = now() - t;
    t = now();
    bool closed = sr_mesh_is_closed(&torus);
    double t_closed = now() - t;
    size_t blob_size = sr_mesh_blob_size(&torus);
    void *blob = malloc(blob_size);
    t = now();
    if (blob)
        sr_mesh_blob_encode(&torus, blob, blob_size);
    double t_encode = now() - t;
    sr_mesh decoded = {0};
    t = now();
    if (blob)
        sr_mesh_blob_decode(blob, blob_size, &decoded, NULL);
    double t_decode = now() - t;
    sr_mesh_release(&decoded);
    free(blob);
    if (st != SR_OK || !closed) {
        printf("  torus is not valid and closed: %s\n", err.msg);
        sr_mesh_release(&torus);
        return;
    }
    (void)vol;
    (void)area;

    char dir[] = "/tmp/symrec-bench-XXXXXX", db[64];
    if (!mkdtemp(dir)) {
        printf("  cannot make a temporary directory\n");
        sr_mesh_release(&torus);
        return;
    }
    snprintf(db, sizeof db, "%s/bench.db", dir);
    sr_catalog *cat = NULL;
    if (sr_catalog_open(db, SR_CATALOG_CREATE, &cat, &err) != SR_OK) {
        printf("  %s\n", err.msg);
        remove_catalogue(dir, db);
        sr_mesh_release(&torus);
        return;
    }
    sr_catalog_close(cat);
    long long empty_bytes = file_size(db);
    if (sr_catalog_open(db, 0, &cat, &err) != SR_OK) {
        printf("  %s\n", err.msg);
        remove_catalogue(dir, db);
        sr_mesh_release(&torus);
        return;
    }

    /* the part insert (one transaction, COMMIT durable), then instances: best of 3 */
    sr_part_new p = {.number = "BENCH-1", .name = "torus", .material = "C45", .mesh = &torus};
    int64_t part_id = 0;
    t = now();
    st = sr_catalog_part_add(cat, &p, &part_id, &err);
    double t_part = now() - t, t_inst = 1e30;
    for (int i = 0; st == SR_OK && i < 3; i++) {
        sr_instance_new in = {.part = "BENCH-1", .mesh = &torus, .serial = "S"};
        t = now();
        st = sr_catalog_instance_add(cat, &in, NULL, &err);
        double dt = now() - t;
        t_inst = dt < t_inst ? dt : t_inst;
    }
    double t_load = 1e30;
    bool same = true;
    for (int i = 0; st == SR_OK && i < 3; i++) {
        sr_mesh back = {0};
        t = now();
        st = sr_catalog_part_mesh(cat, part_id, &back, &err);
        double dt = now() - t;
        t_load = dt < t_load ? dt : t_load;
        if (st == SR_OK)
            same = same && back.vertex_count == torus.vertex_count &&
                   memcmp(back.xyz, torus.xyz, torus.vertex_count * 24) == 0 &&
                   memcmp(back.tri, torus.tri, torus.tri_count * 12) == 0;
        sr_mesh_release(&back);
    }
    sr_catalog_close(cat);   /* checkpoints the WAL into the file */
    if (st != SR_OK) {
        printf("  failed: %s\n", err.msg);
        remove_catalogue(dir, db);
        sr_mesh_release(&torus);
        return;
    }
    long long full_bytes = file_size(db);
    double per_m = (double)(full_bytes - empty_bytes) / 4.0 / ((double)torus.tri_count / 1e6);

    printf("  %-44s %9.4f s\n", "validate (sr_mesh_validate)", t_validate);
    printf("  %-44s %9.4f s\n", "volume + area", t_measure);
    printf("  %-44s %9.4f s\n", "closedness (sr_mesh_is_closed)", t_closed);
    printf("  %-44s %9.4f s\n", "encode blob (memory)", t_encode);
    printf("  %-44s %9.4f s\n", "decode blob (memory, with checks)", t_decode);
    printf("  %-44s %9.4f s\n", "part add with mesh (all of the above + write)", t_part);
    printf("  %-44s %9.4f s   (best of 3)\n", "instance add with mesh", t_inst);
    printf("  %-44s %9.4f s   (best of 3, bit-identical: %s)\n", "load part mesh", t_load,
           same ? "yes" : "NO");
    printf("  catalogue: %.1f MiB per million triangles on disk (blob alone %.1f MiB; 4 meshes "
           "in %.1f MiB)\n",
           per_m / (1 << 20), (double)sr_mesh_blob_size(&torus) / (1 << 20) /
                                  ((double)torus.tri_count / 1e6),
           (double)full_bytes / (1 << 20));
    remove_catalogue(dir, db);
    sr_mesh_release(&torus);
}
