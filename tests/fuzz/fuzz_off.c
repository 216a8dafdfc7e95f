/*
 * fuzz_off.c: libFuzzer target: OFF bytes through sr_mesh_read_memory (the body is
 * fuzz_read.h's). Built and run by `make fuzz`; seeds in build/fuzz/corpus/off.
 */
#define FUZZ_FORMAT SR_FMT_OFF
#include "fuzz/fuzz_read.h"
