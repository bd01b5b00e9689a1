// pcss: blocker search -> penumbra -> PCF (see techniques/pcss.c).
#include "shadow_taps.glsl"
#include "pcss_geometry.glsl"

float shadow_visibility(ShadowInput s)
{
    const bool plane = PCSS_RECEIVER_PLANE_BIAS != 0;
    float bias = PCSS_CONSTANT_BIAS + (plane ? 0.0 : PCSS_SLOPE_BIAS * s.texel_depth_slope);
    float bias_hw = sm_bias_hw(s, bias);
    const bool square = SM_RECT_LIGHT;  // the taps follow the light's shape
    vec2 noise = sm_rotation_noise(s.frag_coord, PCSS_ROTATION);
    // seed 003's two radii: each step's own light size scale, 0 = light_size_scale
    const float search_scale = PCSS_SEARCH_LIGHT_SIZE_SCALE > 0.0 ? PCSS_SEARCH_LIGHT_SIZE_SCALE
                                                                  : PCSS_LIGHT_SIZE_SCALE;
    const float filter_scale = PCSS_FILTER_LIGHT_SIZE_SCALE > 0.0 ? PCSS_FILTER_LIGHT_SIZE_SCALE
                                                                  : PCSS_LIGHT_SIZE_SCALE;

    // 1. Blocker search: the mean planar depth of the occluding taps.
    TapFrame search = sm_tap_frame(s, sm_search_half_uv(s, search_scale), square, PCSS_PATTERN,
                                   PCSS_BLOCKER_SAMPLES, noise, plane, bias_hw);
    float z_sum = 0.0, blockers = 0.0, stored;
#define PCSS_BLOCKER_TAP(i) \
    if (sm_occluded_at(search, sm_tap_point(search, i), stored)) { \
        z_sum += sm_planar_depth(stored); \
        blockers += 1.0; \
    }
    SM_UNROLL(PCSS_BLOCKER_SAMPLES, PCSS_BLOCKER_TAP)
    if (blockers == 0.0)
        return 1.0;
    if (blockers == float(PCSS_BLOCKER_SAMPLES))
        return 0.0;

    // 2. Penumbra by similar triangles; 3. PCF over it (another scramble).
    vec2 filter_uv = sm_penumbra_half_uv(s, z_sum / blockers, filter_scale);
    float lit;
    SM_PCF(lit, sm_tap_frame(s, filter_uv, square, PCSS_PATTERN, PCSS_FILTER_SAMPLES, noise.yx, plane, bias_hw),
           PCSS_FILTER_SAMPLES, false)
    return lit;
}
