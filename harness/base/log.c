#include "log.h"
#include "util.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static enum log_level max_level = LOG_INFO;
static const char *context;

const char *log_set_context(const char *c)
{
    const char *was = context;
    context = c;
    return was;
}

void log_set_level(enum log_level level) { max_level = level; }

static bool errors_as_warnings;
void log_errors_as_warnings(bool on) { errors_as_warnings = on; }
enum log_level log_get_level(void) { return max_level; }

/* The progress line on the terminal: its length (0: none open). */
static size_t progress_len;

static void end_progress_line(void)
{
    if (progress_len)
        fputc('\n', stderr);
    progress_len = 0;
}

void log_msg(enum log_level level, const char *fmt, ...)
{
    static const char *const prefix[] = {
        [LOG_ERROR] = "error: ", [LOG_WARN] = "warning: ",
        [LOG_INFO] = "", [LOG_DEBUG] = "debug: ",
    };
    if (level == LOG_ERROR && errors_as_warnings)
        level = LOG_WARN;
    if (level > max_level)
        return;
    struct strbuf text = {0};  /* whole, however long: a line cut short could lose its reason */
    va_list ap;
    va_start(ap, fmt);
    strbuf_vprintf(&text, fmt, ap);
    va_end(ap);
    util_printable(text.data);
    /* One fprintf per message so lines from OpenMP threads never interleave. */
    end_progress_line();
    fprintf(stderr, "shadowbench: %s%s%s%s\n", prefix[level], context ? context : "", context ? ": " : "",
            text.data);
    strbuf_free(&text);
}

void log_error_unallocated(const char *text)
{
    char line[512];
    const int n = snprintf(line, sizeof line, "shadowbench: error: %s%s%s\n", context ? context : "",
                           context ? ": " : "", text);
    end_progress_line();
    if (n > 0 && write(STDERR_FILENO, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1) < 0)
        return;  /* nothing left to tell it to */
}

void log_progress(const char *fmt, ...)
{
    static double last_ms;
    if (max_level < LOG_INFO)
        return;
    const bool tty = isatty(STDERR_FILENO);
    const double now = util_now_ms();
    if (!tty && (last_ms == 0 || now - last_ms < LOG_PROGRESS_EVERY_MS)) {
        if (last_ms == 0)
            last_ms = now;  /* the first line after the first interval */
        return;
    }
    last_ms = now;
    struct strbuf text = {0};
    va_list ap;
    va_start(ap, fmt);
    strbuf_vprintf(&text, fmt, ap);
    va_end(ap);
    if (tty) {  /* spaces over what is left of a longer last line */
        fprintf(stderr, "\r%s%*s", text.data, progress_len > text.len ? (int)(progress_len - text.len) : 0, "");
        progress_len = text.len > 0 ? text.len : 1;
    } else {
        log_msg(LOG_INFO, "%s", text.data + strspn(text.data, " "));
    }
    strbuf_free(&text);
}

void log_progress_done(void) { end_progress_line(); }
