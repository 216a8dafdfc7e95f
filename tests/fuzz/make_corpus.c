/*
 * make_corpus.c: writes the fuzz targets' seed corpus into DIR/FORMAT/ with the
 * project's own writers (tests/support/fuzz_seeds.c): `make_corpus DIR`. Run by
 * `make fuzz`.
 */
#include <stdio.h>

#include "support/fuzz_seeds.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: make_corpus DIR\n");
        return 2;
    }
    int n = sr_fuzz_write_seeds(argv[1]);
    if (n < 0) {
        fprintf(stderr, "make_corpus: cannot write the seeds into '%s'\n", argv[1]);
        return 1;
    }
    fprintf(stderr, "make_corpus: %d seed files in %s\n", n, argv[1]);
    return 0;
}
