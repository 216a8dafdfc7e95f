/*
 * test_cli_text.c: what catalogue text does on a terminal or in a spreadsheet (issue
 * 17, item 5; rules in cli/escape.c). A part whose name holds ESC[2J (clear the
 * screen) and a newline is listed as one line with the controls escaped, and comes
 * back exactly through --json; history --csv writes formula-leading text cells with a
 * leading "'" and leaves number cells alone.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support/cli_case.h"
#include "support/json_query.h"
#include "support/test_select.h"
#include "support/tmpdir.h"

typedef struct fixture {
    tmpdir dir;
    char db[TMPDIR_PATH_MAX];
    char cyl[TMPDIR_PATH_MAX];
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    assert_non_null(f);
    assert_int_equal(tmpdir_make(&f->dir), 0);
    tmpdir_join(&f->dir, "cat.db", f->db);
    tmpdir_join(&f->dir, "cyl.stl", f->cyl);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    tmpdir_remove(&f->dir);
    free(f);
    return 0;
}

/* No byte of text is a control character other than the newline ending a line, and
 * no C1 control (U+0080-U+009F) is in it; returns the number of lines. */
static size_t expect_terminal_safe(const char *text)
{
    size_t lines = 0;
    for (const unsigned char *p = (const unsigned char *)text; *p; p++) {
        if (*p == '\n')
            lines++;
        else if (*p < 0x20 || *p == 0x7f || (p[0] == 0xc2 && p[1] >= 0x80 && p[1] <= 0x9f))
            fail_msg("raw control byte 0x%02x at offset %ld in: %s", *p,
                     (long)(p - (const unsigned char *)text), text);
    }
    return lines;
}

static const char evil_name[] = "shaft\x1b[2J\nforged line\x7f";
static const char evil_notes[] = "tab\there\r\xc2\x9b"
                                 "31m \xc3\xa9t\xc3\xa9 back\\slash";

static void add_evil_part(const fixture *f)
{
    cli_case_synth_catalogue(f->db, "S1", "steel", f->cyl);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "add", "--number", "EV-1", "--name", evil_name, "--material",
            "steel", "--mesh", f->cyl, "--notes", evil_notes);
    cli_expect_ok(&r);
    expect_terminal_safe(r.err);
    cli_result_free(&r);
}

static void control_characters_in_a_name_are_escaped_on_one_line(void **state)
{
    const fixture *f = *state;
    add_evil_part(f);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "list");
    cli_expect_ok(&r);
    assert_int_equal(expect_terminal_safe(r.out), 3); /* header, P1, EV-1 */
    cli_expect_contains(r.out, "shaft\\x1b[2J\\nforged line\\x7f");
    cli_result_free(&r);

    CLI_RUN(&r, "--db", f->db, "part", "show", "EV-1");
    cli_expect_ok(&r);
    expect_terminal_safe(r.out);
    cli_expect_contains(r.out, "  name:       shaft\\x1b[2J\\nforged line\\x7f\n");
    /* printable UTF-8 and the backslash stay as they are; C1 CSI is escaped */
    cli_expect_contains(r.out,
                        "  notes:      tab\\there\\r\\u009b31m \xc3\xa9t\xc3\xa9 back\\slash\n");
    cli_result_free(&r);
}

static void json_output_round_trips_control_characters_exactly(void **state)
{
    const fixture *f = *state;
    add_evil_part(f);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "part", "show", "EV-1", "--json");
    cli_expect_ok(&r);
    expect_terminal_safe(r.out);
    assert_true(jq_valid(r.out));
    char *name = jq_text(r.out, "$.name"), *notes = jq_text(r.out, "$.notes");
    assert_non_null(name);
    assert_non_null(notes);
    assert_string_equal(name, evil_name);
    assert_string_equal(notes, evil_notes);
    free(name);
    free(notes);
    cli_result_free(&r);
}

static void history_csv_neutralises_formula_text_and_keeps_numbers(void **state)
{
    const fixture *f = *state;
    cli_case_synth_catalogue(f->db, "=HYPERLINK(\"http://x\",\"y\")", "@steel", NULL);
    cli_result r;
    CLI_RUN(&r, "--db", f->db, "history", "--csv");
    cli_expect_ok(&r);
    const char *row = strstr(r.out, "\r\n");
    assert_non_null(row);
    row += 2;
    /* run_id and instance_id are numbers: as they are */
    assert_true(strncmp(row, "1,", 2) == 0);
    cli_expect_contains(row, ",1,P1,\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\",\"'@steel\",");
    /* the missing volume is written as a plain number, unquoted */
    const char *vol = strstr(row, ",ok,2,");
    assert_non_null(vol);
    char *end;
    double v = strtod(vol + 6, &end);
    assert_true(v > 0 && *end == ',');
    cli_result_free(&r);

    CLI_RUN(&r, "--db", f->db, "history", "--summary", "--csv");
    cli_expect_ok(&r);
    cli_expect_contains(r.out, "\r\nP1,1,");
    cli_result_free(&r);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    struct CMUnitTest tests[] = {
        T(control_characters_in_a_name_are_escaped_on_one_line),
        T(json_output_round_trips_control_characters_exactly),
        T(history_csv_neutralises_formula_text_and_keeps_numbers),
    };
#undef T
    size_t n = sr_test_select(tests, sizeof tests / sizeof tests[0]);
    return _cmocka_run_group_tests("tests", tests, n, NULL, NULL);
}
