// Depth conversions of docs/design.md §5, shared by the receiver pass and the
// products' compute passes. Linear depth d is planar depth rescaled to [0, 1]
// between the frustum's near and far planes; hardware depth is reversed Z
// (1 at near, 0 at far).
#include "shadow_block.glsl"

// The sun's map is orthographic (light_pos_world.w = 0: a direction): its
// hardware depth is linear depth reversed, d_hw = 1 - d. An area light's
// is perspective, d_hw = n (f - z) / (z (f - n)).
bool sm_sun()
{
    return sm.light_pos_world.w == 0.0;
}

// Hardware depth -> planar depth in world units. `precise` here and below:
// no fused multiply-adds, so the CPU reproduces it bit for bit
// (tests/test_sat.c).
float sm_planar_depth(float d_hw)
{
    float n = sm.near_world, f = sm.far_world;
    precise float z = sm_sun() ? n + (1.0 - d_hw) * (f - n) : n * f / (d_hw * (f - n) + n);
    return z;
}

// Hardware depth -> linear depth in [0, 1].
float sm_linear_depth(float d_hw)
{
    float n = sm.near_world, f = sm.far_world;
    precise float d = sm_sun() ? 1.0 - d_hw : (sm_planar_depth(d_hw) - n) / (f - n);
    return d;
}

// The moment family's depth (evsm's warps, msm's moments): linear depth
// mapped to w = 2d - 1 in [-1, 1], the product's and the receiver's alike.
float sm_moment_depth(float d)
{
    return 2.0 * d - 1.0;
}

// evsm's warps of w with exponents c = (c+, c-): (e^{c+ w}, -e^{-c- w}).
vec2 sm_evsm_warp(float w, vec2 c)
{
    return vec2(exp(c.x * w), -exp(-c.y * w));
}

// Linear depth in [0, 1] -> hardware depth.
float sm_hw_depth(float d)
{
    float n = sm.near_world, f = sm.far_world;
    float z = n + d * (f - n);
    return sm_sun() ? 1.0 - d : n * (f - z) / (z * (f - n));
}

// Linear depth in [0, 1] -> planar depth in world units.
float sm_world_depth(float d)
{
    return sm.near_world + d * (sm.far_world - sm.near_world);
}
