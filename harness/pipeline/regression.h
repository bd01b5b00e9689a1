/* The regression check's cells (`shadowbench check`; docs/regression.md).
 * Its cells: every selected technique at its defaults on every
 * selected scene, its tuned cell where it has a tuned file, the cells its
 * descriptor declares (technique.h: .regression, each parameter away from
 * its default at least once, on a scene where it acts), and any other
 * baseline file found. A cell is named as run names it,
 * "<technique>[@<param>=<value>,...]", which is also its file's stem under
 * <baselines>/<scene>/. Baselines themselves are score/baseline.h's.
 *
 * Coverage (FFmpeg's FATE): a technique x scene without a baseline fails;
 * with every scene selected, a parameter that no declared cell sets fails;
 * and for each declared cell, setting each of its parameters back to the
 * default must change the picture (else the parameter is ignored). */
#ifndef SB_REGRESSION_H
#define SB_REGRESSION_H

#include "cell.h"
#include "score/baseline.h"

#include <stdbool.h>

/* The noise frame (the receiver's) at which check renders every cell: a
 * program that does not animate its noise ignores it, and one
 * that does (animate_noise) shows a frame other than the still one, so the
 * parameter is seen to act. */
#define REGRESSION_NOISE_FRAME 1

struct regression_cell {
    const struct scene *scene;
    char *label;                 /* the cell's name and file stem */
    const struct technique *t;
    void *settings;              /* rendered: the baseline's, or (update, none) the label's */
    void *label_settings;        /* what the label means today */
    bool declared;               /* one of its technique's .regression cells */
    struct baseline_setup setup; /* what it is rendered at */
    char *json_path, *png_path;
    struct baseline base;        /* base.doc NULL: none */
    /* results */
    struct metrics now;
    float *v;                    /* V_tech now */
    struct baseline_comparison cmp;
    bool compared;               /* cmp is against the baseline */
    double spread[BASELINE_GUARDS];  /* update: over the ground-truth seeds */
};

struct regression {
    const char *baselines_dir, *tuned_dir;
    struct regression_cell *cells;
    int count, capacity;
};

/* The cells of the selected techniques on the selected scenes (see
 * above). Returns 0 or -1 (logged); regression_free either way. */
int regression_collect(struct regression *r, const struct scene *scenes, int scene_count,
                       const struct technique *const *techniques, int technique_count);

/* "<dir>/<scene>/<label>.<ext>": where c's baseline files lie in a
 * baselines folder (ext "json" or "png"); malloc'ed. */
char *regression_file(const char *dir, const struct regression_cell *c, const char *ext);

/* Reads cell c's baseline, if it has one. Returns 0 or -1 (logged). */
int regression_read(struct regression_cell *c);

/* Renders c at its settings on ss (its scene, opened at c->setup) into
 * c->now and c->v. Returns 0 or -1 (logged). */
int regression_render(struct scene_setup *ss, struct regression_cell *c);

/* A parameter of a technique, and its default as text. */
struct regression_param {
    const struct technique *t;
    const struct technique_param *p;
    char def[64];
};

/* The parameters of declared cell c (rendered on ss) that do not act:
 * setting one back to its default changes no pixel. Into out[0..max-1];
 * returns how many. Rules across parameters may refuse setting one back
 * alone (a grid needs a square tap count): such a parameter is shown to
 * act by another cell. */
int regression_idle_params(struct scene_setup *ss, const struct regression_cell *c, struct regression_param *out,
                           int max);

/* The parameters of the selected techniques that no declared cell sets
 * away from its default, into out[0..max-1]; returns how many. */
int regression_uncovered(const struct regression *r, const struct technique *const *techniques,
                         int technique_count, struct regression_param *out, int max);

/* Whether c's recorded parameters are what its label means today. */
bool regression_params_current(const struct regression_cell *c);

void regression_free(struct regression *r);

#endif
