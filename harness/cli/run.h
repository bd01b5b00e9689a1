/* The harness loop: scenes x techniques -> cells, and the `gt` command. */
#ifndef SB_RUN_H
#define SB_RUN_H

#include "gl/gl_context.h"
#include "gl/scene_mesh.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
#include "score/metrics.h"
#include "techniques/shadowmap.h"
#include "techniques/technique.h"
#include "truth/groundtruth.h"

#include <cjson/cJSON.h>

/* Exit statuses (DESIGN.md §10). */
enum { EXIT_OK = 0, EXIT_CHECK_FAILED = 1, EXIT_USAGE = 2 };

#define RUN_MAX_SCENES 64
#define RUN_MAX_TECHNIQUES 32
#define RUN_MAX_SWEEPS 16
#define RUN_MAX_CONFIGS 256

/* The commands that render: they share struct run_options. */
enum run_command { RUN_CMD_RUN, RUN_CMD_GT, RUN_CMD_BENCH, RUN_CMD_CHECK, RUN_CMD_TUNE, RUN_CMD_STABILITY, RUN_CMD_VIEW };

/* Which cells of each technique run makes (--settings). */
enum run_settings_mode { RUN_SETTINGS_BOTH, RUN_SETTINGS_DEFAULT, RUN_SETTINGS_TUNED };

/* Option defaults and ranges, one definition each: run_options_defaults()
 * and the option parser use them, and --help prints them (as text, through
 * RUN_STR). The shadow map's and the ground truth's own come from their
 * modules (SHADOWMAP_*, GT_*), the frame limit from the timer. */
#define RUN_DEFAULT_SIZE 512    /* run and gt: --width, --height */
#define BENCH_DEFAULT_SIZE 1024 /* bench: the receiver */
#define RUN_MIN_SIZE 16
#define RUN_MAX_SIZE 8192
#define RUN_DEFAULT_FRAMES 3
#define BENCH_DEFAULT_FRAMES 9
#define RUN_DEFAULT_WARMUP 0   /* the render that scores a cell warms it first */
#define BENCH_DEFAULT_WARMUP 3
#define RUN_MAX_WARMUP 100
#define RUN_DEFAULT_OUT "results/runs/latest"
#define GT_DEFAULT_OUT "results/gt"
#define RUN_DEFAULT_CACHE "results/cache"
#define CHECK_DEFAULT_OUT "results/check"
#define CHECK_DEFAULT_BASELINES "results/baselines"
#define TUNE_DEFAULT_OUT "results/tune/latest"
#define TUNE_DEFAULT_SIZE 256   /* tune: --width, --height */
#define TUNE_DEFAULT_FRAMES 3   /* the cells the files report, timed again (the search: 1) */
#define TUNE_DEFAULT_WARMUP 0   /* the cells timed again were rendered before */
#define STABILITY_DEFAULT_OUT "results/stability/latest"
#define STABILITY_DEFAULT_SIZE 256    /* stability: --width, --height */
#define STABILITY_DEFAULT_FRAMES 16   /* stability: frames of each motion */
#define STABILITY_DEFAULT_ACCUMULATE 0.1  /* stability: a new frame's weight in the moving average */
#define STABILITY_MIN_FRAMES 2
#define STABILITY_MAX_FRAMES 256
#define VIEW_DEFAULT_GT_SAMPLES 256  /* view: the last level of the ground truth's refinement */
#define RUN_MAX_MOTIONS 16
#define RUN_MAX_VARIES 16
#define RUN_STR_(x) #x
#define RUN_STR(x) RUN_STR_(x)  /* a default as text, for --help: plain literals only */

/* One technique with one parameter set: a column of the matrix. */
struct run_config {
    const struct technique *technique;
    void *settings;  /* owned */
    char *label;     /* the technique's name, or with its swept values:
                        "pcss@blocker_samples=16,filter_samples=64", or "pcss@tuned";
                        the cell's folder */
    struct tuned *tuned;  /* owned; a tuned cell: its settings differ by scene (tuned.h) */
};

/* The receiver programs of a command, one per technique, settings (their
 * bytes) and light shape, compiled on first use: a tuned cell's settings
 * differ by scene and are often the same. Zero-initialise. */
struct run_programs {
    struct run_program {
        const struct technique *t;
        void *settings;
        enum light_shape shape;
        GLuint program;
    } *entries;
    int count;
};

/* The program, compiled on first use; 0 after a logged compile error. */
GLuint run_program_get(struct run_programs *pc, const struct technique *t, const void *settings,
                       enum light_shape shape);
void run_programs_free(struct run_programs *pc);

/* The settings of config c on scene s: a tuned cell's for that scene. */
const void *run_config_settings(const struct run_config *c, const struct scene *s);

struct run_options {
    const char *scenes[RUN_MAX_SCENES];  /* names or paths; none = every shipped scene */
    int scene_count;
    const struct technique *techniques[RUN_MAX_TECHNIQUES];  /* at least one */
    int technique_count;
    void *settings[RUN_MAX_TECHNIQUES];  /* per technique_list index, every one set */
    int set_count;                       /* --set options given */
    const char *sweeps[RUN_MAX_SWEEPS];  /* --sweep T.P=v1,v2,... as given */
    int sweep_count;
    struct run_config *configs;          /* run: filled by sweep_configs() */
    struct strbuf untuned;               /* run: techniques without a tuned file ("a, b") */
    int config_count;
    int width, height;                   /* image size in pixels */
    int gt_samples;                      /* light samples per pixel of the ground truth */
    int shadow_map_size;                 /* texels */
    int frames;                          /* timed frames */
    int warmup;                          /* untimed frames first (0 allowed) */
    const char *out_dir;
    const char *cache_dir;               /* NULL: no ground-truth cache */
    const char *shader_dir;              /* NULL: found automatically */
    enum gl_backend gl;                  /* --gl: the context's backend */
    enum stage_timing timing;            /* --timing: how stages are timed */
    const char *baselines_dir;           /* check: the baselines read (and written by update) */
    bool update;                         /* check: record the selected baselines anew */
    bool strict;                         /* check: an improvement fails too */
    const char *tuned_dir;               /* run, check: tuned settings read; tune: written */
    enum run_settings_mode settings_mode;  /* run: default, tuned or both cells */
    int objective;                       /* tune: the metric minimised (METRIC_*) */
    bool write_tuned;                    /* tune: write tuned_dir/<technique>.json */
    const char *motions[RUN_MAX_MOTIONS];  /* stability: --motion specs as given */
    int motion_count;
    const char *varies[RUN_MAX_VARIES];    /* stability: --vary specs as given */
    int vary_count;
    double accumulate;                   /* stability: the accumulation's weight of a new frame */
    const char *screenshot;              /* view: the PNG the last frame is written to */
    const char *script;                  /* view: key events replayed */
    int argc;                            /* the command line, for run.json */
    char **argv;
};

/* Every option of command cmd at its default (before the command line
 * overrides them: 0 warm-up frames and no cache are choices, not "unset"). */
void run_options_defaults(struct run_options *o, enum run_command cmd);

int run_main(const struct run_options *o);
int run_gt(const struct run_options *o);

/* What the cells of one scene share (run and check): the ground truth, the
 * scene's mesh, the shadow map, the receiver, and the last cell's images. */
struct scene_setup_desc {
    int width, height, shadow_map_size, gt_samples;
    uint32_t gt_seed;       /* 0: the ground truth's default */
    const char *cache_dir;  /* NULL: no ground-truth cache */
    float near_scale;       /* the shadow map's (shadowmap_desc); 0: 1 */
};

struct scene_setup {
    const struct scene *scene;
    int width, height;
    struct gt_image gt;
    struct scene_mesh mesh;
    struct shadowmap sm;
    struct receiver receiver;
    struct stage_timer timer;      /* untimed: frames and warm-up unset */
    float *v, *distance, *scored;  /* the last cell's V_tech, GL distance, scored mask */
};

/* Returns 0 or -1 (logged); scene_setup_free either way. */
int scene_setup_open(struct scene_setup *ss, const struct scene *s, const struct scene_setup_desc *d);

/* Renders a cell once, untimed, reads it back (ss->v, ss->distance) and
 * scores it into m (the accuracy metrics; its timing fields are left as
 * they are). Returns 0 or -1 (logged). */
int scene_setup_cell(struct scene_setup *ss, const struct stage_timer_cell *cell, struct metrics *m);

/* Scores what the receiver holds now (the last frame rendered). */
void scene_setup_score(struct scene_setup *ss, struct metrics *m);

void scene_setup_free(struct scene_setup *ss);

/* Loads every scene named in o (or every shipped one) before any heavy
 * work, so bad input fails fast. Returns 0 or -1 (logged). */
int run_load_scenes(const struct run_options *o, struct scene *scenes, int *count);

/* Creates dir and checks it is writable. Returns 0 or -1 (logged). */
int run_prepare_out_dir(const char *dir);

/* run_prepare_out_dir, then an exclusive lock on it for the rest of the
 * process (a second shadowbench on it fails at once) and the removal of
 * temporaries a killed run left there. Returns 0 or -1 (logged). */
int run_claim_out_dir(const char *dir);

/* The command line, as UTF-8 text (any other byte as U+FFFD); malloc'ed. */
char *run_command_line(const struct run_options *o);

/* A committed results folder (baselines, tuned settings: files in it and
 * no .lock in a fresh clone): made if need be, locked, and its own
 * temporaries (depth levels down) removed; nothing else touched. Returns 0
 * or -1 (logged). */
int run_claim_results_dir(const char *dir, int depth);

/* Now, in UTC, as the outputs write it: "2026-11-23T22:28:48Z"; malloc'ed. */
char *run_utc_date(void);

/* What run.json records of a command: its line, the versions, the device,
 * the date, the sizes, frames and the seconds it took. */
cJSON *run_json(const struct run_options *o, double seconds);

/* `git describe --always --dirty` of the source tree, or "unknown"; malloc'ed. */
char *run_git_describe(void);

/* The settings of technique t in o. */
void *run_settings(const struct run_options *o, const struct technique *t);

#endif
