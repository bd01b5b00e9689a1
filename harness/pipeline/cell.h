/* The cell pipeline (docs/design.md §2): the library every command calls. A
 * scene is opened once for its cells (its mesh, its shadow map, its
 * receiver, its ground truth); a cell (one technique at one parameter set)
 * is rendered on it, its stages untimed, and scored against the truth;
 * the cells of a scene are then timed together, interleaved. Writing a
 * cell's files is output/cell_output.h's.
 *
 * Receiver programs come from a program cache the caller keeps across
 * scenes (programs.h): a setting met again is not compiled again. */
#ifndef SB_CELL_H
#define SB_CELL_H

#include "programs.h"
#include "engine/engine.h"
#include "gl/scene_mesh.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
#include "score/depth_metrics.h"
#include "score/metrics.h"
#include "techniques/cascades.h"
#include "techniques/technique.h"
#include "truth/groundtruth.h"

#include <cjson/cJSON.h>

struct scene_setup;

/* One (scene, technique, parameter set) evaluation: a row of the matrix. */
struct cell {
    const char *scene;                   /* scene name */
    const struct technique *technique;
    const char *label;                   /* the configuration: the technique's name, or with its
                                            swept values ("pcss@blocker_samples=16"), or
                                            "pcss@tuned"; its folder */
    cJSON *params;                       /* values used (owned) */
    char *params_text;                   /* "name=value name=value" (owned) */
    const char *gl_renderer;             /* the device the timings were taken on (an engine cell's:
                                            its browser's WebGL renderer) */
    char *engine_version;                /* an engine cell's engine version (owned), or NULL */
    char *engine_renderer;               /* its renderer string (owned; gl_renderer points to it) */
    double engine_texel_ratio[2];        /* its map's texel over shadowbench's (engine.h); NaN: not said */
    char *failed;                        /* a failed engine cell's reason (run --keep-going; owned), or
                                            NULL; its metrics are then none (metrics_none) */
    char *notice;                        /* what the numbers do not show, one line (owned), or NULL:
                                            cell_note_search */
    struct metrics m;
    struct depth_metrics depth;          /* the error by view depth, by slice, at each split */
    cJSON *cascades;                     /* the maps it was rendered with (owned; shadow_cascades_json) */
};

/* c as technique t at settings on scene `scene`, named label (strings
 * not copied); its metrics zero. */
void cell_describe(struct cell *c, const char *scene, const struct technique *t, const void *settings,
                   const char *label);

/* The times of a frame of c into its metrics. */
void cell_set_times(struct cell *c, const struct stage_times *t);

/* Notes (c->notice, and once in the log) that c's technique searches for
 * blockers over a region wider than a shadow map of cs: its
 * light_size_scale times the light's size, at the map's farthest
 * receiver, against the map's side (light_frustum_search_box_texels).
 * Past the map's edge the search reads edge texels (the edge policy),
 * never what is there. */
void cell_note_search(struct cell *c, const void *settings, const struct shadow_cascades *cs);

/* After scene_setup_cell: what ss rendered c with (c->cascades; an engine
 * cell's engine, version and renderer) and c's error by view depth
 * (c->depth). */
void cell_take_setup(struct cell *c, const struct scene_setup *ss);

/* Frees what cell_describe made. */
void cell_free(struct cell *c);

/* What the cells of one scene share. Zero means default (gt_seed, near_scale). */
struct scene_setup_desc {
    int width, height, shadow_map_size, gt_samples;
    uint32_t gt_seed;                /* 0: the ground truth's default */
    const char *cache_dir;           /* NULL: no ground-truth cache */
    float near_scale;                /* the shadow map's (shadowmap_desc); 0: 1 */
    struct program_cache *programs;  /* the caller's, required */
    const struct cascade_settings *cascades;  /* the sun's (NULL: one map over the view) */
};

struct scene_setup {
    const struct scene *scene;
    int width, height;
    struct program_cache *programs;
    struct gt_image gt;
    struct scene_mesh mesh;
    struct shadow_cascades cascades;  /* its maps: one, or the sun's cascades */
    struct receiver receiver;
    struct stage_timer timer;      /* untimed: frames and warm-up unset */
    float *v, *distance, *scored;  /* the last cell's V_tech, GL distance, scored mask */
    float *shortcut;               /* the last scored cell's pixels an early-out or the mask decided */
    struct depth_metrics depth;    /* the last cell's error by view depth */
    float *view_depth;             /* each pixel's view depth (the truth's hit along the camera's
                                      axis; -1: none), what cascades are cut by */
    bool engine_last;              /* the last frame was an engine's: ss->v holds it */
    struct engine_result engine;   /* the last engine frame's version, renderer and times */
};

/* Opens scene s for cells: mesh, shadow map, receiver, ground truth
 * (obtained through the cache). Returns 0 or -1 (logged); scene_setup_free
 * either way. */
int scene_setup_open(struct scene_setup *ss, const struct scene *s, const struct scene_setup_desc *d);

/* After the ground truth of a new pose is in ss->gt: the pixels' view
 * depths, and the pixels past the shadow distance out of its mask
 * (scene_setup_open calls it). */
void scene_setup_truth_posed(struct scene_setup *ss);

/* Technique t at settings on this scene, to be timed: its programs (not
 * the counting ones); .programs.receiver 0 after a logged compile error
 * (scene_setup_cell_ready says which). An engine cell has no programs. */
struct stage_timer_cell scene_setup_timer_cell(struct scene_setup *ss, const struct technique *t,
                                               const void *settings);

/* Whether a timer cell can be rendered: an engine cell, or one whose
 * programs compiled. */
static inline bool scene_setup_cell_ready(const struct stage_timer_cell *c)
{
    return technique_is_engine(c->technique) || c->programs.receiver != 0;
}

/* Renders a cell once, untimed, with its counting programs, reads it back
 * (ss->v, ss->distance) and scores it into m: the accuracy metrics and the
 * counted costs (fetches_per_pixel, prep_texels, expensive_fraction,
 * misclassified_fraction); its timing fields are left as they are. An
 * engine cell is rendered by its engine (engine/engine.h), its counted
 * costs unknown (NaN: null in its files). Returns 0 or -1 (logged). */
int scene_setup_cell(struct scene_setup *ss, const struct technique *t, const void *settings, struct metrics *m);

/* Scores what the receiver holds now (the last frame rendered, of t) into
 * m, and its error by view depth into ss->depth: the accuracy metrics, not
 * the counted costs. */
void scene_setup_score(struct scene_setup *ss, const struct technique *t, struct metrics *m);

/* How a scene's cells are timed (stage_timer.h): warmup untimed rounds,
 * then frames rounds, each round one frame of every cell in turn; on_round
 * (may be NULL) is called after each round. */
struct scene_setup_timing {
    int warmup, frames;
    enum stage_timing timing;
    void (*on_round)(void *user, int round, int rounds);
    void *user;
    bool *engine_failed;  /* NULL: an engine cell's failure fails the timing; else [n]: set for a failed
                             engine cell (its times NaN) while the others are timed (run --keep-going) */
};

/* Times the n cells interleaved; out[i] is cell i's. An engine cell is
 * timed by its engine, in its browser, its frames after its warm-up in a
 * row (not interleaved: another process), its stages unknown (NaN); its
 * last frame is left in ss->v. Returns 0 or -1 (logged). */
int scene_setup_time(struct scene_setup *ss, const struct scene_setup_timing *how, const struct stage_timer_cell *cells,
                     int n, struct stage_times *out);

void scene_setup_free(struct scene_setup *ss);

#endif
