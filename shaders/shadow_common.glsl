// Shared by every technique: the shadow-map products, the receiver's
// description (ShadowInput), the depth conventions of DESIGN.md §5, and the
// helpers the PCF/PCSS family shares (sample patterns, receiver-plane depth
// bias, the PCSS geometry).
//
// Depth conventions: `depth` is linear light-space planar depth rescaled to
// [0, 1] between the frustum's near and far planes; the D32F map stores
// hardware depth with reversed Z (1 at near, 0 at far), converted by
// sm_linear_depth() and back by sm_hw_depth(). Hardware depth is an affine
// function of the map's uv over any plane (it is affine in 1/z), linear depth
// is not: so receiver planes are fitted in hardware depth.

#include "depth.glsl"
#include "sample_patterns.glsl"

layout(binding = 0) uniform sampler2D sm_depth;               // D32F, nearest, border = far
layout(binding = 1) uniform sampler2DShadow sm_depth_compare; // same texture: linear, GEQUAL
layout(binding = 2) uniform sampler2D sm_moments;             // RG32F (d, d²), filtered, mipmapped

struct ShadowInput {
    vec3 pos_world;          // receiver point
    vec3 normal_world;       // geometric normal, facing the camera
    vec2 uv;                 // shadow-map coordinates of the receiver
    vec2 uv_dx, uv_dy;       // their screen-space derivatives (for filtered lookups)
    float depth;             // linear depth in [0, 1] (near..far)
    float depth_world;       // planar depth from the light (world units)
    float depth_hw;          // hardware depth (reversed Z) of the receiver
    vec2 depth_hw_gradient;  // d(depth_hw)/d(uv) of the receiver's plane; 0 if degenerate
    float cos_light;         // cosine between normal and direction to the light centre
    float texel_depth_slope; // depth change (linear units) across one texel at this slope
    vec2 frag_coord;         // window position, for per-pixel rotations
};

// Receiver-plane depth bias (Isidoro 2006, "Shadow mapping: GPU-based tips
// and techniques"): the chain rule through the screen-space Jacobian of
// (u, v) gives the receiver's depth gradient in the map's uv. Needs
// derivatives, so it runs in uniform control flow, in sm_make_input.
vec2 sm_depth_gradient(vec2 uv, float depth_hw)
{
    vec3 dx = dFdx(vec3(uv, depth_hw)), dy = dFdy(vec3(uv, depth_hw));
    float det = dx.x * dy.y - dx.y * dy.x;
    if (abs(det) < 1e-20)
        return vec2(0.0);  // edge-on to the light: no usable plane
    vec2 g = vec2(dy.y * dx.z - dx.y * dy.z, dx.x * dy.z - dy.x * dx.z) / det;
    return all(lessThan(abs(g), vec2(1e10))) ? g : vec2(0.0);
}

// tan(theta) is capped at 10 (theta ~ 84 deg) so grazing receivers keep a
// finite slope bias.
ShadowInput sm_make_input(vec3 p, vec3 n)
{
    ShadowInput s;
    vec4 c = sm.light_view_proj * vec4(p, 1.0);
    s.pos_world = p;
    s.normal_world = n;
    s.uv = c.xy / c.w * 0.5 + 0.5;
    s.uv_dx = dFdx(s.uv);
    s.uv_dy = dFdy(s.uv);
    s.depth_world = c.w;  // planar depth: clip w of a perspective projection
    s.depth = (c.w - sm.near_world) / (sm.far_world - sm.near_world);
    s.depth_hw = c.z / c.w;
    s.depth_hw_gradient = sm_depth_gradient(s.uv, s.depth_hw);
    s.cos_light = dot(n, normalize(sm.light_pos_world.xyz - p));
    float texel_world = max(sm.near_window_world.x, sm.near_window_world.y) * sm.texel_size_uv.x
                        * c.w / sm.near_world;
    float cos_t = clamp(s.cos_light, 0.0995, 1.0);
    float tan_t = sqrt(1.0 - cos_t * cos_t) / cos_t;
    s.texel_depth_slope = texel_world * tan_t / (sm.far_world - sm.near_world);
    s.frag_coord = gl_FragCoord.xy;
    return s;
}

// Inside the light frustum, and so covered by the map?
bool sm_inside(ShadowInput s)
{
    return s.depth_world > 0.0 && all(greaterThanEqual(s.uv, vec2(0.0)))
        && all(lessThanEqual(s.uv, vec2(1.0))) && s.depth >= 0.0 && s.depth <= 1.0;
}

// ---- comparisons (PCF family) -------------------------------------------

// A linear-depth bias (constant + slope-scaled, in linear units) as an
// offset in hardware depth at the receiver, to be added to its depth_hw
// (reversed Z: nearer the light is larger).
float sm_bias_hw(ShadowInput s, float bias)
{
    return sm_hw_depth(max(s.depth - bias, 0.0)) - s.depth_hw;
}

// Bilinear-weighted 2x2 comparison by the texture unit at uv against the
// reference hardware depth ref (GEQUAL: 1 = lit).
float sm_lit_2x2(vec2 uv, float ref)
{
    return textureLod(sm_depth_compare, vec3(uv, ref), 0.0);
}

// Per-pixel random numbers in [0, 1): interleaved gradient noise (Jimenez
// 2014, "Next generation post processing in Call of Duty"), decorrelated
// for the second coordinate by a shifted window position.
vec2 sm_pixel_noise(vec2 frag_coord)
{
    const vec3 k = vec3(0.06711056, 0.00583715, 52.9829189);
    return vec2(fract(k.z * fract(dot(frag_coord, k.xy))),
                fract(k.z * fract(dot(frag_coord + vec2(47.0, 17.0), k.xy))));
}

// SM_UNROLL(n, F) expands to F(0) F(1) ... F(n-1) for a sample count n
// (0, 16, 25, 32, 64, 100 or 128, or a macro naming one). Tap loops are
// unrolled by the preprocessor so the sample tables are always indexed by
// constants: llvmpipe does not unroll a loop whose body is as large as a
// PCSS tap, and a table indexed at run time cost more than the fetch itself
// (pcss 32+32 went from ~170 to ~95 ms at 1024^2).
#define SM_T4(F, b) F(b) F(b + 1) F(b + 2) F(b + 3)
#define SM_T16(F, b) SM_T4(F, b) SM_T4(F, b + 4) SM_T4(F, b + 8) SM_T4(F, b + 12)
#define SM_T32(F, b) SM_T16(F, b) SM_T16(F, b + 16)
#define SM_UNROLL_0(F)
#define SM_UNROLL_16(F) SM_T16(F, 0)
#define SM_UNROLL_25(F) SM_T16(F, 0) SM_T4(F, 16) SM_T4(F, 20) F(24)
#define SM_UNROLL_32(F) SM_T32(F, 0)
#define SM_UNROLL_64(F) SM_T32(F, 0) SM_T32(F, 32)
#define SM_UNROLL_100(F) SM_T32(F, 0) SM_T32(F, 32) SM_T32(F, 64) SM_T4(F, 96)
#define SM_UNROLL_128(F) SM_T32(F, 0) SM_T32(F, 32) SM_T32(F, 64) SM_T32(F, 96)
#define SM_UNROLL_EXPANDED(n, F) SM_UNROLL_##n(F)
#define SM_UNROLL(n, F) SM_UNROLL_EXPANDED(n, F)

// Everything about a pixel's taps that does not change from tap to tap,
// computed once: tap i is at uv + axes * q_i, where q_i is pattern point i
// scrambled per pixel, and the receiver's reference depth there is
// ref + dot(ref_gradient, q_i).
struct TapFrame {
    vec2 uv;
    mat2 axes;          // pattern space -> uv offset (scale, and the disk's rotation)
    bool square;        // square pattern, else disk (a constant at every call site)
    vec2 shift;         // square: Cranley-Patterson shift, 1 + 2 noise
    float ref;          // receiver hardware depth + bias
    vec2 ref_gradient;  // receiver plane in pattern space (0 without the plane)
};

// The frame of a pattern scaled to half_uv: the square set shifted by
// 2 noise modulo [-1, 1]^2 (keeps its toroidal spacing), or the disk set
// rotated by 2 pi noise.x. With `plane`, the reference follows the
// receiver's plane (receiver-plane depth bias, Isidoro 2006), evaluated at
// the tap; half a texel of its slope is added to the bias, since the
// nearest texel's centre, where the map's depth was taken, lies up to half
// a texel away.
TapFrame sm_tap_frame(ShadowInput s, vec2 half_uv, bool square, vec2 noise, bool plane, float bias_hw)
{
    TapFrame f;
    float a = 6.28318531 * noise.x;
    mat2 rotation = square ? mat2(1.0) : mat2(cos(a), sin(a), -sin(a), cos(a));
    f.uv = s.uv;
    f.axes = mat2(half_uv.x, 0.0, 0.0, half_uv.y) * rotation;
    f.square = square;
    f.shift = 1.0 + 2.0 * noise;
    vec2 g = plane ? s.depth_hw_gradient : vec2(0.0);
    f.ref = s.depth_hw + bias_hw + 0.5 * dot(abs(g), sm.texel_size_uv);
    f.ref_gradient = g * f.axes;  // d(ref)/dq = axes^T g
    return f;
}

// Pattern point i of the frame (before `axes`); i a constant. The square's
// wrap is a compare and subtract: p + shift lies in [0, 4).
vec2 sm_tap_point(TapFrame f, int i)
{
    if (!f.square)
        return sample_disk[i];
    vec2 q = sample_square[i] + f.shift;
    return q - 2.0 * step(2.0, q) - 1.0;
}

// Does the nearest texel at pattern point q occlude the receiver? `stored`
// is that texel's hardware depth.
bool sm_occluded_at(TapFrame f, vec2 q, out float stored)
{
    stored = textureLod(sm_depth, f.uv + f.axes * q, 0.0).r;
    return stored > f.ref + dot(f.ref_gradient, q);
}

// 1 = lit, 0 = occluded, at pattern point q; hw_2x2: the texture unit's
// bilinear 2x2 comparison instead of the nearest texel.
float sm_lit_at(TapFrame f, vec2 q, bool hw_2x2)
{
    float stored;
    if (hw_2x2)
        return sm_lit_2x2(f.uv + f.axes * q, f.ref + dot(f.ref_gradient, q));
    return sm_occluded_at(f, q, stored) ? 0.0 : 1.0;
}

// PCF: result = the mean lit fraction over the first n pattern taps of
// frame f (n a sample count, see SM_UNROLL).
#define SM_PCF_TAP(i) sm_lit_ += sm_lit_at(sm_frame_, sm_tap_point(sm_frame_, i), sm_hw_2x2_);
#define SM_PCF(result, f, n, hw_2x2) \
    { \
        TapFrame sm_frame_ = f; \
        bool sm_hw_2x2_ = hw_2x2; \
        float sm_lit_ = 0.0; \
        SM_UNROLL(n, SM_PCF_TAP) \
        result = sm_lit_ / float(n); \
    }

// ---- PCSS geometry (Fernando 2005), perspective light --------------------
//
// A light of size L at depth 0 and a receiver at planar depth z_r: a blocker
// at depth z_b occludes a light point l where the segment receiver -> l
// crosses depth z_b. Projected from the light centre onto the near plane n,
// those crossings cover, around the receiver's own uv, a region of size
//     light_size_uv * n * (z_r - z_b) / (z_b * z_r)
// (the light's shape, scaled). For a blocker plane parallel to the light this
// region is exact: the visible fraction is the unblocked share of it.

// Half-extent (uv) of that region for a blocker at world depth z_b.
vec2 sm_penumbra_half_uv(ShadowInput s, float z_b, float light_scale)
{
    float z_r = s.depth_world;
    return 0.5 * light_scale * sm.light_size_uv * sm.near_world * max(z_r - z_b, 0.0)
           / (max(z_b, sm.near_world) * z_r);
}

// The blocker-search region: the same region for the nearest possible
// blocker (z_b = near), which contains every other.
vec2 sm_search_half_uv(ShadowInput s, float light_scale)
{
    return sm_penumbra_half_uv(s, sm.near_world, light_scale);
}

// The receiver program is compiled per light shape: the harness defines
// SM_LIGHT_SHAPE (SM_LIGHT_RECT or SM_LIGHT_DISK), so the choice of pattern
// costs nothing per tap.
const bool SM_RECT_LIGHT = SM_LIGHT_SHAPE == SM_LIGHT_RECT;
