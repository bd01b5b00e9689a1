#version 450 core
// Receiver pass: V_tech from the technique's shadow_visibility() (its file is
// appended to this one) and the camera distance used for the mismatch mask.
#include "shadow_common.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

uniform vec3 u_camera_pos;

layout(location = 0) out float out_visibility;
layout(location = 1) out float out_camera_distance;

float shadow_visibility(ShadowInput s);

void main()
{
    vec3 p = v_pos_world;
    // Geometric normal, flipped to face the camera: the ground truth's
    // convention (DESIGN.md §6), so both shade the same side. A triangle too
    // small for screen-space derivatives falls back to the vertex normal
    // rather than feeding NaN to the technique.
    vec3 c = cross(dFdx(p), dFdy(p));
    vec3 n = dot(c, c) > 0.0 ? normalize(c) : normalize(v_normal_world);
    vec3 to_camera = u_camera_pos - p;
    if (dot(n, to_camera) < 0.0)
        n = -n;
    ShadowInput s = sm_make_input(p, n);
    // Outside the frustum counts as lit (those pixels are not scored).
    out_visibility = sm_inside(s) ? shadow_visibility(s) : 1.0;
    out_camera_distance = length(to_camera);
}
