// Not a technique: the texture-fetch probe of `shadowbench bench`. It does
// FETCH_PROBE_FIRST_TAPS + FETCH_PROBE_SECOND_TAPS nearest fetches of the depth map per
// pixel (two groups, as PCSS's blocker search and filter), spread like
// their taps, with the least arithmetic that keeps them alive: the receiver
// pass's time with it is the fetch limit a PCF-family technique is held to.
#include "shadow_taps.glsl"

float shadow_visibility(ShadowInput s)
{
    vec2 radius_uv = 8.0 * sm.texel_size_uv;
    float sum = 0.0;
#define PROBE_TAP(i) sum += textureLod(sm_depth, s.uv + sample_disk[i] * radius_uv, 0.0).r;
#define PROBE_TAP_2(i) sum += textureLod(sm_depth, s.uv - sample_disk[i] * radius_uv, 0.0).r;
    SM_UNROLL(FETCH_PROBE_FIRST_TAPS, PROBE_TAP)
    SM_UNROLL(FETCH_PROBE_SECOND_TAPS, PROBE_TAP_2)
    return sum / float(FETCH_PROBE_FIRST_TAPS + FETCH_PROBE_SECOND_TAPS);
}
