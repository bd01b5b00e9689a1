// vssm: variance soft shadow mapping with kernel subdivision (see
// techniques/vssm.c).
#include "shadow_common.glsl"
#include "pcss_geometry.glsl"
#include "chebyshev.glsl"
#include "sat.glsl"

const int N = VSSM_SUBDIVISIONS;

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

// The centre of sub-box (i, j) of the N x N grid over centre ± half.
vec2 vssm_sub_centre(vec2 centre, vec2 half_uv, int i, int j)
{
    return centre + half_uv * ((2.0 * vec2(i, j) + 1.0) / float(N) - 1.0);
}

float shadow_visibility(ShadowInput s)
{
    float t = s.depth;
    vec2 mean_var;

    // 1. Blockers of the search box; where its estimate is not to be
    // trusted, the mean of the sub-boxes' estimates.
    vec2 search_uv = sm_search_half_uv(s, VSSM_LIGHT_SIZE_SCALE);
    if (!sat_mean_variance(s.uv, search_uv, mean_var))
        return 1.0;
    vec2 blockers = vssm_blockers(mean_var, t);
    if (!vssm_reliable(mean_var, t) && N > 1) {
        blockers = vec2(0.0);
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                vec2 c = vssm_sub_centre(s.uv, search_uv, i, j);
                if (sat_mean_variance(c, search_uv / float(N), mean_var))
                    blockers += vssm_blockers(mean_var, vssm_receiver_depth(s, c));
            }
        blockers /= float(N * N);
    }
    if (!(blockers.x > 0.0) || blockers.x < VSSM_MIN_BLOCKER_FRACTION)  // none: lit, also at a fraction of 0
        return 1.0;
    float z_occ = blockers.y / blockers.x;

    // 2. Penumbra as PCSS; 3. VSM over it, again subdivided where not to
    // be trusted.
    vec2 filter_uv = sm_filter_half_uv(s, sm_world_depth(z_occ), VSSM_LIGHT_SIZE_SCALE);
    if (!sat_mean_variance(s.uv, filter_uv, mean_var))
        return 1.0;
    if (vssm_reliable(mean_var, t) || N == 1)
        return reduce_light_bleeding(chebyshev_upper_bound(mean_var.x, mean_var.y, t, VSSM_MIN_VARIANCE),
                                     VSSM_BLEED_REDUCTION);
    float v = 0.0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            vec2 c = vssm_sub_centre(s.uv, filter_uv, i, j);
            float p = 1.0;
            if (sat_mean_variance(c, filter_uv / float(N), mean_var))
                p = chebyshev_upper_bound(mean_var.x, mean_var.y, vssm_receiver_depth(s, c), VSSM_MIN_VARIANCE);
            v += reduce_light_bleeding(p, VSSM_BLEED_REDUCTION);
        }
    return v / float(N * N);
}
