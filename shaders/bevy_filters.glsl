// Bevy's shadow filters for spot and directional lights (techniques/bevy.c):
// crates/bevy_pbr/src/render/shadow_sampling.wesl and render/utils.wesl, as
// read at bevyengine/bevy 0.19.1 (the same in 0.20.0-dev). Bevy's map is
// addressed with v running down (uv = ndc * (0.5, -0.5) + 0.5), GL's with v
// up: every filter below works in Bevy's coordinates (bevy_flip, its own
// inverse) so that its texel grid and its patterns' handedness are Bevy's.
// (Bevy's window position runs down from the top, GL's up from the bottom:
// its noise field is mirrored here, the same noise.)
#include "shadow_taps.glsl"

vec2 bevy_flip(vec2 uv) { return vec2(uv.x, 1.0 - uv.y); }

// Bevy's biases, in its sampling shader: the lookup moved towards the
// light by depth_bias world units and along the geometric normal by
// normal_bias x sqrt(2) texels of the map at the receiver
// (fetch_spot_shadow: times 2 tan(outer) / size at the distance along the
// axis; a cascade's: times its texel), whatever the angle; the reference
// depth the moved point's. Returns Bevy's uv of it.
vec2 bevy_lookup(ShadowInput s, float normal_bias, float depth_bias, out float ref)
{
    vec3 offset = depth_bias * sm_to_light(s.pos_world) + s.normal_world * normal_bias * 1.41421356 * sm_texel_world(s);
    vec2 uv;
    sm_offset_lookup(s, offset, uv, ref);
    return bevy_flip(uv);
}

// One bilinear hardware comparison (Bevy's sample_shadow_map_hardware), at
// Bevy's uv.
float bevy_lit_2x2(vec2 uv_bevy, float ref)
{
    return sm_lit_2x2(bevy_flip(uv_bevy), ref);
}

// random_rotation_matrix: interleaved gradient noise as render/utils.wesl
// has it, the pixel centre moved by 5.588238 a frame (frame modulo 64;
// not temporal: frame 1, always); WGSL's mat2x2(cos, -sin, sin, cos) is
// column major, a turn by -2 pi ign.
mat2 bevy_rotation(vec2 pixel, bool temporal)
{
    uint frame = temporal ? uint(sm_noise_frame) : 1u;
    float a = 6.28318531 * sm_ign(pixel + 5.588238 * float(frame % 64u));
    return mat2(cos(a), -sin(a), sin(a), cos(a));
}

// Jimenez 2014's 8-point spiral (utils.wesl's SPIRAL_OFFSET_*), as Bevy
// stores it.
const vec2 BEVY_SPIRAL[8] = vec2[8](vec2(-0.7071, 0.7071), vec2(-0.0000, -0.8750), vec2(0.5303, 0.5303),
                                    vec2(-0.6250, -0.0000), vec2(0.3536, -0.3536), vec2(-0.0000, 0.3750),
                                    vec2(-0.1768, -0.1768), vec2(0.1250, 0.0000));

// The D3D 8x MSAA positions / 8, the PCSS blocker search's fixed points.
const vec2 BEVY_D3D_POINTS[8] = vec2[8](vec2(0.125, -0.375), vec2(-0.125, 0.375), vec2(0.625, 0.125),
                                        vec2(-0.375, -0.625), vec2(-0.625, 0.625), vec2(-0.875, -0.125),
                                        vec2(0.375, 0.875), vec2(0.875, -0.875));

// The `texel_size` Bevy's filters take: a spot light's is the constant
// SPOT_SHADOW_TEXEL_SIZE ("determined by trial and error"); a directional
// cascade's its texel's world size (the cascade's diameter over the map's
// size: here the sun map's wider side over its texels).
float bevy_texel_size()
{
    return sm_sun() ? sm_texel_world_at(sm.near_world) : 0.0134277345;  // the sun's: at any depth
}

// Castano 2013's 5 x 5 tent from 9 bilinear comparisons
// (sample_shadow_map_castano_thirteen): per axis weights 4 - 3s, 7, 1 + 3s
// at offsets (3 - 2s) / (4 - 3s) - 2, (3 + s) / 7, s / (1 + 3s) + 2 texels
// from the texel centre below the nearest corner.
float bevy_castano(vec2 uv_bevy, float ref)
{
    vec2 size = vec2(sm.map_size_texels);
    vec2 uv = uv_bevy * size;
    vec2 base = floor(uv + 0.5);
    vec2 st = uv + 0.5 - base;
    vec2 base_uv = (base - 0.5) / size;
    vec3 wu = vec3(4.0 - 3.0 * st.x, 7.0, 1.0 + 3.0 * st.x);
    vec3 wv = vec3(4.0 - 3.0 * st.y, 7.0, 1.0 + 3.0 * st.y);
    vec3 ou = vec3((3.0 - 2.0 * st.x) / wu.x - 2.0, (3.0 + st.x) / 7.0, st.x / wu.z + 2.0);
    vec3 ov = vec3((3.0 - 2.0 * st.y) / wv.x - 2.0, (3.0 + st.y) / 7.0, st.y / wv.z + 2.0);
    float sum = 0.0;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++)
            sum += wu[i] * wv[j] * bevy_lit_2x2(base_uv + vec2(ou[i], ov[j]) / size, ref);
    return sum * (1.0 / 144.0);
}

// Jimenez 2014's spiral (sample_shadow_map_jimenez_fourteen): 8 bilinear
// comparisons at the turned spiral's points, scaled to
// f * blur_size / (texel_size * size) uv, f the linear map of texel_size
// from [0.00390625, 0.022949219] to [0.015, 0.035] (unclamped).
float bevy_jimenez(vec2 uv_bevy, float ref, float blur_size, bool temporal, vec2 pixel)
{
    float texel_size = bevy_texel_size();
    float f = 0.015 + (texel_size - 0.00390625) * (0.02 / (0.022949219 - 0.00390625));
    vec2 scale = f * blur_size / (texel_size * vec2(sm.map_size_texels));
    mat2 rotation = bevy_rotation(pixel, temporal);
    float sum = 0.0;
    for (int i = 0; i < 8; i++)
        sum += bevy_lit_2x2(uv_bevy + (rotation * BEVY_SPIRAL[i]) * scale, ref);
    return sum * 0.125;
}
