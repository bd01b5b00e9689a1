// evsm: Chebyshev bounds on exponentially warped moments (see techniques/evsm.c).
#include "shadow_common.glsl"
#include "chebyshev.glsl"

// The bound of one warp: moments m = (E[W], E[W²]) at the receiver's own
// warped depth t, whose slope in linear depth is slope (dW/dd): the depth
// variance floor carried into the warp's space. sqrt(floor) * slope first:
// slope² alone overflows fp32 near w = 1 (80 e^40 squared > FLT_MAX).
float evsm_bound(vec2 m, float t, float slope)
{
    float s = sqrt(EVSM_MIN_VARIANCE) * slope;
    return chebyshev_upper_bound(m.x, m.y - m.x * m.x, t, s * s);
}

float shadow_visibility(ShadowInput s)
{
    SM_FETCHED(1);
    vec4 m = textureGrad(sm_evsm, s.uv, s.uv_dx, s.uv_dy);  // trilinear at the footprint
    vec2 e = sm_evsm_warp(sm_moment_depth(s.depth), vec2(EVSM_POSITIVE_EXPONENT, EVSM_NEGATIVE_EXPONENT));
    float p = evsm_bound(m.xy, e.x, 2.0 * EVSM_POSITIVE_EXPONENT * e.x);
#if EVSM_VARIANT == EVSM_VARIANT_EVSM4
    p = min(p, evsm_bound(m.zw, e.y, 2.0 * EVSM_NEGATIVE_EXPONENT * e.y));
#endif
    return reduce_light_bleeding(p, EVSM_BLEED_REDUCTION);
}
