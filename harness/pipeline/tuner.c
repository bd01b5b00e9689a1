#include "tuner.h"
#include "base/log.h"
#include "base/util.h"
#include "score/frontier.h"
#include "score/tuned.h"
#include "techniques/params.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The search renders each cell once, timed, and scores that frame (a new
 * program is first rendered once untimed, so the JIT compile is not
 * timed); the cells a file reports (the frontiers' candidates, the
 * defaults, the tuned and oracle settings) are timed again with --frames
 * after --warmup. */
#define TUNE_SEARCH_FRAMES 1

double tune_space_size(const struct technique *t, unsigned long long held)
{
    double values = 1, v[TUNE_MAX_VALUES];
    for (const struct technique_param *p = t->params; p->name; p++)
        if (!(p - t->params < 64 && (held >> (p - t->params) & 1)))
            values += fmax(params_tune_values(p, v, TUNE_MAX_VALUES) - 1, 0);
    return values;
}

double tuner_size(const struct tuner *tn)
{
    return tune_space_size(tn->t, tn->held) * tn->scene_count;
}

static void *settings_of(const struct tuner *tn, const int *point)
{
    void *s = memcpy(xmalloc(tn->t->settings_size), tn->base, tn->t->settings_size);
    for (int d = 0; d < tn->dim_count; d++)
        params_put(tn->dims[d].p, s, tn->dims[d].values[point[d]]);
    return s;
}

/* The cell of these settings for scene k's light; a new program is
 * rendered once on scene k, untimed, before any frame of it is timed.
 * .programs.receiver 0 on failure. */
static struct stage_timer_cell cell_for(struct tuner *tn, const void *settings, int k)
{
    struct scene_setup *ss = &tn->setups[k];
    const int known = ss->programs->count;
    struct stage_timer_cell cell = scene_setup_timer_cell(ss, tn->t, settings);
    if (cell.programs.receiver && ss->programs->count > known && stage_timer_render(&ss->timer, &cell, false) != 0)
        cell.programs.receiver = 0;
    return cell;
}

static void show_progress(const struct tune_progress *p, const char *technique)
{
    const double elapsed = (util_now_ms() - p->start_ms) * 1e-3;
    const double expected = (double)p->cells_finished + p->per_size * p->size_left;
    const double left = (expected - (double)p->cells) * elapsed / (double)p->cells;
    if (left > 0 && left < 90)
        log_progress("  tune %s: %ld cells in %.0f s; ETA about %.0f s", technique, p->cells, elapsed, ceil(left));
    else if (left > 0)
        log_progress("  tune %s: %ld cells in %.0f s; ETA about %.0f min", technique, p->cells, elapsed,
                     round(left / 60));
    else  /* this search runs longer than the guess of its size: no honest ETA */
        log_progress("  tune %s: %ld cells in %.0f s; past the estimate of %.0f cells, no ETA", technique,
                     p->cells, elapsed, expected);
}

/* Times point on scene k (frames after warmup) into out's times, and
 * scores the last frame into *m when m is not NULL. Returns 0 or -1. */
static int measure(struct tuner *tn, const int *point, int k, int warmup, int frames, struct metrics *m,
                   struct tune_sample *out)
{
    void *s = settings_of(tn, point);
    struct scene_setup *ss = &tn->setups[k];
    const struct stage_timer_cell cell = cell_for(tn, s, k);
    struct stage_times times;
    const struct scene_setup_timing how = {.warmup = warmup, .frames = frames, .timing = tn->o->timing};
    int rc = !scene_setup_cell_ready(&cell) || scene_setup_time(ss, &how, &cell, 1, &times) != 0;
    if (rc) {
        free(s);
        return -1;
    }
    /* the search scores the timed frame, or with --cost fetches a counting frame (the same picture) */
    if (m && tn->o->cost_fetches) {
        if (scene_setup_cell(ss, tn->t, cell.settings, m) != 0)
            return -1;
        out->fetches = m->fetches_per_pixel;
    } else if (m) {
        scene_setup_score(ss, tn->t, m);
        out->fetches = NAN;
    }
    out->ms = times.total_ms, out->ms_q1 = times.total_q1_ms, out->ms_q3 = times.total_q3_ms;
    free(s);
    out->retimed = !m;  /* only the search scores what it times */
    tn->progress->cells++;
    show_progress(tn->progress, tn->t->name);
    return 0;
}

/* The search's evaluation: point on scene k, scored, then timed. */
static int evaluate(void *user, const int *point, int k, struct tune_sample *out)
{
    struct tuner *tn = user;
    void *s = settings_of(tn, point);
    char why[256];
    const bool refused = tn->t->check && tn->t->check(s, why, sizeof why) != 0;
    free(s);
    if (refused) {  /* a combination the technique refuses */
        *out = (struct tune_sample){INFINITY, NAN, NAN, NAN, NAN, false};
        return 0;
    }
    struct metrics m = {0};
    if (measure(tn, point, k, 0, TUNE_SEARCH_FRAMES, &m, out) != 0)
        return -1;
    const double e = metrics_value(&m, tn->o->objective);
    out->objective = isfinite(e) && m.nonfinite == 0 ? e : INFINITY;
    return 0;
}

/* ---- the file ---- */

static cJSON *point_json(struct tune_sample mean)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "error", mean.objective);
    cJSON_AddNumberToObject(o, "ms", mean.ms);
    cJSON_AddNumberToObject(o, "ms_q1", mean.ms_q1);
    cJSON_AddNumberToObject(o, "ms_q3", mean.ms_q3);
    if (isfinite(mean.fetches))
        cJSON_AddNumberToObject(o, "fetches", mean.fetches);
    return o;
}

/* Sums of samples, for means over scenes. */
static void sample_add(struct tune_sample *sum, const struct tune_sample *s)
{
    sum->objective += s->objective, sum->ms += s->ms, sum->ms_q1 += s->ms_q1, sum->ms_q3 += s->ms_q3;
    sum->fetches += s->fetches;
}

static struct tune_sample sample_scaled(struct tune_sample s, double f)
{
    return (struct tune_sample){s.objective * f, s.ms * f, s.ms_q1 * f, s.ms_q3 * f, s.fetches * f, s.retimed};
}

/* Mean of entry e's samples over every scene (each evaluated: callers check). */
static struct tune_sample entry_mean(const struct tuner *tn, const struct tune_entry *e)
{
    struct tune_sample sum = {0};
    for (int k = 0; k < tn->scene_count; k++)
        sample_add(&sum, &e->s[k]);
    return sample_scaled(sum, 1.0 / tn->scene_count);
}

static cJSON *settings_json(const struct tuner *tn, const int *point)
{
    void *s = settings_of(tn, point);
    cJSON *j = params_json(tn->t, s);
    free(s);
    return j;
}

/* The Pareto front of error against cost (time, or fetches) over the entries evaluated on
 * scene k (k < 0: the means over every scene), only the cells timed again
 * when retimed: into front[] (memo indices, by time) and their samples into
 * means[] (may be NULL); returns the count. */
static int pareto_entries(const struct tuner *tn, int k, bool retimed, int *front, struct tune_sample *means)
{
    const int n = tn->memo.count;
    double *x = xcalloc((size_t)n + 1, sizeof *x), *y = xcalloc((size_t)n + 1, sizeof *y);
    int *on = xcalloc((size_t)n + 1, sizeof *on), *src = xcalloc((size_t)n + 1, sizeof *src), m = 0;
    struct tune_sample *all = xcalloc((size_t)n + 1, sizeof *all);
    for (int i = 0; i < n; i++) {
        const struct tune_entry *e = &tn->memo.entries[i];
        bool usable = true;  /* evaluated (and timed again, when asked) on every scene that counts */
        for (int j = 0; j < tn->scene_count; j++)
            if (k < 0 || j == k)
                usable &= e->done[j] && (!retimed || e->s[j].retimed);
        const struct tune_sample s = k < 0 ? entry_mean(tn, e) : e->s[k];
        if (usable && isfinite(s.objective)) {
            all[m] = s, src[m] = i, x[m] = tn->o->cost_fetches ? s.fetches : s.ms, y[m] = s.objective;
            m++;
        }
    }
    const int f = frontier_pareto(x, y, m, on);
    for (int j = 0; j < f; j++) {
        front[j] = src[on[j]];
        if (means)
            means[j] = all[on[j]];
    }
    free(x), free(y), free(on), free(src), free(all);
    return f;
}

/* The frontier of scene k (k < 0: over every scene), as points with their
 * settings' text, from the cells timed again. */
static cJSON *frontier_json(const struct tuner *tn, int k)
{
    const int n = tn->memo.count;
    int *front = xcalloc((size_t)n + 1, sizeof *front);
    struct tune_sample *means = xcalloc((size_t)n + 1, sizeof *means);
    const int f = pareto_entries(tn, k, true, front, means);
    cJSON *a = cJSON_CreateArray();
    for (int j = 0; j < f; j++) {
        cJSON *p = point_json(means[j]);
        void *s = settings_of(tn, tn->memo.entries[front[j]].point);
        struct strbuf text = {0};
        params_summary(tn->t, s, &text);
        cJSON_AddStringToObject(p, "settings", text.data ? text.data : "");
        strbuf_free(&text);
        free(s);
        cJSON_AddItemToArray(a, p);
    }
    free(front), free(means);
    return a;
}

static struct tune_sample sample_at(const struct tuner *tn, const int *point, int k)
{
    return tune_find(&tn->memo, point)->s[k];
}

static cJSON *technique_json(const struct tuner *tn, const int *start, const int *all, const bool *have_kind,
                             int (*by_kind)[TUNE_MAX_DIMS], int (*fold)[TUNE_MAX_DIMS],
                             int (*oracle)[TUNE_MAX_DIMS], double seconds)
{
    const struct tune_options *o = tn->o;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "technique", tn->t->name);
    if (technique_is_engine(tn->t)) {  /* its times are its browser's device's, not gl_renderer's */
        const struct engine_result *e = &tn->setups[0].engine;
        cJSON *engine = cJSON_AddObjectToObject(j, "engine");
        cJSON_AddStringToObject(engine, "name", tn->t->engine);
        cJSON_AddStringToObject(engine, "package", tn->t->engine_package);
        cJSON_AddStringToObject(engine, "version", e->version);
        cJSON_AddStringToObject(engine, "renderer", e->renderer);
    }
    if (technique_is_preset(tn->t)) {  /* the engine filter it re-implements (docs/presets.md) */
        cJSON *preset = cJSON_AddObjectToObject(j, "preset");
        cJSON_AddStringToObject(preset, "of", tn->t->preset_of);
        cJSON_AddStringToObject(preset, "source", tn->t->preset_source);
    }
    cJSON_AddStringToObject(j, "objective", metric_info[o->objective].key);
    cJSON_AddStringToObject(j, "cost", o->cost_fetches ? "fetches" : "ms");
    cJSON_AddStringToObject(j, "search", TUNE_SEARCH_TEXT);
    cJSON *space = cJSON_AddObjectToObject(j, "space");
    for (int d = 0; d < tn->dim_count; d++) {
        cJSON *values = cJSON_AddArrayToObject(space, tn->dims[d].p->name);
        void *s = params_defaults(tn->t);
        for (int v = 0; v < tn->dims[d].count; v++) {
            params_put(tn->dims[d].p, s, tn->dims[d].values[v]);
            cJSON *one = params_json(tn->t, s);
            cJSON_AddItemToArray(values, cJSON_Duplicate(cJSON_GetObjectItem(one, tn->dims[d].p->name), true));
            cJSON_Delete(one);
        }
        free(s);
    }
    cJSON *base = params_json(tn->t, tn->base), *held = cJSON_AddObjectToObject(j, "held");
    for (const struct technique_param *p = tn->t->params; p->name; p++)
        if (p - tn->t->params < 64 && (tn->held >> (p - tn->t->params) & 1))
            cJSON_AddItemToObject(held, p->name, cJSON_Duplicate(cJSON_GetObjectItem(base, p->name), true));
    cJSON_Delete(base);
    cJSON *scenes = cJSON_AddArrayToObject(j, "scenes");
    for (int k = 0; k < tn->scene_count; k++)
        cJSON_AddItemToArray(scenes, cJSON_CreateString(tn->scenes[k].name));
    cJSON_AddNumberToObject(j, "width", o->width);
    cJSON_AddNumberToObject(j, "height", o->height);
    cJSON_AddNumberToObject(j, "gt_samples", o->gt_samples);
    cJSON_AddNumberToObject(j, "shadow_map_size", o->shadow_map_size);
    cJSON_AddNumberToObject(j, "frames", o->frames);
    cJSON_AddItemToObject(j, "settings", settings_json(tn, all));
    cJSON *by_light = NULL;
    for (int k = 0; k < 2; k++)
        if (have_kind[k]) {
            if (!by_light)
                by_light = cJSON_AddObjectToObject(j, "settings_by_light");
            cJSON_AddItemToObject(by_light, tuned_kind_names[k], settings_json(tn, by_kind[k]));
        }

    struct tune_sample sums[4] = {{0}};  /* default, tuned (held out), oracle, fitted on every scene */
    cJSON *folds = cJSON_AddArrayToObject(j, "folds");
    for (int k = 0; k < tn->scene_count; k++) {
        const struct tune_sample s[4] = {sample_at(tn, start, k), sample_at(tn, fold[k], k),
                                         sample_at(tn, oracle[k], k), sample_at(tn, all, k)};
        for (int i = 0; i < 4; i++)
            sample_add(&sums[i], &s[i]);
        cJSON *f = cJSON_CreateObject();
        cJSON_AddStringToObject(f, "scene", tn->scenes[k].name);
        cJSON_AddItemToObject(f, "settings", settings_json(tn, fold[k]));
        cJSON_AddItemToObject(f, "held_out", point_json(s[1]));
        cJSON_AddItemToObject(f, "default", point_json(s[0]));
        cJSON *or = point_json(s[2]);
        cJSON_AddItemToObject(or, "settings", settings_json(tn, oracle[k]));
        cJSON_AddItemToObject(f, "oracle", or);
        cJSON_AddItemToArray(folds, f);
    }
    cJSON *summary = cJSON_AddObjectToObject(j, "summary");
    static const char *const names[] = {"default", "tuned", "oracle", "fitted"};
    for (int i = 0; i < 4; i++)
        cJSON_AddItemToObject(summary, names[i], point_json(sample_scaled(sums[i], 1.0 / tn->scene_count)));
    cJSON_AddStringToObject(summary, "note",
                            "means over the scenes. default: the defaults; tuned: each scene's setting chosen "
                            "on the other scenes, scored on it (what a user can expect); oracle: each "
                            "scene's best setting (fitted to it, not a prediction); fitted: the one "
                            "setting chosen on every scene, scored on them");
    cJSON *frontier = cJSON_AddObjectToObject(j, "frontier");
    cJSON_AddItemToObject(frontier, "all", frontier_json(tn, -1));
    cJSON *per = cJSON_AddObjectToObject(frontier, "scenes");
    for (int k = 0; k < tn->scene_count; k++)
        cJSON_AddItemToObject(per, tn->scenes[k].name, frontier_json(tn, k));
    cJSON_AddNumberToObject(j, "settings_tried", tn->memo.count);
    cJSON_AddNumberToObject(j, "cells_evaluated", (double)tn->memo.evaluations);
    cJSON_AddNumberToObject(j, "seconds", seconds);
    return j;
}

/* ---- one technique ---- */

int tuner_init(struct tuner *tn, const struct technique *t, const void *base, unsigned long long held,
               const struct tune_options *o, const struct scene *scenes, struct scene_setup *setups, int scene_count,
               struct tune_progress *progress)
{
    *tn = (struct tuner){.o = o, .t = t, .base = base, .held = held, .scenes = scenes, .setups = setups,
                         .scene_count = scene_count, .progress = progress};
    int *start = tn->start;
    for (const struct technique_param *p = t->params; p->name; p++) {
        struct tune_dim d = {.p = p};
        if ((p - t->params < 64 && (held >> (p - t->params) & 1)) ||
            !(d.count = params_tune_values(p, d.values, TUNE_MAX_VALUES)))
            continue;
        int at = -1;
        for (int v = 0; v < d.count; v++)
            if ((p->type == PARAM_FLOAT ? (double)(float)d.values[v] == (double)(float)p->def
                                        : d.values[v] == p->def))
                at = v;
        if (at < 0 || tn->dim_count == TUNE_MAX_DIMS) {  /* a table error: test_tune guards it */
            log_error("%s.%s: %s", t->name, p->name,
                      at < 0 ? "its tune values lack its default" : "too many tuned parameters");
            return -1;
        }
        start[tn->dim_count] = at;
        tn->dims[tn->dim_count++] = d;
    }
    tn->memo = (struct tune_memo){.dims = tn->dim_count, .scenes = tn->scene_count, .eval = evaluate, .user = tn};
    for (int d = 0; d < tn->dim_count; d++)
        tn->memo.counts[d] = tn->dims[d].count;
    return 0;
}

void tuner_free(struct tuner *tn)
{
    tune_memo_free(&tn->memo);
}

/* Times again, with --frames after --warmup, the cells the files report:
 * the defaults, the setting chosen on every scene, each fold's and each
 * oracle's on its scene, and the frontiers' candidates (chosen by the
 * search's one-frame times: which cells those are can vary between
 * tunings, the choices above cannot). */
static int retime(struct tuner *tn, const int *start, const int *all, int (*fold)[TUNE_MAX_DIMS],
                  int (*oracle)[TUNE_MAX_DIMS])
{
    const int n = tn->memo.count, scenes = tn->scene_count;
    bool *mark = xcalloc((size_t)n * (size_t)scenes, sizeof *mark);
    int *front = xcalloc((size_t)n + 1, sizeof *front);
#define MARK(entry, k) mark[(size_t)((entry) - tn->memo.entries) * (size_t)scenes + (size_t)(k)] = true
    for (int k = 0; k < scenes; k++) {
        MARK(tune_find(&tn->memo, start), k);
        MARK(tune_find(&tn->memo, all), k);
        MARK(tune_find(&tn->memo, fold[k]), k);
        MARK(tune_find(&tn->memo, oracle[k]), k);
    }
    for (int k = -1; k < scenes; k++) {
        const int f = pareto_entries(tn, k, false, front, NULL);
        for (int j = 0; j < f; j++)
            for (int i = 0; i < scenes; i++)
                if (k < 0 || i == k)
                    mark[(size_t)front[j] * (size_t)scenes + (size_t)i] = true;
    }
#undef MARK
    int rc = 0;
    for (int e = 0; e < n && !rc; e++)
        for (int k = 0; k < scenes && !rc; k++)
            if (mark[(size_t)e * (size_t)scenes + (size_t)k])
                rc = measure(tn, tn->memo.entries[e].point, k, tn->o->warmup, tn->o->frames, NULL,
                             &tn->memo.entries[e].s[k]);
    free(mark), free(front);
    return rc;
}

enum tuner_result tuner_run(struct tuner *tn, cJSON **record)
{
    const double start_ms = util_now_ms();
    const int *start = tn->start;
    int all[TUNE_MAX_DIMS], by_kind[2][TUNE_MAX_DIMS], fold[TUNE_MAX_SCENES][TUNE_MAX_DIMS],
        oracle[TUNE_MAX_SCENES][TUNE_MAX_DIMS];
    double def, best, held_out[TUNE_MAX_SCENES];
    log_info("tune %s: %d parameters (%g settings in one round on %d scenes)", tn->t->name, tn->dim_count,
             tuner_size(tn) / tn->scene_count, tn->scene_count);
    /* The defaults first, scene by scene: a scene where the objective is
     * undefined (no penumbra band) cannot take part. */
    for (int k = 0; k < tn->scene_count; k++) {
        if (tune_mean(&tn->memo, start, &k, 1, &def) != 0)
            return TUNER_FAILED;
        if (!isfinite(def)) {
            log_error("%s: %s of %s at its defaults is undefined (no pixel to score it on): tune without "
                      "this scene", tn->scenes[k].path, metric_info[tn->o->objective].key, tn->t->name);
            return TUNER_UNDEFINED;
        }
    }
    int scenes[TUNE_MAX_SCENES], kind[TUNE_MAX_SCENES];
    for (int k = 0; k < tn->scene_count; k++)
        scenes[k] = k, kind[k] = tuned_kind(&tn->scenes[k]);
    if (tune_mean(&tn->memo, start, scenes, tn->scene_count, &def) != 0 ||
        tune_descend(&tn->memo, scenes, tn->scene_count, start, all, &best) != 0 ||
        tune_cross_validate(&tn->memo, start, kind, fold, held_out) != 0)
        return TUNER_FAILED;
    /* For a scene it did not see, each light kind's setting, chosen on its
     * scenes, when both kinds are here and the kind has two or more (a
     * scene's fold is chosen the same way: on its kind's other scenes). */
    bool have_kind[2] = {false, false};
    for (int g = 0; g < 2; g++) {
        int members[TUNE_MAX_SCENES], n = 0;
        for (int k = 0; k < tn->scene_count; k++)
            if (kind[k] == g)
                members[n++] = k;
        double fitted;
        have_kind[g] = n >= 2 && n < tn->scene_count;
        if (have_kind[g] && tune_descend(&tn->memo, members, n, start, by_kind[g], &fitted) != 0)
            return TUNER_FAILED;
    }
    /* The oracle: on each scene, the best of every setting tried there. */
    double cv = 0, or = 0;
    for (int k = 0; k < tn->scene_count; k++) {
        double oracle_score = INFINITY;
        for (int i = 0; i < tn->memo.count; i++) {
            const struct tune_entry *e = &tn->memo.entries[i];
            if (e->done[k] && e->s[k].objective < oracle_score) {
                oracle_score = e->s[k].objective;
                memcpy(oracle[k], e->point, sizeof oracle[k]);
            }
        }
        cv += held_out[k] / tn->scene_count, or += oracle_score / tn->scene_count;
    }
    for (int k = 0; k < tn->scene_count; k++)
        if (!isfinite(held_out[k])) {  /* a file cannot hold it, and no run should use it */
            log_error("tune %s: the setting chosen without %s gives NaN, Inf or no %s on it: nothing written",
                      tn->t->name, tn->scenes[k].name, metric_info[tn->o->objective].key);
            return TUNER_FAILED;
        }
    if (retime(tn, start, all, fold, oracle) != 0)
        return TUNER_FAILED;
    log_progress_done();
    const double seconds = (util_now_ms() - start_ms) * 1e-3;
    log_info("tune %s: mean %s: defaults %.4f, tuned (each scene's setting chosen on the others) %.4f, "
             "oracle %.4f; %d settings, %ld cells, %.0f s", tn->t->name, metric_info[tn->o->objective].key, def,
             cv, or, tn->memo.count, tn->memo.evaluations, seconds);
    /* Refine the ETA with what the techniques so far cost against their size. */
    struct tune_progress *p = tn->progress;
    p->size_left -= tuner_size(tn), p->size_finished += tuner_size(tn);
    p->cells_finished = p->cells;
    p->per_size = (double)p->cells / p->size_finished;

    *record = technique_json(tn, start, all, have_kind, by_kind, fold, oracle, seconds);
    return TUNER_DONE;
}

