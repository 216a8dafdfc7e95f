/*
 * cli.h: what the files of cli/ share: the command signature and table entry, exit
 * codes, the global context (which catalogue), the strict argument parser, the one-line
 * diagnostics, and the human formatting helpers (tables, symmetry, units).
 *
 * Only cli/ prints or exits. Every command is one cmd_<name>.c with its usage text at
 * the top; a command gets argv starting at its own name and returns an exit code:
 * 0 ok, 1 failure (the library refused: "symrec: error: ..."), 2 usage
 * ("symrec: usage: ..."). Results go to stdout, progress and diagnostics to stderr,
 * and every diagnostic is exactly one line.
 */
#ifndef SR_CLI_H
#define SR_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "catalog/catalog.h"
#include "base/status.h"
#include "base/symmetry.h"
#include "mesh/mesh.h"
#include "mesh/scan_describe.h"
#include "mesh/units.h"

enum {
    CLI_OK = 0,
    CLI_FAIL = 1,
    CLI_USAGE = 2,
};

/* Global options, parsed by main.c before the command. */
typedef struct cli_ctx {
    const char *db_path; /* --db, else $SYMREC_DB, else CLI_DEFAULT_DB */
    bool read_only;      /* --read-only: open the catalogue read-only, refuse writes */
    bool quiet;          /* --quiet: no progress, no notes */
} cli_ctx;

#define CLI_DEFAULT_DB "./symrec.db"

/* A command: argv[0] is the command's own name; returns the exit code. */
typedef int (*cli_fn)(const cli_ctx *ctx, int argc, char **argv);

typedef struct cli_command {
    const char *name;
    cli_fn fn;
    const char *summary; /* one line for `symrec --help` */
} cli_command;

int cmd_catalog(const cli_ctx *ctx, int argc, char **argv);
int cmd_part(const cli_ctx *ctx, int argc, char **argv);
int cmd_instance(const cli_ctx *ctx, int argc, char **argv);
int cmd_export(const cli_ctx *ctx, int argc, char **argv);
int cmd_params(const cli_ctx *ctx, int argc, char **argv);
int cmd_demo(const cli_ctx *ctx, int argc, char **argv);
int cmd_fixtures(const cli_ctx *ctx, int argc, char **argv);
int cmd_check(const cli_ctx *ctx, int argc, char **argv);
int cmd_convert(const cli_ctx *ctx, int argc, char **argv);
int cmd_reconstruct(const cli_ctx *ctx, int argc, char **argv);
int cmd_run(const cli_ctx *ctx, int argc, char **argv);
int cmd_compare(const cli_ctx *ctx, int argc, char **argv);
int cmd_identify(const cli_ctx *ctx, int argc, char **argv);
int cmd_history(const cli_ctx *ctx, int argc, char **argv);
int cmd_report(const cli_ctx *ctx, int argc, char **argv);
int cmd_rules(const cli_ctx *ctx, int argc, char **argv);
int cmd_materials(const cli_ctx *ctx, int argc, char **argv);
int cmd_plan(const cli_ctx *ctx, int argc, char **argv);
int cmd_symmetry(const cli_ctx *ctx, int argc, char **argv);
int cmd_inspect(const cli_ctx *ctx, int argc, char **argv);

/* ---- the heap (cli/main.c): big blocks kept on one heap, not trimmed ---- */

/* Gives the heap's free pages back to the system: once, before a command writes its
 * files after long work (reconstruct). */
void cli_heap_give_back(void);

/* ---- diagnostics (cli/diag.c): each prints exactly one line to stderr ---- */

/* "symrec: error: <msg>"; returns CLI_FAIL. */
int cli_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Prints a library failure: err->msg, or the status name when the library left it
 * empty. Returns CLI_FAIL. */
int cli_fail(sr_status status, const sr_err *err);

/* "symrec: usage: <msg>"; returns CLI_USAGE. */
int cli_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* "symrec: <msg>": progress and notes; nothing after cli_set_quiet(true). */
void cli_note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* --quiet: cli_note prints nothing (errors and usage lines still do). */
void cli_set_quiet(bool quiet);

/* ---- arguments (cli/args.c) ---- */

/* One option of a command: a value option stores its argument in *value (the last
 * one given wins); a flag (value == NULL) sets *flag to true. */
typedef struct cli_opt {
    const char *name; /* with the dashes: "--layers" */
    const char **value;
    bool *flag;
} cli_opt;

typedef struct cli_spec {
    const char *cmd;      /* "part add", for messages */
    const char *usage;    /* printed to stdout for --help */
    const cli_opt *opts;  /* terminated by { NULL } */
    int min_pos, max_pos; /* allowed number of positional arguments */
    const char *pos_name; /* what a positional is, for messages ("ID") */
} cli_spec;

/* Parses argv[0..argc) (the words after the command and subcommand names): options
 * as `--name VALUE` or `--name=VALUE`, positionals into pos[] (room for max_pos),
 * `--` ends the options. `--help` prints spec->usage to stdout. Returns true when the
 * command should run; false with *rc = 0 after --help, or *rc = CLI_USAGE after
 * printing a usage error (unknown option, missing value, wrong positional count). */
bool cli_parse(const cli_spec *spec, int argc, char **argv, const char **pos, int *pos_count,
               int *rc);

/* Strict number parsing of option values: the whole string must parse, be finite and
 * lie in [min, max]. On failure prints "symrec: usage: bad OPT 'TEXT': expected WHAT"
 * and returns false (*out untouched). */
bool cli_parse_int(const char *opt, const char *text, long min, long max, const char *what,
                   int *out);
bool cli_parse_id(const char *opt, const char *text, int64_t *out);
bool cli_parse_double(const char *opt, const char *text, double min, double max, const char *what,
                      double *out);

/* A real calendar date written YYYY-MM-DD. */
bool cli_date_valid(const char *text);

/* Builds a symmetry from --symmetry/--order/--shift (any may be NULL). With no
 * --symmetry, *out is kind NONE and --order/--shift are usage errors. allow_auto: 1
 * takes "--order auto" (SR_ORDER_AUTO: found by reconstruct; a catalogue keeps only
 * orders). Prints the usage error and returns false on failure. */
bool cli_parse_symmetry(const char *kind, const char *order, const char *shift, int allow_auto,
                        sr_symmetry *out);

/* One subcommand of a command group: its name and what runs it, given the words after
 * it. */
typedef struct cli_subcommand {
    const char *name;
    int (*run)(const cli_ctx *ctx, int argc, char **argv);
} cli_subcommand;

/* The one dispatcher of every command group (`part add`, `rules enable`, ...): argv[1]
 * picks the subcommand from subs (ended by a NULL name), which runs with the words
 * after it; --help / -h print `usage`; a missing or unknown one is a usage error
 * naming the group. Returns the exit code. */
int cli_run_subcommand(const cli_ctx *ctx, const char *cmd, const char *usage,
                       const cli_subcommand *subs, int argc, char **argv);

/* ---- mesh files the user names (cli/mesh_in.c) ---- */

/* The help line every command that reads a mesh file shows for --units. */
#define CLI_UNITS_HELP                                                                             \
    "  --units U      the unit the mesh file is drawn in: mm, cm, m or in (default: the\n"         \
    "                 format's own: mm for .stl .obj .ply .off, m for .gltf .glb, glTF's\n"        \
    "                 unit); read into mm. A glTF keeps its axes (Y up) unless symrec\n"           \
    "                 wrote it\n"

/* --units' value (`opt` names the option in messages) into *out: NULL gives
 * SR_UNIT_DEFAULT. Anything but mm, cm, m, in is a usage error ("bad --units 'x':
 * expected mm, cm, m or in", printed) and false. */
bool cli_parse_units(const char *opt, const char *text, sr_unit *out);

/* Reads mesh file `path` drawn in `unit` (SR_UNIT_DEFAULT: its format's own) into *out
 * in mm (sr_mesh_read_units), and prints one warning when its size is not a machined
 * part's but would be in another unit. *used (may be NULL) gets the unit read in, never
 * SR_UNIT_DEFAULT. On failure *out is untouched and err says why. */
sr_status cli_mesh_read(const char *path, sr_unit unit, sr_mesh *out, sr_unit *used, sr_err *err);

/* ---- catalogue (cli/open.c) ---- */

/* What a command does with the catalogue. */
typedef enum cli_access {
    CLI_READ,       /* only reads: opened read-only (an older schema is migrated first) */
    CLI_WRITE,      /* writes: refused in one line when the catalogue is read-only */
    CLI_CREATE,     /* writes, and creates the file when missing */
    CLI_READ_CACHE, /* reads, and stores what it computed (descriptors) when it can:
                     * read-write when the catalogue can be written and --read-only is
                     * not given, otherwise as CLI_READ */
} cli_access;

/* Opens ctx's catalogue for `access`. Except with CLI_CREATE a missing file is an
 * error that says how to create one. For CLI_WRITE/CLI_CREATE, `why` says what the
 * command would write ("record the run"): a catalogue that cannot be written (file,
 * folder or --read-only) is refused as "catalogue 'X' is read-only: cannot <why>"
 * before anything else is done. Prints the error and returns false on failure. */
bool cli_open(const cli_ctx *ctx, cli_access access, const char *why, sr_catalog **out);

/* ---- records gathered in memory (cli/collect.c) ----
 * The catalogue hands records to a callback; commands that print tables or look other
 * records up per row first gather them here (no catalogue call runs inside a callback). */

typedef struct cli_parts {
    sr_part_info *v;
    size_t count, cap;
} cli_parts;

typedef struct cli_instances {
    sr_instance_info *v;
    size_t count, cap;
} cli_instances;

/* Loads the matching parts / the instances of `part` (number or id; NULL = all).
 * On failure the vector is empty and err says why. Release with the _release calls. */
sr_status cli_parts_load(sr_catalog *cat, const sr_part_filter *filter, cli_parts *out,
                         sr_err *err);
void cli_parts_release(cli_parts *parts);
sr_status cli_instances_load(sr_catalog *cat, const char *part, cli_instances *out, sr_err *err);
void cli_instances_release(cli_instances *instances);

/* ---- printers shared by several commands ---- */

/* cmd_part.c: the part table (`part list`, `demo`) and one part in full with its
 * instances (`part show`, `demo`). Return an exit code. */
int cli_part_list_print(sr_catalog *cat, const sr_part_filter *filter, bool json);
int cli_part_show_print(sr_catalog *cat, const char *key, bool json);

/* cmd_part.c: what a removal took, as "2 instances and 3 runs" (the instances only
 * when `instances`), into buf. */
void cli_removal_str(const sr_removal *r, bool instances, char *buf, size_t size);

/* cmd_materials.c: whether material `name` is in the catalogue; if not, prints the
 * one-line refusal listing the known materials and how to add one (another failure:
 * its error line) and returns false. */
bool cli_material_known(sr_catalog *cat, const char *name);

/* cmd_instance.c: a table of instances; with_part adds the part number column. The
 * missing volume is the part's intact volume minus the instance's. Returns false
 * (after an error line) on failure. */
bool cli_instance_table(sr_catalog *cat, const cli_instances *list, bool with_part, int indent);

/* ---- text of the user's in output (cli/escape.c) ---- */

/* s as it may reach a terminal: control characters (C0, DEL, C1) written as escapes
 * ("\x1b", "\n", "\u009b"), bytes that are not UTF-8 as "\xHH", printable UTF-8 as it
 * is. Returns s itself when nothing changes, else one of 8 rotating static buffers
 * (so up to 8 may appear in one printf; texts over 1100 bytes may be cut). NULL gives
 * NULL. For every plain-text print of catalogue text; JSON escapes on its own. */
const char *cli_tx(const char *s);

/* cli_tx into a new malloc'd string of any length (NULL when out of memory). */
char *cli_tx_dup(const char *s);

/* One CSV cell and its separator (',' or, when last, CRLF), quoted as RFC 4180 wants.
 * A text cell starting with '=', '+', '-', '@', TAB or CR is written with a leading
 * "'" so a spreadsheet does not run it as a formula; a number cell never is. */
void cli_csv_text(FILE *f, const char *s, bool last);
void cli_csv_number(FILE *f, const char *s, bool last);

/* ---- human output (cli/format.c) ---- */

/* "axial, continuous", "axial, 6-fold", "mirror", "glide, shift 10 mm",
 * "glide, shift by search", "-" (none). */
const char *cli_sym_str(const sr_symmetry *sym, char *buf, size_t size);

/* A text table: cells added row by row, columns sized to their widest cell (counted
 * in UTF-8 characters) and aligned right when `right` is set. */
#define CLI_TABLE_MAX_COLS 16

typedef struct cli_table {
    size_t cols;
    const char *const *headers;
    const bool *right;
    char **cells; /* rows * cols strings, owned */
    size_t cell_count, cell_cap;
    bool failed; /* out of memory while adding */
} cli_table;

void cli_table_init(cli_table *t, size_t cols, const char *const *headers, const bool *right);
void cli_table_cell(cli_table *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prints the table (a header line, then the rows), every line indented by `indent`
 * spaces; at most CLI_TABLE_MAX_COLS columns. Returns false (after an error line) if a
 * cell could not be stored. */
bool cli_table_print(const cli_table *t, FILE *f, int indent);
void cli_table_release(cli_table *t);

/* A labelled bounding box in mm, with its size on a second line. */
void cli_print_bbox(FILE *f, const char *label, const double min[3], const double max[3]);

/* A run's description as `run show` and `reconstruct` print it (cli/cmd_run.c): one
 * "    features of N: {...}" line per described section, then "  advice:" with one
 * line per advice ("  advice:      none" without). */
void cli_run_advice_print(const sr_run *r);

/* ---- symmetry proposals (cli/cmd_symmetry.c) ---- */

/* Fits the symmetry of `scan` (align/symmetry_fit.h) and its JSON object
 * (run/run_symfit.h, *fit_json malloc'd). */
struct sr_symmetry_fit;
sr_status cli_symfit_run(const sr_mesh *scan, struct sr_symmetry_fit *fit, char **fit_json,
                         sr_err *err);

/* reconstruct --symmetry auto: fits `scan`, notes the proposal on stderr and sets *sym
 * to it and *fit_json (malloc'd). False after an error line. */
bool cli_symfit_auto(const sr_mesh *scan, const char *source, sr_symmetry *sym, char **fit_json);

/* "<label><summary>" on stdout from a fit's JSON object; nothing for NULL. */
void cli_symfit_print_line(const char *label, const char *fit_json);

/* The nominal's second opinion (cli/nominal_out.c), human-readable: the registration,
 * the totals, a table "symmetry vs nominal" per section, the pieces only the nominal
 * sees and the sections only the symmetry sees, the flag. n NULL: one line "nominal:
 * no nominal (why)". */
void cli_nominal_print(const sr_run_nominal *n, const char *why_none);

/* reconstruct's second opinion: the intact mesh of part part_id (0 = a --mesh run:
 * none) compared with the reconstruction r of scan (nominal.h). *out = the record, or
 * NULL with why[] saying why there is none (no intact mesh, --no-nominal, the
 * comparison failed). With reference_nominal the nominal is the restoration:
 * r->restored becomes the registered intact mesh and *patches the nominal's missing
 * pieces; a nominal that is missing, fails or does not fit the scan is then an error
 * (one line, CLI_FAIL). Returns CLI_OK or CLI_FAIL. */
struct sr_recon_result;
int cli_nominal_step(sr_catalog *cat, int64_t part_id, const sr_mesh *scan,
                     struct sr_recon_result *r, double min_volume_mm3, bool skip,
                     bool reference_nominal, sr_run_nominal **out, sr_mesh *patches, char *why,
                     size_t why_size);

/* "label value" on one line, the value written with cli_tx (user text). */
void cli_print_field(FILE *f, const char *label, const char *value);

/* ---- identification (cli/cmd_identify.c) ---- */

/* Prints an identification as `symrec identify` does (table and verdict, or JSON);
 * `scan` names the file. Returns the exit code of the printing (0, or 1 when the JSON
 * could not be written). */
struct sr_identify_result;
int cli_identify_print(const struct sr_identify_result *res, const char *scan, bool json);

/* ---- input meshes read as scans (cli/scan_out.c) ---- */

/* True when d is a plain closed part: no opening, one component, no non-manifold edge. */
bool cli_scan_is_plain(const sr_scan_desc *d);
/* The description as `check` prints it: lines on stdout. */
void cli_scan_print(const sr_scan_desc *d);
/* The description as reconstruct's text output prints it (stdout, the openings as the
 * scan gaps closed (rec, may be NULL: how each was closed), the strays as dropped),
 * nothing for a plain closed part. */
void cli_scan_summary(const sr_scan_desc *d, const sr_run_scan *rec);
/* Describes the input scan, closes its openings (sr_scan_close_openings_how) and drops
 * its strays from *scan (the caller prints it with cli_scan_summary). *out (released by
 * the caller) is the description before; *rec (sr_run_scan_free; NULL for a closed
 * input without strays) the run's record of its gaps. On failure both are untouched. */
sr_status cli_scan_input(sr_mesh *scan, sr_scan_desc *out, sr_run_scan **rec, sr_err *err);
/* The run record's scan gaps as `run show` prints them (nothing when s is NULL). */
void cli_run_scan_print(const sr_run_scan *s);

#endif
