// bevy_pcss: Bevy's PCSS for spot and directional lights (see techniques/bevy.c).
#include "bevy_filters.glsl"

// The light's size as Bevy takes it (its `radius`, or the sun's
// soft_shadow_size): techniques/bevy.c says how it follows from the scene's
// light.
float bevy_light_size()
{
    vec2 extent = sm_sun() ? sm.light_size_uv * (sm.far_world - sm.near_world) * sm.near_window_world
                           : sm.light_size_uv * sm.near_window_world;
    // a rect light as the disk of its area; a disk light and the sun's cone as they are
    float radius = SM_RECT_LIGHT ? sqrt(extent.x * extent.y / 3.14159265) : 0.5 * extent.x;
    return BEVY_PCSS_LIGHT_SIZE_SCALE * radius;
}

// Bevy's depth of a hardware depth here: a spot's is near / z (an infinite
// reversed-Z perspective), the sun's its orthographic depth, reversed.
float bevy_depth(float d_hw)
{
    return sm_sun() ? d_hw : sm.near_world / sm_planar_depth(d_hw);
}

// A linear (bilinear) read of the raw depth, as Bevy's blocker search reads
// its map through a filtering sampler: one gather, weighted.
float bevy_depth_bilinear(vec2 uv)
{
    SM_FETCHED(1);
    vec4 t = textureGather(sm_depth, uv, 0);  // (0,1) (1,1) (1,0) (0,0)
    vec2 w = fract(uv * vec2(sm.map_size_texels) - 0.5);
    return mix(mix(t.w, t.z, w.x), mix(t.x, t.y, w.x), w.y);
}

float shadow_visibility(ShadowInput s)
{
    float ref;
    vec2 uv = bevy_lookup(s, BEVY_PCSS_NORMAL_BIAS, BEVY_PCSS_DEPTH_BIAS, ref);
    float light_size = bevy_light_size(), texel_size = bevy_texel_size();
    // search_for_blockers_in_shadow_map: the 8 fixed points, unturned, at
    // light_size / (texel_size * size) uv; a blocker is at least as near
    // the light as the receiver
    vec2 search = light_size / (texel_size * vec2(sm.map_size_texels));
    float z_sum = 0.0, blockers = 0.0;
    for (int i = 0; i < 8; i++) {
        float d = bevy_depth_bilinear(bevy_flip(uv + BEVY_D3D_POINTS[i] * search));
        if (d >= ref) {
            z_sum += d;
            blockers += 1.0;
        }
    }
    // Bevy's blocker depth is 0 when none is found: the blur's floor then
    // decides, and the filter runs all the same
    float z_blocker = blockers > 0.0 ? bevy_depth(z_sum / blockers) : 0.0, z = bevy_depth(ref);
    float blur = max((z_blocker - z) * light_size / z, 0.5);
    return bevy_jimenez(uv, ref, blur, false, s.frag_coord);
}
