#version 450 core
// Moments product without a prefilter: the depth map's hardware depth ->
// (d, d²), d linear in [0, 1] (DESIGN.md §5).
#include "depth.glsl"

layout(binding = 0) uniform sampler2D depth_map;
layout(location = 0) out vec2 out_moments;

void main()
{
    float d = sm_linear_depth(texelFetch(depth_map, ivec2(gl_FragCoord.xy), 0).r);
    out_moments = vec2(d, d * d);
}
