/* Runs a shell command for the CLI tests; returns its exit status and what
 * it wrote to stderr (stdout is kept separately). */
#ifndef SB_RUN_CMD_H
#define SB_RUN_CMD_H

#include "base/util.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

static inline int run_cmd(const char *cmd, struct strbuf *err, struct strbuf *out)
{
    char err_path[] = "/tmp/sb_test_stderr_XXXXXX";
    int fd = mkstemp(err_path);
    close(fd);
    char *full = util_printf("%s 2>%s", cmd, err_path);
    FILE *p = popen(full, "r");
    char buf[4096];
    size_t n;
    while (p && (n = fread(buf, 1, sizeof buf, p)) > 0)
        if (out)
            strbuf_append(out, buf, n);
    int status = p ? pclose(p) : -1;
    char *text = NULL;
    size_t size = 0;
    if (err && util_read_file(err_path, &text, &size) == 0) {
        strbuf_append(err, text, size);
        free(text);
    }
    if (err && !err->data)
        strbuf_append(err, "", 0);
    unlink(err_path);
    free(full);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* A CLI test's start: its argument (the shadowbench binary) and its
 * temporary folder (a mkdtemp template, made). The binary, or NULL. */
static inline const char *test_begin(int argc, char **argv, char *dir_template)
{
    return argc >= 2 && mkdtemp(dir_template) ? argv[1] : NULL;
}

/* The main of a CLI test whose parts take nothing: each part in turn, then
 * its folder removed and the tally. TEST_MAIN(dir, part, part, ...) after
 * `static const char *sb;`. */
#define TEST_MAIN(dir_, ...)                                            \
    int main(int argc, char **argv)                                     \
    {                                                                   \
        if (!(sb = test_begin(argc, argv, dir_)))                       \
            return 1;                                                   \
        void (*const parts_[])(void) = {__VA_ARGS__};                   \
        for (size_t i_ = 0; i_ < sizeof parts_ / sizeof *parts_; i_++) \
            parts_[i_]();                                               \
        remove_tree(dir_);                                              \
        return check_finish();                                          \
    }

/* Removes a test's temporary folder. */
static inline void remove_tree(const char *dir)
{
    char *rm = util_printf("rm -rf '%s'", dir);
    if (system(rm) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    free(rm);
}

#endif
