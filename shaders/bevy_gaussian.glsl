// bevy_gaussian: Bevy's default shadow filter (see techniques/bevy.c).
#include "bevy_filters.glsl"

float shadow_visibility(ShadowInput s)
{
    float ref;
    vec2 uv = bevy_lookup(s, BEVY_GAUSSIAN_NORMAL_BIAS, BEVY_GAUSSIAN_DEPTH_BIAS, ref);
    return bevy_castano(uv, ref);
}
