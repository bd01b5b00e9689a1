// vssm: variance soft shadow mapping with kernel subdivision (see
// techniques/vssm.c).
#include "shadow_common.glsl"
#include "pcss_geometry.glsl"
#include "chebyshev.glsl"
#include "sat.glsl"

const int N = VSSM_SUBDIVISIONS;
// Adaptive: levels of 2 x 2 splits, ceil(log2 N) (N <= 8).
const int LEVELS = N > 4 ? 3 : N > 2 ? 2 : N > 1 ? 1 : 0;

// The depth t of the receiver at uv: its own depth at its own uv; with
// receiver_plane, elsewhere its plane's (fitted in hardware depth, where
// it is affine in uv, clamped to the frustum).
float vssm_receiver_depth(ShadowInput s, vec2 uv)
{
#if VSSM_RECEIVER_PLANE
    return sm_linear_depth(clamp(s.depth_hw + dot(s.depth_hw_gradient, uv - s.uv), 0.0, 1.0));
#else
    return s.depth;
#endif
}

// A box's blockers at receiver depth t, from its mean and variance: x =
// the blocked share 1 - alpha, alpha the Chebyshev bound; y = that share
// times its mean depth z_occ = (mu - alpha t) / (1 - alpha). None where
// t <= mu (the bound says lit).
vec2 vssm_blockers(vec2 mean_var, float t)
{
    if (t <= mean_var.x)
        return vec2(0.0);
    float alpha = chebyshev_upper_bound(mean_var.x, mean_var.y, t, VSSM_MIN_VARIANCE);
    float z_occ = clamp((mean_var.x - alpha * t) / (1.0 - alpha), 0.0, t);
    return (1.0 - alpha) * vec2(1.0, z_occ);
}

// Is the box's Chebyshev estimate to be trusted? It assumes two depths, the
// receiver's t and one blocker depth, and there are two ways a box shows
// that it holds something else (surfaces beyond the receiver): t <= mu,
// where the bound says "lit" (the paper's case), and a variance so large
// that the blocker depth the two-depth model needs, mu - s² / (t - mu),
// lies nearer than the near plane (depth 0), where there is no geometry.
bool vssm_reliable(vec2 mean_var, float t)
{
    float var = max(mean_var.y, VSSM_MIN_VARIANCE);
    return t > mean_var.x && mean_var.x - var / (t - mean_var.x) >= 0.0;
}

// One box's estimate at receiver depth t: the search's blockers, or the
// filter's visibility (in x).
vec2 vssm_estimate(bool search, vec2 mean_var, float t)
{
    if (search)
        return vssm_blockers(mean_var, t);
    float p = chebyshev_upper_bound(mean_var.x, mean_var.y, t, VSSM_MIN_VARIANCE);
    return vec2(reduce_light_bleeding(p, VSSM_BLEED_REDUCTION), 0.0);
}

// The box centre ± half_uv, whose estimate is not to be trusted, as the
// area-weighted mean of estimates of its parts, each at the receiver's
// depth at its centre. Uniform: N x N sub-boxes. Adaptive (the paper's
// scheme): 2 x 2, and each part still not to be trusted split again, down
// to parts 1/2^LEVELS of the box wide; a part trusted on the way is
// estimated whole. A part past the map reads as no blockers, lit.
vec2 vssm_subdivided(ShadowInput s, vec2 centre, vec2 half_uv, bool search)
{
    vec2 sum = vec2(0.0), mean_var;
    const vec2 outside = search ? vec2(0.0) : vec2(1.0, 0.0);
#if VSSM_ADAPTIVE
    // Depth first; a pop pushes at most 4, and parts at the last level are
    // never pushed: at most 3 LEVELS - 2 entries of (centre, level),
    // sized 3 LEVELS + 1 so that N = 1 (LEVELS 0) still compiles.
    vec3 stack[3 * LEVELS + 1];
    int top = 0;
    stack[top++] = vec3(centre, 0.0);
    while (top > 0) {
        vec3 e = stack[--top];
        int level = int(e.z) + 1;
        vec2 h = half_uv / float(1 << level);
        float weight = 1.0 / float(1 << (2 * level));
        for (int k = 0; k < 4; k++) {
            vec2 c = e.xy + h * vec2((k & 1) != 0 ? 1.0 : -1.0, (k & 2) != 0 ? 1.0 : -1.0);
            float t = vssm_receiver_depth(s, c);
            if (!sat_mean_variance(c, h, mean_var))
                sum += weight * outside;
            else if (level < LEVELS && !vssm_reliable(mean_var, t))
                stack[top++] = vec3(c, float(level));
            else
                sum += weight * vssm_estimate(search, mean_var, t);
        }
    }
    return sum;
#else
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            vec2 c = centre + half_uv * ((2.0 * vec2(i, j) + 1.0) / float(N) - 1.0);
            sum += sat_mean_variance(c, half_uv / float(N), mean_var)
                       ? vssm_estimate(search, mean_var, vssm_receiver_depth(s, c))
                       : outside;
        }
    return sum / float(N * N);
#endif
}

// The box at the pixel, centre ± half_uv, of moments mean_var: its
// estimate at the pixel's depth, or its parts' where that is not to be
// trusted.
vec2 vssm_box(ShadowInput s, vec2 half_uv, vec2 mean_var, bool search)
{
    return N > 1 && !vssm_reliable(mean_var, s.depth) ? vssm_subdivided(s, s.uv, half_uv, search)
                                                      : vssm_estimate(search, mean_var, s.depth);
}

float shadow_visibility(ShadowInput s)
{
    vec2 mean_var;

    // 1. Blockers of the search box; where its estimate is not to be
    // trusted, the mean of the sub-boxes' estimates.
    vec2 search_uv = sm_search_half_uv(s, VSSM_LIGHT_SIZE_SCALE);
    if (!sat_mean_variance(s.uv, search_uv, mean_var))
        SM_EARLY_OUT(1.0);
    vec2 blockers = vssm_box(s, search_uv, mean_var, true);
    if (!(blockers.x > 0.0) || blockers.x < VSSM_MIN_BLOCKER_FRACTION)  // none: lit, also at a fraction of 0
        SM_EARLY_OUT(1.0);
    float z_occ = blockers.y / blockers.x;

    // 2. Penumbra as PCSS; 3. VSM over it, again subdivided where not to
    // be trusted.
    vec2 filter_uv = sm_filter_half_uv(s, sm_world_depth(z_occ), VSSM_LIGHT_SIZE_SCALE);
    if (!sat_mean_variance(s.uv, filter_uv, mean_var))
        return 1.0;
    return vssm_box(s, filter_uv, mean_var, false).x;
}
