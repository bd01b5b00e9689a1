/* The closed-form parallel-planes scene (tools/scene_library.h) written to a
 * file, with a light of any width: the shipped parallel_planes scenes are
 * light_width 1. */
#ifndef SB_PARALLEL_PLANES_H
#define SB_PARALLEL_PLANES_H

#include "check.h"
#include "scene_library.h"

static inline void write_parallel_planes(const char *path, float light_width, bool disk)
{
    struct mesh_builder m = {0};
    struct gltf_scene_desc d;
    scene_parallel_planes(&m, &d, light_width, disk);
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

/* The sun's parallel planes (scene_sun_parallel_planes) at angular_diameter_deg, written to path. */
static inline void write_sun_parallel_planes(const char *path, double angular_diameter_deg)
{
    struct mesh_builder m = {0};
    struct gltf_scene_desc d;
    scene_sun_parallel_planes(&m, &d, angular_diameter_deg);
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

/* The surface point pixel i of a w x h ground truth sees: its camera ray
 * through the pixel's centre, distance along it (the ray tracer's). */
static inline struct vec3 pixel_hit(const struct scene_camera *c, int i, int w, int h, float distance)
{
    const float t = tanf(0.5f * c->yfov_rad);
    const float sx = (2.0f * ((float)(i % w) + 0.5f) / (float)w - 1.0f) * t;
    const float sy = (1.0f - 2.0f * ((float)(i / w) + 0.5f) / (float)h) * t;
    const struct vec3 d = v3_normalize(v3_add(v3_add(v3_scale(c->x, sx), v3_scale(c->y, sy)), v3_scale(c->z, -1.0f)));
    return v3_add(c->pos, v3_scale(d, distance));
}

#endif
