/* The harness loop. Per scene: the ground truth (cached), the shadow-map
 * products the selected techniques need (rendered once, timed), then one
 * receiver pass per technique, scored and written out (DESIGN.md §2, §8). */
#include "run.h"
#include "catalog.h"
#include "gl/gl_context.h"
#include "truth/groundtruth.h"
#include "base/image.h"
#include "base/log.h"
#include "score/metrics.h"
#include "techniques/params.h"
#include "output/picture.h"
#include "render/receiver.h"
#include "output/report.h"
#include "gl/scene_mesh.h"
#include "gl/shader.h"
#include "render/stage_timer.h"
#include "base/util.h"

#include <OpenEXR/openexr.h>
#include <embree3/rtcore.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static void fill_defaults(struct run_options *o)
{
    if (!o->width) o->width = 512;
    if (!o->height) o->height = 512;
    if (!o->gt_samples) o->gt_samples = 1024;
    if (!o->shadow_map_size) o->shadow_map_size = SHADOWMAP_DEFAULT_SIZE;
    if (!o->frames) o->frames = 5;
    if (!o->out_dir) o->out_dir = "results/runs/latest";
}

void *run_settings(const struct run_options *o, const struct technique *t)
{
    int i = 0;
    while (technique_list[i] != t)
        i++;
    return o->settings[i];
}

/* Loads every scene named on the command line (or every shipped one) before
 * any heavy work, so bad input fails fast with status 2. */
static int load_scenes(const struct run_options *o, struct scene *scenes, int *count)
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

static int prepare_out_dir(const char *dir)
{
    if (util_mkdirs(dir) != 0)
        return -1;
    if (!util_dir_writable(dir)) {
        log_error("%s: output folder is not writable", dir);
        return -1;
    }
    return 0;
}

static int write_pictures(const char *dir, const char *name, const float *v, const float *distance,
                          const float *scored, int w, int h)
{
    struct picture p;
    picture_visibility(v, distance, scored, w, h, &p);
    char *path = util_printf("%s/%s.png", dir, name);
    int rc = image_write_png(path, p.width, p.height, 3, p.rgb);
    free(path);
    picture_free(&p);
    return rc;
}

/* Everything of one scene that the cells share. */
struct scene_run {
    const struct run_options *o;
    const struct scene *scene;
    struct gt_image gt;
    struct scene_mesh mesh;
    struct shadowmap sm;
    struct receiver receiver;
    struct stage_timer timer;
    float *v, *distance, *scored, *error;
    char *dir;
    int *cells_done, cells_total, label_width;  /* progress */
};

static int run_cell(struct scene_run *sr, const struct run_config *config, GLuint program,
                    struct cell *c)
{
    const struct run_options *o = sr->o;
    const struct technique *t = config->technique;
    const void *settings = config->settings;
    const int w = o->width, h = o->height, count = w * h;
    struct shadowmap_request req;
    technique_request(t, settings, &sr->sm.frustum, sr->sm.desc.size_texels, &req);
    if (shadowmap_prepare(&sr->sm, &req) != 0)
        return -1;
    c->m.ms_shadowmap = stage_timer_products_ms(&sr->timer, &req, SM_DEPTH);
    c->m.ms_filter_prep = stage_timer_products_ms(&sr->timer, &req, SM_MOMENTS | SM_MOMENTS_SAT);
    shadowmap_require(&sr->sm, &sr->mesh, &req);
    c->m.ms_receiver = stage_timer_receiver_ms(&sr->timer, &sr->receiver, program);
    c->m.ms_total = c->m.ms_shadowmap + c->m.ms_filter_prep + c->m.ms_receiver;
    receiver_read(&sr->receiver, sr->v, sr->distance);

    c->m.mismatch_pixels = metrics_score_mask(sr->gt.mask, sr->gt.distance, sr->distance, count,
                                              sr->scored);
    metrics_compute(sr->v, sr->gt.v, sr->gt.v_alt, sr->scored, sr->distance, w, h, &c->m);

    c->scene = sr->scene->name;
    c->technique = t;
    c->label = config->label;
    c->gl_renderer = gl_context_renderer();
    c->params = params_json(t, settings);
    struct strbuf text = {0};
    params_summary(t, settings, &text);
    c->params_text = text.data ? text.data : xstrdup("");

    for (int i = 0; i < count; i++)
        sr->error[i] = sr->scored[i] > 0.5f ? sr->v[i] - sr->gt.v[i] : 0.0f;
    char *dir = util_printf("%s/%s", sr->dir, config->label);
    char *vis_exr = util_printf("%s/visibility.exr", dir), *err_exr = util_printf("%s/error.exr", dir);
    char *heat = util_printf("%s/heatmap.png", dir), *json = util_printf("%s/metrics.json", dir);
    struct picture hm;
    picture_error_heatmap(sr->v, sr->gt.v, sr->scored, w, h, &hm);
    cJSON *mj = report_cell_json(c);
    int rc = util_mkdirs(dir) ||
             image_write_exr(vis_exr, w, h, &(struct exr_channel){"V", sr->v}, 1) ||
             image_write_exr(err_exr, w, h, &(struct exr_channel){"E", sr->error}, 1) ||
             write_pictures(dir, "visibility", sr->v, sr->distance, NULL, w, h) ||
             image_write_png(heat, hm.width, hm.height, 3, hm.rgb) || report_write_json(json, mj);
    cJSON_Delete(mj);
    picture_free(&hm);
    free(vis_exr), free(err_exr), free(heat), free(json), free(dir);

    log_info("  [%d/%d] %-*s rmse %.4f  penumbra_rmse %.4f  leak %.4f  dark %.4f  %7.2f ms%s",
             ++*sr->cells_done, sr->cells_total, sr->label_width, config->label, c->m.rmse,
             c->m.penumbra_rmse, c->m.leak_fraction, c->m.dark_fraction, c->m.ms_total,
             c->m.nonfinite ? "  NON-FINITE VALUES" : "");
    return rc ? -1 : 0;
}

static int run_scene(struct scene_run *sr, GLuint (*programs)[2], struct cell *cells, int *cell_count)
{
    const struct run_options *o = sr->o;
    const int w = o->width, h = o->height, count = w * h;
    log_info("scene %s: %zu triangles", sr->scene->name, sr->scene->triangle_count);
    sr->dir = util_printf("%s/%s", o->out_dir, sr->scene->name);
    if (util_mkdirs(sr->dir) != 0)
        return -1;

    scene_mesh_upload(sr->scene, &sr->mesh);
    if (shadowmap_create(&sr->sm, sr->scene, &(struct shadowmap_desc){.size_texels = o->shadow_map_size}) ||
        receiver_create(&sr->receiver, sr->scene, w, h))
        return -1;
    sr->timer = (struct stage_timer){.sm = &sr->sm, .mesh = &sr->mesh, .warmup = o->warmup,
                                     .frames = o->frames};
    if (gt_obtain(sr->scene, &sr->sm.frustum,
                  &(struct gt_desc){.width = w, .height = h, .samples = o->gt_samples},
                  o->cache_dir, &sr->gt) != 0)
        return -1;

    sr->v = xmalloc(sizeof(float) * (size_t)count);
    sr->distance = xmalloc(sizeof(float) * (size_t)count);
    sr->scored = xmalloc(sizeof(float) * (size_t)count);
    sr->error = xmalloc(sizeof(float) * (size_t)count);
    for (int i = 0; i < o->config_count; i++)
        if (run_cell(sr, &o->configs[i], programs[i][sr->scene->light.shape],
                     &cells[(*cell_count)++]) != 0)
            return -1;

    /* The scored mask is the same for every cell of the scene (same camera,
     * same geometry): groundtruth.exr carries the last cell's. */
    char *gt_path = util_printf("%s/groundtruth.exr", sr->dir);
    struct exr_channel ch[] = {{"V", sr->gt.v}, {"V_weighted", sr->gt.v_weighted}, {"mask", sr->scored}};
    int rc = image_write_exr(gt_path, w, h, ch, 3) ||
             write_pictures(sr->dir, "groundtruth", sr->gt.v, sr->gt.distance, sr->scored, w, h);
    free(gt_path);
    return rc ? -1 : 0;
}

static void scene_run_free(struct scene_run *sr)
{
    gt_image_free(&sr->gt);
    receiver_destroy(&sr->receiver);
    shadowmap_destroy(&sr->sm);
    scene_mesh_destroy(&sr->mesh);
    free(sr->v), free(sr->distance), free(sr->scored), free(sr->error), free(sr->dir);
    memset(sr, 0, sizeof *sr);
}

static char *git_describe(void)
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

static cJSON *run_json(const struct run_options *o, double seconds)
{
    cJSON *r = cJSON_CreateObject();
    struct strbuf cmd = {0};
    for (int i = 0; i < o->argc; i++)
        strbuf_printf(&cmd, "%s%s", i ? " " : "", o->argv[i]);
    cJSON_AddStringToObject(r, "command_line", cmd.data ? cmd.data : "");
    strbuf_free(&cmd);
    char *git = git_describe(), *cpu = cpu_model();
    cJSON_AddStringToObject(r, "shadowbench_version", SB_VERSION);
    cJSON_AddStringToObject(r, "git_describe", git);
    cJSON_AddStringToObject(r, "gl_renderer", gl_context_renderer());
    cJSON_AddStringToObject(r, "gl_version", gl_context_version());
    cJSON_AddStringToObject(r, "embree_version", RTC_VERSION_STRING);
    cJSON_AddStringToObject(r, "openexr_version", OPENEXR_VERSION_STRING);
    cJSON_AddStringToObject(r, "cpu", cpu);
    cJSON_AddNumberToObject(r, "cpu_threads", (double)sysconf(_SC_NPROCESSORS_ONLN));
    char date[64];
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", gmtime(&now));
    cJSON_AddStringToObject(r, "date", date);
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

int run_main(const struct run_options *given)
{
    double start = util_now_ms();
    struct run_options o = *given;
    fill_defaults(&o);

    static struct scene scenes[RUN_MAX_SCENES];
    int scene_count = 0, status = EXIT_CHECK_FAILED;
    struct cell *cells = NULL;
    int cell_count = 0;
    GLuint (*programs)[2] = xcalloc((size_t)o.config_count, sizeof *programs);  /* by light shape */
    struct report_scene rs[RUN_MAX_SCENES] = {0};

    if (load_scenes(&o, scenes, &scene_count) != 0 || prepare_out_dir(o.out_dir) != 0) {
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
    if (gl_context_create() != 0 || shader_init(o.shader_dir) != 0)
        goto out_free_scenes;
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < o.config_count; i++) {
            enum light_shape shape = scenes[s].light.shape;
            if (!programs[i][shape] &&
                !(programs[i][shape] =
                      receiver_program(o.configs[i].technique, o.configs[i].settings, shape)))
                goto out_free_gl;
        }

    int cells_total = scene_count * o.config_count, cells_done = 0, label_width = 0;
    for (int i = 0; i < o.config_count; i++)
        if ((int)strlen(o.configs[i].label) > label_width)
            label_width = (int)strlen(o.configs[i].label);
    log_info("run: %d scene(s) x %d technique configuration(s), %dx%d, %d GT samples, %d^2 shadow "
             "map, median of %d frames after %d warm-up on %s", scene_count, o.config_count, o.width,
             o.height, o.gt_samples, o.shadow_map_size, o.frames, o.warmup, gl_context_renderer());
    cells = xcalloc((size_t)cells_total, sizeof *cells);
    int failed = 0;
    for (int s = 0; s < scene_count; s++) {
        struct scene_run sr = {.o = &o, .scene = &scenes[s], .cells_done = &cells_done,
                               .cells_total = cells_total, .label_width = label_width};
        failed |= run_scene(&sr, programs, cells, &cell_count);
        rs[s] = (struct report_scene){scenes[s].name, scenes[s].description, scenes[s].shows,
                                      sr.gt.seconds, sr.gt.mrays_per_second, sr.gt.cached};
        scene_run_free(&sr);
        if (failed)
            break;
    }
    if (!failed) {
        double seconds = (util_now_ms() - start) * 1e-3;
        struct report rep = {.out_dir = o.out_dir, .width = o.width, .height = o.height,
                             .run = run_json(&o, seconds), .scenes = rs,
                             .scene_count = scene_count, .cells = cells, .cell_count = cell_count};
        failed = report_write(&rep);
        cJSON_Delete(rep.run);
    }
    if (!failed) {
        long bad = 0;
        for (int i = 0; i < cell_count; i++)
            bad += cells[i].m.nonfinite > 0;
        status = bad ? EXIT_CHECK_FAILED : EXIT_OK;
        if (bad)
            log_error("%ld cell(s) produced NaN or Inf visibility", bad);
        printf("report: %s/report.html\nmatrix: %s/matrix.csv\n", o.out_dir, o.out_dir);
        log_info("run finished in %.1f s", (util_now_ms() - start) * 1e-3);
    }

    for (int i = 0; i < cell_count; i++) {
        cJSON_Delete(cells[i].params);
        free(cells[i].params_text);
    }
    free(cells);
out_free_gl:
    for (int i = 0; i < o.config_count; i++)
        for (int k = 0; k < 2; k++)
            if (programs[i][k])
                glDeleteProgram(programs[i][k]);
    gl_context_destroy();
out_free_scenes:
    free(programs);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}

int run_gt(const struct run_options *given)
{
    struct run_options o = *given;
    fill_defaults(&o);
    struct scene s;
    char *path = catalog_resolve(o.scenes[0]);
    if (!path)
        return EXIT_USAGE;
    int rc = scene_load(path, &s);
    free(path);
    struct light_frustum f;
    if (rc != 0 || light_frustum_fit(&s, &f) != 0) {
        scene_free(&s);
        return EXIT_USAGE;
    }
    char *dir = util_printf("%s/%s", o.out_dir, s.name);
    if (prepare_out_dir(dir) != 0) {
        free(dir);
        scene_free(&s);
        return EXIT_USAGE;
    }
    struct gt_image gt;
    int status = EXIT_CHECK_FAILED;
    if (gt_obtain(&s, &f, &(struct gt_desc){.width = o.width, .height = o.height, .samples = o.gt_samples},
                  o.cache_dir, &gt) == 0) {
        /* No GL pass here: the mask lacks run's silhouette check (DESIGN.md §6). */
        char *out = util_printf("%s/groundtruth.exr", dir);
        struct exr_channel ch[] = {{"V", gt.v}, {"V_weighted", gt.v_weighted}, {"mask", gt.mask}};
        if (image_write_exr(out, o.width, o.height, ch, 3) == 0 &&
            write_pictures(dir, "groundtruth", gt.v, gt.distance, gt.mask, o.width, o.height) == 0) {
            double noise = gt_rms_difference(gt.v, gt.v_alt, gt.mask, o.width * o.height) / sqrt(2.0);
            printf("%s\nnoise floor (rms error of V at %d samples): %.5f\n", out, o.gt_samples, noise);
            status = EXIT_OK;
        }
        free(out);
        gt_image_free(&gt);
    }
    free(dir);
    scene_free(&s);
    return status;
}
