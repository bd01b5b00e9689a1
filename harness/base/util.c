#include "util.h"

#include <cjson/cJSON.h>
#include "log.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <stdatomic.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

void *xmalloc(size_t size)
{
    void *p = malloc(size ? size : 1);
    if (!p)
        util_out_of_memory(size);
    return p;
}

void *xcalloc(size_t count, size_t size)
{
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p)
        util_out_of_memory(count > SIZE_MAX / (size ? size : 1) ? SIZE_MAX : count * size);
    return p;
}

void *xrealloc(void *p, size_t size)
{
    p = realloc(p, size ? size : 1);
    if (!p)
        util_out_of_memory(size);
    return p;
}

char *xstrdup(const char *s)
{
    size_t n = strlen(s) + 1;
    return memcpy(xmalloc(n), s, n);
}

int util_read_file(const char *path, char **data, size_t *size)
{
    /* Non-blocking, so a FIFO does not wait for a writer: refused below. */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0)
        return -errno;
    struct stat st;
    int err = fstat(fd, &st) != 0 ? -errno : S_ISDIR(st.st_mode) ? -EISDIR : !S_ISREG(st.st_mode) ? -ENODEV : 0;
    if (err) {
        close(fd);
        return err;
    }
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        err = -errno;
        close(fd);
        return err;
    }
    char *buf = xmalloc((size_t)st.st_size + 1);
    size_t n = fread(buf, 1, (size_t)st.st_size, f);
    err = ferror(f) ? -EIO : 0;
    fclose(f);
    if (err) {
        free(buf);
        return err;
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return 0;
}

const char *util_read_error(int err)
{
    return err == -ENODEV ? "not a regular file" : strerror(-err);
}

/* The temporary being written, for the signal handler (one at a time: the
 * program writes its files from one thread). */
static char temp_path[4096];
static volatile sig_atomic_t temp_active;

int util_temp_create(const char *path, char **tmp)
{
    *tmp = util_printf("%s" UTIL_TEMP_SUFFIX "%ld", path, (long)getpid());
    temp_active = 0;
    snprintf(temp_path, sizeof temp_path, "%s", *tmp);
    temp_active = strlen(*tmp) < sizeof temp_path;
    /* what is there (a dead process's of the same pid, a planted link) is
     * removed, never written through: the file made here is new */
    unlink(*tmp);
    const int fd = open(*tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
        const int err = -errno;
        log_error("%s: cannot write: %s", path, strerror(errno));
        util_temp_end();
        free(*tmp);
        *tmp = NULL;
        return err;
    }
    return fd;
}

void util_temp_end(void) { temp_active = 0; }

/* What a signal does now: while a command writes the record that says it
 * is complete, it is held (util_signals_defer); once that is written, it
 * ends the process with the command's own status (util_signals_finished).
 * Lock-free atomics: any thread may take the signal. */
enum { SIGNALS_KILL, SIGNALS_HELD, SIGNALS_FINISHED };
static atomic_int signal_mode, signal_held, finished_status;

/* The process's last act on a signal or a failed allocation: the temporary
 * being written removed, the child process group killed (unlink, kill and
 * _exit are async-signal-safe). */
static volatile sig_atomic_t child_group_id;

void util_child_group(pid_t group) { child_group_id = group; }

static void leave(int status) __attribute__((noreturn));
static void leave(int status)
{
    if (temp_active)
        unlink(temp_path);
    if (child_group_id > 0)
        kill(-child_group_id, SIGKILL);
    _exit(status);
}

static void on_signal(int sig)
{
    const int mode = atomic_load(&signal_mode);
    if (mode == SIGNALS_HELD)
        atomic_store(&signal_held, 1);
    else
        leave(mode == SIGNALS_FINISHED ? atomic_load(&finished_status) : 128 + sig);
}

void util_exit_cleanly_on_signals(void)
{
    /* SA_RESTART: a signal held while finishing interrupts no write */
    struct sigaction sa = {.sa_handler = on_signal, .sa_flags = SA_RESTART};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
    /* A write past the file-size limit or into a pipe nobody reads fails
     * (EFBIG, EPIPE) and is reported by its writer, rather than killing the
     * process without a word and leaving its temporary. (Children started
     * by popen inherit it: git, whose output is read whole.) */
    signal(SIGXFSZ, SIG_IGN);
    signal(SIGPIPE, SIG_IGN);
}

void util_signals_defer(void) { atomic_store(&signal_mode, SIGNALS_HELD); }

void util_signals_finished(int status)
{
    atomic_store(&finished_status, status);
    atomic_store(&signal_mode, SIGNALS_FINISHED);
    if (atomic_load(&signal_held)) {  /* asked to stop while finishing: now */
        fflush(stdout);
        leave(status);
    }
}

void util_out_of_memory(size_t size)
{
    char text[120];
    snprintf(text, sizeof text, "out of memory: %zu more bytes were needed and could not be had", size);
    log_error_unallocated(text);
    fflush(stdout);
    leave(1);
}

int util_remove_stale_temps(const char *dir, int depth)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int removed = 0;
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] == '.')
            continue;
        char *path = util_printf("%s/%s", dir, e->d_name);
        const char *mark = strstr(e->d_name, UTIL_TEMP_SUFFIX);
        char *end = NULL;
        long pid = mark ? strtol(mark + strlen(UTIL_TEMP_SUFFIX), &end, 10) : 0;
        struct stat st;
        if (mark && end && !*end && pid > 0 && kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
            removed += unlink(path) == 0;  /* its writer is gone */
        } else if (depth > 0 && lstat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
            removed += util_remove_stale_temps(path, depth - 1);
        }
        free(path);
    }
    closedir(d);
    return removed;
}

int util_lock_dir(const char *dir)
{
    char *path = util_printf("%s/.lock", dir);
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);  /* a link there: refused */
    int rc = 0;
    if (fd < 0) {
        log_error("%s: cannot lock: %s", dir, strerror(errno));
        rc = -1;
    } else if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        log_error("%s: another shadowbench is writing there (it holds %s)", dir, path);
        close(fd);
        rc = -1;
    }
    /* On success fd stays open: the lock lasts until the process ends. */
    free(path);
    return rc;
}

int util_write_file_atomic(const char *path, const void *data, size_t size)
{
    char *tmp;
    const int fd = util_temp_create(path, &tmp);
    if (fd < 0)
        return fd;
    const char *p = data;
    size_t left = size;
    while (left > 0) {
        ssize_t n = write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            int err = -errno;
            log_error("%s: cannot write: %s", path, strerror(errno));
            close(fd);
            unlink(tmp);
            util_temp_end();
            free(tmp);
            return err;
        }
        p += n;
        left -= (size_t)n;
    }
    if (close(fd) != 0 || rename(tmp, path) != 0) {
        int err = -errno;
        log_error("%s: cannot write: %s", path, strerror(errno));
        unlink(tmp);
        util_temp_end();
        free(tmp);
        return err;
    }
    util_temp_end();
    free(tmp);
    return 0;
}

int util_mkdirs(const char *path)
{
    if (!*path) {
        log_error("an empty folder name");
        return -EINVAL;
    }
    char *p = xstrdup(path);
    for (char *s = p + 1;; s++) {
        char c = *s;
        if (c != '/' && c != '\0')
            continue;
        *s = '\0';
        if (mkdir(p, 0755) != 0 && errno != EEXIST) {
            int err = -errno;
            log_error("%s: cannot create folder: %s", p, strerror(errno));
            free(p);
            return err;
        }
        *s = c;
        if (c == '\0')
            break;
    }
    free(p);
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
        log_error("%s: not a folder", path);
        return -ENOTDIR;
    }
    return 0;
}

/* One of util_mkdirs_own's own parts, p: not a link, then made. */
static int mkdir_own(const char *p)
{
    struct stat st;
    if (lstat(p, &st) == 0 && S_ISLNK(st.st_mode)) {
        log_error("%s: a link: shadowbench writes inside its output folder, never through a link out of it "
                  "(remove the link)", p);
        return -ELOOP;
    }
    if (mkdir(p, 0755) != 0 && errno != EEXIST) {
        const int err = -errno;
        log_error("%s: cannot create folder: %s", p, strerror(errno));
        return err;
    }
    if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)) {
        log_error("%s: not a folder", p);
        return -ENOTDIR;
    }
    return 0;
}

int util_mkdirs_own(const char *path, int own)
{
    /* the folders above the last `own` parts as mkdir -p makes them; each
     * of those parts looked at before it is made or gone into */
    char *p = xstrdup(path);
    char *part[UTIL_MKDIRS_OWN_MAX];
    int n = 0;
    for (char *slash; n < own && n < UTIL_MKDIRS_OWN_MAX && (slash = strrchr(p, '/')) && slash != p; n++)
        *slash = '\0', part[n] = slash + 1;
    /* p: the folder above them, or (a path of no more parts) the first of them */
    int rc = n < own ? mkdir_own(p) : util_mkdirs(p);
    for (int k = n - 1; k >= 0 && !rc; k--) {
        part[k][-1] = '/';
        rc = mkdir_own(p);
    }
    free(p);
    return rc;
}

int util_utf8_next(const char *s, unsigned *cp)
{
    const unsigned char *p = (const unsigned char *)s;
    int n = *p < 0x80 ? 0 : (*p & 0xe0) == 0xc0 ? 1 : (*p & 0xf0) == 0xe0 ? 2 : (*p & 0xf8) == 0xf0 ? 3 : -1;
    *cp = UTIL_NOT_UTF8;
    if (n < 0)
        return 1;
    unsigned c = n == 0 ? *p : *p & (0x3f >> n);
    for (int i = 1; i <= n; i++) {
        if ((p[i] & 0xc0) != 0x80)
            return 1;
        c = c << 6 | (p[i] & 0x3f);
    }
    static const unsigned min[4] = {0, 0x80, 0x800, 0x10000};
    if (c < min[n] || c > 0x10ffff || (c >= 0xd800 && c <= 0xdfff))
        return 1;
    *cp = c;
    return n + 1;
}

char *util_utf8_copy(const char *s)
{
    struct strbuf out = {0};
    strbuf_append(&out, "", 0);
    unsigned cp;
    for (int n; *s; s += n) {
        n = util_utf8_next(s, &cp);
        if (cp == UTIL_NOT_UTF8)
            strbuf_append(&out, "\xef\xbf\xbd", 3);
        else
            strbuf_append(&out, s, (size_t)n);
    }
    return out.data;
}

bool util_valid_utf8(const char *s)
{
    unsigned cp = 0;
    while (*s && cp != UTIL_NOT_UTF8)
        s += util_utf8_next(s, &cp);
    return cp != UTIL_NOT_UTF8;
}

void util_printable(char *s)
{
    char *out = s;
    unsigned cp;
    for (const char *in = s; *in;) {
        const int n = util_utf8_next(in, &cp);
        if (cp < 32 || cp == 127 || util_bidi_control(cp))
            *out++ = '?';
        else
            memmove(out, in, (size_t)n), out += n;
        in += n;
    }
    *out = '\0';
}

bool util_bidi_control(unsigned cp)
{
    return cp == 0x061c || cp == 0x200e || cp == 0x200f || (cp >= 0x202a && cp <= 0x202e) ||
           (cp >= 0x2066 && cp <= 0x2069);
}

static int compare_keys(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

const char *util_json_duplicate_key(const cJSON *v)
{
    const char *twice = NULL;
    size_t n = 0;
    for (const cJSON *c = v ? v->child : NULL; c; c = c->next)
        n++;
    const char **keys = xcalloc(n + 1, sizeof *keys);
    size_t k = 0;
    for (const cJSON *c = v ? v->child : NULL; c && !twice; c = c->next) {
        if (cJSON_IsObject(v) && c->string)
            keys[k++] = c->string;
        twice = util_json_duplicate_key(c);
    }
    qsort(keys, k, sizeof *keys, compare_keys);  /* n log n: an object may hold many keys */
    for (size_t i = 1; i < k && !twice; i++)
        if (strcmp(keys[i - 1], keys[i]) == 0)
            twice = keys[i];
    free(keys);
    return twice;
}

/* path made absolute with its links resolved, as far as it exists (the rest
 * appended as written); malloc'ed. */
static char *absolute(const char *path)
{
    char *real = realpath(path, NULL);
    if (real)
        return real;
    const char *slash = strrchr(path, '/');
    if (!slash) {
        char *cwd = realpath(".", NULL), *joined = util_printf("%s/%s", cwd ? cwd : ".", path);
        free(cwd);
        return joined;
    }
    char *parent = slash == path ? xstrdup("/") : util_printf("%.*s", (int)(slash - path), path);
    char *head = absolute(parent);
    free(parent);
    /* a part that does not exist yet is no link: "." and ".." are read as words */
    if (!strcmp(slash + 1, ".") || !slash[1])
        return head;
    if (!strcmp(slash + 1, "..")) {
        char *up = strrchr(head, '/');
        if (up)
            up[up == head] = '\0';  /* "/a" -> "/", "/a/b" -> "/a" */
        return head;
    }
    char *joined = util_printf("%s%s%s", head, head[strlen(head) - 1] == '/' ? "" : "/", slash + 1);
    free(head);
    return joined;
}

bool util_path_within(const char *path, const char *dir)
{
    char *p = absolute(path), *d = absolute(dir);
    const size_t n = strlen(d);
    const bool within = strncmp(p, d, n) == 0 && (p[n] == '\0' || p[n] == '/' || (n && d[n - 1] == '/'));
    free(p), free(d);
    return within;
}

bool util_is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

bool util_dir_writable(const char *dir)
{
    char *probe = util_printf("%s/.shadowbench-probe.%ld", dir, (long)getpid());
    int fd = open(probe, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
        close(fd);
        unlink(probe);
    }
    free(probe);
    return fd >= 0;
}

bool util_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Directory part of the running executable's path (from /proc/self/exe). */
static const char *exe_dir(void)
{
    static char dir[4096];
    if (dir[0])
        return dir;
    ssize_t n = readlink("/proc/self/exe", dir, sizeof dir - 1);
    if (n <= 0) {
        strcpy(dir, ".");
        return dir;
    }
    dir[n] = '\0';
    char *slash = strrchr(dir, '/');
    if (slash && slash != dir)
        *slash = '\0';
    return dir;
}

uint64_t util_hash(uint64_t h, const void *data, size_t size)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

double util_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double util_quantile(double *values, int n, double q)
{
    qsort(values, (size_t)n, sizeof *values, cmp_double);
    double at = q * (double)(n - 1);
    int i = (int)at;
    return i + 1 < n ? values[i] + (at - i) * (values[i + 1] - values[i]) : values[n - 1];
}

/* Room for `extra` more characters and the NUL. */
static void strbuf_reserve(struct strbuf *sb, size_t extra)
{
    if (sb->len + extra + 1 > sb->cap) {
        sb->cap = (sb->len + extra + 1) * 2;
        sb->data = xrealloc(sb->data, sb->cap);
    }
}

void strbuf_append(struct strbuf *sb, const char *s, size_t n)
{
    strbuf_reserve(sb, n);
    memcpy(sb->data + sb->len, s, n);
    sb->len += n;
    sb->data[sb->len] = '\0';
}

void strbuf_vprintf(struct strbuf *sb, const char *fmt, va_list ap)
{
    va_list again;
    va_copy(again, ap);
    int n = vsnprintf(NULL, 0, fmt, ap);
    strbuf_reserve(sb, (size_t)n);
    vsnprintf(sb->data + sb->len, (size_t)n + 1, fmt, again);
    va_end(again);
    sb->len += (size_t)n;
}

void strbuf_printf(struct strbuf *sb, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    strbuf_vprintf(sb, fmt, ap);
    va_end(ap);
}

void strbuf_list_printf(struct strbuf *sb, const char *sep, const char *fmt, ...)
{
    if (sb->len > 0)
        strbuf_append(sb, sep, strlen(sep));
    va_list ap;
    va_start(ap, fmt);
    strbuf_vprintf(sb, fmt, ap);
    va_end(ap);
}

void strbuf_join(struct strbuf *sb, const char *const *items, const char *sep)
{
    for (int k = 0; items[k]; k++)
        strbuf_list_printf(sb, sep, "%s", items[k]);
}

void strbuf_free(struct strbuf *sb)
{
    free(sb->data);
    *sb = (struct strbuf){0};
}

void strbuf_xml(struct strbuf *sb, const char *s)
{
    unsigned cp;
    for (int n; *s; s += n) {
        n = util_utf8_next(s, &cp);
        switch (cp) {
        case '<': strbuf_printf(sb, "&lt;"); break;
        case '>': strbuf_printf(sb, "&gt;"); break;
        case '&': strbuf_printf(sb, "&amp;"); break;
        case '"': strbuf_printf(sb, "&quot;"); break;
        default:
            if (util_bidi_control(cp))
                strbuf_printf(sb, "[U+%04X]", cp);
            else if (cp == UTIL_NOT_UTF8 || (cp < 32 && !strchr("\t\n\r", (int)cp)) || cp == 127 ||
                     cp == 0xfffe || cp == 0xffff)
                strbuf_printf(sb, "\xef\xbf\xbd");  /* U+FFFD: XML forbids these */
            else
                strbuf_append(sb, s, (size_t)n);
        }
    }
}

char *util_printf(const char *fmt, ...)
{
    struct strbuf sb = {0};
    va_list ap;
    va_start(ap, fmt);
    strbuf_vprintf(&sb, fmt, ap);
    va_end(ap);
    return sb.data;  /* never NULL: the buffer holds at least the NUL */
}

const char *util_find_dir(const char *override, const char *env, const char *sub, const char *probe)
{
    /* each distinct folder found keeps its slot for the process's life (a
     * caller keeps the pointer): a few folders are ever looked for */
    static char found[16][4096];
    static int used;
    const char *given = override ? override : getenv(env);
    char *candidates[4] = {0};
    int n = 0;
    if (given && *given)
        candidates[n++] = xstrdup(given);
    else {
        candidates[n++] = util_printf("%s/%s", exe_dir(), sub);
        candidates[n++] = util_printf("%s/../share/shadowbench/%s", exe_dir(), sub);
        candidates[n++] = util_printf("%s/%s", SB_SOURCE_DIR, sub);
    }
    const char *result = NULL;
    for (int i = 0; i < n && !result; i++) {
        char *p = util_printf("%s/%s", candidates[i], probe);
        if (util_file_exists(p)) {
            for (int k = 0; k < used && !result; k++)
                if (strcmp(found[k], candidates[i]) == 0)
                    result = found[k];
            if (!result && used < (int)ARRAY_SIZE(found)) {
                snprintf(found[used], sizeof found[0], "%s", candidates[i]);
                result = found[used++];
            }
        }
        free(p);
    }
    if (!result) {
        if (given && *given)
            log_error("%s: not a shadowbench %s folder (no %s in it)", given, sub, probe);
        else
            log_error("cannot find the %s folder (looked next to the executable and in %s); set %s",
                      sub, SB_SOURCE_DIR, env);
    }
    for (int i = 0; i < n; i++)
        free(candidates[i]);
    return result;
}

void util_json_merge(cJSON *into, const cJSON *from)
{
    for (const cJSON *e = from ? from->child : NULL; e; e = e->next)
        cJSON_AddItemToObject(into, e->string, cJSON_Duplicate(e, true));
}

void util_json_add_number(cJSON *o, const char *key, double v)
{
    if (isfinite(v))
        cJSON_AddNumberToObject(o, key, v);
    else
        cJSON_AddNullToObject(o, key);
}

double util_json_number(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItem(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

bool util_json_whole(const cJSON *o, const char *key, double lo, double hi, long *out)
{
    const double v = util_json_number(o, key);
    if (!(v >= lo && v <= hi && v == floor(v)))  /* NaN too */
        return false;
    *out = (long)v;
    return true;
}

int util_parse_finite(const char *what, const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    if (!*text || *end || errno == ERANGE || !isfinite(*out)) {
        log_error("%s: '%s' is not a finite number", what, text);
        return -1;
    }
    return 0;
}
