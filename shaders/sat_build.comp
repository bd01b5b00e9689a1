#version 450 core
// Summed-area table of the moments (Crow 1984; for shadows Lauritzen 2007,
// "Summed-area variance shadow maps", GPU Gems 3 ch. 8). Two dispatches of
// this shader: SAT_PASS_ROWS (one invocation per row, a serial prefix sum of
// the row's moments, converted from the depth map on the way: a separate
// moments pass would cost more than both scans) then SAT_PASS_COLUMNS (one
// per column, in place). The
// table is (N+1)^2 with a zero first row and column, so a box sum never
// needs a bounds test. On llvmpipe a serial scan per row/column beat a
// shared-memory work-group scan, and storage buffers beat image load/store.
//
// Formats (sm.sat_format):
//   SM_SAT_FP32           float sums of (d, d²), stored as bits
//   SM_SAT_FP32_CENTERED  float sums of (d - 0.5, (d - 0.5)²): smaller sums,
//                         fewer bits lost (the variance is shift-invariant)
//   SM_SAT_INT32          fixed point, round(m * sm.sat_scale), summed in
//                         uint32 with wrap-around: a 4-tap box difference is
//                         exact modulo 2^32, hence exact while the box sum fits
#include "depth.glsl"

layout(local_size_x = 64) in;
layout(binding = SM_BINDING_DEPTH) uniform sampler2D depth_map;
layout(std430, binding = SM_BINDING_MOMENTS_SAT) buffer SatBuffer { uvec2 sat[]; };

void main()
{
    int n = int(sm.map_size_texels), stride = n + 1, line = int(gl_GlobalInvocationID.x);
#if SAT_PASS_ROWS
    if (line >= n)
        return;
    int base = (line + 1) * stride;
    sat[base] = uvec2(0);
    if (sm.sat_format == SM_SAT_INT32) {
        uvec2 acc = uvec2(0);
        for (int x = 0; x < n; x++) {
            float d = sm_linear_depth(texelFetch(depth_map, ivec2(x, line), 0).r);
            precise vec2 q = vec2(d, d * d) * sm.sat_scale + 0.5;  // as tests/test_sat.c does
            acc += uvec2(q);
            sat[base + x + 1] = acc;
        }
    } else {
        bool centered = sm.sat_format == SM_SAT_FP32_CENTERED;
        vec2 acc = vec2(0.0);
        for (int x = 0; x < n; x++) {
            float d = sm_linear_depth(texelFetch(depth_map, ivec2(x, line), 0).r);
            vec2 m = centered ? vec2(d - 0.5, (d - 0.5) * (d - 0.5)) : vec2(d, d * d);
            acc += m;
            sat[base + x + 1] = floatBitsToUint(acc);
        }
    }
#else  // SAT_PASS_COLUMNS
    int x = line + 1;  // column 0 stays zero
    if (x > n)
        return;
    if (sm.sat_format == SM_SAT_INT32) {
        uvec2 acc = uvec2(0);
        for (int y = 1; y <= n; y++) {
            acc += sat[y * stride + x];
            sat[y * stride + x] = acc;
        }
    } else {
        vec2 acc = vec2(0.0);
        for (int y = 1; y <= n; y++) {
            acc += uintBitsToFloat(sat[y * stride + x]);
            sat[y * stride + x] = floatBitsToUint(acc);
        }
    }
#endif
}
