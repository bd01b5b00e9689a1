#include "results_set.h"
#include "out_dir.h"
#include "base/log.h"
#include "base/util.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Removes path and, if it is a folder (not a link), all below it. */
static void remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    if (!S_ISDIR(st.st_mode)) {
        unlink(path);
        return;
    }
    DIR *d = opendir(path);
    for (struct dirent *e; d && (e = readdir(d));)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
            char *child = util_printf("%s/%s", path, e->d_name);
            remove_tree(child);
            free(child);
        }
    if (d)
        closedir(d);
    rmdir(path);
}

bool results_set_own_name(const char *name)
{
    return !strcmp(name, ".") || !strcmp(name, "..") || !strcmp(name, ".lock") || strstr(name, UTIL_TEMP_SUFFIX);
}

/* Calls visit(src, dst, st) for each result in folder from (its writer's
 * own names left out): src its path, dst the same name under to, st its
 * lstat; until one fails. Returns 0 or -1 (logged). */
static int each_result(const char *from, const char *to,
                       int (*visit)(const char *src, const char *dst, const struct stat *st))
{
    DIR *d = opendir(from);
    int rc = d ? 0 : -1;
    if (!d)
        log_error("%s: cannot read: %s", from, strerror(errno));
    for (struct dirent *e; !rc && (e = readdir(d));) {
        if (results_set_own_name(e->d_name))
            continue;
        char *src = util_printf("%s/%s", from, e->d_name), *dst = util_printf("%s/%s", to, e->d_name);
        struct stat st;
        if (lstat(src, &st) != 0) {
            log_error("%s: %s", src, strerror(errno));
            rc = -1;
        } else {
            rc = visit(src, dst, &st);
        }
        free(src), free(dst);
    }
    if (d)
        closedir(d);
    return rc;
}

static int mirror(const char *from, const char *to);

/* One result of mirror: a folder copied, a file linked (copied where the
 * filesystem has no hard links); anything else (a link, a FIFO) refused. */
static int mirror_one(const char *src, const char *dst, const struct stat *st)
{
    if (S_ISDIR(st->st_mode))
        return mirror(src, dst);
    if (!S_ISREG(st->st_mode)) {
        log_error("%s: not a file or a folder (a link?): a results folder holds only its own files", src);
        return -1;
    }
    if (link(src, dst) == 0)
        return 0;
    char *data = NULL;
    size_t size = 0;
    const int err = util_read_file(src, &data, &size);
    if (err)
        log_error("%s: cannot read: %s", src, util_read_error(err));
    const int rc = err || util_write_file_atomic(dst, data, size) ? -1 : 0;
    free(data);
    return rc;
}

/* to made as a copy of folder from (a results folder holds only its own
 * files and folders). Returns 0 or -1 (logged). */
static int mirror(const char *from, const char *to)
{
    struct stat st;
    if (stat(from, &st) != 0 || mkdir(to, st.st_mode & 07777) != 0) {
        log_error("%s: cannot create folder: %s", to, strerror(errno));
        return -1;
    }
    return each_result(from, to, mirror_one);
}

/* Removes the next sets that killed writers left beside real: folders
 * "<name>.tmp.<pid>" whose process is gone. */
static void remove_dead_sets(const char *real)
{
    const char *slash = strrchr(real, '/');
    char *parent = slash == real ? xstrdup("/") : util_printf("%.*s", (int)(slash - real), real);
    char *prefix = util_printf("%s" UTIL_TEMP_SUFFIX, slash + 1);
    DIR *d = opendir(parent);
    for (struct dirent *e; d && (e = readdir(d));) {
        char *end = NULL;
        const long pid = strncmp(e->d_name, prefix, strlen(prefix)) == 0
                             ? strtol(e->d_name + strlen(prefix), &end, 10) : 0;
        if (pid > 0 && end && !*end && kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
            char *path = util_printf("%s/%s", parent, e->d_name);
            remove_tree(path);
            free(path);
        }
    }
    if (d)
        closedir(d);
    free(parent), free(prefix);
}

/* Whether path is real or lies below it. */
static bool below(const char *path, const char *real)
{
    const size_t n = strlen(real);
    return strncmp(path, real, n) == 0 && (path[n] == '\0' || path[n] == '/' || !strcmp(real, "/"));
}

/* A folder its set can be swapped into: not a mount point (the sibling
 * would be on another filesystem) and not holding the current folder (the
 * process, and its user's shell, would be left in the removed set).
 * Returns 0 or -1 (logged). */
static int swappable(const char *dir, const char *real)
{
    char *parent = util_printf("%s/..", real), *cwd = realpath(".", NULL);
    struct stat self, up;
    int rc = 0;
    if (stat(real, &self) != 0 || stat(parent, &up) != 0 || self.st_dev != up.st_dev) {
        log_error("%s: a mount point (or beside one): its set cannot be swapped in whole; name a folder inside it",
                  dir);
        rc = -1;
    } else if (cwd && below(cwd, real)) {
        log_error("%s: holds the current folder, which swapping its set in would remove: run from outside it", dir);
        rc = -1;
    }
    free(parent), free(cwd);
    return rc;
}

int results_set_open(struct results_set *rs, const char *dir, int depth)
{
    *rs = (struct results_set){.dir = xstrdup(dir)};
    if (out_dir_prepare(dir) != 0 || util_lock_dir(dir) != 0)
        return -1;
    /* The real folder: its sibling is the next set (dir may end in '/', be
     * ".." or reach it through a link), and commit swaps that same one. */
    if (!(rs->real = realpath(dir, NULL))) {
        log_error("%s: %s", dir, strerror(errno));
        return -1;
    }
    if (swappable(dir, rs->real) != 0)
        return -1;
    util_remove_stale_temps(rs->real, depth);
    remove_dead_sets(rs->real);
    char *next = util_printf("%s" UTIL_TEMP_SUFFIX "%ld", rs->real, (long)getpid());
    remove_tree(next);  /* a dead process's of the same pid (pids are reused) */
    if (mirror(dir, next) != 0 || util_lock_dir(next) != 0) {  /* locked: in dir's place it keeps dir locked */
        remove_tree(next);
        free(next);
        return -1;
    }
    rs->next = next;
    return 0;
}

/* One result of move_over: a folder made (if need be) and moved into, a
 * file renamed over its namesake. */
static int move_one(const char *src, const char *dst, const struct stat *st)
{
    if (!S_ISDIR(st->st_mode)) {
        if (rename(src, dst) == 0)
            return 0;
        log_error("%s: cannot move it to %s: %s", src, dst, strerror(errno));
        return -1;
    }
    if (mkdir(dst, st->st_mode & 07777) != 0 && errno != EEXIST) {
        log_error("%s: cannot create folder: %s", dst, strerror(errno));
        return -1;
    }
    return each_result(src, dst, move_one);
}

/* Moves every file of folder from over its namesake under to (each move
 * atomic, the whole not). Returns 0 or -1 (the failing move logged). */
static int move_over(const char *from, const char *to)
{
    return each_result(from, to, move_one);
}

int results_set_commit(struct results_set *rs)
{
    int rc = 0;
    if (renameat2(AT_FDCWD, rs->next, AT_FDCWD, rs->real, RENAME_EXCHANGE) == 0) {
        remove_tree(rs->next);  /* now the previous set */
    } else if (errno == EINVAL || errno == ENOSYS || errno == ENOTSUP) {
        log_warn("%s: this filesystem cannot swap two folders at once (%s): its files are replaced one by one, "
                 "so a writer stopped now would leave a mix", rs->dir, strerror(errno));
        if ((rc = move_over(rs->next, rs->real)) != 0)
            log_error("%s: holds part of the new set and part of the previous one: record it again", rs->dir);
        remove_tree(rs->next);  /* either way no longer a whole set */
    } else {
        log_error("%s: cannot put the new set in its place: %s", rs->dir, strerror(errno));
        return -1;  /* dir as it was; the next set is dropped by results_set_free */
    }
    free(rs->next);
    rs->next = NULL;
    return rc;
}

void results_set_free(struct results_set *rs, bool say)
{
    if (rs->next && say)
        log_info("%s: left as it was (the command did not finish)", rs->dir);
    if (rs->next)
        remove_tree(rs->next);
    free(rs->next), free(rs->dir), free(rs->real);
    *rs = (struct results_set){0};
}
