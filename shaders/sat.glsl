// Reading the summed-area table of the moments (see sat_build.comp): the
// mean and variance of linear depth over any box, past the map's edges too,
// from 16 SAT values, whatever the box's size.
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

// A box's extent along one axis, as weights of the pairs (first line, last
// line) of SAT_PAIRS among the 4 SAT lines read around the edges of its
// in-map part: the 4 bilinear pairs of those edges (fractions f_lo, f_hi
// into the texels they fall in), then the edge texel's own pair times the
// width past that edge. Past the low edge the in-map part starts at line 0,
// so lines 0-1 bound texel 0; past the high edge it ends at line n, so
// lines 2-3 bound texel n - 1.
const ivec2 SAT_PAIRS[6] = ivec2[](ivec2(0, 2), ivec2(0, 3), ivec2(1, 2), ivec2(1, 3), ivec2(0, 1),
                                   ivec2(2, 3));

float[6] sat_pair_weights(float f_lo, float f_hi, float past_lo, float past_hi)
{
    return float[6]((1.0 - f_lo) * (1.0 - f_hi), (1.0 - f_lo) * f_hi, f_lo * (1.0 - f_hi),
                    f_lo * f_hi, past_lo, past_hi);
}

// Mean and variance of linear depth over the box centre_uv ± half_uv of the
// map extended past its edges by the edge policy (clamp-to-edge,
// techniques/shadowmap.h); centre_uv is in the map (sm_inside). The box
// keeps its full area; for int32 its side is capped at sm.sat_max_box_texels
// (no overflow). Its edges fall at fractional texel positions: the SAT is
// read bilinearly, which is the exact integral of the texels'
// piecewise-constant moments over the in-map part. Past an edge each column
// (row) repeats the edge one, which adds the width past it times the edge
// column's sum over the in-map rows, and past a corner its area times the
// corner texel: boxes of the same 16 values, so no more reads. x = mean,
// y = variance (not clamped); returns false for an empty box.
bool sat_mean_variance(vec2 centre_uv, vec2 half_uv, out vec2 mean_var)
{
    float n = sm.map_size_texels;
    vec2 half_texels = min(half_uv * n, vec2(0.5 * sm.sat_max_box_texels));
    vec2 lo = centre_uv * n - half_texels, hi = centre_uv * n + half_texels;
    float area = (hi.x - lo.x) * (hi.y - lo.y);
    mean_var = vec2(0.0);
    if (!(area > 0.0))
        return false;
    // The 4 x 4 SAT values around the corners of the in-map part.
    vec2 in_lo = clamp(lo, 0.0, n), in_hi = clamp(hi, 0.0, n);
    ivec2 i0 = min(ivec2(floor(in_lo)), ivec2(n) - 1), i1 = min(ivec2(floor(in_hi)), ivec2(n) - 1);
    vec2 f0 = in_lo - vec2(i0), f1 = in_hi - vec2(i1);
    ivec4 xs = ivec4(i0.x, i0.x + 1, i1.x, i1.x + 1), ys = ivec4(i0.y, i0.y + 1, i1.y, i1.y + 1);
    uvec2 s[16];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            s[r * 4 + c] = sat_at(xs[c], ys[r]);
    vec2 past_lo = in_lo - lo, past_hi = hi - in_hi;
    float wx[6] = sat_pair_weights(f0.x, f1.x, past_lo.x, past_hi.x);
    float wy[6] = sat_pair_weights(f0.y, f1.y, past_lo.y, past_hi.y);
    // An x pair and a y pair bound a box of texels, summed exactly. A box
    // inside the map gives the edges' pairs weight 0, and they are summed
    // anyway: on llvmpipe skipping them cost more than their 20 box sums
    // (savsm's receiver pass on map_border, 512^2, 1024^2 map: 34 ms with
    // the 16 bilinear sums alone, 35 with all 36, 41 with the edges' behind
    // an if, 46 with a loop bound of 4 or 6).
    vec2 sum = vec2(0.0);
    for (int j = 0; j < 6; j++)
        for (int i = 0; i < 6; i++) {
            ivec2 x = SAT_PAIRS[i], y = SAT_PAIRS[j];
            sum += wx[i] * wy[j] * sat_box_sum(s[y.x * 4 + x.x], s[y.x * 4 + x.y], s[y.y * 4 + x.x],
                                               s[y.y * 4 + x.y]);
        }
    vec2 m = sum / area;
    if (sm.sat_format == SM_SAT_FP32_CENTERED)
        mean_var = vec2(m.x + 0.5, m.y - m.x * m.x);
    else
        mean_var = vec2(m.x, m.y - m.x * m.x);
    return true;
}
