/*
 * tmpdir.c: temporary directories and exact-byte files for tests (see tmpdir.h).
 */
#define _XOPEN_SOURCE 700   /* nftw */
#include "tmpdir.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int tmpdir_make(tmpdir *dir)
{
    strcpy(dir->path, "/tmp/symrec-test-XXXXXX");
    if (!mkdtemp(dir->path)) {
        dir->path[0] = '\0';
        return -1;
    }
    return 0;
}

int tmpdir_setup(void **state)
{
    tmpdir *d = malloc(sizeof *d);
    if (!d || tmpdir_make(d) != 0) {
        free(d);
        return -1;
    }
    *state = d;
    return 0;
}

int tmpdir_teardown(void **state)
{
    tmpdir_remove(*state);
    free(*state);
    return 0;
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st;
    (void)flag;
    (void)ftw;
    if (remove(path) != 0 && errno != ENOENT) {
        /* a directory made read-only by a test: make it writable and retry */
        chmod(path, 0700);
        remove(path);
    }
    return 0;
}

void tmpdir_remove(tmpdir *dir)
{
    if (!dir || !dir->path[0])
        return;
    /* never delete anything that is not ours, whatever the struct holds */
    if (strncmp(dir->path, "/tmp/symrec-test-", 17) != 0 || strstr(dir->path, "..")) {
        fprintf(stderr, "tmpdir_remove: refusing to remove '%s'\n", dir->path);
        abort();
    }
    chmod(dir->path, 0700);
    nftw(dir->path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    dir->path[0] = '\0';
}

char *tmpdir_join(const tmpdir *dir, const char *name, char out[TMPDIR_PATH_MAX])
{
    int n = snprintf(out, TMPDIR_PATH_MAX, "%s%s%s", dir->path, name[0] ? "/" : "", name);
    if (n <= 0 || n >= TMPDIR_PATH_MAX) {   /* a test bug: never run on a cut path */
        fprintf(stderr, "tmpdir_join: path too long: %s/%s\n", dir->path, name);
        abort();
    }
    return out;
}

int tmpdir_write_file(const char *path, const void *bytes, size_t size)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return -1;
    const unsigned char *p = bytes;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            close(fd);
            return -1;
        }
        p += n;
        size -= (size_t)n;
    }
    return close(fd);
}

int tmpdir_write_text(const char *path, const char *text)
{
    return tmpdir_write_file(path, text, strlen(text));
}

unsigned char *tmpdir_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0;
    unsigned char *buf = malloc(cap + 1);
    while (buf) {
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap)
            break;
        unsigned char *bigger = realloc(buf, 2 * cap + 1);
        if (!bigger) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = bigger;
        cap *= 2;
    }
    if (buf && ferror(f)) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf) {
        buf[n] = 0;
        *size = n;
    }
    return buf;
}
