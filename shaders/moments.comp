#version 450 core
// Moments product, step 1: the depth map's hardware depth -> (d, d²) with d
// linear in [0, 1] (DESIGN.md §5). The SAT is built from this image.
#include "depth.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D depth_map;
layout(rg32f, binding = 0) uniform writeonly image2D moments;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(moments))))
        return;
    float d = sm_linear_depth(texelFetch(depth_map, p, 0).r);
    imageStore(moments, p, vec4(d, d * d, 0.0, 0.0));
}
