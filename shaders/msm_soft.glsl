// msm_soft: PCSS with both area queries answered by 4MSM from the SAT of
// four moments (see techniques/msm_soft.c).
#define SAT_CHANNELS 4
#include "shadow_common.glsl"
#include "pcss_geometry.glsl"
#include "msm_common.glsl"
#include "sat.glsl"

float shadow_visibility(ShadowInput s)
{
    float z = sm_moment_depth(s.depth - MSM_SOFT_DEPTH_BIAS), z_blocker;
    // The user's moment bias plus what int32's fixed point needs.
    float alpha = MSM_SOFT_MOMENT_BIAS +
                  (SAT_TABLE.format == SM_SAT_INT32 ? msm_quantisation_bias(1.0 / SAT_TABLE.scale) : 0.0);
    vec4 b;

    // 1. Blocker share and mean depth over the search box.
    if (!sat_box_mean(s.uv, sm_search_half_uv(s, MSM_SOFT_LIGHT_SIZE_SCALE), b))
        SM_EARLY_OUT(1.0);
    if (msm_occlusion(msm_bias(b, alpha), z, z_blocker) < MSM_SOFT_MIN_BLOCKER_FRACTION)
        SM_EARLY_OUT(1.0);
    float d_blocker = clamp(0.5 * (z_blocker + 1.0), 0.0, s.depth);

    // 2. Penumbra as PCSS; 3. 4MSM over it.
    vec2 filter_uv = sm_filter_half_uv(s, sm_world_depth(d_blocker), MSM_SOFT_LIGHT_SIZE_SCALE);
    if (!sat_box_mean(s.uv, filter_uv, b))
        return 1.0;
    return 1.0 - msm_occlusion(msm_bias(b, alpha), z, z_blocker);
}
