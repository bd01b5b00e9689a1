// pcf: fixed-kernel percentage-closer filtering (see techniques/pcf.c).
#include "shadow_taps.glsl"

float shadow_visibility(ShadowInput s)
{
    const bool plane = PCF_RECEIVER_PLANE_BIAS != 0, hw_2x2 = PCF_HARDWARE_2X2 != 0;
    float bias = PCF_CONSTANT_BIAS + (plane ? 0.0 : PCF_SLOPE_BIAS * s.texel_depth_slope);
    vec2 radius_uv = PCF_RADIUS_TEXELS * sm.texel_size_uv;
    const bool square = PCF_PATTERN == SM_PATTERN_GRID;  // the grid on the square, the rest in the disk
    vec2 noise = sm_rotation_noise(s.frag_coord, PCF_ROTATION, PCF_ANIMATE_NOISE != 0);
    TapFrame f = sm_tap_frame(s, radius_uv, square, PCF_PATTERN, PCF_SAMPLES, noise, plane, sm_bias_hw(s, bias));
    float lit;
    SM_PCF(lit, f, PCF_SAMPLES, hw_2x2)
    return lit;
}
