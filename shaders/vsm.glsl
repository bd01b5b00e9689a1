// vsm: Chebyshev bound from filtered moments (see techniques/vsm.c).
#include "shadow_common.glsl"
#include "chebyshev.glsl"

float shadow_visibility(ShadowInput s)
{
    SM_FETCHED(1);
    vec2 m = textureGrad(sm_moments, s.uv, s.uv_dx, s.uv_dy).rg;  // trilinear at the footprint
    float p = chebyshev_upper_bound(m.x, m.y - m.x * m.x, s.depth, VSM_MIN_VARIANCE);
    return reduce_light_bleeding(p, VSM_BLEED_REDUCTION);
}
