/*
 * cli_case.c: running symrec and checking its result for the CLI test files (see
 * cli_case.h).
 */
#include "support/cli_case.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "support/run_cmd.h"

void cli_case_run_under(cli_result *r, const char *const *prefix, const char *const *words)
{
    const char *argv[64];
    size_t n = 0;
    for (size_t i = 0; prefix && prefix[i]; i++) {
        assert_true(n < 62);
        argv[n++] = prefix[i];
    }
    argv[n++] = sr_test_bin();
    for (size_t i = 0; words[i]; i++) {
        assert_true(n < 63);
        argv[n++] = words[i];
    }
    argv[n] = NULL;
    r->code = prefix ? sr_test_run_native(argv, NULL, &r->out, &r->err)
                     : sr_test_run(argv, NULL, &r->out, &r->err);
    if (r->code < 0)
        fail_msg("cannot run %s (set SYMREC_BIN)", argv[0]);
}

void cli_case_run(cli_result *r, const char *const *words)
{
    cli_case_run_under(r, NULL, words);
}

void cli_result_free(cli_result *r)
{
    free(r->out);
    free(r->err);
    r->out = r->err = NULL;
}

void cli_expect_ok(const cli_result *r)
{
    if (r->code != 0)
        fail_msg("expected success, got exit %d; stderr: %s", r->code, r->err);
}

void cli_expect_error(const cli_result *r, const char *needle)
{
    if (r->code != 1)
        fail_msg("expected exit 1, got %d; stderr: %s", r->code, r->err);
    static const char prefix[] = "symrec: error: ";
    if (strncmp(r->err, prefix, sizeof prefix - 1) != 0)
        fail_msg("stderr does not start with '%s': %s", prefix, r->err);
    const char *nl = strchr(r->err, '\n');
    if (!nl || nl[1] != '\0')
        fail_msg("stderr is not exactly one line: %s", r->err);
    if (needle && !strstr(r->err, needle))
        fail_msg("stderr lacks '%s': %s", needle, r->err);
    assert_string_equal(r->out, "");
}

void cli_expect_contains(const char *haystack, const char *needle)
{
    if (!strstr(haystack, needle))
        fail_msg("'%s' not found in: %s", needle, haystack);
}

bool cli_path_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int cli_path_mode(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0 ? (int)(st.st_mode & 07777) : -1;
}
