// bevy_temporal: Bevy's ShadowFilteringMethod::Temporal (see techniques/bevy.c).
#include "bevy_filters.glsl"

float shadow_visibility(ShadowInput s)
{
    float ref;
    vec2 uv = bevy_lookup(s, BEVY_TEMPORAL_NORMAL_BIAS, BEVY_TEMPORAL_DEPTH_BIAS, ref);
    return bevy_jimenez(uv, ref, 1.0, true, s.frag_coord);
}
