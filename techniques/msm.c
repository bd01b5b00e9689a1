/* msm — moment shadow maps (Peters and Klein 2015, "Moment shadow mapping",
 * I3D), Hamburger or Hausdorff 4MSM.
 *
 * Computes V = 1 - G, G the sharpest lower bound on the share of the
 * filter region's depths in front of the receiver that is consistent with
 * four moments (w, w², w³, w⁴) of the depth there (w = 2d - 1, d linear
 * depth in [0, 1]), read from the msm product (prefiltered by a separable
 * Gaussian, mipmapped, sampled trilinearly at the receiver's footprint):
 * the distribution with those moments that puts the least mass in front of
 * the receiver's depth z is supported on z and the two roots z2 <= z3 of
 * the quadratic whose coefficients solve B c = (1, z, z²), B the Hankel
 * matrix of the moments; G follows in closed form from z, z2, z3 and the
 * first two moments. Four moments pin the depths down far better than two:
 * where vsm's bound lights a near occluder's umbra because a far one adds
 * variance, msm's puts that mass at the far depth.
 *
 * Parameters:
 *   bound               hamburger: the bound over distributions on the
 *                       whole line, as above; hausdorff: over those on
 *                       [-1, 1], where depths lie. Where Hamburger's roots
 *                       leave [-1, 1] the least mass in front sits on
 *                       {-1, z, x, 1} instead, a tighter bound (less
 *                       bleeding) for a second branch's cost.
 *   moment_bias         alpha: the moments drawn towards those of a spread
 *                       distribution, (1 - alpha) b + alpha (0, 0.375, 0,
 *                       0.375) (hausdorff: the uniform's, (0, 1/3, 0,
 *                       1/5), msm_common.glsl), which keeps B invertible
 *                       against fp32 rounding and flat regions (one
 *                       depth); larger values bleed more. Hausdorff's
 *                       guarantee against fp32 rounding holds from 1.1e-6
 *                       up; the range goes down to 1e-7 for Hamburger's,
 *                       and tuning measures what lower values do.
 *   depth_bias          subtracted from the receiver's linear depth before
 *                       the test (linear depth units): against acne.
 *   blur_radius_texels  Gaussian prefilter of the moments (sigma = r / 2;
 *                       0 = mipmaps only), timed as filter prep.
 *
 * How it fails: some bleeding remains where three or more depths overlap
 * (four moments describe at most two well), grown by moment_bias; a
 * receiver whose own depth spreads across the filter region (a slope
 * under a wide blur) shadows itself, as the bound counts the nearer half
 * of that spread as occluders: depth_bias (0 by default; the tuning picks
 * 0.001) trades that for detached shadows; fp32 power moments lose
 * precision for depths crowded near one value, which the moment bias
 * covers at the cost of bleeding. No contact hardening: the blur is
 * fixed. The paper's optimised moment basis (precision in 16 bits) is
 * not implemented: the moments are fp32. */
#include "param_rows.h"

struct msm_settings {
    int bound;               /* 0: hamburger, 1: hausdorff */
    float moment_bias;       /* [1e-7, 0.01]: 0 leaves B singular where one depth covers the region */
    float depth_bias;        /* linear depth, [0, 0.05] */
    int blur_radius_texels;  /* [0, SM_MAX_BLUR_RADIUS_TEXELS] */
};

static const char *const msm_bounds[] = {"hamburger", "hausdorff", NULL};

static const struct technique_param msm_params[] = {
    {"bound", "hamburger: over distributions on the whole line; hausdorff: on [-1, 1], tighter where "
     "Hamburger's support leaves it", offsetof(struct msm_settings, bound), PARAM_ENUM, 0, 0, 0, msm_bounds,
     TUNE_CHOICES},
    {"moment_bias", "alpha, the moments drawn towards a spread distribution's: guards fp32 rounding "
     "(hausdorff: guaranteed from 1.1e-6 up, msm_common.glsl), bleeds as it grows", offsetof(struct msm_settings, moment_bias), PARAM_FLOAT, 3e-5, 1e-7, 0.01, NULL,
     TUNE(3e-7, 3e-6, 3e-5, 3e-4, 3e-3)},
    {"depth_bias", "subtracted from the receiver's linear depth before the test",
     offsetof(struct msm_settings, depth_bias), PARAM_FLOAT, 0.0, 0.0, 0.05, NULL, TUNE(0, 1e-4, 1e-3, 1e-2)},
    PARAM_ROW_BLUR_RADIUS(struct msm_settings, "moments"),
    {NULL},
};

static void msm_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    (void)c;
    r->msm.blur_radius_texels = ((const struct msm_settings *)settings)->blur_radius_texels;
}

static const struct technique_cell msm_cells[] = {
    {"overlapping_occluders", {"moment_bias=0.003,blur_radius_texels=8"}},
    {"grazing_receiver", {"depth_bias=0.001"}},
    {"stanford_bunny", {"bound=hausdorff"}},
    {NULL},
};

TECHNIQUE(msm, .needs = SM_MSM, .request = msm_request, .regression = msm_cells,
          .summary = "4MSM (Hamburger or Hausdorff): the sharpest bound from four filtered moments, little bleeding");
