/* Engine cells (docs/engines.md; docs/design.md §12): a real renderer's own
 * shadow output, scored like a technique's. The cell's technique names an
 * adapter (engines/<engine>/) instead of a shader; this module starts the
 * engine driver (engines/driver/driver.mjs, under Node.js) the first time
 * a cell needs it, which starts one headless Chromium for the whole
 * process, and hands it one cell at a time over a pipe.
 *
 * No browser outlives the command: Chromium, on its DevTools pipe, exits
 * when the driver does (and cleans up after itself). The driver runs in
 * its own process group, which the signal handler kills (util.h:
 * util_child_group); the shutdown at exit lets the driver close the
 * browser, then kills what is left of both (the browser runs in a session
 * of its own). */
#ifndef SB_ENGINE_H
#define SB_ENGINE_H

#include "techniques/technique.h"

#include <stdbool.h>

struct scene;
struct light_frustum;

/* What an engine cell can hand back, each W x H float32, top row first:
 * X(ID, name). */
#define ENGINE_OUTPUTS(X)                                                                      \
    X(SHADOW, "shadow")     /* the shadow factor alone, through the engine's material path */  \
    X(DISTANCE, "distance") /* the camera distance of the surface seen; -1: none (coverage) */  \
    X(LIT, "lit")           /* a lit render (the engine's diffuse material), shadows on */     \
    X(UNLIT, "unlit")       /* the same render with the receivers' shadows off */

enum engine_output {
#define X(id, name) ENGINE_OUT_##id,
    ENGINE_OUTPUTS(X)
#undef X
    ENGINE_OUTPUT_COUNT
};

struct engine_request {
    const struct technique *t;         /* t->engine names the adapter */
    const void *settings;
    const struct scene *scene;         /* its file is what the engine loads */
    const struct light_frustum *frustum;  /* the scene's fitted light frustum (the spot's or the sun's) */
    const char *label;                 /* the cell's name, for messages */
    int width, height, map_size;
    int warmup, frames;                /* frames >= 1 are timed, after warmup untimed ones */
    unsigned outputs;                  /* 1u << ENGINE_OUT_*: the images wanted */
};

struct engine_result {
    float *image[ENGINE_OUTPUT_COUNT];  /* the caller's W x H buffers, one per output asked */
    char version[64];                   /* the engine's, as it reports it (three's "r187") */
    char renderer[256];                 /* the WebGL renderer string: the device of its times */
    double ms, ms_q1, ms_q3;            /* median and quartiles of its frames' times */
    double texel_ratio[2];              /* its map's texel over shadowbench's fitted map's at the same
                                           size, along the light's x and y (docs/engines.md); NaN where
                                           the adapter does not say (a map not of one texel size) */
    char notice[256];                   /* what the adapter says the numbers do not show, one line;
                                           "" for nothing */
};

/* Renders r with its engine into out. Returns 0, or -1 after logging one
 * line that names the engine and the cell (no Chromium, an engine that is
 * not installed or fails to load, a page error, over the time limit, an
 * image of the wrong size). After a failure the driver is stopped; the
 * next request starts a new one, but a browser that did not start is
 * not waited for again: every later request fails at once with its
 * reason. */
int engine_render(const struct engine_request *r, struct engine_result *out);

/* Whether engine (a technique's .engine) can render here: Chromium, the
 * driver's and the engine's npm packages installed (tools/setup). */
bool engine_installed(const char *engine);

/* Whether an engine request has failed since the process started (a
 * command's exit status is then 2), and the last failure's line. */
bool engine_faulted(void);
const char *engine_last_error(void);

/* The longest a request may take, seconds, from its start to its reply
 * (the browser's start and the engine's load included); 0 restores the
 * default, ENGINE_TIME_LIMIT_S. */
#define ENGINE_TIME_LIMIT_S 120.0
void engine_set_time_limit(double seconds);

/* Stops the driver (and so the browser), if running; removes its
 * temporary folder. Registered with atexit at the first start. */
void engine_shutdown(void);

#endif
