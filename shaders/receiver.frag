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
    ShadowInput s = sm_make_input(p, sm_facing_normal(p, v_normal_world, u_camera_pos));
    // Outside the frustum counts as lit (those pixels are not scored).
    out_visibility = sm_inside(s) ? shadow_visibility(s) : 1.0;
    out_camera_distance = length(u_camera_pos - p);
}
