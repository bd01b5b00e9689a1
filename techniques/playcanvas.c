/* PlayCanvas's shadows as they ship (npm playcanvas 2.23.3), rendered by
 * PlayCanvas itself in headless Chromium (engines/playcanvas/adapter.js;
 * docs/engines.md). Each mode is a value of light.shadowType; the
 * parameters are the LightComponent's shadow settings, under their own
 * names, at PlayCanvas's defaults. Clustered lighting is off (the forward
 * path: each light its own map, type and resolution).
 *
 * What PlayCanvas does (2.23.3: src/scene/shader-lib/glsl/chunks/lit/frag/
 * lighting/shadowPCF1.js, shadowPCF3.js, shadowPCF5.js, shadowEVSM.js,
 * shadowPCSS.js, shadowSoft.js, lightFunctionShadow.js; the biases in
 * src/scene/light.js; the maps in src/scene/renderer/shadow-map.js and
 * shadow-renderer*.js; PCSS's uniforms in
 * src/scene/lighting/light-slot-uniforms.js):
 *   playcanvas_pcf1  SHADOW_PCF1_32F: one hardware-compare tap, and the map
 *                    is sampled with linear filtering, so it is a bilinear
 *                    2 x 2 compare, not a nearest texel.
 *   playcanvas_pcf3  SHADOW_PCF3_32F (PlayCanvas's default type): 4
 *                    bilinear-compare taps weighted as a 3 x 3 tent
 *                    (Castaño's fast PCF).
 *   playcanvas_pcf5  SHADOW_PCF5_32F: 9 bilinear-compare taps, a 5 x 5 tent.
 *   playcanvas_vsm   SHADOW_VSM_32F: exponential variance shadow maps (EVSM,
 *                    the positive moments of exp(c (2d - 1)), c = 15; 16F: c
 *                    = 5.54), blurred by a separable box or Gaussian of
 *                    vsmBlurSize taps, Chebyshev's bound with a fixed bleed
 *                    reduction of 0.1. A spot light stores its distance over
 *                    its range, not the depth buffer's.
 *   playcanvas_pcss  SHADOW_PCSS_32F: a blocker search and a filter over a
 *                    disk. For a spot: 16 taps on a Vogel disk turned by a
 *                    per-pixel hash, the filter's radius (d_receiver -
 *                    d_blocker) / 3 times the search radius, penumbraSize /
 *                    mapSize / tan(half fov) in map uv (no division by the
 *                    blocker's depth). For the sun: shadowBlockerSamples and
 *                    shadowSamples taps, a filter radius of penumbraSize
 *                    times (1 - (1 - t)^penumbraFalloff) times the depth
 *                    range, t the blocker-receiver gap over that range. No
 *                    depth bias either way.
 * The 16-bit variants (SHADOW_PCF*_16F: a 16-bit depth map; SHADOW_VSM_16F:
 * half-float moments) are the `format` parameter of their modes, not modes
 * of their own: they differ from the 32-bit ones in precision, not in
 * filter.
 *
 * The PCSS size is derived from the scene's light (light_size_scale = 1):
 * for the sun, penumbraSize = tan(half-angle): at penumbraFalloff 1 the
 * filter's extent is the sun's cone (a disk of that radius over a depth gap
 * d), its taps' profile PlayCanvas's own; for an area light (the disk's
 * radius a, a rect's mean half-side), penumbraSize = 3 mapSize a / (2 near
 * far), the light's extent for a blocker at the fitted near plane over a
 * receiver at its far one: PlayCanvas's spot filter grows with the
 * depth gap alone, the true penumbra with gap / (d_blocker d_receiver)
 * (docs/engines.md has the derivation).
 *
 * Parameters:
 *   bias              LightComponent.shadowBias, in [0, 1] (PlayCanvas's
 *                     default 0.05): the light's shadowBias is -0.01 times
 *                     it, which the caster pass applies as a polygon offset
 *                     of 10 times it, both its constant and its slope
 *                     factor. VSM: the sun's only (a spot's VSM map holds
 *                     distances over the range, which the offset does not
 *                     move); PCSS has none (no bias at all).
 *   normal_bias       normalOffsetBias, world units along the receiver's
 *                     normal before the lookup (default 0; PCF and PCSS
 *                     only: PlayCanvas ignores it for VSM).
 *   shadow_side       double: both faces drawn into the map (cull none),
 *                     shadowbench's choice; engine: the file's materials'
 *                     culling, which PlayCanvas's caster pass keeps (a
 *                     one-sided material's back faces are not drawn).
 *   map_size          shadowResolution, texels a side; 0: the run's
 *                     --shadow-map-size (PlayCanvas's own default is 1024).
 *   format            32f (the default type) or 16f: the map's precision.
 *   vsm_blur_size     vsmBlurSize: taps of each blur pass, odd, 1 to 25
 *                     (default 11; 1 is no blur).
 *   vsm_blur_mode     vsmBlurMode: gaussian (default) or box.
 *   vsm_bias          vsmBias (default 0.0025): the variance floor's scale,
 *                     which PlayCanvas divides by the light's range (the
 *                     spot's) or depth range (the sun's) over 7.
 *   light_size_scale  multiplies the derived penumbraSize (1: the true light).
 *   penumbra_falloff  penumbraFalloff (default 1): the sun's penumbra shape;
 *                     a spot's PCSS ignores it.
 *   shadow_samples, shadow_blocker_samples
 *                     shadowSamples, shadowBlockerSamples (default 16 each):
 *                     the sun's filter and blocker-search taps (0 blocker
 *                     samples: a fixed filter of penumbraSize); a spot's
 *                     PCSS takes 16 of each, fixed. */
#include "param_rows.h"

static const char *const playcanvas_formats[] = {"32f", "16f", NULL};
static const char *const playcanvas_blur_modes[] = {"gaussian", "box", NULL};

/* note: "" or where it does not act. */
#define PLAYCANVAS_BIAS(settings, note)                                                                \
    {"bias", "LightComponent.shadowBias, [0, 1]: a polygon offset of 10 times it in the caster pass" note, \
     offsetof(settings, bias), PARAM_FLOAT, 0.05, 0.0, 1.0, NULL, TUNE(0.0, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0)}

#define PLAYCANVAS_NORMAL_BIAS(settings)                                                               \
    {"normal_bias", "normalOffsetBias: the receiver moved along its normal, world units",                \
     offsetof(settings, normal_bias), PARAM_FLOAT, 0.0, 0.0, 1.0, NULL, TUNE(0.0, 0.005, 0.01, 0.02, 0.05)}

#define PLAYCANVAS_MAP(settings)                                                                       \
    PARAM_ROW_ENGINE_SIDE(settings, "the file's culling, which PlayCanvas keeps"),                       \
    PARAM_ROW_ENGINE_MAP_SIZE(settings, "shadowResolution", 8192)

#define PLAYCANVAS_FORMAT(settings, what)                                                              \
    {"format", "the shadow type's precision: 32f (PlayCanvas's default) or 16f, " what,                  \
     offsetof(settings, format), PARAM_ENUM, 0, 0, 0, playcanvas_formats, TUNE_CHOICES}

#define PLAYCANVAS_PCF_SETTINGS \
    float bias, normal_bias; \
    int shadow_side, map_size, format

#define PLAYCANVAS_PCF_PARAMS(settings)                                          \
    PLAYCANVAS_BIAS(settings, ""), PLAYCANVAS_NORMAL_BIAS(settings), PLAYCANVAS_MAP(settings), \
    PLAYCANVAS_FORMAT(settings, "the depth map's bits"), {NULL}

struct playcanvas_pcf1_settings {
    PLAYCANVAS_PCF_SETTINGS;
};
struct playcanvas_pcf3_settings {
    PLAYCANVAS_PCF_SETTINGS;
};
struct playcanvas_pcf5_settings {
    PLAYCANVAS_PCF_SETTINGS;
};
static const struct technique_param playcanvas_pcf1_params[] = {PLAYCANVAS_PCF_PARAMS(struct playcanvas_pcf1_settings)};
static const struct technique_param playcanvas_pcf3_params[] = {PLAYCANVAS_PCF_PARAMS(struct playcanvas_pcf3_settings)};
static const struct technique_param playcanvas_pcf5_params[] = {PLAYCANVAS_PCF_PARAMS(struct playcanvas_pcf5_settings)};

struct playcanvas_vsm_settings {
    float bias;
    int shadow_side, map_size, format;
    int vsm_blur_size;  /* taps, odd */
    int vsm_blur_mode;
    float vsm_bias;
};

static const struct technique_param playcanvas_vsm_params[] = {
    PLAYCANVAS_BIAS(struct playcanvas_vsm_settings, " (the sun's: a spot's map holds distances, which it does not "
                    "move)"),
    PLAYCANVAS_MAP(struct playcanvas_vsm_settings),
    PLAYCANVAS_FORMAT(struct playcanvas_vsm_settings, "the moments' floats (16f: exponent 5.54, 32f: 15)"),
    {"vsm_blur_size", "vsmBlurSize: taps of each of the blur's two passes, odd (an even one is made the next odd)",
     offsetof(struct playcanvas_vsm_settings, vsm_blur_size), PARAM_INT, 11, 1, 25, NULL,
     TUNE(1, 3, 5, 7, 11, 15, 21, 25)},
    {"vsm_blur_mode", "vsmBlurMode: gaussian (PlayCanvas's default) or box",
     offsetof(struct playcanvas_vsm_settings, vsm_blur_mode), PARAM_ENUM, 0, 0, 0, playcanvas_blur_modes, TUNE_CHOICES},
    {"vsm_bias", "vsmBias: the variance floor's scale, over the light's range (spot) or depth range (sun) / 7",
     offsetof(struct playcanvas_vsm_settings, vsm_bias), PARAM_FLOAT, 0.0025, 0.0, 1.0, NULL,
     TUNE(0.0005, 0.001, 0.0025, 0.005, 0.01, 0.02, 0.05)},
    {NULL},
};

struct playcanvas_pcss_settings {
    float normal_bias;
    int shadow_side, map_size;
    float light_size_scale;
    float penumbra_falloff;
    int shadow_samples, shadow_blocker_samples;
};

static const struct technique_param playcanvas_pcss_params[] = {
    PLAYCANVAS_NORMAL_BIAS(struct playcanvas_pcss_settings),
    PLAYCANVAS_MAP(struct playcanvas_pcss_settings),
    PARAM_ROW_LIGHT_SIZE_SCALE(struct playcanvas_pcss_settings),
    {"penumbra_falloff", "penumbraFalloff: the sun's penumbra grows as 1 - (1 - gap / depth range)^this (a spot "
     "ignores it)", offsetof(struct playcanvas_pcss_settings, penumbra_falloff), PARAM_FLOAT, 1.0, 0.01, 16.0, NULL,
     TUNE(0.5, 1.0, 2.0, 4.0)},
    {"shadow_samples", "shadowSamples: the sun's filter taps (a spot takes 16)",
     offsetof(struct playcanvas_pcss_settings, shadow_samples), PARAM_INT, 16, 1, 128, NULL, TUNE(8, 16, 32)},
    {"shadow_blocker_samples", "shadowBlockerSamples: the sun's blocker-search taps, 0: no search, a fixed "
     "filter (a spot takes 16)", offsetof(struct playcanvas_pcss_settings, shadow_blocker_samples), PARAM_INT, 16,
     0, 128, NULL, TUNE(8, 16, 32)},
    {NULL},
};

/* Each parameter away from its default where it acts: the biases and the
 * format where acne shows, the faces where a one-sided plate would vanish,
 * the filters where a penumbra is wide; the sun's PCSS settings on a sun. */
#define PLAYCANVAS_PCF_CELLS                                                                   \
    {"grazing_receiver", {"bias=0.2", "normal_bias=0.02", "map_size=512", "format=16f"}},      \
    {"thin_features", {"shadow_side=engine"}}

static const struct technique_cell playcanvas_pcf1_cells[] = {PLAYCANVAS_PCF_CELLS, {NULL}};
static const struct technique_cell playcanvas_pcf3_cells[] = {PLAYCANVAS_PCF_CELLS, {NULL}};
static const struct technique_cell playcanvas_pcf5_cells[] = {PLAYCANVAS_PCF_CELLS, {NULL}};

static const struct technique_cell playcanvas_vsm_cells[] = {
    {"grazing_receiver", {"map_size=512", "format=16f"}},
    {"thin_features", {"shadow_side=engine", "vsm_bias=0.01"}},
    {"sun_contact", {"bias=0.2"}},
    {"overlapping_occluders", {"vsm_blur_size=21", "vsm_blur_mode=box"}},
    {NULL},
};

static const struct technique_cell playcanvas_pcss_cells[] = {
    {"grazing_receiver", {"normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {"contact_hardening", {"light_size_scale=2"}},
    {"sun_contact", {"penumbra_falloff=4", "shadow_samples=32,shadow_blocker_samples=8"}},
    {NULL},
};

ENGINE_TECHNIQUE(playcanvas_pcf1, playcanvas, "playcanvas", .regression = playcanvas_pcf1_cells,
                 .summary = "PlayCanvas SHADOW_PCF1: one bilinear hardware-compare tap");
ENGINE_TECHNIQUE(playcanvas_pcf3, playcanvas, "playcanvas", .regression = playcanvas_pcf3_cells,
                 .summary = "PlayCanvas SHADOW_PCF3 (its default): 4 bilinear-compare taps, a 3 x 3 tent");
ENGINE_TECHNIQUE(playcanvas_pcf5, playcanvas, "playcanvas", .regression = playcanvas_pcf5_cells,
                 .summary = "PlayCanvas SHADOW_PCF5: 9 bilinear-compare taps, a 5 x 5 tent");
ENGINE_TECHNIQUE(playcanvas_vsm, playcanvas, "playcanvas", .regression = playcanvas_vsm_cells,
                 .summary = "PlayCanvas SHADOW_VSM: blurred exponential moments (EVSM), Chebyshev's bound");
ENGINE_TECHNIQUE(playcanvas_pcss, playcanvas, "playcanvas", .regression = playcanvas_pcss_cells,
                 .summary = "PlayCanvas SHADOW_PCSS: blocker search and a disk filter, sized from the scene's light");
