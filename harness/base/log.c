#include "log.h"

#include <stdarg.h>
#include <stdio.h>

static enum log_level max_level = LOG_INFO;
static const char *context;

void log_set_context(const char *c) { context = c; }

void log_set_level(enum log_level level) { max_level = level; }
enum log_level log_get_level(void) { return max_level; }

void log_msg(enum log_level level, const char *fmt, ...)
{
    static const char *const prefix[] = {
        [LOG_ERROR] = "error: ", [LOG_WARN] = "warning: ",
        [LOG_INFO] = "", [LOG_DEBUG] = "debug: ",
    };
    if (level > max_level)
        return;
    char line[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    /* One line, whatever a file name or a file's text quoted in it holds:
     * control characters (a newline, a terminal escape) print as '?'. */
    for (char *c = line; *c; c++)
        if ((unsigned char)*c < 32 || *c == 127)
            *c = '?';
    /* One fprintf per message so lines from OpenMP threads never interleave. */
    fprintf(stderr, "shadowbench: %s%s%s%s\n", prefix[level], context ? context : "", context ? ": " : "",
            line);
}
