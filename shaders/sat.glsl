// Reading the summed-area table of the moments (see sat_build.comp): the
// mean and variance of linear depth over any box of the map, from 16 SAT
// values, whatever the box's size.
#include "shadow_common.glsl"

layout(std430, binding = SM_BINDING_MOMENTS_SAT) readonly buffer SatBuffer { uvec2 sat[]; };

uvec2 sat_at(int x, int y)
{
    return sat[y * (int(sm.map_size_texels) + 1) + x];
}

// The sum over the box [x0, x1) x [y0, y1) from its corner values
// s00 = S(x0, y0), s10 = S(x1, y0), s01 = S(x0, y1), s11 = S(x1, y1), as
// floats. int32: the difference wraps modulo 2^32 and is exact; the
// fixed-point scale keeps every box this code forms below 2^31, so a box
// with x0 > x1 (both box edges in one texel) reads correctly as negative.
vec2 sat_box_sum(uvec2 s00, uvec2 s10, uvec2 s01, uvec2 s11)
{
    if (sm.sat_format == SM_SAT_INT32)
        return vec2(ivec2(s11 - s01 - s10 + s00)) / sm.sat_scale;
    return (uintBitsToFloat(s11) - uintBitsToFloat(s01)) - (uintBitsToFloat(s10) - uintBitsToFloat(s00));
}

// Mean and variance of linear depth over the box centre_uv ± half_uv, edges
// at fractional texel positions: the SAT is read bilinearly, which is the
// exact integral of the texels' piecewise-constant moments over the box. The
// box is clipped to the map and, for int32, to sm.sat_max_box_texels. x =
// mean, y = variance (not clamped); returns false when nothing is left.
bool sat_mean_variance(vec2 centre_uv, vec2 half_uv, out vec2 mean_var)
{
    float n = sm.map_size_texels;
    vec2 half_texels = min(half_uv * n, vec2(0.5 * sm.sat_max_box_texels));
    vec2 lo = clamp(centre_uv * n - half_texels, 0.0, n), hi = clamp(centre_uv * n + half_texels, 0.0, n);
    float area = (hi.x - lo.x) * (hi.y - lo.y);
    mean_var = vec2(0.0);
    if (!(area > 0.0))
        return false;
    // The 4 x 4 SAT values around the box's corners.
    ivec2 i0 = min(ivec2(floor(lo)), ivec2(n) - 1), i1 = min(ivec2(floor(hi)), ivec2(n) - 1);
    vec2 f0 = lo - vec2(i0), f1 = hi - vec2(i1);
    ivec4 xs = ivec4(i0.x, i0.x + 1, i1.x, i1.x + 1), ys = ivec4(i0.y, i0.y + 1, i1.y, i1.y + 1);
    uvec2 s[16];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            s[r * 4 + c] = sat_at(xs[c], ys[r]);
    vec2 wx0 = vec2(1.0 - f0.x, f0.x), wx1 = vec2(1.0 - f1.x, f1.x);
    vec2 wy0 = vec2(1.0 - f0.y, f0.y), wy1 = vec2(1.0 - f1.y, f1.y);
    vec2 sum = vec2(0.0);
    for (int a = 0; a < 2; a++)          // left edge: column a
        for (int b = 2; b < 4; b++)      // right edge: column b
            for (int c = 0; c < 2; c++)  // bottom edge: row c
                for (int d = 2; d < 4; d++) {
                    float w = wx0[a] * wx1[b - 2] * wy0[c] * wy1[d - 2];
                    sum += w * sat_box_sum(s[c * 4 + a], s[c * 4 + b], s[d * 4 + a], s[d * 4 + b]);
                }
    vec2 m = sum / area;
    if (sm.sat_format == SM_SAT_FP32_CENTERED)
        mean_var = vec2(m.x + 0.5, m.y - m.x * m.x);
    else
        mean_var = vec2(m.x, m.y - m.x * m.x);
    return true;
}
