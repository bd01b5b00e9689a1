#version 450 core
// The penumbra mask's pre-pass (seed 003; docs/techniques.md): the scene from
// the camera at a quarter of the receiver's width and height, so a fragment
// is a 4 x 4 block of receiver pixels at its centre, each asking the
// technique's shadow_classify() (its file is appended) whether the block is
// lit (1), in umbra (0) or in penumbra (0.5), beside its view depth (the
// dilation's distance-dependent radius: a block spans depth x its angle). A block the technique is not
// asked about (no geometry at its centre, outside the map or this cascade)
// is penumbra: the receiver pass runs the full filter there. One layer per
// cascade; penumbra_dilate.frag then spreads the penumbra.
#include "shadow_common.glsl"
#include "receiver_common.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

layout(location = 0) out vec2 out_class;  // class, camera distance
#if SM_COUNT_FETCHES
layout(location = 1) out float out_fetches;
#endif

float shadow_classify(ShadowInput s, vec2 block_half_uv);

void main()
{
#if SM_COUNT_FETCHES
    sm_fetches = 0.0;
#endif
    vec3 p = v_pos_world;
    ShadowInput s = sm_make_input(p, sm_facing_normal(p, v_normal_world, u_camera_pos), u_camera_pos);
    // at this resolution the derivatives span a block
    vec2 block_half_uv = 0.5 * (abs(s.uv_dx) + abs(s.uv_dy));
    out_class = vec2(cascade_weight_at(p) > 0.0 && sm_inside(s) ? shadow_classify(s, block_half_uv) : 0.5,
                     dot(p - u_camera_pos, u_camera_fwd));
#if SM_COUNT_FETCHES
    out_fetches = sm_fetches;
#endif
}
