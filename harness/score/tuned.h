/* Tuned settings: results/tuned/<technique>.json (docs/design.md §8), written by
 * `shadowbench tune --write-tuned`, read by run (the <technique>@tuned
 * cells), check (their baselines) and the report (the frontier chart).
 *
 * A tuned file holds, besides its evidence, one setting per shipped scene:
 * the one the search chose on every other scene (leave-one-scene-out), so a
 * tuned cell is never scored on a scene its setting was fitted to; and, for
 * a scene the tuning did not see, the setting chosen on every scene of its
 * light's kind (area lights, the sun: "settings_by_light", written when the
 * tuning saw both kinds, for a kind of two or more scenes), else the one
 * chosen on every scene. */
#ifndef SB_TUNED_H
#define SB_TUNED_H

#include "scene/scene.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>

#define TUNED_DEFAULT_DIR "results/tuned"
#define TUNED_SUFFIX "@tuned"  /* a tuned cell's name: <technique>@tuned */
#define TUNED_MAX_ERROR 1e3      /* what a file may hold: errors, */
#define TUNED_MAX_FRONTIER 10000 /* and points in one frontier */

/* The light kinds a tuning chooses apart ("settings_by_light"'s keys). */
enum { TUNED_KIND_AREA, TUNED_KIND_SUN };
extern const char *const tuned_kind_names[2];  /* by TUNED_KIND_* */

/* Scene s's kind, TUNED_KIND_*. */
int tuned_kind(const struct scene *s);

/* A point of a frontier chart: mean error and time over scenes. */
struct tuned_point {
    double error, ms, ms_q1, ms_q3;
    double fetches;  /* fetches_per_pixel, or NAN: not counted */
};

struct tuned {
    const struct technique *t;
    char *path;
    cJSON *doc;                /* the whole file, validated */
    int width, height, shadow_map_size;           /* the tuning's */
    const char *objective, *gl_renderer, *date;   /* into doc */
    bool cost_fetches;                            /* its frontiers by fetches ("cost": "fetches"), else by ms */
    void *settings;            /* chosen on every scene */
    void *kind_settings[2];    /* chosen on every scene of a light kind (TUNED_KIND_*), or NULL */
    int fold_count;
    const char **fold_scene;   /* into doc */
    void **fold_settings;      /* chosen without that scene */
};

/* What tuned_load found. */
enum tuned_load_result {
    TUNED_ERROR = -1,  /* one line logged, naming the file */
    TUNED_LOADED = 0,
    TUNED_NONE = 1,    /* no file: nothing logged */
};

/* Reads dir/<t>.json: TUNED_LOADED; TUNED_NONE when there is none; or
 * TUNED_ERROR: not JSON, another technique, a setting that names an
 * unknown parameter, lacks one, or is out of range (a stale file: tune
 * again). */
enum tuned_load_result tuned_load(const char *dir, const struct technique *t, struct tuned *out);

/* The settings of t's tuned cell on scene s: its fold's, or (a scene the
 * tuning did not see) its light kind's, or the all-scene one. */
const void *tuned_settings(const struct tuned *tu, const struct scene *s);

/* The frontier over every scene ("all") or one scene's, as points sorted by
 * time, with the labels of their settings; and the default and tuned
 * points. Returns the count (0: none recorded). *points is malloc'ed. */
int tuned_frontier(const struct tuned *tu, const char *scene_name, struct tuned_point **points,
                   struct tuned_point *def, struct tuned_point *tuned);

void tuned_free(struct tuned *tu);

#endif
