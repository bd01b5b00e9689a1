#version 450 core
// Moments products: one direction of a separable Gaussian, taps
// -radius..radius clamped at the map's edge (the edge policy,
// techniques/shadowmap.h), normalised weights from the harness (sigma =
// radius / 2; radius 0: the conversion alone).
// BLUR_FROM_DEPTH: the rows pass reads the depth map and converts each tap
// (one full-map pass fewer: on llvmpipe each costs ~40 ms at 2048^2). Filtering moments is what makes
// VSM filterable (Donnelly and Lauritzen 2006).
// MOMENTS_KIND, the product made (its SM_PRODUCT_<ID>): SM_PRODUCT_MOMENTS,
// the moments (d, d²) of linear depth d; SM_PRODUCT_EVSM, the moments of two
// exponential warps of w = 2d - 1 (Annen et al. 2008, Lauritzen and McCool
// 2008): (e^{c+ w}, e^{2 c+ w}, -e^{-c- w}, e^{-2 c- w}), the exponents at
// most 42 (SM_EVSM_MAX_EXPONENT in techniques/technique.h), so e^{2c} stays
// finite; SM_PRODUCT_MSM, the power moments (w, w², w³, w⁴) (Peters and Klein
// 2015), in fp32.
#include "depth.glsl"

layout(binding = SM_BINDING_PASS_SOURCE) uniform sampler2D source;  // depth map, or the rows pass's output

uniform ivec2 u_direction;                        // (1, 0) or (0, 1)
uniform int u_radius;                             // 0..SM_MAX_BLUR_RADIUS
uniform float u_weights[SM_MAX_BLUR_RADIUS + 1];  // by |offset|

#if MOMENTS_KIND == SM_PRODUCT_MOMENTS
#define MOMENTS vec2
#else
#define MOMENTS vec4
#endif
#if MOMENTS_KIND == SM_PRODUCT_EVSM
uniform vec2 u_exponents;  // c+, c-
#endif
layout(location = 0) out MOMENTS out_moments;

MOMENTS moments_at(ivec2 p)
{
#if BLUR_FROM_DEPTH
    float d = sm_linear_depth(texelFetch(source, p, 0).r);
#if MOMENTS_KIND == SM_PRODUCT_EVSM
    vec2 e = sm_evsm_warp(sm_moment_depth(d), u_exponents);
    return vec4(e.x, e.x * e.x, e.y, e.y * e.y);
#elif MOMENTS_KIND == SM_PRODUCT_MSM
    float w = sm_moment_depth(d), w2 = w * w;
    return vec4(w, w2, w2 * w, w2 * w2);
#else
    return vec2(d, d * d);
#endif
#elif MOMENTS_KIND == SM_PRODUCT_MOMENTS
    return texelFetch(source, p, 0).rg;
#else
    return texelFetch(source, p, 0);
#endif
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(source, 0) - 1;
    MOMENTS sum = u_weights[0] * moments_at(p);
    for (int k = 1; k <= u_radius; k++)
        sum += u_weights[k] * (moments_at(clamp(p + k * u_direction, ivec2(0), last)) +
                               moments_at(clamp(p - k * u_direction, ivec2(0), last)));
    out_moments = sum;
}
