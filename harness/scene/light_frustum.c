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

const char *const cascade_split_names[] = {
#define X(id, name) name,
    CASCADE_SPLITS(X)
#undef X
    NULL};

/* What the camera sees of s between view depths z_lo and z_hi (INFINITY:
 * no far plane), in the sun's light space (view): the box of the geometry
 * clipped to that slice of the camera's frustum, its farthest light-space
 * depth and its nearest, and the farthest view depth. Returns false when
 * nothing is seen. */
struct seen {
    float x_lo, x_hi, y_lo, y_hi, d_lo, d_hi, z_hi;
};
static bool see(const struct scene *s, float aspect, float z_lo, float z_hi, const struct mat4 *view,
                struct seen *out)
{
    const struct scene_camera *c = &s->camera;
    /* The camera's planes, normals inwards: near, top, bottom, right, left, far. */
    const float ty = tanf(0.5f * c->yfov_rad), tx = ty * (aspect > 0 ? aspect : 1.0f);
    const struct vec3 fwd = v3_scale(c->z, -1.0f);
    const struct vec3 pn[6] = {fwd, v3_sub(v3_scale(fwd, ty), c->y), v3_add(v3_scale(fwd, ty), c->y),
                               v3_sub(v3_scale(fwd, tx), c->x), v3_add(v3_scale(fwd, tx), c->x),
                               v3_scale(fwd, -1.0f)};
    float pd[6];
    for (int k = 0; k < 5; k++)
        pd[k] = v3_dot(pn[k], c->pos) + (k == 0 ? z_lo : 0.0f);
    pd[5] = -(v3_dot(fwd, c->pos) + z_hi);
    const int planes = isinf(z_hi) ? 5 : 6;
    *out = (struct seen){INFINITY, -INFINITY, INFINITY, -INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (size_t t = 0; t < s->triangle_count; t++) {
        struct vec3 poly[2][20];  /* a triangle clipped by six planes: 9 corners, with room for rounding */
        int n = 3;
        for (int k = 0; k < 3; k++) {
            const float *p = &s->positions[3 * s->indices[3 * t + k]];
            poly[0][k] = v3(p[0], p[1], p[2]);
        }
        for (int k = 0; k < planes && n > 0; k++)
            n = clip_plane(poly[k & 1], n, pn[k], pd[k], poly[(k + 1) & 1]);
        for (int k = 0; k < n; k++) {
            const struct vec3 w = poly[planes & 1][k];
            const struct vec3 q = m4_point(*view, w);
            out->x_lo = fminf(out->x_lo, q.x), out->x_hi = fmaxf(out->x_hi, q.x);
            out->y_lo = fminf(out->y_lo, q.y), out->y_hi = fmaxf(out->y_hi, q.y);
            out->d_lo = fminf(out->d_lo, -q.z), out->d_hi = fmaxf(out->d_hi, -q.z);
            out->z_hi = fmaxf(out->z_hi, v3_dot(fwd, v3_sub(w, c->pos)));
        }
    }
    return !isinf(out->d_hi);
}

/* The sun's view: its origin a scene's extent above the light's position
 * along the sun (the loader puts it at the scene's centre, and only
 * `light_shift` moves it). Moving it moves the map's texel grid and
 * nothing else; turning the sun turns the map about the scene. */
static struct mat4 sun_view(const struct scene *s)
{
    const struct scene_light *L = &s->light;
    const struct vec3 mid = v3_scale(v3_add(s->bounds_min, s->bounds_max), 0.5f);
    const struct vec3 o = v3_add(v3_sub(L->pos, v3_scale(L->z, v3_dot(v3_sub(L->pos, mid), L->z))),
                                 v3_scale(L->z, scene_extent(s)));
    return m4_view(o, L->x, L->y, L->z);
}

/* The sun's map over one slice of the view, [z_lo, z_hi] in view depth
 * (docs/design.md §5, docs/cascades.md): orthographic along the sun. Box
 * fit: the window fitted to what the camera sees in the slice (the
 * geometry inside it, for images of the given aspect). Sphere fit: a
 * square about the slice's bounding sphere. Either widened by the
 * farthest a blocker of a visible receiver can lie beside it, (depth
 * range) tan(alpha); snapped, moved to whole texels of an n x n map. The
 * depth range runs from the nearest caster over the window (with depth
 * clamp, the nearest receiver: casters in front are clamped onto the near
 * plane) to the farthest visible point. */
static int fit_sun(const struct scene *s, float aspect, const struct cascade_settings *cs, float z_lo,
                   float z_hi, int n, struct light_frustum *f)
{
    const struct scene_light *L = &s->light;
    const struct scene_camera *c = &s->camera;
    const float extent = scene_extent(s);
    f->sun = 1;
    f->view = sun_view(s);
    struct seen v;
    if (!see(s, aspect, z_lo, z_hi, &f->view, &v)) {
        log_error("%s: the camera sees no geometry to fit the sun's shadow map to (view depths %g to %g)",
                  s->path, (double)z_lo, (double)z_hi);
        return -1;
    }
    const float tan_a = tanf(L->half_angle);
    float d_lo, d_hi = v.d_hi;
    if (cs->fit == CASCADE_FIT_SPHERE) {
        /* The slice's bounding sphere: its centre on the view axis where
         * the near and far corners are equally far, at most the far end. */
        const float ty = tanf(0.5f * c->yfov_rad), tx = ty * (aspect > 0 ? aspect : 1.0f), k = tx * tx + ty * ty;
        const float zf = isinf(z_hi) ? v.z_hi : z_hi;
        const float zc = fminf(0.5f * (zf + z_lo) * (1.0f + k), zf);
        const float radius = fmaxf(sqrtf((zc - z_lo) * (zc - z_lo) + z_lo * z_lo * k),
                                   sqrtf((zf - zc) * (zf - zc) + zf * zf * k));
        const struct vec3 q = m4_point(f->view, v3_add(c->pos, v3_scale(c->z, -zc)));
        const float half = radius * (1.0f + 2.0f * tan_a);  /* widened by the sphere's depth times tan(alpha) */
        f->l = q.x - half, f->r = q.x + half, f->b = q.y - half, f->t = q.y + half;
        d_hi = -q.z + radius;
        d_lo = cs->depth_clamp ? -q.z - radius : caster_depth(s, f);
    } else {
        /* Margins as the area light's: 1% of the window, 0.1% of the depths. */
        const float mx = 0.01f * (v.x_hi - v.x_lo) + 1e-6f * extent, my = 0.01f * (v.y_hi - v.y_lo) + 1e-6f * extent;
        f->l = v.x_lo - mx, f->r = v.x_hi + mx, f->b = v.y_lo - my, f->t = v.y_hi + my;
        /* Every caster between the window and the sun: the nearest depth of
         * any triangle whose light-space box meets the window; then the
         * window widened by the farthest a blocker of a visible receiver
         * can lie beside it, (d_hi - d_lo) tan(alpha), and the casters over
         * that. With depth clamp the depths start at the receivers. */
        d_lo = cs->depth_clamp ? v.d_lo : caster_depth(s, f);
        const float reach = (d_hi - d_lo) * tan_a;
        f->l -= reach, f->r += reach, f->b -= reach, f->t += reach;
        if (!cs->depth_clamp)
            d_lo = caster_depth(s, f);
    }
    if (cs->snap && n > 0) {
        /* Whole texels of a grid fixed in the sun's frame; and the depth
         * range in steps of 1/64 of the window, so that it too changes only
         * now and then (every depth in the map moves when it does). */
        const float tx = (f->r - f->l) / (float)n, ty = (f->t - f->b) / (float)n;
        const float l = floorf(f->l / tx) * tx, b = floorf(f->b / ty) * ty;
        f->r += l - f->l, f->l = l, f->t += b - f->b, f->b = b;
        const float step = (f->r - f->l) / 64.0f;
        d_lo = floorf(d_lo / step) * step, d_hi = ceilf(d_hi / step) * step;
    }
    const float margin = 1e-3f * fmaxf(d_hi - d_lo, 1e-3f * extent);
    f->near_world = d_lo - margin;
    f->far_world = d_hi + margin;
    project(f, L);
    return 0;
}

int light_frustum_splits(const struct scene *s, float aspect, const struct cascade_settings *cs, float *z)
{
    const int n = cs->count > 0 ? cs->count : 1;
    const float z_near = s->camera.znear;
    float z_far = cs->shadow_distance;
    if (!(z_far > 0)) {
        if (n == 1) {
            z[0] = z_near, z[1] = INFINITY;
            return 1;
        }
        const struct mat4 view = sun_view(s);
        struct seen v;
        if (!see(s, aspect, z_near, INFINITY, &view, &v)) {
            log_error("%s: the camera sees no geometry to cut into cascades", s->path);
            return -1;
        }
        z_far = v.z_hi * 1.001f;
    }
    if (!(z_far > z_near)) {
        log_error("%s: the shadow distance %g is not beyond the camera's near plane %g", s->path, (double)z_far,
                  (double)z_near);
        return -1;
    }
    z[0] = z_near, z[n] = z_far;
    for (int i = 1; i < n; i++) {
        const double t = (double)i / n;
        const double lin = z_near + (z_far - z_near) * t, lg = z_near * pow(z_far / z_near, t);
        switch (cs->split) {
        case CASCADE_SPLIT_UNIFORM: z[i] = (float)lin; break;
        case CASCADE_SPLIT_LOG: z[i] = (float)lg; break;
        case CASCADE_SPLIT_PRACTICAL: z[i] = (float)(cs->lambda * lg + (1.0 - cs->lambda) * lin); break;
        case CASCADE_SPLIT_FRACTIONS: z[i] = z_far * cs->fractions[i - 1]; break;
        }
    }
    for (int i = 0; i < n; i++)
        if (!(z[i + 1] > z[i])) {
            log_error("%s: cascade %d's slice is empty (view depths %g to %g): the splits must increase "
                      "beyond the camera's near plane %g", s->path, i, (double)z[i], (double)z[i + 1],
                      (double)z_near);
            return -1;
        }
    return n;
}

float light_frustum_band(const struct cascade_settings *cs, const float *z, int c)
{
    const int n = cs->count > 0 ? cs->count : 1;
    return c < n - 1 ? cs->blend * (z[c + 1] - z[c]) : 0.0f;
}

int light_frustum_fit_cascade(const struct scene *s, float aspect, const struct cascade_settings *cs,
                              const float *z, int c, int n, struct light_frustum *f)
{
    memset(f, 0, sizeof *f);
    const float z_lo = c > 0 ? z[c] - light_frustum_band(cs, z, c - 1) : z[0];
    return fit_sun(s, aspect, cs, z_lo, z[c + 1], n, f);
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
        return fit_sun(s, aspect, &(struct cascade_settings){0}, s->camera.znear, INFINITY, 0, f);
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

void light_frustum_set_window(struct light_frustum *f, const struct scene *s, const struct light_frustum *window)
{
    const float k = f->sun ? 1.0f : f->near_world / window->near_world;  /* the sun's window: world units */
    f->l = window->l * k, f->r = window->r * k, f->b = window->b * k, f->t = window->t * k;
    project(f, &s->light);
}

void light_frustum_texel_ratio(struct light_frustum *f, const struct light_frustum *first)
{
    const float k = (first->far_world - first->near_world) / (f->far_world - f->near_world);
    f->light_size_uv[0] = first->light_size_uv[0] * k;
    f->light_size_uv[1] = first->light_size_uv[1] * k;
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

float light_frustum_cone_tan(const struct scene *s, const struct light_frustum *f)
{
    /* the window at unit depth: half-planes n . (u, v) >= d */
    const float k = 1.0f / f->near_world;
    const struct vec3 n[4] = {v3(1, 0, 0), v3(-1, 0, 0), v3(0, 1, 0), v3(0, -1, 0)};
    const float d[4] = {f->l * k, -f->r * k, f->b * k, -f->t * k};
    float cone = 0;
    for (size_t t = 0; t < s->triangle_count; t++) {
        struct light_point tri[3], front[4];
        for (int j = 0; j < 3; j++) {
            const float *p = &s->positions[3 * s->indices[3 * t + j]];
            const struct vec3 q = m4_point(f->view, v3(p[0], p[1], p[2]));
            tri[j] = (struct light_point){q.x, q.y, -q.z};
        }
        struct vec3 poly[2][12];  /* a triangle clipped by five planes: 8 corners, with room for rounding */
        int count = clip_front(tri, f->near_world, front);
        for (int j = 0; j < count; j++)
            poly[0][j] = v3(front[j].x / front[j].d, front[j].y / front[j].d, 0);
        for (int j = 0; j < 4 && count > 0; j++)
            count = clip_plane(poly[j & 1], count, n[j], d[j], poly[(j + 1) & 1]);
        for (int j = 0; j < count; j++)  /* a convex polygon's farthest point from the axis is a corner */
            cone = fmaxf(cone, hypotf(poly[0][j].x, poly[0][j].y));
    }
    return cone;
}

float light_frustum_view_far(const struct scene *s, float aspect)
{
    struct seen v;
    const struct mat4 identity = m4_identity();
    return see(s, aspect, s->camera.znear, INFINITY, &identity, &v) ? v.z_hi : -1.0f;
}
