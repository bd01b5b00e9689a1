/* The harness loop. Per scene: the ground truth (cached), the shadow-map
 * products the selected techniques need (rendered once, timed), then one
 * receiver pass per technique, scored and written out (DESIGN.md §2, §8). */
#include "run.h"
#include "catalog.h"
#include "tuned.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/scene_mesh.h"
#include "gl/shader.h"
#include "output/cell_output.h"
#include "output/report.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
#include "score/metrics.h"
#include "techniques/params.h"
#include "truth/groundtruth.h"

#include <OpenEXR/openexr.h>
#include <embree3/rtcore.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

void run_options_defaults(struct run_options *o, enum run_command cmd)
{
    bool bench = cmd == RUN_CMD_BENCH, tune = cmd == RUN_CMD_TUNE, stability = cmd == RUN_CMD_STABILITY;
    o->width = o->height = bench ? BENCH_DEFAULT_SIZE : tune ? TUNE_DEFAULT_SIZE
                         : stability                  ? STABILITY_DEFAULT_SIZE
                                                      : RUN_DEFAULT_SIZE;
    o->gt_samples = cmd == RUN_CMD_VIEW ? VIEW_DEFAULT_GT_SAMPLES : GT_DEFAULT_SAMPLES;
    o->shadow_map_size = SHADOWMAP_DEFAULT_SIZE;
    o->frames = bench       ? BENCH_DEFAULT_FRAMES
                : tune      ? TUNE_DEFAULT_FRAMES
                : stability ? STABILITY_DEFAULT_FRAMES
                : cmd == RUN_CMD_VIEW ? 0  /* until the window closes */
                            : RUN_DEFAULT_FRAMES;
    o->warmup = bench ? BENCH_DEFAULT_WARMUP : tune ? TUNE_DEFAULT_WARMUP : RUN_DEFAULT_WARMUP;
    o->out_dir = cmd == RUN_CMD_GT      ? GT_DEFAULT_OUT
                 : cmd == RUN_CMD_CHECK ? CHECK_DEFAULT_OUT
                 : tune                 ? TUNE_DEFAULT_OUT
                 : stability            ? STABILITY_DEFAULT_OUT
                                        : RUN_DEFAULT_OUT;
    o->cache_dir = RUN_DEFAULT_CACHE;
    o->baselines_dir = CHECK_DEFAULT_BASELINES;
    o->tuned_dir = TUNED_DEFAULT_DIR;
    o->objective = METRIC_penumbra_rmse;
    o->accumulate = STABILITY_DEFAULT_ACCUMULATE;
}

const void *run_config_settings(const struct run_config *c, const struct scene *s)
{
    return c->tuned ? tuned_settings(c->tuned, s->name) : c->settings;
}

void *run_settings(const struct run_options *o, const struct technique *t)
{
    int i = 0;
    while (technique_list[i] != t)
        i++;
    return o->settings[i];
}

/* A scene's name is its file's stem and becomes <out>/<name>: it must name a
 * folder of its own there, not climb out, hide, or take a run file's
 * name. Refused before any work. */
static int check_scene_name(const struct scene *s)
{
    static const char *const taken[] = {"charts", "report.html", "matrix.csv", "matrix.json", "run.json",
                                        "check.html"};
    const char *n = s->name;
    bool control = false, bidi = false;
    unsigned cp;
    for (const char *p = n; *p;) {
        p += util_utf8_next(p, &cp);
        control |= cp < 32 || cp == 127 || cp == '/';
        bidi |= util_bidi_control(cp);
    }
    bool reserved = false;
    for (size_t i = 0; i < sizeof taken / sizeof *taken; i++)
        reserved |= strcmp(n, taken[i]) == 0;
    const bool long_name = strlen(n) > 200;  /* with "_tradeoff.svg" and the like, under 255 bytes */
    const bool utf8 = util_valid_utf8(n);
    if (!*n || n[0] == '.' || control || bidi || reserved || long_name || !utf8) {
        log_error("%s: its name (the file's stem) cannot name its output folder: %s", s->path,
                  !*n || n[0] == '.' ? "it is empty or starts with '.'"
                  : control           ? "it holds a control character"
                  : bidi              ? "it holds a bidirectional formatting character (it would show reordered)"
                  : long_name         ? "it is longer than 200 bytes"
                  : !utf8             ? "it is not valid UTF-8"
                                      : "a run's own file has that name");
        return -1;
    }
    return 0;
}

int run_load_scenes(const struct run_options *o, struct scene *scenes, int *count)
{
    char **paths = NULL;
    int n = o->scene_count;
    if (n == 0) {
        n = catalog_shipped(&paths);
        if (n <= 0) {
            if (n == 0)
                log_error("no shipped scenes found");
            return -1;
        }
    } else {
        paths = xcalloc((size_t)n, sizeof *paths);
        for (int i = 0; i < n; i++)
            if (!(paths[i] = catalog_resolve(o->scenes[i]))) {
                catalog_free(paths, n);
                return -1;
            }
    }
    int rc = 0;
    *count = 0;
    for (int i = 0; i < n && i < RUN_MAX_SCENES && !rc; i++) {
        rc = scene_load(paths[i], &scenes[i]);
        if (!rc)
            (*count)++;
        if (!rc && (rc = check_scene_name(&scenes[i])) != 0)
            continue;
        /* Outputs go to <out>/<scene name>: two scenes may not share one. */
        for (int j = 0; j < i && !rc; j++)
            if (strcmp(scenes[j].name, scenes[i].name) == 0) {
                log_error("%s: its name '%s' is taken by %s (outputs are per scene name)",
                          scenes[i].path, scenes[i].name, scenes[j].path);
                rc = -1;
            }
    }
    catalog_free(paths, n);
    return rc;
}

int run_prepare_out_dir(const char *dir)
{
    if (util_mkdirs(dir) != 0)
        return -1;
    if (!util_dir_writable(dir)) {
        log_error("%s: output folder is not writable", dir);
        return -1;
    }
    return 0;
}

/* Whether dir exists with something in it other than what shadowbench
 * itself leaves (its .lock). */
static bool foreign_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return false;
    bool any = false, lock = false;
    for (struct dirent *e; (e = readdir(d));) {
        lock |= strcmp(e->d_name, ".lock") == 0;
        any |= strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    }
    closedir(d);
    return any && !lock;
}

int run_claim_out_dir(const char *dir)
{
    /* A folder shadowbench did not make is not cleaned: its report.html or
     * *.tmp.<pid> files may be someone else's. */
    if (foreign_dir(dir)) {
        log_error("%s: holds files and was not made by shadowbench (no .lock in it): name a new or empty "
                  "output folder", dir);
        return -1;
    }
    if (run_prepare_out_dir(dir) != 0 || util_lock_dir(dir) != 0)
        return -1;
    util_remove_stale_temps(dir, 3);  /* <out>/<scene>/<cell>/files: a killed run's */
    return 0;
}

int run_claim_results_dir(const char *dir, int depth)
{
    if (run_prepare_out_dir(dir) != 0 || util_lock_dir(dir) != 0)
        return -1;
    util_remove_stale_temps(dir, depth);
    return 0;
}

int scene_setup_open(struct scene_setup *ss, const struct scene *s, const struct scene_setup_desc *d)
{
    memset(ss, 0, sizeof *ss);
    ss->scene = s;
    ss->width = d->width, ss->height = d->height;
    scene_mesh_upload(s, &ss->mesh);
    if (shadowmap_create(&ss->sm, s,
                         &(struct shadowmap_desc){.size_texels = d->shadow_map_size, .near_scale = d->near_scale}) ||
        receiver_create(&ss->receiver, s, d->width, d->height) ||
        gt_obtain(s, &ss->sm.frustum,
                  &(struct gt_desc){.width = d->width, .height = d->height, .samples = d->gt_samples,
                                    .seed = d->gt_seed},
                  d->cache_dir, &ss->gt) != 0)
        return -1;
    const size_t count = (size_t)d->width * (size_t)d->height;
    ss->v = xmalloc(sizeof(float) * count);
    ss->distance = xmalloc(sizeof(float) * count);
    ss->scored = xcalloc(count, sizeof(float));  /* written whole even before any cell is scored */
    ss->timer = (struct stage_timer){.sm = &ss->sm, .mesh = &ss->mesh, .receiver = &ss->receiver};
    return 0;
}

int scene_setup_cell(struct scene_setup *ss, const struct stage_timer_cell *cell, struct metrics *m)
{
    if (stage_timer_render(&ss->timer, cell) != 0)
        return -1;
    scene_setup_score(ss, m);
    return 0;
}

void scene_setup_score(struct scene_setup *ss, struct metrics *m)
{
    receiver_read(&ss->receiver, ss->v, ss->distance);
    m->mismatch_pixels = metrics_score_mask(ss->gt.mask, ss->gt.distance, ss->distance,
                                            ss->width * ss->height, ss->scored);
    metrics_compute(ss->v, &ss->gt, ss->scored, ss->distance, m);
}

void scene_setup_free(struct scene_setup *ss)
{
    gt_image_free(&ss->gt);
    receiver_destroy(&ss->receiver);
    shadowmap_destroy(&ss->sm);
    scene_mesh_destroy(&ss->mesh);
    free(ss->v), free(ss->distance), free(ss->scored);
    memset(ss, 0, sizeof *ss);
}

GLuint run_program_get(struct run_programs *pc, const struct technique *t, const void *settings,
                       enum light_shape shape)
{
    for (int i = 0; i < pc->count; i++) {
        const struct run_program *e = &pc->entries[i];
        if (e->t == t && e->shape == shape && memcmp(e->settings, settings, t->settings_size) == 0)
            return e->program;
    }
    GLuint program = receiver_program(t, settings, shape);
    if (program) {
        pc->entries = xrealloc(pc->entries, sizeof *pc->entries * (size_t)(pc->count + 1));
        pc->entries[pc->count++] = (struct run_program){
            t, memcpy(xmalloc(t->settings_size), settings, t->settings_size), shape, program};
    }
    return program;
}

void run_programs_free(struct run_programs *pc)
{
    for (int i = 0; i < pc->count; i++) {
        glDeleteProgram(pc->entries[i].program);
        free(pc->entries[i].settings);
    }
    free(pc->entries);
    memset(pc, 0, sizeof *pc);
}

/* A scene of the run: its shared set-up, timing and progress. */
struct scene_run {
    const struct run_options *o;
    struct scene_setup ss;
    char *dir;
    int *cells_done, cells_total, label_width;  /* progress */
};

/* What a cell is: its scene, technique, name and parameter values. */
static void describe_cell(const struct scene_run *sr, const struct run_config *config, struct cell *c)
{
    const void *settings = run_config_settings(config, sr->ss.scene);
    c->scene = sr->ss.scene->name;
    c->technique = config->technique;
    c->label = config->label;
    c->gl_renderer = gl_context_renderer();
    c->params = params_json(config->technique, settings);
    struct strbuf text = {0};
    params_summary(config->technique, settings, &text);
    c->params_text = text.data ? text.data : xstrdup("");
}

/* Renders the cell (untimed: this also warms it for the timing), scores it
 * and writes its pictures. */
static int score_cell(struct scene_run *sr, const struct stage_timer_cell *tc, const struct run_config *config,
                      struct cell *c)
{
    struct scene_setup *ss = &sr->ss;
    c->m = (struct metrics){0};
    describe_cell(sr, config, c);
    if (scene_setup_cell(ss, tc, &c->m) != 0)
        return -1;
    char *dir = util_printf("%s/%s", sr->dir, config->label);
    const struct cell_images im = {ss->width, ss->height, ss->v, ss->distance, ss->gt.v, ss->scored};
    int rc = output_cell_images(dir, &im);
    free(dir);
    return rc;
}

/* The cell's times into its metrics, then its metrics.json and its line. */
static int finish_cell(struct scene_run *sr, const struct run_config *config, const struct stage_times *times,
                       struct cell *c)
{
    c->m.ms_shadowmap = times->shadowmap_ms, c->m.ms_filter_prep = times->filter_prep_ms;
    c->m.ms_receiver = times->receiver_ms, c->m.ms_total = times->total_ms;
    c->m.ms_total_q1 = times->total_q1_ms, c->m.ms_total_q3 = times->total_q3_ms;
    char *dir = util_printf("%s/%s", sr->dir, config->label);
    int rc = output_cell_metrics(dir, c);
    free(dir);
    ++*sr->cells_done;
    if (!metrics_scored(&c->m))
        log_info("  [%d/%d] %-*s UNSCORED: no pixel to score (%ld GL/ray-tracer mismatches)",
                 *sr->cells_done, sr->cells_total, sr->label_width, config->label,
                 c->m.mismatch_pixels);
    else
        log_info("  [%d/%d] %-*s rmse %.4f  penumbra_rmse %.4f  leak %.4f  dark %.4f  %7.2f ms%s",
                 *sr->cells_done, sr->cells_total, sr->label_width, config->label, c->m.rmse,
                 c->m.penumbra_rmse, c->m.leak_fraction, c->m.dark_fraction, c->m.ms_total,
                 c->m.nonfinite ? "  NON-FINITE VALUES" : "");
    return rc;
}

/* Progress of the interleaved timing, on one line while stderr is a terminal. */
static void timing_progress(void *user, int round, int rounds)
{
    const struct scene_run *sr = user;
    if (isatty(STDERR_FILENO) && log_get_level() >= LOG_INFO)
        fprintf(stderr, "\r  timing %s: round %d/%d%s", sr->ss.scene->name, round, rounds,
                round == rounds ? "\n" : "");
}

static int run_scene(struct scene_run *sr, const struct scene *scene, struct run_programs *programs,
                     struct cell *cells, int *cell_count)
{
    const struct run_options *o = sr->o;
    log_info("scene %s: %zu triangles", scene->name, scene->triangle_count);
    sr->dir = util_printf("%s/%s", o->out_dir, scene->name);
    if (util_mkdirs(sr->dir) != 0 ||
        scene_setup_open(&sr->ss, scene,
                         &(struct scene_setup_desc){o->width, o->height, o->shadow_map_size,
                                                    o->gt_samples, 0, o->cache_dir, 0}) != 0)
        return -1;
    struct stage_timer timer = sr->ss.timer;
    timer.warmup = o->warmup, timer.frames = o->frames, timer.timing = o->timing;
    timer.on_round = timing_progress, timer.user = sr;

    struct stage_timer_cell *tc = xcalloc((size_t)o->config_count, sizeof *tc);
    struct stage_times *times = xcalloc((size_t)o->config_count, sizeof *times);
    for (int i = 0; i < o->config_count; i++) {
        const void *settings = run_config_settings(&o->configs[i], scene);
        tc[i] = (struct stage_timer_cell){o->configs[i].technique, settings,
                                          run_program_get(programs, o->configs[i].technique, settings,
                                                      scene->light.shape)};
    }
    /* Each cell rendered and scored first, which warms it (shader JIT,
     * caches), then every cell timed, interleaved. */
    const int base = *cell_count;
    int rc = 0, scored = 0;
    for (; scored < o->config_count && !rc; scored++)
        rc = score_cell(sr, &tc[scored], &o->configs[scored], &cells[base + scored]);
    *cell_count = base + scored;  /* the cells described: the caller frees them whatever happens */
    if (!rc)
        rc = stage_timer_run(&timer, tc, o->config_count, times);
    for (int i = 0; i < o->config_count && !rc; i++)
        rc = finish_cell(sr, &o->configs[i], &times[i], &cells[base + i]);
    free(tc);
    free(times);

    /* The scored mask is the same for every cell of the scene (same camera,
     * same geometry): groundtruth.exr carries the last cell's. */
    return rc ? -1 : output_groundtruth(sr->dir, &sr->ss.gt, sr->ss.scored);
}

static void scene_run_free(struct scene_run *sr)
{
    scene_setup_free(&sr->ss);
    free(sr->dir);
    sr->dir = NULL;
}

char *run_command_line(const struct run_options *o)
{
    struct strbuf cmd = {0};
    for (int i = 0; i < o->argc; i++)
        strbuf_list_printf(&cmd, " ", "%s", o->argv[i]);
    char *text = util_utf8_copy(cmd.data ? cmd.data : "");
    strbuf_free(&cmd);
    return text;
}

char *run_utc_date(void)
{
    char date[64];
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", gmtime(&now));
    return xstrdup(date);
}

char *run_git_describe(void)
{
    char buf[128] = "unknown";
    char *cmd = util_printf("git -C '%s' describe --always --dirty 2>/dev/null", SB_SOURCE_DIR);
    FILE *p = popen(cmd, "r");
    free(cmd);
    if (p) {
        if (!fgets(buf, sizeof buf, p))
            strcpy(buf, "unknown");
        pclose(p);
    }
    buf[strcspn(buf, "\n")] = '\0';
    return xstrdup(buf);
}

static char *cpu_model(void)
{
    char line[512];
    FILE *f = fopen("/proc/cpuinfo", "r");
    char *model = NULL;
    while (f && !model && fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0 && strchr(line, ':')) {
            char *v = strchr(line, ':') + 2;
            v[strcspn(v, "\n")] = '\0';
            model = xstrdup(v);
        }
    if (f)
        fclose(f);
    return model ? model : xstrdup("unknown");
}

cJSON *run_json(const struct run_options *o, double seconds)
{
    cJSON *r = cJSON_CreateObject();
    char *cmd = run_command_line(o);
    cJSON_AddStringToObject(r, "command_line", cmd);
    free(cmd);
    char *git = run_git_describe(), *cpu = cpu_model();
    cJSON_AddStringToObject(r, "shadowbench_version", SB_VERSION);
    cJSON_AddStringToObject(r, "git_describe", git);
    cJSON_AddStringToObject(r, "gl_renderer", gl_context_renderer());
    cJSON_AddStringToObject(r, "gl_vendor", gl_context_vendor());
    cJSON_AddStringToObject(r, "gl_version", gl_context_version());
    cJSON_AddStringToObject(r, "gl_platform", gl_context_platform());
    cJSON_AddStringToObject(r, "timing_method", stage_timing_text(o->timing));
    cJSON_AddStringToObject(r, "embree_version", RTC_VERSION_STRING);
    cJSON_AddStringToObject(r, "openexr_version", OPENEXR_VERSION_STRING);
    cJSON_AddStringToObject(r, "cpu", cpu);
    cJSON_AddNumberToObject(r, "cpu_threads", (double)sysconf(_SC_NPROCESSORS_ONLN));
    char *date = run_utc_date();
    cJSON_AddStringToObject(r, "date", date);
    free(date);
    cJSON_AddNumberToObject(r, "width", o->width);
    cJSON_AddNumberToObject(r, "height", o->height);
    cJSON_AddNumberToObject(r, "gt_samples", o->gt_samples);
    cJSON_AddNumberToObject(r, "shadow_map_size", o->shadow_map_size);
    cJSON_AddNumberToObject(r, "frames", o->frames);
    cJSON_AddNumberToObject(r, "warmup_frames", o->warmup);
    cJSON_AddNumberToObject(r, "seconds", seconds);
    free(git);
    free(cpu);
    return r;
}

/* The folder says what state it is in (DESIGN.md §8): run.json with
 * "complete": false first, the previous run's report and matrix removed
 * (they would describe another run); report_write ends with run.json
 * "complete": true. A run that fails or is killed leaves false. */
static int begin_run(const struct run_options *o)
{
    static const char *const stale[] = {"report.html", "matrix.csv", "matrix.json"};
    for (size_t i = 0; i < sizeof stale / sizeof *stale; i++) {
        char *path = util_printf("%s/%s", o->out_dir, stale[i]);
        unlink(path);
        free(path);
    }
    cJSON *run = run_json(o, 0.0);
    cJSON_AddFalseToObject(run, "complete");
    char *path = util_printf("%s/run.json", o->out_dir);
    int rc = report_write_json(path, run);
    free(path);
    cJSON_Delete(run);
    return rc;
}

/* The frontier charts' data, from the tuned cells' files. */
struct frontiers {
    struct chart_curve *all, *scene[RUN_MAX_SCENES];
    int all_count, scene_count[RUN_MAX_SCENES];
    double **arrays;
    int array_count;
    char *source, *objective;
};

/* t's frontier from tu over every scene (scene NULL) or one, appended to
 * curves[*n] (nothing when the file has none for it). */
static void add_curve(struct frontiers *f, const struct tuned *tu, const char *scene, struct chart_curve *curves,
                      int *n)
{
    struct tuned_point *p, def, tuned;
    const int count = tuned_frontier(tu, scene, &p, &def, &tuned);
    if (count) {
        double *a = xmalloc(sizeof(double) * 4 * (size_t)count);
        for (int i = 0; i < count; i++)
            a[i] = p[i].ms, a[count + i] = p[i].error, a[2 * count + i] = p[i].ms_q1, a[3 * count + i] = p[i].ms_q3;
        f->arrays = xrealloc(f->arrays, sizeof *f->arrays * (size_t)(f->array_count + 1));
        f->arrays[f->array_count++] = a;
        int group = 0;
        while (technique_list[group] != tu->t)
            group++;
        curves[(*n)++] = (struct chart_curve){{tu->t->name, tu->t->name, group}, count, a, a + count, a + 2 * count,
                                              a + 3 * count, def.ms, def.error, tuned.ms, tuned.error};
    }
    free(p);
}

static void frontiers_build(struct frontiers *f, const struct run_options *o, const struct scene *scenes,
                            int scene_count)
{
    memset(f, 0, sizeof *f);
    f->all = xcalloc((size_t)o->config_count + 1, sizeof *f->all);
    for (int s = 0; s < scene_count; s++)
        f->scene[s] = xcalloc((size_t)o->config_count + 1, sizeof *f->scene[s]);
    const struct tuned *first = NULL;  /* one chart, one tuning: its size, map, scenes and objective */
    for (int i = 0; i < o->config_count; i++) {
        const struct tuned *tu = o->configs[i].tuned;
        if (!tu)
            continue;
        if (first && (tu->width != first->width || tu->height != first->height ||
                      tu->shadow_map_size != first->shadow_map_size || strcmp(tu->objective, first->objective) ||
                      !cJSON_Compare(cJSON_GetObjectItemCaseSensitive(tu->doc, "scenes"),
                                     cJSON_GetObjectItemCaseSensitive(first->doc, "scenes"), true))) {
            log_warn("%s: tuned at another size, map, objective or set of scenes than %s: its cell runs, its "
                     "frontier is left out of the chart", tu->path, first->path);
            continue;
        }
        first = first ? first : tu;
        add_curve(f, tu, NULL, f->all, &f->all_count);
        for (int s = 0; s < scene_count; s++)
            add_curve(f, tu, scenes[s].name, f->scene[s], &f->scene_count[s]);
        if (!f->source) {
            f->source = util_printf("shadowbench tune at %dx%d, a %d^2 shadow map, on %s (%s, %s)", tu->width,
                                    tu->height, tu->shadow_map_size, tu->gl_renderer, o->tuned_dir, tu->date);
            f->objective = xstrdup(tu->objective);
        }
    }
}

static void frontiers_free(struct frontiers *f, int scene_count)
{
    for (int i = 0; i < f->array_count; i++)
        free(f->arrays[i]);
    free(f->arrays), free(f->all), free(f->source), free(f->objective);
    for (int s = 0; s < scene_count; s++)
        free(f->scene[s]);
}

int run_main(const struct run_options *o)
{
    double start = util_now_ms();

    static struct scene scenes[RUN_MAX_SCENES];
    int scene_count = 0, status = EXIT_CHECK_FAILED;
    struct cell *cells = NULL;
    int cell_count = 0;
    struct run_programs programs = {0};
    struct frontiers frontiers = {0};
    struct report_scene rs[RUN_MAX_SCENES] = {0};

    if (run_load_scenes(o, scenes, &scene_count) != 0 || run_claim_out_dir(o->out_dir) != 0 ||
        begin_run(o) != 0) {
        status = EXIT_USAGE;
        goto out_free_scenes;
    }
    for (int s = 0; s < scene_count; s++) {
        struct light_frustum f;
        if (light_frustum_fit(&scenes[s], &f) != 0) {
            status = EXIT_USAGE;
            goto out_free_scenes;
        }
    }
    if (shader_init(o->shader_dir) != 0) {  /* a bad --shaders is bad usage */
        status = EXIT_USAGE;
        goto out_free_scenes;
    }
    if (gl_context_create(o->gl) != 0) {  /* no such context here: bad usage (exit 2), as a bad --shaders */
        status = EXIT_USAGE;
        goto out_free_scenes;
    }
    for (int s = 0; s < scene_count; s++)  /* every program first: a compile error fails at once */
        for (int i = 0; i < o->config_count; i++)
            if (!run_program_get(&programs, o->configs[i].technique, run_config_settings(&o->configs[i], &scenes[s]),
                             scenes[s].light.shape))
                goto out_free_gl;

    int cells_total = scene_count * o->config_count, cells_done = 0, label_width = 0;
    for (int i = 0; i < o->config_count; i++)
        if ((int)strlen(o->configs[i].label) > label_width)
            label_width = (int)strlen(o->configs[i].label);
    if (o->untuned.data)
        log_info("no tuned settings in %s for %s: their default cells only (shadowbench tune --write-tuned "
                 "writes them)", o->tuned_dir, o->untuned.data);
    log_info("run: %d scene(s) x %d technique configuration(s), %dx%d, %d GT samples, %d^2 shadow "
             "map, median of %d frames after %d warm-up, cells interleaved, on %s (%s, %s), timed by %s", scene_count,
             o->config_count, o->width, o->height, o->gt_samples, o->shadow_map_size, o->frames, o->warmup,
             gl_context_renderer(), gl_context_vendor(), gl_context_platform(), stage_timing_text(o->timing));
    cells = xcalloc((size_t)cells_total, sizeof *cells);
    frontiers_build(&frontiers, o, scenes, scene_count);
    int failed = 0;
    for (int s = 0; s < scene_count; s++) {
        struct scene_run sr = {.o = o, .cells_done = &cells_done, .cells_total = cells_total,
                               .label_width = label_width};
        failed |= run_scene(&sr, &scenes[s], &programs, cells, &cell_count);
        rs[s] = (struct report_scene){scenes[s].name, scenes[s].description, scenes[s].shows,
                                      sr.ss.gt.seconds, sr.ss.gt.msamples_per_second, sr.ss.gt.cached,
                                      frontiers.scene[s], frontiers.scene_count[s]};
        scene_run_free(&sr);
        if (failed)
            break;
    }
    if (!failed) {
        double seconds = (util_now_ms() - start) * 1e-3;
        cJSON *run = run_json(o, seconds);
        cJSON_AddTrueToObject(run, "complete");
        struct report rep = {.out_dir = o->out_dir, .width = o->width, .height = o->height,
                             .run = run, .scenes = rs,
                             .scene_count = scene_count, .cells = cells, .cell_count = cell_count,
                             .frontier = frontiers.all, .frontier_count = frontiers.all_count,
                             .frontier_source = frontiers.source, .frontier_objective = frontiers.objective};
        failed = report_write(&rep);
        cJSON_Delete(rep.run);
    }
    if (!failed) {
        long bad = 0, unscored = 0;
        for (int i = 0; i < cell_count; i++) {
            bad += cells[i].m.nonfinite > 0;
            unscored += !metrics_scored(&cells[i].m);
        }
        status = bad || unscored ? EXIT_CHECK_FAILED : EXIT_OK;
        if (bad)
            log_error("%ld cell(s) produced NaN or Inf visibility", bad);
        for (int i = 0; i < cell_count; i++)
            if (!metrics_scored(&cells[i].m))
                log_error("%s/%s: unscored: no pixel where the camera sees a surface that the "
                          "light's frustum holds, that sees the light above its horizon and that "
                          "GL and the ray tracer agree on; its metrics are null", cells[i].scene,
                          cells[i].label);
        printf("report: %s/report.html\nmatrix: %s/matrix.csv\n", o->out_dir, o->out_dir);
        log_info("run finished in %.1f s", (util_now_ms() - start) * 1e-3);
    }

    for (int i = 0; i < cell_count; i++) {
        cJSON_Delete(cells[i].params);
        free(cells[i].params_text);
    }
    free(cells);
    frontiers_free(&frontiers, scene_count);
out_free_gl:
    run_programs_free(&programs);
    gl_context_destroy();
out_free_scenes:
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}

int run_gt(const struct run_options *o)
{
    struct scene s;
    char *path = catalog_resolve(o->scenes[0]);
    if (!path)
        return EXIT_USAGE;
    int rc = scene_load(path, &s);
    free(path);
    struct light_frustum f;
    if (rc != 0 || check_scene_name(&s) != 0 || light_frustum_fit(&s, &f) != 0) {
        scene_free(&s);
        return EXIT_USAGE;
    }
    char *dir = util_printf("%s/%s", o->out_dir, s.name);
    if (run_claim_out_dir(dir) != 0) {
        free(dir);
        scene_free(&s);
        return EXIT_USAGE;
    }
    struct gt_image gt;
    int status = EXIT_CHECK_FAILED;
    if (gt_obtain(&s, &f, &(struct gt_desc){.width = o->width, .height = o->height, .samples = o->gt_samples},
                  o->cache_dir, &gt) == 0) {
        /* No GL pass here: the mask lacks run's silhouette check (DESIGN.md §6). */
        const size_t count = (size_t)o->width * (size_t)o->height;
        size_t scored = 0;
        for (size_t i = 0; i < count; i++)
            scored += gt.mask[i] > 0;
        if (!scored)  /* as run says of an unscored cell; a noise floor of nothing is no number */
            log_error("%s: no pixel to score: the camera sees no surface inside the light's frustum that sees "
                      "the light above its horizon", s.path);
        else if (output_groundtruth(dir, &gt, gt.mask) == 0) {
            double noise = gt_noise_floor(gt.noise, gt.mask, count);
            printf("%s/groundtruth.exr\nnoise floor (rms error of V at %d samples): %.5f\n", dir,
                   o->gt_samples, noise);
            status = EXIT_OK;
        }
        gt_image_free(&gt);
    }
    free(dir);
    scene_free(&s);
    return status;
}
