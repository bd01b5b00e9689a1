/* msm_soft — moment soft shadow mapping (Peters, Münstermann, Wetzstein and
 * Klein 2016, "Beyond hard shadows: moment shadow maps for single
 * scattering, soft shadows and translucent occluders", I3D; extended in
 * JCGT 6(1), 2017): PCSS whose two area queries are answered by Hamburger
 * 4MSM (msm_common.glsl) from the summed-area table of the four moments
 * (w, w², w³, w⁴), w = 2d - 1 (the msm_sat product): O(1) in the light size.
 *
 * Computes V like PCSS. Blocker search: over the search box (as pcss),
 * 4MSM's bound G is the least blocked share the box's moments allow, and
 * the distribution that attains it puts that share at one or two depths in
 * front of the receiver: their mean is the blocker depth (w = (b1 - (1 - G)
 * z) / G when both are in front, VSSM's estimate with the bound's weights).
 * G below min_blocker_fraction: lit. Penumbra width as PCSS; then 1 - G of
 * the moments over that box. Exact, like pcss_savsm, for a planar blocker
 * over a planar receiver parallel to a rect light (two depths, where four
 * moments determine the distribution); where three or more depths share
 * the search box (overlapping blockers, a receiver sloping through it)
 * four moments still place the blockers where two cannot, which is what
 * this technique buys over pcss_savsm.
 *
 * Parameters:
 *   sat_format            the table's precision: int32 (fixed point, exact
 *                         box sums, each box moment good to half a step
 *                         2^-k, k set by the widest search box as for
 *                         pcss_savsm: k = 15 at 2048² with the default
 *                         light, 13 at 4096², 4 at the widest box of an
 *                         8192² map) or fp32 (float sums: over a 2048² map
 *                         the box means err by ~5e-3, far more than 4MSM
 *                         tolerates, and no bias can be derived for them;
 *                         shown, not recommended).
 *   light_size_scale      multiplies the scene's light size.
 *   moment_bias           alpha, as msm: guards fp32 arithmetic, bleeds as
 *                         it grows. int32 adds msm_quantisation_bias(2^-k)
 *                         = SM_MSM_QUANTISATION_FACTOR 2^-k (msm_common.glsl), a bias that
 *                         guarantees rounded moments' Hankel matrix
 *                         positive definite: 2.2e-4 at k = 15. Without it, at k =
 *                         13 (a 4096² map) 78 % of the lit pixels went
 *                         dark.
 *   depth_bias            subtracted from the receiver's linear depth.
 *   min_blocker_fraction  below this blocked share of the search box, lit.
 *
 * How it fails: 4MSM's bound is a lower bound on the blocked share, so
 * where more than two depths overlap it still leaks (less than VSM); a
 * receiver sloping across a wide search box counts its own nearer half as
 * a blocker (both queries are boxes of the map, not of the receiver's
 * plane), which depth_bias trades against detached shadows; box kernels;
 * SAT precision limits the moment bias from below: the added bias doubles
 * with each bit the fixed point loses to a wider box (0.44 at k = 4), and
 * with it the leak and the blocker-depth error near contact (test_msm
 * bounds both by alpha / P², P the receiver's distances to the depths in
 * front of it). */
#include "param_rows.h"
#include "base/util.h"

struct msm_soft_settings {
    int sat_format;              /* index into msm_soft_sat_formats */
    float light_size_scale;      /* [0.01, 10] */
    float moment_bias;           /* [1e-7, 0.01] */
    float depth_bias;            /* linear depth, [0, 0.05] */
    float min_blocker_fraction;  /* [0, 0.5] */
};

/* The formats the msm_sat product offers (fp32_centered does not apply). */
static const char *const msm_soft_sat_formats[] = {"fp32", "int32", NULL};
static const enum sat_format msm_soft_sat_format_ids[] = {SAT_FP32, SAT_INT32};

static const struct technique_param msm_soft_params[] = {
    {"sat_format", "summed-area table precision: fp32, int32 (exact box sums)",
     offsetof(struct msm_soft_settings, sat_format), PARAM_ENUM, 1, 0, 0, msm_soft_sat_formats, NULL},
    PARAM_ROW_LIGHT_SIZE_SCALE(struct msm_soft_settings),
    {"moment_bias", "alpha, the moments drawn towards a spread distribution's: guards rounding, "
     "bleeds as it grows; int32 adds " UTIL_STR(SM_MSM_QUANTISATION_FACTOR) " x its fixed-point step",
     offsetof(struct msm_soft_settings, moment_bias), PARAM_FLOAT, 3e-5, 1e-7, 0.01, NULL, TUNE(3e-6, 3e-5, 3e-4)},
    {"depth_bias", "subtracted from the receiver's linear depth before both queries",
     offsetof(struct msm_soft_settings, depth_bias), PARAM_FLOAT, 0.0, 0.0, 0.05, NULL, TUNE(0, 1e-3, 1e-2)},
    PARAM_ROW_MIN_BLOCKER_FRACTION(struct msm_soft_settings, "blocked share"),
    {NULL},
};

static void msm_soft_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    const struct msm_soft_settings *s = settings;
    sat_request_search_box(&r->msm_sat, msm_soft_sat_format_ids[s->sat_format], s->light_size_scale, c);
}

static const struct technique_cell msm_soft_cells[] = {
    {"floating_box_sphere", {"sat_format=fp32"}},
    {"parallel_planes", {"light_size_scale=0.5"}},
    {"overlapping_occluders", {"moment_bias=0.003"}},
    {"grazing_receiver", {"depth_bias=0.001"}},
    {"contact_hardening", {"min_blocker_fraction=0.05"}},
    {NULL},
};

TECHNIQUE(msm_soft, .needs = SM_MSM_SAT, .request = msm_soft_request, .regression = msm_soft_cells,
          .summary = "PCSS with blocker depth and filtering by 4MSM from a SAT of four moments");
