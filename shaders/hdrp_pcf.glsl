// hdrp_pcf: Unity HDRP's tent PCF (see techniques/hdrp.c).
#include "hdrp_filters.glsl"

// The area of the tent of half-width h (45-degree sides, height h) centred
// at o, over [a, b], over its whole area h^2: the weight of the texel
// there (ShadowSamplingTent.hlsl computes the same in closed form).
float hdrp_tent_integral(float x, float h)  // of the unit-height-per-texel tent, from -h to x
{
    x = clamp(x, -h, h);
    return x <= 0.0 ? 0.5 * (x + h) * (x + h) : h * h - 0.5 * (h - x) * (h - x);
}

float hdrp_texel_weight(float a, float b, float o, float h)
{
    return (hdrp_tent_integral(b - o, h) - hdrp_tent_integral(a - o, h)) / (h * h);
}

// SampleShadow_PCF_Tent_NxN, N = 2h: per axis the n = N + 1 texels the tent
// overlaps, paired into n / 2 bilinear fetches, each at the pair's first
// texel centre plus b / (a + b); the 2D taps their outer product.
float shadow_visibility(ShadowInput s)
{
    vec2 uv;
    float ref = hdrp_ref(s, HDRP_PCF_NORMAL_BIAS, HDRP_PCF_SLOPE_BIAS, uv);
    // the level's tent: Low 3x3 for a spot, 5x5 for the sun; Medium 5x5, 7x7
    const int width = (HDRP_PCF_QUALITY == 0 ? 3 : 5) + (SM_LIGHT_SHAPE == SM_LIGHT_SUN ? 2 : 0);  // N = 2h
    const float h = 0.5 * float(width);
    const int pairs = (width + 1) / 2;
    vec2 size = vec2(sm.map_size_texels);
    vec2 t = uv * size, c = floor(t + 0.5), o = t - c;
    vec4 wu = vec4(0.0), wv = vec4(0.0), pu = vec4(0.0), pv = vec4(0.0);
    for (int p = 0; p < pairs; p++) {
        float base = -h + 2.0 * float(p);  // the pair's first texel centre, from the corner c
        float au = hdrp_texel_weight(base - 0.5, base + 0.5, o.x, h), bu = hdrp_texel_weight(base + 0.5, base + 1.5, o.x, h);
        float av = hdrp_texel_weight(base - 0.5, base + 0.5, o.y, h), bv = hdrp_texel_weight(base + 0.5, base + 1.5, o.y, h);
        wu[p] = au + bu, wv[p] = av + bv;
        pu[p] = base + bu / max(au + bu, 1e-20), pv[p] = base + bv / max(av + bv, 1e-20);
    }
    float sum = 0.0;
    for (int j = 0; j < pairs; j++)
        for (int i = 0; i < pairs; i++)
            sum += wu[i] * wv[j] * sm_lit_2x2((c + vec2(pu[i], pv[j])) / size, ref);
    return sum;
}
