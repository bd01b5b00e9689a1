/* The light's frustum (docs/design.md §5): pure math on the scene, shared by the
 * ground truth (its mask) and the shadow-map layer (its projection). */
#include "light_frustum.h"
#include "base/log.h"

#include <math.h>
#include <string.h>

struct light_point { float x, y, d; };  /* light space, d = planar depth (-z) */

/* Clips a triangle to d >= d_min (Sutherland-Hodgman against one plane). */
static int clip_front(const struct light_point in[3], float d_min, struct light_point out[4])
{
    int n = 0;
    for (int i = 0; i < 3; i++) {
        struct light_point a = in[i], b = in[(i + 1) % 3];
        bool a_in = a.d >= d_min, b_in = b.d >= d_min;
        if (a_in)
            out[n++] = a;
        if (a_in != b_in) {
            float t = (d_min - a.d) / (b.d - a.d);
            out[n++] = (struct light_point){a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), d_min};
        }
    }
    return n;
}

/* The projection and the light's size at the near plane, from the window. */
static void project(struct light_frustum *f, const struct scene_light *L)
{
    struct mat4 proj = m4_frustum_reversed_z(f->l, f->r, f->b, f->t, f->near_world, f->far_world);
    f->view_proj = m4_mul(proj, f->view);
    f->light_size_uv[0] = L->width / (f->r - f->l);  /* a disk's: its diameter */
    f->light_size_uv[1] = L->height / (f->t - f->b);
}

int light_frustum_fit(const struct scene *s, struct light_frustum *f)
{
    const struct scene_light *L = &s->light;
    memset(f, 0, sizeof *f);
    f->view = m4_view(L->pos, L->x, L->y, L->z);

    const float d_clip = 1e-4f * scene_extent(s);  /* keeps x/d finite at the light plane */
    const float t_max = (float)tan(LIGHT_FRUSTUM_MAX_HALF_ANGLE_DEG * M_PI / 180.0);
    float tx_lo = INFINITY, tx_hi = -INFINITY, ty_lo = INFINITY, ty_hi = -INFINITY;
    float d_lo = INFINITY, d_hi = 0;
    for (size_t t = 0; t < s->triangle_count; t++) {
        struct light_point tri[3], poly[4];
        for (int k = 0; k < 3; k++) {
            const float *p = &s->positions[3 * s->indices[3 * t + k]];
            struct vec3 q = m4_point(f->view, v3(p[0], p[1], p[2]));
            tri[k] = (struct light_point){q.x, q.y, -q.z};
        }
        int n = clip_front(tri, d_clip, poly);
        for (int k = 0; k < n; k++) {
            float tx = fminf(fmaxf(poly[k].x / poly[k].d, -t_max), t_max);
            float ty = fminf(fmaxf(poly[k].y / poly[k].d, -t_max), t_max);
            tx_lo = fminf(tx_lo, tx), tx_hi = fmaxf(tx_hi, tx);
            ty_lo = fminf(ty_lo, ty), ty_hi = fmaxf(ty_hi, ty);
            d_lo = fminf(d_lo, poly[k].d), d_hi = fmaxf(d_hi, poly[k].d);
        }
    }
    if (isinf(d_lo)) {  /* nothing survived the clip: all of it is behind the light */
        log_error("%s: no geometry in front of the area light (it emits towards its local -Z)",
                  s->path);
        return -1;
    }
    /* Margins: 0.1% in depth so nothing clips at near/far, 1% of the window
     * so the outermost geometry is not sampled on the border texel. */
    f->near_world = fmaxf(d_lo * 0.999f, d_clip);
    f->far_world = d_hi * 1.001f;
    float mx = 0.01f * (tx_hi - tx_lo), my = 0.01f * (ty_hi - ty_lo);
    f->l = (fmaxf(tx_lo - mx, -t_max)) * f->near_world;
    f->r = (fminf(tx_hi + mx, t_max)) * f->near_world;
    f->b = (fmaxf(ty_lo - my, -t_max)) * f->near_world;
    f->t = (fminf(ty_hi + my, t_max)) * f->near_world;
    project(f, L);
    return 0;
}

int light_frustum_fit_window(const struct scene *s, const struct light_frustum *window, struct light_frustum *f)
{
    if (light_frustum_fit(s, f) != 0)
        return -1;
    const float k = f->near_world / window->near_world;
    f->l = window->l * k, f->r = window->r * k, f->b = window->b * k, f->t = window->t * k;
    project(f, &s->light);
    return 0;
}

void light_frustum_widen(struct light_frustum *f, const struct scene *s, float k)
{
    f->l /= k, f->r /= k, f->b /= k, f->t /= k;
    f->near_world /= k;
    project(f, &s->light);
}

float light_frustum_search_box_texels(const struct light_frustum *f, float light_size_scale, int n)
{
    float size_uv = fmaxf(f->light_size_uv[0], f->light_size_uv[1]) * light_size_scale;
    return size_uv * (1.0f - f->near_world / f->far_world) * (float)n;
}

bool light_frustum_inside(const struct light_frustum *f, struct vec3 p)
{
    struct vec3 q = m4_point(f->view, p);
    float d = -q.z;
    if (!(d >= f->near_world && d <= f->far_world))
        return false;
    float x = q.x * f->near_world / d, y = q.y * f->near_world / d;
    return x >= f->l && x <= f->r && y >= f->b && y <= f->t;
}
