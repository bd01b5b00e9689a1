// Unity HDRP's shadow filters (techniques/hdrp.c): ShadowSamplingTent.hlsl,
// HDShadowSampling.hlsl, HDPCSS.hlsl and HDShadowAlgorithms.hlsl of
// Unity-Technologies/Graphics, HDRP 17.2.
#include "shadow_taps.glsl"

// HDRP's lookup: the normal, flipped towards the light, moves it by
// normal_bias x sqrt(2) texels of the map at the receiver
// (EvalShadow_NormalBiasProj/Ortho); every filter then adds
// FIXED_UNIFORM_BIAS, 1/65536, to the device depth (reversed Z: towards
// the light). The map's own biases (constant 1 unit, slope 0.5 x 5) stand
// here as slope_bias texels of the receiver's depth slope.
float hdrp_ref(ShadowInput s, float normal_bias, float slope_bias, out vec2 uv)
{
    vec3 n = dot(s.normal_world, sm_to_light(s.pos_world)) < 0.0 ? -s.normal_world : s.normal_world;
    float depth_hw;
    sm_offset_lookup(s, n * normal_bias * 1.41421356 * sm_texel_world(s), uv, depth_hw);
    return depth_hw + sm_bias_hw(s, slope_bias * s.texel_depth_slope) + 1.0 / 65536.0;
}

// InterleavedGradientNoise (Random.hlsl) of the pixel moved by TAA's
// frame index (0 to 7; 0 without TAA: `animate`) times (2.083, 4.867), as
// an angle: HDRP turns its taps by it.
mat2 hdrp_rotation(vec2 pixel, bool animate)
{
    float a = 6.28318531 * sm_ign(pixel + (animate ? mod(sm_noise_frame, 8.0) : 0.0) * vec2(2.083, 4.867));
    // offset' = (x cos + y sin, -x sin + y cos)
    return mat2(cos(a), -sin(a), sin(a), cos(a));
}

// fibonacciSpiralDirection[i]: the golden angle's turns, 2 pi frac(i (3 - sqrt 5) / 2).
vec2 hdrp_spiral_direction(int i)
{
    float a = 6.28318531 * fract(float(i) * 0.38196601);
    return vec2(cos(a), sin(a));
}
