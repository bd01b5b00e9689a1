/* The search behind `shadowbench tune` (docs/tuning.md), apart from GL so
 * that it can be tested on a synthetic objective. A point is one value
 * index per tuned parameter; a cell is a point on one scene, evaluated at
 * most once (the memo) and shared by every search that asks for it.
 *
 * A search is coordinate descent on the mean objective over a set of
 * scenes: from a start point, each parameter in turn is tried at every one
 * of its values with the others held, and the best strictly better point is
 * taken; rounds repeat until one changes nothing. There is no randomness:
 * the same objective gives the same points, in the same order. */
#ifndef SB_TUNE_SEARCH_H
#define SB_TUNE_SEARCH_H

#include <stdbool.h>

#define TUNE_MAX_DIMS 12
#define TUNE_MAX_SCENES 64
#define TUNE_MAX_ROUNDS 4

/* What one cell measured. objective: lower is better; +inf where the
 * point cannot be rendered (a combination the technique refuses). */
struct tune_sample {
    double objective;
    double ms, ms_q1, ms_q3;  /* time per frame: median and quartiles */
    double fetches;           /* fetches_per_pixel, counted (tune --cost fetches); NAN: not counted */
    bool retimed;             /* timed again for the files (pipeline/tuner.c), not by the search */
};

/* Evaluates point on scene into *s. Returns 0, or -1 to stop the search (an
 * error, logged). */
typedef int (*tune_eval_fn)(void *user, const int *point, int scene, struct tune_sample *s);

struct tune_entry {
    int point[TUNE_MAX_DIMS];
    bool done[TUNE_MAX_SCENES];
    struct tune_sample s[TUNE_MAX_SCENES];
};

struct tune_memo {
    int dims, counts[TUNE_MAX_DIMS];  /* values per parameter */
    int scenes;
    tune_eval_fn eval;
    void *user;
    struct tune_entry *entries;       /* in the order they were first asked for */
    int count, capacity;
    long evaluations;                 /* cells evaluated (calls of eval) */
};

/* Mean objective of point over scenes[0..n-1], n >= 1, into *mean
 * (evaluating the cells not yet in the memo). Returns 0 or -1. */
int tune_mean(struct tune_memo *m, const int *point, const int *scenes, int n, double *mean);

/* Coordinate descent over scenes[0..n-1] from start; the best point into
 * best and its mean objective into *score. Returns 0 or -1. */
int tune_descend(struct tune_memo *m, const int *scenes, int n, const int *start, int *best, double *score);

/* Leave-one-scene-out: for each k in 0..m->scenes-1, fold[k] is the point
 * tune_descend chooses on every other scene of k's group (group[i] == group[k];
 * every other scene when group is NULL or k is alone in its group), and
 * held_out[k] its objective on k (evaluated after the search). Returns 0 or
 * -1. */
int tune_cross_validate(struct tune_memo *m, const int *start, const int *group, int (*fold)[TUNE_MAX_DIMS],
                        double *held_out);

/* The memo's entry for point, or NULL. */
const struct tune_entry *tune_find(const struct tune_memo *m, const int *point);

void tune_memo_free(struct tune_memo *m);

#endif
