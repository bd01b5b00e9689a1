#include "log.h"
#include "util.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

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
    /* One line, shown in the order it is stored, whatever a file name or a
     * file's text quoted in it holds: control characters (a newline, a
     * terminal escape) and bidirectional formatting characters print as '?'. */
    char *out = line;
    unsigned cp;
    for (const char *in = line; *in;) {
        int n = util_utf8_next(in, &cp);
        if (cp < 32 || cp == 127 || util_bidi_control(cp))
            *out++ = '?';
        else
            memmove(out, in, (size_t)n), out += n;
        in += n;
    }
    *out = '\0';
    /* One fprintf per message so lines from OpenMP threads never interleave. */
    fprintf(stderr, "shadowbench: %s%s%s%s\n", prefix[level], context ? context : "", context ? ": " : "",
            line);
}
