// filament_pcss_glsl: Filament's PCSS, see techniques/filament_presets.c.
#include "filament_filters.glsl"

float shadow_visibility(ShadowInput s)
{
    float ref = s.depth_hw + sm_bias_hw(s, FILAMENT_PCSS_GLSL_CONSTANT_BIAS);
    float penumbra = FILAMENT_PCSS_GLSL_PENUMBRA_SCALE
                     * filament_penumbra_texels(s, FILAMENT_PCSS_GLSL_LIGHT_SIZE_SCALE * filament_bulb_radius());
    mat2 rotation = filament_rotation(s.frag_coord, FILAMENT_PCSS_GLSL_ANIMATE_NOISE != 0);
    float occluded, z_sum;
    filament_blocker_search(s, ref, penumbra * sm.texel_size_uv, rotation, 16, occluded, z_sum);
    if (z_sum == 0.0)
        SM_EARLY_OUT(1.0)
    // the ratio unclamped: at contact the 16 taps meet on the receiver's own 2 x 2
    float ratio = FILAMENT_PCSS_GLSL_PENUMBRA_RATIO_SCALE * filament_penumbra_ratio(ref, z_sum / occluded);
    vec2 radius_uv = penumbra * ratio * sm.texel_size_uv;
    vec2 size = vec2(sm.map_size_texels);
    float occluded_sum = 0.0;
    for (int i = 0; i < 16; i++) {
        // filterPCSS: a manual bilinear 2 x 2 per tap, each texel against
        // the receiver's plane at the tap
        vec2 duv = rotation * (FILAMENT_POISSON[i] * radius_uv);
        vec2 tc = s.uv + duv;
        vec2 grad = fract(tc * size - 0.5);
        SM_FETCHED(1);
        vec4 d = textureGather(sm_depth, tc, 0);  // (0,1) (1,1) (1,0) (0,0)
        vec4 pcf = step(vec4(dot(s.depth_hw_gradient, duv)), d - ref);
        occluded_sum += mix(mix(pcf.w, pcf.z, grad.x), mix(pcf.x, pcf.y, grad.x), grad.y);
    }
    return 1.0 - occluded_sum / 16.0;
}
