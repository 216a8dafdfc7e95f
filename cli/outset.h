/*
 * outset.h: an output folder written as a set (`plan --out DIR`, `reconstruct --out
 * DIR`): the command writes every file into a staging folder beside DIR, then
 * cli_outset_commit puts the whole set in place at once, so DIR only ever holds one
 * complete set - never files of two runs side by side, never half a set after a
 * failure or a kill.
 *
 *   cli_outset s;
 *   if (!cli_outset_begin(&s, out, "plan", plan_names))   // refused: one line printed
 *       return CLI_FAIL;
 *   ... write files into s.stage ...
 *   ok ? cli_outset_commit(&s) : cli_outset_abort(&s);
 *
 * How symrec knows a folder is its own: every set holds a manifest, ".symrec-set",
 * naming the command and the files it wrote. An existing DIR may be replaced when each
 * entry in it is the manifest, a file the manifest lists, or a name the command itself
 * writes (`names`, fnmatch patterns: sets written before the manifest existed, and
 * temporary files of killed earlier writes); an empty DIR may be replaced too. Any
 * other entry is the user's: the command refuses in one line naming DIR, before it
 * does its work, and deletes nothing.
 *
 * Staging folders are named ".<DIR's name>.partial-<pid>-XXXXXX" in DIR's parent.
 * One left by a killed run is removed by the next write to the same DIR: any whose
 * process <pid> no longer runs (kill(pid, 0) says ESRCH).
 *
 * Putting the set in place: when DIR exists, Linux renameat2(RENAME_EXCHANGE) swaps
 * the two folders atomically and the old set (now under the staging name) is then
 * removed; where the file system cannot exchange, DIR is first renamed aside under a
 * staging name. A new DIR is a plain rename. Every file, the staging folder and the
 * parent are fsync'ed around the rename.
 *
 * Modes: the staging folder (which becomes DIR) gets 0777 & ~umask, like mkdir; every
 * file in a set is created 0666 & ~umask, like fopen (the writers' own rule).
 *
 * Test hook: with SYMREC_TEST_OUTSET_FAIL set, cli_outset_commit fails just before
 * the rename, as a full disk would (the staging folder is removed, DIR is untouched).
 */
#ifndef SR_CLI_OUTSET_H
#define SR_CLI_OUTSET_H

#include <stdbool.h>

/* The manifest's file name inside every set. */
#define CLI_OUTSET_MANIFEST ".symrec-set"

typedef struct cli_outset {
    char *dir;    /* DIR as the user gave it (messages) */
    char *target; /* DIR with a symlink or '.' resolved: what is replaced */
    char *stage;  /* the staging folder: write the set's files in here */
    const char *cmd;
    const char *const *names;
} cli_outset;

/* Checks DIR (a folder that symrec wrote, an empty one, or none yet, in an existing
 * parent), removes stale staging folders of DIR and creates a new one. `cmd` names the
 * command in the manifest; `names` (NULL-terminated fnmatch patterns) are the files
 * the command writes. On failure prints one error line naming DIR, returns false and
 * leaves *s empty (cli_outset_abort accepts it). */
bool cli_outset_begin(cli_outset *s, const char *dir, const char *cmd, const char *const *names);

/* Writes the manifest, syncs, and puts the staging folder in DIR's place, removing the
 * set it replaces. On failure prints one error line, removes the staging folder and
 * leaves DIR as it was. Frees s either way. */
bool cli_outset_commit(cli_outset *s);

/* Removes the staging folder and frees s (after a failure); accepts a set that was
 * never begun or already committed. */
void cli_outset_abort(cli_outset *s);

#endif
