/*
 * cli_case.h: the small kit of the CLI test files other than test_cli.c
 * (test_cli_outputs.c, test_cli_readonly.c, test_cli_text.c): run the symrec binary
 * ($SYMREC_BIN through run_cmd.h) with a NULL-terminated list of words, keep its exit
 * code and both streams, and check the usual shapes: success with nothing on stderr,
 * one "symrec: error: ..." line with exit 1. test_cli.c keeps its own copies (it
 * predates this file); new CLI tests use these.
 */
#ifndef SR_TEST_CLI_CASE_H
#define SR_TEST_CLI_CASE_H

#include <stdbool.h>

typedef struct cli_result {
    int code;  /* exit status (run_cmd.h) */
    char *out; /* stdout, owned */
    char *err; /* stderr, owned */
} cli_result;

/* Runs symrec with words[] (NULL-terminated, after the binary), under $SYMREC_WRAP.
 * Fails the test if the binary cannot be started. */
void cli_case_run(cli_result *r, const char *const *words);

/* Runs `prefix` (a NULL-terminated command line that runs another, e.g. setpriv with
 * its options) with the symrec binary and words[] after it, not under $SYMREC_WRAP.
 * prefix NULL: cli_case_run. */
void cli_case_run_under(cli_result *r, const char *const *prefix, const char *const *words);

#define CLI_RUN(r, ...)                                                                            \
    do {                                                                                           \
        const char *const cli_words_[] = {__VA_ARGS__, NULL};                                      \
        cli_case_run((r), cli_words_);                                                             \
    } while (0)

void cli_result_free(cli_result *r);

/* Exit 0 (notes on stderr allowed), else the test fails showing stderr. */
void cli_expect_ok(const cli_result *r);

/* Exit 1, nothing on stdout, stderr exactly one "symrec: error: " line containing
 * needle (NULL: any). */
void cli_expect_error(const cli_result *r, const char *needle);

/* The test fails unless haystack contains needle. */
void cli_expect_contains(const char *haystack, const char *needle);

/* Whether path names anything (stat). */
bool cli_path_exists(const char *path);

/* The permission bits of path (lstat), or -1 when it does not exist. */
int cli_path_mode(const char *path);

/* Creates catalogue db through the library with part P1 (material `material`, added
 * first with density 7.85 g/cm³ and family steel when it is not seeded; the
 * cylinder r 10, z 0..12 of 32 sides, axial), its instance 1 (serial `serial`) and
 * run 1 of it: a synthetic run (synth_run.h) of 12 layers x 72 sectors with section 1
 * dug over 10 layers (1..10) and section 2 over 3 (4..6), both 2 mm deep. When
 * mesh_path is not NULL the cylinder is also written there. */
void cli_case_synth_catalogue(const char *db, const char *serial, const char *material,
                              const char *mesh_path);

#endif
