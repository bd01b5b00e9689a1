// hard: one comparison against the nearest texel (see techniques/hard.c).
#include "shadow_common.glsl"

float shadow_visibility(ShadowInput s)
{
    float bias = HARD_CONSTANT_BIAS + HARD_SLOPE_BIAS * s.texel_depth_slope;
    SM_FETCHED(1);
    float blocker = sm_linear_depth(textureLod(sm_depth, s.uv, 0.0).r);
    return s.depth - bias > blocker ? 0.0 : 1.0;
}
