/* Unity HDRP's shadow filters as it ships them, re-implemented
 * (docs/presets.md): presets, shadowbench's own shaders following
 * Unity-Technologies/Graphics, HDRP 17.2 (Unity 6000.2):
 * com.unity.render-pipelines.high-definition/Runtime/Lighting/Shadow/
 * HDShadowAlgorithms.hlsl (which filter each quality level takes, the
 * biases), com.unity.render-pipelines.core/ShaderLibrary/Shadow/
 * ShadowSamplingTent.hlsl (the tents), HDShadowSampling.hlsl and
 * HDPCSS.hlsl (the taps, PCSS), HDShadowManager.cs and
 * HDAdditionalLightData.cs, HDGpuLightsBuilder.LightLoop.cs (the levels,
 * their defaults, the softness). Read file by file as stored (the newest
 * version of each found), not as one tagged tree.
 *
 * Confirmed against that source (shaders/hdrp_filters.glsl, hdrp_*.glsl):
 *   - the lookup: the normal, flipped towards the light, moves it by
 *     normalBias (0.75) x sqrt(2) texels at the receiver; every filter
 *     adds 1/65536 to the device depth;
 *   hdrp_pcf  the shadow filtering quality, punctual and directional
 *             alike Medium by default (HDShadowInitParameters.NewDefault):
 *             Low is the 3 x 3 tent for a spot and the 5 x 5 for the sun,
 *             Medium the 5 x 5 for a spot and the 7 x 7 for the sun. A
 *             tent N x N is a triangle of half-width N / 2 texels and 45
 *             degree sides centred at the receiver; each texel weighs the
 *             tent's area over it (per axis, N + 1 texels), adjacent texels
 *             are paired into one bilinear hardware comparison at b / (a +
 *             b) of the way from the first's centre: 4, 9 or 16 fetches.
 *             No receiver-plane bias.
 *   hdrp_pcss High: PCSS, 24 blocker and 16 filter taps by default
 *             (1 to 64), on a 64-direction Fibonacci spiral (2 pi frac(i
 *             (3 - sqrt 5) / 2)) turned by interleaved gradient noise of
 *             the pixel and TAA's frame index, 0 to 7
 *             (`animate_noise`). A spot: its softness a quartic of
 *             shapeRadius x softnessScale fitted at 512 texels
 *             (GetNonDirectionalSoftness), the search that radius (at most
 *             0.04 x tile / 512) in the 4096 reference atlas, point-sampled
 *             raw depths nearer than the receiver averaged; the softness
 *             times a quartic of the blocker's distance (at most 7.5), the
 *             penumbra it times |(z_r - z_b) / z_b| of device depths, at
 *             least Min Filter Size x 0.001 (also the radius with no
 *             blocker: the filter always runs). The sun: the search the cone's radius at the near
 *             plane (or at dirLightPCSSMaxPenumbraSize 0.56 / (2 tan(half
 *             angle)) if nearer), at least 1.5 texels, its taps clumped
 *             (i / N), each compared against the receiver moved up the
 *             cone; no blocker: lit; the filter the blocker distance x 0.9
 *             (at most that maximum) in radial units, its taps' depths
 *             moved up the cone by at most dirLightPCSSMaxSamplingDistance
 *             0.5 and a quarter of the blocker distance.
 *
 * Approximated, and why:
 *   - the weights are the tent integral in full precision; HDRP's code
 *     normalises by 0.44444 and 0.081632 (1/2.25, 1/12.25 truncated), so
 *     its weights sum to 0.99999 and 0.999992: a difference below 1e-5.
 *   - the map is shadowbench's at the run's size, as a tile of HDRP's
 *     default 4096 atlas; HDRP's map-side biases (a constant unit and a
 *     slope bias of 0.5 x 5, 0.5 x up to 18 for a soft PCSS spot) stand as
 *     slope_bias texels of the receiver's slope (2.5).
 *   - the light: a spot's shapeRadius is the disk light's radius or the
 *     rect light's equal-area disk's; the sun's angular diameter its own.
 *     A spot's blocker distance is its planar depth here (HDRP's
 *     LinearEyeDepth of the light's map); the sun's K = |m00 / m22| is the
 *     fitted map's 2 / width over 1 / depth range (HDRP reads it as tile
 *     uv; whether that halves it is not settled in its code either).
 *   - a spot's penumbra |(z_r - z_b) / z_b| divides hardware depths, which
 *     depend on the map's far plane: HDRP's is the light's range, here
 *     the fitted far plane, so wide penumbrae come out up to f / (f - z_b)
 *     wider than HDRP's at a long range would be;
 *   - HDRP renders a soft spot's map with a slope bias of 0.5 x up to 18
 *     (GetBaseBias); slope_bias keeps PCF's 2.5 unless tuned;
 *   - HDRP drops the taps that leave its tile, and lights a spot lookup
 *     within a texel of the tile's edge (its guard band); here the map
 *     continues as its edge texels for every technique (the edge policy,
 *     techniques/shadowmap.h), so neither is modelled;
 *   - the map's v axis is GL's: patterns are mirrored against HDRP's.
 *
 * How they fail: pcf is a fixed tent, 1.5 to 3.5 texels either side of
 * every edge, no contact hardening; pcss's spot softness is a fit to
 * HDRP's reference scenes (a quartic of the light's size and of the
 * blocker's distance), not the similar triangles, and its few taps are
 * noisy on wide penumbrae. */
#include "param_rows.h"

static const char *const hdrp_quality_names[] = {"low", "medium", NULL};

#define HDRP_SOURCE "Unity-Technologies/Graphics HDRP 17.2: Runtime/Lighting/Shadow/HDShadowSampling.hlsl"

#define HDRP_BIAS_ROWS(settings)                                                                          \
    {"normal_bias", "normalBias: the lookup moved along the normal (towards the light) by this x sqrt(2) "  \
     "texels", offsetof(settings, normal_bias), PARAM_FLOAT, 0.75, 0.0, 10.0, NULL, TUNE(0.0, 0.375, 0.75, 1.5, 3.0)}, \
    {"slope_bias", "the map's slope bias (HDRP's slopeBias 0.5 x base 5), texels of the receiver's depth "  \
     "slope", offsetof(settings, slope_bias), PARAM_FLOAT, 2.5, 0.0, 16.0, NULL, TUNE(0.0, 1.0, 2.5, 5.0)}

struct hdrp_pcf_settings {
    int quality;
    float normal_bias, slope_bias;
};

static const struct technique_param hdrp_pcf_params[] = {
    {"quality", "shadow filtering quality: low (3 x 3 tent for a spot, 5 x 5 for the sun), medium (the "
     "default: 5 x 5, 7 x 7); high is hdrp_pcss", offsetof(struct hdrp_pcf_settings, quality), PARAM_ENUM, 1, 0, 0,
     hdrp_quality_names, TUNE_CHOICES},
    HDRP_BIAS_ROWS(struct hdrp_pcf_settings),
    {NULL},
};

static const struct technique_preset hdrp_levels[] = {
    {"low", "quality=low", "Low: the 3 x 3 tent (the sun's 5 x 5), 4 (9) fetches"},
    {NULL},
};

static const struct technique_cell hdrp_pcf_cells[] = {
    {"grazing_receiver", {"normal_bias=0", "slope_bias=0"}},
    {"parallel_planes", {"quality=low"}},
    {NULL},
};

TECHNIQUE(hdrp_pcf, .needs = SM_DEPTH, .regression = hdrp_pcf_cells, .presets = hdrp_levels, .preset_of = "hdrp",
          .preset_source = HDRP_SOURCE,
          .summary = "Unity HDRP's tent PCF: 3 x 3 to 7 x 7 tents from 4 to 16 bilinear comparisons");

struct hdrp_pcss_settings {
    int blocker_samples, filter_samples;
    float softness_scale, min_filter_size;
    int animate_noise;
    float normal_bias, slope_bias;
};

static const struct technique_param hdrp_pcss_params[] = {
    {"blocker_samples", "blockerSampleCount: taps of the blocker search (1 to 64)",
     offsetof(struct hdrp_pcss_settings, blocker_samples), PARAM_INT, 24, 1, 64, NULL, TUNE(8, 16, 24, 32, 64)},
    {"filter_samples", "filterSampleCount: taps of the filter (1 to 64)",
     offsetof(struct hdrp_pcss_settings, filter_samples), PARAM_INT, 16, 1, 64, NULL, TUNE(8, 16, 32, 64)},
    {"softness_scale", "softnessScale: multiplies the light's shapeRadius or angular diameter",
     offsetof(struct hdrp_pcss_settings, softness_scale), PARAM_FLOAT, 1.0, 0.01, 10.0, NULL,
     TUNE(0.5, 1.0, 2.0, 4.0)},
    {"min_filter_size", "Min Filter Size (a spot's, 0 to 1: times 0.001 of the 4096 atlas, the filter's "
     "least radius)", offsetof(struct hdrp_pcss_settings, min_filter_size), PARAM_FLOAT, 0.1, 0.0, 1.0, NULL, NULL},
    PARAM_ROW_ANIMATE_NOISE(struct hdrp_pcss_settings),
    HDRP_BIAS_ROWS(struct hdrp_pcss_settings),
    {NULL},
};

static const struct technique_cell hdrp_pcss_cells[] = {
    {"grazing_receiver", {"normal_bias=0", "slope_bias=0"}},
    {"parallel_planes", {"blocker_samples=8,filter_samples=8", "softness_scale=2", "animate_noise=true"}},
    {"contact_hardening", {"min_filter_size=1"}},
    {NULL},
};

TECHNIQUE(hdrp_pcss, .needs = SM_DEPTH, .regression = hdrp_pcss_cells, .preset_of = "hdrp",
          .preset_source = HDRP_SOURCE,
          .summary = "Unity HDRP's High: PCSS on a Fibonacci spiral, softness fitted to the light's size");
