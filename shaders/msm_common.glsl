// 4MSM (Peters and Klein 2015), shared by msm and msm_soft: from four
// moments b = (E[w], E[w²], E[w³], E[w⁴]) of the depths w in a filter
// region, the least share G of them in front of a depth z that the moments
// allow, and where that share sits. Hamburger: over distributions on the
// whole line; Hausdorff: over those on [-1, 1], where the depths are, a
// bound as tight or tighter.

// The moment bias's target, towards which b is drawn by alpha: Peters and
// Klein's (0, 0.375, 0, 0.375), moments of a spread, symmetric
// distribution, which keep the Hankel matrix well conditioned.
const vec4 MSM_BIAS_TARGET = vec4(0.0, 0.375, 0.0, 0.375);

vec4 msm_bias(vec4 b, float alpha)
{
    return mix(b, MSM_BIAS_TARGET, alpha);
}

// Hausdorff's target: the uniform distribution on [-1, 1]. It must lie
// inside the moment space of distributions on [-1, 1], which Peters and
// Klein's (on {-1, 0, 1}: of index 2) does not: mixed with one depth,
// their moments stay on that space's edge, where the matrix
// E[(1 - W²)(1, W)^T (1, W)] is singular, and fp32's rounding alone
// (2^-25 of the moments) gave a receiver on its own depth 146 alpha of
// shadow (test_msm's control). The uniform's Hankel and localised
// matrices have least eigenvalues 0.0793 and 2/15: the bias keeps both
// positive definite against moment errors E with ||E|| < 0.0793 alpha.
// fp32's rounding alone (||E|| <= sqrt(8) 2^-25 = 8.4e-8, as for
// msm_quantisation_bias) is covered from alpha 1.1e-6 up; below that
// (moment_bias goes down to 1e-7), and for the blur's own rounding, it is
// not guaranteed.
const vec4 MSM_HAUSDORFF_BIAS_TARGET = vec4(0.0, 1.0 / 3.0, 0.0, 0.2);

vec4 msm_hausdorff_bias(vec4 b, float alpha)
{
    return mix(b, MSM_HAUSDORFF_BIAS_TARGET, alpha);
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
// first order: SM_MSM_QUANTISATION_FACTOR (techniques/technique.h) is
// just above that. Sufficient, not least: E rarely aligns with H(target)'s
// weakest direction. Without it the quadratic's roots can land anywhere:
// with alpha 3e-5 on a 4096² map (k = 13) 78 % of the lit pixels went
// dark.
float msm_quantisation_bias(float step)
{
    return SM_MSM_QUANTISATION_FACTOR * step;
}

// The quadratic's roots z2 <= z3; NaN or infinite where B is singular.
void msm_roots(vec4 b, float z, out float z2, out float z3)
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
    // The other two support points: the roots of c3 x² + c2 x + c1.
    float p = c2 / c3, q = c1 / c3;
    float r = sqrt(max(0.25 * p * p - q, 0.0));
    z2 = -0.5 * p - r, z3 = -0.5 * p + r;
}

// G; and z_blocker, the mean depth of that share: the distribution with
// moments b that puts the least mass in front of z is supported on z and
// the two roots z2 <= z3 of the quadratic whose coefficients c solve
// B c = (1, z, z²), B the Hankel matrix of b; G is the mass of the roots in
// front of z. Its first moment is b1 = (1 - G) z + (the roots' mass times
// their mean), so where both roots are in front, z_blocker =
// (b1 - (1 - G) z) / G; where only z2 is, z_blocker = z2. With G = 0,
// z_blocker = z. Where c3 is 0 the roots are infinite or NaN (GLSL leaves
// NaN through max() and clamp() undefined): read as lit.
float msm_hamburger(vec4 b, float z, float z2, float z3, out float z_blocker)
{
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

float msm_occlusion(vec4 b, float z, out float z_blocker)
{
    float z2, z3;
    msm_roots(b, z, z2, z3);
    return msm_hamburger(b, z, z2, z3, z_blocker);
}

// E[(V - r.x)(V - r.y)(V - r.z)(V - r.w)] from m = (E[V], .., E[V⁴]).
float msm_quartic_mean(vec4 m, vec4 r)
{
    float e1 = r.x + r.y + r.z + r.w;
    float e2 = r.x * (r.y + r.z + r.w) + r.y * (r.z + r.w) + r.z * r.w;
    float e3 = r.x * r.y * (r.z + r.w) + r.z * r.w * (r.x + r.y);
    float e4 = r.x * r.y * r.z * r.w;
    return m.w - e1 * m.z + e2 * m.y - e3 * m.x + e4;
}

// Hausdorff 4MSM: G over distributions on [-1, 1]. Where Hamburger's
// roots lie in [-1, 1] its bound is this one. Where one leaves, the least
// mass in front of z is placed on {-1, z, x, 1} (the canonical
// representation of index 3 through z with both ends), x solving
// E[(W + 1)(W - z)(W - x)(W - 1)] = 0; G is the mass in front of z: that
// at -1, plus x's where x < z. G is taken as E[p(W)] for the quartic p
// that is 1 in front of z and 0 behind at the four points, touching at x
// (p'(x) = 0): then G's derivative in x is the very expectation that
// fixes x, 0, and an x off by fp32 rounding errs G only to second order.
// All in V = W - z, the moments shifted to the receiver (m): the shift
// itself cancels O(1) terms once, in fp32, and what follows works on the
// small shifted moments without cancelling again.
// msm_soft keeps Hamburger, whose z_blocker it needs.
float msm_occlusion_hausdorff(vec4 b, float z)
{
    float z2, z3, z_blocker;
    msm_roots(b, z, z2, z3);
    if (z > -1.0 && z < 1.0 && !(z2 >= -1.0 && z3 <= 1.0)) {  // NaN roots fail the test: here
        float zz = z * z;
        vec4 m = vec4(b.x - z,
                      b.y - 2.0 * z * b.x + zz,
                      b.z - 3.0 * z * b.y + 3.0 * zz * b.x - zz * z,
                      b.w - 4.0 * z * b.z + 6.0 * zz * b.y - 4.0 * zz * z * b.x + zz * zz);
        float u0 = -1.0 - z, u1 = 1.0 - z;  // the ends, shifted
        // v = x - z from E[(V - u0) V (V - v)(V - u1)] = 0; (V - u0)(V - u1)
        // = V² + 2 z V - (1 - z²).
        float v = (m.w + 2.0 * z * m.z - (1.0 - zz) * m.y) / (m.z + 2.0 * z * m.y - (1.0 - zz) * m.x);
        if (v > 0.0 && z + v < 1.0) {
            // Only -1 in front: p = V (V - v)² (V - u1), scaled to 1 at u0.
            float g = msm_quartic_mean(m, vec4(0.0, v, v, u1)) / (u0 * (u0 - v) * (u0 - v) * (u0 - u1));
            return clamp(g, 0.0, 1.0);
        }
        if (v < 0.0 && z + v > -1.0) {
            // -1 and x in front: 1 - p = (V - u0)(V - v)² l(V), l linear
            // with 1 - p = 1 at z (V = 0) and at 1 (V = u1).
            float l0 = -1.0 / (u0 * v * v), l1 = 1.0 / ((u1 - u0) * (u1 - v) * (u1 - v));
            float g = 1.0 - (l1 * msm_quartic_mean(m, vec4(u0, v, v, 0.0)) -
                             l0 * msm_quartic_mean(m, vec4(u0, v, v, u1))) / u1;
            return clamp(g, 0.0, 1.0);
        }
        // Rounding left no valid x (0, NaN, infinite or past an end).
    }
    return msm_hamburger(b, z, z2, z3, z_blocker);  // a bound still, and this one where its roots hold
}
