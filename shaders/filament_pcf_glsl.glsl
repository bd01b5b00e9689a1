// filament_pcf_glsl: Filament's PCF (ShadowSample_PCF_Low), see techniques/filament_presets.c.
#include "filament_filters.glsl"

float shadow_visibility(ShadowInput s)
{
    // computeLightSpacePosition: the lookup moved along the geometric
    // normal by normalBias texels at the receiver, times sin of the angle
    // to the spot's axis as Filament passes it (pointing away from the
    // light: 1 on every surface facing the light), or to the sun
    float c = clamp(dot(s.normal_world, sm_sun() ? sm_to_light(s.pos_world) : sm.light_dir_world.xyz),
                    0.0, 1.0);
    float scale = sm_sun() ? 0.5 : 1.0;  // Filament halves the sun's
    vec2 uv;
    float depth;
    sm_offset_lookup(s, s.normal_world * sqrt(1.0 - c * c) * scale * FILAMENT_PCF_GLSL_NORMAL_BIAS * sm_texel_world(s),
                     uv, depth);
    float ref = depth + sm_bias_hw(s, FILAMENT_PCF_GLSL_CONSTANT_BIAS);

    // Castano 2013, 3 x 3 from 4 bilinear comparisons: per axis weights
    // 3 - 2s, 1 + 2s at (2 - s) / (3 - 2s) - 1, s / (1 + 2s) + 1 texels
    vec2 size = vec2(sm.map_size_texels);
    vec2 t = uv * size + 0.5;
    vec2 base = (floor(t) - 0.5) / size, st = fract(t);
    vec2 uw = vec2(3.0 - 2.0 * st.x, 1.0 + 2.0 * st.x), vw = vec2(3.0 - 2.0 * st.y, 1.0 + 2.0 * st.y);
    vec2 u = vec2((2.0 - st.x) / uw.x - 1.0, st.x / uw.y + 1.0) / size.x;
    vec2 v = vec2((2.0 - st.y) / vw.x - 1.0, st.y / vw.y + 1.0) / size.y;
    float sum = uw.x * vw.x * sm_lit_2x2(base + vec2(u.x, v.x), ref)
              + uw.y * vw.x * sm_lit_2x2(base + vec2(u.y, v.x), ref)
              + uw.x * vw.y * sm_lit_2x2(base + vec2(u.x, v.y), ref)
              + uw.y * vw.y * sm_lit_2x2(base + vec2(u.y, v.y), ref);
    return sum * (1.0 / 16.0);
}
