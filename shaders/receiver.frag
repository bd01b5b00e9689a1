#version 450 core
// Receiver pass: V_tech from the technique's shadow_visibility() (its file is
// appended to this one) and the camera distance used for the mismatch mask.
// With cascades (docs/cascades.md) it runs once per cascade, this pass's map
// bound, and writes w V, where w is this cascade's weight at the pixel's
// view depth; the passes add up.
#include "shadow_common.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

uniform vec3 u_camera_pos;
uniform vec3 u_camera_fwd;
uniform int u_cascade;        // this pass's
uniform int u_cascade_count;  // 1: one map, weight 1 everywhere
uniform float u_cascade_z[SM_CASCADES_MAX + 1];  // the slices' view depths
uniform float u_cascade_band[SM_CASCADES_MAX];   // each slice's blend band, at its far end

layout(location = 0) out float out_visibility;
layout(location = 1) out float out_camera_distance;

float shadow_visibility(ShadowInput s);

// Cascade c's weight at view depth z: 1 inside its slice, falling to 0
// over its band (where c + 1 rises), rising over the band of c - 1.
float cascade_weight(int c, float z)
{
    float lo = u_cascade_z[c], hi = u_cascade_z[c + 1];
    float w_in = c > 0 && u_cascade_band[c - 1] > 0.0 ? clamp(1.0 - (lo - z) / u_cascade_band[c - 1], 0.0, 1.0)
                                                      : float(z > lo || c == 0);
    float w_out = u_cascade_band[c] > 0.0 ? clamp((hi - z) / u_cascade_band[c], 0.0, 1.0) : float(z <= hi);
    return w_in * w_out;
}

void main()
{
    vec3 p = v_pos_world;
    ShadowInput s = sm_make_input(p, sm_facing_normal(p, v_normal_world, u_camera_pos));
    float z = dot(p - u_camera_pos, u_camera_fwd);
    float w = u_cascade_count > 1 ? cascade_weight(u_cascade, z) : 1.0;
    // Outside the frustum counts as lit (those pixels are not scored).
    float v = w > 0.0 && sm_inside(s) ? shadow_visibility(s) : 1.0;
    float rest = 0.0;  // past the shadow distance: lit
    if (u_cascade == 0 && u_cascade_count > 1) {
        rest = 1.0;
        for (int c = 0; c < u_cascade_count; c++)
            rest -= cascade_weight(c, z);
    }
    out_visibility = u_cascade_count > 1 ? w * v + rest : v;
    out_camera_distance = length(u_camera_pos - p);
}
