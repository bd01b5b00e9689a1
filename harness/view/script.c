#include "script.h"
#include "base/log.h"
#include "base/util.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The keys the viewer answers to, by the names --script uses. */
const struct key_name key_names[KEY_NAME_COUNT] = {
    {"TAB", GLFW_KEY_TAB},       {"SPACE", GLFW_KEY_SPACE},
    {"LEFT", GLFW_KEY_LEFT},     {"RIGHT", GLFW_KEY_RIGHT},
    {"UP", GLFW_KEY_UP},         {"DOWN", GLFW_KEY_DOWN},
    {"MINUS", GLFW_KEY_MINUS},   {"EQUAL", GLFW_KEY_EQUAL},
    {"LEFT_BRACKET", GLFW_KEY_LEFT_BRACKET}, {"RIGHT_BRACKET", GLFW_KEY_RIGHT_BRACKET},
    {"ESCAPE", GLFW_KEY_ESCAPE},
};

/* "A".."Z", "0".."9" or a name of key_names, optionally after "shift+". */
static int parse_key(const char *text, int *key, int *mods)
{
    *mods = 0;
    if (strncasecmp(text, "shift+", 6) == 0)
        *mods = GLFW_MOD_SHIFT, text += 6;
    if (text[0] && !text[1] && (isalpha((unsigned char)text[0]) || isdigit((unsigned char)text[0]))) {
        *key = isdigit((unsigned char)text[0]) ? GLFW_KEY_0 + (text[0] - '0')
                                               : GLFW_KEY_A + (toupper((unsigned char)text[0]) - 'A');
        return 0;
    }
    for (size_t i = 0; i < KEY_NAME_COUNT; i++)
        if (strcasecmp(text, key_names[i].name) == 0) {
            *key = key_names[i].key;
            return 0;
        }
    return -1;
}

/* Lines "FRAME KEY" (the key pressed before frame FRAME is drawn, frames
 * counted from 0, in order), blank lines and # comments. Returns the
 * number of events, or -1 (logged). */
int script_load(const char *path, struct script_event *out, int max)
{
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > SCRIPT_MAX_BYTES) {
        log_error("--script %s: %lld bytes, more than a script of %d events needs (%d at most)", path,
                  (long long)st.st_size, max, SCRIPT_MAX_BYTES);
        return -1;
    }
    char *text;
    size_t size;
    int err = util_read_file(path, &text, &size);
    if (err != 0) {
        log_error("--script %s: %s", path, util_read_error(err));
        return -1;
    }
    if (memchr(text, 0, size)) {
        log_error("--script %s: a NUL byte: not a text file", path);
        free(text);
        return -1;
    }
    int n = 0, line = 0, rc = 0;
    for (char *rest = text, *l; !rc && (l = strsep(&rest, "\n"));) {
        line++;
        char *hash = strchr(l, '#');
        if (hash)
            *hash = 0;
        char number[32], key[32], extra[2];
        const int fields = sscanf(l, "%31s %31s %1s", number, key, extra);
        if (fields <= 0)
            continue;  /* blank, or a comment */
        char *end;
        errno = 0;
        const long frame = strtol(number, &end, 10);
        if (fields != 2 || *end || errno || !isdigit((unsigned char)number[0]) || frame > SCRIPT_MAX_FRAME) {
            log_error("--script %s:%d: not 'FRAME KEY' with FRAME a whole number in [0, %d] (e.g. '3 TAB')", path,
                      line, SCRIPT_MAX_FRAME);
            rc = -1;
        } else if (n && frame < out[n - 1].frame) {
            log_error("--script %s:%d: frame %ld comes before the previous line's %d", path, line, frame,
                      out[n - 1].frame);
            rc = -1;
        } else if (n == max) {
            log_error("--script %s:%d: more than %d events", path, line, max);
            rc = -1;
        } else if (parse_key(key, &out[n].key, &out[n].mods) != 0) {
            struct strbuf names = {0};
            for (size_t i = 0; i < KEY_NAME_COUNT; i++)
                strbuf_printf(&names, ", %s", key_names[i].name);
            log_error("--script %s:%d: unknown key '%s' (A-Z, 0-9%s; shift+KEY)", path, line, key, names.data);
            strbuf_free(&names);
            rc = -1;
        } else {
            out[n++].frame = (int)frame;
        }
    }
    free(text);
    return rc ? -1 : n;
}
