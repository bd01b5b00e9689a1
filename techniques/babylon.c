/* Babylon.js's ShadowGenerator as it ships (npm babylonjs and
 * babylonjs-loaders 9.28.0, the newest matched pair), rendered by Babylon
 * itself in headless Chromium (engines/babylon/adapter.js;
 * docs/engines.md). Each mode is one of the generator's filters; the
 * parameters are its settings under their own names, at Babylon's
 * defaults.
 *
 * What Babylon does (Shaders/ShadersInclude/shadowsFragmentFunctions.fx,
 * 9.28.0): it stores a linear depth metric, (z - shadowMinZ) /
 * (shadowMaxZ - shadowMinZ), and
 *   babylon_hard     filter none: one comparison, nearest texel;
 *   babylon_poisson  usePoissonSampling: 4 comparisons on a fixed Poisson
 *                    pattern within about a texel;
 *   babylon_pcf      usePercentageCloserFiltering: hardware-compare
 *                    (bilinear) taps on Castaño's kernels: 1 tap (low), 4 on
 *                    3 x 3 (medium), 9 on 5 x 5 (high, the default);
 *   babylon_pcss     useContactHardeningShadow (computeShadowWithPCSS): a
 *                    blocker search of 16 taps (32 at high) on a Poisson disk
 *                    of radius contactHardeningLightSizeUVRatio in map UV,
 *                    then 16, 32 or 64 comparison taps (low, medium, high) on
 *                    a rotated Poisson disk of radius ratio * (the depth
 *                    metric's gap between receiver and mean blocker + 10
 *                    texels); the shadow is then faded towards lit by that
 *                    gap (mix(shadow, 1, gap)), so a tight depth range lights
 *                    a shadow whose blocker is far above its receiver:
 *                    parallel_planes, fitted, is lit all over.
 *
 * babylon_pcss's parameters besides the shared ones:
 *   light_size_uv_ratio  contactHardeningLightSizeUVRatio; 0 (the default):
 *                    derived from the scene's light so that the filter's
 *                    radius is the true penumbra's half-width where
 *                    z_blocker * z_receiver = near * far (for the sun at
 *                    every depth) (engines/babylon/adapter.js,
 *                    derivedRatio): the radius only, Babylon's 10-texel
 *                    widening and its fade on top. Its own default is 0.1.
 *   shadow_max_z_scale   light.shadowMaxZ = shadowMinZ + this * (the fitted
 *                    depth range): the depth metric's range, and the map's
 *                    far plane. A wider range shrinks the fade, but the
 *                    derived ratio, which is also the blocker search's
 *                    radius, grows with it.
 *
 * Parameters shared by the modes:
 *   bias         ShadowGenerator.bias (Babylon's default 0.00005): added to
 *                the caster's depth metric in the map (babylon_hard,
 *                babylon_poisson, which compare the metric); the modes that
 *                compare the map's depth texture (babylon_pcf, babylon_pcss)
 *                add it to the caster's clip-space z instead (times w:
 *                post-projective depth, in [-1, 1] over the depth range;
 *                shadowMapVertexMetric), so one value is not one offset
 *                across the modes.
 *   normal_bias  ShadowGenerator.normalBias: the receiver moved along its
 *                normal, scaled by its slope to the light, world units.
 *   shadow_side  double: both faces drawn (backFaceCulling off), into the
 *                map and by the camera; engine: the file's one-sided
 *                materials culled as Babylon culls them.
 *   map_size     the generator's map size; 0: the run's --shadow-map-size
 *                (Babylon's own default is 512). */
#include "param_rows.h"

static const char *const babylon_qualities[] = {"high", "medium", "low", NULL};  /* QUALITY_HIGH = 0, ... */

#define BABYLON_COMMON(settings)                                                                      \
    {"bias", "ShadowGenerator.bias: the casters' depth offset: in the linear depth metric (0 = near, 1 = " \
     "far) for hard and poisson, in clip-space z for pcf and pcss", offsetof(settings, bias), PARAM_FLOAT,  \
     0.00005, 0.0, 0.05, NULL, TUNE(0.0, 0.00005, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05)},             \
    {"normal_bias", "ShadowGenerator.normalBias: the receiver moved along its normal, world units",      \
     offsetof(settings, normal_bias), PARAM_FLOAT, 0.0, 0.0, 1.0, NULL, TUNE(0.0, 0.005, 0.01, 0.02, 0.05)}, \
    PARAM_ROW_ENGINE_SIDE(settings, "the file's one-sided culling, into the map and by the camera"),     \
    PARAM_ROW_ENGINE_MAP_SIZE(settings, "the ShadowGenerator's map size", 8192)

#define BABYLON_SETTINGS \
    float bias, normal_bias; \
    int shadow_side, map_size

#define BABYLON_QUALITY(settings)                                                                  \
    {"filtering_quality", "ShadowGenerator.filteringQuality: high (the default), medium or low",     \
     offsetof(settings, filtering_quality), PARAM_ENUM, 0, 0, 0, babylon_qualities, TUNE_CHOICES}

struct babylon_hard_settings {
    BABYLON_SETTINGS;
};

static const struct technique_param babylon_hard_params[] = {
    BABYLON_COMMON(struct babylon_hard_settings),
    {NULL},
};

struct babylon_poisson_settings {
    BABYLON_SETTINGS;
};

static const struct technique_param babylon_poisson_params[] = {
    BABYLON_COMMON(struct babylon_poisson_settings),
    {NULL},
};

struct babylon_pcf_settings {
    BABYLON_SETTINGS;
    int filtering_quality;
};

static const struct technique_param babylon_pcf_params[] = {
    BABYLON_COMMON(struct babylon_pcf_settings),
    BABYLON_QUALITY(struct babylon_pcf_settings),
    {NULL},
};

static const struct technique_cell babylon_hard_cells[] = {
    {"grazing_receiver", {"bias=0.0005", "normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {NULL},
};

static const struct technique_cell babylon_poisson_cells[] = {
    {"grazing_receiver", {"bias=0.0005", "normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {NULL},
};

static const struct technique_cell babylon_pcf_cells[] = {
    {"grazing_receiver", {"bias=0.0005", "normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {"contact_hardening", {"filtering_quality=low", "filtering_quality=medium"}},
    {NULL},
};

struct babylon_pcss_settings {
    BABYLON_SETTINGS;
    int filtering_quality;
    float light_size_uv_ratio;  /* map UV per unit of depth metric; 0: derived */
    float shadow_max_z_scale;   /* >= 1 */
};

static const struct technique_param babylon_pcss_params[] = {
    BABYLON_COMMON(struct babylon_pcss_settings),
    BABYLON_QUALITY(struct babylon_pcss_settings),
    {"light_size_uv_ratio", "ShadowGenerator.contactHardeningLightSizeUVRatio: the blocker search's radius and "
     "the filter's per unit of depth-metric difference, map UV; 0: derived from the scene's light (Babylon's own "
     "default is 0.1)", offsetof(struct babylon_pcss_settings, light_size_uv_ratio), PARAM_FLOAT, 0.0, 0.0, 1.0,
     NULL, TUNE(0.0, 0.02, 0.05, 0.1, 0.2)},
    {"shadow_max_z_scale", "light.shadowMaxZ as a multiple of the fitted depth range from shadowMinZ (1: the "
     "fitted far plane): Babylon's PCSS fades a shadow towards lit by the depth metric's gap, which a wider range "
     "shrinks", offsetof(struct babylon_pcss_settings, shadow_max_z_scale), PARAM_FLOAT, 1.0, 1.0, 1000.0, NULL,
     TUNE(1.0, 2.0, 5.0, 20.0)},
    {NULL},
};

static const struct technique_cell babylon_pcss_cells[] = {
    {"grazing_receiver", {"bias=0.0005", "normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {"parallel_planes", {"shadow_max_z_scale=20", "shadow_max_z_scale=20,light_size_uv_ratio=0.05",
                         "shadow_max_z_scale=20,filtering_quality=low"}},
    {NULL},
};

ENGINE_TECHNIQUE(babylon_hard, babylon, "babylonjs", .regression = babylon_hard_cells,
                 .summary = "Babylon.js ShadowGenerator, no filter: one nearest-texel comparison");
ENGINE_TECHNIQUE(babylon_poisson, babylon, "babylonjs", .regression = babylon_poisson_cells,
                 .summary = "Babylon.js usePoissonSampling: 4 comparisons on a fixed Poisson pattern");
ENGINE_TECHNIQUE(babylon_pcf, babylon, "babylonjs", .regression = babylon_pcf_cells,
                 .summary = "Babylon.js usePercentageCloserFiltering: bilinear-compare kernels of 1, 4 or 9 taps");
ENGINE_TECHNIQUE(babylon_pcss, babylon, "babylonjs", .regression = babylon_pcss_cells,
                 .summary = "Babylon.js useContactHardeningShadow: PCSS, blocker search then a Poisson filter");
