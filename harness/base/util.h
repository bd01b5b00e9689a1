/* Small helpers every module uses: files, atomic writes, hashing, a growable
 * string, the wall clock. */
#ifndef SB_UTIL_H
#define SB_UTIL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#define ARRAY_SIZE(a) (sizeof(a) / sizeof((a)[0]))

/* A macro's value as text, for help and messages: plain literals only. */
#define UTIL_STR_(x) #x
#define UTIL_STR(x) UTIL_STR_(x)

/* Reads a whole file; *data is NUL-terminated (not counted in *size).
 * Returns 0 or -errno (-EISDIR for a folder, -ENODEV for anything else that
 * is not a regular file: a FIFO, a device; neither blocks); logs nothing
 * (the caller knows what the file is). */
int util_read_file(const char *path, char **data, size_t *size);

/* What util_read_file's error means, in words. */
const char *util_read_error(int err);

/* Temporary files are "<path>.tmp.<pid>". util_temp_create names one
 * (*tmp, malloc'ed), registers it as the one being written (the signal
 * handler removes it) and creates it anew, removing whatever had the name
 * (O_EXCL | O_NOFOLLOW: never written through a link); util_temp_end after
 * it is renamed or removed. Returns its descriptor, or -errno (logged,
 * *tmp NULL). */
#define UTIL_TEMP_SUFFIX ".tmp."
int util_temp_create(const char *path, char **tmp);
void util_temp_end(void);

/* SIGINT, SIGTERM and SIGHUP remove the temporary being written, then exit
 * with 128 + the signal (130, 143, 129): no half-written file is left.
 * SIGXFSZ and SIGPIPE are ignored: the write fails instead (EFBIG, EPIPE)
 * and its writer says so. */
void util_exit_cleanly_on_signals(void);

/* A command's last writes (its outputs, then the record that says they are
 * complete) as one step for signals: util_signals_defer holds a signal
 * until util_signals_finished(status), after which a held or a new signal
 * ends the process at once with that status. So a command is either
 * killed before it says "complete" (128 + the signal) or ends with its own
 * status, and never ignores a signal for longer than its last writes. */
void util_signals_defer(void);

/* The process group of a child the process runs (the engine driver,
 * engine/engine.h), which a signal's exit kills with SIGKILL; 0: none. */
void util_child_group(pid_t group);
void util_signals_finished(int status);

/* One line on stderr ("out of memory: N more bytes were needed ..."), the
 * temporary being written removed, exit 1 (a runtime error). What xmalloc
 * and its kin do when the memory is not there. */
void util_out_of_memory(size_t size) __attribute__((noreturn));

/* Removes "<name>.tmp.<pid>" files under dir (depth levels of folders
 * below it) whose process is gone: leftovers of a killed run. Returns how
 * many. */
int util_remove_stale_temps(const char *dir, int depth);

/* Takes an exclusive lock on dir (flock on dir/.lock) for the rest of the
 * process, or fails at once: 0, or -1 after one line saying another
 * shadowbench holds it. */
int util_lock_dir(const char *dir);

/* Writes to "<path>.tmp.<pid>" then renames over path, so a reader never sees
 * a half-written file. Returns 0 or a negative errno, and logs the failure. */
int util_write_file_atomic(const char *path, const void *data, size_t size);

/* mkdir -p. Returns 0 or -errno, and logs the failure. */
int util_mkdirs(const char *path);

/* util_mkdirs, and the last `own` parts of path must be folders of their
 * own: one that is a link (<out>/<scene> leading elsewhere) would take the
 * files written into it out of the folder the command owns. Returns 0 or
 * -errno (logged). */
#define UTIL_MKDIRS_OWN_MAX 8
int util_mkdirs_own(const char *path, int own);

/* True when a file can be created in dir (it is probed, then removed). */
bool util_dir_writable(const char *dir);

bool util_file_exists(const char *path);
/* Decodes the UTF-8 character at s (not at its NUL) into *cp and returns its
 * length; a byte that starts no well-formed character (overlong forms and
 * surrogates included) gives UTIL_NOT_UTF8 and length 1. */
#define UTIL_NOT_UTF8 0xffffffffu
int util_utf8_next(const char *s, unsigned *cp);
/* A malloc'ed copy of s with every byte that starts no well-formed UTF-8
 * character replaced by U+FFFD: text JSON can hold. */
char *util_utf8_copy(const char *s);
/* Whether s is well-formed UTF-8. */
bool util_valid_utf8(const char *s);
/* s made one line shown in the order it is stored, in place: control
 * characters (a newline, a terminal escape) and bidirectional formatting
 * characters become '?' (what error lines and names printed from files
 * show). */
void util_printable(char *s);
/* Whether cp is a bidirectional formatting character (U+061C, U+200E/F,
 * U+202A-E, U+2066-9): text that shows in another order than it is stored. */
bool util_bidi_control(unsigned cp);

/* The first key found twice in one object of JSON value v (cJSON keeps
 * both and reads the first), or NULL. */
struct cJSON;
const char *util_json_duplicate_key(const struct cJSON *v);
/* Adds a copy of every key of object `from` (may be NULL) to `into`. */
void util_json_merge(struct cJSON *into, const struct cJSON *from);
/* A number as the files write it: key's value, null (NaN: nothing
 * measured) where it is not finite. */
void util_json_add_number(struct cJSON *o, const char *key, double v);
/* Key's number in o; NaN when it is null, absent or not a number. */
double util_json_number(const struct cJSON *o, const char *key);
/* Whether key's value in o is a whole number in [lo, hi] (into *out). What
 * another process wrote is read with it before it indexes or counts. */
bool util_json_whole(const struct cJSON *o, const char *key, double lo, double hi, long *out);

/* Whether path is dir or lies inside it, both made absolute with their
 * links resolved as far as they exist. */
bool util_path_within(const char *path, const char *dir);

/* Whether path is a folder (following links). */
bool util_is_dir(const char *path);

/* FNV-1a, 64 bit: a cache key, not a cryptographic hash. */
#define UTIL_HASH_INIT 0xcbf29ce484222325ull
uint64_t util_hash(uint64_t h, const void *data, size_t size);

double util_now_ms(void);

/* The q-quantile (0 <= q <= 1) of n values (n >= 1), interpolated linearly
 * between order statistics (q = 0.5: the median); sorts the array in place. */
double util_quantile(double *values, int n, double q);

/* A growable NUL-terminated string. Zero-initialise; free with strbuf_free. */
struct strbuf {
    char *data;
    size_t len, cap;
};
void strbuf_printf(struct strbuf *sb, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
void strbuf_append(struct strbuf *sb, const char *s, size_t n);
void strbuf_free(struct strbuf *sb);
void strbuf_vprintf(struct strbuf *sb, const char *fmt, va_list ap);
/* Appends one item of a list: sep first unless sb is empty, then the
 * formatted item ("a, b, c" item by item). sb holds just this list. */
void strbuf_list_printf(struct strbuf *sb, const char *sep, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Appends the NULL-terminated items separated by sep. */
void strbuf_join(struct strbuf *sb, const char *const *items, const char *sep);
/* Appends s with &, <, > and " escaped (for HTML and SVG), bidirectional
 * formatting characters shown as "[U+202E]" (nothing a file holds reorders
 * the page), and what XML forbids (control characters but tab and line
 * ends, bytes that are not UTF-8, U+FFFE/F) as U+FFFD. */
void strbuf_xml(struct strbuf *sb, const char *s);

/* text, the whole of it, as a finite double into *out: 0, or -1 after
 * "<what>: '<text>' is not a finite number". */
int util_parse_finite(const char *what, const char *text, double *out);

/* Returns a malloc'ed formatted string (aborts on out of memory). */
char *util_printf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

void *xmalloc(size_t size);
void *xcalloc(size_t count, size_t size);
void *xrealloc(void *p, size_t size);
char *xstrdup(const char *s);



/* Finds a data folder (shaders/, scenes/): `override` if non-NULL, else the
 * environment variable `env`, else "<exe dir>/<sub>", "<exe dir>/../share/
 * shadowbench/<sub>", then the source tree's "<sub>". The first that holds
 * `probe` wins. Returns a static string or NULL (logged). */
const char *util_find_dir(const char *override, const char *env, const char *sub, const char *probe);

#endif
