// pcss: blocker search -> penumbra -> PCF (see techniques/pcss.c).
#include "shadow_taps.glsl"
#include "pcss_geometry.glsl"

// seed 003's two radii: each step's own light size scale, 0 = light_size_scale
const float PCSS_SEARCH_SCALE = PCSS_SEARCH_LIGHT_SIZE_SCALE > 0.0 ? PCSS_SEARCH_LIGHT_SIZE_SCALE
                                                                    : PCSS_LIGHT_SIZE_SCALE;
const float PCSS_FILTER_SCALE = PCSS_FILTER_LIGHT_SIZE_SCALE > 0.0 ? PCSS_FILTER_LIGHT_SIZE_SCALE
                                                                    : PCSS_LIGHT_SIZE_SCALE;

// Early bail's probes (NVIDIA's PCSS integration): 8 of the search's taps,
// spread over the pattern, taps floor(k n / 8) for k = 0..7; i and n
// constants, so the test folds.
const int PCSS_PROBES = 8;
bool pcss_is_probe(int i, int n)
{
    int k = (i * PCSS_PROBES + n - 1) / n;  // the first k with floor(k n / 8) >= i
    return k < PCSS_PROBES && k * n < PCSS_PROBES * (i + 1);
}

float shadow_visibility(ShadowInput s)
{
    const bool plane = PCSS_RECEIVER_PLANE_BIAS != 0, bail = PCSS_EARLY_BAIL != 0;
    float bias = PCSS_CONSTANT_BIAS + (plane ? 0.0 : PCSS_SLOPE_BIAS * s.texel_depth_slope);
    float bias_hw = sm_bias_hw(s, bias);
    const bool square = SM_RECT_LIGHT;  // the taps follow the light's shape
    vec2 noise = sm_rotation_noise(s.frag_coord, PCSS_ROTATION, PCSS_ANIMATE_NOISE != 0);

    // 1. Blocker search: the mean planar depth of the occluding taps; with
    // early bail the probes first, and where they agree that is the answer.
    TapFrame search = sm_tap_frame(s, sm_search_half_uv(s, PCSS_SEARCH_SCALE), square, PCSS_PATTERN,
                                   PCSS_BLOCKER_SAMPLES, noise, plane, bias_hw);
    float z_sum = 0.0, blockers = 0.0, stored;
#define PCSS_BLOCKER_TAP(i) \
    if (sm_occluded_at(search, sm_tap_point(search, i), stored)) { \
        z_sum += sm_planar_depth(stored); \
        blockers += 1.0; \
    }
#define PCSS_PROBE_TAP(i) if (bail && pcss_is_probe(i, PCSS_BLOCKER_SAMPLES)) PCSS_BLOCKER_TAP(i)
#define PCSS_OTHER_TAP(i) if (!bail || !pcss_is_probe(i, PCSS_BLOCKER_SAMPLES)) PCSS_BLOCKER_TAP(i)
    SM_UNROLL(PCSS_BLOCKER_SAMPLES, PCSS_PROBE_TAP)
    if (bail && (blockers == 0.0 || blockers == float(PCSS_PROBES)))
        SM_EARLY_OUT(blockers == 0.0 ? 1.0 : 0.0)
    SM_UNROLL(PCSS_BLOCKER_SAMPLES, PCSS_OTHER_TAP)
    if (blockers == 0.0)
        SM_EARLY_OUT(1.0)
    if (blockers == float(PCSS_BLOCKER_SAMPLES))
        SM_EARLY_OUT(0.0)

    // 2. Penumbra by similar triangles; 3. PCF over it (another scramble).
    vec2 filter_uv = sm_penumbra_half_uv(s, z_sum / blockers, PCSS_FILTER_SCALE);
    float lit;
    SM_PCF(lit, sm_tap_frame(s, filter_uv, square, PCSS_PATTERN, PCSS_FILTER_SAMPLES, noise.yx, plane, bias_hw),
           PCSS_FILTER_SAMPLES, false)
    return lit;
}

// The penumbra mask's question (its pre-pass, shaders/penumbra_mask.frag):
// is the block whose footprint on the map spans block_half_uv around s.uv
// lit (1), in umbra (0) or in between (0.5)? Asked of 16 taps of the
// blocker search widened by the footprint: lit or umbra only when all agree.
float shadow_classify(ShadowInput s, vec2 block_half_uv)
{
    const bool plane = PCSS_RECEIVER_PLANE_BIAS != 0;
    float bias = PCSS_CONSTANT_BIAS + (plane ? 0.0 : PCSS_SLOPE_BIAS * s.texel_depth_slope);
    vec2 noise = sm_rotation_noise(s.frag_coord, PCSS_ROTATION, PCSS_ANIMATE_NOISE != 0);
    TapFrame search = sm_tap_frame(s, sm_search_half_uv(s, PCSS_SEARCH_SCALE) + block_half_uv, SM_RECT_LIGHT,
                                   PCSS_PATTERN, 16, noise, plane, sm_bias_hw(s, bias));
    float blockers = 0.0, stored;
#define PCSS_CLASSIFY_TAP(i) blockers += sm_occluded_at(search, sm_tap_point(search, i), stored) ? 1.0 : 0.0;
    SM_UNROLL(16, PCSS_CLASSIFY_TAP)
    return blockers == 0.0 ? 1.0 : blockers == 16.0 ? 0.0 : 0.5;
}
