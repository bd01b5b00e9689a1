// The PCF family's tap machinery (pcf, pcss, bench's fetch probe): depth
// comparisons with bias, per-pixel scrambled tap patterns, tap loops
// unrolled by the preprocessor.
#include "shadow_common.glsl"
#include "sample_patterns.glsl"

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

// The frame index the noise is animated by (the receiver sets it: 0 unless
// `shadowbench stability` animates it). A program that does not read it
// (no noise) is deterministic from frame to frame.
uniform float sm_noise_frame;

// Per-pixel random numbers in [0, 1): interleaved gradient noise (Jimenez
// 2014, "Next generation post processing in Call of Duty"), decorrelated
// for the second coordinate by a shifted window position, and animated as
// that talk does, by moving the window position 5.588238 pixels a frame
// (frame 0: the still pattern every other command scores).
vec2 sm_pixel_noise(vec2 frag_coord)
{
    const vec3 k = vec3(0.06711056, 0.00583715, 52.9829189);
    frag_coord += 5.588238 * sm_noise_frame;
    return vec2(fract(k.z * fract(dot(frag_coord, k.xy))),
                fract(k.z * fract(dot(frag_coord + vec2(47.0, 17.0), k.xy))));
}

// SM_UNROLL(n, F) expands to F(0) F(1) ... F(n-1) for a tap count n (0 or
// one of TAP_COUNTS in techniques/technique.h, or a macro naming one): the
// layer defines SM_UNROLL_<n> from that list in blocks of the SM_T* below.
// Tap loops are unrolled by the preprocessor so the sample tables are
// always indexed by constants: llvmpipe does not unroll a loop whose body
// is as large as a PCSS tap, and a table indexed at run time cost more than
// the fetch itself (pcss 32+32 went from ~170 to ~95 ms at 1024^2).
#define SM_T4(F, b) F(b) F(b + 1) F(b + 2) F(b + 3)
#define SM_T16(F, b) SM_T4(F, b) SM_T4(F, b + 4) SM_T4(F, b + 8) SM_T4(F, b + 12)
#define SM_T32(F, b) SM_T16(F, b) SM_T16(F, b + 16)
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
