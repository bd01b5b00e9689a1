// bevy_pcss: Bevy's PCSS for spot and directional lights (see techniques/bevy.c).
#include "bevy_filters.glsl"

// The light's size as Bevy takes it (its `radius`, or the sun's
// soft_shadow_size): techniques/bevy.c says how it follows from the scene's
// light.
float bevy_light_size()
{
    return BEVY_PCSS_LIGHT_SIZE_SCALE * sm_light_radius() * (sm_sun() ? sm.far_world - sm.near_world : 1.0);
}

// Bevy's depth of a hardware depth here: a spot's is near / z (an infinite
// reversed-Z perspective), the sun's its orthographic depth, reversed.
float bevy_depth(float d_hw)
{
    return sm_sun() ? d_hw : sm.near_world / sm_planar_depth(d_hw);
}

float shadow_visibility(ShadowInput s)
{
    float ref;
    vec2 uv = bevy_lookup(s, BEVY_PCSS_NORMAL_BIAS, BEVY_PCSS_DEPTH_BIAS, ref);
    float light_size = bevy_light_size(), texel_size = bevy_texel_size();
    // search_for_blockers_in_shadow_map: the 8 fixed points, unturned, at
    // light_size / (texel_size * size) uv, reading the depth through a
    // linear sampler; a blocker is at least as near the light as the
    // receiver
    vec2 search = light_size / (texel_size * vec2(sm.map_size_texels));
    float z_sum = 0.0, blockers = 0.0;
    for (int i = 0; i < 8; i++) {
        float d = sm_depth_bilinear(bevy_flip(uv + BEVY_D3D_POINTS[i] * search));
        if (d >= ref) {
            z_sum += d;
            blockers += 1.0;
        }
    }
    // Bevy's blocker depth is 0 when none is found: the blur's floor then
    // decides, and the filter runs all the same
    // (z is above 0 but for a receiver moved past the sun's map's far plane)
    float z_blocker = blockers > 0.0 ? bevy_depth(z_sum / blockers) : 0.0, z = max(bevy_depth(ref), 1e-6);
    float blur = max((z_blocker - z) * light_size / z, 0.5);
    return bevy_jimenez(uv, ref, blur, false, s.frag_coord);
}
