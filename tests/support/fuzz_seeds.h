/*
 * fuzz_seeds.h: the seed corpus of the fuzz targets (tests/fuzz/), made by symrec's own
 * writers: a box and a 16-sided cylinder in every format and variant (binary and ASCII
 * STL, OBJ, binary and ASCII PLY, OFF, glTF with its buffer as a data URI, GLB) and a
 * two-mesh glTF/GLB scene. tests/fuzz/make_corpus.c writes them for `make fuzz`,
 * test_fuzz_replay.c into its own temporary folder, so no build artefact is needed.
 */
#ifndef SR_TEST_FUZZ_SEEDS_H
#define SR_TEST_FUZZ_SEEDS_H

/* The formats with a fuzz target, in order: "stl", "obj", "ply", "off", "gltf", "glb";
 * NULL-terminated. */
extern const char *const sr_fuzz_formats[];

/* Writes the seeds into dir/FORMAT/ (the folders are created; dir must exist). Returns
 * the number of files written, or -1 with errno-style failure when a folder or a file
 * cannot be made (nothing is printed). */
int sr_fuzz_write_seeds(const char *dir);

#endif
