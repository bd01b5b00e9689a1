// msm: 4MSM from four filtered power moments (see techniques/msm.c).
#include "shadow_common.glsl"
#include "msm_common.glsl"

float shadow_visibility(ShadowInput s)
{
    SM_FETCHED(1);
    vec4 b = textureGrad(sm_msm, s.uv, s.uv_dx, s.uv_dy);  // trilinear at the footprint
    float z = sm_moment_depth(s.depth - MSM_DEPTH_BIAS);
#if MSM_BOUND == MSM_BOUND_HAUSDORFF
    return 1.0 - msm_occlusion_hausdorff(msm_hausdorff_bias(b, MSM_MOMENT_BIAS), z);
#else
    float z_blocker;
    return 1.0 - msm_occlusion(msm_bias(b, MSM_MOMENT_BIAS), z, z_blocker);
#endif
}
