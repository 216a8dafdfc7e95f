/*
 * fuzz_gltf.c: libFuzzer target: GLTF bytes through sr_mesh_read_memory (the body is
 * fuzz_read.h's). Built and run by `make fuzz`; seeds in build/fuzz/corpus/gltf.
 */
#define FUZZ_FORMAT SR_FMT_GLTF
#include "fuzz/fuzz_read.h"
