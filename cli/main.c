/*
 * main.c: the symrec command line's entry point: the command table, the global
 * options parsed before the command (--db, --help, --version), and dispatch, including
 * `symrec help CMD [SUB]`. Each command lives in its own cli/cmd_<name>.c.
 *
 * Exit codes: 0 ok, 1 failure, 2 usage. The catalogue is --db FILE, else $SYMREC_DB,
 * else ./symrec.db.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "cli.h"
#include "base/version.h"

/* A big scan's pipeline allocates and frees arrays of tens of megabytes many times
 * over (each copy, description and closing of the scan); glibc maps each afresh and
 * the kernel zero-fills its pages again: on a 1.86M-triangle open scan a sixth of the
 * run went to page faults. Kept on the heap and not trimmed, the blocks are reused:
 * 41.4 s -> 32.5 s wall, peak memory 524 -> 608 MB (measured on that scan). The
 * library leaves the heap to this policy: it trimmed it after the alignment and in
 * each union once, and the union's arrays then faulted their pages in again (the
 * 1.85M-triangle open scan: 1.0-1.9 s more, the same peak; a 1.09M closed scan's peak
 * is 2 % higher without). One heap for every thread: glibc gives each thread that
 * allocates an arena of its own, whose blocks the main thread never reuses, so the
 * crossing search's candidate pairs (made on two threads) stayed mapped beside the
 * main heap for the rest of the run (a 1.09M closed scan: peak 318 -> 232 MB with the
 * arenas shared). */
static void keep_big_blocks(void)
{
#ifdef __GLIBC__
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_ARENA_MAX, 1);
#endif
}

/* Once, when the work is done and only the files are left to write: the free pages
 * the phases left between their blocks go back to the system, so the files' buffers
 * (a GLB holds the scan's geometry twice while tinygltf writes it) take pages in
 * those holes rather than growing the heap past the run's peak (a 1.02M open scan:
 * 195 -> 177 MB; the 1 and 2M closed and the 2M open scans 1-2 MB lower, as fast). */
void cli_heap_give_back(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

static const char usage[] =
    "usage: symrec [--db FILE] [--read-only] [--quiet] COMMAND [ARGS...]\n"
    "       symrec --help | --version | help COMMAND [SUBCOMMAND]\n"
    "\n"
    "Restores damaged mechanical parts by their symmetry, keeping parts, damaged\n"
    "instances and their meshes in a catalogue (an SQLite file).\n"
    "\n"
    "Global options (before the command):\n"
    "  --db FILE    the catalogue; default: $SYMREC_DB if set, else " CLI_DEFAULT_DB "\n"
    "  --read-only  open the catalogue read-only: commands that only read work (as they\n"
    "               do on a catalogue this user cannot write), the others refuse\n"
    "  --quiet, -q  no progress, notes or warnings on stderr (errors stay)\n"
    "               The options above may also follow the command\n"
    "               ('symrec part list --db shop.db').\n"
    "  --help       this text\n"
    "  --version    print the version\n"
    "\n"
    "Commands:\n";

static const char usage_tail[] =
    "\n"
    "Every command takes --help. Commands with output take --json (one JSON value on\n"
    "stdout). Lengths are in mm, areas in mm², volumes in mm³.\n"
    "Exit status: 0 ok, 1 failure, 2 usage error.\n";

static int cmd_help(const cli_ctx *ctx, int argc, char **argv);

static const cli_command commands[] = {
    {"catalog", cmd_catalog, "create, describe, back up or check a catalogue"},
    {"part", cmd_part, "add, list, show, correct and remove parts (models with their mesh)"},
    {"instance", cmd_instance, "add, list, show, correct and remove damaged instances of a part"},
    {"export", cmd_export, "write a stored mesh to STL, OBJ, PLY, OFF, glTF or GLB"},
    {"check", cmd_check, "what a mesh file holds: size, volume, closed, pieces, unit"},
    {"convert", cmd_convert, "rewrite a mesh file in another format"},
    {"reconstruct", cmd_reconstruct, "restore a damaged instance or mesh by its symmetry"},
    {"symmetry", cmd_symmetry, "fit every kind of symmetry to a scan and propose one"},
    {"run", cmd_run, "list and show recorded reconstruction runs"},
    {"history", cmd_history, "repair history of a part, instance, material or date range"},
    {"report", cmd_report, "write a run's self-contained HTML report"},
    {"compare", cmd_compare, "volume difference and surface deviation of two meshes"},
    {"identify", cmd_identify, "which catalogue part a scan is of, ranked, or no match"},
    {"plan", cmd_plan, "plan the layer-by-layer rebuild of a run's missing section"},
    {"inspect", cmd_inspect, "check a repaired part against its run's restoration"},
    {"params", cmd_params, "list, show and set named parameter sets"},
    {"rules", cmd_rules, "list, show and edit the repair rules advice is drawn from"},
    {"materials", cmd_materials,
     "list, add and correct materials (density, family, process limits)"},
    {"demo", cmd_demo, "build the demo catalogue and show it"},
    {"fixtures", cmd_fixtures, "write the demo parts' meshes and known volumes"},
    {"help", cmd_help, "show the help of a command"},
};
static const size_t command_count = sizeof commands / sizeof commands[0];

static const cli_command *find_command(const char *name)
{
    for (size_t i = 0; i < command_count; i++)
        if (strcmp(commands[i].name, name) == 0)
            return &commands[i];
    return NULL;
}

static void print_usage(FILE *f)
{
    fputs(usage, f);
    for (size_t i = 0; i < command_count; i++)
        fprintf(f, "  %-12s %s\n", commands[i].name, commands[i].summary);
    fputs(usage_tail, f);
}

/* `symrec help CMD [SUB]` runs `symrec CMD [SUB] --help`. */
static int cmd_help(const cli_ctx *ctx, int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        print_usage(stdout);
        return CLI_OK;
    }
    if (argc > 3)
        return cli_usage_error("unexpected argument '%s' for 'help' (see 'symrec --help')",
                               argv[3]);
    const cli_command *cmd = find_command(argv[1]);
    if (!cmd)
        return cli_usage_error("unknown command '%s' (see 'symrec --help')", argv[1]);
    char help_flag[] = "--help";
    char *args[3] = {argv[1], argc == 3 ? argv[2] : help_flag, help_flag};
    return cmd->fn(ctx, argc == 3 ? 3 : 2, args);
}

/* One global option at argv[0]: the count of words it takes (1 or 2), 0 when it is not
 * one, -1 after a usage error. */
static int global_option(cli_ctx *ctx, int argc, char **argv)
{
    const char *arg = argv[0];
    if (strcmp(arg, "--read-only") == 0) {
        ctx->read_only = true;
        return 1;
    }
    if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0) {
        ctx->quiet = true;
        return 1;
    }
    if (strcmp(arg, "--db") == 0) {
        if (argc < 2 || argv[1][0] == '\0' || strncmp(argv[1], "--", 2) == 0) {
            cli_usage_error("option '--db' needs a file name");
            return -1;
        }
        ctx->db_path = argv[1];
        return 2;
    }
    if (strncmp(arg, "--db=", 5) == 0) {
        if (arg[5] == '\0') {
            cli_usage_error("option '--db' needs a file name");
            return -1;
        }
        ctx->db_path = arg + 5;
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    keep_big_blocks();
    cli_ctx ctx = {0};
    const char *env = getenv("SYMREC_DB");
    ctx.db_path = env && env[0] ? env : CLI_DEFAULT_DB;

    int i = 1;
    for (; i < argc && argv[i][0] == '-'; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            print_usage(stdout);
            return CLI_OK;
        }
        if (strcmp(arg, "--version") == 0) {
            printf("symrec %s\n", SR_VERSION);
            return CLI_OK;
        }
        int used = global_option(&ctx, argc - i, argv + i);
        if (used < 0)
            return CLI_USAGE;
        if (used == 0)
            return cli_usage_error("unknown option '%s' (see 'symrec --help')", arg);
        i += used - 1;
    }
    /* the global options may also follow the command ('symrec part list --db F'):
     * taken out of its arguments, up to a '--' */
    int kept = i + 1;
    for (int k = i + 1; k < argc; k++) {
        if (strcmp(argv[k], "--") == 0) {
            while (k < argc)
                argv[kept++] = argv[k++];
            break;
        }
        int used = global_option(&ctx, argc - k, argv + k);
        if (used < 0)
            return CLI_USAGE;
        if (used == 0)
            argv[kept++] = argv[k];
        else
            k += used - 1;
    }
    argc = i < argc ? kept : argc;
    cli_set_quiet(ctx.quiet);
    if (i >= argc)
        return cli_usage_error("missing command (see 'symrec --help')");

    const cli_command *cmd = find_command(argv[i]);
    if (!cmd)
        return cli_usage_error("unknown command '%s' (see 'symrec --help')", argv[i]);
    int rc = cmd->fn(&ctx, argc - i, argv + i);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        cli_error("cannot write the output: standard output failed");
        return CLI_FAIL;
    }
    return rc;
}
