#include "pose.h"
#include "base/util.h"

#include <math.h>
#include <string.h>

void scene_posed(const struct scene *base, const struct scene_pose *p, struct scene *out)
{
    *out = *base;
    struct scene_light *L = &out->light;
    L->pos = v3_add(L->pos, v3_scale(L->x, p->light_shift));
    if (p->light_turn_rad != 0) {  /* about y: x and z turn in their plane, still orthonormal */
        const float c = cosf(p->light_turn_rad), s = sinf(p->light_turn_rad);
        const struct vec3 x = L->x, z = L->z;
        L->x = v3_normalize(v3_add(v3_scale(x, c), v3_scale(z, -s)));
        L->z = v3_normalize(v3_cross(L->x, L->y));
    }
    if (p->light_scale > 0) {
        L->width *= p->light_scale, L->height *= p->light_scale, L->radius *= p->light_scale;
    }
    out->camera.pos = v3_add(out->camera.pos, v3_scale(out->camera.x, p->camera_shift));
    const struct scene_pose zero = {0};
    if (memcmp(p, &zero, sizeof zero) != 0)  /* the base pose is the scene itself */
        out->hash = util_hash(base->hash, p, sizeof *p);
}

float pose_texel_world(float window_world, float near_world, int size, float d)
{
    return window_world / (float)size * d / near_world;
}

static struct vec3 centre(const struct scene *s)
{
    return v3_scale(v3_add(s->bounds_min, s->bounds_max), 0.5f);
}

float pose_light_depth_of_centre(const struct scene *s)
{
    return -v3_dot(v3_sub(centre(s), s->light.pos), s->light.z);
}

float pose_pixel_world(const struct scene *s, int height)
{
    const float d = -v3_dot(v3_sub(centre(s), s->camera.pos), s->camera.z);
    return 2 * fabsf(d) * tanf(0.5f * s->camera.yfov_rad) / (float)height;
}
