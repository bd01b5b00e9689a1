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
 * Not yet here: useContactHardeningShadow (PCSS). Set up as above it lights
 * every pixel on every scene here, with shadowbench's frustum and with
 * Babylon's own, and so does Babylon's own minimal scene on SwiftShader, so
 * it is not shipped as a cell until that is understood (docs/engines.md).
 *
 * Parameters shared by the modes:
 *   bias         ShadowGenerator.bias: added to the receiver's depth metric
 *                (Babylon's default 0.00005).
 *   normal_bias  ShadowGenerator.normalBias: the receiver moved along its
 *                normal, scaled by its slope to the light, world units.
 *   shadow_side  double: both faces drawn (backFaceCulling off), into the
 *                map and by the camera; engine: the file's one-sided
 *                materials culled as Babylon culls them.
 *   map_size     the generator's map size; 0: the run's --shadow-map-size
 *                (Babylon's own default is 512). */
#include "param_rows.h"

static const char *const babylon_sides[] = {"double", "engine", NULL};
static const char *const babylon_qualities[] = {"high", "medium", "low", NULL};  /* QUALITY_HIGH = 0, ... */

#define BABYLON_COMMON(settings)                                                                      \
    {"bias", "ShadowGenerator.bias: the receiver's depth offset, in the linear depth metric (0 = near, 1 = " \
     "far)", offsetof(settings, bias), PARAM_FLOAT, 0.00005, 0.0, 0.05, NULL,                            \
     TUNE(0.0, 0.00005, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05)},                                  \
    {"normal_bias", "ShadowGenerator.normalBias: the receiver moved along its normal, world units",      \
     offsetof(settings, normal_bias), PARAM_FLOAT, 0.0, 0.0, 1.0, NULL, TUNE(0.0, 0.005, 0.01, 0.02, 0.05)}, \
    {"shadow_side", "faces drawn: double (both, shadowbench's choice) or engine (the file's one-sided culling)", \
     offsetof(settings, shadow_side), PARAM_ENUM, 0, 0, 0, babylon_sides, NULL},                         \
    {"map_size", "the ShadowGenerator's map size, texels a side; 0: the run's --shadow-map-size",        \
     offsetof(settings, map_size), PARAM_INT, 0, 0, 8192, NULL, NULL}

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

ENGINE_TECHNIQUE(babylon_hard, babylon, "babylonjs", .regression = babylon_hard_cells,
                 .summary = "Babylon.js ShadowGenerator, no filter: one nearest-texel comparison");
ENGINE_TECHNIQUE(babylon_poisson, babylon, "babylonjs", .regression = babylon_poisson_cells,
                 .summary = "Babylon.js usePoissonSampling: 4 comparisons on a fixed Poisson pattern");
ENGINE_TECHNIQUE(babylon_pcf, babylon, "babylonjs", .regression = babylon_pcf_cells,
                 .summary = "Babylon.js usePercentageCloserFiltering: bilinear-compare kernels of 1, 4 or 9 taps");
