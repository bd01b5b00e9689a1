// PCSS geometry (Fernando 2005) for a perspective light, shared by pcss and
// pcss_savsm. A light of size L at depth 0 and a receiver at planar depth z_r: a blocker
// at depth z_b occludes a light point l where the segment receiver -> l
// crosses depth z_b. Projected from the light centre onto the near plane n,
// those crossings cover, around the receiver's own uv, a region of size
//     light_size_uv * n * (z_r - z_b) / (z_b * z_r)
// (the light's shape, scaled). For a blocker plane parallel to the light this
// region is exact: the visible fraction is the unblocked share of it.
#include "shadow_common.glsl"

//
// The sun (an orthographic map): the segments from the receiver run along
// the cone of half-angle alpha, so at depth z_b they cover a disk of radius
// (z_r - z_b) tan alpha round the receiver's uv, in world units: the
// similar triangles taken in world space (light_size_uv is 2 tan alpha over
// the window's width).

// Half-extent (uv) of that region for a blocker at world depth z_b.
vec2 sm_penumbra_half_uv(ShadowInput s, float z_b, float light_scale)
{
    float z_r = s.depth_world;
    if (sm_sun())
        return 0.5 * light_scale * sm.light_size_uv * max(z_r - z_b, 0.0);
    return 0.5 * light_scale * sm.light_size_uv * sm.near_world * max(z_r - z_b, 0.0)
           / (max(z_b, sm.near_world) * z_r);
}

// The filter box of the SAT techniques for a blocker at world depth z_b:
// that region for a rect light; for a disk light the square of the same
// area; at least one texel wide.
vec2 sm_filter_half_uv(ShadowInput s, float z_b, float light_scale)
{
    vec2 h = sm_penumbra_half_uv(s, z_b, light_scale);
    if (!SM_RECT_LIGHT)
        h *= 0.88622693;  // sqrt(pi) / 2
    return max(h, 0.5 * sm.texel_size_uv);
}

// The blocker-search region: the same region for the nearest possible
// blocker (z_b = near), which contains every other.
vec2 sm_search_half_uv(ShadowInput s, float light_scale)
{
    return sm_penumbra_half_uv(s, sm.near_world, light_scale);
}
