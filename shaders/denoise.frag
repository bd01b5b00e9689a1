#version 450 core
// The denoiser (seed 003; docs/techniques.md): one direction of a separable
// bilateral blur of V_tech, after the receiver pass, for any technique.
// Taps -u_radius..u_radius pixels, weighted by a Gaussian of the offset
// (sigma = radius / 2, as the moments' prefilter) times a Gaussian of the
// world-space distance between the tap's surface point and the centre's
// (sigma u_sigma_world), so it does not blur across a depth step: where an
// object stands in front of its shadow, a plain blur lights the shadow's
// edge. A pixel without geometry keeps its value and lends none.
layout(binding = SM_BINDING_PASS_SOURCE) uniform sampler2D source;  // V_tech, or the first direction's
layout(binding = SM_BINDING_PASS_SOURCE + 1) uniform sampler2D camera_distance;  // -1: no geometry

uniform ivec2 u_direction;  // (1, 0) or (0, 1)
uniform int u_radius;       // pixels, >= 1
uniform float u_sigma_world;
uniform vec3 u_camera_pos;
uniform vec3 u_ray_fwd, u_ray_right, u_ray_up;  // a pixel's ray: fwd + x right + y up, x, y in [-1, 1]
uniform vec2 u_size;

layout(location = 0) out float out_visibility;

vec3 surface_at(ivec2 q, float d)
{
    vec2 c = (vec2(q) + 0.5) / u_size * 2.0 - 1.0;
    return u_camera_pos + d * normalize(u_ray_fwd + c.x * u_ray_right + c.y * u_ray_up);
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy), last = ivec2(u_size) - 1;
    float v = texelFetch(source, p, 0).r, d = texelFetch(camera_distance, p, 0).r;
    if (d < 0.0) {
        out_visibility = v;
        return;
    }
    vec3 x = surface_at(p, d);
    float spatial = -2.0 / float(u_radius * u_radius), range = -0.5 / (u_sigma_world * u_sigma_world);
    float sum = v, weight = 1.0;
    for (int k = -u_radius; k <= u_radius; k++) {
        ivec2 q = p + k * u_direction;
        if (k == 0 || any(lessThan(q, ivec2(0))) || any(greaterThan(q, last)))
            continue;
        float dq = texelFetch(camera_distance, q, 0).r;
        if (dq < 0.0)
            continue;
        vec3 y = surface_at(q, dq);
        float w = exp(spatial * float(k * k) + range * dot(y - x, y - x));
        sum += w * texelFetch(source, q, 0).r;
        weight += w;
    }
    out_visibility = sum / weight;
}
