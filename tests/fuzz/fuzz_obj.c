/*
 * fuzz_obj.c: libFuzzer target: OBJ bytes through sr_mesh_read_memory (the body is
 * fuzz_read.h's). Built and run by `make fuzz`; seeds in build/fuzz/corpus/obj.
 */
#define FUZZ_FORMAT SR_FMT_OBJ
#include "fuzz/fuzz_read.h"
