#version 450 core
// Receiver pass: V_tech from the technique's shadow_visibility() (its file is
// appended to this one) and the camera distance used for the mismatch mask.
// With cascades (docs/cascades.md) it runs once per cascade, this pass's map
// bound, and writes w V, where w is this cascade's weight at the pixel's
// view depth; the passes add up. With a penumbra mask (SM_PENUMBRA_MASK,
// docs/techniques.md), a pixel whose 4 x 4 block the mask's pre-pass found
// lit or in umbra takes that answer without the technique.
#include "shadow_common.glsl"
#include "receiver_common.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

layout(location = 0) out float out_visibility;
layout(location = 1) out float out_camera_distance;
#if SM_COUNT_FETCHES
// fetches, passes that ran the full filter, passes an early-out or the mask decided
layout(location = 2) out vec4 out_cost;
#endif
#if SM_PENUMBRA_MASK
layout(binding = SM_BINDING_SCREEN) uniform sampler2DArray sm_penumbra_mask;  // a layer a cascade
#endif

float shadow_visibility(ShadowInput s);

void main()
{
#if SM_COUNT_FETCHES
    sm_fetches = 0.0;
    sm_shortcut = false;
#endif
    vec3 p = v_pos_world;
    ShadowInput s = sm_make_input(p, sm_facing_normal(p, v_normal_world, u_camera_pos), u_camera_pos);
    float z = dot(p - u_camera_pos, u_camera_fwd);
    float w = u_cascade_count > 1 ? cascade_weight(u_cascade, z) : 1.0;
    // Outside the frustum counts as lit (those pixels are not scored).
    bool evaluated = w > 0.0 && sm_inside(s);
    float v = 1.0;
    if (evaluated) {
#if SM_PENUMBRA_MASK
        v = texelFetch(sm_penumbra_mask, ivec3(ivec2(gl_FragCoord.xy) / 4, u_cascade), 0).r;
        if (v != 0.5)
            SM_SHORTCUT();
        else
#endif
            v = shadow_visibility(s);
    }
    float rest = 0.0;  // past the shadow distance: lit
    if (u_cascade == 0 && u_cascade_count > 1) {
        rest = 1.0;
        for (int c = 0; c < u_cascade_count; c++)
            rest -= cascade_weight(c, z);
    }
    out_visibility = u_cascade_count > 1 ? w * v + rest : v;
    out_camera_distance = length(u_camera_pos - p);
#if SM_COUNT_FETCHES
    out_cost = vec4(sm_fetches, float(evaluated && !sm_shortcut), float(evaluated && sm_shortcut), 0.0);
#endif
}
