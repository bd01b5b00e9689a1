/* The stability study (`shadowbench stability`; docs/stability.md): where
 * methods fail, on purpose.
 *
 * Motions (scene/motion.h): the scene moves for K frames, each frame ray
 * traced (its own ground truth, cached per pose) and rendered by every
 * technique, and scored by flicker (score/flicker.h): how much each pixel's
 * error changes from frame to frame, against the ground truth's own
 * frame-to-frame noise. Techniques with per-pixel noise are measured with
 * it still (as every other command scores them) and animated by the frame
 * index (their animate_noise on; Jimenez 2014), each per frame and
 * accumulated by the moving average TAA keeps.
 *
 * Variations: one thing varied over a list of values (the shadow map's
 * size, the light's size, the map's depth range, or a technique
 * parameter), the error of each technique against it, and where each
 * breaks (score/break_rule.h). The pages are output/stability_page.h's. */
#ifndef SB_STABILITY_H
#define SB_STABILITY_H

#include "cell.h"
#include "scene/motion.h"
#include "score/flicker.h"

#include <stdbool.h>

#define STABILITY_MIN_FRAMES 2             /* of a motion: flicker needs a pair */
#define STABILITY_MAX_FRAMES 256
#define STABILITY_DEFAULT_ACCUMULATE 0.1   /* a new frame's weight in the moving average */
#define STABILITY_MAX_VALUES 32
#define STABILITY_MAX_VARIATIONS 16
#define STABILITY_MAX_TECHNIQUES TECHNIQUE_SELECTION_MAX

/* What --vary takes besides T.P: X(ID, name, reference value, smallest,
 * largest, meaning). */
#define STABILITY_VARIABLES(X)                                                                        \
    X(MAP_SIZE, "shadow_map_size", NAN, SHADOWMAP_MIN_SIZE, SHADOWMAP_MAX_SIZE,                      \
      "the shadow map's side in texels (reference: --shadow-map-size)")                              \
    X(LIGHT_SCALE, "light_scale", 1.0, 1.0 / 64, 64.0,                                               \
      "the light's size times this (the ground truth follows)")                                       \
    X(DEPTH_RANGE, "depth_range", 1.0, 1.0, 1e6,                                                      \
      "the shadow map's near plane pulled towards the light to near / this: the scene's depths fill " \
      "less of the map's depth range, as with an engine's fixed small near plane")                     \
    X(CASCADES, "cascades", NAN, 1, CASCADES_MAX,                                                      \
      "the sun's cascades (reference: --cascades; a scene with an area light has one map whatever the value)") \
    X(CASCADE_LAMBDA, "cascade_lambda", NAN, 0, 1,                                                     \
      "the practical split's lambda, 0 uniform to 1 log (reference: --cascade-split's, practical:0.5 by default)")

enum variable_kind {
#define X(id, name, ref, lo, hi, help) VARY_##id,
    STABILITY_VARIABLES(X)
#undef X
    VARY_PARAM,  /* a technique parameter: T.P */
};

struct stability_variable {
    const char *name, *help;
    double reference, lo, hi;  /* reference NAN: --shadow-map-size */
};
extern const struct stability_variable stability_variables[VARY_PARAM];

struct variation {
    enum variable_kind kind;
    const struct technique *t;       /* VARY_PARAM: the technique and its parameter */
    const struct technique_param *p;
    char name[96];                   /* "shadow_map_size", "pcf.radius_texels" */
    int count;
    double values[STABILITY_MAX_VALUES];  /* increasing; VARY_PARAM enum/bool: the index */
    char *texts[STABILITY_MAX_VALUES];    /* as given (VARY_PARAM: for params_set) */
    int reference;                   /* the index of the reference value */
    bool log_x;                      /* the values span decades: a log axis */
};

/* One line of the motion results: a technique with its noise still or
 * animated, per frame or accumulated, on one scene and motion. */
struct motion_row {
    int scene, motion;
    const struct technique *t;
    bool animated, accumulated;
    char label[64];  /* "pcf", "pcf+ema", "pcf~anim", "pcf~anim+ema": its folder */
    struct flicker_result r;
    double *frame_rmse;  /* each frame's rmse (NAN: nothing scored), r.frames of them (owned) */
    long nonfinite;  /* NaN/Inf values over the frames */
};

/* One point of a variation: a technique at one value on one scene. */
struct vary_point {
    int scene, variation, value;
    const struct technique *t;
    struct metrics m;
    bool broken;  /* against the reference value (stability_judge) */
};

/* A frame of a motion row that is not accumulated, as it is rendered: for
 * its pictures. Returns 0, or -1 (logged) to stop. */
typedef int (*stability_frame_fn)(void *user, const struct motion_row *row, int frame, int frames,
                                  const struct scene_setup *ss, const float *v);

struct stability {
    /* set by the caller */
    int width, height, gt_samples, shadow_map_size, frames;
    struct cascade_settings cascades;    /* the sun's maps (the reference of --vary cascades, ...) */
    double accumulate;                   /* a new frame's weight in the moving average */
    const char *cache_dir;
    const struct technique *techniques[STABILITY_MAX_TECHNIQUES];
    const void *settings[STABILITY_MAX_TECHNIQUES];  /* each technique's */
    int technique_count;
    const struct scene *scenes;
    int scene_count;
    stability_frame_fn on_frame;         /* may be NULL */
    void *user;
    /* the study */
    struct motion *motions;
    int motion_count, motion_capacity;
    struct variation vars[STABILITY_MAX_VARIATIONS];
    int var_count;
    struct program_cache programs;
    struct motion_row *rows;
    int row_count;
    struct vary_point *points;
    int point_count;
};

/* Adds m to the motions unless an equal one already runs on the scenes m
 * runs on: a motion given twice on the command line or in one scene's
 * list is an error; a scene's motion that the command line gives already
 * runs once. Two different motions whose folder names agree are an
 * error. Returns 0 or -1 (logged). */
int stability_add_motion(struct stability *st, const struct motion *m);

/* The node each caster motion moves, found in every scene it runs on; and
 * each light_scale value keeps every sun within the scene format's 30
 * degrees across. Returns 0 or -1 (logged). */
int stability_check_nodes(const struct stability *st);

/* Parses --vary spec (NAME=V1,V2,...) into the next variation; the
 * reference value is added when not listed. Returns 0 or -1 (logged). */
int stability_add_variation(struct stability *st, const char *spec);

/* Runs motion m on scene s: its rows, scored. Returns 0 or -1 (logged). */
int stability_motion(struct stability *st, int s, int m);

/* Runs variation v on scene s: its points. Returns 0 or -1 (logged). */
int stability_vary(struct stability *st, int s, int v);

/* Marks each point broken or not against its reference value. */
void stability_judge(struct stability *st);

/* The point of (scene, variation, value, technique), or NULL. */
const struct vary_point *stability_point(const struct stability *st, int s, int var, int value,
                                         const struct technique *t);

/* Where t breaks on scene s under var (indices of values, -1: holds). */
void stability_break_points(const struct stability *st, int s, int var, const struct technique *t, int *below,
                            int *above);

/* Every value that breaks t on scene s under var, in the variable's
 * order, as text ("" for none): past a break point a value may hold again
 * (a break point is where breaking starts, not a range). */
void stability_broken_values(const struct stability *st, int s, int var, const struct technique *t,
                             struct strbuf *out);

void stability_free(struct stability *st);

#endif
