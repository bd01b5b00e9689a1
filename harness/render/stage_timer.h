/* Time of the GL stages of a frame (docs/design.md §7). The cells of a scene are
 * timed interleaved: warm-up rounds, then K rounds, each round one frame of
 * every cell in turn, so a slow spell of the machine is shared by the cells
 * rather than landing on one. A timed frame is the whole of a cell's work:
 * its shadow-map products rendered afresh (every cascade's), then its
 * screen-space stages and receiver pass (one per cascade): the penumbra
 * mask, the receiver pass, the denoiser. Each stage is
 * timed by wall clock around glFinish on a CPU rasteriser (llvmpipe, where
 * GL timer queries do not measure the work), by a GL_TIME_ELAPSED query on
 * a GPU (the wall clock there would add the driver's submission and the
 * stall). */
#ifndef SB_STAGE_TIMER_H
#define SB_STAGE_TIMER_H

#include "receiver.h"
#include "techniques/cascades.h"

#define STAGE_TIMER_MAX_FRAMES 1000

/* One cell to time: a technique at its settings, drawn with programs. */
struct stage_timer_cell {
    const struct technique *technique;
    const void *settings;
    struct receiver_programs programs;
};

/* Milliseconds per frame of one cell: the median of each stage over the K
 * frames, and the median and quartiles of the frames' totals. */
struct stage_times {
    double shadowmap_ms;    /* the depth pass */
    double filter_prep_ms;  /* the products derived from it that the technique samples */
    double mask_ms;         /* the penumbra mask's pre-pass and dilation */
    double receiver_ms;     /* the receiver pass */
    double denoise_ms;      /* the denoiser's passes */
    double total_ms, total_q1_ms, total_q3_ms;
};

enum stage_timing { STAGE_TIMING_AUTO, STAGE_TIMING_WALL, STAGE_TIMING_QUERY };

/* "auto", "wall" or "query" into *out: 0, or -1 for another name (not logged). */
int stage_timing_parse(const char *name, enum stage_timing *out);

/* The method auto picks for the current context (wall on a CPU
 * rasteriser, query elsewhere), or m itself. */
enum stage_timing stage_timing_resolve(enum stage_timing m);

/* The method in words, for run.json and the charts. */
const char *stage_timing_text(enum stage_timing m);

struct stage_timer {
    struct shadow_cascades *cascades;  /* the scene's maps (one, or a cascade each) */
    const struct scene_mesh *mesh;
    struct receiver *receiver;
    int warmup, frames;  /* frames in [1, STAGE_TIMER_MAX_FRAMES] */
    enum stage_timing timing;
    /* Called after each round (may be NULL): progress on long work. */
    void (*on_round)(void *user, int round, int rounds);
    void *user;
};

/* Times the n cells interleaved; out[i] is cell i's. Returns 0 or -1 (logged). */
int stage_timer_run(const struct stage_timer *timer, const struct stage_timer_cell *cells, int n,
                    struct stage_times *out);

/* One untimed frame of a cell, which leaves its V_tech in the receiver's
 * targets: its products rendered only where the shadow map does not hold
 * them for this pose and these options already (shadowmap_ensure_product:
 * the cells of a pose that agree share them), then its stages. counting:
 * the cell's programs are the counting variants (receiver_read_cost).
 * Returns 0 or -1 (logged). */
int stage_timer_render(const struct stage_timer *timer, const struct stage_timer_cell *cell, bool counting);

/* Texels read and written by the passes that build cell's products other
 * than the depth map, every cascade's, per frame (docs/metrics.md:
 * prep_texels). */
double stage_timer_prep_texels(const struct stage_timer *timer, const struct stage_timer_cell *cell);

#endif
