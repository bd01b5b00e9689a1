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
    SM_FETCHED(1);
    return textureLod(sm_depth_compare, vec3(uv, ref), 0.0);
}

// The frame index the noise is animated by (the receiver sets it: 0, but
// in `stability`'s frames and `check`'s frame 1), read by a technique whose
// `animate_noise` is on, or whose noise moves with the frame as its engine
// ships it (bevy_temporal); a program that does not read it is the same
// from frame to frame.
uniform float sm_noise_frame;

// Interleaved gradient noise (Jimenez 2014, "Next generation post
// processing in Call of Duty") of a window position, in [0, 1): every
// engine's per-pixel noise, each moving p by its own frame offset.
float sm_ign(vec2 p)
{
    return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715))));
}

// Per-pixel random numbers in [0, 1) for frame `frame`: sm_ign,
// decorrelated for the second coordinate by a shifted window position,
// and animated as Jimenez's talk does, by moving the window position
// 5.588238 pixels a frame (frame 0: the still pattern every other command
// scores).
vec2 sm_pixel_noise(vec2 frag_coord, float frame)
{
    frag_coord += 5.588238 * frame;
    return vec2(sm_ign(frag_coord), sm_ign(frag_coord + vec2(47.0, 17.0)));
}

// pcg2d (Jarzynski and Olano 2020, "Hash functions for GPU rendering") of
// v, as two numbers in [0, 1) (24 bits of each word, so the float is below 1).
vec2 sm_pcg2d(uvec2 v)
{
    v = v * 1664525u + 1013904223u;
    v.x += v.y * 1664525u;
    v.y += v.x * 1664525u;
    v ^= v >> 16u;
    v.x += v.y * 1664525u;
    v.y += v.x * 1664525u;
    v ^= v >> 16u;
    return vec2(v >> 8u) * (1.0 / 16777216.0);
}

// White noise in [0, 1)^2 per pixel (and frame): pcg2d of the pixel.
vec2 sm_hash_noise(vec2 frag_coord, float frame)
{
    return sm_pcg2d(uvec2(ivec2(floor(frag_coord))) ^ uvec2(uint(frame) * 0x9E3779B9u));
}

// Blue noise in [0, 1)^2 per pixel: the tileable void-and-cluster texture
// (tools/blue_noise.c), a tile a channel, and for frame f that many steps of
// the R2 sequence (Roberts 2018: 1/g and 1/g^2, g the plastic number) added
// modulo 1: every pixel walks through [0, 1) evenly, and each frame stays
// mostly blue (the wrap costs some of it; test_tap_patterns measures it).
layout(binding = SM_BINDING_BLUE_NOISE) uniform sampler2D sm_blue_noise;
vec2 sm_blue_noise_at(vec2 frag_coord, float frame)
{
    vec2 v = texelFetch(sm_blue_noise, ivec2(floor(frag_coord)) & (SM_BLUE_NOISE_SIDE - 1), 0).rg;
    return fract(v + frame * vec2(0.7548776662, 0.5698402910));
}

// The noise a `rotation` parameter names (SM_ROTATION_*, techniques/technique.h's
// TAP_ROTATIONS): 0 (the same taps everywhere), white, interleaved gradient
// noise of the pixel, or of its 2 x 2 block (one rotation a block), or blue;
// animated by the frame index where `animate` (the technique's
// `animate_noise`, a constant: off, the program never reads the frame).
vec2 sm_rotation_noise(vec2 frag_coord, int mode, bool animate)
{
    float frame = animate ? sm_noise_frame : 0.0;
    if (mode == SM_ROTATION_NONE)
        return vec2(0.0);
    if (mode == SM_ROTATION_HASH)
        return sm_hash_noise(frag_coord, frame);
    if (mode == SM_ROTATION_BLUE_NOISE)
        return sm_blue_noise_at(frag_coord, frame);
    if (mode == SM_ROTATION_IGN_2X2)
        frag_coord = floor(0.5 * frag_coord) + 0.5;
    return sm_pixel_noise(frag_coord, frame);
}

// Shirley and Chiu's concentric map (1997, "A low distortion map between
// disk and square"), [-1, 1]^2 -> the unit disk, which keeps area; and its
// inverse. The tap patterns are laid out in one and carried to the other.
vec2 sm_square_to_disk(vec2 p)
{
    if (p == vec2(0.0))
        return p;
    const float quarter = 0.78539816;  // pi / 4
    if (abs(p.x) > abs(p.y)) {
        float phi = quarter * p.y / p.x;
        return p.x * vec2(cos(phi), sin(phi));
    }
    float phi = 2.0 * quarter - quarter * p.x / p.y;
    return p.y * vec2(cos(phi), sin(phi));
}

vec2 sm_disk_to_square(vec2 d)
{
    float r = length(d);
    if (r == 0.0)
        return d;
    const float quarter = 0.78539816;
    float phi = atan(d.y, d.x);  // (-pi, pi]
    if (phi < -quarter)
        phi += 8.0 * quarter;    // [-pi/4, 7 pi/4)
    if (phi < quarter)
        return vec2(r, phi * r / quarter);
    if (phi < 3.0 * quarter)
        return vec2((2.0 * quarter - phi) * r / quarter, r);
    if (phi < 5.0 * quarter)
        return vec2(-r, (phi - 4.0 * quarter) * -r / quarter);
    return vec2((6.0 * quarter - phi) * -r / quarter, -r);
}

// Point i of n of a pattern (SM_PATTERN_*) before any rotation, on the
// square (square) or the disk: poisson from the tables; grid the n x n
// cell centres (n a square count); vogel the golden-angle spiral,
// r = sqrt((i + 0.5) / n) (Vogel 1979); uniform_disk point i drawn alone,
// r = sqrt(u), angle 2 pi v for (u, v) = pcg2d(i), as GAMES202's
// uniformDiskSamples draws them (the same first points at every n). i and
// n are constants at every call (SM_UNROLL), so all of it folds.
vec2 sm_pattern_point(int pattern, bool square, int i, int n)
{
    if (pattern == SM_PATTERN_GRID) {
        int side = int(round(sqrt(float(n))));
        vec2 q = (vec2(i % side, i / side) + 0.5) * (2.0 / float(side)) - 1.0;
        return square ? q : sm_square_to_disk(q);
    }
    if (pattern == SM_PATTERN_VOGEL) {
        float a = 2.39996323 * float(i);  // the golden angle, pi (3 - sqrt 5)
        vec2 d = sqrt((float(i) + 0.5) / float(n)) * vec2(cos(a), sin(a));
        return square ? sm_disk_to_square(d) : d;
    }
    if (pattern == SM_PATTERN_UNIFORM_DISK) {
        vec2 uv = sm_pcg2d(uvec2(i, 0x5EEDu));
        vec2 d = sqrt(uv.x) * vec2(cos(6.28318531 * uv.y), sin(6.28318531 * uv.y));
        return square ? sm_disk_to_square(d) : d;
    }
    return square ? sample_square[i] : sample_disk[i];
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
    int pattern, count; // SM_PATTERN_*, and the taps (constants at every call site)
    vec2 shift;         // square: Cranley-Patterson shift, 1 + 2 noise
    float ref;          // receiver hardware depth + bias
    vec2 ref_gradient;  // receiver plane in pattern space (0 without the plane)
};

// The frame of count taps of a pattern scaled to half_uv: the square set
// shifted by 2 noise modulo [-1, 1]^2 (keeps the poisson set's toroidal
// spacing), or the disk set rotated by 2 pi noise.x. With `plane`, the reference follows the
// receiver's plane (receiver-plane depth bias, Isidoro 2006), evaluated at
// the tap; half a texel of its slope is added to the bias, since the
// nearest texel's centre, where the map's depth was taken, lies up to half
// a texel away.
TapFrame sm_tap_frame(ShadowInput s, vec2 half_uv, bool square, int pattern, int count, vec2 noise, bool plane,
                      float bias_hw)
{
    TapFrame f;
    f.pattern = pattern, f.count = count;
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
    vec2 p = sm_pattern_point(f.pattern, f.square, i, f.count);
    if (!f.square)
        return p;
    vec2 q = p + f.shift;
    return q - 2.0 * step(2.0, q) - 1.0;
}

// Does the nearest texel at pattern point q occlude the receiver? `stored`
// is that texel's hardware depth.
bool sm_occluded_at(TapFrame f, vec2 q, out float stored)
{
    SM_FETCHED(1);
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

// The map's texel at the receiver in world units.
float sm_texel_world(ShadowInput s)
{
    return sm_texel_world_at(s.depth_world);
}

// A normal-offset bias, as engines apply it: the receiver's lookup moved
// by `offset` (world units); its map uv and hardware depth there.
void sm_offset_lookup(ShadowInput s, vec3 offset, out vec2 uv, out float depth_hw)
{
    vec3 q = sm_project(s.pos_world + offset);
    uv = q.xy;
    depth_hw = q.z;
}

// The hardware depth of the nearest texel at uv: one fetch.
float sm_depth_nearest(vec2 uv)
{
    SM_FETCHED(1);
    return textureLod(sm_depth, uv, 0.0).r;
}

// The hardware depth at uv filtered bilinearly, as a linear sampler reads
// a depth map without comparison: one gather (one fetch), weighted.
float sm_depth_bilinear(vec2 uv)
{
    SM_FETCHED(1);
    vec4 t = textureGather(sm_depth, uv, 0);  // texels (0,1) (1,1) (1,0) (0,0)
    vec2 w = fract(uv * vec2(sm.map_size_texels) - 0.5);
    return mix(mix(t.w, t.z, w.x), mix(t.x, t.y, w.x), w.y);
}
