/*
 * fuzz_stl.c: libFuzzer target: STL bytes through sr_mesh_read_memory (the body is
 * fuzz_read.h's). Built and run by `make fuzz`; seeds in build/fuzz/corpus/stl.
 */
#define FUZZ_FORMAT SR_FMT_STL
#include "fuzz/fuzz_read.h"
