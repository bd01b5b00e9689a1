/* Filament's shadow filters as it ships them, re-implemented
 * (docs/presets.md): presets, shadowbench's own shaders following
 * google/filament 1.53.4 (the npm build the filament_pcf engine cell runs),
 * shaders/src/shadowing.fs and common_shadowing.glsl, with
 * filament/src/ShadowMap.cpp, ShadowMapManager.cpp, include/filament/
 * LightManager.h and Options.h for the defaults. Read at the commit the
 * 1.53.4 release was cut from; the shaders compiled into npm 1.53.4's
 * WebAssembly hold the same table, constants and tap counts. Each takes
 * the engine cell's name with _glsl (techniques/filament.c is the engine's
 * own: only its PCF can be asked for from a web page, so only
 * filament_pcf_glsl has an engine to agree with: tests/test_presets.c).
 *
 * Confirmed against that source (shaders/filament_filters.glsl, filament_*_glsl.glsl):
 *   filament_pcf_glsl   ShadowType::PCF, the default: ShadowSample_PCF_Low,
 *                       Castano 2013's 3 x 3 from 4 bilinear hardware
 *                       comparisons (per axis texel weights (1 - s, 2 - s,
 *                       1 + s, s) / 4), after the lookup is moved along the
 *                       geometric normal by normalBias texels at the
 *                       receiver times sin of the angle to the light's
 *                       direction as Filament passes it: for a spot, its
 *                       axis pointing away from the light, so surfaces
 *                       facing the light get the whole offset (a quirk of
 *                       Filament's, kept); the sun's half of it.
 *   filament_dpcf_glsl  ShadowType::DPCF: 12 taps of the Poisson disk (the
 *                       first 12 of its 64, in its order: all in the
 *                       upper half of the disk), turned by
 *                       interleaved gradient noise of the pixel (moved by
 *                       TAA's random number a frame: `animate_noise`), nearest
 *                       fetches against the receiver's plane (receiver-
 *                       plane depth bias); radius shadowBulbRadius in texels
 *                       at the receiver times penumbraScale; no blocker: lit;
 *                       else 1 - mix(hardened(p), p, ratio), p the blocked
 *                       share, ratio (d_r - d_b) / d_b times
 *                       penumbraRatioScale, clamped to [0, 1], hardened
 *                       4x^3 / 1 - 4(1-x)^3. No second pass.
 *   filament_pcss_glsl  ShadowType::PCSS: the same search with 16 taps, then
 *                       16 taps of the same turned disk at radius times the
 *                       unclamped ratio, each a manual bilinear 2 x 2 of
 *                       texels compared against the receiver's plane.
 * Defaults are Filament's: normalBias 1, penumbraScale 1,
 * penumbraRatioScale 1 (Filament clamps it to at least 1), TAA off.
 *
 * Approximated, and why:
 *   - the map is shadowbench's (fitted, D32F) at the run's size, not
 *     Filament's (the square around the cone with a 1-texel border, near
 *     plane 1 cm, DEPTH16): Filament's constantBias and polygon offset act
 *     on its map as it is drawn, so here the one constant_bias
 *     (shadowbench's linear units) stands for them.
 *   - shadowBulbRadius (default 2 cm, a bulb) is the scene's light: a disk
 *     light's radius, a rect light's equal-area disk's, the sun's
 *     tan(half angle) times the map's depth range; light_size_scale
 *     multiplies it.
 *   - PCSS's 2 x 2 is one gather here (desktop Filament's path; its WebGL
 *     build fetches the 4 texels one by one), counted as one fetch.
 *   - TAA's per-frame random number is the frame's R2 step here.
 *   - EVSM (ShadowType::VSM) is not built as a preset: shadowbench's evsm
 *     takes Filament's exponent (5.54, its fp16 choice, or 42) and bleed
 *     reduction (0.15) on its own fp32 product, whose minimum variance is
 *     in other units than Filament's (docs/presets.md).
 *
 * How they fail: pcf is a fixed 2-texel blur; dpcf's 12 lopsided taps and
 * its hardening make contact edges crisp but noisy and far ones
 * mis-shaped; pcss's filter has no width floor, so contact shadows are the
 * 2 x 2's alone, and its 16 taps are noisy on wide penumbrae. */
#include "param_rows.h"

#define FILAMENT_SOURCE "google/filament 1.53.4: shaders/src/shadowing.fs"

#define FILAMENT_SOFT_ROWS(settings)                                                                  \
    PARAM_ROW_LIGHT_SIZE_SCALE(settings),                                                             \
    {"penumbra_scale", "SoftShadowOptions::penumbraScale: the search radius's multiplier",           \
     offsetof(settings, penumbra_scale), PARAM_FLOAT, 1.0, 0.0, 10.0, NULL, NULL},                    \
    {"penumbra_ratio_scale", "SoftShadowOptions::penumbraRatioScale: the penumbra ratio's multiplier (Filament: "  \
     "at least 1)", offsetof(settings, penumbra_ratio_scale), PARAM_FLOAT, 1.0, 1.0, 100.0, NULL,      \
     TUNE(1.0, 2.0, 4.0)},                                                                             \
    PARAM_ROW_ANIMATE_NOISE(settings),                                                                \
    PARAM_ROW_CONSTANT_BIAS(settings)

struct filament_pcf_glsl_settings {
    float normal_bias, constant_bias;
};

static const struct technique_param filament_pcf_glsl_params[] = {
    {"normal_bias", "ShadowOptions::normalBias: the lookup moved along the normal, texels at the receiver",
     offsetof(struct filament_pcf_glsl_settings, normal_bias), PARAM_FLOAT, 1.0, 0.0, 3.0, NULL,
     TUNE(0.0, 0.5, 1.0, 2.0, 3.0)},
    PARAM_ROW_CONSTANT_BIAS(struct filament_pcf_glsl_settings),
    {NULL},
};

static const struct technique_cell filament_pcf_glsl_cells[] = {
    {"grazing_receiver", {"normal_bias=0", "constant_bias=0.005"}},
    {NULL},
};

TECHNIQUE(filament_pcf_glsl, .needs = SM_DEPTH, .regression = filament_pcf_glsl_cells, .preset_of = "filament",
          .preset_source = FILAMENT_SOURCE,
          .summary = "Filament's PCF: normal offset, Castano's 3 x 3 from 4 bilinear comparisons");

struct filament_dpcf_glsl_settings {
    float light_size_scale, penumbra_scale, penumbra_ratio_scale;
    int animate_noise;
    float constant_bias;
};

static const struct technique_param filament_dpcf_glsl_params[] = {
    FILAMENT_SOFT_ROWS(struct filament_dpcf_glsl_settings),
    {NULL},
};

static const struct technique_cell filament_dpcf_glsl_cells[] = {
    {"contact_hardening", {"light_size_scale=0.5", "penumbra_scale=2", "penumbra_ratio_scale=4"}},
    {"grazing_receiver", {"constant_bias=0.005"}},
    {"parallel_planes", {"animate_noise=true"}},
    {NULL},
};

TECHNIQUE(filament_dpcf_glsl, .needs = SM_DEPTH, .regression = filament_dpcf_glsl_cells, .preset_of = "filament",
          .preset_source = FILAMENT_SOURCE,
          .summary = "Filament's DPCF: 12 Poisson taps turned by IGN, the blocked share hardened near contact");

struct filament_pcss_glsl_settings {
    float light_size_scale, penumbra_scale, penumbra_ratio_scale;
    int animate_noise;
    float constant_bias;
};

static const struct technique_param filament_pcss_glsl_params[] = {
    FILAMENT_SOFT_ROWS(struct filament_pcss_glsl_settings),
    {NULL},
};

static const struct technique_cell filament_pcss_glsl_cells[] = {
    {"contact_hardening", {"light_size_scale=0.5", "penumbra_scale=2", "penumbra_ratio_scale=4"}},
    {"grazing_receiver", {"constant_bias=0.005"}},
    {"parallel_planes", {"animate_noise=true"}},
    {NULL},
};

TECHNIQUE(filament_pcss_glsl, .needs = SM_DEPTH, .regression = filament_pcss_glsl_cells, .preset_of = "filament",
          .preset_source = FILAMENT_SOURCE,
          .summary = "Filament's PCSS: 16 Poisson search taps, 16 bilinear 2 x 2 filter taps");
