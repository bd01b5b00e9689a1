/* Parameter rows that several techniques share, one definition each (STYLE.md
 * item 6a): PARAM_ROW_CONSTANT_BIAS(struct pcf_settings) is the row for that
 * struct's member `constant_bias`, with the same name, help, default and
 * range in every technique that has it. */
#ifndef SB_PARAM_ROWS_H
#define SB_PARAM_ROWS_H

#include "technique.h"

#define PARAM_ROW_CONSTANT_BIAS(settings)                                                  \
    {"constant_bias", "constant depth offset, linear shadow-map depth units (1 = near..far)", \
     offsetof(settings, constant_bias), PARAM_FLOAT, 0.0005, 0.0, 0.1, NULL}

/* note: "" or what else decides whether it applies, e.g. " (unused with
 * receiver_plane_bias)". */
#define PARAM_ROW_SLOPE_BIAS(settings, note)                                               \
    {"slope_bias", "slope-scaled offset, texels of the receiver's depth slope" note,        \
     offsetof(settings, slope_bias), PARAM_FLOAT, 1.0, 0.0, 16.0, NULL}

#define PARAM_ROW_RECEIVER_PLANE_BIAS(settings)                                            \
    {"receiver_plane_bias", "compare against the receiver's plane at each tap",            \
     offsetof(settings, receiver_plane_bias), PARAM_BOOL, 1, 0, 1, NULL}

#define PARAM_ROW_LIGHT_SIZE_SCALE(settings)                                               \
    {"light_size_scale", "multiplies the scene's light size (1 = the true light)",         \
     offsetof(settings, light_size_scale), PARAM_FLOAT, 1.0, 0.01, 10.0, NULL}

#define PARAM_ROW_MIN_VARIANCE(settings)                                                   \
    {"min_variance", "floor on the variance, linear depth units squared",                  \
     offsetof(settings, min_variance), PARAM_FLOAT, 1e-5, 0.0, 0.01, NULL}

#define PARAM_ROW_BLEED_REDUCTION(settings)                                                \
    {"bleed_reduction", "light-bleeding reduction: p_max below this becomes 0, the rest "  \
     "is rescaled (0 = off)", offsetof(settings, bleed_reduction), PARAM_FLOAT, 0.0, 0.0, 0.99, NULL}

#define PARAM_ROW_SAT_FORMAT(settings)                                                     \
    {"sat_format", "summed-area table precision: fp32, fp32_centered (sums of d - 0.5), "  \
     "int32 (exact)", offsetof(settings, sat_format), PARAM_ENUM, SAT_INT32, 0, 0, sat_format_names}

#endif
