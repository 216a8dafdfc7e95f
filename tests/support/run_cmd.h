/*
 * run_cmd.h: runs a command for the CLI tests and captures what it printed: both
 * streams in full, and its exit status. The symrec binary under test comes from
 * $SYMREC_BIN (default build/debug/symrec); $SYMREC_WRAP, if set, is a command line
 * to run it under (e.g. "valgrind -q --error-exitcode=99"), split on spaces and put in
 * front of argv. The child gets SYMREC_PROGRESS_AFTER=100000 unless the test set it:
 * no progress lines on stderr unless a test asks for them.
 */
#ifndef SR_TEST_RUN_CMD_H
#define SR_TEST_RUN_CMD_H

/* $SYMREC_BIN, else "build/debug/symrec". */
const char *sr_test_bin(void);

/* Runs argv[0] (looked up in PATH if it has no '/') with argv, NULL-terminated,
 * prefixed by the words of $SYMREC_WRAP when set. stdin_text (may be NULL: empty
 * input) is fed to its standard input. *out and *err receive what it wrote to
 * stdout and stderr as NUL-terminated strings, owned by the caller (free()); either
 * pointer may be NULL to discard that stream. Returns the exit status (0..255),
 * 128 + N if it was killed by signal N, or -1 if it could not be started (then *out
 * and *err are NULL). */
int sr_test_run(const char *const argv[], const char *stdin_text, char **out, char **err);

/* sr_test_run without $SYMREC_WRAP: for the commands that only set a test up (fill a
 * catalogue with runs) and are tested under the wrap by tests of their own. */
int sr_test_run_native(const char *const argv[], const char *stdin_text, char **out, char **err);

#endif
