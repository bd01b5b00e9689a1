// godot_pcf: Godot 4's PCF at a quality level (see techniques/godot.c).
#include "godot_filters.glsl"

float shadow_visibility(ShadowInput s)
{
    float depth_hw;
    godot_lookup(s, GODOT_PCF_NORMAL_BIAS, s.uv, depth_hw);
    // soft_shadow_scale = shadow_blur * the level's radius, in texels
    float scale = GODOT_PCF_BLUR * GODOT_QUALITY_RADIUS[GODOT_PCF_QUALITY];
    float ref = godot_ref(depth_hw, GODOT_PCF_BIAS, scale);
    vec2 radius_uv = scale * sm.texel_size_uv;
    return godot_pcf(s.uv, ref, radius_uv, GODOT_PCF_TAPS[GODOT_PCF_QUALITY],
                     godot_rotation(s.frag_coord, GODOT_PCF_ANIMATE_NOISE != 0));
}
