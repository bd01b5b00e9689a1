// hdrp_pcss: Unity HDRP's High shadow filtering quality, PCSS (see techniques/hdrp.c).
#include "hdrp_filters.glsl"

// The scene's light as HDRP's: a spot's shapeRadius (a disk light's
// radius, a rect light's equal-area disk's), the sun's angular diameter
// (radians); times softnessScale.
float hdrp_light_size()
{
    return HDRP_PCSS_SOFTNESS_SCALE * (sm_sun() ? 2.0 * atan(sm_light_radius()) : sm_light_radius());
}

// SampleShadow_PCSS, a spot: radii in the tile's uv here (HDRP's are the
// 4096 atlas's: times 4096 / tile size).
float hdrp_pcss_punctual(ShadowInput s, vec2 uv, float z, mat2 rotation)
{
    const int blocker_n = HDRP_PCSS_BLOCKER_SAMPLES, filter_n = HDRP_PCSS_FILTER_SAMPLES;
    float tile = sm.map_size_texels, to_tile = 4096.0 / tile;
    // GetNonDirectionalSoftness: a quartic fitted to a ray-traced reference at 512
    float x = hdrp_light_size();
    float softness = (0.02403461 + 3.452916 * x - 1.362672 * x * x + 0.6700115 * x * x * x
                      + 0.2159474 * x * x * x * x) / 100.0 * (tile / 512.0);
    float max_softness = 0.04 * tile / 512.0;
    float search = min(softness + 1e-6, max_softness) * to_tile;
    float z_sum = 0.0, blockers = 0.0;
    for (int i = 0; i < blocker_n; i++) {
        vec2 tap = uv + rotation * (hdrp_spiral_direction(i) * search * sqrt((float(i) + 0.5) / float(blocker_n)));
        float d = sm_depth_nearest(tap);
        if (d > z) {
            z_sum += d;
            blockers += 1.0;
        }
    }
    float min_filter = HDRP_PCSS_MIN_FILTER_SIZE * 0.001 * to_tile, w = min_filter;
    if (blockers > 0.0) {
        float z_b = z_sum / blockers;
        // the blocker's distance from the light, at most 7.5, scales the softness
        float d = min(sm_planar_depth(z_b), 7.5);
        softness *= 3.298300241 - 2.001364639 * d + 0.4967311427 * d * d - 0.05464058455 * d * d * d
                    + 0.0021974 * d * d * d * d;
        softness = min(softness, max_softness);
        // PenumbraSizePunctual, of device depths
        w = max(softness * abs((z - z_b) / z_b) * to_tile, min_filter);
    }
    float lit = 0.0;
    for (int i = 0; i < filter_n; i++)
        lit += sm_lit_2x2(uv + rotation * (hdrp_spiral_direction(i) * w * sqrt((float(i) + 0.5) / float(filter_n))), z);
    return lit / float(filter_n);
}

// SampleShadow_PCSS_Directional: radii in the tile's uv; K converts device
// depth to HDRP's radial unit (|m00 / m22| of the map's projection).
float hdrp_pcss_directional(ShadowInput s, vec2 uv, float z, mat2 rotation)
{
    const int blocker_n = HDRP_PCSS_BLOCKER_SAMPLES, filter_n = HDRP_PCSS_FILTER_SAMPLES;
    float depth_range = sm.far_world - sm.near_world;
    float diam = hdrp_light_size(), t = tan(0.5 * diam);
    float k = 2.0 / sm.near_window_world.x * depth_range;
    float depth2radial = t * k;
    float max_sample_z = 0.56 / (2.0 * t) / depth_range;  // dirLightPCSSMaxPenumbraSize, as device depth
    float max_offset = 0.5 / depth_range;                  // dirLightPCSSMaxSamplingDistance
    float min_filter = 1.5 * sm.texel_size_uv.x;           // dirLightPCSSMinFilterSizeTexels
    // minFilterRadial2Depth and blockerRadial2Depth: HDRP takes the first's
    // angle as max(12, 10 degrees, diam), the second's as max(12 degrees,
    // diam): one value, so the search's choice between them is moot
    float radial2depth = 1.0 / (tan(0.5 * max(radians(12.0), diam)) * k);
    float search = max(min(1.0 - z, max_sample_z) * depth2radial, min_filter);
    float z_sum = 0.0, blockers = 0.0;
    for (int i = 0; i < blocker_n; i++) {
        float r = float(i) / float(blocker_n);  // the clumped spiral, exponent 2.0 x 0.5
        vec2 tap = uv + rotation * (hdrp_spiral_direction(i) * r * search);
        float coord_z = z + search * r * radial2depth;  // the receiver moved up the cone
        float d = sm_depth_nearest(tap);
        if (d > coord_z) {
            z_sum += d;
            blockers += 1.0;
        }
    }
    if (blockers == 0.0)
        SM_EARLY_OUT(1.0)
    float blocker_distance = min(abs(z_sum / blockers - z) * 0.9, max_sample_z);
    float filter_size = blocker_distance * depth2radial, sampling = max(filter_size, min_filter);
    max_offset = min(max_offset, 0.25 * blocker_distance);
    float lit = 0.0;
    for (int i = 0; i < filter_n; i++) {
        float r = sqrt((float(i) + 0.5) / float(filter_n));
        vec2 tap = uv + rotation * (hdrp_spiral_direction(i) * r * sampling);
        lit += sm_lit_2x2(tap, z + min(filter_size * r * radial2depth, max_offset));
    }
    return lit / float(filter_n);
}

float shadow_visibility(ShadowInput s)
{
    vec2 uv;
    float z = hdrp_ref(s, HDRP_PCSS_NORMAL_BIAS, HDRP_PCSS_SLOPE_BIAS, uv);
    mat2 rotation = hdrp_rotation(s.frag_coord, HDRP_PCSS_ANIMATE_NOISE != 0);
    return sm_sun() ? hdrp_pcss_directional(s, uv, z, rotation) : hdrp_pcss_punctual(s, uv, z, rotation);
}
