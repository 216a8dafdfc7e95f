/* test_select: picks a test binary's tests from SYMREC_TEST_FILTER, SYMREC_TEST_SKIP
 * and SYMREC_TEST_SHARD (see test_select.h). */
#include "support/test_select.h"

#include <fnmatch.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Whether name matches one of the comma-separated globs of list. Blanks round a glob
 * are not part of it: a list continued over lines in the Makefile (backslash-newline
 * becomes a space) put a space before the first glob of every line, which then
 * matched nothing (four of VALGRIND_SKIP's globs: whole reconstructions ran under
 * Memcheck, and test_cli's shards took 3 to 8 min there on a loaded machine). */
static bool matches_one_of(const char *name, const char *list)
{
    char glob[256];
    for (const char *p = list; *p;) {
        while (*p == ' ' || *p == '\t' || *p == '\n')
            p++;
        size_t len = strcspn(p, ",");
        size_t end = len;
        while (end > 0 && (p[end - 1] == ' ' || p[end - 1] == '\t' || p[end - 1] == '\n'))
            end--;
        if (end > 0 && end < sizeof glob) {
            memcpy(glob, p, end);
            glob[end] = '\0';
            if (fnmatch(glob, name, 0) == 0)
                return true;
        }
        p += len;
        if (*p == ',')
            p++;
    }
    return false;
}

/* Keeps the tests matching one of list's globs (keep) or none of them (!keep). */
static size_t select_by_name(struct CMUnitTest *tests, size_t n, const char *list, bool keep)
{
    if (!list || !*list)
        return n;
    size_t kept = 0;
    for (size_t i = 0; i < n; i++)
        if (matches_one_of(tests[i].name, list) == keep)
            tests[kept++] = tests[i];
    return kept;
}

size_t sr_test_select(struct CMUnitTest *tests, size_t n)
{
    n = select_by_name(tests, n, getenv("SYMREC_TEST_FILTER"), true);
    n = select_by_name(tests, n, getenv("SYMREC_TEST_SKIP"), false);
    const char *shard = getenv("SYMREC_TEST_SHARD");
    if (!shard || !*shard)
        return n;
    int k = 0, of = 0;
    char extra;
    if (sscanf(shard, "%d/%d%c", &k, &of, &extra) != 2 || of < 1 || k < 1 || k > of) {
        fprintf(stderr, "SYMREC_TEST_SHARD: '%s' is not K/N with 1 <= K <= N\n", shard);
        exit(2);
    }
    size_t kept = 0;
    for (size_t i = 0; i < n; i++)
        if (i % (size_t)of == (size_t)(k - 1))
            tests[kept++] = tests[i];
    return kept;
}
