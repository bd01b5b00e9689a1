/* Parameter rows that several techniques share, one definition each (STYLE.md
 * item 6a): PARAM_ROW_CONSTANT_BIAS(struct pcf_settings) is the row for that
 * struct's member `constant_bias`, with the same name, help, default and
 * range in every technique that has it. */
#ifndef SB_PARAM_ROWS_H
#define SB_PARAM_ROWS_H

#include "technique.h"
#include "base/util.h"

#define PARAM_ROW_CONSTANT_BIAS(settings)                                                  \
    {"constant_bias", "constant depth offset, linear shadow-map depth units (1 = near..far)", \
     offsetof(settings, constant_bias), PARAM_FLOAT, 0.0005, 0.0, 0.1, NULL,                 \
     TUNE(0.0, 0.0001, 0.0005, 0.002, 0.005)}

/* note: "" or what else decides whether it applies, e.g. " (unused with
 * receiver_plane_bias)". */
#define PARAM_ROW_SLOPE_BIAS(settings, note)                                               \
    {"slope_bias", "slope-scaled offset, texels of the receiver's depth slope" note,        \
     offsetof(settings, slope_bias), PARAM_FLOAT, 1.0, 0.0, 16.0, NULL, TUNE(0.0, 0.5, 1.0, 2.0, 4.0)}

#define PARAM_ROW_RECEIVER_PLANE_BIAS(settings)                                            \
    {"receiver_plane_bias", "compare against the receiver's plane at each tap",            \
     offsetof(settings, receiver_plane_bias), PARAM_BOOL, 1, 0, 1, NULL, TUNE_CHOICES}

#define PARAM_ROW_LIGHT_SIZE_SCALE(settings)                                               \
    {"light_size_scale", "multiplies the scene's light size (1 = the true light)",         \
     offsetof(settings, light_size_scale), PARAM_FLOAT, 1.0, 0.01, 10.0, NULL,               \
     TUNE(0.5, 0.75, 1.0, 1.25, 1.5, 2.0)}

/* The tap loops' layout and per-pixel noise (technique.h's TAP_PATTERNS,
 * TAP_ROTATIONS). tune: TUNE_CHOICES, or NULL where the choices are
 * measured as named cells instead. */
#define PARAM_ROW_TAP_PATTERN(settings, tune)                                              \
    {"pattern", "tap layout over the light's shape: poisson (best-candidate set), grid (n x n, " \
     "a square tap count), vogel (golden-angle spiral), uniform_disk (independent uniform points)", \
     offsetof(settings, pattern), PARAM_ENUM, TAP_PATTERN_POISSON, 0, 0, tap_pattern_names, tune}

#define PARAM_ROW_TAP_ROTATION(settings)                                                   \
    {"rotation", "per-pixel noise turning (disk) or shifting (square) the taps: none "       \
     "(banding), hash (white), ign (interleaved gradient noise), ign_2x2 (one per 2 x 2 block), " \
     "blue_noise (a tileable void-and-cluster texture)", \
     offsetof(settings, rotation), PARAM_ENUM, TAP_ROTATION_IGN, 0, 0, tap_rotation_names, NULL}

#define PARAM_ROW_ANIMATE_NOISE(settings)                                                  \
    {"animate_noise", "the frame index moves the per-pixel noise (a new rotation each frame, "  \
     "for TAA to average); `stability` animates it, `check` renders frame 1 so it is seen to act",               \
     offsetof(settings, animate_noise), PARAM_BOOL, 0, 0, 1, NULL, NULL}

#define PARAM_ROW_MIN_VARIANCE(settings)                                                   \
    {"min_variance", "floor on the variance, linear depth units squared",                  \
     offsetof(settings, min_variance), PARAM_FLOAT, 1e-5, 0.0, 0.01, NULL, TUNE(1e-6, 1e-5, 1e-4, 1e-3)}

#define PARAM_ROW_BLEED_REDUCTION(settings)                                                \
    {"bleed_reduction", "light-bleeding reduction: p_max below this becomes 0, the rest "  \
     "is rescaled (0 = off)", offsetof(settings, bleed_reduction), PARAM_FLOAT, 0.0, 0.0, 0.99, NULL, \
     TUNE(0.0, 0.1, 0.2, 0.3, 0.5)}

/* what: what is filtered, e.g. "moments", "warped moments". */
#define PARAM_ROW_BLUR_RADIUS(settings, what)                                              \
    {"blur_radius_texels", "Gaussian prefilter of the " what ", radius in texels (sigma = r/2)", \
     offsetof(settings, blur_radius_texels), PARAM_INT, 2, 0, SM_MAX_BLUR_RADIUS_TEXELS, NULL, \
     TUNE(0, 1, 2, 3, 4, 6, 8, 12, 16, 24, 32)}

/* share: how the blocked share is had, e.g. "estimated blocked share". */
#define PARAM_ROW_MIN_BLOCKER_FRACTION(settings, share)                                    \
    {"min_blocker_fraction", share " of the search box below which it is lit",             \
     offsetof(settings, min_blocker_fraction), PARAM_FLOAT, 0.001, 0.0, 0.5, NULL,           \
     TUNE(0.0, 0.001, 0.01, 0.05)}

#define PARAM_ROW_SAT_FORMAT(settings)                                                     \
    {"sat_format", "summed-area table precision: fp32, fp32_centered (sums of d - 0.5), "  \
     "int32 (exact)", offsetof(settings, sat_format), PARAM_ENUM, SAT_INT32, 0, 0, sat_format_names, TUNE_CHOICES}

/* The screen-space stages around the receiver pass (docs/techniques.md,
 * render/receiver.h's receiver_stages_of): a technique declares a stage by
 * having its rows, and the harness reads them by these names (a
 * contract: scripts set them). Not tuned: measured as named settings. */
#define PARAM_ROWS_DENOISE(settings)                                                       \
    {"denoise_radius_px", "bilateral denoiser after the receiver pass: radius in pixels, " \
     "separable, weighted by world distance (0 = off)",                                   \
     offsetof(settings, denoise_radius_px), PARAM_INT, 0, 0, 8, NULL, NULL},               \
    {"denoise_sigma_world", "the denoiser's world-distance weight: its sigma, world units", \
     offsetof(settings, denoise_sigma_world), PARAM_FLOAT, 0.1, 0.001, 100.0, NULL, NULL},       \
    {"denoise_normal_power", "the denoiser's normal weight: max(0, n . n_tap) to this power, normals " \
     "rebuilt from the camera distances (0 = position only, seed 003's)",                  \
     offsetof(settings, denoise_normal_power), PARAM_FLOAT, 0.0, 0.0, 256.0, NULL, NULL}

/* The technique defines shadow_classify() (shaders/penumbra_mask.frag).
 * mask_dilate_world asks a block for at most MASK_MAX_DILATE_BLOCKS. */
#define MASK_MAX_DILATE_BLOCKS 8

#define PARAM_ROWS_PENUMBRA_MASK(settings)                                                 \
    {"penumbra_mask", "a quarter-resolution pre-pass classifies 4 x 4 blocks as lit, umbra " \
     "or penumbra; the full filter runs only on penumbra blocks",                          \
     offsetof(settings, penumbra_mask), PARAM_BOOL, 0, 0, 1, NULL, NULL},                  \
    {"mask_dilate_blocks", "the mask's dilation: a block stays lit or umbra only if every "  \
     "block this many blocks around agrees",                                               \
     offsetof(settings, mask_dilate_blocks), PARAM_INT, 1, 0, 4, NULL, NULL},                \
    {"mask_dilate_world", "seed 003's distance-dependent dilation: this radius in world units, "  \
     "made blocks at each block's view depth (more blocks when near), if more than "   \
     "mask_dilate_blocks, at most " UTIL_STR(MASK_MAX_DILATE_BLOCKS) " (0 = off)",                                            \
     offsetof(settings, mask_dilate_world), PARAM_FLOAT, 0.0, 0.0, 100.0, NULL, NULL}

/* Engine cells (docs/engines.md). engine: what the engine's own choice is,
 * e.g. "three's default for the file's one-sided materials". */
#define PARAM_ROW_ENGINE_SIDE(settings, engine)                                                         \
    {"shadow_side", "faces drawn into the map: double (both, shadowbench's choice) or engine (" engine ")", \
     offsetof(settings, shadow_side), PARAM_ENUM, 0, 0, 0, engine_side_names, NULL}

/* what: the engine's own name for it, e.g. "shadow.mapSize"; max: the
 * largest the engine draws. */
#define PARAM_ROW_ENGINE_MAP_SIZE(settings, what, max)                                                   \
    {"map_size", what ", texels a side; 0: the run's --shadow-map-size", offsetof(settings, map_size),  \
     PARAM_INT, 0, 0, max, NULL, NULL}

#endif
