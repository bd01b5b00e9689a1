// msm: Hamburger 4MSM from four filtered power moments (see techniques/msm.c).
#include "shadow_common.glsl"

// G, the least share of occluder mass in front of z that the moments
// b = (E[w], E[w²], E[w³], E[w⁴]) allow (Peters and Klein 2015).
float msm_occlusion(vec4 b, float z)
{
    // B c = (1, z, z²), B = [[1, b1, b2], [b1, b2, b3], [b2, b3, b4]], by
    // B = L D L^T with L unit lower triangular.
    // The moment bias keeps d2 and d3 positive; the floors guard fp32
    // rounding, so no division below is by zero.
    float d2 = max(b.y - b.x * b.x, 1e-12);
    float l32 = (b.z - b.x * b.y) / d2;
    float d3 = max(b.w - b.y * b.y - l32 * l32 * d2, 1e-12);
    float y2 = z - b.x;
    float y3 = z * z - b.y - l32 * y2;
    float c3 = y3 / d3;
    float c2 = y2 / d2 - l32 * c3;
    float c1 = 1.0 - b.x * c2 - b.y * c3;
    // The other two support points: the roots of c3 x² + c2 x + c1.
    float p = c2 / c3, q = c1 / c3;
    float r = sqrt(max(0.25 * p * p - q, 0.0));
    float z2 = -0.5 * p - r, z3 = -0.5 * p + r;
    if (z <= z2)
        return 0.0;
    if (z <= z3)
        return clamp((z * z3 - b.x * (z + z3) + b.y) / ((z3 - z2) * (z - z2)), 0.0, 1.0);
    return clamp(1.0 - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((z - z2) * (z - z3)), 0.0, 1.0);
}

float shadow_visibility(ShadowInput s)
{
    vec4 b = textureGrad(sm_msm, s.uv, s.uv_dx, s.uv_dy);  // trilinear at the footprint
    b = mix(b, vec4(0.0, 0.375, 0.0, 0.375), MSM_MOMENT_BIAS);
    float z = sm_moment_depth(s.depth - MSM_DEPTH_BIAS);
    return 1.0 - msm_occlusion(b, z);
}
