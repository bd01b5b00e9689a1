// godot_pcf: Godot 4's PCF at a quality level (see techniques/godot.c).
#include "godot_filters.glsl"

float shadow_visibility(ShadowInput s)
{
    float depth_hw;
    godot_lookup(s, GODOT_PCF_NORMAL_BIAS, s.uv, depth_hw);
    float ref = depth_hw + sm_bias_hw(s, GODOT_PCF_CONSTANT_BIAS);
    // soft_shadow_scale = shadow_blur * the level's radius, in texels
    vec2 radius_uv = GODOT_PCF_BLUR * GODOT_QUALITY_RADIUS[GODOT_PCF_QUALITY] * sm.texel_size_uv;
    return godot_pcf(s.uv, ref, radius_uv, GODOT_PCF_TAPS[GODOT_PCF_QUALITY],
                     godot_rotation(s.frag_coord, GODOT_PCF_TAA != 0));
}
