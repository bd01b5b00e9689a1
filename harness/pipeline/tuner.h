/* What `shadowbench tune` does for one technique (docs/tuning.md): its tuned
 * parameters explored over the scenes by coordinate descent
 * (score/tune_search.h) from the defaults; its frontier (error against
 * time over every setting tried, score/frontier.h), the best setting per
 * scene (an oracle) and a setting per scene chosen on the other scenes
 * (leave-one-scene-out), as the record a tuned file holds
 * (score/tuned.h). */
#ifndef SB_TUNER_H
#define SB_TUNER_H

#include "cell.h"
#include "score/tune_search.h"

#include <cjson/cJSON.h>

#define TUNE_MAX_VALUES 32

/* How the search is described in every file it writes. */
#define TUNE_SEARCH_TEXT                                                                          \
    "coordinate descent from the defaults: each tuned parameter in table order tried at every "   \
    "one of its values with the others held, the strictly best mean objective over the scenes "   \
    "taken; rounds until one changes nothing (at most " UTIL_STR(TUNE_MAX_ROUNDS) "). "           \
    "Deterministic: no random choices, ties keep the earlier point. Each scene's fold is chosen on the "  \
    "other scenes of its light's kind (area lights, the sun), which generalises better than all of "      \
    "them (docs/tuning.md); a scene alone of its kind, on every other scene"

/* What a tuning measures with. */
struct tune_options {
    int width, height, gt_samples, shadow_map_size;
    int frames, warmup;           /* of the cells the record reports, timed again */
    enum stage_timing timing;
    int objective;                /* METRIC_*: the error minimised, its mean over the scenes */
    bool cost_fetches;            /* the frontiers' cost: fetches_per_pixel (counted), else ms_total */
};

/* Starting guess of the cells per unit of tuner_size: coordinate descent
 * runs two or three rounds, and the folds add some more (measured: 2.5-4
 * on the shipped scenes). */
#define TUNE_PER_SIZE_GUESS 3.5

/* Progress over every technique of a command, for the ETA: start_ms now,
 * per_size TUNE_PER_SIZE_GUESS, size_left the sum of the tuners' sizes. */
struct tune_progress {
    double start_ms;
    long cells;          /* evaluated so far, every technique */
    long cells_finished; /* by the techniques finished */
    double size_left;    /* tuner_size of the others */
    double per_size;     /* cells per unit of tuner_size: a guess, then measured */
    double size_finished;
};

struct tune_dim {
    const struct technique_param *p;
    double values[TUNE_MAX_VALUES];
    int count;
};

struct tuner {
    const struct tune_options *o;
    const struct technique *t;
    const void *base;          /* the settings the search starts from: the defaults, or --set's */
    unsigned long long held;   /* bit k: t->params[k] is held at base's value, not searched */
    struct tune_dim dims[TUNE_MAX_DIMS];
    int dim_count;
    int start[TUNE_MAX_DIMS];  /* the defaults, as value indices */
    const struct scene *scenes;
    struct scene_setup *setups;  /* opened, one per scene */
    int scene_count;
    struct tune_memo memo;
    struct tune_progress *progress;
};

/* Technique t's space (its tuned parameters and their values, but those
 * `held`) over the scenes, their setups open; every point takes base's
 * value of each parameter it does not search (base outlives the tuner).
 * Returns 0 or -1 (logged: a table whose tune values lack its default). */
int tuner_init(struct tuner *tn, const struct technique *t, const void *base, unsigned long long held,
               const struct tune_options *o, const struct scene *scenes, struct scene_setup *setups, int scene_count,
               struct tune_progress *progress);

/* The cells one search round costs: one point per value of each
 * parameter, on every scene (the ETA's unit). */
double tuner_size(const struct tuner *tn);

/* The same of technique t with the parameters `held` held, per scene. */
double tune_space_size(const struct technique *t, unsigned long long held);

enum tuner_result {
    TUNER_FAILED = -1,    /* a runtime error, logged */
    TUNER_DONE = 0,
    TUNER_UNDEFINED = 1,  /* the objective has no value on a scene at the defaults (logged): bad input */
};

/* Searches, cross-validates and times again what the record reports; the
 * record (without provenance) into *record. */
enum tuner_result tuner_run(struct tuner *tn, cJSON **record);

void tuner_free(struct tuner *tn);

#endif
