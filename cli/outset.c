/*
 * outset.c: output folders written as a set: a staging folder beside DIR, checked,
 * synced and swapped into place (the rules are in outset.h). The only code that
 * renames or removes output folders; the writers (src/plan/plan_export.c, the mesh
 * bridge) only create files in the folder they are given.
 */
#define _GNU_SOURCE /* renameat2, RENAME_EXCHANGE (glibc 2.28) */
#include "outset.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <fnmatch.h>
#include <ftw.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

/* ---- paths ---- */

/* malloc'd "a/b" (a may be ""). NULL when out of memory. */
static char *join(const char *a, const char *b)
{
    size_t n = strlen(a) + strlen(b) + 2;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s%s%s", a, *a ? "/" : "", b);
    return p;
}

/* Splits target into its parent folder ("." for a bare name) and last name, both
 * malloc'd; trailing slashes are ignored. False when out of memory. */
static bool split(const char *target, char **parent, char **base)
{
    size_t n = strlen(target);
    while (n > 1 && target[n - 1] == '/')
        n--;
    size_t b = n;
    while (b > 0 && target[b - 1] != '/')
        b--;
    *base = strndup(target + b, n - b);
    size_t p = b;
    while (p > 1 && target[p - 1] == '/')
        p--;
    *parent = b == 0 ? strdup(".") : strndup(target, p);
    return *base && *parent;
}

/* ---- removing a folder symrec wrote ---- */

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path) == 0 || errno == ENOENT ? 0 : -1;
}

/* Removes a staging or replaced folder with what is in it (symlinks not followed). */
static bool remove_tree(const char *path)
{
    return nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS) == 0;
}

/* ---- what is symrec's ---- */

/* Whether `name` is listed in the manifest text (one name per line after the first). */
static bool listed(const char *manifest, const char *name)
{
    size_t n = strlen(name);
    const char *line = manifest ? strchr(manifest, '\n') : NULL;
    while (line) {
        line++;
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        if (len == n && memcmp(line, name, n) == 0)
            return true;
        line = end;
    }
    return false;
}

/* The manifest of folder dir, malloc'd and NUL-terminated, or NULL when it has none
 * (or it is not one: a manifest starts with "symrec output set"). */
static char *read_manifest(const char *dir)
{
    char *path = join(dir, CLI_OUTSET_MANIFEST);
    FILE *f = path ? fopen(path, "rb") : NULL;
    free(path);
    if (!f)
        return NULL;
    char *text = malloc(1 << 20);
    size_t len = text ? fread(text, 1, (1 << 20) - 1, f) : 0;
    fclose(f);
    if (!text)
        return NULL;
    text[len] = '\0';
    if (strncmp(text, "symrec output set", 17) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

static bool ours(const cli_outset *s, const char *manifest, const char *name)
{
    if (strcmp(name, CLI_OUTSET_MANIFEST) == 0 || listed(manifest, name))
        return true;
    /* temporary files of a killed write (the mesh writers' and plan_export's) */
    if (fnmatch(".symrec-*.tmp", name, FNM_PERIOD) == 0 ||
        fnmatch("*.tmp-??????", name, FNM_PERIOD) == 0)
        return true;
    for (size_t i = 0; s->names[i]; i++)
        if (fnmatch(s->names[i], name, FNM_PERIOD) == 0)
            return true;
    return false;
}

/* Checks that every entry of the existing folder s->target is symrec's; prints the
 * refusal naming DIR and the first foreign entry otherwise. */
static bool only_ours(const cli_outset *s)
{
    DIR *d = opendir(s->target);
    if (!d) {
        cli_error("cannot read the output folder '%s': %s", s->dir, strerror(errno));
        return false;
    }
    char *manifest = read_manifest(s->target);
    bool ok = true;
    struct dirent *e;
    while (ok && (e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        if (!ours(s, manifest, e->d_name)) {
            cli_error("output folder '%s' holds '%s', which symrec did not write: give "
                      "--out a new or empty folder, or one that symrec %s wrote",
                      s->dir, e->d_name, s->cmd);
            ok = false;
        }
    }
    closedir(d);
    free(manifest);
    return ok;
}

/* ---- staging folders ---- */

/* Removes the staging folders of DIR in parent whose process is gone. */
static void clean_stale(const char *parent, const char *base)
{
    DIR *d = opendir(parent);
    if (!d)
        return;
    size_t plen = strlen(base) + 10; /* "." base ".partial-" */
    char *prefix = malloc(plen + 1);
    if (!prefix) {
        closedir(d);
        return;
    }
    snprintf(prefix, plen + 1, ".%s.partial-", base);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strncmp(e->d_name, prefix, plen) != 0)
            continue;
        char *end;
        long pid = strtol(e->d_name + plen, &end, 10);
        if (end == e->d_name + plen || *end != '-' || pid <= 0 || pid == (long)getpid())
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue; /* still running (or not ours to ask): leave it */
        char *path = join(parent, e->d_name);
        struct stat sb;
        if (path && lstat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
            remove_tree(path);
        free(path);
    }
    free(prefix);
    closedir(d);
}

/* A new empty folder ".<base>.partial-<pid>-XXXXXX" in parent (malloc'd path), mode
 * 0777 & ~umask. NULL with errno set on failure. */
static char *make_stage(const char *parent, const char *base)
{
    size_t n = strlen(parent) + strlen(base) + 48;
    char *path = malloc(n);
    if (!path) {
        errno = ENOMEM;
        return NULL;
    }
    snprintf(path, n, "%s/.%s.partial-%ld-XXXXXX", parent, base, (long)getpid());
    if (!mkdtemp(path)) {
        free(path);
        return NULL;
    }
    mode_t mask = umask(0);
    umask(mask);
    if (chmod(path, 0777 & ~mask) != 0) {
        int e = errno;
        rmdir(path);
        free(path);
        errno = e;
        return NULL;
    }
    return path;
}

static void outset_free(cli_outset *s)
{
    free(s->dir);
    free(s->target);
    free(s->stage);
    s->dir = s->target = s->stage = NULL;
}

bool cli_outset_begin(cli_outset *s, const char *dir, const char *cmd, const char *const *names)
{
    static const char *const none[] = {NULL};
    memset(s, 0, sizeof *s);
    s->cmd = cmd;
    s->names = names ? names : none;
    struct stat sb;
    bool exists = stat(dir, &sb) == 0;
    if (exists && !S_ISDIR(sb.st_mode)) {
        cli_error("cannot write into '%s': it exists and is not a folder", dir);
        return false;
    }
    s->dir = strdup(dir);
    /* an existing folder by its real path (a symlink's target is what gets replaced;
     * "." or "x/.." become names) */
    s->target = exists ? realpath(dir, NULL) : strdup(dir);
    char *parent = NULL, *base = NULL;
    if (!s->dir || !s->target || !split(s->target, &parent, &base)) {
        cli_error("cannot write into '%s': %s", dir, exists ? strerror(errno) : "out of memory");
        goto fail;
    }
    if (!*base || strcmp(base, ".") == 0 || strcmp(base, "..") == 0 ||
        strcmp(s->target, "/") == 0) {
        cli_error("cannot write into '%s': give the output folder by name", dir);
        goto fail;
    }
    if (exists && !only_ours(s))
        goto fail;
    clean_stale(parent, base);
    s->stage = make_stage(parent, base);
    if (!s->stage) {
        cli_error("cannot write the output folder '%s': %s", dir, strerror(errno));
        goto fail;
    }
    free(parent);
    free(base);
    return true;
fail:
    free(parent);
    free(base);
    outset_free(s);
    return false;
}

/* ---- committing ---- */

static bool sync_path(const char *path, int flags)
{
    int fd = open(path, flags | O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return false;
    /* some file systems refuse fsync on a folder: only a file's failure counts */
    bool ok = fsync(fd) == 0 || (flags & O_DIRECTORY);
    close(fd);
    return ok;
}

/* Writes the manifest (the command, then every file's name) and syncs every file and
 * the folder. False with errno set on failure. */
static bool seal(const cli_outset *s)
{
    DIR *d = opendir(s->stage);
    char *mpath = join(s->stage, CLI_OUTSET_MANIFEST);
    FILE *m = mpath && d ? fopen(mpath, "w") : NULL;
    bool ok = m != NULL;
    if (ok)
        fprintf(m, "symrec output set (%s)\n", s->cmd);
    struct dirent *e;
    while (ok && (e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0 ||
            strcmp(e->d_name, CLI_OUTSET_MANIFEST) == 0)
            continue;
        fprintf(m, "%s\n", e->d_name);
        char *path = join(s->stage, e->d_name);
        ok = path && sync_path(path, 0);
        free(path);
    }
    int saved = errno;
    if (m) {
        ok = fflush(m) == 0 && fsync(fileno(m)) == 0 && !ferror(m) && ok;
        saved = ok ? saved : errno;
        ok = fclose(m) == 0 && ok;
    }
    if (d)
        closedir(d);
    free(mpath);
    ok = ok && sync_path(s->stage, O_DIRECTORY);
    errno = ok ? 0 : (saved ? saved : EIO);
    return ok;
}

/* Puts the staging folder in target's place; *old receives the folder that now holds
 * the replaced set (NULL when there was none). False with errno set. */
static bool swap_in(cli_outset *s, char **old)
{
    *old = NULL;
    struct stat sb;
    if (stat(s->target, &sb) != 0)
        return rename(s->stage, s->target) == 0;
    if (renameat2(AT_FDCWD, s->stage, AT_FDCWD, s->target, RENAME_EXCHANGE) == 0) {
        *old = s->stage;
        s->stage = NULL;
        return true;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != EOPNOTSUPP)
        return false;
    /* no exchange here: the old set aside under a staging name, then the new one in */
    char *parent, *base;
    if (!split(s->target, &parent, &base)) {
        errno = ENOMEM;
        return false;
    }
    char *aside = make_stage(parent, base);
    free(parent);
    free(base);
    if (!aside)
        return false;
    if (rename(s->target, aside) != 0) {
        int e = errno;
        rmdir(aside);
        free(aside);
        errno = e;
        return false;
    }
    if (rename(s->stage, s->target) != 0) {
        int e = errno;
        rename(aside, s->target); /* put the old set back */
        free(aside);
        errno = e;
        return false;
    }
    *old = aside;
    return true;
}

bool cli_outset_commit(cli_outset *s)
{
    if (!s->stage) {
        outset_free(s);
        return false;
    }
    bool ok = seal(s);
    int e = errno;
    const char *hook = getenv("SYMREC_TEST_OUTSET_FAIL");
    if (ok && hook && *hook) {
        ok = false;
        e = ENOSPC;
    }
    char *old = NULL;
    if (ok) {
        ok = swap_in(s, &old);
        e = errno;
    }
    if (!ok) {
        cli_error("cannot write the output folder '%s': %s", s->dir, strerror(e));
        cli_outset_abort(s);
        return false;
    }
    char *parent, *base;
    if (split(s->target, &parent, &base))
        sync_path(parent, O_DIRECTORY);
    free(parent);
    free(base);
    if (old && !remove_tree(old))
        cli_note("could not remove the replaced set '%s': %s", old, strerror(errno));
    free(old);
    outset_free(s);
    return true;
}

void cli_outset_abort(cli_outset *s)
{
    if (s->stage)
        remove_tree(s->stage);
    outset_free(s);
}
