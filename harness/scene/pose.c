#include "pose.h"
#include "base/util.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
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
        L->half_angle *= p->light_scale;  /* the sun's */
    }
    out->camera.pos = v3_add(out->camera.pos, v3_scale(out->camera.x, p->camera_shift));
    if (p->camera_yaw_rad != 0) {  /* about its y: x and z turn in their plane */
        struct scene_camera *c = &out->camera;
        const float cs = cosf(p->camera_yaw_rad), sn = sinf(p->camera_yaw_rad);
        const struct vec3 x = c->x, z = c->z;
        c->x = v3_normalize(v3_add(v3_scale(x, cs), v3_scale(z, -sn)));
        c->z = v3_normalize(v3_cross(c->x, c->y));
    }
    const struct scene_node *n = NULL;
    if (p->caster) {
        assert(p->caster > 0 && (size_t)p->caster <= base->node_count);
        n = &base->nodes[p->caster - 1];
        const struct vec3 d = v3_scale(base->light.x, p->caster_shift);
        out->positions = memcpy(xmalloc(sizeof(float) * 3 * base->vertex_count), base->positions,
                                sizeof(float) * 3 * base->vertex_count);
        for (size_t v = n->first_vertex; v < n->first_vertex + n->vertex_count; v++) {
            float *q = &out->positions[3 * v];
            q[0] += d.x, q[1] += d.y, q[2] += d.z;
        }
        out->bounds_min = v3(INFINITY, INFINITY, INFINITY), out->bounds_max = v3(-INFINITY, -INFINITY, -INFINITY);
        for (size_t v = 0; v < base->vertex_count; v++) {
            const float *q = &out->positions[3 * v];
            out->bounds_min = v3_min(out->bounds_min, v3(q[0], q[1], q[2]));
            out->bounds_max = v3_max(out->bounds_max, v3(q[0], q[1], q[2]));
        }
    }
    const struct scene_pose zero = {0};
    if (memcmp(p, &zero, sizeof zero) != 0)  /* the base pose is the scene itself */
        out->hash = util_hash(base->hash, p, sizeof *p);
    if (n) {  /* the vertices moved, not only the node's index in the loader's order */
        const size_t range[2] = {n->first_vertex, n->vertex_count};
        out->hash = util_hash(out->hash, range, sizeof range);
    }
}

void scene_unpose(struct scene *posed, const struct scene *base)
{
    if (posed->positions != base->positions)
        free(posed->positions);
    posed->positions = base->positions;
}

int pose_find_node(const struct scene *s, const char *name, int *count)
{
    int found = -1, n = 0;
    for (size_t i = 0; i < s->node_count; i++)
        if (!strcmp(s->nodes[i].name, name))
            found = (int)i, n++;
    if (count)
        *count = n;
    return n == 1 ? found : -1;
}

float pose_light_depth_of_node(const struct scene *s, int node)
{
    const struct scene_node *n = &s->nodes[node];
    struct vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t v = n->first_vertex; v < n->first_vertex + n->vertex_count; v++) {
        const float *q = &s->positions[3 * v];
        lo = v3_min(lo, v3(q[0], q[1], q[2])), hi = v3_max(hi, v3(q[0], q[1], q[2]));
    }
    return -v3_dot(v3_sub(v3_scale(v3_add(lo, hi), 0.5f), s->light.pos), s->light.z);
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

/* Rodrigues: a turned by angle about the unit axis k. */
static struct vec3 turn(struct vec3 a, struct vec3 k, float angle)
{
    const float c = cosf(angle), s = sinf(angle);
    return v3_add(v3_add(v3_scale(a, c), v3_scale(v3_cross(k, a), s)), v3_scale(k, v3_dot(k, a) * (1 - c)));
}

struct scene scene_orbited(const struct scene *base, const struct scene_orbit *p, float extent)
{
    struct scene s = *base;
    struct scene_light *L = &s.light;
    if (L->shape == LIGHT_SUN && (p->light_dx != 0 || p->light_dy != 0)) {
        /* the sun turns (yaw and pitch) as a light a scene's extent away would
         * move in its plane: its direction towards that moved point */
        L->z = v3_normalize(v3_add(v3_scale(L->z, extent),
                                   v3_add(v3_scale(L->x, p->light_dx), v3_scale(L->y, p->light_dy))));
        L->x = v3_normalize(v3_sub(L->x, v3_scale(L->z, v3_dot(L->x, L->z))));
        L->y = v3_cross(L->z, L->x);
    } else {
        L->pos = v3_add(L->pos, v3_add(v3_scale(L->x, p->light_dx), v3_scale(L->y, p->light_dy)));
    }
    if (p->yaw == 0 && p->pitch == 0 && p->dolly == 0)
        return s;  /* the scene's own camera, bit for bit */
    struct scene_camera *c = &s.camera;
    const struct vec3 mid = centre(&s);
    const float along = fmaxf(v3_dot(v3_sub(c->pos, mid), c->z), 1e-3f * extent);
    /* yaw about the world's up (glTF's +y), or the camera's own up when it looks along it */
    const struct vec3 target = v3_sub(c->pos, v3_scale(c->z, along));
    const struct vec3 up = fabsf(c->z.y) < 0.99f ? v3(0, 1, 0) : c->y;
    struct vec3 arm = v3_sub(c->pos, target);
    arm = turn(arm, up, p->yaw), c->x = turn(c->x, up, p->yaw), c->y = turn(c->y, up, p->yaw), c->z = turn(c->z, up, p->yaw);
    arm = turn(arm, c->x, p->pitch), c->y = turn(c->y, c->x, p->pitch), c->z = turn(c->z, c->x, p->pitch);
    c->pos = v3_add(target, v3_scale(arm, expf(p->dolly)));
    return s;
}
