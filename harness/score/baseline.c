#include "baseline.h"
#include "base/image.h"
#include "base/log.h"
#include "base/util.h"
#include "render/receiver.h"
#include "techniques/params.h"
#include "techniques/shadowmap.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The most each moved over the 94 cells under llvmpipe's variations
 * (tools/check-variation): all of it from the run without AVX and FMA. */
const struct baseline_guard baseline_guards[BASELINE_GUARDS] = {
    {METRIC_rmse, 3.9e-6}, {METRIC_mae, 2.7e-6}, {METRIC_bias, 4.2e-6}, {METRIC_p99_abs, 1.02e-4},
    {METRIC_penumbra_rmse, 6.2e-6}, {METRIC_leak_fraction, 2.2e-5}, {METRIC_dark_fraction, 4.4e-5},
    {METRIC_shaded_rmse, 1.02e-5}, {METRIC_nonfinite, 0.0},
};

const struct baseline_setup baseline_setup_default = {BASELINE_SIZE, BASELINE_SIZE, BASELINE_GT_SAMPLES,
                                                      SHADOWMAP_DEFAULT_SIZE, BASELINE_GT_SEED};

const char *const baseline_status_names[] = {"pass", "REGRESSED", "improved", "no baseline"};

bool baseline_setup_equal(const struct baseline_setup *a, const struct baseline_setup *b)
{
    return a->width == b->width && a->height == b->height && a->shadow_map_size == b->shadow_map_size &&
           a->gt_samples == b->gt_samples && a->gt_seed == b->gt_seed;
}

static double json_number(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* A number in [lo, hi] at key of o, or NAN. */
static double json_in_range(const cJSON *o, const char *key, double lo, double hi)
{
    const double v = json_number(o, key);
    return v >= lo && v <= hi ? v : NAN;
}

double baseline_metric(const struct baseline *b, int metric)
{
    return json_number(cJSON_GetObjectItemCaseSensitive(b->doc, "metrics"), metric_info[metric].key);
}

double baseline_tolerance(const struct baseline *b, int metric)
{
    const cJSON *tol = cJSON_GetObjectItemCaseSensitive(b->doc, "tolerances");
    return json_number(cJSON_GetObjectItemCaseSensitive(tol, metric_info[metric].key), "value");
}

/* The fingerprint of a picture, recorded beside it: a JSON and a PNG from
 * different recordings (an interrupted --update, a file copied over) are
 * refused. */
static char *picture_hash(const uint16_t *pixels, size_t count)
{
    return util_printf("%016llx", (unsigned long long)util_hash(UTIL_HASH_INIT, pixels, count * sizeof *pixels));
}

/* What is wrong with the document of cell `label` (technique t, scene
 * `scene`), or NULL; fills b's setup and picture budget. buf holds a
 * composed message. */
static const char *problem_of(struct baseline *b, const char *scene, const char *label, const struct technique *t,
                              char *buf, size_t size)
{
    const cJSON *d = b->doc;
    const cJSON *settings = cJSON_GetObjectItemCaseSensitive(d, "settings");
    const cJSON *metrics = cJSON_GetObjectItemCaseSensitive(d, "metrics");
    const cJSON *tolerances = cJSON_GetObjectItemCaseSensitive(d, "tolerances");
    const cJSON *picture = cJSON_GetObjectItemCaseSensitive(d, "picture");
    const char *cell = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "cell"));
    const char *its_scene = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "scene"));
    const char *technique = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "technique"));
    if (!cell || strcmp(cell, label) != 0)
        return "its \"cell\" is not its file name";
    if (!its_scene || strcmp(its_scene, scene) != 0)
        return "its \"scene\" is not its folder's";
    if (!technique || strcmp(technique, t->name) != 0)
        return "its \"technique\" is not its cell's";
    if (!cJSON_IsObject(settings) || !cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(settings, "params")) ||
        !cJSON_IsObject(metrics) || !cJSON_IsObject(tolerances) || !cJSON_IsObject(picture))
        return "lacks \"settings\" (with \"params\"), \"metrics\", \"tolerances\" or \"picture\"";
    const double version = json_number(d, "gt_version");
    if (version != GT_VERSION) {
        snprintf(buf, size, "recorded with ground-truth version %g, this build renders version %d (record "
                 "it anew: shadowbench check --update)", version, GT_VERSION);
        return buf;
    }
    const double w = json_in_range(settings, "width", RECEIVER_MIN_SIZE, RECEIVER_MAX_SIZE);
    const double h = json_in_range(settings, "height", RECEIVER_MIN_SIZE, RECEIVER_MAX_SIZE);
    const double n = json_in_range(settings, "gt_samples", 1, GT_MAX_SAMPLES);
    const double seed = json_in_range(settings, "gt_seed", 1, UINT32_MAX);
    const double map = json_in_range(settings, "shadow_map_size", SHADOWMAP_MIN_SIZE, SHADOWMAP_MAX_SIZE);
    const double root = round(sqrt(n));
    if (!(w == floor(w) && h == floor(h) && root * root == n && seed == floor(seed) && map == floor(map)))
        return "its settings (width, height, gt_samples, gt_seed, shadow_map_size) are missing or out of range";
    b->setup = (struct baseline_setup){(int)w, (int)h, (int)n, (int)map, (uint32_t)seed};
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const int k = baseline_guards[g].metric;
        const char *key = metric_info[k].key;
        const cJSON *m = cJSON_GetObjectItemCaseSensitive(metrics, key);
        const double tol = json_in_range(cJSON_GetObjectItemCaseSensitive(tolerances, key), "value", 0, 1);
        /* A scored cell's value: an error or a share in [0, 1] (bias in
         * [-1, 1], shaded_rmse from 0), a count whole from 0. Never null:
         * an unscored cell is not a baseline, and a null would make any
         * value "better". */
        const double v = cJSON_IsNumber(m) ? m->valuedouble : NAN, lo = k == METRIC_bias ? -1 : 0,
                     hi = k == METRIC_nonfinite || k == METRIC_shaded_rmse ? INFINITY : 1;
        if (!(v >= lo && v <= hi) || (k == METRIC_nonfinite && v != floor(v)) || isnan(tol)) {
            snprintf(buf, size, "metric %s: needs a number in [%g, %g]%s and a tolerance in [0, 1]", key, lo, hi,
                     k == METRIC_nonfinite ? ", whole" : "");
            return buf;
        }
    }
    b->pixel_threshold = json_in_range(picture, "pixel_threshold", 0, 1);
    b->max_moved = json_in_range(picture, "max_moved_fraction", 0, 1);
    if (isnan(b->pixel_threshold) || isnan(b->max_moved) ||
        !cJSON_IsString(cJSON_GetObjectItemCaseSensitive(picture, "hash")))
        return "its \"picture\" needs pixel_threshold and max_moved_fraction in [0, 1] and a hash";
    return NULL;
}

int baseline_read(const char *json_path, const char *png_path, const char *scene, const char *label,
                  const struct technique *t, struct baseline *b, void *settings)
{
    memset(b, 0, sizeof *b);
    char *text;
    size_t size;
    int rc = util_read_file(json_path, &text, &size);
    if (rc == -ENOENT)
        return 0;
    if (rc) {
        log_error("%s: cannot read: %s", json_path, util_read_error(rc));
        return -1;
    }
    const char *end = NULL;
    b->doc = cJSON_ParseWithLengthOpts(text, size, &end, false);
    while (b->doc && end < text + size && strchr(" \t\r\n", *end))
        end++;
    char buf[256];
    const char *problem = NULL;
    if (!b->doc || end != text + size) {
        snprintf(buf, sizeof buf, "not valid JSON (at byte %td)",
                 b->doc ? end - text : cJSON_GetErrorPtr() ? cJSON_GetErrorPtr() - text : (ptrdiff_t)0);
        problem = buf;
    } else if (!cJSON_IsObject(b->doc)) {
        problem = "not a JSON object";
    } else if (util_json_duplicate_key(b->doc)) {
        snprintf(buf, sizeof buf, "the key \"%.64s\" appears twice in one object", util_json_duplicate_key(b->doc));
        problem = buf;
    } else {
        problem = problem_of(b, scene, label, t, buf, sizeof buf);
    }
    free(text);

    /* The parameters it was rendered with: every one, named once, in range;
     * a bad one is reported by params_from_json, prefixed with the file. */
    log_set_context(json_path);
    if (problem)
        log_error("%s", problem);
    void *recorded = problem ? NULL
                             : params_from_json(t, cJSON_GetObjectItemCaseSensitive(
                                                       cJSON_GetObjectItemCaseSensitive(b->doc, "settings"), "params"));
    log_set_context(NULL);
    if (!recorded)
        return -1;
    memcpy(settings, recorded, t->settings_size);
    free(recorded);

    rc = image_read_png16(png_path, b->setup.width, b->setup.height, &b->picture);
    if (rc == -ENOENT)
        log_error("%s: its picture %s is missing", json_path, png_path);
    if (rc)
        return -1;
    char *hash = picture_hash(b->picture, (size_t)b->setup.width * (size_t)b->setup.height);
    const char *want = cJSON_GetStringValue(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(b->doc, "picture"), "hash"));
    rc = strcmp(hash, want) != 0;
    if (rc)
        log_error("%s: its picture is not the one it recorded (an interrupted --update? record it anew)", json_path);
    free(hash);
    return rc ? -1 : 0;
}

void baseline_free(struct baseline *b)
{
    cJSON_Delete(b->doc);
    free(b->picture);
    memset(b, 0, sizeof *b);
}

void baseline_quantize(const float *v, size_t count, uint16_t *out)
{
    for (size_t i = 0; i < count; i++) {
        float x = v[i] > 0.0f ? (v[i] < 1.0f ? v[i] : 1.0f) : 0.0f;  /* NaN -> 0 */
        out[i] = (uint16_t)lrintf(x * 65535.0f);
    }
}

static bool worse(int k, double base, double now) { return k == METRIC_bias ? fabs(now) > fabs(base) : now > base; }

void baseline_compare(const struct baseline *b, const struct metrics *m, const float *v,
                      struct baseline_comparison *out)
{
    memset(out, 0, sizeof *out);
    const size_t count = (size_t)b->setup.width * (size_t)b->setup.height;
    uint16_t *now = xmalloc(count * sizeof *now);
    baseline_quantize(v, count, now);
    size_t moved = 0;
    for (size_t i = 0; i < count; i++)
        moved += fabs(((double)now[i] - (double)b->picture[i]) / 65535.0) > b->pixel_threshold;
    free(now);
    out->moved_fraction = (double)moved / (double)count;
    out->picture_moved = out->moved_fraction > b->max_moved;
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const int k = baseline_guards[g].metric;
        const double base = baseline_metric(b, k), now_value = metrics_value(m, k), tol = baseline_tolerance(b, k);
        bool is_worse, is_better;
        if (isnan(base) || isnan(now_value)) {  /* unscored on one side */
            is_worse = isnan(now_value) && !isnan(base);
            is_better = isnan(base) && !isnan(now_value);
        } else {
            const bool beyond = fabs(now_value - base) > (isnan(tol) ? 0.0 : tol);
            is_worse = beyond && worse(k, base, now_value);
            is_better = beyond && worse(k, now_value, base);
        }
        out->direction[g] = is_worse ? 1 : is_better ? -1 : 0;
        out->worse += is_worse, out->better += is_better;
    }
    out->status = out->worse || (out->picture_moved && !out->better) ? BASELINE_REGRESSED
                   : out->better                                      ? BASELINE_IMPROVED
                                                                      : BASELINE_PASS;
}

void baseline_spread(const float *v, const float *gl_distance, float depth_tolerance, const struct metrics *m,
                     const struct gt_image *others, int n, double spread[BASELINE_GUARDS])
{
    for (int g = 0; g < BASELINE_GUARDS; g++)
        spread[g] = 0;
    if (n <= 0)
        return;
    const int w = others[0].width, h = others[0].height, count = w * h;  /* at most RECEIVER_MAX_SIZE^2: an int */
    float *scored = xmalloc(sizeof(float) * (size_t)count);
    for (int s = 0; s < n; s++) {
        struct metrics other = {0};
        other.mismatch_pixels =
            metrics_score_mask(others[s].mask, others[s].distance, gl_distance, w, h, depth_tolerance, scored);
        metrics_compute(v, &others[s], scored, gl_distance, &other);
        for (int g = 0; g < BASELINE_GUARDS; g++) {
            const int k = baseline_guards[g].metric;
            const double d = fabs(metrics_value(&other, k) - metrics_value(m, k));
            if (isfinite(d) && d > spread[g])
                spread[g] = d;
        }
    }
    free(scored);
}

int baseline_write(const char *json_path, const char *png_path, const struct baseline_record *r)
{
    cJSON *b = cJSON_CreateObject();
    cJSON_AddStringToObject(b, "scene", r->scene);
    cJSON_AddStringToObject(b, "cell", r->label);
    cJSON_AddStringToObject(b, "technique", r->t->name);
    cJSON *s = cJSON_AddObjectToObject(b, "settings");
    cJSON_AddNumberToObject(s, "width", r->setup.width);
    cJSON_AddNumberToObject(s, "height", r->setup.height);
    cJSON_AddNumberToObject(s, "gt_samples", r->setup.gt_samples);
    cJSON_AddNumberToObject(s, "gt_seed", r->setup.gt_seed);
    cJSON_AddNumberToObject(s, "shadow_map_size", r->setup.shadow_map_size);
    cJSON *params = cJSON_AddObjectToObject(s, "params");
    for (const struct technique_param *p = r->t->params; p->name; p++) {
        char value[64];
        params_value_text(r->t, r->settings, p->name, value, sizeof value);
        cJSON_AddStringToObject(params, p->name, value);
    }
    cJSON *m = cJSON_AddObjectToObject(b, "metrics"), *tol = cJSON_AddObjectToObject(b, "tolerances");
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const int k = baseline_guards[g].metric;
        const double v = metrics_value(r->m, k);
        cJSON_AddItemToObject(m, metric_info[k].key, isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull());
        cJSON *t = cJSON_AddObjectToObject(tol, metric_info[k].key);
        char why[256];
        if (k == METRIC_nonfinite) {
            cJSON_AddNumberToObject(t, "value", 0);
            snprintf(why, sizeof why, "a count: any NaN or Inf more is a regression");
        } else {
            cJSON_AddNumberToObject(t, "value", 2.0 * (r->spread[g] + baseline_guards[g].device));
            snprintf(why, sizeof why, "2 x (its spread over ground-truth seeds %u..%u: %.2g, + the most "
                     "it moved on any cell with llvmpipe built for another CPU: %.2g)", r->setup.gt_seed,
                     r->setup.gt_seed + BASELINE_SEEDS - 1, r->spread[g], baseline_guards[g].device);
        }
        cJSON_AddStringToObject(t, "why", why);
    }
    const size_t count = (size_t)r->setup.width * (size_t)r->setup.height;
    uint16_t *pixels = xmalloc(count * sizeof *pixels);
    baseline_quantize(r->v, count, pixels);
    char *hash = picture_hash(pixels, count);
    cJSON *pic = cJSON_AddObjectToObject(b, "picture");
    cJSON_AddStringToObject(pic, "hash", hash);
    free(hash);
    cJSON_AddNumberToObject(pic, "pixel_threshold", BASELINE_PIXEL_THRESHOLD);
    cJSON_AddNumberToObject(pic, "max_moved_fraction", BASELINE_PIXEL_FRACTION);
    cJSON_AddStringToObject(pic, "why", "V_tech does not depend on the ground truth and is the same bit "
                            "for bit across LP_NUM_THREADS and LP_NATIVE_VECTOR_WIDTH; without AVX and "
                            "FMA at most 0.075 % of a cell's pixels moved: twice that");
    cJSON_AddNumberToObject(b, "gt_version", GT_VERSION);
    char *command = util_printf("shadowbench check --update --scene %s --technique %s", r->scene, r->t->name);
    cJSON_AddStringToObject(b, "command", command);  /* how to record this cell again */
    free(command);
    util_json_merge(b, r->provenance);

    char *text = cJSON_Print(b);
    cJSON_Delete(b);
    char *dir = xstrdup(json_path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    int rc = (slash && util_mkdirs_own(dir, 1)) ||
             image_write_png16(png_path, r->setup.width, r->setup.height, pixels) ||
             util_write_file_atomic(json_path, text, strlen(text));
    free(pixels);
    free(dir);
    free(text);
    return rc ? -1 : 0;
}
