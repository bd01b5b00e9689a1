/* Just the vector and matrix algebra the harness needs. Matrices are
 * column-major (m[col * 4 + row]) as GL expects. */
#ifndef SB_VECMATH_H
#define SB_VECMATH_H

#include <math.h>

struct vec3 { float x, y, z; };
struct mat4 { float m[16]; };

static inline struct vec3 v3(float x, float y, float z) { return (struct vec3){x, y, z}; }
static inline struct vec3 v3_add(struct vec3 a, struct vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline struct vec3 v3_sub(struct vec3 a, struct vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline struct vec3 v3_scale(struct vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline float v3_dot(struct vec3 a, struct vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline struct vec3 v3_cross(struct vec3 a, struct vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float v3_length(struct vec3 a) { return sqrtf(v3_dot(a, a)); }
static inline struct vec3 v3_normalize(struct vec3 a)
{
    float l = v3_length(a);
    return l > 0.0f ? v3_scale(a, 1.0f / l) : a;
}
static inline struct vec3 v3_min(struct vec3 a, struct vec3 b) { return v3(fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)); }
static inline struct vec3 v3_max(struct vec3 a, struct vec3 b) { return v3(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)); }

static inline struct mat4 m4_identity(void)
{
    return (struct mat4){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
}

static inline struct mat4 m4_mul(struct mat4 a, struct mat4 b)
{
    struct mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++)
                s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

static inline struct vec3 m4_point(struct mat4 a, struct vec3 p)
{
    return v3(a.m[0] * p.x + a.m[4] * p.y + a.m[8] * p.z + a.m[12],
              a.m[1] * p.x + a.m[5] * p.y + a.m[9] * p.z + a.m[13],
              a.m[2] * p.x + a.m[6] * p.y + a.m[10] * p.z + a.m[14]);
}

static inline struct vec3 m4_vector(struct mat4 a, struct vec3 v)
{
    return v3(a.m[0] * v.x + a.m[4] * v.y + a.m[8] * v.z,
              a.m[1] * v.x + a.m[5] * v.y + a.m[9] * v.z,
              a.m[2] * v.x + a.m[6] * v.y + a.m[10] * v.z);
}

/* World-to-frame matrix of an orthonormal frame (origin o, axes x, y, z). */
static inline struct mat4 m4_view(struct vec3 o, struct vec3 x, struct vec3 y, struct vec3 z)
{
    return (struct mat4){{x.x, y.x, z.x, 0, x.y, y.y, z.y, 0, x.z, y.z, z.z, 0,
                          -v3_dot(x, o), -v3_dot(y, o), -v3_dot(z, o), 1}};
}

/* Off-centre perspective with reversed Z for glClipControl(GL_ZERO_TO_ONE):
 * depth 1 at the near plane, 0 at the far plane. l, r, b, t are the window
 * at the near plane. far = INFINITY gives an infinite far plane. */
static inline struct mat4 m4_frustum_reversed_z(float l, float r, float b, float t, float n, float f)
{
    float a = isinf(f) ? 0.0f : n / (f - n);
    float c = isinf(f) ? n : n * f / (f - n);
    return (struct mat4){{2 * n / (r - l), 0, 0, 0,
                          0, 2 * n / (t - b), 0, 0,
                          (r + l) / (r - l), (t + b) / (t - b), a, -1,
                          0, 0, c, 0}};
}

/* Orthographic with reversed Z for glClipControl(GL_ZERO_TO_ONE): depth 1
 * at the near plane, 0 at the far plane, linear between. l, r, b, t: the
 * window; n, f: planar depths (the view looks along -z). */
static inline struct mat4 m4_ortho_reversed_z(float l, float r, float b, float t, float n, float f)
{
    return (struct mat4){{2 / (r - l), 0, 0, 0,
                          0, 2 / (t - b), 0, 0,
                          0, 0, 1 / (f - n), 0,
                          -(r + l) / (r - l), -(t + b) / (t - b), f / (f - n), 1}};
}

#endif
