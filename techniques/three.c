/* three.js's shadow maps as they ship (npm three 0.187.0, r187), rendered by
 * three itself in headless Chromium (engines/three/adapter.js;
 * docs/engines.md). Each mode is a value of WebGLRenderer.shadowMap.type;
 * the parameters are the light's LightShadow settings, under their own
 * names, at three's defaults.
 *
 * What three does (src/renderers/shaders/ShaderChunk/
 * shadowmap_pars_fragment.glsl.js, r187):
 *   three_basic  BasicShadowMap: one depth comparison, nearest texel.
 *   three_pcf    PCFShadowMap: 5 hardware-compare (bilinear) taps on a Vogel
 *                disk of shadow.radius texels, rotated per pixel by
 *                interleaved gradient noise. (r187 removed PCFSoftShadowMap:
 *                it falls back to this, bit for bit.)
 *   three_vsm    VSMShadowMap: a separable blur of blur_samples taps over
 *                shadow.radius texels of (depth, depth²), then Chebyshev's
 *                bound; receivers are drawn into the map too.
 * None has a light size: three has no PCSS, so nothing is derived from the
 * scene's light but its pose and frustum.
 *
 * Parameters of the modes (three_vsm has no shadow_side: three's default for
 * VSM draws the front faces, which are the faces nearest the light in every
 * shipped scene, so both choices give one map here; it draws both):
 *   bias         shadow.bias: added to the receiver's depth in the map's own
 *                depth units (the spot's perspective depth, the sun's linear
 *                one); negative moves it towards the light.
 *   normal_bias  shadow.normalBias: the receiver's position moved along its
 *                normal before the lookup, world units.
 *   shadow_side  double: both faces drawn into the map (material.shadowSide
 *                = DoubleSide), shadowbench's own choice; engine: three's
 *                default for the file's one-sided materials (their back
 *                faces; VSM: their front faces), which drops single-sided
 *                plates from the map.
 *   map_size     shadow.mapSize, texels a side; 0: the run's
 *                --shadow-map-size, so that the cells compare with
 *                shadowbench's own at one resolution (three's own default
 *                is 512). */
#include "param_rows.h"

#define THREE_BIASES(settings)                                                                      \
    {"bias", "shadow.bias: the receiver's depth offset, the map's depth units (negative: towards the " \
     "light)", offsetof(settings, bias), PARAM_FLOAT, 0.0, -0.05, 0.05, NULL,                         \
     TUNE(0.0, -0.0001, -0.0005, -0.001, -0.002, -0.005, -0.01, -0.02)},                                             \
    {"normal_bias", "shadow.normalBias: the receiver moved along its normal, world units",            \
     offsetof(settings, normal_bias), PARAM_FLOAT, 0.0, 0.0, 1.0, NULL,                               \
     TUNE(0.0, 0.005, 0.01, 0.02, 0.05)},                                                              \
    PARAM_ROW_ENGINE_MAP_SIZE(settings, "shadow.mapSize", 8192)

#define THREE_SIDE(settings) PARAM_ROW_ENGINE_SIDE(settings, "three's default for the file's one-sided materials")

#define THREE_SETTINGS \
    float bias, normal_bias; \
    int map_size

struct three_basic_settings {
    THREE_SETTINGS;
    int shadow_side;
};

static const struct technique_param three_basic_params[] = {
    THREE_BIASES(struct three_basic_settings),
    THREE_SIDE(struct three_basic_settings),
    {NULL},
};

struct three_pcf_settings {
    THREE_SETTINGS;
    int shadow_side;
    float radius;  /* texels */
};

static const struct technique_param three_pcf_params[] = {
    THREE_BIASES(struct three_pcf_settings),
    THREE_SIDE(struct three_pcf_settings),
    {"radius", "shadow.radius: the Vogel disk's radius, texels", offsetof(struct three_pcf_settings, radius),
     PARAM_FLOAT, 1.0, 0.0, 64.0, NULL, TUNE(1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0)},
    {NULL},
};

struct three_vsm_settings {
    THREE_SETTINGS;
    float radius;      /* texels */
    int blur_samples;  /* taps of each blur pass */
};

static const struct technique_param three_vsm_params[] = {
    THREE_BIASES(struct three_vsm_settings),
    {"radius", "shadow.radius: the blur's half-width, texels", offsetof(struct three_vsm_settings, radius),
     PARAM_FLOAT, 1.0, 0.0, 64.0, NULL, TUNE(1.0, 2.0, 4.0, 8.0, 12.0, 16.0)},
    {"blur_samples", "shadow.blurSamples: taps of each of the blur's two passes",
     offsetof(struct three_vsm_settings, blur_samples), PARAM_INT, 8, 1, 64, NULL, TUNE(4, 8, 16)},
    {NULL},
};

/* Each parameter away from its default where it acts: the bias and the
 * faces where acne and a one-sided plate show, the map size on an edge. */
static const struct technique_cell three_basic_cells[] = {
    {"grazing_receiver", {"bias=-0.0005", "normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {NULL},
};

static const struct technique_cell three_pcf_cells[] = {
    {"grazing_receiver", {"bias=-0.0005", "normal_bias=0.02", "map_size=512"}},
    {"thin_features", {"shadow_side=engine"}},
    {"contact_hardening", {"radius=4,normal_bias=0.02"}},
    {NULL},
};

static const struct technique_cell three_vsm_cells[] = {
    {"grazing_receiver", {"bias=-0.0005", "normal_bias=0.02", "map_size=512"}},
    {"overlapping_occluders", {"radius=8,blur_samples=16"}},
    {NULL},
};

ENGINE_TECHNIQUE(three_basic, three, "three", .regression = three_basic_cells,
                 .summary = "three.js BasicShadowMap: one nearest-texel comparison, as three ships it");
ENGINE_TECHNIQUE(three_pcf, three, "three", .regression = three_pcf_cells,
                 .summary = "three.js PCFShadowMap: 5 bilinear-compare taps on an IGN-rotated Vogel disk");
ENGINE_TECHNIQUE(three_vsm, three, "three", .regression = three_vsm_cells,
                 .summary = "three.js VSMShadowMap: blurred depth moments, Chebyshev's bound");
