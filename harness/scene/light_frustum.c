/* The light's frustum (docs/design.md §5): pure math on the scene, shared by the
 * ground truth (its mask) and the shadow-map layer (its projection):
 * perspective from an area light's centre, orthographic along the sun. */
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

/* The projection and the light's size in uv, from the window: an area
 * light's at the near plane; the sun's, the width of its cone in uv per
 * world unit of depth (2 tan alpha / window). */
static void project(struct light_frustum *f, const struct scene_light *L)
{
    struct mat4 proj = f->sun ? m4_ortho_reversed_z(f->l, f->r, f->b, f->t, f->near_world, f->far_world)
                              : m4_frustum_reversed_z(f->l, f->r, f->b, f->t, f->near_world, f->far_world);
    f->view_proj = m4_mul(proj, f->view);
    const float w = f->sun ? 2.0f * tanf(L->half_angle) : L->width;  /* a disk's: its diameter */
    const float h = f->sun ? w : L->height;
    f->light_size_uv[0] = w / (f->r - f->l);
    f->light_size_uv[1] = h / (f->t - f->b);
}

/* Clips a convex polygon (n corners, at most 8 after) to the half-space
 * n.p >= d (Sutherland-Hodgman). */
static int clip_plane(const struct vec3 *in, int count, struct vec3 n, float d, struct vec3 *out)
{
    int k = 0;
    for (int i = 0; i < count && k < 15; i++) {
        struct vec3 a = in[i], b = in[(i + 1) % count];
        float sa = v3_dot(n, a) - d, sb = v3_dot(n, b) - d;
        if (sa >= 0)
            out[k++] = a;
        if ((sa >= 0) != (sb >= 0))
            out[k++] = v3_add(a, v3_scale(v3_sub(b, a), sa / (sa - sb)));
    }
    return k;
}

static float caster_depth(const struct scene *s, const struct light_frustum *f);

/* The sun's map (docs/design.md §5): orthographic along the sun, its window
 * fitted to what the camera can see (the geometry inside its frustum, for
 * images of the given aspect), its depth range from the
 * nearest caster over that window to the farthest visible point. The view's
 * origin sits a scene's extent above the light's position along the sun
 * (the loader puts it at the scene's centre, and only `light_shift` moves
 * it): moving it moves the map's texel grid and nothing else, and turning
 * the sun turns the map about the scene. */
static int fit_sun(const struct scene *s, float aspect, struct light_frustum *f)
{
    const struct scene_light *L = &s->light;
    const struct scene_camera *c = &s->camera;
    const struct vec3 mid = v3_scale(v3_add(s->bounds_min, s->bounds_max), 0.5f);
    const float extent = scene_extent(s);
    const struct vec3 o = v3_add(v3_sub(L->pos, v3_scale(L->z, v3_dot(v3_sub(L->pos, mid), L->z))),
                                 v3_scale(L->z, extent));
    f->sun = 1;
    f->view = m4_view(o, L->x, L->y, L->z);
    /* The camera's planes, normals inwards: near, top, bottom, right, left. */
    const float ty = tanf(0.5f * c->yfov_rad), tx = ty * (aspect > 0 ? aspect : 1.0f);
    const struct vec3 fwd = v3_scale(c->z, -1.0f);
    const struct vec3 pn[5] = {fwd, v3_sub(v3_scale(fwd, ty), c->y), v3_add(v3_scale(fwd, ty), c->y),
                               v3_sub(v3_scale(fwd, tx), c->x), v3_add(v3_scale(fwd, tx), c->x)};
    float pd[5];
    for (int k = 0; k < 5; k++)
        pd[k] = v3_dot(pn[k], c->pos) + (k == 0 ? c->znear : 0.0f);
    float x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY, d_hi = -INFINITY;
    for (size_t t = 0; t < s->triangle_count; t++) {
        struct vec3 poly[2][16];  /* a triangle clipped by five planes: 8 corners, with room for rounding */
        int n = 3;
        for (int k = 0; k < 3; k++) {
            const float *p = &s->positions[3 * s->indices[3 * t + k]];
            poly[0][k] = v3(p[0], p[1], p[2]);
        }
        for (int k = 0; k < 5 && n > 0; k++)
            n = clip_plane(poly[k & 1], n, pn[k], pd[k], poly[(k + 1) & 1]);
        for (int k = 0; k < n; k++) {
            struct vec3 q = m4_point(f->view, poly[1][k]);  /* five clips end in poly[1] */
            x_lo = fminf(x_lo, q.x), x_hi = fmaxf(x_hi, q.x);
            y_lo = fminf(y_lo, q.y), y_hi = fmaxf(y_hi, q.y);
            d_hi = fmaxf(d_hi, -q.z);
        }
    }
    if (isinf(d_hi)) {
        log_error("%s: the camera sees no geometry to fit the sun's shadow map to", s->path);
        return -1;
    }
    /* Margins as the area light's: 1% of the window, 0.1% of the depths. */
    const float mx = 0.01f * (x_hi - x_lo) + 1e-6f * extent, my = 0.01f * (y_hi - y_lo) + 1e-6f * extent;
    f->l = x_lo - mx, f->r = x_hi + mx, f->b = y_lo - my, f->t = y_hi + my;
    /* Every caster between the window and the sun: the nearest depth of
     * any triangle whose light-space box meets the window; then the window
     * widened by the farthest a blocker of a visible receiver can lie
     * beside it, (d_hi - d_lo) tan(alpha), and the casters over that. */
    float d_lo = caster_depth(s, f);
    const float reach = (d_hi - d_lo) * tanf(L->half_angle);
    f->l -= reach, f->r += reach, f->b -= reach, f->t += reach;
    d_lo = caster_depth(s, f);
    const float margin = 1e-3f * fmaxf(d_hi - d_lo, 1e-3f * extent);
    f->near_world = d_lo - margin;
    f->far_world = d_hi + margin;
    project(f, L);
    return 0;
}

/* The nearest light-space depth of the triangles whose box meets f's window. */
static float caster_depth(const struct scene *s, const struct light_frustum *f)
{
    float d_lo = INFINITY;
    for (size_t t = 0; t < s->triangle_count; t++) {
        float bx_lo = INFINITY, bx_hi = -INFINITY, by_lo = INFINITY, by_hi = -INFINITY, bd = INFINITY;
        for (int k = 0; k < 3; k++) {
            const float *p = &s->positions[3 * s->indices[3 * t + k]];
            struct vec3 q = m4_point(f->view, v3(p[0], p[1], p[2]));
            bx_lo = fminf(bx_lo, q.x), bx_hi = fmaxf(bx_hi, q.x);
            by_lo = fminf(by_lo, q.y), by_hi = fmaxf(by_hi, q.y);
            bd = fminf(bd, -q.z);
        }
        if (bx_hi >= f->l && bx_lo <= f->r && by_hi >= f->b && by_lo <= f->t)
            d_lo = fminf(d_lo, bd);
    }
    return d_lo;
}

int light_frustum_fit(const struct scene *s, float aspect, struct light_frustum *f)
{
    const struct scene_light *L = &s->light;
    memset(f, 0, sizeof *f);
    if (L->shape == LIGHT_SUN)
        return fit_sun(s, aspect, f);
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

int light_frustum_fit_window(const struct scene *s, float aspect, const struct light_frustum *window,
                             struct light_frustum *f)
{
    if (light_frustum_fit(s, aspect, f) != 0)
        return -1;
    const float k = f->sun ? 1.0f : f->near_world / window->near_world;  /* the sun's window: world units */
    f->l = window->l * k, f->r = window->r * k, f->b = window->b * k, f->t = window->t * k;
    project(f, &s->light);
    return 0;
}

void light_frustum_widen(struct light_frustum *f, const struct scene *s, float k)
{
    if (f->sun) {  /* the depth range k times as deep towards the sun, the window kept */
        f->near_world = f->far_world - (f->far_world - f->near_world) * k;
    } else {
        f->l /= k, f->r /= k, f->b /= k, f->t /= k;
        f->near_world /= k;
    }
    project(f, &s->light);
}

float light_frustum_search_box_texels(const struct light_frustum *f, float light_size_scale, int n)
{
    float size_uv = fmaxf(f->light_size_uv[0], f->light_size_uv[1]) * light_size_scale;
    float depth = f->sun ? f->far_world - f->near_world : 1.0f - f->near_world / f->far_world;
    return size_uv * depth * (float)n;
}

float light_frustum_texel_world(const struct light_frustum *f, int n, float d)
{
    float texel = (f->r - f->l) / (float)n;
    return f->sun ? texel : texel * d / f->near_world;
}

bool light_frustum_inside(const struct light_frustum *f, struct vec3 p)
{
    struct vec3 q = m4_point(f->view, p);
    float d = -q.z;
    if (!(d >= f->near_world && d <= f->far_world))
        return false;
    float k = f->sun ? 1.0f : f->near_world / d;
    float x = q.x * k, y = q.y * k;
    return x >= f->l && x <= f->r && y >= f->b && y <= f->t;
}
