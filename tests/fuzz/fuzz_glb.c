/*
 * fuzz_glb.c: libFuzzer target: GLB bytes through sr_mesh_read_memory (the body is
 * fuzz_read.h's). Built and run by `make fuzz`; seeds in build/fuzz/corpus/glb.
 */
#define FUZZ_FORMAT SR_FMT_GLB
#include "fuzz/fuzz_read.h"
