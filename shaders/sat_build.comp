#version 450 core
// Summed-area tables of moments (Crow 1984; for shadows Lauritzen 2007,
// "Summed-area variance shadow maps", GPU Gems 3 ch. 8). Two dispatches of
// this shader: SAT_PASS_ROWS (one invocation per row, a serial prefix sum of
// the row's moments, converted from the depth map on the way: a separate
// moments pass would cost more than both scans) then SAT_PASS_COLUMNS (one
// per column, in place). The table is (N+1)^2 with a zero first row and
// column, so a box sum never needs a bounds test. On llvmpipe a serial scan
// per row/column beat a shared-memory work-group scan, and storage buffers
// beat image load/store.
//
// SAT_CHANNELS 2: the moments_sat product, (d, d²) of linear depth d.
// SAT_CHANNELS 4: the msm_sat product, (w, w², w³, w⁴) of w = 2d - 1, the
// msm product's moments (Peters et al. 2016 filter them by a SAT).
//
// Formats (SAT_TABLE.format):
//   SM_SAT_FP32           float sums, stored as bits
//   SM_SAT_FP32_CENTERED  2 channels: float sums of (d - 0.5, (d - 0.5)²),
//                         smaller sums, fewer bits lost (the variance is
//                         shift-invariant). 4 channels: not offered, w is
//                         centred on [-1, 1] already
//   SM_SAT_INT32          fixed point, floor(m * SAT_TABLE.scale + 0.5), summed
//                         in uint32 with wrap-around (two's complement for
//                         w's odd powers): a 4-tap box difference is exact
//                         modulo 2^32, hence exact while the box sum fits
#include "depth.glsl"
#include "sat_table.glsl"

layout(std430, binding = SAT_BINDING) buffer SatBuffer { SAT_UVEC sat[]; };

#if SAT_CHANNELS == 4
vec4 sat_moments(float d)
{
    float w = sm_moment_depth(d), w2 = w * w;
    return vec4(w, w2, w2 * w, w2 * w2);
}
#else
vec2 sat_moments(float d)
{
    float c = SAT_TABLE.format == SM_SAT_FP32_CENTERED ? d - 0.5 : d;
    return vec2(c, c * c);
}
#endif

layout(local_size_x = 64) in;
layout(binding = SM_BINDING_DEPTH) uniform sampler2D depth_map;

void main()
{
    int n = int(sm.map_size_texels), stride = n + 1, line = int(gl_GlobalInvocationID.x);
#if SAT_PASS_ROWS
    if (line >= n)
        return;
    int base = (line + 1) * stride;
    sat[base] = SAT_UVEC(0);
    if (SAT_TABLE.format == SM_SAT_INT32) {
        SAT_UVEC acc = SAT_UVEC(0);
        for (int x = 0; x < n; x++) {
            float d = sm_linear_depth(texelFetch(depth_map, ivec2(x, line), 0).r);
            precise SAT_VEC q = sat_moments(d) * SAT_TABLE.scale + 0.5;  // as tests/test_sat.c does
            acc += SAT_UVEC(SAT_IVEC(floor(q)));
            sat[base + x + 1] = acc;
        }
    } else {
        SAT_VEC acc = SAT_VEC(0.0);
        for (int x = 0; x < n; x++) {
            acc += sat_moments(sm_linear_depth(texelFetch(depth_map, ivec2(x, line), 0).r));
            sat[base + x + 1] = floatBitsToUint(acc);
        }
    }
#else  // SAT_PASS_COLUMNS
    int x = line + 1;  // column 0 stays zero
    if (x > n)
        return;
    if (SAT_TABLE.format == SM_SAT_INT32) {
        SAT_UVEC acc = SAT_UVEC(0);
        for (int y = 1; y <= n; y++) {
            acc += sat[y * stride + x];
            sat[y * stride + x] = acc;
        }
    } else {
        SAT_VEC acc = SAT_VEC(0.0);
        for (int y = 1; y <= n; y++) {
            acc += uintBitsToFloat(sat[y * stride + x]);
            sat[y * stride + x] = floatBitsToUint(acc);
        }
    }
#endif
}
