/* Unity HDRP's shadow filters as it ships them, re-implemented
 * (docs/presets.md): a preset, shadowbench's own shader following
 * Unity-Technologies/Graphics, HDRP 17.2 (Unity 6000.2):
 * com.unity.render-pipelines.high-definition/Runtime/Lighting/Shadow/
 * HDShadowAlgorithms.hlsl (which filter each quality level takes),
 * com.unity.render-pipelines.core/ShaderLibrary/Shadow/
 * ShadowSamplingTent.hlsl (the tents), HDShadowSampling.hlsl (the taps)
 * and HDShadowManager.cs (the levels and their defaults).
 *
 * Confirmed against that source (shaders/hdrp_pcf.glsl):
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
 *
 * Approximated, and why:
 *   - the weights are the tent integral in full precision; HDRP's code
 *     normalises by 0.44444 and 0.081632 (1/2.25, 1/12.25 truncated), so
 *     its weights sum to 0.99999 and 0.999992: a difference below 1e-5.
 *   - the map is shadowbench's at the run's size (HDRP's atlas tile, 4096
 *     atlas by default); bias: shadowbench's constant and slope-scaled
 *     depth bias instead of HDRP's normal bias 0.75 and slope bias 0.5 in
 *     its own units, and its 1/65536 on every lookup (docs/presets.md).
 *   - High (PCSS: a 64-entry Fibonacci spiral, 24 blocker and 16 filter
 *     taps, Min Filter Size) is not built yet: hdrp_pcss (docs/presets.md
 *     says what remains).
 *
 * How it fails: a fixed tent, 1.5 to 3.5 texels either side of every edge:
 * no contact hardening, and on the sun a blur that grows with the map's
 * texel. */
#include "param_rows.h"

static const char *const hdrp_quality_names[] = {"low", "medium", NULL};

struct hdrp_pcf_settings {
    int quality;
    float constant_bias, slope_bias;
};

static const struct technique_param hdrp_pcf_params[] = {
    {"quality", "shadow filtering quality: low (3 x 3 tent for a spot, 5 x 5 for the sun), medium (the "
     "default: 5 x 5, 7 x 7)", offsetof(struct hdrp_pcf_settings, quality), PARAM_ENUM, 1, 0, 0,
     hdrp_quality_names, TUNE_CHOICES},
    PARAM_ROW_CONSTANT_BIAS(struct hdrp_pcf_settings),
    PARAM_ROW_SLOPE_BIAS(struct hdrp_pcf_settings, ""),
    {NULL},
};

static const struct technique_preset hdrp_levels[] = {
    {"low", "quality=low", "Low: the 3 x 3 tent (the sun's 5 x 5), 4 (9) fetches"},
    {NULL},
};

static const struct technique_cell hdrp_pcf_cells[] = {
    {"grazing_receiver", {"constant_bias=0.005", "slope_bias=0"}},
    {"parallel_planes", {"quality=low"}},
    {NULL},
};

TECHNIQUE(hdrp_pcf, .needs = SM_DEPTH, .regression = hdrp_pcf_cells, .presets = hdrp_levels, .preset_of = "hdrp",
          .preset_source = "Unity-Technologies/Graphics HDRP 17.2: ShaderLibrary/Shadow/ShadowSamplingTent.hlsl",
          .summary = "Unity HDRP's tent PCF: 3 x 3 to 7 x 7 tents from 4 to 16 bilinear comparisons");
