// pcf: fixed-kernel percentage-closer filtering (see techniques/pcf.c).
#include "shadow_taps.glsl"

float shadow_visibility(ShadowInput s)
{
    const bool plane = PCF_RECEIVER_PLANE_BIAS != 0, hw_2x2 = PCF_HARDWARE_2X2 != 0;
    float bias = PCF_CONSTANT_BIAS + (plane ? 0.0 : PCF_SLOPE_BIAS * s.texel_depth_slope);
    vec2 radius_uv = PCF_RADIUS_TEXELS * sm.texel_size_uv;
    float lit;
#if PCF_PATTERN == PCF_PATTERN_GRID
    TapFrame f = sm_tap_frame(s, radius_uv, true, SM_PATTERN_GRID, PCF_SAMPLES, vec2(0.0), plane, sm_bias_hw(s, bias));
    const int side = int(round(sqrt(float(PCF_SAMPLES))));
    lit = 0.0;
    for (int j = 0; j < side; j++)
        for (int i = 0; i < side; i++)  // cell centres of an n x n grid over [-1, 1]^2
            lit += sm_lit_at(f, (vec2(i, j) + 0.5) * (2.0 / float(side)) - 1.0, hw_2x2);
    lit /= float(side * side);
#else
    TapFrame f = sm_tap_frame(s, radius_uv, false, SM_PATTERN_POISSON, PCF_SAMPLES, sm_pixel_noise(s.frag_coord),
                              plane, sm_bias_hw(s, bias));
    SM_PCF(lit, f, PCF_SAMPLES, hw_2x2)
#endif
    return lit;
}
