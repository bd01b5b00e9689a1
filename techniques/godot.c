/* Godot 4's shadow filters as it ships them, re-implemented
 * (docs/presets.md): presets, shadowbench's own shaders following
 * godotengine/godot 4.4 to 4.6 (the same filter code in every version
 * read), servers/rendering/renderer_rd/shaders/scene_forward_lights_inc.glsl,
 * the quality tables of renderer_scene_render_rd.cpp
 * (positional_soft_shadow_filter_set_quality, get_vogel_disk) and
 * storage_rd/light_storage.cpp (update_light_buffers) for the radii.
 *
 * Confirmed against that source (shaders/godot_filters.glsl, godot_*.glsl):
 *   - the quality levels, rendering/lights_and_shadows/ (positional and directional)
 *     soft_shadow_filter_quality, default Soft Low (the mobile default is
 *     Hard): PCF taps 0 (one comparison at the centre) / 1 / 4 / 8 / 16 /
 *     32, PCSS taps 4 / 4 / 8 / 12 / 24 / 32, PCF radius x 1 / 1.5 / 2 / 2
 *     / 3 / 4 (PCSS's radii take no multiplier);
 *   - the taps: a Vogel disk, point i of n at radius sqrt(i + 0.5) / sqrt(n)
 *     and angle 2.4 i, turned per pixel by interleaved gradient noise of
 *     the window position (moved by 5.588238 a frame under TAA:
 *     `animate_noise`);
 *     every tap a bilinear hardware comparison, weighted equally;
 *   godot_pcf   a light with no size: radius shadow_blur x the level's
 *               multiplier, in texels (a spot's and the first cascade's).
 *   godot_pcss  a spot with light_size > 0, or the sun with
 *               light_angular_distance > 0: the search (the level's PCSS
 *               taps, bilinear raw depths, blockers nearer than the
 *               receiver averaged) over, for a spot, (size / 2 / range) /
 *               tan(half angle) x z_norm (z_norm the receiver's distance
 *               along the axis over the range), for the sun, tan(angular
 *               distance) x the receiver's distance from the map's near
 *               plane; no blocker: lit; the radius times
 *               (blocker - z) / (1 - blocker), no clamp; the same taps
 *               compared there. A spot's blocker depth is a perspective
 *               depth and its z_norm a linear one: Godot mixes the two, and
 *               so does this (the penumbra barely follows the blocker's
 *               distance).
 *
 * Approximated, and why:
 *   - the map is shadowbench's fitted one at the run's size, not Godot's
 *     atlas cell; a spot's range is the map's far plane and its z_near
 *     Godot's min(0.025, range). The map's v axis is GL's, so the turned
 *     patterns are mirrored against Godot's (the same statistics).
 *   - light_size (a diameter) is the scene's light: a disk light's
 *     diameter, a rect light's equal-area disk's; the sun's
 *     light_angular_distance its angular diameter. light_size_scale
 *     multiplies it.
 *   - bias: Godot's own, its normal bias and its depth bias as its shader
 *     applies them, at its defaults; a spot's range is the map's far plane
 *     (the depth bias is a distance proportional to it).
 *   - blend_splits and later cascades are not modelled (one map).
 *
 * How they fail: pcf is a fixed blur whose few taps (4 at the default)
 * leave noise; pcss's spot penumbra barely follows the blocker's distance,
 * and its few taps band or speckle wide penumbrae. */
#include "param_rows.h"

static const char *const godot_quality_names[] = {"hard", "very_low", "low", "medium", "high", "ultra", NULL};

#define GODOT_SOURCE "godotengine/godot 4.4-4.6: servers/rendering/renderer_rd/shaders/scene_forward_lights_inc.glsl"

#define GODOT_COMMON_ROWS(settings)                                                                    \
    {"quality", "soft_shadow_filter_quality: hard, very_low, low (the default), medium, high, ultra",  \
     offsetof(settings, quality), PARAM_ENUM, 2, 0, 0, godot_quality_names, TUNE_CHOICES},             \
    {"blur", "shadow_blur: the light's blur multiplier", offsetof(settings, blur), PARAM_FLOAT, 1.0, 0.0, 10.0, \
     NULL, TUNE(0.5, 1.0, 2.0)},                                                                        \
    PARAM_ROW_ANIMATE_NOISE(settings),                                                                  \
    {"normal_bias", "shadow_normal_bias: the lookup moved along the normal (a spot: dist x this x 10 / "   \
     "map size, times 1 - |N.L|; the sun: this many texels on every face it lights); below 0: Godot's "    \
     "default for the light (spot 1, sun 2)", offsetof(settings, normal_bias), PARAM_FLOAT, -1.0, -1.0, 10.0, \
     NULL, TUNE(-1.0, 0.0, 0.5, 3.0, 6.0)},                                                              \
    {"bias", "shadow_bias: the reference moved towards the light (a spot: bias / 100 x range / z_near; "       \
     "the sun: bias / 100 of the map's depth range), times the filter's soft_shadow_scale; -1: Godot's "    \
     "default for the light (below 0: spot 0.03, sun 0.1)", offsetof(settings, bias), PARAM_FLOAT, -1.0, -1.0, 10.0, \
     NULL, TUNE(-1.0, 0.0, 0.01, 0.3)}

/* The levels as named cells of a run: the quality curve (docs/presets.md). */
static const struct technique_preset godot_levels[] = {
    {"hard", "quality=hard", "Soft Hard: one comparison (PCSS: 4 taps)"},
    {"very_low", "quality=very_low", "Soft Very Low: 1 tap x 1.5 (PCSS: 4)"},
    {"medium", "quality=medium", "Soft Medium: 8 taps x 2 (PCSS: 12)"},
    {"high", "quality=high", "Soft High: 16 taps x 3 (PCSS: 24)"},
    {"ultra", "quality=ultra", "Soft Ultra: 32 taps x 4 (PCSS: 32)"},
    {NULL},
};

struct godot_pcf_settings {
    int quality;
    float blur;
    int animate_noise;
    float normal_bias, bias;
};

static const struct technique_param godot_pcf_params[] = {
    GODOT_COMMON_ROWS(struct godot_pcf_settings),
    {NULL},
};

static const struct technique_cell godot_pcf_cells[] = {
    {"grazing_receiver", {"bias=0.3", "normal_bias=0"}},
    {"parallel_planes", {"blur=2", "animate_noise=true", "quality=ultra"}},
    {NULL},
};

TECHNIQUE(godot_pcf, .needs = SM_DEPTH, .regression = godot_pcf_cells, .presets = godot_levels,
          .preset_of = "godot", .preset_source = GODOT_SOURCE,
          .summary = "Godot 4's PCF: a Vogel disk turned by IGN, taps and radius by quality level");

struct godot_pcss_settings {
    int quality;
    float blur;
    int animate_noise;
    float normal_bias, bias;
    float light_size_scale;
};

static const struct technique_param godot_pcss_params[] = {
    GODOT_COMMON_ROWS(struct godot_pcss_settings),
    PARAM_ROW_LIGHT_SIZE_SCALE(struct godot_pcss_settings),
    {NULL},
};

static const struct technique_cell godot_pcss_cells[] = {
    {"contact_hardening", {"light_size_scale=0.5", "blur=2"}},
    {"grazing_receiver", {"bias=0.3", "normal_bias=0"}},
    {"parallel_planes", {"animate_noise=true", "quality=ultra"}},
    {NULL},
};

TECHNIQUE(godot_pcss, .needs = SM_DEPTH, .regression = godot_pcss_cells, .presets = godot_levels,
          .preset_of = "godot", .preset_source = GODOT_SOURCE,
          .summary = "Godot 4's soft shadows: Vogel-disk blocker search and filter, taps by quality level");
