/*
 * fuzz_ply.c: libFuzzer target: PLY bytes through sr_mesh_read_memory (the body is
 * fuzz_read.h's). Built and run by `make fuzz`; seeds in build/fuzz/corpus/ply.
 */
#define FUZZ_FORMAT SR_FMT_PLY
#include "fuzz/fuzz_read.h"
