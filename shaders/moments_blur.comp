#version 450 core
// Moments product, step 2 (optional): one direction of a separable Gaussian
// prefilter of (d, d²), sigma = radius / 2, taps -radius..radius, clamped at
// the map's edge. Filtering moments is what makes VSM filterable (Donnelly
// and Lauritzen 2006).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D source;
layout(rg32f, binding = 0) uniform writeonly image2D target;

uniform ivec2 u_direction;  // (1, 0) or (0, 1)
uniform int u_radius;       // texels, >= 1

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy), size = imageSize(target);
    if (any(greaterThanEqual(p, size)))
        return;
    float inv_two_sigma2 = 2.0 / float(u_radius * u_radius);  // 1 / (2 (r/2)^2)
    vec2 sum = vec2(0.0);
    float weight = 0.0;
    for (int k = -u_radius; k <= u_radius; k++) {
        float w = exp(-float(k * k) * inv_two_sigma2);
        sum += w * texelFetch(source, clamp(p + k * u_direction, ivec2(0), size - 1), 0).rg;
        weight += w;
    }
    imageStore(target, p, vec4(sum / weight, 0.0, 0.0));
}
