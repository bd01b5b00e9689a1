// Hamburger 4MSM (Peters and Klein 2015), shared by msm and msm_soft: from
// four moments b = (E[w], E[w²], E[w³], E[w⁴]) of the depths w in a filter
// region, the least share G of them in front of a depth z that the moments
// allow, and where that share sits.

// The moment bias's target, towards which b is drawn by alpha: Peters and
// Klein's (0, 0.375, 0, 0.375), moments of a spread, symmetric
// distribution, which keep the Hankel matrix well conditioned.
const vec4 MSM_BIAS_TARGET = vec4(0.0, 0.375, 0.0, 0.375);

vec4 msm_bias(vec4 b, float alpha)
{
    return mix(b, MSM_BIAS_TARGET, alpha);
}

// An alpha that guarantees the Hankel matrix B of moments known to within
// step / 2 each positive definite, as B of any true distribution is
// (fixed point of step 2^-k, rounded to nearest: a box mean of such texels
// errs by no more, in exact arithmetic; fp32's own error is the caller's
// bias to cover). With b0 = 1 exact, the error matrix E has b1 and b3 in
// two entries each, b2 in three, b4 in one: ||E||_2 <= ||E||_F <=
// sqrt(8) step / 2. Biasing adds alpha (H(target) - B), and H(target)'s
// least eigenvalue is (1.375 - sqrt(0.953125)) / 2 = 0.19936; so alpha
// 0.19936 >= (1 - alpha) sqrt(2) step suffices, alpha >= 7.094 step to
// first order. Sufficient, not least: E rarely aligns with H(target)'s
// weakest direction. Without it the quadratic's roots can land anywhere:
// with alpha 3e-5 on a 4096² map (k = 13) 78 % of the lit pixels went
// dark.
float msm_quantisation_bias(float step)
{
    return 7.1 * step;
}

// G; and z_blocker, the mean depth of that share: the distribution with
// moments b that puts the least mass in front of z is supported on z and
// the two roots z2 <= z3 of the quadratic whose coefficients c solve
// B c = (1, z, z²), B the Hankel matrix of b; G is the mass of the roots in
// front of z. Its first moment is b1 = (1 - G) z + (the roots' mass times
// their mean), so where both roots are in front, z_blocker =
// (b1 - (1 - G) z) / G; where only z2 is, z_blocker = z2. With G = 0,
// z_blocker = z.
float msm_occlusion(vec4 b, float z, out float z_blocker)
{
    // B = L D L^T with L unit lower triangular. The moment bias keeps d2
    // and d3 positive; the floors guard fp32 rounding, so no division
    // below is by zero.
    float d2 = max(b.y - b.x * b.x, 1e-12);
    float l32 = (b.z - b.x * b.y) / d2;
    float d3 = max(b.w - b.y * b.y - l32 * l32 * d2, 1e-12);
    float y2 = z - b.x;
    float y3 = z * z - b.y - l32 * y2;
    float c3 = y3 / d3;
    float c2 = y2 / d2 - l32 * c3;
    float c1 = 1.0 - b.x * c2 - b.y * c3;
    // The other two support points: the roots of c3 x² + c2 x + c1. Where
    // c3 is 0 the roots are infinite or NaN (GLSL leaves NaN through
    // max() and clamp() undefined): read as lit.
    float p = c2 / c3, q = c1 / c3;
    float r = sqrt(max(0.25 * p * p - q, 0.0));
    float z2 = -0.5 * p - r, z3 = -0.5 * p + r;
    z_blocker = z;
    if (isnan(z2) || isnan(z3) || isinf(z2) || isinf(z3) || z <= z2)
        return 0.0;
    if (z <= z3) {
        z_blocker = max(z2, -1.0);
        return clamp((z * z3 - b.x * (z + z3) + b.y) / ((z3 - z2) * (z - z2)), 0.0, 1.0);
    }
    float g = clamp(1.0 - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((z - z2) * (z - z3)), 0.0, 1.0);
    if (g > 0.0)
        z_blocker = clamp((b.x - (1.0 - g) * z) / g, -1.0, z);
    return g;
}
