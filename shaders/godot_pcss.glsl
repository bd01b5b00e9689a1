// godot_pcss: Godot 4's soft shadows of a light with a size (see techniques/godot.c).
#include "godot_filters.glsl"

// The light's diameter (light_size) from the scene's light: a disk light's,
// a rect light's equal-area disk's; the sun's angular diameter, 2 alpha.
float godot_light_size()
{
    return sm_sun() ? 2.0 * atan(sm_light_radius()) : 2.0 * sm_light_radius();
}

// Godot's depth of a hardware depth here: a spot's map is reversed-Z
// perspective from z_near = min(0.025, range) to its range (here the map's
// far plane); the sun's is its orthographic depth, reversed, as here.
float godot_depth(float d_hw)
{
    if (sm_sun())
        return d_hw;
    float f = sm.far_world, n = min(0.025, f), z = sm_planar_depth(d_hw);
    return n * (f - z) / (z * (f - n));
}

float shadow_visibility(ShadowInput s)
{
    float depth_hw;
    godot_lookup(s, GODOT_PCSS_NORMAL_BIAS, s.uv, depth_hw);
    float ref = godot_ref(depth_hw, GODOT_PCSS_BIAS, GODOT_PCSS_BLUR);
    float size = GODOT_PCSS_LIGHT_SIZE_SCALE * godot_light_size();
    int taps = GODOT_PCSS_TAPS[GODOT_PCSS_QUALITY];
    mat2 rotation = godot_rotation(s.frag_coord, GODOT_PCSS_ANIMATE_NOISE != 0);
    float z_receiver;  // the receiver's depth as the penumbra's formula takes it
    vec2 uv_size;      // the search's radius
    if (sm_sun()) {
        // tan of the angular distance (the full angle) times the receiver's
        // distance from the map's near plane, in the map's uv
        uv_size = tan(size) * (s.depth_world - sm.near_world) / sm.near_window_world * GODOT_PCSS_BLUR;
        z_receiver = ref;
    } else {
        // (size / 2 / range) / tan(half angle) of the map, times the
        // receiver's distance along the axis over the range: Godot's
        // z_norm, linear, against the perspective depths its blockers
        // average (a mix of depth spaces, kept as Godot has it)
        float range = sm.far_world, z_norm = s.depth_world / range;
        vec2 tan_half = 0.5 * sm.near_window_world / sm.near_world;
        uv_size = (0.5 * size / range) / tan_half * z_norm * GODOT_PCSS_BLUR;
        z_receiver = z_norm;
    }
    // blocker search: bilinear raw depths nearer the light than the receiver, averaged
    float blocker_sum = 0.0, blockers = 0.0;
    for (int i = 0; i < taps; i++) {
        float d = sm_depth_bilinear(s.uv + (rotation * godot_vogel(i, taps)) * uv_size);
        if (d > ref) {
            blocker_sum += godot_depth(d);
            blockers += 1.0;
        }
    }
    if (blockers == 0.0)
        SM_EARLY_OUT(1.0)
    float blocker = blocker_sum / blockers;
    // (the sun's denominator is the blocker's distance from the map's near
    // plane: a blocker on it gives a ratio as large as the fit's margin
    // allows; kept above 1e-4)
    uv_size *= (blocker - z_receiver) / max(1.0 - blocker, 1e-4);
    return godot_pcf(s.uv, ref, uv_size, taps, rotation);
}
