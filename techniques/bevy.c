/* Bevy's shadow filters as it ships them, re-implemented (docs/presets.md):
 * presets, shadowbench's own shaders following bevyengine/bevy 0.19.1,
 * crates/bevy_pbr/src/render/shadow_sampling.wgsl, shadows.wgsl and
 * utils.wgsl (read again at 0.20.0-dev, shadow_sampling.wesl: the same
 * arithmetic), and crates/bevy_light for the defaults.
 *
 * Confirmed against that source (shaders/bevy_filters.glsl, bevy_*.glsl):
 *   bevy_gaussian  ShadowFilteringMethod::Gaussian, the default: Castano
 *                  2013's 5 x 5 tent from 9 bilinear hardware comparisons
 *                  (sample_shadow_map_castano_thirteen), for spot and
 *                  directional lights.
 *   bevy_temporal  ShadowFilteringMethod::Temporal: Jimenez 2014's 8-point
 *                  spiral (Bevy's table), turned per pixel by interleaved
 *                  gradient noise of the pixel and the frame (frame modulo
 *                  64, 5.588238 pixels a frame), 8 bilinear comparisons at
 *                  f / texel_size texels (f: Bevy's linear map of
 *                  texel_size; a spot's texel_size is the constant
 *                  0.0134277345, so 1.86 texels, whatever the map).
 *   bevy_pcss      a spot light with soft_shadows_enabled (its `radius` the
 *                  light's size) or a directional light's soft_shadow_size
 *                  (feature experimental_pbr_pcss): 8 fixed points (the D3D
 *                  8x MSAA pattern / 8), unturned, at light_size /
 *                  texel_size texels, reading the depth through a linear
 *                  sampler; the blur max((z_b - z) L / z, 0.5) in Bevy's
 *                  reversed depths (0 for z_b when no blocker: the floor
 *                  holds, no early out); then the spiral at that blur,
 *                  turned by the noise of frame 1 (Bevy moves it with
 *                  the frame only when the camera's method is Temporal,
 *                  which is bevy_temporal's).
 * Each tap is counted as the one fetch Bevy makes (a bilinear comparison, or
 * the search's filtered read: here one gather, weighted as the sampler
 * would).
 *
 * Approximated, and why:
 *   - the map is shadowbench's fitted one at the run's size (Bevy's spot map
 *     is the square around its cone at 2048 by default); texel counts that
 *     Bevy fixes (1.86 texels, 74.5 texels per unit of radius) stay fixed,
 *     so they cover what they cover on that map.
 *   - the light as Bevy would be given it: a spot light of `radius` the
 *     disk light's radius, or a rect light's equal-area disk's; the sun as
 *     soft_shadow_size = tan(half angle) times the map's depth range (the
 *     search reaches the true search region at the far plane). Bevy's
 *     directional blur divides orthographic depths, as Bevy's does: here
 *     the fitted map's reversed depths, so its scale follows the fit.
 *   - bias: Bevy's own, as its shader applies them at its defaults: the
 *     lookup moved 0.02 world units towards the light and 1.8 sqrt(2)
 *     texels along the normal (the scenes' units taken as Bevy's metres).
 *   - point lights' cube-map variants are not built (no scene has a point
 *     light).
 *
 * How they fail: gaussian is a fixed 5 x 5 blur (no contact hardening,
 * 2.5 texels either side of every edge); temporal leaves noise a frame
 * that only TAA averages; pcss's 8 unturned search points miss small
 * blockers between them, its 8-tap filter is noisy, and the 0.5 floor blurs
 * every hard edge at least a texel. */
#include "param_rows.h"

#define BEVY_NORMAL_BIAS_ROW(settings)                                                                  \
    {"normal_bias", "shadow_normal_bias: the lookup moved along the normal by this x sqrt(2) texels "     \
     "(Bevy's default 1.8)", offsetof(settings, normal_bias), PARAM_FLOAT, 1.8, 0.0, 10.0, NULL,           \
     TUNE(0.0, 0.9, 1.8, 3.6)}

#define BEVY_DEPTH_BIAS_ROW(settings)                                                                   \
    {"depth_bias", "shadow_depth_bias: the lookup moved towards the light, world units (Bevy's default "    \
     "0.02)", offsetof(settings, depth_bias), PARAM_FLOAT, 0.02, 0.0, 1.0, NULL, TUNE(0.0, 0.01, 0.02, 0.05, 0.1)}

#define BEVY_SOURCE "bevyengine/bevy 0.19.1: crates/bevy_pbr/src/render/shadow_sampling.wgsl"

struct bevy_gaussian_settings {
    float depth_bias, normal_bias;
};

static const struct technique_param bevy_gaussian_params[] = {
    BEVY_DEPTH_BIAS_ROW(struct bevy_gaussian_settings),
    BEVY_NORMAL_BIAS_ROW(struct bevy_gaussian_settings),
    {NULL},
};

static const struct technique_cell bevy_gaussian_cells[] = {
    {"grazing_receiver", {"depth_bias=0.1", "normal_bias=0"}},
    {NULL},
};

TECHNIQUE(bevy_gaussian, .needs = SM_DEPTH, .regression = bevy_gaussian_cells, .preset_of = "bevy",
          .preset_source = BEVY_SOURCE,
          .summary = "Bevy's default: Castano's 5 x 5 tent from 9 bilinear comparisons");

struct bevy_temporal_settings {
    float depth_bias, normal_bias;
};

static const struct technique_param bevy_temporal_params[] = {
    BEVY_DEPTH_BIAS_ROW(struct bevy_temporal_settings),
    BEVY_NORMAL_BIAS_ROW(struct bevy_temporal_settings),
    {NULL},
};

static const struct technique_cell bevy_temporal_cells[] = {
    {"grazing_receiver", {"depth_bias=0.1", "normal_bias=0"}},
    {NULL},
};

TECHNIQUE(bevy_temporal, .needs = SM_DEPTH, .regression = bevy_temporal_cells, .preset_of = "bevy",
          .preset_source = BEVY_SOURCE,
          .summary = "Bevy's Temporal: Jimenez's 8-tap spiral turned by IGN of pixel and frame");

struct bevy_pcss_settings {
    float light_size_scale;
    float depth_bias, normal_bias;
};

static const struct technique_param bevy_pcss_params[] = {
    PARAM_ROW_LIGHT_SIZE_SCALE(struct bevy_pcss_settings),
    BEVY_DEPTH_BIAS_ROW(struct bevy_pcss_settings),
    BEVY_NORMAL_BIAS_ROW(struct bevy_pcss_settings),
    {NULL},
};

static const struct technique_cell bevy_pcss_cells[] = {
    {"large_light", {"light_size_scale=3"}},
    {"grazing_receiver", {"depth_bias=0.1", "normal_bias=0"}},
    {NULL},
};

TECHNIQUE(bevy_pcss, .needs = SM_DEPTH, .regression = bevy_pcss_cells, .preset_of = "bevy",
          .preset_source = BEVY_SOURCE,
          .summary = "Bevy's PCSS: 8 fixed search points, blur at least 0.5, the 8-tap spiral");
