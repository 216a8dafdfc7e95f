/*
 * run_cmd.c: fork/exec with three pipes for the CLI tests (see run_cmd.h). Both
 * output pipes and the input pipe are served by one poll() loop, so a child that
 * writes a lot to one stream while the test is feeding or draining another never
 * deadlocks.
 */
#include "run_cmd.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

const char *sr_test_bin(void)
{
    const char *bin = getenv("SYMREC_BIN");
    return bin && bin[0] ? bin : "build/debug/symrec";
}

typedef struct buf {
    char *data;
    size_t len, cap;
} buf;

static int buf_add(buf *b, const char *p, size_t n)
{
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *d = realloc(b->data, cap);
        if (!d)
            return -1;
        b->data = d;
        b->cap = cap;
    }
    memcpy(b->data + b->len, p, n);
    b->len += n;
    b->data[b->len] = '\0';
    return 0;
}

/* Splits $SYMREC_WRAP on blanks into a NULL-terminated array (words point into *copy). */
static char **wrap_words(char **copy, size_t *count)
{
    *count = 0;
    *copy = NULL;
    const char *wrap = getenv("SYMREC_WRAP");
    if (!wrap || !wrap[0])
        return NULL;
    *copy = strdup(wrap);
    char **words = calloc(strlen(wrap) / 2 + 2, sizeof *words);
    if (!*copy || !words) {
        free(*copy);
        free(words);
        *copy = NULL;
        return NULL;
    }
    char *save = NULL;
    for (char *w = strtok_r(*copy, " \t", &save); w; w = strtok_r(NULL, " \t", &save))
        words[(*count)++] = w;
    return words;
}

static int run_command(const char *const argv[], int wrapped, const char *stdin_text, char **out,
                       char **err)
{
    if (out)
        *out = NULL;
    if (err)
        *err = NULL;

    char *wrap_copy = NULL;
    size_t wrap_count = 0;
    char **wrap = wrapped ? wrap_words(&wrap_copy, &wrap_count) : NULL;
    size_t argc = 0;
    while (argv[argc])
        argc++;
    char **args = calloc(wrap_count + argc + 1, sizeof *args);
    if (!args) {
        free(wrap);
        free(wrap_copy);
        return -1;
    }
    for (size_t i = 0; i < wrap_count; i++)
        args[i] = wrap[i];
    for (size_t i = 0; i < argc; i++)
        args[wrap_count + i] = (char *)argv[i];

    int in_p[2] = {-1, -1}, out_p[2] = {-1, -1}, err_p[2] = {-1, -1};
    int status = -1;
    pid_t pid = -1;
    if (pipe(in_p) != 0 || pipe(out_p) != 0 || pipe(err_p) != 0)
        goto cleanup;
    pid = fork();
    if (pid < 0)
        goto cleanup;
    if (pid == 0) {
        dup2(in_p[0], 0);
        dup2(out_p[1], 1);
        dup2(err_p[1], 2);
        close(in_p[0]);
        close(in_p[1]);
        close(out_p[0]);
        close(out_p[1]);
        close(err_p[0]);
        close(err_p[1]);
        /* progress lines only where a test asks for them (SYMREC_PROGRESS_AFTER=0): a
         * slow machine must not put them before the one line a test expects */
        setenv("SYMREC_PROGRESS_AFTER", "100000", 0);
        execvp(args[0], args);
        _exit(127);
    }
    close(in_p[0]);
    close(out_p[1]);
    close(err_p[1]);
    in_p[0] = out_p[1] = err_p[1] = -1;

    /* Writes to a child that has exited must fail with EPIPE, not kill the test. */
    struct sigaction ign = {0}, old_pipe;
    ign.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ign, &old_pipe);

    const char *in_data = stdin_text ? stdin_text : "";
    size_t in_left = strlen(in_data);
    if (in_left == 0) {
        close(in_p[1]);
        in_p[1] = -1;
    } else {
        fcntl(in_p[1], F_SETFL, fcntl(in_p[1], F_GETFL) | O_NONBLOCK);
    }
    buf bo = {0}, be = {0};
    int fail = 0;
    while (out_p[0] >= 0 || err_p[0] >= 0) {
        struct pollfd fds[3] = {{out_p[0], POLLIN, 0}, {err_p[0], POLLIN, 0},
                                {in_p[1], POLLOUT, 0}};
        if (poll(fds, 3, -1) < 0) {
            if (errno == EINTR)
                continue;
            fail = 1;
            break;
        }
        for (int k = 0; k < 2; k++) {
            int *fd = k == 0 ? &out_p[0] : &err_p[0];
            if (*fd < 0 || !(fds[k].revents & (POLLIN | POLLHUP | POLLERR)))
                continue;
            char chunk[8192];
            ssize_t n = read(*fd, chunk, sizeof chunk);
            if (n > 0) {
                if (buf_add(k == 0 ? &bo : &be, chunk, (size_t)n) != 0)
                    fail = 1;
            } else if (n == 0 || errno != EINTR) {
                close(*fd);
                *fd = -1;
            }
        }
        if (in_p[1] >= 0 && (fds[2].revents & (POLLOUT | POLLERR | POLLHUP))) {
            ssize_t n = write(in_p[1], in_data, in_left);
            if (n > 0) {
                in_data += n;
                in_left -= (size_t)n;
            }
            if ((n < 0 && errno != EAGAIN && errno != EINTR) || in_left == 0) {
                close(in_p[1]);
                in_p[1] = -1;
            }
        }
    }
    sigaction(SIGPIPE, &old_pipe, NULL);
    /* After a failure the child may still be writing: closing our ends lets it end. */
    for (int k = 0; k < 2; k++) {
        int *fd = k == 0 ? &out_p[0] : &err_p[0];
        if (*fd >= 0)
            close(*fd);
        *fd = -1;
    }
    if (in_p[1] >= 0)
        close(in_p[1]);
    in_p[1] = -1;

    int ws;
    while (waitpid(pid, &ws, 0) < 0) {
        if (errno != EINTR) {
            ws = -1;
            break;
        }
    }
    pid = -1;
    if (fail || ws == -1) {
        free(bo.data);
        free(be.data);
        goto cleanup;
    }
    if (WIFEXITED(ws))
        status = WEXITSTATUS(ws);
    else if (WIFSIGNALED(ws))
        status = 128 + WTERMSIG(ws);
    /* Empty streams still come back as "" so callers can strcmp them. */
    if (!bo.data)
        buf_add(&bo, "", 0);
    if (!be.data)
        buf_add(&be, "", 0);
    if (out)
        *out = bo.data;
    else
        free(bo.data);
    if (err)
        *err = be.data;
    else
        free(be.data);

cleanup:
    for (int k = 0; k < 2; k++) {
        if (in_p[k] >= 0)
            close(in_p[k]);
        if (out_p[k] >= 0)
            close(out_p[k]);
        if (err_p[k] >= 0)
            close(err_p[k]);
    }
    if (pid > 0)
        waitpid(pid, NULL, 0);
    free(args);
    free(wrap);
    free(wrap_copy);
    return status;
}

int sr_test_run(const char *const argv[], const char *stdin_text, char **out, char **err)
{
    return run_command(argv, 1, stdin_text, out, err);
}

int sr_test_run_native(const char *const argv[], const char *stdin_text, char **out, char **err)
{
    return run_command(argv, 0, stdin_text, out, err);
}
