/* One logging function for the whole program. A message names the file,
 * technique or option it is about and is written once, where the problem is
 * detected (STYLE.md item 9). */
#ifndef SB_LOG_H
#define SB_LOG_H

#include <stdbool.h>

enum log_level { LOG_NONE = -1, LOG_ERROR, LOG_WARN, LOG_INFO, LOG_DEBUG };  /* NONE: silence */

void log_msg(enum log_level level, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
void log_set_level(enum log_level max_level);
enum log_level log_get_level(void);
/* While on, log_error prints a warning: for a failure the caller recovers
 * from (an unreadable cache entry, rendered again). */
void log_errors_as_warnings(bool on);

/* While context is not NULL, every message starts with "<context>: " (e.g.
 * the file whose contents are being checked by code that does not know
 * it). The string must outlive its use; NULL ends it. Returns the context
 * it replaces (to put back). */
const char *log_set_context(const char *context);

/* Progress on long work (docs/design.md §6, the CLI standards), one printer for
 * every command: on a terminal, one line rewritten in place, ended by
 * log_progress_done or by the next message; elsewhere (a log file, CI) the
 * line is logged as a message at most every LOG_PROGRESS_EVERY_MS. Shown
 * at the default level and above (not with -q). */
#define LOG_PROGRESS_EVERY_MS 30000.0
void log_progress(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void log_progress_done(void);

/* An error line written with no allocation (a stack buffer, one write):
 * for when the memory has run out. */
void log_error_unallocated(const char *text);

#define log_error(...) log_msg(LOG_ERROR, __VA_ARGS__)
#define log_warn(...)  log_msg(LOG_WARN, __VA_ARGS__)
#define log_info(...)  log_msg(LOG_INFO, __VA_ARGS__)
#define log_debug(...) log_msg(LOG_DEBUG, __VA_ARGS__)

#endif
