/* shadowbench run: per scene, the ground truth (cached), then every cell
 * rendered and scored and its pictures written, then the cells timed
 * interleaved and their metrics written; the report at the end (docs/design.md
 * §2, §8). */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "output/cell_output.h"
#include "output/frontiers.h"
#include "output/out_dir.h"
#include "output/provenance.h"
#include "output/report.h"
#include "pipeline/cell.h"
#include "pipeline/configs.h"
#include "techniques/params.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

cJSON *cli_run_record(const struct options *o, bool timed, double seconds)
{
    cJSON *r = provenance_json(o->argc, o->argv, timed, o->timing);
    cJSON_AddNumberToObject(r, "width", o->width);
    cJSON_AddNumberToObject(r, "height", o->height);
    cJSON_AddNumberToObject(r, "gt_samples", o->gt_samples);
    cJSON_AddNumberToObject(r, "shadow_map_size", o->shadow_map_size);
    cJSON_AddItemToObject(r, "cascades", cascade_settings_json(&o->cascades));
    cJSON_AddNumberToObject(r, "frames", o->frames);
    cJSON_AddNumberToObject(r, "warmup_frames", o->warmup);
    cJSON_AddNumberToObject(r, "seconds", seconds);
    return r;
}

/* The folder says what state it is in (docs/design.md §8): run.json with
 * "complete": false first, the previous run's report and matrix removed
 * (they would describe another run); report_write ends with run.json
 * "complete": true. A run that fails or is killed leaves false. */
static int begin_run(const struct options *o)
{
    static const enum output_file stale[] = {OUTPUT_REPORT, OUTPUT_MATRIX_CSV, OUTPUT_MATRIX_JSON, OUTPUT_DEPTH_CSV};
    for (size_t i = 0; i < ARRAY_SIZE(stale); i++) {
        char *path = out_dir_path(o->out_dir, stale[i]);
        unlink(path);
        free(path);
    }
    cJSON *run = cli_run_record(o, true, 0.0);
    cJSON_AddFalseToObject(run, "complete");
    char *path = out_dir_path(o->out_dir, OUTPUT_RUN_JSON);
    int rc = report_write_json(path, run);
    free(path);
    cJSON_Delete(run);
    return rc;
}

/* The run: its configurations, its cells so far, its progress. */
struct run {
    const struct options *o;
    struct config_set configs;
    struct program_cache programs;
    struct cell *cells;
    int cell_count, cells_total, label_width;
};

static void timing_progress(void *user, int round, int rounds)
{
    log_progress("  timing %s: round %d/%d", (const char *)user, round, rounds);
}

/* One scene's cells, configurations which[0..n-1] (this shard's):
 * rendered, scored and pictured, then timed together and their metrics
 * written. */
static int run_scene(struct run *r, const struct scene *scene, struct scene_setup *ss, const int *which, int n)
{
    const struct options *o = r->o;
    log_info("scene %s: %zu triangles", scene->name, scene->triangle_count);
    char *dir = util_printf("%s/%s", o->out_dir, scene->name);
    const struct scene_setup_desc desc = {o->width, o->height, o->shadow_map_size, o->gt_samples, 0, o->cache_dir, 0,
                                          &r->programs, &o->cascades};
    if (scene_setup_open(ss, scene, &desc) != 0) {
        free(dir);
        return -1;
    }
    struct stage_timer_cell *tc = xcalloc((size_t)n, sizeof *tc);
    struct stage_times *times = xcalloc((size_t)n, sizeof *times);
    struct cell *cells = &r->cells[r->cell_count];
    int rc = 0;
    /* Each cell rendered and scored first, which warms it (shader JIT,
     * caches), then every cell timed, interleaved. */
    for (int i = 0; i < n && !rc; i++, r->cell_count++) {
        const struct run_config *c = &r->configs.configs[which[i]];
        const void *settings = config_settings(c, scene);
        tc[i] = scene_setup_timer_cell(ss, c->technique, settings);
        cell_describe(&cells[i], scene->name, c->technique, settings, c->label);
        cell_note_search(&cells[i], settings, &ss->cascades);
        char *cell_dir = util_printf("%s/%s", dir, c->label);
        rc = scene_setup_cell(ss, c->technique, settings, &cells[i].m);
        if (rc && technique_is_engine(c->technique) && o->keep_going) {  /* marked, and the run goes on */
            cells[i].failed = xstrdup(engine_last_error());
            metrics_none(&cells[i].m);
            rc = util_mkdirs_own(cell_dir, 1);  /* its metrics.json says why */
        } else if (!rc) {
            cell_take_setup(&cells[i], ss);
            rc = output_cell_images(cell_dir, &(struct cell_images){ss->width, ss->height, ss->v, ss->distance,
                                                                    ss->gt.v, ss->scored});
        }
        free(cell_dir);
    }
    /* the cells that rendered, timed */
    int live = 0;
    for (int i = 0; i < n; i++)
        if (!cells[i].failed)
            tc[live++] = tc[i];
    bool *timing_failed = xcalloc((size_t)n, sizeof *timing_failed);
    if (!rc)
        rc = scene_setup_time(ss, &(struct scene_setup_timing){o->warmup, o->frames, o->timing, timing_progress,
                                                               (void *)scene->name,
                                                               o->keep_going ? timing_failed : NULL},
                              tc, live, times);
    /* back to the cells' order: times[k] is the k-th timed cell's */
    struct stage_times *timed = rc ? NULL : memcpy(xmalloc(sizeof *timed * (size_t)(live ? live : 1)), times,
                                                   sizeof *timed * (size_t)live);
    for (int i = 0, k = 0; i < n && !rc; i++) {
        const struct stage_times none = {NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN};
        if (cells[i].failed) {
            times[i] = none;
            continue;
        }
        if (timing_failed[k]) {  /* it rendered, then failed while timed: marked as one that failed */
            cells[i].failed = xstrdup(engine_last_error());
            metrics_none(&cells[i].m);
        }
        times[i] = timing_failed[k] ? none : timed[k];
        k++;
    }
    free(timed), free(timing_failed);
    log_progress_done();
    for (int i = 0; i < n && !rc; i++) {
        struct cell *c = &cells[i];
        cell_set_times(c, &times[i]);
        char *cell_dir = util_printf("%s/%s", dir, c->label);
        rc = output_cell_metrics(cell_dir, c);
        free(cell_dir);
        const int done = (int)(c - r->cells) + 1;
        if (c->failed)
            log_info("  [%d/%d] %-*s FAILED (engine): see above", done, r->cells_total, r->label_width, c->label);
        else if (!metrics_scored(&c->m))
            log_info("  [%d/%d] %-*s UNSCORED: no pixel to score (%ld GL/ray-tracer mismatches)", done,
                     r->cells_total, r->label_width, c->label, c->m.mismatch_pixels);
        else
            log_info("  [%d/%d] %-*s rmse %.4f  penumbra_rmse %.4f  leak %.4f  dark %.4f  %7.2f ms%s", done,
                     r->cells_total, r->label_width, c->label, c->m.rmse, c->m.penumbra_rmse, c->m.leak_fraction,
                     c->m.dark_fraction, c->m.ms_total, c->m.nonfinite ? "  NON-FINITE VALUES" : "");
    }
    free(tc), free(times);
    /* The scored mask is the same for every cell of shadowbench's own (same
     * camera, same geometry, one GL pass); an engine cell's may differ by the
     * silhouette pixels it sees otherwise (its mismatch_pixels):
     * groundtruth.exr carries the last cell's. */
    if (!rc)
        rc = output_groundtruth(dir, &ss->gt, ss->scored);
    free(dir);
    return rc ? -1 : 0;
}

/* The exit status of the cells: NaN/Inf or unscored cells fail (each
 * said); a failed engine cell (--keep-going) is a fault, 2. */
static int judge(const struct run *r)
{
    long bad = 0, unscored = 0, failed = 0;
    for (int i = 0; i < r->cell_count; i++) {
        bad += r->cells[i].m.nonfinite > 0;
        failed += r->cells[i].failed != NULL;
        unscored += !metrics_scored(&r->cells[i].m) && !r->cells[i].failed;
    }
    if (bad)
        log_error("%ld cell(s) produced NaN or Inf visibility", bad);
    if (failed)  /* each said when it failed */
        log_error("%ld engine cell(s) failed (marked failed in the matrix)", failed);
    for (int i = 0; i < r->cell_count; i++)
        if (!metrics_scored(&r->cells[i].m) && !r->cells[i].failed)
            log_error("%s/%s: unscored: no pixel where the camera sees a surface that the light's frustum holds, "
                      "that sees the light above its horizon and that GL and the ray tracer agree on; its metrics "
                      "are null", r->cells[i].scene, r->cells[i].label);
    return failed || engine_faulted() ? EXIT_USAGE : bad || unscored ? EXIT_CHECK_FAILED : EXIT_OK;
}

/* A run larger than the main job says, before it starts, how long it will
 * take at the pace of the committed benchmark (tools/bench-main:
 * results/bench/main_job.json, in the current folder or the source tree),
 * when it runs at the benchmark's settings on its renderer: the line
 * through the benchmark's two warm runs (the main job and run --settings
 * both) at this run's cell count. Nothing when the file is missing or
 * does not fit. */
#define MAIN_JOB_BENCH "results/bench/main_job.json"
static void say_estimate(const struct options *o, int cells)
{
    char *text = NULL, *source = xstrdup(MAIN_JOB_BENCH);
    size_t size;
    if (util_read_file(source, &text, &size) != 0) {
        free(source);
        source = util_printf("%s/%s", SB_SOURCE_DIR, MAIN_JOB_BENCH);
        if (util_read_file(source, &text, &size) != 0) {
            free(source);
            return;
        }
    }
    cJSON *bench = cJSON_Parse(text);
    const cJSON *main_job = cJSON_GetObjectItem(bench, "main_job"), *full = cJSON_GetObjectItem(bench, "full_run"),
                *device = cJSON_GetObjectItem(bench, "device"), *settings = cJSON_GetObjectItem(bench, "settings");
    const double n0 = cJSON_GetNumberValue(cJSON_GetObjectItem(main_job, "cells")),
                 t0 = cJSON_GetNumberValue(cJSON_GetObjectItem(main_job, "warm_median_seconds")),
                 n1 = cJSON_GetNumberValue(cJSON_GetObjectItem(full, "cells")),
                 t1 = cJSON_GetNumberValue(cJSON_GetObjectItem(full, "warm_seconds"));
    const char *renderer = cJSON_GetStringValue(cJSON_GetObjectItem(device, "gl_renderer"));
    const char *cpu = cJSON_GetStringValue(cJSON_GetObjectItem(device, "cpu"));
    const struct { const char *key; int value; } same[] = {
        {"width", o->width}, {"height", o->height}, {"gt_samples", o->gt_samples},
        {"shadow_map_size", o->shadow_map_size}, {"frames", o->frames}, {"warmup_frames", o->warmup}};
    /* Whole cell counts and times of a benchmark (0.1 s to 11 days): a file
     * of another shape says nothing; the comparisons also refuse NaN. */
    bool fits = n0 >= 1 && n1 > n0 && n1 <= 1e6 && n0 == floor(n0) && n1 == floor(n1) && t0 >= 0.1 && t1 >= t0 &&
                t1 <= 1e6 && cells > n0 && renderer && strcmp(renderer, gl_context_renderer()) == 0;
    for (size_t i = 0; i < ARRAY_SIZE(same) && fits; i++)
        fits = cJSON_GetNumberValue(cJSON_GetObjectItem(settings, same[i].key)) == same[i].value;
    if (fits)
        log_info("run: %d cells: about %.0f s on %s (%s: the main job's %.0f cells in %.1f s, and %.0f in %.1f s, "
                 "warm), more for ground truth not yet cached", cells, t0 + (t1 - t0) * (cells - n0) / (n1 - n0),
                 cpu ? cpu : "its machine", source, n0, t0, n1, t1);
    cJSON_Delete(bench);
    free(text), free(source);
}

/* The run's report (report_write) of the cells in r over scenes rs, with
 * its record run. Returns 0 or -1. */
static int write_report(const struct options *o, cJSON *run, const struct report_scene *rs, int scene_count,
                        const struct run *r, const struct frontiers *f)
{
    const struct report rep = {.out_dir = o->out_dir, .width = o->width, .height = o->height, .run = run,
                               .scenes = rs, .scene_count = scene_count, .cells = r->cells,
                               .cell_count = r->cell_count, .frontier = f->all, .frontier_count = f->all_count,
                               .frontier_source = f->source, .frontier_objective = f->objective,
                               .frontier_fetches = f->cost_fetches};
    return report_write(&rep);
}

/* --out is not inside the tuned folder: a report among the tuned files.
 * Returns 0 or -1 (logged). */
static int out_folders_apart(const struct options *o)
{
    if (!o->tuned_dir || !util_path_within(o->out_dir, o->tuned_dir))
        return 0;
    log_error("--out %s: inside the tuned folder %s; name a folder apart", o->out_dir, o->tuned_dir);
    return -1;
}

/* The run's cells in its order with the settings each renders at (a
 * tuned cell's come from its tuned file), as one number (cli_merge_plan). */
static uint64_t run_plan(const struct config_set *configs, const struct scene *scenes, int scene_count)
{
    uint64_t h = UTIL_HASH_INIT;
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < configs->count; i++) {
            const struct run_config *c = &configs->configs[i];
            struct strbuf settings = {0};
            params_summary(c->technique, config_settings(c, &scenes[s]), &settings);
            h = cli_plan_add(cli_plan_add(cli_plan_add(h, scenes[s].name), c->label),
                             settings.data ? settings.data : "");
            strbuf_free(&settings);
        }
    return h;
}

int run_main(const struct options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE;
    struct run r = {.o = o};
    struct frontiers frontiers = {0};
    struct report_scene rs[CLI_MAX_SCENES] = {0};
    int *owner = NULL, rs_count = 0;
    cJSON *truths = cJSON_CreateArray();  /* each scene's ground truth, for the shard's record */
    const struct config_desc cd = {o->techniques, o->technique_count, o->settings, o->sweeps, o->sweep_count,
                                   o->set_count, o->settings_mode, o->tuned_dir};
    if (out_folders_apart(o) != 0)
        goto out;
    if (configs_build(&r.configs, &cd) != 0 || cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0 ||
        out_dir_claim(o->out_dir) != 0)
        goto out;
    cli_shard_begin(o);
    /* this shard's cells (every cell unsharded); a scene with none is not opened */
    const int n = r.configs.count;
    owner = xcalloc((size_t)(scene_count * n) + 1, sizeof *owner);
    run_owners(&r.configs, scene_count, o->shard.count ? o->shard.count : 1, owner);
#define OWNED(s, i) shard_owns(&o->shard, owner[(s) * n + (i)])
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < n; i++)
            r.cells_total += OWNED(s, i);
    for (int s = 0; s < scene_count; s++) {  /* their folders, before any work: none may be a link out of --out */
        bool any = false;
        for (int i = 0; i < n; i++)
            any = any || OWNED(s, i);
        if (!any)
            continue;
        char *dir = util_printf("%s/%s", o->out_dir, scenes[s].name);
        const int rc = util_mkdirs_own(dir, 1);
        free(dir);
        if (rc != 0)
            goto out;
    }
    if (begin_run(o) != 0) {  /* a write that fails: a runtime error */
        status = EXIT_CHECK_FAILED;
        goto out;
    }
    if (cli_gl_open(o, o->gl) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    for (int s = 0; s < scene_count; s++)  /* every program first: a compile error fails at once */
        for (int i = 0; i < n; i++) {
            const struct run_config *c = &r.configs.configs[i];
            if (!OWNED(s, i))
                continue;
            for (int counting = 0; counting <= 1 && !technique_is_engine(c->technique); counting++)  /* scored by the one, timed by the other */
                if (!programs_get(&r.programs, c->technique, config_settings(c, &scenes[s]), scenes[s].light.shape,
                                  counting).receiver)
                    goto out_gl;
        }
    say_estimate(o, r.cells_total);
    for (int i = 0; i < r.configs.count; i++)
        if ((int)strlen(r.configs.configs[i].label) > r.label_width)
            r.label_width = (int)strlen(r.configs.configs[i].label);
    if (r.configs.untuned.data)
        log_info("no tuned settings in %s for %s: their default cells only (shadowbench tune --write-tuned "
                 "writes them)", o->tuned_dir, r.configs.untuned.data);
    if (o->shard.count)
        log_info("run: shard %d of %d: %d of the %d cells", o->shard.index, o->shard.count, r.cells_total,
                 scene_count * n);
    log_info("run: %d scene(s) x %d technique configuration(s), %dx%d, %d GT samples, %d^2 shadow map, median of %d "
             "frames after %d warm-up, cells interleaved, on %s (%s, %s), timed by %s", scene_count, r.configs.count,
             o->width, o->height, o->gt_samples, o->shadow_map_size, o->frames, o->warmup, gl_context_renderer(),
             gl_context_vendor(), gl_context_platform(), stage_timing_text(o->timing));
    r.cells = xcalloc((size_t)r.cells_total + 1, sizeof *r.cells);
    frontiers_build(&frontiers, r.configs.configs, r.configs.count, scenes, scene_count, o->tuned_dir);
    int failed = 0;
    int *which = xcalloc((size_t)n + 1, sizeof *which);
    for (int s = 0; s < scene_count && !failed; s++) {
        int owned = 0;
        for (int i = 0; i < n; i++)
            if (OWNED(s, i))
                which[owned++] = i;
        if (!owned)
            continue;
        struct scene_setup ss = {0};
        failed = run_scene(&r, &scenes[s], &ss, which, owned);
        rs[rs_count++] = (struct report_scene){scenes[s].name, scenes[s].description, scenes[s].shows,
                                               ss.gt.seconds, ss.gt.msamples_per_second, ss.gt.cached,
                                               frontiers.scene[s], frontiers.scene_count[s]};
        cJSON *t = cJSON_CreateObject();
        cJSON_AddStringToObject(t, "scene", scenes[s].name);
        cJSON_AddNumberToObject(t, "seconds", ss.gt.seconds);
        cJSON_AddNumberToObject(t, "msamples_per_second", ss.gt.msamples_per_second);
        cJSON_AddBoolToObject(t, "cached", ss.gt.cached);
        cJSON_AddItemToArray(truths, t);
        scene_setup_free(&ss);
    }
    free(which);
#undef OWNED
    if (!failed) {
        /* The report, then run.json "complete": a signal waits until they
         * are written (killed in between, the folder would say complete
         * with the status of a kill, or hold a report that says nothing) */
        util_signals_defer();
        cJSON *run = cli_run_record(o, true, (util_now_ms() - start) * 1e-3);
        cJSON_AddTrueToObject(run, "complete");
        failed = write_report(o, run, rs, rs_count, &r, &frontiers);
        cJSON_Delete(run);
        cJSON *more = cli_shard_more((util_now_ms() - start) * 1e-3, run_plan(&r.configs, scenes, scene_count));
        cJSON_AddItemToObject(more, "ground_truth", truths);
        truths = NULL;
        if (failed)
            cJSON_Delete(more);
        else
            failed = cli_shard_end(o, scenes, scene_count, more) != 0;
    }
    if (!failed)
        status = judge(&r);
    else if (engine_faulted())  /* an engine that could not render: a fault, said in one line */
        status = EXIT_USAGE;
    cli_done(o, status, !failed, "run", OUTPUT_REPORT, "matrix", OUTPUT_MATRIX_CSV, start);
    for (int i = 0; i < r.cell_count; i++)
        cell_free(&r.cells[i]);
    free(r.cells);
    frontiers_free(&frontiers, scene_count);
out_gl:
    programs_free(&r.programs);
    gl_context_destroy();
out:
    cJSON_Delete(truths);
    free(owner);
    configs_free(&r.configs);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}

void run_owners(const struct config_set *configs, int scene_count, int shards, int *owner)
{
    const int n = configs->count;
    double *cost = xmalloc(sizeof *cost * (size_t)(scene_count * n + 1));
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < n; i++)
            cost[s * n + i] = cli_cell_cost(configs->configs[i].technique);
    shard_split_contiguous(cost, scene_count * n, shards, owner);
    free(cost);
}

/* The files a run writes of a cell (of one that failed, its metrics.json
 * alone), from this one to CELL_METRICS_JSON. */
static int cell_file_first(const struct cell *c)
{
    return c->failed ? CELL_METRICS_JSON : CELL_VISIBILITY_EXR;
}

/* "<dir>/<scene>/<cell>/<name>" (cell NULL: the scene's). */
static char *merge_path(const char *dir, const struct scene *s, const struct run_config *c, int file)
{
    return c ? util_printf("%s/%s/%s/%s", dir, s->name, c->label, cell_files[file])
             : util_printf("%s/%s/%s", dir, s->name, cell_files[file]);
}

/* Cell (scene s, configuration c) from the shard in dir that owns it: its
 * metrics.json read into *cell (the parsed record into *doc, which the
 * cell's device name points into) and each file it should have there. */
static int merge_cell(const char *dir, const struct scene *s, const struct run_config *c, struct cell *cell,
                      cJSON **doc)
{
    char *path = merge_path(dir, s, c, CELL_METRICS_JSON), *text = NULL;
    size_t size;
    cell_describe(cell, s->name, c->technique, config_settings(c, s), c->label);
    int rc = util_read_file(path, &text, &size);
    *doc = rc ? NULL : cJSON_Parse(text);
    if (rc || !*doc || report_cell_read(*doc, cell) != 0 ||
        strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(*doc, "cell")) ?: "", c->label) != 0 ||
        strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(*doc, "scene")) ?: "", s->name) != 0) {
        log_error("merge: %s: %s (the shard that owns cell %s/%s)", path,
                  rc ? util_read_error(rc) : "not the metrics.json of this cell", s->name, c->label);
        rc = -1;
    }
    for (int f = cell_file_first(cell); !rc && f <= CELL_METRICS_JSON; f++) {
        char *file = merge_path(dir, s, c, f);
        rc = cli_is_file(file) ? 0 : -1;
        free(file);
    }
    free(path), free(text);
    return rc ? -1 : 0;
}

/* File `file` of cell c (NULL: of scene s) from shard folder dir into out. */
static int copy_from(const char *dir, const char *out, const struct scene *s, const struct run_config *c, int file)
{
    char *from = merge_path(dir, s, c, file), *to = merge_path(out, s, c, file);
    const int rc = cli_copy_file(from, to);
    free(from), free(to);
    return rc;
}

int run_merge(const struct options *o, const struct merge_input *in)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE, cell_count = 0;
    struct run r = {.o = o};
    struct frontiers frontiers = {0};
    struct report_scene rs[CLI_MAX_SCENES] = {0};
    const struct config_desc cd = {o->techniques, o->technique_count, o->settings, o->sweeps, o->sweep_count,
                                   o->set_count, o->settings_mode, o->tuned_dir};
    int *owner = NULL;
    cJSON **docs = NULL;
    if (out_folders_apart(o) != 0 || configs_build(&r.configs, &cd) != 0 ||
        cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0)
        goto out;
    const int n = r.configs.count;
    if (cli_merge_plan(in, run_plan(&r.configs, scenes, scene_count)) != 0)
        goto out;
    owner = xcalloc((size_t)(scene_count * n) + 1, sizeof *owner);
    run_owners(&r.configs, scene_count, in->count, owner);
    r.cells = xcalloc((size_t)(scene_count * n) + 1, sizeof *r.cells);
    docs = xcalloc((size_t)(scene_count * n) + 1, sizeof *docs);
    for (int s = 0; s < scene_count && n; s++) {  /* every cell read and every file seen before OUT is made */
        for (int i = 0; i < n; i++, cell_count++)
            if (merge_cell(in->dirs[owner[s * n + i]], &scenes[s], &r.configs.configs[i], &r.cells[cell_count],
                           &docs[cell_count]) != 0) {
                cell_count++;
                goto out;
            }
        for (int f = CELL_GROUNDTRUTH_EXR; f <= CELL_GROUNDTRUTH_PNG; f++) {
            char *file = merge_path(in->dirs[owner[s * n + n - 1]], &scenes[s], NULL, f);
            const bool there = cli_is_file(file);
            free(file);
            if (!there)
                goto out;
        }
    }
    r.cell_count = cell_count;
    if (out_dir_claim(o->out_dir) != 0 || begin_run(o) != 0)
        goto out;
    cli_shard_begin(o);  /* a shard's record left in OUT would make it pass for one */
    status = EXIT_CHECK_FAILED;  /* the shards are read: what fails now is a write, or the run's */
    for (int s = 0, k = 0; s < scene_count && n; s++) {
        for (int i = 0; i < n; i++, k++)  /* each cell's files from its shard */
            for (int f = cell_file_first(&r.cells[k]); f <= CELL_METRICS_JSON; f++)
                if (copy_from(in->dirs[owner[s * n + i]], o->out_dir, &scenes[s], &r.configs.configs[i], f) != 0)
                    goto out;
        /* the scene's ground-truth pictures from the shard of its last cell, as a run writes them after it */
        for (int f = CELL_GROUNDTRUTH_EXR; f <= CELL_GROUNDTRUTH_PNG; f++)
            if (copy_from(in->dirs[owner[s * n + n - 1]], o->out_dir, &scenes[s], NULL, f) != 0)
                goto out;
    }
    /* each scene's ground truth as the shard that traced it saw it (one traced, the others read it cached) */
    frontiers_build(&frontiers, r.configs.configs, n, scenes, scene_count, o->tuned_dir);
    for (int s = 0; s < scene_count; s++) {
        const cJSON *truth = NULL;
        for (int k = 1; k <= in->count; k++) {
            const cJSON *t;
            cJSON_ArrayForEach(t, cJSON_GetObjectItem(in->records[k], "ground_truth"))
                if (!strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(t, "scene")) ?: "", scenes[s].name) &&
                    (!truth || cJSON_IsTrue(cJSON_GetObjectItem(truth, "cached"))))
                    truth = t;
        }
        rs[s] = (struct report_scene){scenes[s].name, scenes[s].description, scenes[s].shows,
                                      cJSON_GetNumberValue(cJSON_GetObjectItem(truth, "seconds")),
                                      cJSON_GetNumberValue(cJSON_GetObjectItem(truth, "msamples_per_second")),
                                      cJSON_IsTrue(cJSON_GetObjectItem(truth, "cached")), frontiers.scene[s],
                                      frontiers.scene_count[s]};
    }
    util_signals_defer();
    cJSON *run = cli_run_record(o, true, cli_merge_seconds(in));
    cJSON_AddTrueToObject(run, "complete");
    cli_merge_record(run, in);
    const bool written = write_report(o, run, rs, scene_count, &r, &frontiers) == 0;
    cJSON_Delete(run);
    status = written ? judge(&r) : EXIT_CHECK_FAILED;
    cli_done(o, status, written, "merge", OUTPUT_REPORT, "matrix", OUTPUT_MATRIX_CSV, start);
    frontiers_free(&frontiers, scene_count);
out:
    for (int i = 0; i < cell_count; i++) {
        cell_free(&r.cells[i]);
        cJSON_Delete(docs[i]);
    }
    free(r.cells), free(docs), free(owner);
    configs_free(&r.configs);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
