// Reading a summed-area table of moments (see sat_build.comp): the mean
// moments over any box, past the map's edges too, from 16 SAT values,
// whatever the box's size. A shader reads one table: the moments_sat
// product's (d, d²) by default, the msm_sat product's (w, w², w³, w⁴) with
// SAT_CHANNELS 4 defined before including this file.
#include "shadow_common.glsl"
#include "sat_table.glsl"

layout(std430, binding = SAT_BINDING) readonly buffer SatBuffer { SAT_UVEC sat[]; };

SAT_UVEC sat_at(int x, int y)
{
    SM_FETCHED(1);
    return sat[y * (int(sm.map_size_texels) + 1) + x];
}

// The sum over the box [x0, x1) x [y0, y1) from its corner values
// s00 = S(x0, y0), s10 = S(x1, y0), s01 = S(x0, y1), s11 = S(x1, y1), as
// floats. int32: the difference wraps modulo 2^32 and is exact; the
// fixed-point scale keeps every box this code forms below 2^31, so a box
// with x0 > x1 (both box edges in one texel) reads correctly as negative.
SAT_VEC sat_box_sum(SAT_UVEC s00, SAT_UVEC s10, SAT_UVEC s01, SAT_UVEC s11)
{
    if (SAT_TABLE.format == SM_SAT_INT32)
        return SAT_VEC(SAT_IVEC(s11 - s01 - s10 + s00)) / SAT_TABLE.scale;
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

// The mean moments over the box centre_uv ± half_uv of the map extended
// past its edges by the edge policy (clamp-to-edge,
// techniques/shadowmap.h); centre_uv may lie outside the map (vssm's
// sub-boxes near an edge), which the same weights cover: for a box wholly
// past the low edge, in_lo = in_hi = 0, and past_lo = -lo plus a negative
// past_hi = hi weigh the edge texel by the box's width (the edge-policy
// test probes such boxes, on both tables). The box
// keeps its full area; for int32 its side is capped at SAT_TABLE.max_box_texels
// (no overflow). Its edges fall at fractional texel positions: the SAT is
// read bilinearly, which is the exact integral of the texels'
// piecewise-constant moments over the in-map part. Past an edge each column
// (row) repeats the edge one, which adds the width past it times the edge
// column's sum over the in-map rows, and past a corner its area times the
// corner texel: boxes of the same 16 values, so no more reads. As stored:
// 2 channels fp32_centered gives (d - 0.5, (d - 0.5)²). Returns false for an
// empty box (mean 0).
bool sat_box_mean(vec2 centre_uv, vec2 half_uv, out SAT_VEC mean)
{
    float n = sm.map_size_texels;
    vec2 half_texels = min(half_uv * n, vec2(0.5 * SAT_TABLE.max_box_texels));
    vec2 lo = centre_uv * n - half_texels, hi = centre_uv * n + half_texels;
    float area = (hi.x - lo.x) * (hi.y - lo.y);
    mean = SAT_VEC(0.0);
    if (!(area > 0.0))
        return false;
    // The 4 x 4 SAT values around the corners of the in-map part.
    vec2 in_lo = clamp(lo, 0.0, n), in_hi = clamp(hi, 0.0, n);
    ivec2 i0 = min(ivec2(floor(in_lo)), ivec2(n) - 1), i1 = min(ivec2(floor(in_hi)), ivec2(n) - 1);
    vec2 f0 = in_lo - vec2(i0), f1 = in_hi - vec2(i1);
    ivec4 xs = ivec4(i0.x, i0.x + 1, i1.x, i1.x + 1), ys = ivec4(i0.y, i0.y + 1, i1.y, i1.y + 1);
    SAT_UVEC s[16];
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
    SAT_VEC sum = SAT_VEC(0.0);
    for (int j = 0; j < 6; j++)
        for (int i = 0; i < 6; i++) {
            ivec2 x = SAT_PAIRS[i], y = SAT_PAIRS[j];
            sum += wx[i] * wy[j] * sat_box_sum(s[y.x * 4 + x.x], s[y.x * 4 + x.y], s[y.y * 4 + x.x],
                                               s[y.y * 4 + x.y]);
        }
    mean = sum / area;
    return true;
}

#if SAT_CHANNELS == 2
// Mean and variance of linear depth over that box: x = mean, y = variance
// (not clamped); false for an empty box.
bool sat_mean_variance(vec2 centre_uv, vec2 half_uv, out vec2 mean_var)
{
    vec2 m;
    bool some = sat_box_mean(centre_uv, half_uv, m);
    mean_var = vec2(m.x + (SAT_TABLE.format == SM_SAT_FP32_CENTERED ? 0.5 : 0.0), m.y - m.x * m.x);
    return some;
}
#endif
