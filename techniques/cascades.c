/* Cascaded shadow maps (docs/cascades.md): the slices, their fits and their
 * maps; the receiver's blending is render/receiver.c's. */
#include "cascades.h"
#include "base/log.h"

#include <math.h>
#include <string.h>

/* The frusta of every map of s, frame window's windows kept when given:
 * the view's (one map over all of it), then each cascade's. */
static int fit_all(struct shadow_cascades *c, const struct scene *s, const struct shadowmap_desc *desc,
                   const struct shadow_cascades *window, struct light_frustum *maps)
{
    if (light_frustum_fit(s, c->aspect, &c->view) != 0)
        return -1;
    if (window)
        light_frustum_set_window(&c->view, s, &window->view);
    if (desc->near_scale > 1)
        light_frustum_widen(&c->view, s, desc->near_scale);
    if (s->light.shape != LIGHT_SUN) {  /* one perspective map: the view's */
        c->count = 1, c->z[0] = s->camera.znear, c->z[1] = INFINITY, c->band[0] = 0;
        maps[0] = c->view;
        return 0;
    }
    c->count = light_frustum_splits(s, c->aspect, &c->settings, c->z);
    if (c->count < 1)
        return -1;
    for (int k = 0; k < c->count; k++) {
        c->band[k] = light_frustum_band(&c->settings, c->z, k);
        if (light_frustum_fit_cascade(s, c->aspect, &c->settings, c->z, k, desc->size_texels, &maps[k]) != 0)
            return -1;
        if (window)
            light_frustum_set_window(&maps[k], s, &window->map[k].frustum);
        if (desc->near_scale > 1)
            light_frustum_widen(&maps[k], s, desc->near_scale);
        if (k > 0 && c->settings.width == CASCADE_WIDTH_TEXEL)
            light_frustum_texel_ratio(&maps[k], &maps[0]);
    }
    return 0;
}

int shadow_cascades_create(struct shadow_cascades *c, const struct scene *s, const struct shadowmap_desc *desc,
                           const struct cascade_settings *cs)
{
    memset(c, 0, sizeof *c);
    if (cs)
        c->settings = *cs;
    c->aspect = desc->aspect > 0 ? desc->aspect : 1.0f;
    struct shadowmap_desc d = *desc;
    if (!d.size_texels)
        d.size_texels = SHADOWMAP_DEFAULT_SIZE;
    struct light_frustum maps[CASCADES_MAX];
    if (fit_all(c, s, &d, NULL, maps) != 0)
        return -1;
    c->settings.count = c->count;
    d.depth_clamp = s->light.shape == LIGHT_SUN && c->settings.depth_clamp;
    for (int k = 0; k < c->count; k++) {
        d.frustum = &maps[k];
        if (shadowmap_create(&c->map[k], s, &d) != 0)
            return -1;
    }
    return 0;
}

int shadow_cascades_refit(struct shadow_cascades *c, const struct scene *s, const struct shadow_cascades *window)
{
    struct light_frustum maps[CASCADES_MAX];
    const int count = c->count;
    if (fit_all(c, s, &c->map[0].desc, window, maps) != 0)
        return -1;
    if (c->count != count) {
        log_error("%s: %d cascades in this pose, %d before", s->path, c->count, count);
        return -1;
    }
    for (int k = 0; k < c->count; k++)
        shadowmap_set_frustum(&c->map[k], s, &maps[k]);
    return 0;
}

cJSON *cascade_settings_json(const struct cascade_settings *cs)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "cascades", cs->count > 0 ? cs->count : 1);
    cJSON_AddStringToObject(o, "split", cascade_split_names[cs->split]);
    if (cs->split == CASCADE_SPLIT_PRACTICAL)
        cJSON_AddNumberToObject(o, "lambda", cs->lambda);
    if (cs->split == CASCADE_SPLIT_FRACTIONS) {
        cJSON *f = cJSON_AddArrayToObject(o, "fractions");
        for (int i = 0; i + 1 < cs->count; i++)
            cJSON_AddItemToArray(f, cJSON_CreateNumber(cs->fractions[i]));
    }
    if (cs->shadow_distance > 0)
        cJSON_AddNumberToObject(o, "shadow_distance", cs->shadow_distance);
    else
        cJSON_AddStringToObject(o, "shadow_distance", "view");
    cJSON_AddStringToObject(o, "fit", cs->fit == CASCADE_FIT_SPHERE ? "sphere" : "box");
    cJSON_AddBoolToObject(o, "snap", cs->snap);
    cJSON_AddNumberToObject(o, "blend", cs->blend);
    cJSON_AddBoolToObject(o, "depth_clamp", cs->depth_clamp);
    cJSON_AddStringToObject(o, "width", cs->width == CASCADE_WIDTH_TEXEL ? "texel" : "world");
    return o;
}

cJSON *shadow_cascades_json(const struct shadow_cascades *c, bool sun)
{
    cJSON *o = cascade_settings_json(&c->settings);
    cJSON_AddBoolToObject(o, "applied", sun);
    if (!sun)
        return o;
    cJSON *maps = cJSON_AddArrayToObject(o, "maps");
    for (int k = 0; k < c->count; k++) {
        const struct light_frustum *f = &c->map[k].frustum;
        cJSON *m = cJSON_CreateObject();
        cJSON_AddNumberToObject(m, "from", c->z[k]);
        if (isfinite(c->z[k + 1]))
            cJSON_AddNumberToObject(m, "to", c->z[k + 1]);
        else
            cJSON_AddNullToObject(m, "to");  /* the whole view */
        cJSON_AddNumberToObject(m, "band", c->band[k]);
        cJSON_AddNumberToObject(m, "window", f->r - f->l);
        cJSON_AddNumberToObject(m, "texel", (f->r - f->l) / (float)c->map[k].desc.size_texels);
        cJSON_AddNumberToObject(m, "depth_range", f->far_world - f->near_world);
        cJSON_AddItemToArray(maps, m);
    }
    return o;
}

void shadow_cascades_destroy(struct shadow_cascades *c)
{
    for (int k = 0; k < CASCADES_MAX; k++)
        shadowmap_destroy(&c->map[k]);
    memset(c, 0, sizeof *c);
}
