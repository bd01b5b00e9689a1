// Godot 4's shadow filters (techniques/godot.c): servers/rendering/
// renderer_rd/shaders/scene_forward_lights_inc.glsl, the quality tables of
// renderer_scene_render_rd.cpp and light_storage.cpp's radii.
#include "shadow_taps.glsl"

// Quality level q (GODOT_QUALITY_*: hard, very_low, low, medium, high,
// ultra): positional_soft_shadow_filter_set_quality's tables.
const int GODOT_PCF_TAPS[6] = int[6](0, 1, 4, 8, 16, 32);
const int GODOT_PCSS_TAPS[6] = int[6](4, 4, 8, 12, 24, 32);
const float GODOT_QUALITY_RADIUS[6] = float[6](1.0, 1.5, 2.0, 2.0, 3.0, 4.0);

// get_vogel_disk: point i of n at radius sqrt(i + 0.5) / sqrt(n), angle
// 2.4 i (Godot's golden angle, 2.4 radians).
vec2 godot_vogel(int i, int n)
{
    float r = sqrt(float(i) + 0.5) / sqrt(float(n)), a = 2.4 * float(i);
    return r * vec2(cos(a), sin(a));
}

// quick_hash (interleaved gradient noise) of the window position moved by
// taa_frame_count * 5.588238 (0 without TAA: `animate`; Godot wraps the
// count at its jitter's phase count, the frame here does not wrap);
// mat2(vec2(c, -s), vec2(s, c)).
mat2 godot_rotation(vec2 frag_coord, bool animate)
{
    float a = 6.28318531 * sm_ign(frag_coord + vec2((animate ? sm_noise_frame : 0.0) * 5.588238));
    return mat2(vec2(cos(a), -sin(a)), vec2(sin(a), cos(a)));
}

// sample_pcf_shadow / sample_directional_pcf_shadow: n taps of the turned
// Vogel disk of radius radius_uv, each a bilinear hardware comparison,
// averaged; no tap (Hard): one comparison at the centre.
float godot_pcf(vec2 uv, float ref, vec2 radius_uv, int taps, mat2 rotation)
{
    if (taps == 0)
        return sm_lit_2x2(uv, ref);
    float sum = 0.0;
    for (int i = 0; i < taps; i++)
        sum += sm_lit_2x2(uv + (rotation * godot_vogel(i, taps)) * radius_uv, ref);
    return sum / float(taps);
}


// Godot's normal bias, in the filter's own shader: the lookup moved along
// the geometric normal by, for a spot, dist x normal_bias x 10 / map size
// (light_storage.cpp's uniform) times 1 - |N.L|; for the sun, normal_bias
// texels of its map times 1 - max(0, dot(light_dir, -N)) (light_dir
// towards the light: the whole offset on every face the sun lights), the
// part along the light removed. normal_bias < 0: Godot's default for the
// light, 1 (SpotLight3D) or 2 (DirectionalLight3D).
void godot_lookup(ShadowInput s, float normal_bias, out vec2 uv, out float depth_hw)
{
    vec3 to_light = sm_to_light(s.pos_world);
    float nl = dot(s.normal_world, to_light);
    if (normal_bias < 0.0)
        normal_bias = sm_sun() ? 2.0 : 1.0;
    vec3 offset;
    if (sm_sun()) {
        offset = s.normal_world * (1.0 - max(0.0, -nl)) * normal_bias * sm_texel_world(s);
        offset -= to_light * dot(offset, to_light);
    } else {
        float light_length = length(sm.light_pos_world.xyz - s.pos_world);
        offset = s.normal_world * light_length * normal_bias * 10.0 * sm.texel_size_uv.x * (1.0 - abs(nl));
    }
    sm_offset_lookup(s, offset, uv, depth_hw);
}

// Godot's depth bias (shadow_bias; < 0: Godot's default for the light,
// 0.03 for SpotLight3D, 0.1 for DirectionalLight3D), times the filter's
// soft_shadow_scale, as the shader applies it to the reference depth
// depth_hw: a spot adds bias / 100 / z_norm to its clip z before the
// divide, which on a reversed-Z map from z_near = min(0.025, range) is a
// distance, bias / 100 x range / z_near, along the light (on the spot's
// axis; off it smaller by the cosine to the axis, not modelled); the sun
// moves the point towards the light by bias / 100 of its cascade's depth
// range.
float godot_ref(float depth_hw, float bias, float soft_shadow_scale)
{
    if (bias < 0.0)
        bias = sm_sun() ? 0.1 : 0.03;
    float b = bias / 100.0 * soft_shadow_scale, range = sm.far_world;
    float linear = sm_sun() ? b : b * range / min(0.025, range) / (sm.far_world - sm.near_world);
    return sm_hw_depth(max(sm_linear_depth(depth_hw) - linear, 0.0));
}
