/* Unreal Engine 5's shadow-map ray tracing (SMRT), the filter of its
 * virtual shadow maps, re-implemented (docs/presets.md): a preset,
 * shadowbench's own shader following Epic's documentation, "Virtual
 * Shadow Maps in Unreal Engine" (dev.epicgames.com, UE 5.6; section
 * "Shadow Map Ray Tracing"), its console variables' defaults and
 * UDirectionalLightComponent::LightSourceAngle's. UE's source is not
 * public (Epic's licence), so nothing else is followed.
 *
 * Confirmed by that documentation (shaders/ue_smrt.glsl):
 *   - rays from the receiver towards points on the light (a directional
 *     light's cone of Source Angle, 0.5357 degrees by default; a local
 *     light's Source Radius), each sampled against the shadow map at a
 *     number of points along it; the shadow the share of rays blocked;
 *   - r.Shadow.Virtual.SMRT.RayCountDirectional / RayCountLocal 7 and
 *     SamplesPerRayDirectional / SamplesPerRayLocal 8 (the defaults; the
 *     page says 4 to 8 samples work well, and Epic scalability 8 rays);
 *   - behind the first occluder the map's depth is extrapolated from the
 *     depths seen before it (ExtrapolateMaxSlopeDirectional 5,
 *     ExtrapolateMaxSlopeLocal 0.05), which fills most leaks and shrinks
 *     penumbrae on surfaces parallel to the light;
 *   - penumbrae are limited so rays stay near their origin:
 *     MaxRayAngleFromLight 0.03 radians (local), RayLengthScaleDirectional
 *     1.5 times the distance from the camera (directional).
 *
 * Approximated, and why:
 *   - the documentation gives no formulas: the samples' spacing (denser
 *     towards the receiver, t = ((m - 1 - i + noise) / m)^2, marched from
 *     the far end, and one at the start), the hit test (the surface in
 *     front of the ray by less than a step), the extrapolation (the last
 *     trusted surface extended along its clamped depth slope) and the
 *     local ray's end (75 % of the way, shortened by the angle limit) are
 *     shadowbench's reading of that description, not Epic's code;
 *   - a virtual shadow map's page tables and clipmap levels are replaced
 *     by one map of the run's size (its texel density where the scenes
 *     need it is what a 16k virtual map would give only near the camera);
 *     off the map a sample is dropped, as an unmapped page's is;
 *   - the noise: shadowbench's blue-noise tile, a new offset per ray by the
 *     R2 sequence (UE 5.7 reads a spatiotemporal blue-noise stack the same
 *     way; earlier versions used interleaved gradient noise and Sobol
 *     points): the light's points and the samples' offset;
 *   - the light: a local light's Source Radius is the disk light's radius
 *     or the rect light's equal-area disk's; the sun's its angular size;
 *   - bias: a normal offset of normal_bias texels and shadowbench's
 *     constant bias towards the light, for UE's screen-space ray and
 *     normal bias; no adaptive ray count (a wave vote);
 *   - UE's classic shadow-map PCF is not built: its kernel is not stated in
 *     Epic's public documentation, so it is not shipped under UE's name.
 *
 * How it fails: 7 rays leave visible noise in every penumbra (UE relies
 * on its temporal filter); the extrapolation narrows penumbrae on
 * receivers parallel to the light and can leak behind a second occluder;
 * the angle and length limits cap the widest penumbra. */
#include "param_rows.h"

struct ue_smrt_settings {
    int ray_count, samples_per_ray;
    float extrapolate_max_slope, max_ray_angle, ray_length_scale, light_size_scale;
    int animate_noise;
    float normal_bias, constant_bias;
};

static const struct technique_param ue_smrt_params[] = {
    {"ray_count", "r.Shadow.Virtual.SMRT.RayCount*: rays per pixel",
     offsetof(struct ue_smrt_settings, ray_count), PARAM_INT, 7, 1, 32, NULL, TUNE(4, 7, 8, 16)},
    {"samples_per_ray", "r.Shadow.Virtual.SMRT.SamplesPerRay*: map samples per ray (and one at its start)",
     offsetof(struct ue_smrt_settings, samples_per_ray), PARAM_INT, 8, 1, 32, NULL, TUNE(2, 4, 8, 16)},
    {"extrapolate_max_slope", "ExtrapolateMaxSlope*: the extrapolated depth's largest slope (-1: UE's default for "
     "the light, 5 world units a ray for the sun, 0.05 of the ray's depth change for a local light)",
     offsetof(struct ue_smrt_settings, extrapolate_max_slope), PARAM_FLOAT, -1.0, -1.0, 100.0, NULL, NULL},
    {"max_ray_angle", "MaxRayAngleFromLight: a local light's rays' largest angle from the light, radians",
     offsetof(struct ue_smrt_settings, max_ray_angle), PARAM_FLOAT, 0.03, 0.001, 1.0, NULL, TUNE(0.03, 0.1, 0.3)},
    {"ray_length_scale", "RayLengthScaleDirectional: the sun's rays' length over the distance to the camera",
     offsetof(struct ue_smrt_settings, ray_length_scale), PARAM_FLOAT, 1.5, 0.01, 100.0, NULL, NULL},
    PARAM_ROW_LIGHT_SIZE_SCALE(struct ue_smrt_settings),
    PARAM_ROW_ANIMATE_NOISE(struct ue_smrt_settings),
    {"normal_bias", "the start moved along the normal, texels at the receiver",
     offsetof(struct ue_smrt_settings, normal_bias), PARAM_FLOAT, 1.0, 0.0, 10.0, NULL, TUNE(0.0, 0.5, 1.0, 2.0)},
    PARAM_ROW_CONSTANT_BIAS(struct ue_smrt_settings),
    {NULL},
};

static const struct technique_cell ue_smrt_cells[] = {
    {"parallel_planes", {"ray_count=16", "samples_per_ray=4", "max_ray_angle=0.3", "animate_noise=true"}},
    {"thin_features", {"extrapolate_max_slope=0"}},
    {"sun_parallel_planes", {"ray_length_scale=0.1"}},
    {"large_light", {"light_size_scale=0.5"}},
    {"grazing_receiver", {"normal_bias=0", "constant_bias=0.005"}},
    {NULL},
};

TECHNIQUE(ue_smrt, .needs = SM_DEPTH, .regression = ue_smrt_cells, .preset_of = "ue",
          .preset_source = "Epic's documentation, Virtual Shadow Maps in Unreal Engine (5.6): Shadow Map Ray Tracing",
          .summary = "Unreal Engine 5's shadow-map ray tracing: 7 rays to the light, 8 map samples each");
