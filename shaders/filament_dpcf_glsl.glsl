// filament_dpcf_glsl: Filament's DPCF, see techniques/filament_presets.c.
#include "filament_filters.glsl"

// hardenedKernel: a steeper smoothstep, 4 x^3 below 1/2, 1 - 4 (1 - x)^3 above.
float filament_hardened(float x)
{
    float y = x < 0.5 ? x : 1.0 - x;
    y = 4.0 * y * y * y;
    return x < 0.5 ? y : 1.0 - y;
}

float shadow_visibility(ShadowInput s)
{
    float ref = s.depth_hw + sm_bias_hw(s, FILAMENT_DPCF_GLSL_CONSTANT_BIAS);
    float penumbra = FILAMENT_DPCF_GLSL_PENUMBRA_SCALE
                     * filament_penumbra_texels(s, FILAMENT_DPCF_GLSL_LIGHT_SIZE_SCALE * filament_bulb_radius());
    float occluded, z_sum;
    filament_blocker_search(s, ref, penumbra * sm.texel_size_uv, filament_rotation(s.frag_coord,
                            FILAMENT_DPCF_GLSL_ANIMATE_NOISE != 0), 12, occluded, z_sum);
    if (z_sum == 0.0)
        SM_EARLY_OUT(1.0)
    float ratio = clamp(FILAMENT_DPCF_GLSL_PENUMBRA_RATIO_SCALE * filament_penumbra_ratio(ref, z_sum / occluded),
                        0.0, 1.0);
    float p = occluded / 12.0;
    return 1.0 - mix(filament_hardened(p), p, ratio);
}
