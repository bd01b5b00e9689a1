#include "tuned.h"
#include "base/log.h"
#include "base/util.h"
#include "techniques/params.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const tuned_kind_names[2] = {"area", "sun"};

/* Settings from the object `what` of file path, or NULL after one line
 * naming both. */
static void *settings_from_json(const struct technique *t, const cJSON *o, const char *path, const char *what)
{
    char *context = util_printf("%s: %s", path, what);
    log_set_context(context);
    void *s = params_from_json(t, o);
    log_set_context(path);
    free(context);
    return s;
}

/* A point: an error (finite, not negative) and times with 0 < q1 <= ms <= q3
 * (a chart's log axis needs them positive). */
static bool read_point(const cJSON *o, struct tuned_point *p)
{
    static const char *const keys[] = {"error", "ms", "ms_q1", "ms_q3"};
    double *dst[] = {&p->error, &p->ms, &p->ms_q1, &p->ms_q3};
    for (int i = 0; i < 4; i++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, keys[i]);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble) || v->valuedouble < 0)
            return false;
        *dst[i] = v->valuedouble;
    }
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(o, "fetches");  /* optional: counted */
    p->fetches = cJSON_IsNumber(f) && isfinite(f->valuedouble) && f->valuedouble > 0 ? f->valuedouble : NAN;
    if (f && isnan(p->fetches))
        return false;
    /* Errors are shares of visibility (shaded_rmse may pass 1, not by 1e3);
     * times from a microsecond to an hour: what a chart's axes can hold. */
    return p->error <= TUNED_MAX_ERROR && p->ms_q1 >= 1e-3 && p->ms_q1 <= p->ms && p->ms <= p->ms_q3 &&
           p->ms_q3 <= 3.6e6;
}

/* A frontier: points with their settings' text, a Pareto front (cost
 * increasing, error decreasing); by_fetches: its cost is fetches, which
 * every point has. */
static bool valid_frontier(const cJSON *a, bool by_fetches)
{
    const cJSON *e;
    struct tuned_point p, last = {INFINITY, 0, 0, 0, 0};
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) > TUNED_MAX_FRONTIER)
        return false;
    cJSON_ArrayForEach(e, a) {
        if (!read_point(e, &p) || !cJSON_IsString(cJSON_GetObjectItemCaseSensitive(e, "settings")) ||
            (by_fetches ? !(p.fetches >= last.fetches) : p.ms < last.ms) || p.error >= last.error)
            return false;
        last = p;
    }
    return true;
}

/* A whole number in [1, 65536] at key of d, or 0. */
static int whole(const cJSON *d, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(d, key);
    return cJSON_IsNumber(v) && v->valuedouble >= 1 && v->valuedouble <= 65536 &&
                   v->valuedouble == floor(v->valuedouble)
               ? (int)v->valuedouble
               : 0;
}

enum tuned_load_result tuned_load(const char *dir, const struct technique *t, struct tuned *out)
{
    memset(out, 0, sizeof *out);
    out->t = t;
    out->path = util_printf("%s/%s.json", dir, t->name);
    char *text = NULL;
    size_t size;
    int rc = util_read_file(out->path, &text, &size);
    if (rc == -ENOENT) {
        tuned_free(out);
        return TUNED_NONE;
    }
    log_set_context(out->path);
    if (rc) {  /* a folder, a FIFO, a device, a loop of links: said, not taken for "none" */
        log_error("cannot read: %s", util_read_error(rc));
        goto fail;
    }
    const char *end = NULL;  /* the whole file is the document: nothing after it, no NUL */
    out->doc = memchr(text, '\0', size) ? NULL : cJSON_ParseWithLengthOpts(text, size, &end, 0);
    while (out->doc && end < text + size && strchr(" \t\r\n", *end))
        end++;
    if (out->doc && end != text + size) {
        cJSON_Delete(out->doc);
        out->doc = NULL;
    }
    free(text);
    const cJSON *d = out->doc, *folds = cJSON_GetObjectItemCaseSensitive(d, "folds"), *f;
    const char *technique = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "technique"));
    if (!d) {
        log_error("not JSON");
        goto fail;
    }
    if (util_json_duplicate_key(d)) {
        log_error("the key \"%.64s\" appears twice in one object", util_json_duplicate_key(d));
        goto fail;
    }
    if (!technique || strcmp(technique, t->name) != 0) {
        log_error("holds the technique '%.64s', not %s", technique ? technique : "(none)", t->name);
        goto fail;
    }
    if (!(out->settings = settings_from_json(t, cJSON_GetObjectItemCaseSensitive(d, "settings"), out->path, "settings")))
        goto fail;
    /* Optional: the settings chosen on each light kind's scenes. */
    const cJSON *by_light = cJSON_GetObjectItemCaseSensitive(d, "settings_by_light");
    bool by_light_ok = !by_light || cJSON_IsObject(by_light);
    for (const cJSON *k = by_light ? by_light->child : NULL; k && by_light_ok; k = k->next)
        by_light_ok = strcmp(k->string, tuned_kind_names[TUNED_KIND_AREA]) == 0 ||
                      strcmp(k->string, tuned_kind_names[TUNED_KIND_SUN]) == 0;
    if (!by_light_ok) {
        log_error("\"settings_by_light\" must be an object with keys area and sun only");
        goto fail;
    }
    for (int k = 0; k < 2 && by_light; k++) {
        const cJSON *o = cJSON_GetObjectItemCaseSensitive(by_light, tuned_kind_names[k]);
        char what[64];
        snprintf(what, sizeof what, "settings_by_light.%s", tuned_kind_names[k]);
        if (o && !(out->kind_settings[k] = settings_from_json(t, o, out->path, what)))
            goto fail;
    }
    /* One fold per scene the tuning saw, in its order: a scene without its
     * fold would get the setting fitted on it. */
    const cJSON *scene_list = cJSON_GetObjectItemCaseSensitive(d, "scenes");
    bool scenes_ok = cJSON_IsArray(scene_list) && cJSON_IsArray(folds) && cJSON_GetArraySize(scene_list) >= 2 &&
                     cJSON_GetArraySize(scene_list) == cJSON_GetArraySize(folds);
    for (const cJSON *a = scene_list ? scene_list->child : NULL, *f = folds ? folds->child : NULL;
         scenes_ok && a && f; a = a->next, f = f->next) {
        const char *fold_scene = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(f, "scene"));
        scenes_ok = cJSON_IsString(a) && fold_scene && strcmp(a->valuestring, fold_scene) == 0;
        for (const cJSON *b = scene_list->child; scenes_ok && b != a; b = b->next)
            scenes_ok = strcmp(b->valuestring, a->valuestring) != 0;
    }
    if (!scenes_ok) {
        log_error("\"scenes\" must name 2 or more scenes, each once, and \"folds\" hold one per scene in that "
                  "order");
        goto fail;
    }
    const int n = cJSON_GetArraySize(folds);
    out->fold_scene = xcalloc((size_t)n + 1, sizeof *out->fold_scene);
    out->fold_settings = xcalloc((size_t)n + 1, sizeof *out->fold_settings);
    cJSON_ArrayForEach(f, folds) {
        const char *scene = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(f, "scene"));
        struct tuned_point p;
        char what[256];
        snprintf(what, sizeof what, "folds[%d].settings", out->fold_count);
        if (!scene || !read_point(cJSON_GetObjectItemCaseSensitive(f, "held_out"), &p) ||
            !read_point(cJSON_GetObjectItemCaseSensitive(f, "default"), &p)) {
            log_error("folds[%d] needs \"scene\", and \"held_out\" and \"default\" with error, ms, ms_q1, "
                      "ms_q3 (finite, not negative)", out->fold_count);
            goto fail;
        }
        out->fold_scene[out->fold_count] = scene;
        if (!(out->fold_settings[out->fold_count++] =
                  settings_from_json(t, cJSON_GetObjectItemCaseSensitive(f, "settings"), out->path, what)))
            goto fail;
    }
    const cJSON *summary = cJSON_GetObjectItemCaseSensitive(d, "summary");
    const cJSON *frontier = cJSON_GetObjectItemCaseSensitive(d, "frontier");
    const cJSON *scenes = cJSON_GetObjectItemCaseSensitive(frontier, "scenes"), *s;
    const char *cost = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "cost"));  /* absent: ms */
    out->cost_fetches = cost && strcmp(cost, "fetches") == 0;
    if (cost && !out->cost_fetches && strcmp(cost, "ms") != 0) {
        log_error("\"cost\" is \"%s\", not ms or fetches", cost);
        goto fail;
    }
    struct tuned_point p;
    bool ok = read_point(cJSON_GetObjectItemCaseSensitive(summary, "default"), &p) &&
              read_point(cJSON_GetObjectItemCaseSensitive(summary, "tuned"), &p) &&
              valid_frontier(cJSON_GetObjectItemCaseSensitive(frontier, "all"), out->cost_fetches) &&
              cJSON_IsObject(scenes);
    cJSON_ArrayForEach(s, scenes)
        ok &= valid_frontier(s, out->cost_fetches);
    if (!ok) {
        log_error("\"summary\" (default, tuned) or \"frontier\" (all, scenes) is missing or malformed");
        goto fail;
    }
    out->width = whole(d, "width"), out->height = whole(d, "height");
    out->shadow_map_size = whole(d, "shadow_map_size");
    out->objective = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "objective"));
    out->gl_renderer = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "gl_renderer"));
    out->date = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(d, "date"));
    if (!out->width || !out->height || !out->shadow_map_size || !out->objective || !out->gl_renderer ||
        !out->date || !(strcmp(out->objective, "penumbra_rmse") == 0 || strcmp(out->objective, "rmse") == 0 ||
                        strcmp(out->objective, "shaded_rmse") == 0)) {
        log_error("needs whole numbers width, height, shadow_map_size, texts gl_renderer and date, and an "
                  "objective of penumbra_rmse, rmse or shaded_rmse");
        goto fail;
    }
    log_set_context(NULL);
    return TUNED_LOADED;
fail:
    log_set_context(NULL);
    tuned_free(out);
    return TUNED_ERROR;
}

int tuned_kind(const struct scene *s)
{
    return s->light.shape == LIGHT_SUN ? TUNED_KIND_SUN : TUNED_KIND_AREA;
}

const void *tuned_settings(const struct tuned *tu, const struct scene *s)
{
    for (int i = 0; i < tu->fold_count; i++)
        if (strcmp(tu->fold_scene[i], s->name) == 0)
            return tu->fold_settings[i];
    const void *kind = tu->kind_settings[tuned_kind(s)];
    return kind ? kind : tu->settings;
}

int tuned_frontier(const struct tuned *tu, const char *scene_name, struct tuned_point **points,
                   struct tuned_point *def, struct tuned_point *tuned)
{
    const cJSON *frontier = cJSON_GetObjectItemCaseSensitive(tu->doc, "frontier"), *a, *e;
    *def = *tuned = (struct tuned_point){NAN, NAN, NAN, NAN, NAN};
    *points = NULL;
    if (!scene_name) {
        a = cJSON_GetObjectItemCaseSensitive(frontier, "all");
        const cJSON *summary = cJSON_GetObjectItemCaseSensitive(tu->doc, "summary");
        read_point(cJSON_GetObjectItemCaseSensitive(summary, "default"), def);
        read_point(cJSON_GetObjectItemCaseSensitive(summary, "tuned"), tuned);
    } else {
        a = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(frontier, "scenes"), scene_name);
        const cJSON *f;
        cJSON_ArrayForEach(f, cJSON_GetObjectItemCaseSensitive(tu->doc, "folds"))
            if (strcmp(cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(f, "scene")), scene_name) == 0) {
                read_point(cJSON_GetObjectItemCaseSensitive(f, "default"), def);
                read_point(cJSON_GetObjectItemCaseSensitive(f, "held_out"), tuned);
            }
    }
    int n = 0;
    *points = xcalloc((size_t)cJSON_GetArraySize(a) + 1, sizeof **points);
    cJSON_ArrayForEach(e, a)
        read_point(e, &(*points)[n++]);
    return n;
}

void tuned_free(struct tuned *tu)
{
    for (int i = 0; i < tu->fold_count; i++)
        free(tu->fold_settings[i]);
    free(tu->fold_settings), free(tu->fold_scene), free(tu->settings), free(tu->path);
    free(tu->kind_settings[0]), free(tu->kind_settings[1]);
    cJSON_Delete(tu->doc);
    memset(tu, 0, sizeof *tu);
}
