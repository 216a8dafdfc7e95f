/*
 * fuzz_read.h: the body of every fuzz target of tests/fuzz/ (fuzz_stl.c ... fuzz_glb.c
 * each define FUZZ_FORMAT and include this): libFuzzer's input goes, as a whole file's
 * bytes, through sr_mesh_read_memory, the check-and-read path sr_mesh_read itself uses
 * (src/bridge/mesh_io.h). A crash, a sanitizer report, or an outcome that breaks the
 * contract aborts: a mesh returned must be valid and inside the physical envelope
 * (io/envelope.h); a refusal must be one line "cannot read 'fuzz.FMT': ..." and never
 * SR_E_INTERNAL (an unexpected exception caught at the barrier).
 *
 * Built by `make fuzz` with clang-14 -fsanitize=fuzzer,address,undefined.
 */
#ifndef SR_FUZZ_READ_H
#define SR_FUZZ_READ_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/mesh_io.h"
#include "io/envelope.h"
#include "mesh/mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char name[16] = "fuzz.";
    strcat(name, sr_format_name(FUZZ_FORMAT));
    sr_mesh m = {0};
    sr_err err;
    sr_err_clear(&err);
    sr_status st = sr_mesh_read_memory(data, size, FUZZ_FORMAT, name, &m, &err);
    if (st == SR_OK) {
        if (sr_mesh_validate(&m, name, NULL, NULL) != SR_OK ||
            sr_envelope_check_mesh(m.xyz, m.vertex_count, m.tri, m.tri_count, name, NULL) != SR_OK)
            abort();
        sr_mesh_release(&m);
        return 0;
    }
    char head[32];
    strcpy(head, "cannot read '");
    strcat(head, name);
    strcat(head, "': ");
    if (st == SR_E_INTERNAL || strncmp(err.msg, head, strlen(head)) != 0 || strchr(err.msg, '\n') ||
        m.xyz || m.tri)
        abort();
    return 0;
}

#endif
