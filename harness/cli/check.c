/* The regression check (check.h; README, Regression check).
 *
 * Cells: every selected technique at its defaults on every selected scene,
 * the cells of the table below (each parameter away from its default at
 * least once), and any other baseline file found. A cell is named as run
 * names it, "<technique>[@<param>=<value>,...]", which is also its file's
 * stem under <baselines>/<scene>/.
 *
 * A baseline records the settings it was rendered at, its metrics, a
 * tolerance per metric and why, and its V_tech as a 16-bit PNG. Checking
 * renders the cell at the recorded settings and compares: a metric worse
 * than its tolerance, or a picture that moved with no metric better, is a
 * regression; a metric better than its tolerance, with none worse, an
 * improvement. Tolerances, measured: twice the sum of the metric's spread
 * when the ground truth is rendered with CHECK_SEEDS seeds (a metric that
 * moves less than the truth's own noise has not measurably moved) and the
 * most it moved when llvmpipe was built for another CPU. V_tech itself
 * does not depend on the truth: the picture budget is twice the most that
 * moved on another CPU.
 *
 * Coverage (FFmpeg's FATE): a technique x scene without a baseline fails;
 * with every scene selected, a parameter that no table cell sets fails; and
 * for each table cell, setting each of its parameters back to the default
 * must change the picture (else the parameter is ignored). */
#include "check.h"
#include "tuned.h"
#include "base/image.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "output/picture.h"
#include "techniques/params.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/* The share of the image's pixels that may move: twice the most that moved
 * (0.075 %, on stanford_bunny's savsm) when llvmpipe ran without AVX and FMA
 * (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1), as on another CPU; none moved across
 * LP_NUM_THREADS 1/2/4, LP_NATIVE_VECTOR_WIDTH 128/256 or AVX without AVX2
 * (tools/check-variation, 2026-11-23). */
#define CHECK_PIXEL_FRACTION 0.0015

/* The metrics a baseline guards, each better lower (bias: its size), with
 * the most each moved over the 94 cells under those variations (the same
 * measurement: all of it from the run without AVX and FMA). */
static const struct {
    int metric;
    double device;
} guarded[] = {
    {METRIC_rmse, 3.9e-6}, {METRIC_mae, 2.7e-6}, {METRIC_bias, 4.2e-6}, {METRIC_p99_abs, 1.02e-4},
    {METRIC_penumbra_rmse, 6.2e-6}, {METRIC_leak_fraction, 2.2e-5}, {METRIC_dark_fraction, 4.4e-5},
    {METRIC_shaded_rmse, 1.02e-5}, {METRIC_nonfinite, 0.0},
};
#define GUARDED_COUNT ((int)(sizeof guarded / sizeof *guarded))

/* Cells beyond the defaults: every parameter of every technique away from
 * its default at least once (checked), on a scene where it acts. The
 * disk-light cases of the PCSS family are the defaults on
 * parallel_planes_disk. */
static const struct {
    const char *scene, *cell;
} table[] = {
    {"grazing_receiver", "hard@constant_bias=0.005"},
    {"grazing_receiver", "hard@slope_bias=4"},
    {"parallel_planes", "pcf@radius_texels=8"},
    {"parallel_planes", "pcf@pattern=grid,samples=25"},
    {"parallel_planes", "pcf@samples=64"},
    {"parallel_planes", "pcf@hardware_2x2=true"},
    {"grazing_receiver", "pcf@receiver_plane_bias=false"},
    {"grazing_receiver", "pcf@receiver_plane_bias=false,slope_bias=4"},
    {"grazing_receiver", "pcf@constant_bias=0.005"},
    {"contact_hardening", "pcss@blocker_samples=16,filter_samples=64"},
    {"parallel_planes", "pcss@light_size_scale=0.5"},
    {"grazing_receiver", "pcss@receiver_plane_bias=false"},
    {"grazing_receiver", "pcss@receiver_plane_bias=false,slope_bias=4"},
    {"grazing_receiver", "pcss@constant_bias=0.005"},
    {"parallel_planes", "vsm@blur_radius_texels=8"},
    {"parallel_planes", "vsm@min_variance=0.001"},
    {"overlapping_occluders", "vsm@bleed_reduction=0.3"},
    {"parallel_planes", "savsm@box_width_texels=15"},
    {"floating_box_sphere", "savsm@sat_format=fp32"},
    {"floating_box_sphere", "savsm@sat_format=fp32_centered"},
    {"parallel_planes", "savsm@min_variance=0.001"},
    {"overlapping_occluders", "savsm@bleed_reduction=0.3"},
    {"floating_box_sphere", "pcss_savsm@sat_format=fp32"},
    {"floating_box_sphere", "pcss_savsm@sat_format=fp32_centered"},
    {"parallel_planes", "pcss_savsm@light_size_scale=0.5"},
    {"parallel_planes", "pcss_savsm@min_variance=0.001"},
    {"contact_hardening", "pcss_savsm@min_blocker_fraction=0.05"},
    {"overlapping_occluders", "pcss_savsm@bleed_reduction=0.3"},
    {"overlapping_occluders", "evsm@variant=evsm2,positive_exponent=20"},
    {"contact_hardening", "evsm@negative_exponent=20,blur_radius_texels=8"},
    {"grazing_receiver", "evsm@min_variance=1e-06"},
    {"overlapping_occluders", "evsm@bleed_reduction=0.3"},
    {"overlapping_occluders", "msm@moment_bias=0.003,blur_radius_texels=8"},
    {"grazing_receiver", "msm@depth_bias=0.001"},
    {"stanford_bunny", "msm@bound=hausdorff"},
    {"floating_box_sphere", "msm_soft@sat_format=fp32"},
    {"parallel_planes", "msm_soft@light_size_scale=0.5"},
    {"overlapping_occluders", "msm_soft@moment_bias=0.003"},
    {"grazing_receiver", "msm_soft@depth_bias=0.001"},
    {"contact_hardening", "msm_soft@min_blocker_fraction=0.05"},
    {"floating_box_sphere", "vssm@sat_format=fp32_centered"},
    {"parallel_planes", "vssm@light_size_scale=0.5"},
    {"grazing_receiver", "vssm@min_variance=0.001"},
    {"contact_hardening", "vssm@min_blocker_fraction=0.05"},
    {"overlapping_occluders", "vssm@bleed_reduction=0.3"},
    {"overlapping_occluders", "vssm@subdivisions=4"},
    {"overlapping_occluders", "vssm@adaptive=true,subdivisions=4"},
    {"curved_receivers", "vssm@receiver_plane=false"},
};
#define TABLE_COUNT ((int)(sizeof table / sizeof *table))

enum status { PASS, REGRESSED, IMPROVED, NO_BASELINE };
static const char *const status_names[] = {"pass", "REGRESSED", "improved", "no baseline"};

struct cell {
    const struct scene *scene;
    char *label;                 /* the cell's name and file stem */
    const struct technique *t;
    void *settings;              /* rendered: the baseline's, or (update, none) the label's */
    void *label_settings;        /* what the label means today */
    bool from_table;
    struct scene_setup_desc desc;
    char *json_path, *png_path;
    cJSON *baseline;             /* NULL: none */
    uint16_t *picture;           /* the baseline's V_tech */
    double pixel_threshold, max_moved;  /* its picture budget */
    /* results */
    struct metrics now;
    float *v;                    /* V_tech now */
    double moved_fraction;       /* of the pixels, against the baseline's picture */
    bool compared;               /* moved_fraction and status are against the baseline */
    double spread[GUARDED_COUNT];  /* update: over the ground-truth seeds */
    enum status status;
};

static void cell_free(struct cell *c)
{
    free(c->label), free(c->settings), free(c->label_settings);
    free(c->json_path), free(c->png_path), free(c->picture), free(c->v);
    cJSON_Delete(c->baseline);
}

/* "pcf@radius_texels=8,pattern=grid" -> technique and settings (defaults
 * plus the values); "pcf@tuned" -> pcf's tuned settings for scene s (from
 * tuned_dir). Returns 0 or -1 (logged). */
static int parse_label(const char *label, const struct scene *s, const char *tuned_dir,
                       const struct technique **t, void **settings)
{
    for (const char *p = label; *p; p++)
        if ((unsigned char)*p < 32 || *p == '/' || *p == 127) {
            log_error("not a cell name: it holds a control character or '/'");
            return -1;
        }
    const char *at = strchr(label, '@');
    char name[64];
    snprintf(name, sizeof name, "%.*s", at ? (int)(at - label) : (int)strlen(label), label);
    if (!(*t = technique_find(name))) {
        log_error("cell '%s': unknown technique '%s'", label, name);
        return -1;
    }
    if (at && strcmp(at, TUNED_SUFFIX) == 0) {
        struct tuned tu;
        const int rc = tuned_load(tuned_dir, *t, &tu);
        if (rc > 0)
            log_error("cell '%s': %s/%s.json does not exist", label, tuned_dir, (*t)->name);
        if (rc)
            return -1;
        *settings = memcpy(xmalloc((*t)->settings_size), tuned_settings(&tu, s->name), (*t)->settings_size);
        tuned_free(&tu);
        return 0;
    }
    *settings = params_defaults(*t);
    char *list = xstrdup(at ? at + 1 : ""), *rest = list, *names[64];
    int rc = 0, given = 0;
    for (char *item = strsep(&rest, ","); at && item && !rc; item = strsep(&rest, ",")) {
        char *eq = strchr(item, '=');
        if (!eq) {
            log_error("cell '%s': '%s' is not parameter=value", label, item);
            rc = -1;
            break;
        }
        *eq = '\0';
        /* Each parameter once: "p=1,p=2" would be two cells in one name. */
        for (int i = 0; i < given && !rc; i++)
            if (strcmp(names[i], item) == 0) {
                log_error("cell '%s': %s is given twice", label, item);
                rc = -1;
            }
        if (given < (int)(sizeof names / sizeof *names))
            names[given++] = item;
        if (!rc)
            rc = params_set(*t, *settings, item, eq + 1);
    }
    free(list);
    if (!rc)
        rc = params_check(*t, *settings);
    if (rc) {
        free(*settings);
        *settings = NULL;
    }
    return rc;
}

/* ---- baseline files ---- */

static double json_number(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* A metric's value as the file holds it (null: unscored). */
static double baseline_metric(const struct cell *c, int k)
{
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(c->baseline, "metrics");
    return json_number(m, metric_info[k].key);
}

static double baseline_tolerance(const struct cell *c, int k)
{
    const cJSON *tol = cJSON_GetObjectItemCaseSensitive(c->baseline, "tolerances");
    return json_number(cJSON_GetObjectItemCaseSensitive(tol, metric_info[k].key), "value");
}

/* The fingerprint of a picture, recorded beside it: a JSON and a PNG from
 * different recordings (an interrupted --update, a file copied over) are
 * refused. */
static char *picture_hash(const uint16_t *pixels, size_t count)
{
    return util_printf("%016llx", (unsigned long long)util_hash(UTIL_HASH_INIT, pixels, count * sizeof *pixels));
}

/* A number in [lo, hi] at key of o, or NAN. */
static double json_in_range(const cJSON *o, const char *key, double lo, double hi)
{
    const double v = json_number(o, key);
    return v >= lo && v <= hi ? v : NAN;
}

/* What is wrong with baseline b of cell c, or NULL; fills c->desc and the
 * picture budget. buf holds a composed message. */
static const char *baseline_problem(struct cell *c, const cJSON *b, char *buf, size_t size)
{
    const cJSON *settings = cJSON_GetObjectItemCaseSensitive(b, "settings");
    const cJSON *metrics = cJSON_GetObjectItemCaseSensitive(b, "metrics");
    const cJSON *tolerances = cJSON_GetObjectItemCaseSensitive(b, "tolerances");
    const cJSON *picture = cJSON_GetObjectItemCaseSensitive(b, "picture");
    const char *cell = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(b, "cell"));
    const char *scene = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(b, "scene"));
    const char *technique = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(b, "technique"));
    if (!cell || strcmp(cell, c->label) != 0)
        return "its \"cell\" is not its file name";
    if (!scene || strcmp(scene, c->scene->name) != 0)
        return "its \"scene\" is not its folder's";
    if (!technique || strcmp(technique, c->t->name) != 0)
        return "its \"technique\" is not its cell's";
    if (!cJSON_IsObject(settings) || !cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(settings, "params")) ||
        !cJSON_IsObject(metrics) || !cJSON_IsObject(tolerances) || !cJSON_IsObject(picture))
        return "lacks \"settings\" (with \"params\"), \"metrics\", \"tolerances\" or \"picture\"";
    const double version = json_number(b, "gt_version");
    if (version != GT_VERSION) {
        snprintf(buf, size, "recorded with ground-truth version %g, this build renders version %d (record "
                 "it anew: shadowbench check --update)", version, GT_VERSION);
        return buf;
    }
    const double w = json_in_range(settings, "width", RUN_MIN_SIZE, RUN_MAX_SIZE);
    const double h = json_in_range(settings, "height", RUN_MIN_SIZE, RUN_MAX_SIZE);
    const double n = json_in_range(settings, "gt_samples", 1, GT_MAX_SAMPLES);
    const double seed = json_in_range(settings, "gt_seed", 1, UINT32_MAX);
    const double map = json_in_range(settings, "shadow_map_size", SHADOWMAP_MIN_SIZE, SHADOWMAP_MAX_SIZE);
    const double root = round(sqrt(n));
    if (!(w == floor(w) && h == floor(h) && root * root == n && seed == floor(seed) && map == floor(map)))
        return "its settings (width, height, gt_samples, gt_seed, shadow_map_size) are missing or out of range";
    c->desc.width = (int)w, c->desc.height = (int)h, c->desc.gt_samples = (int)n;
    c->desc.gt_seed = (uint32_t)seed, c->desc.shadow_map_size = (int)map;
    for (int g = 0; g < GUARDED_COUNT; g++) {
        const char *key = metric_info[guarded[g].metric].key;
        const cJSON *m = cJSON_GetObjectItemCaseSensitive(metrics, key);
        const double tol = json_in_range(cJSON_GetObjectItemCaseSensitive(tolerances, key), "value", 0, 1);
        /* A scored cell's value: an error or a share in [0, 1] (bias in
         * [-1, 1], shaded_rmse from 0), a count whole from 0. Never null:
         * an unscored cell is not a baseline, and a null would make any
         * value "better". */
        const int k = guarded[g].metric;
        const double v = cJSON_IsNumber(m) ? m->valuedouble : NAN,
                     lo = k == METRIC_bias ? -1 : 0,
                     hi = k == METRIC_nonfinite || k == METRIC_shaded_rmse ? INFINITY : 1;
        if (!(v >= lo && v <= hi) || (k == METRIC_nonfinite && v != floor(v)) || isnan(tol)) {
            snprintf(buf, size, "metric %s: needs a number in [%g, %g]%s and a tolerance in [0, 1]", key, lo, hi,
                     k == METRIC_nonfinite ? ", whole" : "");
            return buf;
        }
    }
    c->pixel_threshold = json_in_range(picture, "pixel_threshold", 0, 1);
    c->max_moved = json_in_range(picture, "max_moved_fraction", 0, 1);
    if (isnan(c->pixel_threshold) || isnan(c->max_moved) ||
        !cJSON_IsString(cJSON_GetObjectItemCaseSensitive(picture, "hash")))
        return "its \"picture\" needs pixel_threshold and max_moved_fraction in [0, 1] and a hash";
    return NULL;
}

/* Reads c's baseline if it has one. Returns 0, or -1 after one line naming
 * the file and the problem. */
static int read_baseline(struct cell *c)
{
    char *text;
    size_t size;
    int rc = util_read_file(c->json_path, &text, &size);
    if (rc == -ENOENT)
        return 0;
    if (rc) {
        log_error("%s: cannot read: %s", c->json_path, util_read_error(rc));
        return -1;
    }
    const char *end = NULL;
    c->baseline = cJSON_ParseWithLengthOpts(text, size, &end, false);
    while (c->baseline && end < text + size && strchr(" \t\r\n", *end))
        end++;
    char buf[256];
    const char *problem = NULL;
    if (!c->baseline || end != text + size) {
        snprintf(buf, sizeof buf, "not valid JSON (at byte %td)",
                 c->baseline ? end - text : cJSON_GetErrorPtr() ? cJSON_GetErrorPtr() - text : (ptrdiff_t)0);
        problem = buf;
    } else if (!cJSON_IsObject(c->baseline))
        problem = "not a JSON object";
    else if (util_json_duplicate_key(c->baseline)) {
        snprintf(buf, sizeof buf, "the key \"%.64s\" appears twice in one object",
                 util_json_duplicate_key(c->baseline));
        problem = buf;
    }
    else
        problem = baseline_problem(c, c->baseline, buf, sizeof buf);
    free(text);

    /* The parameters it was rendered with: every one, named once, in range;
     * a bad one is reported by params_from_json, prefixed with the file. */
    log_set_context(c->json_path);
    if (problem)
        log_error("%s", problem);
    void *settings = problem ? NULL
                             : params_from_json(c->t, cJSON_GetObjectItemCaseSensitive(
                                                          cJSON_GetObjectItemCaseSensitive(c->baseline, "settings"),
                                                          "params"));
    log_set_context(NULL);
    if (!settings)
        return -1;
    memcpy(c->settings, settings, c->t->settings_size);
    free(settings);

    rc = image_read_png16(c->png_path, c->desc.width, c->desc.height, &c->picture);
    if (rc == -ENOENT)
        log_error("%s: its picture %s is missing", c->json_path, c->png_path);
    if (rc)
        return -1;
    char *hash = picture_hash(c->picture, (size_t)c->desc.width * (size_t)c->desc.height);
    const char *recorded = cJSON_GetStringValue(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(c->baseline, "picture"), "hash"));
    rc = strcmp(hash, recorded) != 0;
    if (rc)
        log_error("%s: its picture is not the one it recorded (an interrupted --update? record it anew)",
                  c->json_path);
    free(hash);
    return rc ? -1 : 0;
}

static void quantize(const float *v, size_t count, uint16_t *out)
{
    for (size_t i = 0; i < count; i++) {
        float x = v[i] > 0.0f ? (v[i] < 1.0f ? v[i] : 1.0f) : 0.0f;  /* NaN -> 0 */
        out[i] = (uint16_t)lrintf(x * 65535.0f);
    }
}

/* Writes c's baseline from its results (JSON and PNG, each atomically). */
static int write_baseline(const struct cell *c, const char *git, const char *date)
{
    cJSON *b = cJSON_CreateObject();
    cJSON_AddStringToObject(b, "scene", c->scene->name);
    cJSON_AddStringToObject(b, "cell", c->label);
    cJSON_AddStringToObject(b, "technique", c->t->name);
    cJSON *s = cJSON_AddObjectToObject(b, "settings");
    cJSON_AddNumberToObject(s, "width", c->desc.width);
    cJSON_AddNumberToObject(s, "height", c->desc.height);
    cJSON_AddNumberToObject(s, "gt_samples", c->desc.gt_samples);
    cJSON_AddNumberToObject(s, "gt_seed", c->desc.gt_seed);
    cJSON_AddNumberToObject(s, "shadow_map_size", c->desc.shadow_map_size);
    cJSON *params = cJSON_AddObjectToObject(s, "params");
    for (const struct technique_param *p = c->t->params; p->name; p++) {
        char value[64];
        params_value_text(c->t, c->settings, p->name, value, sizeof value);
        cJSON_AddStringToObject(params, p->name, value);
    }
    cJSON *m = cJSON_AddObjectToObject(b, "metrics"), *tol = cJSON_AddObjectToObject(b, "tolerances");
    for (int g = 0; g < GUARDED_COUNT; g++) {
        const int k = guarded[g].metric;
        const double v = metrics_value(&c->now, k);
        cJSON_AddItemToObject(m, metric_info[k].key, isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull());
        cJSON *t = cJSON_AddObjectToObject(tol, metric_info[k].key);
        char why[256];
        if (k == METRIC_nonfinite) {
            cJSON_AddNumberToObject(t, "value", 0);
            snprintf(why, sizeof why, "a count: any NaN or Inf more is a regression");
        } else {
            cJSON_AddNumberToObject(t, "value", 2.0 * (c->spread[g] + guarded[g].device));
            snprintf(why, sizeof why, "2 x (its spread over ground-truth seeds %u..%u: %.2g, + the most "
                     "it moved on any cell with llvmpipe built for another CPU: %.2g)", c->desc.gt_seed,
                     c->desc.gt_seed + CHECK_SEEDS - 1, c->spread[g], guarded[g].device);
        }
        cJSON_AddStringToObject(t, "why", why);
    }
    const size_t count = (size_t)c->desc.width * (size_t)c->desc.height;
    uint16_t *pixels = xmalloc(count * sizeof *pixels);
    quantize(c->v, count, pixels);
    char *hash = picture_hash(pixels, count);
    cJSON *pic = cJSON_AddObjectToObject(b, "picture");
    cJSON_AddStringToObject(pic, "hash", hash);
    free(hash);
    cJSON_AddNumberToObject(pic, "pixel_threshold", CHECK_PIXEL_THRESHOLD);
    cJSON_AddNumberToObject(pic, "max_moved_fraction", CHECK_PIXEL_FRACTION);
    cJSON_AddStringToObject(pic, "why", "V_tech does not depend on the ground truth and is the same bit "
                            "for bit across LP_NUM_THREADS and LP_NATIVE_VECTOR_WIDTH; without AVX and "
                            "FMA at most 0.075 % of a cell's pixels moved: twice that");
    cJSON_AddNumberToObject(b, "gt_version", GT_VERSION);
    cJSON_AddStringToObject(b, "date", date);
    cJSON_AddStringToObject(b, "git_describe", git);
    char *command = util_printf("shadowbench check --update --scene %s --technique %s", c->scene->name,
                                c->t->name);
    cJSON_AddStringToObject(b, "command", command);
    free(command);

    char *text = cJSON_Print(b);
    cJSON_Delete(b);
    char *dir = util_printf("%s", c->json_path);
    *strrchr(dir, '/') = '\0';
    /* The picture first: a JSON is never newer than its picture, and the
     * hash tells an interrupted pair apart. */
    int rc = util_mkdirs(dir) || image_write_png16(c->png_path, c->desc.width, c->desc.height, pixels) ||
             util_write_file_atomic(c->json_path, text, strlen(text));
    free(pixels);
    free(dir);
    free(text);
    return rc ? -1 : 0;
}

/* ---- the cells ---- */

struct check {
    const struct run_options *o;
    struct cell *cells;
    int count, capacity;
    bool all_scenes;
};

static bool technique_selected(const struct run_options *o, const struct technique *t)
{
    for (int i = 0; i < o->technique_count; i++)
        if (o->techniques[i] == t)
            return true;
    return false;
}

static bool known_cell(const struct check *ch, const struct scene *s, const char *label)
{
    for (int i = 0; i < ch->count; i++)
        if (ch->cells[i].scene == s && strcmp(ch->cells[i].label, label) == 0)
            return true;
    return false;
}

/* Adds cell `label` of scene s (when its technique is selected and it is
 * not there yet). Returns 0 or -1 (logged). */
static int add_cell(struct check *ch, const struct scene *s, const char *label, bool from_table)
{
    const struct technique *t;
    void *settings;
    if (known_cell(ch, s, label))
        return 0;
    char name[64];  /* a technique not selected: its cells are not read (a tuned one needs its file) */
    snprintf(name, sizeof name, "%.*s", (int)strcspn(label, "@"), label);
    if ((t = technique_find(name)) && !technique_selected(ch->o, t))
        return 0;
    if (parse_label(label, s, ch->o->tuned_dir, &t, &settings) != 0)
        return -1;
    if (ch->count == ch->capacity) {
        ch->capacity = ch->capacity ? 2 * ch->capacity : 64;
        ch->cells = xrealloc(ch->cells, (size_t)ch->capacity * sizeof *ch->cells);
    }
    struct cell *c = &ch->cells[ch->count++];
    *c = (struct cell){.scene = s, .label = xstrdup(label), .t = t, .label_settings = settings,
                       .from_table = from_table};
    c->settings = memcpy(xmalloc(t->settings_size), settings, t->settings_size);
    c->desc = (struct scene_setup_desc){CHECK_SIZE, CHECK_SIZE, SHADOWMAP_DEFAULT_SIZE, CHECK_GT_SAMPLES,
                                        CHECK_GT_SEED, ch->o->cache_dir, 0};
    c->json_path = util_printf("%s/%s/%s.json", ch->o->baselines_dir, s->name, label);
    c->png_path = util_printf("%s/%s/%s.png", ch->o->baselines_dir, s->name, label);
    return 0;
}

/* The baseline files under <baselines>/<scene>/ (their stems), in name
 * order. */
static int add_files(struct check *ch, const struct scene *s)
{
    char *dir = util_printf("%s/%s", ch->o->baselines_dir, s->name);
    struct dirent **names = NULL;
    const int n = scandir(dir, &names, NULL, alphasort);
    int rc = 0;
    for (int i = 0; i < n; i++) {
        const size_t len = strlen(names[i]->d_name);
        if (!rc && len > 5 && strcmp(names[i]->d_name + len - 5, ".json") == 0) {
            char *path = util_printf("%s/%s", dir, names[i]->d_name);
            names[i]->d_name[len - 5] = '\0';
            log_set_context(path);
            rc = add_cell(ch, s, names[i]->d_name, false);
            log_set_context(NULL);
            free(path);
        }
        free(names[i]);
    }
    free(names);
    free(dir);
    return rc;
}

static int collect_cells(struct check *ch, const struct scene *scenes, int scene_count)
{
    for (int s = 0; s < scene_count; s++) {
        for (int i = 0; i < ch->o->technique_count; i++) {
            const struct technique *t = ch->o->techniques[i];
            char *tuned = util_printf("%s/%s.json", ch->o->tuned_dir, t->name),
                 *label = util_printf("%s" TUNED_SUFFIX, t->name);
            const int rc = add_cell(ch, &scenes[s], t->name, false) ||
                           (util_file_exists(tuned) && add_cell(ch, &scenes[s], label, false));
            free(tuned), free(label);
            if (rc)
                return -1;
        }
        for (int i = 0; i < TABLE_COUNT; i++)
            if (strcmp(table[i].scene, scenes[s].name) == 0 && add_cell(ch, &scenes[s], table[i].cell, true) != 0)
                return -1;
        if (add_files(ch, &scenes[s]) != 0)
            return -1;
    }
    return 0;
}

/* ---- rendering and comparing ---- */

/* Renders c (its settings) on ss; ss->v holds V_tech after. */
static int render(struct scene_setup *ss, const struct technique *t, const void *settings, struct metrics *m)
{
    GLuint program = receiver_program(t, settings, ss->scene->light.shape);
    if (!program)
        return -1;
    int rc = scene_setup_cell(ss, &(struct stage_timer_cell){t, settings, program}, m);
    glDeleteProgram(program);
    return rc;
}

static bool same_params(const struct technique *t, const void *a, const void *b)
{
    for (const struct technique_param *p = t->params; p->name; p++) {
        char x[64], y[64];
        params_value_text(t, a, p->name, x, sizeof x);
        params_value_text(t, b, p->name, y, sizeof y);
        if (strcmp(x, y) != 0)
            return false;
    }
    return true;
}

static bool worse(int k, double base, double now) { return k == METRIC_bias ? fabs(now) > fabs(base) : now > base; }

/* c's status against its baseline; prints its line and, unless it passed,
 * what moved. */
static void compare(struct cell *c, const struct run_options *o)
{
    const size_t count = (size_t)c->desc.width * (size_t)c->desc.height;
    uint16_t *now = xmalloc(count * sizeof *now);
    quantize(c->v, count, now);
    size_t moved = 0;
    for (size_t i = 0; i < count; i++)
        moved += fabs(((double)now[i] - (double)c->picture[i]) / 65535.0) > c->pixel_threshold;
    free(now);
    c->moved_fraction = (double)moved / (double)count;
    c->compared = true;
    const bool picture_moved = c->moved_fraction > c->max_moved;

    struct strbuf why = {0};
    int better = 0, poorer = 0;
    for (int g = 0; g < GUARDED_COUNT; g++) {
        const int k = guarded[g].metric;
        const double base = baseline_metric(c, k), v = metrics_value(&c->now, k);
        const double tol = baseline_tolerance(c, k);
        bool is_worse, is_better;
        if (isnan(base) || isnan(v)) {  /* unscored on one side */
            is_worse = isnan(v) && !isnan(base);
            is_better = isnan(base) && !isnan(v);
        } else {
            const bool beyond = fabs(v - base) > (isnan(tol) ? 0.0 : tol);
            is_worse = beyond && worse(k, base, v);
            is_better = beyond && worse(k, v, base);
        }
        poorer += is_worse, better += is_better;
        if (is_worse || is_better)
            strbuf_printf(&why, "      %-16s %10.5f -> %10.5f  (%+.5f, tolerance %.5f: %s)\n", metric_info[k].key,
                          base, v, v - base, tol, is_worse ? "worse" : "better");
    }
    c->status = poorer || (picture_moved && !better) ? REGRESSED : better ? IMPROVED : PASS;
    printf("  %-11s %-22s %s\n", status_names[c->status], c->scene->name, c->label);
    fflush(stdout);  /* progress, in order with stderr's */
    if (c->status != PASS || picture_moved) {
        fputs(why.data ? why.data : "", stdout);
        printf("      picture: %.2f %% of pixels moved by more than %g (allowed %.2f %%)%s\n",
               100.0 * c->moved_fraction, c->pixel_threshold, 100.0 * c->max_moved,
               picture_moved && !poorer && !better ? ", with no metric better" : "");
    }
    if (c->status == IMPROVED)
        printf("      record it: shadowbench check --update --scene %s --technique %s --baselines %s\n",
               c->scene->name, c->t->name, o->baselines_dir);
    strbuf_free(&why);

    /* The baseline's parameters against what its name means today. */
    if (!same_params(c->t, c->settings, c->label_settings)) {
        printf("      its recorded parameters are no longer what '%s' means (a default changed?): "
               "record it anew\n", c->label);
        if (c->status == PASS)
            c->status = REGRESSED;
    }
}

/* The metrics' spread over the ground truth's seeds, for the tolerances. */
static int seed_spread(struct cell *c, struct scene_setup *ss, struct gt_image extra[CHECK_SEEDS - 1])
{
    const int count = c->desc.width * c->desc.height;
    float *scored = xmalloc(sizeof(float) * (size_t)count);
    for (int s = 0; s < CHECK_SEEDS - 1; s++) {
        struct metrics m = {0};
        m.mismatch_pixels = metrics_score_mask(extra[s].mask, extra[s].distance, ss->distance, count, scored);
        metrics_compute(c->v, &extra[s], scored, ss->distance, &m);
        for (int g = 0; g < GUARDED_COUNT; g++) {
            const double d = fabs(metrics_value(&m, guarded[g].metric) - metrics_value(&c->now, guarded[g].metric));
            if (isfinite(d) && d > c->spread[g])
                c->spread[g] = d;
        }
    }
    free(scored);
    return 0;
}

/* Setting each parameter of a table cell back to its default changes its
 * picture. Returns the parameters that did not (printed). */
static int parameters_act(struct cell *c, struct scene_setup *ss)
{
    const size_t count = (size_t)c->desc.width * (size_t)c->desc.height;
    int idle = 0;
    void *defaults = params_defaults(c->t);
    for (const struct technique_param *p = c->t->params; p->name; p++) {
        char mine[64], def[64];
        params_value_text(c->t, c->settings, p->name, mine, sizeof mine);
        params_value_text(c->t, defaults, p->name, def, sizeof def);
        if (strcmp(mine, def) == 0)
            continue;
        void *back = memcpy(xmalloc(c->t->settings_size), c->settings, c->t->settings_size);
        params_set(c->t, back, p->name, def);
        /* Some cells need their values together (a grid needs a square tap
         * count): where setting one back breaks the rules, that parameter
         * is shown to act by another cell. */
        char why[256];
        const bool allowed = !c->t->check || c->t->check(back, why, sizeof why) == 0;
        struct metrics m = {0};
        const bool same = allowed && render(ss, c->t, back, &m) == 0 &&
                          memcmp(ss->v, c->v, count * sizeof(float)) == 0;
        if (same) {
            printf("  IDLE        %-22s %s: setting %s.%s back to %s changes no pixel (is it used?)\n",
                   c->scene->name, c->label, c->t->name, p->name, def);
            idle++;
        }
        free(back);
    }
    free(defaults);
    return idle;
}

/* With every scene selected: each parameter of each selected technique is
 * set away from its default by some table cell. Returns the ones that are
 * not (printed). */
static int parameters_covered(const struct check *ch)
{
    int missing = 0;
    for (int i = 0; i < ch->o->technique_count; i++) {
        const struct technique *t = ch->o->techniques[i];
        void *defaults = params_defaults(t);
        for (const struct technique_param *p = t->params; p->name; p++) {
            char def[64], mine[64];
            params_value_text(t, defaults, p->name, def, sizeof def);
            bool set = false;
            for (int c = 0; c < ch->count && !set; c++)
                if (ch->cells[c].from_table && ch->cells[c].t == t) {
                    params_value_text(t, ch->cells[c].label_settings, p->name, mine, sizeof mine);
                    set = strcmp(mine, def) != 0;
                }
            if (!set) {
                printf("  UNCOVERED   %s.%s: no cell sets it away from its default (add one to the table "
                       "in harness/cli/check.c)\n", t->name, p->name);
                missing++;
            }
        }
        free(defaults);
    }
    return missing;
}

/* ---- the page of moved cells ---- */

static int write_page(const struct check *ch, const char *out)
{
    struct strbuf html = {0};
    strbuf_printf(&html, "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>shadowbench check</title>\n"
                         "<style>body{font:14px sans-serif;margin:2em}td,th{padding:2px 8px;text-align:left}"
                         "img{image-rendering:pixelated;width:384px}</style></head><body>\n"
                         "<h1>shadowbench check: cells that moved</h1>\n");
    int shown = 0;
    for (int i = 0; i < ch->count; i++) {
        const struct cell *c = &ch->cells[i];
        if (!c->picture || !c->v || !c->compared || (c->status == PASS && c->moved_fraction == 0.0))
            continue;
        shown++;
        const size_t count = (size_t)c->desc.width * (size_t)c->desc.height;
        float *base = xmalloc(count * sizeof *base), *shown_px = xmalloc(count * sizeof *shown_px);
        double largest = 0.0;
        for (size_t p = 0; p < count; p++) {
            base[p] = (float)c->picture[p] / 65535.0f;
            shown_px[p] = 1.0f;
            if (isfinite(c->v[p]))
                largest = fmax(largest, fabs((double)c->v[p] - base[p]));
        }
        static const float steps[] = {0.01f, 0.02f, 0.05f, 0.1f, 0.2f, 0.5f, 1.0f};
        float scale = 1.0f;
        for (int s = 6; s >= 0; s--)
            if (steps[s] >= largest)
                scale = steps[s];
        struct picture pic;
        picture_difference(c->v, base, shown_px, c->desc.width, c->desc.height,
                           &(struct picture_legend){scale, "darker now", "brighter now", "V_now - V_baseline"},
                           &pic);
        char *name = util_printf("%s/%s/%s.png", out, c->scene->name, c->label);
        char *dir = util_printf("%s/%s", out, c->scene->name);
        int rc = util_mkdirs(dir) || image_write_png(name, pic.width, pic.height, pic.rgb);
        picture_free(&pic);
        free(base), free(shown_px), free(name), free(dir);
        if (rc) {
            strbuf_free(&html);
            return -1;
        }
        strbuf_printf(&html, "<h2>%s: ", status_names[c->status]);
        strbuf_xml(&html, c->scene->name);
        strbuf_printf(&html, " / ");
        strbuf_xml(&html, c->label);
        strbuf_printf(&html, "</h2>\n<p>%.2f %% of pixels moved by more than %g (allowed %.2f %%).</p>\n"
                             "<table><tr><th>metric</th><th>baseline</th><th>now</th><th>difference</th>"
                             "<th>tolerance</th></tr>\n",
                      100.0 * c->moved_fraction, c->pixel_threshold, 100.0 * c->max_moved);
        for (int g = 0; g < GUARDED_COUNT; g++) {
            const int k = guarded[g].metric;
            const double b = baseline_metric(c, k), v = metrics_value(&c->now, k);
            strbuf_printf(&html, "<tr><td>%s</td><td>%.5f</td><td>%.5f</td><td>%+.5f</td><td>%.5f</td></tr>\n",
                          metric_info[k].key, b, v, v - b, baseline_tolerance(c, k));
        }
        strbuf_printf(&html, "</table>\n<p><img src=\"");
        strbuf_xml(&html, c->scene->name);
        strbuf_printf(&html, "/");
        strbuf_xml(&html, c->label);
        strbuf_printf(&html, ".png\" alt=\"V_now - V_baseline\"></p>\n");
    }
    if (!shown)
        strbuf_printf(&html, "<p>No cell moved.</p>\n");
    strbuf_printf(&html, "</body></html>\n");
    char *path = util_printf("%s/check.html", out);
    int rc = util_write_file_atomic(path, html.data, html.len);
    free(path);
    strbuf_free(&html);
    return rc ? -1 : 0;
}

/* ---- the command ---- */

static bool same_desc(const struct scene_setup_desc *a, const struct scene_setup_desc *b)
{
    return a->width == b->width && a->height == b->height && a->shadow_map_size == b->shadow_map_size &&
           a->gt_samples == b->gt_samples && a->gt_seed == b->gt_seed;
}

/* Renders, compares (or records) every cell of one scene. Returns -1 on a
 * runtime error, else the number of failures (regressions, missing
 * baselines, idle parameters, improvements with --strict). */
static int check_scene(struct check *ch, const struct scene *s, const char *git, const char *date)
{
    const struct run_options *o = ch->o;
    int failures = 0;
    struct scene_setup ss = {0};
    struct scene_setup_desc current = {0};
    struct gt_image extra[CHECK_SEEDS - 1] = {0};
    bool open = false;
    for (int i = 0; i < ch->count; i++) {
        struct cell *c = &ch->cells[i];
        if (c->scene != s)
            continue;
        if (!c->baseline && !o->update) {
            c->status = NO_BASELINE;
            printf("  %-11s %-22s %s   (record it: shadowbench check --update --scene %s --technique %s "
                   "--baselines %s)\n", status_names[NO_BASELINE], s->name, c->label, s->name, c->t->name,
                   o->baselines_dir);
            failures++;
            continue;
        }
        bool comparable = c->baseline != NULL;
        if (o->update) {  /* recorded anew: today's settings for its name */
            const struct scene_setup_desc fresh = {CHECK_SIZE, CHECK_SIZE, SHADOWMAP_DEFAULT_SIZE,
                                                   CHECK_GT_SAMPLES, CHECK_GT_SEED, o->cache_dir, 0};
            comparable = comparable && same_desc(&c->desc, &fresh) &&
                         same_params(c->t, c->settings, c->label_settings);
            memcpy(c->settings, c->label_settings, c->t->settings_size);
            c->desc = fresh;
        }
        c->desc.cache_dir = o->cache_dir;
        if (!open || !same_desc(&current, &c->desc)) {
            if (open)
                scene_setup_free(&ss);
            for (int k = 0; k < CHECK_SEEDS - 1; k++)
                gt_image_free(&extra[k]);
            if (scene_setup_open(&ss, s, &c->desc) != 0) {
                scene_setup_free(&ss);
                return -1;
            }
            open = true;
            current = c->desc;
            for (int k = 0; k < CHECK_SEEDS - 1 && o->update; k++) {
                struct gt_desc d = {.width = c->desc.width, .height = c->desc.height,
                                    .samples = c->desc.gt_samples, .seed = c->desc.gt_seed + 1 + (uint32_t)k};
                if (gt_obtain(s, &ss.sm.frustum, &d, o->cache_dir, &extra[k]) != 0) {
                    scene_setup_free(&ss);
                    return -1;
                }
            }
        }
        c->now = (struct metrics){0};
        if (render(&ss, c->t, c->settings, &c->now) != 0) {
            failures = -1;
            break;
        }
        const size_t count = (size_t)c->desc.width * (size_t)c->desc.height;
        c->v = memcpy(xmalloc(count * sizeof(float)), ss.v, count * sizeof(float));
        if (o->update) {
            seed_spread(c, &ss, extra);
            if (comparable)
                compare(c, o);
            else
                printf("  %-11s %-22s %s%s\n", "new", s->name, c->label,
                       c->baseline ? "   (its settings changed: not compared)" : "");
            if (write_baseline(c, git, date) != 0) {
                failures = -1;
                break;
            }
        } else {
            compare(c, o);
            failures += c->status == REGRESSED || (c->status == IMPROVED && o->strict);
        }
        if (c->from_table)
            failures += parameters_act(c, &ss);
    }
    if (open)
        scene_setup_free(&ss);
    for (int k = 0; k < CHECK_SEEDS - 1; k++)
        gt_image_free(&extra[k]);
    return failures;
}

/* path made absolute with its links resolved, as far as it exists (the rest
 * appended as written); malloc'ed. */
static char *absolute(const char *path)
{
    char *real = realpath(path, NULL);
    if (real)
        return real;
    const char *slash = strrchr(path, '/');
    if (!slash) {
        char *cwd = realpath(".", NULL), *joined = util_printf("%s/%s", cwd ? cwd : ".", path);
        free(cwd);
        return joined;
    }
    char *parent = slash == path ? xstrdup("/") : util_printf("%.*s", (int)(slash - path), path);
    char *head = absolute(parent);
    char *joined = util_printf("%s%s%s", head, head[strlen(head) - 1] == '/' ? "" : "/", slash + 1);
    free(parent), free(head);
    return joined;
}

/* The baselines folder is a folder (made and writable for --update), and
 * --out is not it or inside it: the page's pictures would overwrite the
 * baselines'. Returns 0 or -1 (logged). */
static int check_folders(const struct run_options *o)
{
    struct stat st;
    if (stat(o->baselines_dir, &st) == 0 && !S_ISDIR(st.st_mode)) {
        log_error("--baselines %s: not a folder", o->baselines_dir);
        return -1;
    }
    char *out = absolute(o->out_dir), *base = absolute(o->baselines_dir);
    const size_t n = strlen(base);
    const bool inside = strncmp(out, base, n) == 0 && (out[n] == '\0' || out[n] == '/');
    if (inside)
        log_error("--out %s: inside the baselines folder %s (its pictures would overwrite them)", o->out_dir,
                  o->baselines_dir);
    free(out), free(base);
    if (inside || (o->update && run_claim_results_dir(o->baselines_dir, 2) != 0))
        return -1;
    return run_claim_out_dir(o->out_dir);
}

int check_main(const struct run_options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[RUN_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE;
    struct check ch = {.o = o, .all_scenes = o->scene_count == 0};
    char *git = NULL, *date = NULL;

    if (run_load_scenes(o, scenes, &scene_count) != 0 || check_folders(o) != 0 ||
        collect_cells(&ch, scenes, scene_count) != 0)
        goto out;
    for (int i = 0; i < ch.count; i++) {
        struct cell *c = &ch.cells[i];
        /* --update repairs what it cannot read: not an error there. */
        const enum log_level level = log_get_level();
        if (o->update)
            log_set_level(LOG_NONE);
        const int rc = read_baseline(c);
        log_set_level(level);
        if (rc == 0)
            continue;
        if (!o->update)
            goto out;
        log_warn("%s: not readable by this build (see check without --update): recorded anew", c->json_path);
        cJSON_Delete(c->baseline);
        c->baseline = NULL;
    }
    for (int s = 0; s < scene_count; s++) {
        struct light_frustum f;
        if (light_frustum_fit(&scenes[s], &f) != 0)
            goto out;
    }
    if (shader_init(o->shader_dir) != 0)  /* a bad --shaders is bad usage */
        goto out;
    status = EXIT_CHECK_FAILED;
    if (gl_context_create(o->gl) != 0) {  /* no such context here: bad usage (exit 2), as a bad --shaders */
        status = EXIT_USAGE;
        goto out;
    }
    git = run_git_describe();
    date = run_utc_date();

    printf("check: %d cells on %d scene(s) against %s%s\n", ch.count, scene_count, o->baselines_dir,
           o->update ? " (recording them anew)" : "");
    int failures = 0;
    for (int s = 0; s < scene_count && failures >= 0; s++) {
        const int f = check_scene(&ch, &scenes[s], git, date);
        failures = f < 0 ? -1 : failures + f;
    }
    if (failures >= 0 && ch.all_scenes)
        failures += parameters_covered(&ch);
    if (failures >= 0 && write_page(&ch, o->out_dir) != 0)
        failures = -1;
    if (failures >= 0) {
        int n[4] = {0};
        for (int i = 0; i < ch.count; i++)
            n[ch.cells[i].status]++;
        printf("check: %d passed, %d REGRESSED, %d improved, %d without a baseline%s; %.1f s; "
               "page of moved cells: %s/check.html\n",
               n[PASS], n[REGRESSED], n[IMPROVED], n[NO_BASELINE], o->update ? " (recorded anew)" : "",
               (util_now_ms() - start) * 1e-3, o->out_dir);
        status = failures ? EXIT_CHECK_FAILED : EXIT_OK;
    }
    gl_context_destroy();
out:
    for (int i = 0; i < ch.count; i++)
        cell_free(&ch.cells[i]);
    free(ch.cells);
    free(git), free(date);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
