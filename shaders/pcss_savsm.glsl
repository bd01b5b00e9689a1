// pcss_savsm: PCSS with the SAT's moments (see techniques/pcss_savsm.c).
#include "shadow_common.glsl"
#include "pcss_geometry.glsl"
#include "chebyshev.glsl"
#include "sat.glsl"

float shadow_visibility(ShadowInput s)
{
    float t = s.depth;
    vec2 mean_var;

    // 1. Blocker depth from the search box's moments.
    if (!sat_mean_variance(s.uv, sm_search_half_uv(s, PCSS_SAVSM_LIGHT_SIZE_SCALE), mean_var)
        || t <= mean_var.x)
        SM_EARLY_OUT(1.0);
    float alpha = chebyshev_upper_bound(mean_var.x, mean_var.y, t, PCSS_SAVSM_MIN_VARIANCE);
    if (1.0 - alpha < PCSS_SAVSM_MIN_BLOCKER_FRACTION)
        SM_EARLY_OUT(1.0);
    float z_occ = clamp((mean_var.x - alpha * t) / (1.0 - alpha), 0.0, t);

    // 2. Penumbra as PCSS; 3. VSM over it.
    vec2 filter_uv = sm_filter_half_uv(s, sm_world_depth(z_occ), PCSS_SAVSM_LIGHT_SIZE_SCALE);
    if (!sat_mean_variance(s.uv, filter_uv, mean_var))
        return 1.0;
    float p = chebyshev_upper_bound(mean_var.x, mean_var.y, t, PCSS_SAVSM_MIN_VARIANCE);
    return reduce_light_bleeding(p, PCSS_SAVSM_BLEED_REDUCTION);
}
