/* vsm — variance shadow maps (Donnelly and Lauritzen 2006, "Variance shadow
 * maps", I3D).
 *
 * Computes V as the one-sided Chebyshev bound p_max = s² / (s² + (t - m)²)
 * (for t > m) from the mean m and variance s² of linear depth around the
 * receiver, read from the moments product (d, d²): prefiltered by a
 * separable Gaussian, mipmapped, sampled trilinearly at the receiver's
 * screen footprint. Filtering depths before the test is what comparisons
 * cannot do, so any linear filter applies.
 *
 * Parameters:
 *   blur_radius_texels  Gaussian prefilter of the moments, taps -r..r with
 *                       sigma = r / 2 (0 = none: mipmaps only); part of the
 *                       shared moments product, timed as filter prep.
 *   min_variance        floor on s², linear depth units squared: hides
 *                       float error and acne on sloped receivers.
 *   bleed_reduction     maps p_max in [amount, 1] to [0, 1] (0 = off).
 *
 * How it fails: light bleeding. The bound is exact only for two depths; where
 * a second occluder lies far behind the first, the large variance makes
 * p_max high inside the nearer one's umbra (leaks). bleed_reduction trades
 * the leaks for darker, narrower penumbrae. The blur is fixed (no contact
 * hardening), and min_variance too large lightens contact shadows. */
#include "param_rows.h"

struct vsm_settings {
    int blur_radius_texels;  /* [0, SM_MAX_BLUR_RADIUS_TEXELS] */
    float min_variance;      /* linear depth², [0, 0.01] */
    float bleed_reduction;   /* [0, 0.99] */
};

static const struct technique_param vsm_params[] = {
    PARAM_ROW_BLUR_RADIUS(struct vsm_settings, "moments"),
    PARAM_ROW_MIN_VARIANCE(struct vsm_settings),
    PARAM_ROW_BLEED_REDUCTION(struct vsm_settings),
    {NULL},
};

static void vsm_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    (void)c;
    r->moments.blur_radius_texels = ((const struct vsm_settings *)settings)->blur_radius_texels;
}

static const struct technique_cell vsm_cells[] = {
    {"parallel_planes", {"blur_radius_texels=8", "min_variance=0.001"}},
    {"overlapping_occluders", {"bleed_reduction=0.3"}},
    {NULL},
};

TECHNIQUE(vsm, .needs = SM_MOMENTS, .request = vsm_request, .regression = vsm_cells,
          .summary = "Chebyshev bound from prefiltered moments: light bleeding where occluders overlap");
