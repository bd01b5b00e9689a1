// savsm: Chebyshev bound over a SAT box (see techniques/savsm.c).
#include "shadow_common.glsl"
#include "chebyshev.glsl"
#include "sat.glsl"

float shadow_visibility(ShadowInput s)
{
    vec2 footprint_uv = 0.5 * (abs(s.uv_dx) + abs(s.uv_dy));
    vec2 half_uv = max(0.5 * SAVSM_BOX_WIDTH_TEXELS * sm.texel_size_uv, footprint_uv);
    vec2 mean_var;
    if (!sat_mean_variance(s.uv, half_uv, mean_var))
        return 1.0;
    float p = chebyshev_upper_bound(mean_var.x, mean_var.y, s.depth, SAVSM_MIN_VARIANCE);
    return reduce_light_bleeding(p, SAVSM_BLEED_REDUCTION);
}
