/* pcf — percentage-closer filtering (Reeves, Salesin and Cook 1987,
 * "Rendering antialiased shadows with depth maps").
 *
 * Computes V as the mean of depth comparisons over a fixed kernel around the
 * receiver: it filters the comparison results, never the depths (averaging
 * depths and comparing once is meaningless). The kernel is a grid of n x n
 * taps or a Poisson-disk set rotated per pixel (noise instead of banding).
 *
 * Parameters:
 *   radius_texels        kernel radius in shadow-map texels.
 *   pattern              grid (n x n regular taps over the square of that
 *                        radius) or poisson (best-candidate disk set, rotated
 *                        per pixel by interleaved gradient noise).
 *   samples              taps per pixel; grid needs a square count.
 *   hardware_2x2         each tap is a bilinear 2x2 comparison by the texture
 *                        unit (sampler2DShadow, linear): smoother for the
 *                        same tap count.
 *   receiver_plane_bias  compare against the receiver's plane (fitted from
 *                        screen-space derivatives) at each tap, instead of
 *                        its depth at the centre: no acne across wide kernels
 *                        on planar receivers.
 *   constant_bias        depth offset, linear units (1 = near..far).
 *   slope_bias           without receiver_plane_bias only: offset in texels
 *                        of the receiver's depth slope.
 *
 * How it fails: the blur is the same everywhere, so contact shadows are too
 * soft and far penumbrae too hard (no contact hardening); few taps band
 * (grid) or are noisy (poisson); without the receiver plane, a kernel wider
 * than the bias covers self-shadows sloped receivers (acne); the plane is
 * wrong across curved receivers and at their silhouettes. */
#include "technique.h"

#include <stdio.h>

struct pcf_settings {
    float radius_texels;      /* [0, 64] */
    int pattern;              /* PCF_GRID, PCF_POISSON */
    int samples;              /* 16, 25, 32, 64, 100, 128 */
    int hardware_2x2;         /* bool */
    int receiver_plane_bias;  /* bool */
    float constant_bias;      /* linear depth units, [0, 0.1] */
    float slope_bias;         /* texels of depth slope, [0, 16] */
};

enum { PCF_GRID, PCF_POISSON };
static const char *const pcf_patterns[] = {"grid", "poisson", NULL};
static const char *const pcf_sample_counts[] = {"16", "25", "32", "64", "100", "128", NULL};

static const struct technique_param pcf_params[] = {
    {"radius_texels", "kernel radius, shadow-map texels",
     offsetof(struct pcf_settings, radius_texels), PARAM_FLOAT, 2.0, 0.0, 64.0, NULL},
    {"pattern", "tap layout: grid (n x n) or poisson (disk, rotated per pixel)",
     offsetof(struct pcf_settings, pattern), PARAM_ENUM, PCF_POISSON, 0, 1, pcf_patterns},
    {"samples", "taps per pixel (grid: 16, 25, 64 or 100)",
     offsetof(struct pcf_settings, samples), PARAM_INT, 32, 16, 128, pcf_sample_counts},
    {"hardware_2x2", "each tap a bilinear 2x2 hardware comparison (sampler2DShadow)",
     offsetof(struct pcf_settings, hardware_2x2), PARAM_BOOL, 0, 0, 1, NULL},
    {"receiver_plane_bias", "compare against the receiver's plane at each tap",
     offsetof(struct pcf_settings, receiver_plane_bias), PARAM_BOOL, 1, 0, 1, NULL},
    {"constant_bias", "constant depth offset, linear shadow-map depth units (1 = near..far)",
     offsetof(struct pcf_settings, constant_bias), PARAM_FLOAT, 0.0005, 0.0, 0.1, NULL},
    {"slope_bias", "without receiver_plane_bias: offset in texels of the receiver's depth slope",
     offsetof(struct pcf_settings, slope_bias), PARAM_FLOAT, 1.0, 0.0, 16.0, NULL},
    {NULL},
};

static int pcf_check(const void *settings, char *why, size_t why_size)
{
    const struct pcf_settings *s = settings;
    int side = 1;
    while (side * side < s->samples)
        side++;
    if (s->pattern == PCF_GRID && side * side != s->samples) {
        snprintf(why, why_size, "pattern=grid needs a square sample count (16, 25, 64 or 100), "
                 "not %d", s->samples);
        return -1;
    }
    return 0;
}

const struct technique technique_pcf = {
    .name = "pcf",
    .summary = "fixed-width average of depth comparisons: constant blur, no contact hardening",
    .needs = SM_DEPTH,
    .params = pcf_params,
    .settings_size = sizeof(struct pcf_settings),
    .shader = "pcf.glsl",
    .check = pcf_check,
};
