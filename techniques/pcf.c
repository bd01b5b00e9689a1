/* pcf — percentage-closer filtering (Reeves, Salesin and Cook 1987,
 * "Rendering antialiased shadows with depth maps").
 *
 * Computes V as the mean of depth comparisons over a fixed kernel around the
 * receiver: it filters the comparison results, never the depths (averaging
 * depths and comparing once is meaningless). The kernel is a grid of n x n
 * taps over a square, or a set of points in a disk, turned (disk) or
 * shifted (square) per pixel: noise instead of banding.
 *
 * Parameters:
 *   radius_texels        kernel radius in shadow-map texels.
 *   pattern              the taps' layout (pcss's, shadow_taps.glsl): grid
 *                        (n x n cell centres of the square of that radius),
 *                        or in the disk of that radius poisson
 *                        (best-candidate set), vogel (golden-angle spiral),
 *                        uniform_disk (independent uniform points).
 *   rotation             the per-pixel noise that turns the disk's taps or
 *                        shifts the grid's modulo its square: none, hash,
 *                        ign (default), ign_2x2, blue_noise (as pcss's).
 *   animate_noise        the frame index moves that noise (as pcss's).
 *   samples              taps per pixel; grid needs a square count.
 *   hardware_2x2         each tap is a bilinear 2x2 comparison by the texture
 *                        unit (sampler2DShadow, linear): smoother for the
 *                        same tap count.
 *   denoise_radius_px, denoise_sigma_world, denoise_normal_power
 *                        the bilateral denoiser after the receiver pass
 *                        (render/receiver.h), which any technique may declare.
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
 * (rotation none) or are noisy (the rest); without the receiver plane, a kernel wider
 * than the bias covers self-shadows sloped receivers (acne); the plane is
 * wrong across curved receivers and at their silhouettes. */
#include "param_rows.h"
#include "params.h"

#include "base/util.h"

#include <stdbool.h>
#include <stdio.h>

struct pcf_settings {
    float radius_texels;      /* [0, 64] */
    int pattern;              /* TAP_PATTERN_* */
    int rotation;             /* TAP_ROTATION_* */
    int animate_noise;        /* bool */
    int samples;              /* TAP_COUNTS */
    int hardware_2x2;         /* bool */
    int denoise_radius_px;    /* [0, 8], 0: off */
    float denoise_sigma_world;
    float denoise_normal_power;
    int receiver_plane_bias;  /* bool */
    float constant_bias;      /* linear depth units, [0, 0.1] */
    float slope_bias;         /* texels of depth slope, [0, 16] */
};

static const struct technique_param pcf_params[] = {
    {"radius_texels", "kernel radius, shadow-map texels",
     offsetof(struct pcf_settings, radius_texels), PARAM_FLOAT, 2.0, 0.0, 64.0, NULL,
     TUNE(1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64)},
    PARAM_ROW_TAP_PATTERN(struct pcf_settings, TUNE_CHOICES),
    PARAM_ROW_TAP_ROTATION(struct pcf_settings),
    PARAM_ROW_ANIMATE_NOISE(struct pcf_settings),
    {"samples", "taps per pixel (grid: a square count)",
     offsetof(struct pcf_settings, samples), PARAM_TAPS, 32, 0, 0, NULL, TUNE_CHOICES},
    {"hardware_2x2", "each tap a bilinear 2x2 hardware comparison (sampler2DShadow)",
     offsetof(struct pcf_settings, hardware_2x2), PARAM_BOOL, 0, 0, 1, NULL, TUNE_CHOICES},
    PARAM_ROWS_DENOISE(struct pcf_settings),
    PARAM_ROW_RECEIVER_PLANE_BIAS(struct pcf_settings),
    PARAM_ROW_CONSTANT_BIAS(struct pcf_settings),
    PARAM_ROW_SLOPE_BIAS(struct pcf_settings, " (unused with receiver_plane_bias)"),
    {NULL},
};

static int pcf_check(const void *settings, char *why, size_t why_size)
{
    const struct pcf_settings *s = settings;
    return s->pattern == TAP_PATTERN_GRID ? params_grid_taps("sample count", s->samples, why, why_size) : 0;
}

static const struct technique_cell pcf_cells[] = {
    {"parallel_planes", {"radius_texels=8", "pattern=grid,samples=25", "pattern=grid,samples=25,rotation=none",
                         "pattern=vogel,rotation=blue_noise", "animate_noise=true", "samples=64",
                         "hardware_2x2=true", "denoise_radius_px=2,denoise_sigma_world=0.5"}},
    {"curved_receivers", {"denoise_radius_px=2,denoise_normal_power=16"}},
    {"grazing_receiver",
     {"receiver_plane_bias=false", "receiver_plane_bias=false,slope_bias=4", "constant_bias=0.005"}},
    {NULL},
};

TECHNIQUE(pcf, .needs = SM_DEPTH, .check = pcf_check, .regression = pcf_cells,
          .summary = "fixed-width average of depth comparisons: constant blur, no contact hardening");
