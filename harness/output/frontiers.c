#include "frontiers.h"
#include "base/log.h"
#include "base/util.h"
#include "score/tuned.h"

#include <stdlib.h>
#include <string.h>

/* t's frontier from tu over every scene (scene NULL) or one, appended to
 * curves[*n] (nothing when the file has none for it). */
static void add_curve(struct frontiers *f, const struct tuned *tu, const char *scene, struct chart_curve *curves,
                      int *n)
{
    struct tuned_point *p, def, tuned;
    const int count = tuned_frontier(tu, scene, &p, &def, &tuned);
    if (count) {
        double *a = xmalloc(sizeof(double) * 4 * (size_t)count);
        const bool by_fetches = tu->cost_fetches;  /* counted: no spread */
        for (int i = 0; i < count; i++)
            a[i] = by_fetches ? p[i].fetches : p[i].ms, a[count + i] = p[i].error,
            a[2 * count + i] = by_fetches ? p[i].fetches : p[i].ms_q1, a[3 * count + i] = by_fetches ? p[i].fetches : p[i].ms_q3;
        f->arrays = xrealloc(f->arrays, sizeof *f->arrays * (size_t)(f->array_count + 1));
        f->arrays[f->array_count++] = a;
        curves[(*n)++] = (struct chart_curve){{tu->t->name, tu->t->name, technique_index(tu->t)}, count, a, a + count, a + 2 * count,
                                              a + 3 * count, by_fetches ? def.fetches : def.ms, def.error,
                                              by_fetches ? tuned.fetches : tuned.ms, tuned.error};
    }
    free(p);
}

void frontiers_build(struct frontiers *f, const struct run_config *configs, int n, const struct scene *scenes,
                     int scene_count, const char *tuned_dir)
{
    memset(f, 0, sizeof *f);
    f->all = xcalloc((size_t)n + 1, sizeof *f->all);
    f->scene = xcalloc((size_t)scene_count + 1, sizeof *f->scene);
    f->scene_count = xcalloc((size_t)scene_count + 1, sizeof *f->scene_count);
    for (int s = 0; s < scene_count; s++)
        f->scene[s] = xcalloc((size_t)n + 1, sizeof *f->scene[s]);
    const struct tuned *first = NULL;  /* one chart, one tuning: its size, map, scenes and objective */
    for (int i = 0; i < n; i++) {
        const struct tuned *tu = configs[i].tuned;
        if (!tu)
            continue;
        if (first && (tu->width != first->width || tu->height != first->height ||
                      tu->shadow_map_size != first->shadow_map_size || strcmp(tu->objective, first->objective) ||
                      tu->cost_fetches != first->cost_fetches ||
                      !cJSON_Compare(cJSON_GetObjectItemCaseSensitive(tu->doc, "scenes"),
                                     cJSON_GetObjectItemCaseSensitive(first->doc, "scenes"), true))) {
            log_warn("%s: tuned at another size, map, objective, cost or set of scenes than %s: its cell runs, its "
                     "frontier is left out of the chart", tu->path, first->path);
            continue;
        }
        first = first ? first : tu;
        add_curve(f, tu, NULL, f->all, &f->all_count);
        for (int s = 0; s < scene_count; s++)
            add_curve(f, tu, scenes[s].name, f->scene[s], &f->scene_count[s]);
        if (!f->source) {
            f->source = util_printf("shadowbench tune at %dx%d, a %d^2 shadow map, on %s (%s, %s)", tu->width,
                                    tu->height, tu->shadow_map_size, tu->gl_renderer, tuned_dir, tu->date);
            f->objective = xstrdup(tu->objective);
            f->cost_fetches = tu->cost_fetches;
        }
    }
}

void frontiers_free(struct frontiers *f, int scene_count)
{
    for (int i = 0; i < f->array_count; i++)
        free(f->arrays[i]);
    free(f->arrays), free(f->all), free(f->source), free(f->objective);
    for (int s = 0; s < scene_count && f->scene; s++)
        free(f->scene[s]);
    free(f->scene), free(f->scene_count);
    memset(f, 0, sizeof *f);
}
