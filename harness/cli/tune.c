#include "tune.h"
#include "tuned.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "output/chart.h"
#include "output/report.h"
#include "score/tune_search.h"
#include "techniques/params.h"

#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define TUNE_MAX_VALUES 32
/* The search renders each cell once, timed, and scores that frame (a new
 * program is first rendered once untimed, so the JIT compile is not
 * timed); the cells a file reports (the frontiers' candidates, the
 * defaults, the tuned and oracle settings) are timed again with --frames
 * after --warmup. */
#define TUNE_SEARCH_FRAMES 1

struct tune_dim {
    const struct technique_param *p;
    double values[TUNE_MAX_VALUES];
    int count;
};

/* Progress over the whole command, for the ETA. */
struct tune_progress {
    double start_ms, last_line_ms;
    long cells;          /* evaluated so far, every technique */
    long cells_finished; /* by the techniques finished */
    double size_left;    /* technique_size of the others */
    double per_size;     /* cells per unit of technique_size: a guess, then measured */
    double size_finished;
};

struct tuner {
    const struct run_options *o;
    const struct technique *t;
    struct tune_dim dims[TUNE_MAX_DIMS];
    int dim_count;
    int start[TUNE_MAX_DIMS];  /* the defaults, as value indices */
    const struct scene *scenes;
    struct scene_setup *setups;
    int scene_count;
    struct run_programs programs;
    struct tune_memo memo;
    struct tune_progress *progress;
};

/* Starting guess of the cells per unit of size: coordinate descent runs
 * two or three rounds, and the folds add some more (measured: 2.5-4 on the
 * shipped scenes). */
#define TUNE_PER_SIZE_GUESS 3.5

/* The cells one search round costs: one point per value of each parameter,
 * on every scene. */
static double technique_size(const struct tuner *tn)
{
    double values = 1;
    for (int d = 0; d < tn->dim_count; d++)
        values += tn->dims[d].count - 1;
    return values * tn->scene_count;
}

static void *settings_of(const struct tuner *tn, const int *point)
{
    void *s = params_defaults(tn->t);
    for (int d = 0; d < tn->dim_count; d++)
        params_put(tn->dims[d].p, s, tn->dims[d].values[point[d]]);
    return s;
}

/* The program of these settings for scene k's light; a new one is
 * rendered once on scene k, untimed, before any frame of it is timed. 0 on
 * failure. */
static GLuint program_for(struct tuner *tn, const void *settings, int k)
{
    const int known = tn->programs.count;
    const GLuint program = run_program_get(&tn->programs, tn->t, settings, tn->scenes[k].light.shape);
    if (program && tn->programs.count > known &&
        stage_timer_render(&tn->setups[k].timer, &(struct stage_timer_cell){tn->t, settings, program}) != 0)
        return 0;
    return program;
}

static void show_progress(struct tune_progress *p, const char *technique)
{
    const double now = util_now_ms(), elapsed = (now - p->start_ms) * 1e-3;
    const bool tty = isatty(STDERR_FILENO);
    if (log_get_level() < LOG_INFO || (!tty && now - p->last_line_ms < 30e3))
        return;
    p->last_line_ms = now;
    const double expected = (double)p->cells_finished + p->per_size * p->size_left;
    const double left = (expected - (double)p->cells) * elapsed / (double)p->cells;
    char line[160];
    if (left > 0 && left < 90)
        snprintf(line, sizeof line, "  tune %s: %ld cells in %.0f s; ETA about %.0f s", technique, p->cells,
                 elapsed, ceil(left));
    else if (left > 0)
        snprintf(line, sizeof line, "  tune %s: %ld cells in %.0f s; ETA about %.0f min", technique, p->cells,
                 elapsed, round(left / 60));
    else  /* this search runs longer than the guess of its size: no honest ETA */
        snprintf(line, sizeof line, "  tune %s: %ld cells in %.0f s; past the estimate of %.0f cells, no ETA",
                 technique, p->cells, elapsed, expected);
    if (tty)
        fprintf(stderr, "\r%-78s", line);
    else
        log_info("%s", line + 2);
}

/* Times point on scene k (frames after warmup) into out's times, and
 * scores the last frame into *m when m is not NULL. Returns 0 or -1. */
static int measure(struct tuner *tn, const int *point, int k, int warmup, int frames, struct metrics *m,
                   struct tune_sample *out)
{
    void *s = settings_of(tn, point);
    struct scene_setup *ss = &tn->setups[k];
    const struct stage_timer_cell cell = {tn->t, s, program_for(tn, s, k)};
    struct stage_timer timer = ss->timer;
    timer.warmup = warmup, timer.frames = frames, timer.timing = tn->o->timing;
    struct stage_times times;
    int rc = !cell.program || stage_timer_run(&timer, &cell, 1, &times) != 0;
    free(s);
    if (rc)
        return -1;
    if (m)
        scene_setup_score(ss, m);
    out->ms = times.total_ms, out->ms_q1 = times.total_q1_ms, out->ms_q3 = times.total_q3_ms;
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
        *out = (struct tune_sample){INFINITY, NAN, NAN, NAN, false};
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
    return o;
}

/* Sums of samples, for means over scenes. */
static void sample_add(struct tune_sample *sum, const struct tune_sample *s)
{
    sum->objective += s->objective, sum->ms += s->ms, sum->ms_q1 += s->ms_q1, sum->ms_q3 += s->ms_q3;
}

static struct tune_sample sample_scaled(struct tune_sample s, double f)
{
    return (struct tune_sample){s.objective * f, s.ms * f, s.ms_q1 * f, s.ms_q3 * f, s.retimed};
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

/* The Pareto front of error against time over the entries evaluated on
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
            all[m] = s, src[m] = i, x[m] = s.ms, y[m] = s.objective;
            m++;
        }
    }
    const int f = chart_pareto(x, y, m, on);
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

static cJSON *technique_json(const struct tuner *tn, const int *start, const int *all, int (*fold)[TUNE_MAX_DIMS],
                             int (*oracle)[TUNE_MAX_DIMS], double seconds)
{
    const struct run_options *o = tn->o;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "technique", tn->t->name);
    cJSON_AddStringToObject(j, "objective", metric_info[o->objective].key);
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
    cJSON *scenes = cJSON_AddArrayToObject(j, "scenes");
    for (int k = 0; k < tn->scene_count; k++)
        cJSON_AddItemToArray(scenes, cJSON_CreateString(tn->scenes[k].name));
    cJSON_AddNumberToObject(j, "width", o->width);
    cJSON_AddNumberToObject(j, "height", o->height);
    cJSON_AddNumberToObject(j, "gt_samples", o->gt_samples);
    cJSON_AddNumberToObject(j, "shadow_map_size", o->shadow_map_size);
    cJSON_AddNumberToObject(j, "frames", o->frames);
    cJSON_AddItemToObject(j, "settings", settings_json(tn, all));

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
    char *cmd = run_command_line(o);
    cJSON_AddStringToObject(j, "command", cmd);
    free(cmd);
    char *date = run_utc_date(), *git = run_git_describe();
    cJSON_AddStringToObject(j, "date", date);
    cJSON_AddStringToObject(j, "git_describe", git);
    cJSON_AddStringToObject(j, "gl_renderer", gl_context_renderer());
    cJSON_AddStringToObject(j, "gl_vendor", gl_context_vendor());
    cJSON_AddStringToObject(j, "timing_method", stage_timing_text(tn->o->timing));
    free(date), free(git);
    return j;
}

/* ---- one technique ---- */

/* The tuned parameters of tn's technique, their values and the defaults'
 * indices (tn->start), and an empty memo. */
static int build_space(struct tuner *tn)
{
    int *start = tn->start;
    tn->dim_count = 0;
    for (const struct technique_param *p = tn->t->params; p->name; p++) {
        struct tune_dim d = {.p = p};
        if (!(d.count = params_tune_values(p, d.values, TUNE_MAX_VALUES)))
            continue;
        int at = -1;
        for (int v = 0; v < d.count; v++)
            if ((p->type == PARAM_FLOAT ? (double)(float)d.values[v] == (double)(float)p->def
                                        : d.values[v] == p->def))
                at = v;
        if (at < 0 || tn->dim_count == TUNE_MAX_DIMS) {  /* a table error: test_tune guards it */
            log_error("%s.%s: %s", tn->t->name, p->name,
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

static int write_file(const char *dir, const char *name, const cJSON *j)
{
    char *path = util_printf("%s/%s.json", dir, name);
    int rc = report_write_json(path, j);
    free(path);
    return rc;
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

static int tune_technique(struct tuner *tn)
{
    const double start_ms = util_now_ms();
    const int *start = tn->start;
    int all[TUNE_MAX_DIMS], fold[TUNE_MAX_SCENES][TUNE_MAX_DIMS], oracle[TUNE_MAX_SCENES][TUNE_MAX_DIMS];
    double def, best, held_out[TUNE_MAX_SCENES];
    log_info("tune %s: %d parameters (%g settings in one round on %d scenes)", tn->t->name, tn->dim_count,
             technique_size(tn) / tn->scene_count, tn->scene_count);
    /* The defaults first, scene by scene: a scene where the objective is
     * undefined (no penumbra band) cannot take part. */
    for (int k = 0; k < tn->scene_count; k++) {
        if (tune_mean(&tn->memo, start, &k, 1, &def) != 0)
            return EXIT_CHECK_FAILED;
        if (!isfinite(def)) {
            log_error("%s: %s of %s at its defaults is undefined (no pixel to score it on): tune without "
                      "this scene", tn->scenes[k].path, metric_info[tn->o->objective].key, tn->t->name);
            return EXIT_USAGE;
        }
    }
    int scenes[TUNE_MAX_SCENES];
    for (int k = 0; k < tn->scene_count; k++)
        scenes[k] = k;
    if (tune_mean(&tn->memo, start, scenes, tn->scene_count, &def) != 0 ||
        tune_descend(&tn->memo, scenes, tn->scene_count, start, all, &best) != 0 ||
        tune_cross_validate(&tn->memo, start, fold, held_out) != 0)
        return EXIT_CHECK_FAILED;
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
            return EXIT_CHECK_FAILED;
        }
    if (retime(tn, start, all, fold, oracle) != 0)
        return EXIT_CHECK_FAILED;
    if (isatty(STDERR_FILENO) && log_get_level() >= LOG_INFO)
        fputc('\n', stderr);
    const double seconds = (util_now_ms() - start_ms) * 1e-3;
    log_info("tune %s: mean %s: defaults %.4f, tuned (each scene's setting chosen on the others) %.4f, "
             "oracle %.4f; %d settings, %ld cells, %.0f s", tn->t->name, metric_info[tn->o->objective].key, def,
             cv, or, tn->memo.count, tn->memo.evaluations, seconds);
    /* Refine the ETA with what the techniques so far cost against their size. */
    struct tune_progress *p = tn->progress;
    p->size_left -= technique_size(tn), p->size_finished += technique_size(tn);
    p->cells_finished = p->cells;
    p->per_size = (double)p->cells / p->size_finished;

    cJSON *j = technique_json(tn, start, all, fold, oracle, seconds);
    int rc = write_file(tn->o->out_dir, tn->t->name, j);
    if (!rc && tn->o->write_tuned)
        rc = write_file(tn->o->tuned_dir, tn->t->name, j);
    cJSON_Delete(j);
    return rc ? EXIT_CHECK_FAILED : EXIT_OK;
}

/* ---- the command ---- */

/* --write-tuned writes into a folder of tuned settings: one holding
 * anything else (someone's own files) is refused. */
static int tuned_dir_ours(const char *dir)
{
    DIR *d = opendir(dir);
    const char *stranger = NULL;
    for (struct dirent *e; d && !stranger && (e = readdir(d));) {
        const char *n = e->d_name, *dot = strrchr(n, '.');
        bool ours = !strcmp(n, ".") || !strcmp(n, "..") || !strcmp(n, ".lock") || strstr(n, UTIL_TEMP_SUFFIX);
        for (int i = 0; technique_list[i] && !ours && dot && !strcmp(dot, ".json"); i++)
            ours = strlen(technique_list[i]->name) == (size_t)(dot - n) &&
                   !strncmp(n, technique_list[i]->name, (size_t)(dot - n));
        if (!ours)
            stranger = n;
    }
    if (stranger)
        log_error("--tuned %s: holds %s, which tune does not write: name a folder of tuned settings", dir,
                  stranger);
    if (d)
        closedir(d);
    return stranger ? -1 : 0;
}

static int begin_tune(const struct run_options *o, bool complete, double seconds)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddBoolToObject(j, "complete", complete);
    cJSON_AddNumberToObject(j, "seconds", seconds);
    cJSON *t = cJSON_AddArrayToObject(j, "techniques");
    for (int i = 0; i < o->technique_count; i++)
        cJSON_AddItemToArray(t, cJSON_CreateString(o->techniques[i]->name));
    int rc = write_file(o->out_dir, "tune", j);
    cJSON_Delete(j);
    return rc;
}

int tune_main(const struct run_options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[RUN_MAX_SCENES];
    static struct scene_setup setups[RUN_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE, opened = 0;
    if (run_load_scenes(o, scenes, &scene_count) != 0)
        goto out;
    if (scene_count < 2 || scene_count > TUNE_MAX_SCENES) {
        log_error("tune: needs 2 to %d scenes (each scene's setting is chosen on the others), got %d",
                  TUNE_MAX_SCENES, scene_count);
        goto out;
    }
    if ((o->write_tuned && tuned_dir_ours(o->tuned_dir) != 0) || run_claim_out_dir(o->out_dir) != 0 ||
        (o->write_tuned && run_claim_results_dir(o->tuned_dir, 1) != 0) ||
        begin_tune(o, false, 0) != 0 || shader_init(o->shader_dir) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    if (gl_context_create(o->gl) != 0) {  /* no such context here: bad usage (exit 2), as a bad --shaders */
        status = EXIT_USAGE;
        goto out;
    }
    log_info("tune: %d technique(s) on %d scenes, %dx%d, %d GT samples, %d^2 shadow map, objective mean %s, "
             "median of %d frames per cell, on %s", o->technique_count, scene_count, o->width, o->height,
             o->gt_samples, o->shadow_map_size, metric_info[o->objective].key, o->frames, gl_context_renderer());
    for (; opened < scene_count; opened++)
        if (scene_setup_open(&setups[opened], &scenes[opened],
                             &(struct scene_setup_desc){o->width, o->height, o->shadow_map_size, o->gt_samples, 0,
                                                        o->cache_dir, 0}) != 0) {
            opened++;  /* scene_setup_open leaves it to be freed */
            goto out_gl;
        }
    struct tune_progress progress = {.start_ms = util_now_ms(), .last_line_ms = util_now_ms(),
                                     .per_size = TUNE_PER_SIZE_GUESS};
    struct tuner tuners[RUN_MAX_TECHNIQUES];
    for (int i = 0; i < o->technique_count; i++) {
        tuners[i] = (struct tuner){.o = o, .t = o->techniques[i], .scenes = scenes, .setups = setups,
                                   .scene_count = scene_count, .progress = &progress};
        if (build_space(&tuners[i]) != 0) {
            status = EXIT_USAGE;
            goto out_gl;
        }
        progress.size_left += technique_size(&tuners[i]);
    }
    status = EXIT_OK;
    for (int i = 0; i < o->technique_count && status == EXIT_OK; i++) {
        status = tune_technique(&tuners[i]);
        run_programs_free(&tuners[i].programs);
        tune_memo_free(&tuners[i].memo);
    }
    if (status == EXIT_OK) {
        const double seconds = (util_now_ms() - start) * 1e-3;
        status = begin_tune(o, true, seconds) ? EXIT_CHECK_FAILED : EXIT_OK;
        printf("tuned: %s/<technique>.json%s%s\n", o->out_dir, o->write_tuned ? " and " : "",
               o->write_tuned ? o->tuned_dir : "");
        log_info("tune finished in %.0f s", seconds);
    }
out_gl:
    for (int s = 0; s < opened; s++)
        scene_setup_free(&setups[s]);
    gl_context_destroy();
out:
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
