/* The harness loop: scenes x techniques -> cells, and the `gt` command. */
#ifndef SB_RUN_H
#define SB_RUN_H

#include "techniques/technique.h"

/* Exit statuses (DESIGN.md §10). */
enum { EXIT_OK = 0, EXIT_CHECK_FAILED = 1, EXIT_USAGE = 2 };

#define RUN_MAX_SCENES 64
#define RUN_MAX_TECHNIQUES 32
#define RUN_MAX_SWEEPS 16
#define RUN_MAX_CONFIGS 256

/* One technique with one parameter set: a column of the matrix. */
struct run_config {
    const struct technique *technique;
    void *settings;  /* owned */
    char *label;     /* the technique's name, or with its swept values:
                        "pcss@blocker_samples=16,filter_samples=64"; the cell's folder */
};

struct run_options {
    const char *scenes[RUN_MAX_SCENES];  /* names or paths; none = every shipped scene */
    int scene_count;
    const struct technique *techniques[RUN_MAX_TECHNIQUES];  /* at least one */
    int technique_count;
    void *settings[RUN_MAX_TECHNIQUES];  /* per technique_list index, every one set */
    const char *sweeps[RUN_MAX_SWEEPS];  /* --sweep T.P=v1,v2,... as given */
    int sweep_count;
    struct run_config *configs;          /* run: filled by sweep_configs() */
    int config_count;
    int width, height;                   /* image size, default 512 x 512 */
    int gt_samples;                      /* default 1024 */
    int shadow_map_size;                 /* default 1024 */
    int frames;                          /* timed frames, default 5 */
    int warmup;                          /* untimed frames first (0 allowed; the CLI's default is 2) */
    const char *out_dir;                 /* default results/runs/latest */
    const char *cache_dir;               /* NULL: no ground-truth cache */
    const char *shader_dir;              /* NULL: found automatically */
    int argc;                            /* the command line, for run.json */
    char **argv;
};

int run_main(const struct run_options *o);
int run_gt(const struct run_options *o);

/* The settings of technique t in o. */
void *run_settings(const struct run_options *o, const struct technique *t);

#endif
