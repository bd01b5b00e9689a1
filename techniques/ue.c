/* Unreal Engine 5's shadow-map ray tracing (SMRT), the filter of its
 * virtual shadow maps, re-implemented (docs/presets.md): a preset,
 * shadowbench's own shader. UE's source is licensed to Epic's account
 * holders, not public; what follows comes from two kinds of source, kept
 * apart here.
 *
 * Epic's documentation, "Virtual Shadow Maps in Unreal Engine"
 * (dev.epicgames.com, UE 5.6, section "Shadow Map Ray Tracing"), and its
 * API reference (UDirectionalLightComponent::LightSourceAngle) state:
 *   - rays from the receiver towards points on the light (a directional
 *     light's cone of Source Angle, 0.5357 degrees by default; a local
 *     light's Source Radius), each sampled against the shadow map at a
 *     number of points along it; the shadow the share of rays blocked;
 *   - the controls r.Shadow.Virtual.SMRT.RayCount* and SamplesPerRay*
 *     (the page's figures: 7 rays, 8 samples; it says 4 to 8 samples work
 *     well and that Epic scalability uses 8 rays);
 *   - behind the first occluder the map's depth is extrapolated from the
 *     depths seen before it (ExtrapolateMaxSlope*), which fills most leaks
 *     and shrinks penumbrae on surfaces parallel to the light;
 *   - penumbrae are limited so rays stay near their origin:
 *     MaxRayAngleFromLight (local lights) and RayLengthScaleDirectional
 *     (rays as long as a multiple of the distance from the camera).
 *
 * Not in that documentation, read (paraphrased, not copied) from UE 5.7's
 * shaders as unofficial public copies of its source show them, and from
 * a public console-variable reference for the defaults: the values 0.03
 * radians, 1.5, 5 (centimetres) and 0.05; the samples' spacing (t = ((m -
 * 1 - i + noise) / m)^2, marched from the far end, and one at the start);
 * the hit test (the surface in front of the ray by less than a step); the
 * extrapolation (the last trusted surface extended along its depth slope,
 * clamped); the local ray's end (75 % of the way, shortened as its angle
 * from the light's centre grows). Those parts are not confirmed by Epic's
 * public documentation: they are the engine's as far as such a copy
 * shows, and this preset is that reading (docs/presets.md).
 *
 * Approximated, and why:
 *   - a virtual shadow map's page tables and clipmap levels are replaced
 *     by one map of the run's size (its texel density where the scenes
 *     need it is what a 16k virtual map would give only near the camera);
 *     off the map a sample reads its edge texels, as every technique's
 *     does (the edge policy), where UE drops an unmapped page's;
 *   - the defaults are the console variables' (7 rays, 8 samples);
 *     UE 5.7's Epic scalability level sets 8 rays and 4 samples
 *     (`--set ue_smrt.ray_count=8,samples_per_ray=4`);
 *   - the noise: shadowbench's blue-noise tile, a new offset per ray by
 *     the R2 sequence, one step offset per pixel (UE 5.7 reads a
 *     spatiotemporal blue-noise stack so; earlier versions used
 *     interleaved gradient noise and Sobol points);
 *   - the light: a local light's Source Radius is sm_light_radius (the
 *     disk light's radius, the rect light's equal-area disk's); the sun's
 *     its angular size; UE's units are centimetres, the scenes' metres;
 *   - bias: a normal offset of normal_bias texels and shadowbench's
 *     constant bias towards the light, for UE's screen-space ray, texel
 *     dither and normal bias; no adaptive ray count (a wave vote);
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
     "the light: the sun's 5 cm, 0.05 scene units, a unit of t; a local light's 0.05 of the ray's depth change)",
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
          .preset_source = "Epic's documentation, Virtual Shadow Maps in Unreal Engine (5.6); UE 5.7's shaders as "
                           "unofficial public copies show them",
          .summary = "Unreal Engine 5's shadow-map ray tracing: 7 rays to the light, 8 map samples each");
