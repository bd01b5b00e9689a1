/* The viewer's --script: key events replayed, one a line, "FRAME KEY" (the
 * key pressed before frame FRAME is drawn, frames counted from 0, in
 * order; KEY: A-Z, 0-9 or a name of key_names, optionally after
 * "shift+"), blank lines and # comments. */
#ifndef SB_SCRIPT_H
#define SB_SCRIPT_H

#include <stddef.h>

#define SCRIPT_MAX_EVENTS 4096        /* key events in a script */
#define SCRIPT_MAX_BYTES (1 << 20)
#define SCRIPT_MAX_FRAME 100000000    /* also the most frames the viewer draws */

/* The keys the viewer answers to besides A-Z and 0-9, by the names a
 * script uses, with their GLFW key codes. */
struct key_name {
    const char *name;
    int key;
};
enum { KEY_NAME_COUNT = 11 };
extern const struct key_name key_names[KEY_NAME_COUNT];

struct script_event {
    int frame, key, mods;  /* GLFW key code and modifier bits */
};

/* Reads path into out[0..max-1]. Returns the number of events, or -1
 * (logged: "--script <path>:<line>: ..."). */
int script_load(const char *path, struct script_event *out, int max);

#endif
