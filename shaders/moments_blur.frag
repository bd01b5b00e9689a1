#version 450 core
// Moments product: one direction of a separable Gaussian of (d, d²), taps
// -radius..radius clamped at the map's edge (the edge policy,
// techniques/shadowmap.h), normalised weights from the harness (sigma =
// radius / 2; radius 0: the conversion alone).
// BLUR_FROM_DEPTH: the rows pass reads the depth map and converts each tap
// (one full-map pass fewer: on llvmpipe each costs ~40 ms at 2048^2). Filtering moments is what makes
// VSM filterable (Donnelly and Lauritzen 2006).
#include "depth.glsl"

layout(binding = SM_BINDING_PASS_SOURCE) uniform sampler2D source;  // depth map, or moments
layout(location = 0) out vec2 out_moments;

uniform ivec2 u_direction;                        // (1, 0) or (0, 1)
uniform int u_radius;                             // 0..SM_MAX_BLUR_RADIUS
uniform float u_weights[SM_MAX_BLUR_RADIUS + 1];  // by |offset|

vec2 moments_at(ivec2 p)
{
#if BLUR_FROM_DEPTH
    float d = sm_linear_depth(texelFetch(source, p, 0).r);
    return vec2(d, d * d);
#else
    return texelFetch(source, p, 0).rg;
#endif
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(source, 0) - 1;
    vec2 sum = u_weights[0] * moments_at(p);
    for (int k = 1; k <= u_radius; k++)
        sum += u_weights[k] * (moments_at(clamp(p + k * u_direction, ivec2(0), last)) +
                               moments_at(clamp(p - k * u_direction, ivec2(0), last)));
    out_moments = sum;
}
