/* Cascaded shadow maps (docs/cascades.md): the shared layer's maps for one
 * scene, one per slice of the camera's view for the sun, each a whole
 * shadow map with every product (shadowmap.h). An area light has one
 * perspective map and the cascade settings do not apply to it. The
 * receiver runs once per cascade (as Unreal projects each cascade in its
 * own pass) and a pixel runs the technique only in the cascades that weigh
 * it (render/receiver.h). */
#ifndef SB_CASCADES_H
#define SB_CASCADES_H

#include "shadowmap.h"

#include <cjson/cJSON.h>
#include <stdbool.h>

struct shadow_cascades {
    struct cascade_settings settings;  /* as given, count filled (1 for an area light) */
    int count;
    float z[CASCADES_MAX + 1];         /* the slices' view depths (light_frustum_splits) */
    float band[CASCADES_MAX];          /* each slice's blend band at its far end (view depth) */
    struct shadowmap map[CASCADES_MAX];
    struct light_frustum view;         /* one map over the whole view (light_frustum_fit): the ground
                                          truth's mask, and the frame a motion is measured in */
    float aspect;
};

/* Fits and creates the maps of s under settings cs (NULL: zero, one map
 * over the view). Returns 0 or -1 (logged); shadow_cascades_destroy
 * either way. */
int shadow_cascades_create(struct shadow_cascades *c, const struct scene *s, const struct shadowmap_desc *desc,
                           const struct cascade_settings *cs);

/* Fits them to s in another pose. window (the frame-0 maps, NULL: none)
 * keeps each map's window (light_frustum_set_window): a light's or a
 * caster's motion moves across a still grid; without it the sun's maps follow the
 * camera, as an engine refits them every frame. Returns 0 or -1 (logged). */
int shadow_cascades_refit(struct shadow_cascades *c, const struct scene *s, const struct shadow_cascades *window);

/* What c is, for run.json and every cell's metrics.json: the settings, and
 * for the sun the slices' view depths and each map's window and depth
 * range (world units); sun false: one perspective map, the settings not
 * applied. */
cJSON *shadow_cascades_json(const struct shadow_cascades *c, bool sun);

/* The settings alone (run.json). */
cJSON *cascade_settings_json(const struct cascade_settings *cs);

void shadow_cascades_destroy(struct shadow_cascades *c);

#endif
