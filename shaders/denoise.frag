#version 450 core
// The denoiser (seed 003; docs/techniques.md): one direction of a separable
// bilateral blur of V_tech, after the receiver pass, for any technique.
// Taps -u_radius..u_radius pixels, weighted by a Gaussian of the offset
// (sigma = radius / 2, as the moments' prefilter) times a Gaussian of the
// world-space distance between the tap's surface point and the centre's
// (sigma u_sigma_world), so it does not blur across a depth step: where an
// object stands in front of its shadow, a plain blur lights the shadow's
// edge; and, with u_normal_power > 0, times max(0, n_p . n_q)^power, so it
// does not blur across a crease either (two faces at one depth). The
// normals are rebuilt from the camera distances: the cross product of the
// surface's differences to its neighbours along x and y, each the smaller
// of the two one-sided differences (the side across a depth step is
// larger), so they need no buffer of their own. A pixel without geometry
// keeps its value and lends none.
layout(binding = SM_BINDING_PASS_SOURCE) uniform sampler2D source;  // V_tech, or the first direction's
layout(binding = SM_BINDING_PASS_SOURCE + 1) uniform sampler2D camera_distance;  // -1: no geometry

uniform ivec2 u_direction;  // (1, 0) or (0, 1)
uniform int u_radius;       // pixels, >= 1
uniform float u_sigma_world;
uniform float u_normal_power;  // 0: position only
uniform vec3 u_camera_pos;
uniform vec3 u_ray_fwd, u_ray_right, u_ray_up;  // a pixel's ray: fwd + x right + y up, x, y in [-1, 1]
uniform vec2 u_size;

layout(location = 0) out float out_visibility;

vec3 surface_at(ivec2 q, float d)
{
    vec2 c = (vec2(q) + 0.5) / u_size * 2.0 - 1.0;
    return u_camera_pos + d * normalize(u_ray_fwd + c.x * u_ray_right + c.y * u_ray_up);
}

// The surface's normal at pixel p (point x), oriented alike everywhere (the
// differences run along +x and +y), or 0 where an axis has no neighbour
// on either side (a sliver against the sky) or the two differences are
// parallel.
vec3 normal_at(ivec2 p, vec3 x)
{
    ivec2 last = ivec2(u_size) - 1;
    vec3 side[2];
    for (int a = 0; a < 2; a++) {
        ivec2 e = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
        ivec2 lo = clamp(p - e, ivec2(0), last), hi = clamp(p + e, ivec2(0), last);
        float dl = texelFetch(camera_distance, lo, 0).r, dh = texelFetch(camera_distance, hi, 0).r;
        bool has_l = dl >= 0.0 && lo != p, has_h = dh >= 0.0 && hi != p;
        if (!has_l && !has_h)
            return vec3(0.0);
        vec3 l = has_l ? x - surface_at(lo, dl) : vec3(0.0), h = has_h ? surface_at(hi, dh) - x : vec3(0.0);
        side[a] = !has_h || (has_l && dot(l, l) < dot(h, h)) ? l : h;
    }
    vec3 n = cross(side[0], side[1]);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0);
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
    const bool normals = u_normal_power > 0.0;
    vec3 n = normals ? normal_at(p, x) : vec3(0.0);
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
        if (normals && n != vec3(0.0)) {
            vec3 m = normal_at(q, y);
            w *= m == vec3(0.0) ? 1.0 : pow(max(dot(n, m), 0.0), u_normal_power);
        }
        sum += w * texelFetch(source, q, 0).r;
        weight += w;
    }
    out_visibility = sum / weight;
}
