/* The report's frontier charts (docs/tuning.md): each tuned technique's
 * Pareto front of error against time over its own settings, as its tuning
 * measured it (score/tuned.h), over every scene and per scene. One chart
 * holds one tuning: files tuned at another size, map, objective or set of
 * scenes than the first are left out of it (said once). */
#ifndef SB_FRONTIERS_H
#define SB_FRONTIERS_H

#include "chart.h"
#include "pipeline/configs.h"
#include "scene/scene.h"

struct frontiers {
    struct chart_curve *all, **scene;  /* curves over every scene; per scene */
    int all_count, *scene_count;
    double **arrays;
    int array_count;
    char *source, *objective;          /* where and how they were measured; the error minimised */
    bool cost_fetches;                 /* their cost axis: fetches per pixel, else ms per frame */
};

/* The curves of the tuned configurations among configs[0..n-1] on the
 * scenes; tuned_dir names the files in the chart's source line. */
void frontiers_build(struct frontiers *f, const struct run_config *configs, int n, const struct scene *scenes,
                     int scene_count, const char *tuned_dir);

void frontiers_free(struct frontiers *f, int scene_count);

#endif
